"""GM602: what a wrapper's ``step`` override does with its inner step's result.

Which attributes hold the wrapped env itself (``self._env`` stored from the parameter
handed to the base's ``__init__``, so ``self._env.step`` is the inner step), whether the
inner ``done`` is a collection of per-agent flags (``all(done)``, ``done[i]``), whether a
line is the ``done = terminated or truncated`` the step family inserts, and whether the
override changes ``done`` anywhere but by its unpacks.

Separate from ``step.py`` because these read the override's lines alone (the ``ast``,
no plan and no rewrite); ``step.py`` holds the decision and the edits built from them.
"""

from __future__ import annotations

import ast

from gymmigrate.facts.module import FUNCTIONS
from gymmigrate.rules.step_done.common import StepUnpack
from gymmigrate.rules.wrappers.common import _assigned_names, _single_assign
from gymmigrate.rules.wrappers.step_ends import _is_initializer


def _reads_per_agent(expr: ast.expr, names: set[str]) -> bool:
    """``all(done)``, ``any(dones)``, ``done.values()``, ``done[i]`` or a comprehension over
    ``done``: the inner step's done (or flags) is a collection of per-agent flags."""
    def is_flag(node: ast.AST) -> bool:
        return isinstance(node, ast.Name) and node.id in names

    for node in ast.walk(expr):
        if isinstance(node, ast.Call):
            func = node.func
            if isinstance(func, ast.Name) and func.id in ("all", "any", "list", "sum", "len") and any(is_flag(a) for a in node.args):
                return True
            if isinstance(func, ast.Attribute) and func.attr in ("values", "items", "keys") and is_flag(func.value):
                return True
        elif isinstance(node, ast.Subscript) and is_flag(node.value):
            return True
        elif isinstance(node, ast.comprehension) and is_flag(node.iter):
            return True
    return False


def _reduces_per_agent(function: ast.AST, name: str, flags: set[str]) -> bool:
    """``done = all(done)`` (or ``any``, ``.values()``, a comprehension) somewhere in
    ``function``: ``name`` holds a reduction of the inner step's per-agent flags."""
    for node in ast.walk(function):
        if (
            isinstance(node, ast.Assign)
            and len(node.targets) == 1
            and isinstance(node.targets[0], ast.Name)
            and node.targets[0].id == name
            and _reads_per_agent(node.value, flags)
        ):
            return True
    return False


def _is_done_line(statement: ast.stmt, flags: tuple[str, str]) -> bool:
    """``done = terminated or truncated`` right after a five-target step unpack."""
    assign = _single_assign(statement)
    if assign is None or not isinstance(assign.targets[0], ast.Name):
        return False
    value = assign.value
    return (
        isinstance(value, ast.BoolOp)
        and isinstance(value.op, ast.Or)
        and len(value.values) == 2
        and all(isinstance(v, ast.Name) for v in value.values)
        and tuple(v.id for v in value.values if isinstance(v, ast.Name)) == flags  # all Names (above)
    )


def _has_other_assignments(
    lines: list[ast.stmt],
    name: str,
    done_line: ast.stmt | None,
    unpacks: dict[ast.stmt, StepUnpack | None],
    inserted: tuple[ast.Assign, StepUnpack] | None,
    flags: tuple[str, str] | None = None,
) -> bool:
    """Is ``name`` changed anywhere but by the unpack, its ``done = ...`` line or an initializer?"""
    seen_unpack = False
    for line in lines:
        if line in unpacks:
            seen_unpack = True
            noted = unpacks[line]
            # another unpack after which the step family keeps ``done`` too assigns it again,
            # unless it is a later inner step (``obs, _, done, _ = self.env.step(1)`` after a
            # lost life) binding ``name`` as its done together with the same two flags: then
            # ``name`` is still ``terminated or truncated`` of the step that ran last
            if noted is not None and noted.done_line is not None and (inserted is None or line is not inserted[0]):
                if name in _assigned_names(line) and not _rebinds_flags_with_done(line, noted, name, flags):
                    return True
            continue
        if line is done_line:
            continue
        if name not in _assigned_names(line):
            if isinstance(line, ast.AugAssign) and isinstance(line.target, ast.Name) and line.target.id == name:
                return True
            continue
        if not seen_unpack and _is_initializer(line, name):
            continue
        return True
    return False


def _rebinds_flags_with_done(line: ast.stmt, noted: StepUnpack, name: str, flags: tuple[str, str] | None) -> bool:
    """``line`` is a legacy inner-step unpack whose done target is ``name`` and which the step
    family split into the same two flags (``flags``) as the override's other unpacks."""
    assign = _single_assign(line)
    if assign is None or flags is None or noted.discarded:
        return False
    target = assign.targets[0]
    return (
        isinstance(target, (ast.Tuple, ast.List))
        and len(target.elts) == 4
        and isinstance(target.elts[2], ast.Name)
        and target.elts[2].id == name
        and name not in _assigned_names_except(target, 2)
        and (noted.names.terminated, noted.names.truncated) == flags
    )


def _assigned_names_except(target: ast.Tuple | ast.List, index: int) -> set[str]:
    return {e.id for i, e in enumerate(target.elts) if i != index and isinstance(e, ast.Name)}


def _inner_aliases(classdef: ast.ClassDef) -> frozenset[str]:
    """Attributes that hold the wrapped env itself: ``__init__`` hands its parameter to the
    base's ``__init__`` (``super().__init__(env)``, ``gym.Wrapper.__init__(self, env)``) and
    stores the same parameter (``self._env = env``), so ``self._env`` is ``self.env``."""
    init = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "__init__"), None)
    if init is None:
        return frozenset()
    handed: set[str] = set()
    stored: dict[str, str] = {}
    rebound: set[str] = set()
    for node in ast.walk(init):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "__init__":
            base = node.func.value
            args = node.args
            if isinstance(base, ast.Call) and isinstance(base.func, ast.Name) and base.func.id == "super":
                handed |= {a.id for a in args[:1] if isinstance(a, ast.Name)}
            elif args and isinstance(args[0], ast.Name) and args[0].id == "self":
                handed |= {a.id for a in args[1:2] if isinstance(a, ast.Name)}
        elif isinstance(node, ast.Assign):
            for target in node.targets:
                if isinstance(target, ast.Name):
                    rebound.add(target.id)
                elif (
                    isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self"
                    and isinstance(node.value, ast.Name)
                ):
                    stored[target.attr] = node.value.id
    written_elsewhere = {
        t.attr
        for method in classdef.body
        if isinstance(method, FUNCTIONS) and method is not init
        for n in ast.walk(method)
        if isinstance(n, ast.Assign)
        for t in n.targets
        if isinstance(t, ast.Attribute) and isinstance(t.value, ast.Name) and t.value.id == "self"
    }
    return frozenset(
        attr for attr, param in stored.items() if param in handed and param not in rebound and attr not in written_elsewhere
    )


def _alias_step(node: ast.AST | None, aliases: frozenset[str]) -> bool:
    """``self.<alias>.step(...)`` for an attribute ``_inner_aliases`` found."""
    return (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and node.func.attr == "step"
        and isinstance(node.func.value, ast.Attribute)
        and isinstance(node.func.value.value, ast.Name)
        and node.func.value.value.id == "self"
        and node.func.value.attr in aliases
    )
