"""GM504: a step whose returns, or whose done, come from another step.

``return self._observe()`` where the helper returns four values other code reads, a
helper that already returns five, and a done unpacked from an inner Gym env's step or
the base class's (``super().step(a)``), with or without the class's own ends of the task
added to it. ``step.py`` decides with them.
"""

from __future__ import annotations

import ast
from typing import NamedTuple

from gymmigrate.facts.env_classes import FunctionIndex, is_super_method_call
from gymmigrate.facts.limit_tests import own_task_end
from gymmigrate.facts.module import own_returns, walk
from gymmigrate.facts.step_calls import foreign_step
from gymmigrate.rules.custom_env.common import (
    ClassDecision,
    Method,
    inner_gym_env_call,
    tuple_len,
)
from gymmigrate.rules.custom_env.step_limits import class_data_ends, class_streaks

_UNPACKED_NAMES = ("obs", "reward", "terminated", "info")


def unpacked_helper_names(decision: ClassDecision, function: Method, ret: ast.Return) -> tuple[str, ...] | None:
    """``return self._observe(...)`` alone on its line, where every return of ``_observe``
    (a method of the class) is a 4-tuple literal: the names step unpacks it into (free in
    ``function``), or None."""
    call = ret.value
    if not (
        isinstance(call, ast.Call)
        and isinstance(call.func, ast.Attribute)
        and isinstance(call.func.value, ast.Name)
        and call.func.value.id == "self"
    ):
        return None
    helper = decision.methods.get(call.func.attr)
    if helper is None or helper is function:
        return None
    values = [r.value for r in own_returns(helper) if r.value is not None]
    if not values or any(tuple_len(v) != 4 for v in values):
        return None
    facts = decision.family.facts
    if ret.end_lineno is None or not 0 < ret.lineno <= ret.end_lineno <= len(facts.lines):
        return None
    # ast's columns count UTF-8 bytes
    if facts.lines[ret.lineno - 1].encode()[: ret.col_offset].strip():
        return None  # ``if x: return self._observe()``: not a statement of its own line
    rest = facts.lines[ret.end_lineno - 1].encode()[ret.end_col_offset or 0 :].strip()
    if rest and not rest.startswith(b"#"):
        return None  # ``return self._observe(); ...``
    used = {n.id for n in walk(function) if isinstance(n, ast.Name)}
    used |= {a.arg for a in walk(function) if isinstance(a, ast.arg)}
    names = []
    for name in _UNPACKED_NAMES:
        while name in used:
            name += "_"
        names.append(name)
    return tuple(names)


def returns_helper(ret: ast.Return, decision: ClassDecision, helpers: set[int]) -> bool:
    call = ret.value
    return (
        isinstance(call, ast.Call)
        and isinstance(call.func, ast.Attribute)
        and id(decision.methods.get(call.func.attr)) in helpers
    )


def returns_five_from_helper(ret: ast.Return, decision: ClassDecision) -> bool:
    """``return self._advance(a)`` where ``_advance`` already returns five values."""
    call = ret.value
    if not (isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute) and isinstance(call.func.value, ast.Name) and call.func.value.id == "self"):
        return False
    helper = decision.methods.get(call.func.attr)
    return helper is not None and any(tuple_len(r.value) == 5 for r in own_returns(helper))


def task_ends(decision: ClassDecision, index: FunctionIndex, name: str) -> list[ast.Assign]:
    """The lines that add the class's own end of the task to ``name`` (``own_task_end``:
    ``name = True`` in one branch of an ``if`` whose test is no step limit and whose other
    branch leaves ``name`` as it was, ``else: reward = -100; done = True``: the agent died;
    ``name = name or <test>`` whose test is no step limit); nothing where no line is one.
    The caller checks that every other assignment of ``name`` but one is such a line."""
    facts = decision.family.facts
    data_ends, streaks = class_data_ends(decision), class_streaks(decision)
    return [
        a  # type: ignore[misc]
        for a in index.of(ast.Assign)
        if own_task_end(a, name, facts.parent(a), data_ends, streaks) is not None
    ]


def unpacked_from_inner_step(decision: ClassDecision, index: FunctionIndex, name: str, besides: frozenset[int] = frozenset()) -> bool:
    """``name`` is bound once, as the done of ``obs, r, done, info = <step>`` where the step is
    an inner Gym env's (``self.env.step(a)``, or ``res = self.env.step(a)`` unpacked) or the
    base class's migrated one (``super().step(a)``): the step family unpacks five values there,
    as ``terminated``/``truncated`` (names the function must not use already)."""
    if any(isinstance(n, ast.Name) and n.id in ("terminated", "truncated") for n in index.of(ast.Name)):
        return False
    selection = decision.family.context.options.selection
    if selection is not None and not selection.allows("GM301"):
        return False  # the unpack stays a legacy one: so does this return's done
    value = _done_unpacked_from(index, name, besides)
    if value is None:
        return False
    named = decision.env.base_method_target(decision.classdef, value, "step")
    if named is not None or is_super_method_call(value, "step"):
        # five values after the run, and the step family unpacks them: both, or the return
        # would name flags the unpack never binds
        return decision.env.base_step_migrates(decision.classdef, named) is True and _step_family_unpacks_super(decision, value)
    return inner_gym_env_call(decision, value, "step")


def unpacked_from_foreign_step(decision: ClassDecision, index: FunctionIndex, name: str) -> ast.Call | None:
    """The ``self.sim.step(a, b)`` that ``name`` is unpacked from as its done, where that
    call is no Gym step (``facts/step_calls.py``): the step family leaves it as it is."""
    value = _done_unpacked_from(index, name)
    if isinstance(value, ast.Call) and foreign_step(value, decision.family.receivers, decision.family.facts):
        return value
    return None


def unknown_base_text(decision: ClassDecision, base: UnknownBase) -> str:
    if decision.env.base_step_migrates(decision.classdef, base.named):
        return f"the step family cannot tell that `{base.text}` is a Gym env"  # it leaves the unpack as it is
    return f"`{base.text}` is no env class this run holds"


def _step_family_unpacks_super(decision: ClassDecision, call: ast.expr) -> bool:
    """The step family takes ``super().step(a)`` here for a Gym env's (``super_kind``), so it
    unpacks five values: the same fact the two halves of the step body must share."""
    kind = decision.env.receivers.super_kind(call.func.value)  # type: ignore[attr-defined]
    return kind is not None and kind.is_gym


def _done_unpacked_from(index: FunctionIndex, name: str, besides: frozenset[int] = frozenset()) -> ast.expr | None:
    """What ``name`` is unpacked from as the done of ``obs, r, name, info = <value>``, its
    one binding but ``besides`` (``res = x.step(a)`` followed to the call); else None."""
    binders = [
        a
        for a in index.of(ast.Assign)
        for t in a.targets  # type: ignore[attr-defined]
        if isinstance(t, ast.Name) and t.id == name
        or isinstance(t, (ast.Tuple, ast.List)) and any(isinstance(e, ast.Name) and e.id == name for e in t.elts)
    ]
    binders = [a for a in binders if id(a) not in besides]  # the class's own task ends, judged by the caller
    others = [n for n in index.of(ast.AugAssign, ast.AnnAssign, ast.For) if isinstance(n.target, ast.Name) and n.target.id == name]  # type: ignore[attr-defined]
    if len(binders) != 1 or others:
        return None
    unpack = binders[0]
    target = unpack.targets[0] if len(unpack.targets) == 1 else None  # type: ignore[attr-defined]
    flags = unpack.value  # type: ignore[attr-defined]
    if isinstance(target, ast.Name) and isinstance(flags, ast.BoolOp) and isinstance(flags.op, ast.Or) and len(flags.values) == 2:
        # ``done = terminated or truncated`` after a five-name unpack (GM301's, seen again
        # when the run verifies its own output): the same done, from the same call.
        pair = [v.id for v in flags.values if isinstance(v, ast.Name)]
        unpacks = [
            a
            for a in index.of(ast.Assign)
            if len(a.targets) == 1  # type: ignore[attr-defined]
            and isinstance(a.targets[0], (ast.Tuple, ast.List))  # type: ignore[attr-defined]
            and len(a.targets[0].elts) == 5  # type: ignore[attr-defined]
            and [e.id if isinstance(e, ast.Name) else None for e in a.targets[0].elts[2:4]] == pair  # type: ignore[attr-defined]
        ]
        return unpacks[0].value if len(unpacks) == 1 else None  # type: ignore[attr-defined]
    if not (
        isinstance(target, (ast.Tuple, ast.List))
        and len(target.elts) == 4
        and isinstance(target.elts[2], ast.Name)
        and target.elts[2].id == name
    ):
        return None
    value = unpack.value  # type: ignore[attr-defined]
    if isinstance(value, ast.Name):  # ``res = self.env.step(a)`` then ``... = res``
        stores = [a for a in index.of(ast.Assign) if any(isinstance(t, ast.Name) and t.id == value.id for t in a.targets)]  # type: ignore[attr-defined]
        if len(stores) != 1:
            return None
        value = stores[0].value  # type: ignore[attr-defined]
    return value


class UnknownBase(NamedTuple):
    """The base step a done is unpacked from, where the run cannot show what it returns."""

    call: str  # ``super().step(...)`` / ``Base.step(...)``, for the report
    text: str  # the class as written
    named: ast.expr | None  # the class ``Base.step(self, a)`` names; None for ``super()``


def from_unknown_base_step(decision: ClassDecision, index: FunctionIndex, name: str) -> UnknownBase | None:
    """``name`` is the done of ``super().step(a)`` or ``Base.step(self, a)`` (or that done
    with the class's own task ends) where the run does not show what the base it reaches
    returns once migrated: that base, else None."""
    ends = frozenset(id(e) for e in task_ends(decision, index, name))
    value = _done_unpacked_from(index, name, ends)
    if value is None:
        return None
    target = decision.env.base_method_target(decision.classdef, value, "step")
    if target is None:
        return None
    named = None if is_super_method_call(value, "step") else target
    if decision.env.base_step_migrates(decision.classdef, named) and _step_family_unpacks_super(decision, value):
        return None
    facts = decision.family.facts
    if named is not None:
        return UnknownBase(f"{facts.segment(named)}.step(...)", facts.segment(named), named)
    return UnknownBase("super().step(...)", facts.segment(target), None)


def single_assignment(index: FunctionIndex, name: str) -> ast.AST | None:
    assigns = [
        a for a in index.of(ast.Assign) if len(a.targets) == 1 and isinstance(a.targets[0], ast.Name) and a.targets[0].id == name  # type: ignore[attr-defined]
    ]
    others = [
        n
        for n in index.of(ast.AugAssign, ast.AnnAssign, ast.For)
        if isinstance(n.target, ast.Name) and n.target.id == name  # type: ignore[attr-defined]
    ]
    in_tuple = any(
        isinstance(t, ast.Tuple) and any(isinstance(e, ast.Name) and e.id == name for e in t.elts)
        for a in index.of(ast.Assign)
        for t in a.targets  # type: ignore[attr-defined]
    )
    if len(assigns) != 1 or others or in_tuple:
        return None
    return assigns[0].value  # type: ignore[attr-defined]
