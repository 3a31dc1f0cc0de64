"""Space drift: what Gymnasium 1.x's spaces build, return and compare differently (GM903, GM905, GM909-GM912).

Each claim was checked against the installed Gymnasium 1.4.0 (``docs/rules/<CODE>.md``
has the script):

* GM903 ``Discrete.n``, ``Discrete.start`` and ``Discrete.sample()`` are ``np.int64``
  (gym 0.21: ``int`` for ``n``, ``int`` from ``sample()``). ``json.dumps(np.int64(3))``
  raises ``TypeError``; ``isinstance(np.int64(3), int)`` and ``type(...) is int`` are
  False. Rewritten where certain: ``isinstance(x, int)`` / ``type(x) is int`` on a
  space's ``.n``, ``.start`` or ``sample()`` become ``isinstance(x, (int, np.integer))``
  (the same answer as before for every space: a Box sample is an array either way), and
  ``isinstance(action, int)`` in the ``step`` of a Gym env class whose action space is only
  ever ``Discrete``;
  ``json.dump(s)`` of a value traced to a ``Discrete`` gets ``int(...)``; a value of a
  space whose class is not known (``env.action_space.n`` may be a ``MultiBinary``'s
  list) is reported.
* GM905 ``Dict.sample()`` (and ``Dict.spaces``) are a plain ``dict`` (gym 0.21: an
  ``OrderedDict``): ``isinstance(x, OrderedDict)`` / ``type(x) is OrderedDict`` on a
  space's ``sample()`` or ``.spaces`` become ``isinstance(x, dict)`` (an OrderedDict is
  a dict; no other space's sample is either). ``Tuple.sample()`` is a tuple in both.
  ``Tuple.spaces`` is a tuple (gym 0.21: the list it was built from): added to a list it
  is read as ``list(...)``, changed in place it is reported (``tuple_spaces.py``).
* GM909 ``MultiBinary(0)`` and ``Discrete(0)`` raise ``ValueError`` (gym 0.21 built
  them); ``Discrete(<float>)`` raises ``TypeError``. Reported: what an empty space
  should become is the env's choice. ``MultiDiscrete([])`` still builds. Except a
  ``MultiBinary(n)`` whose size is a name or ``self`` attribute known to be an int that
  can be 0 (a parameter among them): ``(MultiBinary(n) if n else Box(0, 1, (0,), "int8"))``,
  the empty space with gym's shape, dtype, sample and flattening.
  ``Box(0, 255, dtype=np.int8)`` (a literal bound outside an integer dtype's range) raises
  ``ValueError`` too (gym cast the bound, 255 to -1 for int8). Reported: the dtype the
  bounds were meant for is the author's choice. So does a ``Box`` whose constant ``low`` lies
  above its ``high`` (a parameter's default among the constants: ``bounds.py``).
* GM910 ``Box.__eq__`` compares ``dtype`` (gym 0.21 compared shape and bounds only):
  ``box_a == box_b`` is False now for a float32 and a float64 Box. Reported. So does
  ``Box.contains`` (gym <= 0.20 did not): a float32 Box with float64 bounds, on an env whose
  observations are float64, whose ``contains()`` the run asks, is reported (``box_contains.py``).
* GM911 a space subclass whose ``__init__`` skips its space's (``super(Discrete,
  self).__init__(...)`` runs ``Space.__init__`` only) lacks what only that ``__init__``
  sets in Gymnasium 1.4 (``Discrete.start``): ``sample()``, ``contains()``, ``repr()``
  raise AttributeError. Reported; for a ``Discrete`` subclass that skipped it to keep a
  dtype, the item names the two calls to choose between (``subclasses.py``).
* GM912 gym 0.9's ``MultiDiscrete.low`` / ``.high`` do not exist in Gymnasium: under an
  isinstance check they become ``start`` / ``start + nvec - 1``; on a space built here
  (gym 0.9's ``[[low, high], ...]``) reported. That construction itself raises ValueError in
  Gymnasium: ``[[0, n], ...]`` becomes the counts ``[n + 1, ...]``, other lows are reported
  (``multi_discrete.py``).

Sources: Gymnasium 1.4.0 ``spaces/discrete.py``, ``spaces/multi_binary.py``,
``spaces/box.py``, ``spaces/dict.py``; gym 0.21 ``spaces/`` (catalog GM903, GM905).

This module is the family (it finds the calls and compares, and decides GM910); the
rules' decisions are ``type_checks.py`` (GM903, GM905: isinstance and type()),
``json_writes.py`` (GM903: json), ``tuple_spaces.py`` (GM905: a Tuple's members), ``sizes.py`` and ``bounds.py`` (GM909), ``box_contains.py``
(GM910) and ``subclasses.py`` (GM911), on
what ``values.py`` says an expression is.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.module import walk
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.spaces.bounds import decide_crossed_bounds
from gymmigrate.rules.spaces.box_contains import decide_box_contains
from gymmigrate.rules.spaces.json_writes import JSON_WRITERS, decide_json
from gymmigrate.rules.spaces.multi_discrete import (
    decide_bounds_read,
    decide_pairs_construction,
)
from gymmigrate.rules.spaces.shape_writes import decide_shape_write
from gymmigrate.rules.spaces.sizes import decide_box_bounds, decide_size
from gymmigrate.rules.spaces.subclasses import decide_subclass
from gymmigrate.rules.spaces.tuple_spaces import decide_tuple_members
from gymmigrate.rules.spaces.type_checks import decide_isinstance, type_check
from gymmigrate.rules.spaces.values import SpaceValues, space_class_of

RULES = (
    Rule(
        "GM903",
        "Discrete ints are NumPy ints",
        FixKind.AUTO,
        "`isinstance(x, int)` / `type(x) is int` on a space's `n`/`sample()` accept `np.integer`; `json.dumps` gets `int(...)`.",
    ),
    Rule(
        "GM905",
        "Dict.sample() is a dict",
        FixKind.AUTO,
        "`isinstance(x, OrderedDict)` on a space's `sample()` becomes `isinstance(x, dict)`; a `Tuple`'s `.spaces` (a tuple "
        "now) added to a list is read as `list(...)`, changed in place it is reported.",
    ),
    Rule(
        "GM909",
        "zero-size spaces raise",
        FixKind.FLAG,
        "`MultiBinary(0)`, `Discrete(0)`, `Discrete(<float>)`, `Box` bounds outside an integer dtype and `Box` low above high "
        "raise in Gymnasium 1.x: reported; "
        "a `MultiBinary(n)` whose int size can be 0 gets an empty `Box` for 0.",
    ),
    Rule(
        "GM912",
        "MultiDiscrete low/high",
        FixKind.AUTO,
        "gym's `MultiDiscrete.low` / `.high` become `start` / `start + nvec - 1` on a space known to be a `MultiDiscrete`; "
        "other receivers are reported.",
    ),
    Rule(
        "GM910",
        "Box equality and contains() compare dtype",
        FixKind.FLAG,
        "`box == other_space` is False across dtypes in Gymnasium 1.x, and `contains()` of a float64 value is False for a "
        "float32 Box: reported.",
    ),
    Rule(
        "GM913",
        "space shape is read-only",
        FixKind.AUTO,
        "`space.shape = ...` raises AttributeError in Gymnasium: removed where the next statement rebuilds the space, "
        "reported elsewhere.",
    ),
    Rule(
        "GM911",
        "space subclasses that skip the space's __init__",
        FixKind.FLAG,
        "A space subclass whose `__init__` skips its space's and never sets what Gymnasium 1.4's space reads (`Discrete.start`) "
        "is reported; for a `Discrete` subclass that skipped it only to keep a dtype, the item names the call with `dtype=` "
        "(whose `contains` refuses other integer types) and the one without (int64).",
    ),
)


# Words one of which every module the family decides on holds (rules/__init__.py's
# PIPELINE loads the family on the same words): checks and comparisons of spaces, their JSON,
# (GM911) subclasses of a space class, named in their bases, and (GM913) writes of a space's shape.
_WORDS = (
    "isinstance", "type(", "json", "==", "space.shape",
    "Box", "Discrete", "MultiBinary", "MultiDiscrete", "Space", "Tuple", "Dict", "Text", "Graph", "Sequence", "OneOf",
)

class SpaceDrift(RuleFamily):
    RULES = RULES

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        profile = context.profile
        if not (profile.imports_gym or profile.imports_gymnasium):
            return False
        return any(word in facts.text for word in _WORDS)

    def decide(self) -> None:
        self.spaces = SpaceValues(self.facts, self.receivers)
        for name in ("isinstance",):
            for call in self.facts.calls_by_name.get(name, ()):
                if not self.facts.bindings_of(call.func):  # type: ignore[arg-type]
                    decide_isinstance(self, self.spaces, call)
        for node in self._compares():
            self._decide_compare(node)
        for name in ("dumps", "dump"):
            for call in self.facts.attribute_calls.get(name, ()):
                if self.facts.qualified_names(call.func) & JSON_WRITERS:
                    decide_json(self, self.spaces, call)
        for name in ("MultiBinary", "Discrete"):
            for call in [*self.facts.calls_by_name.get(name, ()), *self.facts.attribute_calls.get(name, ())]:
                if space_class_of(self.facts.qualified_names(call.func)) == name:
                    decide_size(self, self.spaces, call, name)
        for call in [*self.facts.calls_by_name.get("MultiDiscrete", ()), *self.facts.attribute_calls.get("MultiDiscrete", ())]:
            if space_class_of(self.facts.qualified_names(call.func)) == "MultiDiscrete":
                decide_pairs_construction(self, call)
        for call in [*self.facts.calls_by_name.get("Box", ()), *self.facts.attribute_calls.get("Box", ())]:
            if space_class_of(self.facts.qualified_names(call.func)) == "Box":
                if not decide_box_bounds(self, call):
                    decide_crossed_bounds(self, call)
                decide_box_contains(self, call)
        for classdef in self.facts.all_classes:
            decide_subclass(self, classdef)
        for name in ("low", "high"):
            for attribute in self.facts.attributes.get(name, ()):
                decide_bounds_read(self, self.spaces, attribute)
        for attribute in self.facts.attributes.get("shape", ()):
            decide_shape_write(self, self.spaces, attribute)
        for attribute in self.facts.attributes.get("spaces", ()):
            decide_tuple_members(self, self.spaces, attribute)

    def _compares(self) -> list[ast.Compare]:
        return self.facts.memo(("space-drift-compares", 0), lambda: [n for n in walk(self.facts.tree) if isinstance(n, ast.Compare)])

    # -- compares: ``type(x) is int`` (GM903, GM905) or ``box == other`` (GM910) ------------

    def _decide_compare(self, node: ast.Compare) -> None:
        if len(node.ops) != 1:
            return
        op, left, right = node.ops[0], node.left, node.comparators[0]
        if isinstance(op, (ast.Is, ast.IsNot, ast.Eq, ast.NotEq)):
            if type_check(self, self.spaces, node, op, left, right) or type_check(self, self.spaces, node, op, right, left):
                return
        if isinstance(op, (ast.Eq, ast.NotEq)):
            self._decide_box_equality(node, left, right)

    # -- GM910: Box equality ----------------------------------------------------------------

    def _decide_box_equality(self, node: ast.Compare, left: ast.expr, right: ast.expr) -> None:
        kinds = (self.spaces.space_class(left), self.spaces.space_class(right))
        if "Box" not in kinds or None in kinds:
            return
        self.report(
            node,
            "GM910",
            "`Box` equality compares the dtype in Gymnasium 1.x (gym compared shape and bounds only): a float32 and a "
            "float64 Box are no longer equal; compare the dtypes you mean, or `.shape`/`.low`/`.high`",
            FixKind.FLAG,
        )

