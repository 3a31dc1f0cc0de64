"""GM504: a step whose done is built from the per-agent dones of a PettingZoo parallel step.

A Gym env class that drives a parallel env (``obs, rew, done, info = self.pz.step(acts)``)
and returns its agents' flags as one array (``flags = np.stack([done["a"], done["b"]])``)
gets, since PettingZoo 1.21, a ``terminations`` and a ``truncations`` dict from that step
(PZ104). The same construction over each dict is this step's terminated and truncated:
``done, False`` would fold the parallel env's own cut (``max_cycles``) into terminated.
Only constructions that keep each agent's flag in its own place split that way (stacking,
lists, tuples, arrays); ``all()`` or ``and`` of the flags does not, and is left as before.
"""

from __future__ import annotations

import ast
from typing import NamedTuple

from gymmigrate.facts.env_classes import FunctionIndex
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import ModuleFacts, walk
from gymmigrate.facts.multi_agent import MultiAgent
from gymmigrate.rules.custom_env.common import ClassDecision
from gymmigrate.rules.custom_env.step_delegates import single_assignment

# What the parallel step's unpack is renamed to (PZ104, ``rules/pettingzoo/parallel.py``).
TERMINATIONS, TRUNCATIONS = "terminations", "truncations"

# Calls that put each element where it was: a flag of one agent stays that agent's.
_ELEMENTWISE = frozenset({"stack", "array", "asarray", "hstack", "vstack", "concatenate", "list", "tuple"})
# Nodes that only arrange the flags (and the keys they are read with).
_ARRANGING = (
    ast.List, ast.Tuple, ast.Constant, ast.Name, ast.Attribute, ast.Subscript, ast.Call, ast.keyword,
    ast.ListComp, ast.comprehension, ast.expr_context, ast.Slice,
)


class PerAgentSplit(NamedTuple):
    """``name = <construction>`` of the parallel step's per-agent dones, as terminated and
    as truncated."""

    name: str
    terminated: str
    truncated: str


def per_agent_split(decision: ClassDecision, index: FunctionIndex, done: ast.expr) -> PerAgentSplit | None:
    """The split of a returned done that is an arrangement of the per-agent dones of a
    PettingZoo parallel step unpacked in the same function (``done["a"]``), or a name
    assigned once from one (``name`` is then that name, else ""); else None."""
    if any(isinstance(n, ast.Name) and n.id in ("terminated", "truncated") for n in index.of(ast.Name)):
        return None
    selection = decision.family.context.options.selection
    if selection is not None and not selection.allows("PZ104"):
        return None  # the parallel unpack stays a four-value one: there are no two dicts to read
    name = ""
    value: ast.AST | None = done
    if isinstance(done, ast.Name):
        name, value = done.id, single_assignment(index, done.id)
    if not isinstance(value, ast.expr):
        return None
    split = _split(decision, index, value)
    return None if split is None else PerAgentSplit(name, *split)


def _split(decision: ClassDecision, index: FunctionIndex, value: ast.expr) -> tuple[str, str] | None:
    facts = decision.family.facts
    dones = _parallel_dones(decision, index, value)
    if dones is None:
        return None
    # What reads no flag: the callee (``np.stack``), an agent's key, a comprehension's
    # loop, a keyword (``axis=0``). Any other name would be one value in both flags.
    aside = {
        id(node)
        for part in walk(value)
        for side in _aside(part, dones)
        for node in walk(side)
    }
    reads: list[ast.Name] = []
    for node in walk(value):
        if isinstance(node, ast.Name) and node.id != dones and id(node) not in aside:
            return None
        if not isinstance(node, _ARRANGING):
            return None
        if isinstance(node, ast.Call) and _callee(node.func) not in _ELEMENTWISE:
            return None
        if isinstance(node, ast.comprehension) and (node.ifs or node.is_async):
            return None  # a filter moves the agents' flags out of their places
        if isinstance(node, ast.Name) and node.id == dones:
            parent = facts.parent(node)
            if not (isinstance(parent, ast.Subscript) and parent.value is node and isinstance(parent.ctx, ast.Load)):
                return None  # the whole dict (``done.values()``, ``done``): no one flag per place
            reads.append(node)
    if not reads:
        return None
    return _renamed(facts, value, reads, TERMINATIONS), _renamed(facts, value, reads, TRUNCATIONS)


def reads_parallel_dones(decision: ClassDecision, index: FunctionIndex, done: ast.expr) -> bool:
    """A returned done that reads the per-agent dones of a PettingZoo parallel step unpacked
    in the function (or a name assigned once from them), however it combines them."""
    value = single_assignment(index, done.id) if isinstance(done, ast.Name) else done
    return isinstance(value, ast.expr) and _parallel_dones(decision, index, value) is not None


def _parallel_dones(decision: ClassDecision, index: FunctionIndex, value: ast.expr) -> str | None:
    """The done name of ``obs, rew, done, info = <parallel env>.step(...)`` in the function,
    bound only there, that ``value`` reads; else None."""
    family = decision.family
    names = {n.id for n in walk(value) if isinstance(n, ast.Name)}
    found = None
    for assign in index.of(ast.Assign):
        targets = assign.targets  # type: ignore[attr-defined]
        call = assign.value  # type: ignore[attr-defined]
        if not (
            len(targets) == 1
            and isinstance(targets[0], (ast.Tuple, ast.List))
            and len(targets[0].elts) == 4
            and isinstance(targets[0].elts[2], ast.Name)
            and targets[0].elts[2].id in names
            and isinstance(call, ast.Call)
            and isinstance(call.func, ast.Attribute)
            and call.func.attr == "step"
        ):
            continue
        if MultiAgent.of(family.facts, family.receivers).kind(call.func.value) is not EnvKind.PZ_PARALLEL:
            continue
        if found is not None:
            return None
        found = targets[0].elts[2].id
    if found is None or _bindings(index, found) != 1:
        return None
    return found


def _bindings(index: FunctionIndex, name: str) -> int:
    stores = [n for n in index.of(ast.Name) if isinstance(n, ast.Name) and n.id == name and isinstance(n.ctx, (ast.Store, ast.Del))]
    params = [a for a in index.of(ast.arg) if isinstance(a, ast.arg) and a.arg == name]
    return len(stores) + len(params)


def _aside(node: ast.AST, dones: str) -> list[ast.AST]:
    if isinstance(node, ast.Call):
        return [node.func, *node.keywords]
    if isinstance(node, ast.Subscript) and isinstance(node.value, ast.Name) and node.value.id == dones:
        return [node.slice]
    if isinstance(node, ast.comprehension):
        return [node.target, node.iter, *node.ifs]
    return []


def _callee(func: ast.expr) -> str | None:
    if isinstance(func, ast.Name):
        return func.id
    if isinstance(func, ast.Attribute):
        return func.attr
    return None


def _renamed(facts: ModuleFacts, value: ast.expr, reads: list[ast.Name], new: str) -> str:
    """The source of ``value`` with each of ``reads`` spelled ``new``."""
    start = facts.offset(value.lineno, value.col_offset)
    end = facts.offset(value.end_lineno or value.lineno, value.end_col_offset or 0)
    text, cursor, pieces = facts.text, start, []
    for read in sorted(reads, key=lambda n: (n.lineno, n.col_offset)):
        begin = facts.offset(read.lineno, read.col_offset)
        pieces += [text[cursor:begin], new]
        cursor = facts.offset(read.end_lineno or read.lineno, read.end_col_offset or 0)
    pieces.append(text[cursor:end])
    return "".join(pieces)
