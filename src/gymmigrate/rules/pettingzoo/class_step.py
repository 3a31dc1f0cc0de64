"""PZ104 in custom parallel env classes: ``step`` returns five dicts.

A parallel env's own ``step`` returns ``terminations`` and ``truncations`` where it
returned ``dones`` (PettingZoo 1.21). An empty dict returns two; a local ``dones`` is split
store by store by its causes (``dones_split.py``), or by what the simulation it is
unpacked from can end with (``inner_dones.py``), and its reads read both; ``self.dones``
returns both stores when every store of the class was split (``env_classes.py``). What is
left is one question for the class.
"""

from __future__ import annotations

import ast
from functools import partial
from typing import TYPE_CHECKING

from gymmigrate.facts.flow import Flow
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import own_returns
from gymmigrate.findings import FixKind
from gymmigrate.rules.pettingzoo.dones_split import DonesSplit, is_empty_dict
from gymmigrate.rules.pettingzoo.inner_dones import (
    dones_question,
    inner_step_unpack,
    plan_inner_dones,
    settled,
    trailing_dels,
)

if TYPE_CHECKING:
    from gymmigrate.rules.pettingzoo.env_classes import EnvClasses


def plan_parallel_step(family: EnvClasses, classdef: ast.ClassDef, step: ast.FunctionDef | ast.AsyncFunctionDef) -> None:
    scope = family.facts.scopes[step]
    if "terminations" in scope.bindings or "truncations" in scope.bindings:
        return  # already migrated
    names: set[str] = set()  # the local dicts split already (two returns may hand one back)
    for returned in own_returns(step):
        value = returned.value
        if not (isinstance(value, ast.Tuple) and len(value.elts) == 4):
            continue
        dones = value.elts[2]
        if isinstance(dones, ast.Dict) and not dones.keys:
            family.split_target(value, 2, "{}", "{}")
            family.report(returned, "PZ104", "a parallel `step` returns five dicts since PettingZoo 1.21", FixKind.AUTO)
            continue
        if isinstance(dones, ast.Name) and _unpacked_from_step(family, scope.bindings.get(dones.id, [])):
            continue  # ``obs, rewards, dones, infos = self.env.step(...)``: parallel.py passes both on
        if isinstance(dones, ast.Name) and dones.id in scope.bindings and (
            dones.id in names or _local_dones(family, classdef, step, dones.id)
        ):
            names.add(dones.id)
            family.split_target(value, 2, "terminations", "truncations")
            family.report(returned, "PZ104", "a parallel `step` returns terminations and truncations since PettingZoo "
                        "1.21", FixKind.AUTO)
        elif _split_self_dones(family, classdef, dones):
            # every store of ``self.dones`` in the class went to one dict, with the other beside it
            family.split_target(value, 2, "self.terminations", "self.truncations")
            family.report(returned, "PZ104", "a parallel `step` returns terminations and truncations since PettingZoo "
                        "1.21", FixKind.AUTO)
        else:
            family.report(returned, "PZ104", "a parallel `step` returns five dicts since PettingZoo 1.21: split "
                        f"`{family.facts.segment(dones)}` into terminations and truncations", FixKind.FLAG,
                        question=dones_question(classdef))

def _split_self_dones(family: EnvClasses, classdef: ast.ClassDef, dones: ast.expr) -> bool:
    return (
        isinstance(dones, ast.Attribute) and dones.attr == "dones"
        and isinstance(dones.value, ast.Name) and family.receivers.is_self(dones.value)
        and id(classdef) in family.classes_dones_split and id(classdef) not in family.classes_dones_left
    )

def _local_dones(family: EnvClasses, classdef: ast.ClassDef, step: ast.FunctionDef | ast.AsyncFunctionDef, name: str) -> bool:
    """Split the local ``dones`` of a parallel ``step``: each whole store and item store by
    its causes, each read of both dicts. False (nothing planned) when a binding is not a
    plain ``dones = ...``."""
    scope = family.facts.scopes[step]
    bindings = [b for b in scope.bindings[name] if isinstance(b, ast.Name)]
    # ``obs, rews, dones, infos = self.<held>.step(actions)``: the dones of what the env drives
    unpacks = {id(b): u for b in bindings if (u := inner_step_unpack(family, b)) is not None and family.multi_agent.kind(u[1]) is None}
    if len(bindings) != len(scope.bindings[name]) or not all(
        id(b) in unpacks or _plain_assign(family.facts.parent(b), b) for b in bindings
    ):
        return False
    dels = {id(b): trailing_dels(family, unpacks[id(b)][0], name) for b in bindings if id(b) in unpacks}
    unsettled = [b for b in bindings if id(b) in unpacks and settled(family, *unpacks[id(b)], dels[id(b)])[0] is None]
    for binding in unsettled or [b for b in bindings if id(b) in unpacks]:
        # an unsettled unpack is asked about there, and nothing of the step is planned
        plan_inner_dones(family, classdef, *unpacks[id(binding)], name, partial(family.rename, binding), dels[id(binding)])
    if unsettled:
        return False
    taken = {id(target.value) for found in dels.values() for statement in found for target in statement.targets}  # type: ignore[attr-defined]
    flow = Flow.of(family.facts)
    reads = [r for r in {id(r): r for b in bindings for r in flow.reads(b)}.values() if id(r) not in taken]
    bindings = [b for b in bindings if id(b) not in unpacks]
    empty = any(is_empty_dict(family.facts.parent(b).value) for b in bindings)  # type: ignore[union-attr]
    splits: list[DonesSplit] = []
    item_stores: list[tuple[ast.Assign, ast.Subscript, DonesSplit]] = []
    other_reads: list[ast.Name] = []
    # An unpack at the top of the step binds both dicts before any later store: such a
    # store keeps an agent that terminated on the step terminated, as ``self.dones`` does.
    bound = [unpacks[key][0] for key in unpacks if unpacks[key][0] in step.body]
    for binding in bindings:
        split = DonesSplit(family, classdef, "terminations", "truncations", partial(family.rename, binding), empty)
        splits.append(split)
        store = family.facts.parent(binding)
        owned = any(assign.lineno < binding.lineno for assign in bound)
        split.whole(store, owned=owned)  # type: ignore[arg-type]
    for read in reads:
        subscript = family.facts.parent(read)
        statement = family.facts.parent(subscript) if subscript is not None else None
        if (
            isinstance(subscript, ast.Subscript) and subscript.value is read and isinstance(subscript.ctx, ast.Store)
            and isinstance(statement, ast.Assign) and statement.targets == [subscript]
        ):
            split = DonesSplit(family, classdef, "terminations", "truncations", partial(family.rename, read), empty)
            item_stores.append((statement, subscript, split))
            split.item(statement, subscript)
            splits.append(split)
        else:
            other_reads.append(read)
    limited = any(split.limited for split in splits)
    for read in other_reads:
        parent = family.facts.parent(read)
        if _is_returned(family, read):
            continue
        if not limited:
            family.rename(read, "terminations")
        elif isinstance(parent, ast.Subscript) and parent.value is read and isinstance(parent.ctx, ast.Load):
            family.read_both(parent, "terminations", "truncations")
        elif not family.aggregate_both(read, "terminations", "truncations"):
            family.rename(read, "terminations")
            family.report(read, "PZ104", f"`{name}` is split into terminations and truncations: this use reads only "
                        "the terminations; check it", FixKind.ASSIST)
    return True

def _is_returned(family: EnvClasses, read: ast.Name) -> bool:
    holder = family.facts.parent(read)
    return isinstance(holder, ast.Tuple) and isinstance(family.facts.parent(holder), ast.Return) and len(holder.elts) == 4 \
        and holder.elts[2] is read

def _unpacked_from_step(family: EnvClasses, bindings: list[ast.AST]) -> bool:
    for binding in bindings:
        holder = family.facts.parent(binding)
        assign = family.facts.parent(holder) if isinstance(holder, (ast.Tuple, ast.List)) else None
        if isinstance(assign, ast.Assign) and isinstance(assign.value, ast.Call):
            func = assign.value.func
            if isinstance(func, ast.Attribute) and func.attr == "step":
                return family.multi_agent.kind(func.value) is EnvKind.PZ_PARALLEL
    return False

def _plain_assign(statement: ast.AST | None, target: ast.AST) -> bool:
    return isinstance(statement, ast.Assign) and statement.targets == [target]
