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

import libcst as cst
import libcst.matchers as m
from libcst.helpers import get_full_name_for_node
from libcst.metadata import Assignment, PositionProvider

from gymmigrate.analysis import env_classes as E
from gymmigrate.analysis import names as N
from gymmigrate.analysis.decisions import receiver_text
from gymmigrate.analysis.receivers import METADATA, EnvKind, ReceiverAnalysis
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileProfile, Rule, RulePass

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


class RngPass(RulePass):
    RULES = RULES
    ORDER = 45
    METADATA_DEPENDENCIES = (PositionProvider, *METADATA)

    @classmethod
    def applies_to(cls, source: str, profile: FileProfile) -> bool:
        return "np_random" in source or "seeding" in source

    def visit_Module(self, node: cst.Module) -> None:
        self.analysis = ReceiverAnalysis(node, self.metadata)
        self._noted_stream = False

    # -- GM505 / GM901 ---------------------------------------------------------------------

    def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.BaseExpression:
        func = original_node.func
        if not isinstance(func, cst.Attribute) or func.attr.value not in RNG_METHODS:
            return updated_node
        verdict = self._rng_receiver(func.value)
        if verdict is None:
            return updated_node
        code, kind, why = verdict
        method = func.attr.value
        if kind is FixKind.FLAG:
            self.report(original_node, code, f"np_random.{method}(...) is RandomState API; {why}: if it is, use the Generator method", FixKind.FLAG)
            return updated_node
        new_func = updated_node.func
        assert isinstance(new_func, cst.Attribute)
        rewritten: cst.BaseExpression | None = None
        message = ""
        if method in RENAMED:
            rewritten = updated_node.with_changes(func=new_func.with_changes(attr=cst.Name(RENAMED[method])))
            message = f"np_random.{method}(...) -> np_random.{RENAMED[method]}(...)"
        elif method == "random_integers":
            rewritten = _inclusive_integers(updated_node, new_func)
            message = "np_random.random_integers(lo, hi) -> np_random.integers(lo, hi, endpoint=True) (both ends inclusive)"
        elif method in PACKED_SIZE:
            new_name = PACKED_SIZE[method]
            if any(a.star or a.keyword is not None for a in updated_node.args):
                self.report(original_node, code, f"np_random.{method}(*dims) takes one size tuple as Generator.{new_name}(size); rewrite by hand", FixKind.FLAG)
                return updated_node
            rewritten = _packed(updated_node, new_func, new_name)
            message = f"np_random.{method}(...) -> np_random.{new_name}(...)"
            if len(updated_node.args) > 1:
                message = f"np_random.{method}(d0, d1, ...) -> np_random.{new_name}((d0, d1, ...)): the dimensions became one size tuple"
                kind = FixKind.ASSIST if kind is FixKind.AUTO else kind
        elif method == "get_state" and not updated_node.args:
            rewritten = cst.Attribute(value=cst.Attribute(value=new_func.value, attr=cst.Name("bit_generator")), attr=cst.Name("state"))
            message = "np_random.get_state() -> np_random.bit_generator.state: the state is now a dict, not the MT19937 tuple"
            kind = FixKind.ASSIST if kind is FixKind.AUTO else kind
        elif method in NO_EQUIVALENT or method in ("get_state", "set_state"):
            if method == "set_state" and self._is_statement(original_node):
                return updated_node  # leave_Expr rewrites the whole statement
            reason = NO_EQUIVALENT.get(method, "set the state with `np_random.bit_generator.state = state` as a statement")
            self.report(original_node, code, f"np_random.{method}(...) on a Generator: {reason}", FixKind.FLAG)
            return updated_node
        if rewritten is None:
            return updated_node
        if kind is not FixKind.AUTO and why:
            message = f"{message}; {why}"
        self.report(original_node, code, message, kind)
        self._note_stream(original_node, code)
        return rewritten

    def leave_Expr(self, original_node: cst.Expr, updated_node: cst.Expr) -> cst.BaseSmallStatement:
        call = original_node.value
        if not m.matches(call, m.Call(func=m.Attribute(attr=m.Name("set_state")), args=[m.Arg(keyword=None, star="")])):
            return updated_node
        verdict = self._rng_receiver(call.func.value)  # type: ignore[attr-defined]
        new_call = updated_node.value
        if verdict is None or not isinstance(new_call, cst.Call) or not isinstance(new_call.func, cst.Attribute):
            return updated_node
        code, kind, _ = verdict
        target = cst.Attribute(value=cst.Attribute(value=new_call.func.value, attr=cst.Name("bit_generator")), attr=cst.Name("state"))
        self.report(call, code, "np_random.set_state(s) -> np_random.bit_generator.state = s: the state must be a PCG64 state dict now", FixKind.ASSIST)
        self._note_stream(call, code)
        return cst.Assign(targets=[cst.AssignTarget(target)], value=new_call.args[0].value)

    def _is_statement(self, call: cst.Call) -> bool:
        return isinstance(self.analysis.parent(call), cst.Expr)

    def _note_stream(self, node: cst.CSTNode, code: str) -> None:
        if not self._noted_stream:
            self._noted_stream = True
            self.report(node, code, STREAM_NOTE, FixKind.FLAG)

    # -- which receivers are Generators ---------------------------------------------------------

    def _rng_receiver(self, receiver: cst.BaseExpression) -> tuple[str, FixKind, str] | None:
        """(rule, fix kind, reason) when ``receiver`` is a gym RNG; None to leave the call alone."""
        if isinstance(receiver, cst.Attribute) and receiver.attr.value == "np_random":
            return self._np_random_owner(receiver.value)
        if isinstance(receiver, cst.Name) and self._name_from_seeding(receiver):
            return "GM505", FixKind.AUTO, ""
        if m.matches(receiver, m.Attribute(value=m.Name("self"))) and self._self_attribute_from_seeding(receiver):  # type: ignore[arg-type]
            return "GM505", FixKind.AUTO, ""
        if m.matches(receiver, m.Subscript(value=m.Call())) and self._seeding_first(receiver):
            return "GM505", FixKind.AUTO, ""
        return None

    def _np_random_owner(self, owner: cst.BaseExpression) -> tuple[str, FixKind, str] | None:
        text = receiver_text(owner)
        if _names_a_space(owner):
            return "GM901", FixKind.AUTO, ""
        if isinstance(owner, cst.Name) and owner.value == "self":
            return self._self_np_random(owner)
        kind = self.analysis.kind_of(owner)
        if kind in (EnvKind.GYM_ENV, EnvKind.GYM_VEC, EnvKind.PZ_AEC, EnvKind.PZ_PARALLEL):
            return "GM505", FixKind.AUTO, ""
        if kind is EnvKind.UNKNOWN and (self.context.profile.imports_gym or self.context.profile.imports_gymnasium):
            return "GM505", FixKind.ASSIST, f"could not trace where `{text}` comes from; every gym/gymnasium np_random is a Generator"
        return None

    def _self_np_random(self, node: cst.Name) -> tuple[str, FixKind, str] | None:
        classdef = self.analysis.enclosing(node, cst.ClassDef)
        if not isinstance(classdef, cst.ClassDef):
            return None
        stores = _self_stores(classdef, "np_random") + _self_stores(classdef, "_np_random")
        if any(_is_random_state(value) for value in stores):
            return None  # np.random.RandomState(seed): still the legacy API (GUARD)
        gym_file = self.context.profile.imports_gym or self.context.profile.imports_gymnasium
        if all(E.is_seeding_np_random(self.analysis, value) for value in stores):
            if stores or E.is_custom_env_class(self.analysis, classdef) or self.analysis.class_kind(classdef).is_gym:
                return "GM505", FixKind.AUTO, ""
            if gym_file:
                return "GM505", FixKind.ASSIST, "this class's np_random is inherited from a base the module does not define; it is a Generator if that base is a gym/gymnasium class"
            return None
        if gym_file:
            return "GM505", FixKind.FLAG, "self.np_random is set from a value this module does not create (an env's np_random passed in is a Generator now)"
        return None

    def _name_from_seeding(self, name: cst.Name) -> bool:
        scope = self.analysis.scope_of(name)
        if scope is None:
            return False
        assignments = [a for a in scope[name.value] if isinstance(a, Assignment)]  # type: ignore[index]
        return bool(assignments) and all(self._binding_from_seeding(a.node) for a in assignments)

    def _binding_from_seeding(self, target: cst.CSTNode) -> bool:
        parent = self.analysis.parent(target)
        if isinstance(parent, cst.AssignTarget):
            assign = self.analysis.parent(parent)
            return isinstance(assign, cst.Assign) and self._seeding_first(assign.value)
        if isinstance(parent, cst.Element):
            container = self.analysis.parent(parent)
            holder = self.analysis.parent(container) if container is not None else None
            if isinstance(container, (cst.Tuple, cst.List)) and container.elements and container.elements[0] is parent:
                assign = self.analysis.parent(holder) if isinstance(holder, cst.AssignTarget) else None
                return isinstance(assign, cst.Assign) and E.is_seeding_np_random(self.analysis, assign.value)
        return False

    def _seeding_first(self, value: cst.BaseExpression) -> bool:
        """``seeding.np_random(s)[0]``."""
        return (
            isinstance(value, cst.Subscript)
            and E.is_seeding_np_random(self.analysis, value.value)
            and len(value.slice) == 1
            and m.matches(value.slice[0].slice, m.Index(m.Integer("0")))
        )

    def _self_attribute_from_seeding(self, attr: cst.Attribute) -> bool:
        classdef = self.analysis.enclosing(attr, cst.ClassDef)
        if not isinstance(classdef, cst.ClassDef):
            return False
        stores = _self_stores(classdef, attr.attr.value)
        return bool(stores) and all(E.is_seeding_np_random(self.analysis, v) or self._seeding_first(v) for v in stores)

    # -- GM506 -------------------------------------------------------------------------------------

    def visit_Attribute(self, node: cst.Attribute) -> None:
        self._check_removed_helper(node)

    def visit_Name(self, node: cst.Name) -> None:
        parent = self.analysis.parent(node)
        if isinstance(parent, cst.Attribute) or self.analysis.enclosing(node, cst.ImportFrom) is not None:
            return
        self._check_removed_helper(node)

    def _check_removed_helper(self, node: cst.BaseExpression) -> None:
        for q in self.analysis.qualified_names(node):
            rest = N.strip_gym_prefix(q)
            if rest is not None and rest.startswith("utils.seeding.") and rest.rsplit(".", 1)[-1] in REMOVED_SEEDING:
                helper = rest.rsplit(".", 1)[-1]
                self.report(node, "GM506", f"seeding.{helper} was removed in gym 0.26: derive seeds with np.random.SeedSequence or draw from np_random")
                return


def _is_random_state(value: cst.BaseExpression) -> bool:
    return isinstance(value, cst.Call) and (get_full_name_for_node(value.func) or "").endswith("RandomState")


def _names_a_space(owner: cst.BaseExpression) -> bool:
    last = owner.attr.value if isinstance(owner, cst.Attribute) else owner.value if isinstance(owner, cst.Name) else ""
    return last == "space" or last.endswith("_space") or last.endswith("_spaces")


def _self_stores(classdef: cst.ClassDef, attribute: str) -> list[cst.BaseExpression]:
    """Values assigned to ``self.<attribute>``, including the first slot of a tuple unpack."""
    values: list[cst.BaseExpression] = []
    target = m.Attribute(value=m.Name("self"), attr=m.Name(attribute))
    for assign in m.findall(classdef, m.Assign()):
        for t in assign.targets:  # type: ignore[attr-defined]
            if m.matches(t.target, target):
                values.append(assign.value)  # type: ignore[attr-defined]
            elif isinstance(t.target, (cst.Tuple, cst.List)) and any(m.matches(el.value, target) for el in t.target.elements):
                values.append(assign.value)  # type: ignore[attr-defined]
    return values


def _inclusive_integers(call: cst.Call, func: cst.Attribute) -> cst.Call:
    args = list(call.args)
    positional = [a for a in args if a.keyword is None]
    if len(positional) == 1 and not any(m.matches(a.keyword, m.Name("high")) for a in args):
        # random_integers(n) draws from [1, n]
        args.insert(0, cst.Arg(cst.Integer("1")))
    if args:
        args[-1] = args[-1].with_changes(comma=cst.MaybeSentinel.DEFAULT)
    args.append(cst.Arg(cst.Name("True"), keyword=cst.Name("endpoint"), equal=cst.AssignEqual(cst.SimpleWhitespace(""), cst.SimpleWhitespace(""))))
    return call.with_changes(func=func.with_changes(attr=cst.Name("integers")), args=args)


def _packed(call: cst.Call, func: cst.Attribute, new_name: str) -> cst.Call:
    args = list(call.args)
    if len(args) > 1:
        elements = [cst.Element(a.value, comma=a.comma) for a in args]
        elements[-1] = elements[-1].with_changes(comma=cst.MaybeSentinel.DEFAULT)
        args = [cst.Arg(cst.Tuple(elements))]
    return call.with_changes(func=func.with_changes(attr=cst.Name(new_name)), args=args)
