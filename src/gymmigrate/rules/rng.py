"""``np_random`` is a ``numpy.random.Generator`` (GM505, GM901) and removed seeding helpers (GM506).

gym 0.22 switched ``seeding.np_random`` from a ``RandomState`` (MT19937) to a
``Generator`` (PCG64), so the ``RandomState`` method names fail with
``AttributeError: 'numpy.random._generator.Generator' object has no attribute 'randint'``.

* GM505 on env RNGs (``self.np_random`` in env and wrapper classes, ``env.np_random``,
  ``env.unwrapped.np_random``, names bound from ``seeding.np_random(...)``):
  ``randint`` -> ``integers``; ``random_integers(lo, hi)`` -> ``integers(lo, hi, endpoint=True)``;
  ``random_sample`` / ``ranf`` / ``sample`` -> ``random``; ``rand(d0, d1)`` ->
  ``random((d0, d1))`` and ``randn`` -> ``standard_normal`` (the varargs become one size
  tuple); ``get_state()`` / ``set_state(s)`` -> ``bit_generator.state``; ``seed`` and
  ``tomaxint`` have no Generator counterpart and are reported.
* GM901 the same table for space RNGs (``self.action_space.np_random.randint``).
* GM506 ``seeding.hash_seed``, ``create_seed``, ``_bigint_from_bytes``,
  ``_int_list_from_bigint`` and the ``seeding.rand/randn/randint`` wrappers were removed
  in gym 0.26.

GUARD: the global ``np.random.*`` functions and ``np.random.RandomState(...)`` objects
keep the legacy API in NumPy and are never touched.

Because the bit generator changed, the same seed draws different numbers than under
gym 0.21: the first rewritten site of each file carries one review item saying so.

Sources: gym 0.22 release notes (``np_random`` is a Generator); gym 0.26 release notes
(seeding helpers removed); Gymnasium ``utils/seeding.py``.
"""

from __future__ import annotations

import ast
import os

from gymmigrate.edits.lazy import cst
from gymmigrate.edits.lazy import matchers as m  # loaded by the first edit that matches
from gymmigrate.facts import names as N
from gymmigrate.facts.decisions import receiver_text
from gymmigrate.facts.env_classes import EnvClasses, is_self_attribute
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import ModuleFacts, full_name, walk
from gymmigrate.facts.rng_handovers import rng_stores
from gymmigrate.findings import FixKind, Tier, removed_helper_question
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.repeats import Repeats

RULES = (
    Rule("GM505", "np_random Generator API", FixKind.AUTO, "RandomState methods on `np_random` become their Generator equivalents."),
    Rule("GM506", "removed seeding helpers", FixKind.FLAG, "`seeding.hash_seed`, `create_seed`, `rand`... were removed in gym 0.26."),
    Rule("GM901", "space RNG", FixKind.AUTO, "`space.np_random` is a Generator too: the GM505 table applies."),
)

RENAMED = {"randint": "integers", "random_sample": "random", "ranf": "random", "sample": "random"}
PACKED_SIZE = {"rand": "random", "randn": "standard_normal"}
NO_EQUIVALENT = {
    "seed": "a Generator cannot be re-seeded: use env.reset(seed=...) or np.random.default_rng(seed)",
    "tomaxint": "Generator has no tomaxint: use integers(np.iinfo(int).max)",
}
RNG_METHODS = frozenset({*RENAMED, *PACKED_SIZE, *NO_EQUIVALENT, "random_integers", "get_state", "set_state"})
REMOVED_SEEDING = frozenset(
    {"hash_seed", "create_seed", "_bigint_from_bytes", "_int_list_from_bigint", "rand", "randn", "randint", "get_state", "set_state"}
)
STREAM_NOTE = (
    "np_random is now a PCG64 Generator instead of MT19937: the same seed draws different numbers than under gym 0.21, "
    "so regenerate stored seeded results"
)


GYM_RNG_KINDS = (EnvKind.GYM_ENV, EnvKind.GYM_VEC, EnvKind.PZ_AEC, EnvKind.PZ_PARALLEL)
Verdict = tuple[str, FixKind, str]


class GeneratorApi(RuleFamily):
    RULES = RULES
    after = ("EnvClassFamily",)  # the seed() statements it drops (FamilyNotes.dropped_statements)

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        return "np_random" in facts.text or "seeding" in facts.text

    def decide(self) -> None:
        self.env = EnvClasses.of(self.facts, self.receivers)
        self._noted_stream = False
        self._asked = Repeats("GM505")  # one question per class: is its inherited np_random a Generator?
        calls = [call for method in RNG_METHODS for call in self.facts.attribute_calls.get(method, ())]
        # In the order a LibCST traversal leaves them (inner calls first): the first
        # rewritten site carries the one note about the changed random stream.
        calls.sort(key=lambda c: (c.end_lineno, c.end_col_offset, -c.lineno, -c.col_offset))
        for call in calls:
            self._rng_call(call)
        self._wrapper_random_states()
        self._removed_helpers()

    def _wrapper_random_states(self) -> None:
        """``self.np_random = np.random.RandomState(0)`` in a subclass of a Gym wrapper. gym
        0.21's Wrapper had no ``np_random`` of its own, so the wrapper kept a private stream;
        Gymnasium's Wrapper hands ``np_random`` to the env it wraps, so the assignment replaces
        the base env's Generator with a RandomState (the env's own ``integers``/``random``
        draws then fail) and the wrapper shares that stream. A duck wrapper has no such
        property: its store stays its own."""
        for node in self.facts.attributes.get("np_random", ()):
            if not (isinstance(node.ctx, ast.Store) and is_self_attribute(node)):
                continue
            assign = self.facts.parent(node)
            if not (isinstance(assign, ast.Assign) and _is_random_state(assign.value)):
                continue
            classdef = self.facts.enclosing_class(node)
            if classdef is None or not self.receivers.has_gym_wrapper_base(classdef):
                continue
            self.report(
                node,
                "GM505",
                f"a RandomState stored as `self.np_random` in the wrapper {classdef.name}: a Gymnasium wrapper's "
                "np_random is its env's (a property that sets `env.np_random`), so this RandomState replaces the base env's "
                "Generator, whose own draws (`integers`, `random`) then fail; keep the wrapper's stream in an attribute of its "
                "own (`self._rng`) and read that",
                FixKind.FLAG,
                # its __init__ and its seed() storing one: one decision for the class
                question=("GM505", "wrapper RandomState", id(classdef)),
            )

    # -- GM505 / GM901 ---------------------------------------------------------------------

    def _rng_call(self, call: ast.Call) -> None:
        func = call.func
        assert isinstance(func, ast.Attribute)
        verdict = self._rng_receiver(func.value)
        if verdict is None:
            return
        code, kind, why = verdict
        method = func.attr
        statement = self.facts.parent(call)
        if kind is FixKind.FLAG:
            self.report(call, code, f"np_random.{method}(...) is RandomState API; {why}: if it is, use the Generator method", FixKind.FLAG)
            if not (method == "set_state" and isinstance(statement, ast.Expr)):
                return
        if method == "set_state" and isinstance(statement, ast.Expr):
            # The statement becomes an assignment (the old pass did this even where it
            # also flagged the receiver).
            if len(call.args) == 1 and not call.keywords and not isinstance(call.args[0], ast.Starred):
                self.report(call, code, "np_random.set_state(s) -> np_random.bit_generator.state = s: the state must be a PCG64 state dict now", FixKind.ASSIST)
                self._note_stream(call, code)
                self.plan.replace(statement, _state_assignment)
            return
        message = ""
        if method in RENAMED:
            self.plan.replace(func, _renamed(RENAMED[method]))
            message = f"np_random.{method}(...) -> np_random.{RENAMED[method]}(...)"
        elif method == "random_integers":
            self.plan.replace(call, _inclusive)
            message = "np_random.random_integers(lo, hi) -> np_random.integers(lo, hi, endpoint=True) (both ends inclusive)"
        elif method in PACKED_SIZE:
            new_name = PACKED_SIZE[method]
            starred = not call.keywords and len(call.args) == 1 and isinstance(call.args[0], ast.Starred)
            if not starred and (call.keywords or any(isinstance(a, ast.Starred) for a in call.args)):
                self.report(call, code, f"np_random.{method}(*dims) takes one size tuple as Generator.{new_name}(size); rewrite by hand", FixKind.FLAG)
                return
            # ``randn(*x.shape)``: the dimensions are already one sequence, which is the size
            self.plan.replace(call, _size_of_starred(new_name) if starred else _packed_call(new_name))
            message = f"np_random.{method}(...) -> np_random.{new_name}(...)"
            if starred:
                message = f"np_random.{method}(*dims) -> np_random.{new_name}(tuple(dims)): the unpacked dimensions became one size tuple"
            elif len(call.args) > 1:
                message = f"np_random.{method}(d0, d1, ...) -> np_random.{new_name}((d0, d1, ...)): the dimensions became one size tuple"
                kind = FixKind.ASSIST if kind is FixKind.AUTO else kind
        elif method == "get_state" and not call.args and not call.keywords:
            self.plan.replace(call, _state_attribute)
            message = "np_random.get_state() -> np_random.bit_generator.state: the state is now a dict, not the MT19937 tuple"
            kind = FixKind.ASSIST if kind is FixKind.AUTO else kind
        else:  # seed, tomaxint, get_state(...) with arguments, set_state not as a statement
            reason = NO_EQUIVALENT.get(method, "set the state with `np_random.bit_generator.state = state` as a statement")
            # One function reseeding several layers (``env.np_random``, ``env.env.np_random``)
            # asks one question: how it seeds now.
            owner = self.facts.enclosing_function(call) or self.facts.tree
            self.report(call, code, f"np_random.{method}(...) on a Generator: {reason}", FixKind.FLAG, question=("GM505", method, id(owner)))
            return
        question = None
        if why:
            # what the run shows about the class, said at its first call; where that is a
            # question (is its base a gym class?), it is one per class: asked at the first
            # call, naming the class's other calls, which are notes that point there
            key = (id(self.facts.enclosing_class(call)), why)
            message = f"{message}; {why}" if self._asked.first(key, call) else message
            question = self._asked.question(key) if kind is not FixKind.AUTO else None
        self.report(call, code, message, kind, question=question)
        self._note_stream(call, code)

    def _note_stream(self, node: ast.AST, code: str) -> None:
        if not self._noted_stream:
            self._noted_stream = True
            # Once per file, about the file rather than this line: nothing here to decide,
            # so it is a note (listed in the JSON report and by `check`).
            self.report(node, code, STREAM_NOTE, FixKind.FLAG, tier=Tier.NOTE)

    # -- which receivers are Generators ---------------------------------------------------------

    def _rng_receiver(self, receiver: ast.AST) -> Verdict | None:
        """(rule, fix kind, reason) when ``receiver`` is a gym RNG; None to leave the call alone."""
        if isinstance(receiver, ast.Attribute) and receiver.attr == "np_random":
            return self._np_random_owner(receiver.value)
        if isinstance(receiver, ast.Name) and self._name_from_seeding(receiver):
            return "GM505", FixKind.AUTO, ""
        if isinstance(receiver, ast.Attribute) and is_self_attribute(receiver) and self._self_attribute_from_seeding(receiver):
            return "GM505", FixKind.AUTO, ""
        if isinstance(receiver, ast.Subscript) and isinstance(receiver.value, ast.Call) and self._seeding_first(receiver):
            return "GM505", FixKind.AUTO, ""
        return None

    def _np_random_owner(self, owner: ast.AST) -> Verdict | None:
        text = receiver_text(owner)
        if _names_a_space(owner):
            return "GM901", FixKind.AUTO, ""
        if isinstance(owner, ast.Name) and owner.id == "self":
            return self._self_np_random(owner)
        kind = self.receivers.kind_of(owner)
        if kind in GYM_RNG_KINDS:
            return "GM505", FixKind.AUTO, ""
        if kind is EnvKind.UNKNOWN and self._gym_file and isinstance(owner, ast.Attribute) and owner.attr == "unwrapped":
            return "GM505", FixKind.AUTO, ""  # ``x.unwrapped.np_random``: only a Gym env has ``unwrapped``
        if kind is EnvKind.UNKNOWN and self._gym_file:
            return "GM505", FixKind.ASSIST, f"could not trace where `{text}` comes from; every gym/gymnasium np_random is a Generator"
        return None

    @property
    def _gym_file(self) -> bool:
        return self.context.profile.imports_gym or self.context.profile.imports_gymnasium

    def _self_np_random(self, node: ast.Name) -> Verdict | None:
        classdef = self.facts.enclosing_class(node)
        if classdef is None:
            return None
        # One verdict per class: an env class reads self.np_random dozens of times.
        return self.facts.memo(("rng-self-np-random", id(classdef)), lambda: self._class_np_random(classdef))

    def _class_np_random(self, classdef: ast.ClassDef) -> Verdict | None:
        index = self.env.index(classdef)
        stores = index.stores_to_self("np_random") + index.stores_to_self("_np_random")
        if any(_is_random_state(value) for value in stores):
            return None  # np.random.RandomState(seed): still the legacy API (GUARD)
        if all(self.env.is_seeding_np_random(value) for value in stores):
            if stores or self.env.is_custom_env(classdef) or self.receivers.class_kind(classdef).is_gym:
                return "GM505", FixKind.AUTO, ""
            decided, handed = self._handed_over(classdef)
            if decided:
                return handed
            if self._gym_file:
                return "GM505", FixKind.ASSIST, "this class's np_random is inherited from a base the module does not define; it is a Generator if that base is a gym/gymnasium class"
            return None
        if self._gym_file:
            return "GM505", FixKind.FLAG, "self.np_random is set from a value this module does not create (an env's np_random passed in is a Generator now)"
        return None

    def _handed_over(self, classdef: ast.ClassDef) -> tuple[bool, Verdict | None]:
        """A class that never sets its np_random gets it from outside: where the run hands
        objects an ``np_random`` (``self.robot.np_random = self.np_random``, this module or
        another), it is a Gym env's Generator when every store of the run is one. (False,
        None): the run hands none, the other evidence decides; (True, None): it hands only
        other values (a RandomState), whose methods stay."""
        project = self.receivers.project
        here = os.path.realpath(self.context.path)
        stores = (
            list(project.facts.rng_stores)
            if project is not None
            else [(here, line, handed, generator, built) for line, handed, generator, built in rng_stores(self.facts, self.receivers)]
        )
        # a handover of this module first: a bare line number would read as one of this file
        handovers = sorted((path != here, path, line, built) for path, line, handed, generator, built in stores if handed and generator)
        if not handovers:
            return any(handed for _, _, handed, _, _ in stores), None
        _, path, line, _ = handovers[0]
        where = f"line {line}" if path == here else f"{os.path.basename(path)}:{line}"
        if all(generator for _, _, _, generator, _ in stores):
            built_here = [(p != here, p, n) for p, n, handed, generator, built in stores if handed and built == classdef.name]
            if built_here and not self._init_reads_np_random(classdef):
                # ``s = Scene()`` then ``s.np_random = self.np_random``: whatever a base set in
                # __init__ is replaced before any method of the class draws from it
                _, path, line = min(built_here)
                where = f"line {line}" if path == here else f"{os.path.basename(path)}:{line}"
                return True, (
                    "GM505",
                    FixKind.AUTO,
                    f"the run hands this class a Generator as `.np_random` right after building it ({where}), "
                    f"over whatever a base set",
                )
            return True, (
                "GM505",
                FixKind.ASSIST,
                f"this class never sets np_random: it is handed one from outside, and the run hands only Generators "
                f"(`.np_random = ...` at {where}); if a base whose module the run does not read sets a RandomState, undo this",
            )
        return True, ("GM505", FixKind.FLAG, f"this class never sets np_random; the run hands a Generator to `.np_random` at {where} but stores other values too")

    def _init_reads_np_random(self, classdef: ast.ClassDef) -> bool:
        """The class's own ``__init__`` reads np_random or calls its own methods: something
        may draw before the object is handed its Generator."""
        init = next((n for n in classdef.body if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)) and n.name == "__init__"), None)
        if init is None:
            return False
        for node in walk(init):
            if isinstance(node, ast.Attribute) and node.attr in ("np_random", "_np_random"):
                return True
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and isinstance(node.func.value, ast.Name) and node.func.value.id == "self":
                return True
        return False

    def _name_from_seeding(self, name: ast.Name) -> bool:
        bindings = self.facts.bindings_of(name)
        return bool(bindings) and all(self._binding_from_seeding(b) for b in bindings)

    def _binding_from_seeding(self, target: ast.AST) -> bool:
        if not isinstance(target, ast.Name):
            return False
        parent = self.facts.parent(target)
        if isinstance(parent, ast.Assign) and any(t is target for t in parent.targets):
            return self._seeding_first(parent.value)
        if isinstance(parent, (ast.Tuple, ast.List)) and parent.elts and parent.elts[0] is target:
            assign = self.facts.parent(parent)
            return isinstance(assign, ast.Assign) and any(t is parent for t in assign.targets) and self.env.is_seeding_np_random(assign.value)
        return False

    def _seeding_first(self, value: ast.AST) -> bool:
        """``seeding.np_random(s)[0]``."""
        return (
            isinstance(value, ast.Subscript)
            and self.env.is_seeding_np_random(value.value)
            and isinstance(value.slice, ast.Constant)
            and type(value.slice.value) is int
            and value.slice.value == 0
            and self.facts.segment(value.slice) == "0"
        )

    def _self_attribute_from_seeding(self, attr: ast.Attribute) -> bool:
        classdef = self.facts.enclosing_class(attr)
        if classdef is None:
            return False
        key = ("rng-self-attribute-" + attr.attr, id(classdef))

        def compute() -> bool:
            stores = self.env.index(classdef).stores_to_self(attr.attr)
            return bool(stores) and all(self.env.is_seeding_np_random(v) or self._seeding_first(v) for v in stores)

        return self.facts.memo(key, compute)

    # -- GM506 -------------------------------------------------------------------------------------

    def _removed_helpers(self) -> None:
        if "seeding" not in self.facts.text:
            return
        # Names an import binds to something under gym(nasium).utils.seeding.
        bound = {
            alias.asname or alias.name.split(".", 1)[0]
            for alias, qualified in self.facts.imports.items()
            if (N.strip_gym_prefix(qualified) or "").startswith("utils.seeding")
            or N.strip_gym_prefix(qualified) in ("", "utils")
        }
        for node in self.facts.parents:
            if isinstance(node, ast.Attribute):
                if node.attr in REMOVED_SEEDING:
                    self._check_removed_helper(node)
            elif isinstance(node, ast.Name) and node.id in bound and not isinstance(self.facts.parent(node), ast.Attribute):
                self._check_removed_helper(node)

    def _check_removed_helper(self, node: ast.AST) -> None:
        for q in sorted(self.facts.qualified_names(node)):
            rest = N.strip_gym_prefix(q)
            if rest is not None and rest.startswith("utils.seeding.") and rest.rsplit(".", 1)[-1] in REMOVED_SEEDING:
                helper = rest.rsplit(".", 1)[-1]
                if self.facts.statement_of(node) in self.context.notes.dropped_statements:
                    # The line goes with the seed() method the rewrite removes: nothing to replace.
                    self.report(node, "GM506", f"seeding.{helper} was removed in gym 0.26; this line goes with the removed seed()", tier=Tier.NOTE)
                    return
                if self.facts.statement_of(node) in self.context.notes.dead_in_hand_ported_seed:
                    # Its value is never read, and the seed() it is in is left to port by
                    # hand (GM503 asks there): porting drops it, no second decision.
                    self.report(
                        node,
                        "GM506",
                        f"seeding.{helper} was removed in gym 0.26; its value is never read: drop this line when porting "
                        "this seed() by hand (the GM503 item there)",
                        tier=Tier.NOTE,
                    )
                    return
                # with its import (GM105), one decision: what replaces the helper
                self.report(
                    node,
                    "GM506",
                    f"seeding.{helper} was removed in gym 0.26: derive seeds with np.random.SeedSequence or draw from np_random",
                    question=removed_helper_question("utils.seeding", helper),
                )
                return


def _is_random_state(value: ast.AST) -> bool:
    return isinstance(value, ast.Call) and (full_name(value.func) or "").endswith("RandomState")


def _names_a_space(owner: ast.AST) -> bool:
    last = owner.attr if isinstance(owner, ast.Attribute) else owner.id if isinstance(owner, ast.Name) else ""
    return last == "space" or last.endswith("_space") or last.endswith("_spaces")


# -- builds: LibCST replacements for the decided sites --------------------------------------------


def _renamed(new: str):
    def build(node: cst.Attribute) -> cst.Attribute:
        return node.with_changes(attr=cst.Name(new))

    return build


def _inclusive(node: cst.Call) -> cst.Call:
    assert isinstance(node.func, cst.Attribute)
    return _inclusive_integers(node, node.func)


def _packed_call(new_name: str):
    def build(node: cst.Call) -> cst.Call:
        assert isinstance(node.func, cst.Attribute)
        return _packed(node, node.func, new_name)

    return build


def _state_attribute(node: cst.Call) -> cst.Attribute:
    assert isinstance(node.func, cst.Attribute)
    return cst.Attribute(value=cst.Attribute(value=node.func.value, attr=cst.Name("bit_generator")), attr=cst.Name("state"))


def _state_assignment(node: cst.Expr) -> cst.Assign:
    call = node.value
    assert isinstance(call, cst.Call) and isinstance(call.func, cst.Attribute)
    target = cst.Attribute(value=cst.Attribute(value=call.func.value, attr=cst.Name("bit_generator")), attr=cst.Name("state"))
    return cst.Assign(targets=[cst.AssignTarget(target)], value=call.args[0].value)


def _inclusive_integers(call: cst.Call, func: cst.Attribute) -> cst.Call:
    args = list(call.args)
    positional = [a for a in args if a.keyword is None]
    if len(positional) == 1 and not any(a.keyword is not None and m.matches(a.keyword, m.Name("high")) for a in args):
        # random_integers(n) draws from [1, n]
        args.insert(0, cst.Arg(cst.Integer("1")))
    if args:
        args[-1] = args[-1].with_changes(comma=cst.MaybeSentinel.DEFAULT)
    args.append(cst.Arg(cst.Name("True"), keyword=cst.Name("endpoint"), equal=cst.AssignEqual(cst.SimpleWhitespace(""), cst.SimpleWhitespace(""))))
    return call.with_changes(func=func.with_changes(attr=cst.Name("integers")), args=args)


def _size_of_starred(new_name: str):
    """``rand(*dims)`` -> ``random(tuple(dims))``: ``tuple`` takes any iterable ``*`` took."""

    def build(node: cst.Call) -> cst.Call:
        assert isinstance(node.func, cst.Attribute) and node.args and node.args[0].star == "*"
        size = cst.Call(func=cst.Name("tuple"), args=[cst.Arg(node.args[0].value)])
        return node.with_changes(func=node.func.with_changes(attr=cst.Name(new_name)), args=[cst.Arg(size)])

    return build


def _packed(call: cst.Call, func: cst.Attribute, new_name: str) -> cst.Call:
    args = list(call.args)
    if len(args) > 1:
        elements = [cst.Element(a.value, comma=a.comma) for a in args]
        elements[-1] = elements[-1].with_changes(comma=cst.MaybeSentinel.DEFAULT)
        args = [cst.Arg(cst.Tuple(elements))]
    return call.with_changes(func=func.with_changes(attr=cst.Name(new_name)), args=args)
