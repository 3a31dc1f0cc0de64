"""Space drift: what Gymnasium 1.x's spaces build, return and compare differently (GM903, GM905, GM909, GM910).

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
* GM909 ``MultiBinary(0)`` and ``Discrete(0)`` raise ``ValueError`` (gym 0.21 built
  them); ``Discrete(<float>)`` raises ``TypeError``. Reported: what an empty space
  should become is the env's choice. ``MultiDiscrete([])`` still builds. Except a
  ``MultiBinary(n)`` whose size is a name or ``self`` attribute known to be an int that
  can be 0 (a parameter among them): ``(MultiBinary(n) if n else Box(0, 1, (0,), "int8"))``,
  the empty space with gym's shape, dtype, sample and flattening.
  ``Box(0, 255, dtype=np.int8)`` (a literal bound outside an integer dtype's range) raises
  ``ValueError`` too (gym cast the bound, 255 to -1 for int8). Reported: the dtype the
  bounds were meant for is the author's choice.
* GM910 ``Box.__eq__`` compares ``dtype`` (gym 0.21 compared shape and bounds only):
  ``box_a == box_b`` is False now for a float32 and a float64 Box. Reported.

Sources: Gymnasium 1.4.0 ``spaces/discrete.py``, ``spaces/multi_binary.py``,
``spaces/box.py``, ``spaces/dict.py``; gym 0.21 ``spaces/`` (catalog GM903, GM905).
"""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.base import FileContext, Rule, RuleFamily

RULES = (
    Rule(
        "GM903",
        "Discrete ints are NumPy ints",
        FixKind.AUTO,
        "`isinstance(x, int)` / `type(x) is int` on a space's `n`/`sample()` accept `np.integer`; `json.dumps` gets `int(...)`.",
    ),
    Rule("GM905", "Dict.sample() is a dict", FixKind.AUTO, "`isinstance(x, OrderedDict)` on a space's `sample()` becomes `isinstance(x, dict)`."),
    Rule(
        "GM909",
        "zero-size spaces raise",
        FixKind.FLAG,
        "`MultiBinary(0)`, `Discrete(0)`, `Discrete(<float>)` and `Box` bounds outside an integer dtype raise in Gymnasium 1.x: reported; "
        "a `MultiBinary(n)` whose int size can be 0 gets an empty `Box` for 0.",
    ),
    Rule("GM910", "Box equality compares dtype", FixKind.FLAG, "`box == other_space` is False across dtypes in Gymnasium 1.x: reported."),
)

SPACE_ATTRIBUTES = frozenset({"action_space", "observation_space", "single_action_space", "single_observation_space"})
SPACE_INT_ATTRIBUTES = frozenset({"n", "start"})
JSON_WRITERS = frozenset({"json.dumps", "json.dump"})
UNKNOWN = "?"  # a space of a class not known here


_INT_RANGES = {
    "int8": (-(2**7), 2**7 - 1),
    "uint8": (0, 2**8 - 1),
    "int16": (-(2**15), 2**15 - 1),
    "uint16": (0, 2**16 - 1),
    "int32": (-(2**31), 2**31 - 1),
    "uint32": (0, 2**32 - 1),
    "int64": (-(2**63), 2**63 - 1),
    "uint64": (0, 2**64 - 1),
}


def _argument(call: ast.Call, position: int, name: str) -> ast.expr | None:
    for kw in call.keywords:
        if kw.arg == name:
            return kw.value
    if any(isinstance(a, ast.Starred) for a in call.args[: position + 1]):
        return None
    return call.args[position] if position < len(call.args) else None


def _number(expr: ast.AST | None) -> float | None:
    """A literal int or float (``255``, ``-1``, ``255.0``), else None."""
    sign = 1
    if isinstance(expr, ast.UnaryOp) and isinstance(expr.op, (ast.USub, ast.UAdd)):
        sign = -1 if isinstance(expr.op, ast.USub) else 1
        expr = expr.operand
    if isinstance(expr, ast.Constant) and isinstance(expr.value, (int, float)) and not isinstance(expr.value, bool):
        return sign * expr.value
    return None


def _wrapped(value: int, limits: tuple[int, int]) -> int:
    """``value`` cast into an integer dtype of range ``limits``, as NumPy wraps it."""
    low, high = limits
    return (value - low) % (high - low + 1) + low


def _legacy_cast(call: ast.Call, name: str, bound: float, limits: tuple[int, int]) -> str:
    """What gym 0.26's Box made of the bound: an integer bound wrapped into the dtype; where
    the other bound is known too and the wrapped bounds cross, a space no value is in. Said
    so that the item shows why no Gymnasium space reproduces it (1.x also rejects low > high)."""
    if not float(bound).is_integer():
        return f"gym cast it into the dtype, so the legacy space's {name} was not {bound:g}"
    wrapped = _wrapped(int(bound), limits)
    text = f"gym cast it into the dtype: the legacy space's {name} was {wrapped}"
    other_name = "high" if name == "low" else "low"
    other = _number(_argument(call, 1 if other_name == "high" else 0, other_name))
    if other is not None and float(other).is_integer():
        low, high = (wrapped, _wrapped(int(other), limits)) if name == "low" else (_wrapped(int(other), limits), wrapped)
        if low > high:
            return (
                f"gym cast it into the dtype: the legacy space had low {low} above high {high}, so contains() was False "
                "for every value, which no Gymnasium space reproduces"
            )
    return text


def _space_class(qualified: set[str]) -> str | None:
    for q in qualified:
        rest = N.strip_gym_prefix(q)
        if rest is not None and rest.startswith("spaces.") and rest.rsplit(".", 1)[-1][:1].isupper():
            return rest.rsplit(".", 1)[-1]
    return None


class SpaceDrift(RuleFamily):
    RULES = RULES

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        profile = context.profile
        if not (profile.imports_gym or profile.imports_gymnasium):
            return False
        return any(word in facts.text for word in ("isinstance", "type(", "json", "MultiBinary", "Discrete", "==", "Box"))

    def decide(self) -> None:
        for name in ("isinstance",):
            for call in self.facts.calls_by_name.get(name, ()):
                if not self.facts.bindings_of(call.func):  # type: ignore[arg-type]
                    self._decide_isinstance(call)
        for node in self._compares():
            self._decide_compare(node)
        for name in ("dumps", "dump"):
            for call in self.facts.attribute_calls.get(name, ()):
                if self.facts.qualified_names(call.func) & JSON_WRITERS:
                    self._decide_json(call)
        for name in ("MultiBinary", "Discrete"):
            for call in [*self.facts.calls_by_name.get(name, ()), *self.facts.attribute_calls.get(name, ())]:
                if _space_class(self.facts.qualified_names(call.func)) == name:
                    self._decide_size(call, name)
        for call in [*self.facts.calls_by_name.get("Box", ()), *self.facts.attribute_calls.get("Box", ())]:
            if _space_class(self.facts.qualified_names(call.func)) == "Box":
                self._decide_box_bounds(call)

    def _compares(self) -> list[ast.Compare]:
        return self.facts.memo(("space-drift-compares", 0), lambda: [n for n in ast.walk(self.facts.tree) if isinstance(n, ast.Compare)])

    # -- what an expression is -----------------------------------------------------------

    def space_class(self, expr: ast.AST, depth: int = 0) -> str | None:
        """The space class of ``expr`` (``"Box"``), ``UNKNOWN`` for a space of a class not
        known here (``env.action_space``), None for what is not known to be a space."""
        if isinstance(expr, ast.Call):
            return _space_class(self.facts.qualified_names(expr.func))
        if isinstance(expr, ast.Attribute) and expr.attr in SPACE_ATTRIBUTES:
            if isinstance(expr.value, ast.Name) and self.receivers.is_self(expr.value):
                values = self.receivers.self_attribute_values(expr, expr.attr)
                found = {self.space_class(v, depth + 1) if isinstance(v, ast.Call) else None for v in values}
                if len(found) == 1 and None not in found:
                    return found.pop()
            return UNKNOWN
        if isinstance(expr, ast.Name) and depth == 0:
            narrowed = self._narrowed(expr)
            if narrowed is not None:
                return narrowed
            values = self._values(expr)
            found = {self.space_class(v, depth + 1) for v in values} if values else {None}
            return found.pop() if len(found) == 1 else (UNKNOWN if None not in found else None)
        return None

    def _narrowed(self, name: ast.Name) -> str | None:
        """The space class an enclosing ``if isinstance(name, spaces.X):`` proves (a helper
        that walks a space of any class: ``def f(space): if isinstance(space, Dict): ...``)."""
        child: ast.AST = name
        parent = self.facts.parent(child)
        while parent is not None and not isinstance(parent, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.Module)):
            if isinstance(parent, ast.If) and any(child is statement for statement in parent.body):
                test = parent.test
                if (
                    isinstance(test, ast.Call)
                    and isinstance(test.func, ast.Name)
                    and test.func.id == "isinstance"
                    and len(test.args) == 2
                    and isinstance(test.args[0], ast.Name)
                    and test.args[0].id == name.id
                    and not isinstance(test.args[1], ast.Tuple)
                ):
                    if any(self._inside(binding, parent) for binding in self.facts.bindings_of(name)):
                        return None  # rebound under the check
                    return _space_class(self.facts.qualified_names(test.args[1]))
            child, parent = parent, self.facts.parent(parent)
        return None

    def _inside(self, node: ast.AST, ancestor: ast.AST) -> bool:
        current: ast.AST | None = node
        while current is not None:
            if current is ancestor:
                return True
            current = self.facts.parent(current)
        return False

    def _values(self, name: ast.Name) -> list[ast.expr]:
        """What every binding of ``name`` assigns (empty when one is not a plain assignment)."""
        values = []
        for binding in self.facts.bindings_of(name):
            statement = self.facts.parent(binding)
            if not (isinstance(binding, ast.Name) and isinstance(statement, ast.Assign) and binding in statement.targets):
                return []
            values.append(statement.value)
        return values

    def space_value(self, expr: ast.AST, what: frozenset[str], depth: int = 0) -> str | None:
        """For ``<space>.n`` / ``<space>.sample()`` (the members in ``what``: "n", "start",
        "sample", "spaces"), or a name every binding of which is one: the space's class."""
        if isinstance(expr, ast.Attribute) and expr.attr in what and expr.attr != "sample":
            return self.space_class(expr.value)
        if (
            isinstance(expr, ast.Call)
            and "sample" in what
            and isinstance(expr.func, ast.Attribute)
            and expr.func.attr == "sample"
        ):
            return self.space_class(expr.func.value)
        if isinstance(expr, ast.Name) and depth == 0:
            values = self._values(expr)
            found = {self.space_value(v, what, depth + 1) for v in values} if values else {None}
            if None in found:
                return None
            return found.pop() if len(found) == 1 else UNKNOWN
        return None

    def _is_builtin(self, expr: ast.AST, name: str) -> bool:
        return isinstance(expr, ast.Name) and expr.id == name and not self.facts.bindings_of(expr)

    def _is_ordered_dict(self, expr: ast.AST) -> bool:
        return "collections.OrderedDict" in self.facts.qualified_names(expr)

    # -- GM903 / GM905: isinstance and type() checks --------------------------------------

    def _decide_isinstance(self, call: ast.Call) -> None:
        if len(call.args) != 2 or call.keywords or any(isinstance(a, ast.Starred) for a in call.args):
            return
        value, classes = call.args
        options = classes.elts if isinstance(classes, ast.Tuple) else [classes]
        if any(self._is_builtin(c, "int") for c in options) and not any(self._integer_class(c) for c in options):
            kind = self.space_value(value, frozenset({"n", "start", "sample"}))
            if kind is None and self._discrete_element(value):
                numpy = self.plan.ensure_import("numpy", asname="np")
                self.report(
                    call,
                    "GM903",
                    "a method of a `Discrete` space subclass receives the space's elements, and Gymnasium 1.x gives them "
                    "as `np.int64` (`sample()`, arithmetic on `n`), not `int`: the check accepts `np.integer` too",
                )
                self.plan.replace(classes, _add_integer(numpy))
                return
            if kind is None and self._discrete_action(value):
                numpy = self.plan.ensure_import("numpy", asname="np")
                self.report(
                    call,
                    "GM903",
                    "this env's actions are Discrete, and `action_space.sample()` gives an `np.int64` in Gymnasium "
                    "1.x, not an `int`: the check accepts `np.integer` too",
                )
                self.plan.replace(classes, _add_integer(numpy))
                return
            if kind is not None and kind in ("Discrete", UNKNOWN):
                numpy = self.plan.ensure_import("numpy", asname="np")
                self.report(call, "GM903", "a space's `n`/`sample()` is an `np.int64` in Gymnasium 1.x, not an `int`: the check accepts `np.integer` too")
                self.plan.replace(classes, _add_integer(numpy))
            return
        if len(options) == 1 and self._is_ordered_dict(classes) and self.space_value(value, frozenset({"sample", "spaces"})) is not None:
            self.report(call, "GM905", "`Dict.sample()` (and `Dict.spaces`) is a plain `dict` in Gymnasium 1.x, not an `OrderedDict`: checked as a dict")
            self.plan.replace(classes, lambda node: cst.Name("dict"))

    def _discrete_element(self, value: ast.AST) -> bool:
        """``idx`` in ``def get_action(self, idx)`` of a subclass of ``spaces.Discrete`` (a
        parameter the method never rebinds): an element of the space, ``np.int64`` when
        it comes from ``sample()`` or from arithmetic on ``n``."""
        if not isinstance(value, ast.Name):
            return False
        function = self.facts.enclosing_function(value)
        classdef = self.facts.enclosing_class(value)
        if function is None or classdef is None or self.facts.parent(function) is not classdef:
            return False
        if function.name in ("__init__", "__new__"):
            return False  # its arguments build the space: a size, not an element
        if not any(_space_class(self.facts.qualified_names(base)) == "Discrete" for base in classdef.bases):
            return False
        params = function.args.args[1:]  # after self
        bindings = self.facts.bindings_of(value)
        return len(bindings) == 1 and any(bindings[0] is p for p in params)

    def _discrete_action(self, value: ast.AST) -> bool:
        """``action`` in ``def step(self, action)`` of a Gym env class whose action space is
        only ever a ``Discrete``: every action is an integer, and a sampled one is ``np.int64``."""
        if not isinstance(value, ast.Name):
            return False
        function = self.facts.enclosing_function(value)
        classdef = self.facts.enclosing_class(value)
        if function is None or classdef is None or function.name != "step" or self.facts.parent(function) is not classdef:
            return False
        params = function.args.args
        if len(params) < 2 or params[1].arg != value.id or self.receivers.class_kind(classdef) is not EnvKind.GYM_ENV:
            return False
        if any(isinstance(b, ast.Name) and b.id == value.id for b in self.facts.bindings_of(value) if b is not params[1]):
            return False
        spaces = [
            node.value
            for node in ast.walk(classdef)
            if isinstance(node, ast.Assign)
            and any(isinstance(t, ast.Attribute) and t.attr == "action_space" for t in node.targets)
        ]
        return bool(spaces) and all(
            isinstance(space, ast.Call)
            and any(q.endswith("spaces.Discrete") or q.endswith("spaces.discrete.Discrete") for q in self.facts.qualified_names(space.func))
            for space in spaces
        )

    def _integer_class(self, expr: ast.AST) -> bool:
        return bool({"numpy.integer", "numbers.Integral", "numpy.int64"} & self.facts.qualified_names(expr))

    def _decide_compare(self, node: ast.Compare) -> None:
        if len(node.ops) != 1:
            return
        op, left, right = node.ops[0], node.left, node.comparators[0]
        if isinstance(op, (ast.Is, ast.IsNot, ast.Eq, ast.NotEq)):
            if self._type_check(node, op, left, right) or self._type_check(node, op, right, left):
                return
        if isinstance(op, (ast.Eq, ast.NotEq)):
            self._decide_box_equality(node, left, right)

    def _type_check(self, node: ast.Compare, op: ast.cmpop, typed: ast.expr, cls: ast.expr) -> bool:
        """``type(x) is int`` / ``type(x) == OrderedDict`` (either side)."""
        if not (isinstance(typed, ast.Call) and self._is_builtin(typed.func, "type") and len(typed.args) == 1 and not typed.keywords):
            return False
        value = typed.args[0]
        if isinstance(value, ast.Starred):
            return False
        negated = isinstance(op, (ast.IsNot, ast.NotEq))
        if self._is_builtin(cls, "int"):
            kind = self.space_value(value, frozenset({"n", "start", "sample"}))
            if kind not in ("Discrete", UNKNOWN):
                return False
            numpy = self.plan.ensure_import("numpy", asname="np")
            self.report(node, "GM903", "a space's `n`/`sample()` is an `np.int64` in Gymnasium 1.x, so `type(...) is int` is False: an isinstance check that accepts `np.integer` too")
            self.plan.replace(node, _isinstance_of(f"(int, {numpy}.integer)", negated))
            return True
        if self._is_ordered_dict(cls) and self.space_value(value, frozenset({"sample", "spaces"})) is not None:
            self.report(node, "GM905", "`Dict.sample()` (and `Dict.spaces`) is a plain `dict` in Gymnasium 1.x: `type(...) is OrderedDict` is False; checked as a dict")
            self.plan.replace(node, _isinstance_of("dict", negated))
            return True
        return False

    # -- GM903: JSON -----------------------------------------------------------------------

    def _decide_json(self, call: ast.Call) -> None:
        if not call.args or isinstance(call.args[0], ast.Starred):
            return
        if any(k.arg in ("default", "cls") for k in call.keywords):
            return  # the code already serializes what json cannot
        certain, unsure = [], []
        for value in _json_values(call.args[0]):
            kind = self.space_value(value, frozenset({"n", "start", "sample"}))
            if kind == "Discrete":
                certain.append(value)
            elif kind == UNKNOWN:
                unsure.append(value)  # a MultiBinary's n may be a list, a Box's sample an array: int() would break them
        for value in certain:
            self.report(value, "GM903", "`Discrete.n`/`sample()` is an `np.int64` in Gymnasium 1.x, which json cannot write: converted with int()")
            self.plan.replace(value, _int_of)
        if unsure:
            text = self.facts.segment(unsure[0])
            self.report(
                call,
                "GM903",
                f"`{text}` is a NumPy value in Gymnasium 1.x (`np.int64` for a Discrete space), which json cannot write "
                "(TypeError): convert it (`int(...)`, `.tolist()`) for the space it is",
                FixKind.FLAG,
            )

    # -- GM909: sizes Gymnasium rejects ------------------------------------------------------

    def _decide_size(self, call: ast.Call, name: str) -> None:
        size = call.args[0] if call.args and not isinstance(call.args[0], ast.Starred) else next((k.value for k in call.keywords if k.arg == "n"), None)
        if size is None:
            return
        parent = self.facts.parent(call)
        if isinstance(parent, ast.IfExp) and parent.body is call and ast.dump(parent.test) == ast.dump(size):
            return  # ``MultiBinary(n) if n else ...``: the size is tested already
        box = self._box_beside(call) if name == "MultiBinary" else None
        # A size from a parameter counts only in a module still on legacy gym, whose callers
        # may pass the 0 gym accepted; code already written for Gymnasium chose its sizes.
        from_legacy_parameter = self.context.profile.imports_gym and self._from_parameter(size)
        if box is not None and _pure(size) and self._int_size(size) and (self._may_be_zero(size) or from_legacy_parameter):
            # gym built an empty MultiBinary for n=0; an empty int8 Box is the space Gymnasium
            # builds with its shape, dtype, sample and flattening: it stands in for n=0 only.
            text = self.facts.segment(size)
            self.report(
                call,
                "GM909",
                f"`MultiBinary(0)` raises ValueError in Gymnasium 1.x (gym built an empty space), and `{text}` can be 0: "
                f'an empty `Box(0, 1, (0,), "int8")` stands in for it then (its `contains()` takes integer arrays only)',
                FixKind.ASSIST,
                tier=Tier.NOTE,
            )
            self.plan.replace(call, _empty_box_when_zero(box))
            return
        if self._may_be_zero(size):
            text = self.facts.segment(size)
            where = "" if isinstance(size, ast.Constant) else f": `{text}` can be 0 here"
            self.report(
                call,
                "GM909",
                f"`{name}` with n=0 raises ValueError in Gymnasium 1.x (gym built an empty space){where}; leave the space "
                "out (or use a Box of shape (0,)) when the feature is off",
                FixKind.FLAG,
            )
        elif name == "Discrete" and self._is_float(size):
            self.report(call, "GM909", f"`Discrete(n)` needs an integer in Gymnasium 1.x (a float raises TypeError): `{self.facts.segment(size)}` is a float; use `//` or int()", FixKind.FLAG)

    def _decide_box_bounds(self, call: ast.Call) -> None:
        """``Box(0, 255, dtype=np.int8)``: gym cast the bound into the dtype (255 wrapped to -1);
        Gymnasium 1.x raises ValueError for a bound outside an integer dtype's range."""
        dtype = _argument(call, 3, "dtype")
        dtype_name = self._dtype_name(dtype) if dtype is not None else None
        limits = _INT_RANGES.get(dtype_name) if dtype_name is not None else None
        if limits is None:
            return
        for position, name in ((0, "low"), (1, "high")):
            bound = _number(_argument(call, position, name))
            if bound is None or limits[0] <= bound <= limits[1]:
                continue
            self.report(
                call,
                "GM909",
                f"`Box` {name}={bound:g} is outside the range of {dtype_name} ({limits[0]}..{limits[1]}): Gymnasium 1.x "
                f"raises ValueError ({_legacy_cast(call, name, bound, limits)}); use the "
                "dtype the bounds were meant for (`np.uint8` for 0..255 pixels) or bounds the dtype holds",
                FixKind.FLAG,
            )
            return

    def _dtype_name(self, dtype: ast.AST) -> str | None:
        if isinstance(dtype, ast.Constant) and isinstance(dtype.value, str):
            return dtype.value
        for q in self.facts.qualified_names(dtype):
            if q.startswith("numpy."):
                return q.rsplit(".", 1)[-1]
        return None

    def _box_beside(self, call: ast.Call) -> str | None:
        """How ``Box`` is spelled beside this ``MultiBinary``: ``spaces.Box`` for
        ``spaces.MultiBinary``, ``Box`` where the module imports it from the spaces; else None."""
        if isinstance(call.func, ast.Attribute):
            return f"{self.facts.segment(call.func.value)}.Box" if "\n" not in self.facts.segment(call.func.value) else None
        for binding in self.facts.module_scope.bindings.get("Box", ()):
            if isinstance(binding, ast.alias) and _space_class({self.facts.imports.get(binding, "")}) == "Box":
                return "Box"
        return None

    def _int_size(self, expr: ast.AST, depth: int = 0) -> bool:
        """``expr`` is an int wherever it comes from: an int literal, a conditional of ints, a
        parameter annotated ``int`` or defaulting to an int, a name or ``self`` attribute every
        assignment of which is one of these."""
        if depth > 3:
            return False
        if isinstance(expr, ast.Constant):
            return isinstance(expr.value, int) and not isinstance(expr.value, bool)
        if isinstance(expr, ast.IfExp):
            return self._int_size(expr.body, depth + 1) and self._int_size(expr.orelse, depth + 1)
        if isinstance(expr, ast.Call) and isinstance(expr.func, ast.Name) and expr.func.id in ("int", "len"):
            return not self.facts.bindings_of(expr.func)
        values: list[ast.AST] = []
        if isinstance(expr, ast.Name):
            bindings = self.facts.bindings_of(expr)
            if not bindings:
                return False
            for binding in bindings:
                if isinstance(binding, ast.arg):
                    if not _int_parameter(binding, self.facts):
                        return False
                    continue
                statement = self.facts.parent(binding)
                if not (isinstance(binding, ast.Name) and isinstance(statement, ast.Assign) and binding in statement.targets):
                    return False
                values.append(statement.value)
        elif isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and self.receivers.is_self(expr.value):
            values = list(self.receivers.self_attribute_values(expr, expr.attr))
            if not values:
                return False
        else:
            return False
        return all(self._int_size(v, depth + 1) for v in values)

    def _from_parameter(self, expr: ast.AST) -> bool:
        """``n`` or ``self.n`` bound from a parameter: the caller chooses the size, 0 too."""
        if isinstance(expr, ast.Name):
            return any(isinstance(b, ast.arg) for b in self.facts.bindings_of(expr))
        if isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and self.receivers.is_self(expr.value):
            return any(
                isinstance(v, ast.Name) and any(isinstance(b, ast.arg) for b in self.facts.bindings_of(v))
                for v in self.receivers.self_attribute_values(expr, expr.attr)
            )
        return False

    def _may_be_zero(self, expr: ast.AST, depth: int = 0) -> bool:
        if isinstance(expr, ast.Constant):
            return expr.value == 0 and not isinstance(expr.value, bool) and isinstance(expr.value, int)
        if isinstance(expr, (ast.List, ast.Tuple)):
            return any(self._may_be_zero(e, depth) for e in expr.elts)
        if isinstance(expr, ast.IfExp):
            return self._may_be_zero(expr.body, depth) or self._may_be_zero(expr.orelse, depth)
        if isinstance(expr, ast.Name) and depth == 0:
            return any(self._may_be_zero(v, depth + 1) for v in self._values(expr))
        return False

    @staticmethod
    def _is_float(expr: ast.AST) -> bool:
        return (isinstance(expr, ast.BinOp) and isinstance(expr.op, ast.Div)) or (isinstance(expr, ast.Constant) and isinstance(expr.value, float))

    # -- GM910: Box equality ----------------------------------------------------------------

    def _decide_box_equality(self, node: ast.Compare, left: ast.expr, right: ast.expr) -> None:
        kinds = (self.space_class(left), self.space_class(right))
        if "Box" not in kinds or None in kinds:
            return
        self.report(
            node,
            "GM910",
            "`Box` equality compares the dtype in Gymnasium 1.x (gym compared shape and bounds only): a float32 and a "
            "float64 Box are no longer equal; compare the dtypes you mean, or `.shape`/`.low`/`.high`",
            FixKind.FLAG,
        )


def _json_values(expr: ast.expr) -> list[ast.expr]:
    """The values json writes: ``expr`` itself, or the items of dict/list/tuple literals."""
    if isinstance(expr, ast.Dict):
        return [v for value in expr.values for v in _json_values(value)]
    if isinstance(expr, (ast.List, ast.Tuple)):
        return [v for e in expr.elts if not isinstance(e, ast.Starred) for v in _json_values(e)]
    return [expr]


# -- building the new code ------------------------------------------------------------------


def _pure(expr: ast.AST) -> bool:
    """A name or an attribute chain of one (``n``, ``self.n``): read twice, the same value."""
    while isinstance(expr, ast.Attribute):
        expr = expr.value
    return isinstance(expr, ast.Name)


def _int_parameter(arg: ast.arg, facts: ModuleFacts) -> bool:
    """A parameter annotated ``int`` or whose default is an int literal."""
    if isinstance(arg.annotation, ast.Name) and arg.annotation.id == "int":
        return True
    function = facts.parent(arg)
    while function is not None and not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
        function = facts.parent(function)
    if function is None:
        return False
    args = function.args
    positional = [*args.posonlyargs, *args.args]
    defaults: dict[int, ast.expr | None] = {id(a): d for a, d in zip(positional[len(positional) - len(args.defaults) :], args.defaults)}
    defaults.update({id(a): d for a, d in zip(args.kwonlyargs, args.kw_defaults)})
    default = defaults.get(id(arg))
    return isinstance(default, ast.Constant) and isinstance(default.value, int) and not isinstance(default.value, bool)


def _empty_box_when_zero(box: str):
    """``spaces.MultiBinary(n)`` -> ``(spaces.MultiBinary(n) if n else spaces.Box(0, 1, (0,), "int8"))``."""

    def build(node: cst.BaseExpression) -> cst.BaseExpression:
        assert isinstance(node, cst.Call)
        size = next((a.value for a in node.args if a.keyword is None or a.keyword.value == "n"), None)
        assert size is not None
        empty = cst.parse_expression('Box(0, 1, (0,), "int8")')
        assert isinstance(empty, cst.Call)
        if isinstance(node.func, cst.Attribute):
            empty = empty.with_changes(func=node.func.with_changes(attr=cst.Name("Box")))  # the same module as changed
        else:
            empty = empty.with_changes(func=cst.Name(box))
        return cst.IfExp(
            test=size.deep_clone(),
            body=node,
            orelse=empty,
            lpar=[cst.LeftParen()],
            rpar=[cst.RightParen()],
        )

    return build


def _add_integer(numpy: str):
    """``int`` -> ``(int, np.integer)``; ``(int, float)`` -> ``(int, float, np.integer)``."""

    def build(node: cst.BaseExpression) -> cst.BaseExpression:
        integer = cst.parse_expression(f"{numpy}.integer")
        if isinstance(node, cst.Tuple):
            elements = list(node.elements)
            last = elements[-1]
            elements[-1] = last.with_changes(comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" ")))
            return node.with_changes(elements=[*elements, cst.Element(integer)])
        return cst.parse_expression(f"(int, {numpy}.integer)")

    return build


def _isinstance_of(classes: str, negated: bool):
    def build(node: cst.Comparison) -> cst.BaseExpression:
        typed = node.left if _is_type_call(node.left) else node.comparisons[0].comparator
        value = typed.args[0].value  # type: ignore[attr-defined]
        check = cst.Call(
            func=cst.Name("isinstance"),
            args=[cst.Arg(value, comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))), cst.Arg(cst.parse_expression(classes))],
        )
        if negated:
            return cst.UnaryOperation(operator=cst.Not(), expression=check, lpar=node.lpar, rpar=node.rpar)
        return check.with_changes(lpar=node.lpar, rpar=node.rpar)

    return build


def _is_type_call(node: cst.BaseExpression) -> bool:
    return isinstance(node, cst.Call) and isinstance(node.func, cst.Name) and node.func.value == "type"


def _int_of(node: cst.CSTNode) -> cst.CSTNode:
    assert isinstance(node, cst.BaseExpression)
    return cst.Call(func=cst.Name("int"), args=[cst.Arg(node.with_changes(lpar=[], rpar=[]))])
