"""Carry out a ``Plan`` on the LibCST tree of the same source, in one traversal.

Edits are addressed by ``ast`` nodes; ``gymmigrate.edits.locate`` finds their LibCST
counterparts without position metadata. The traversal only enters the statements that
hold an edit, so applying costs little more than printing.
"""

from __future__ import annotations

import ast
from collections import defaultdict
from collections.abc import Callable
from typing import Any, cast

import libcst as cst

from gymmigrate.edits.locate import (
    ApplyError,
    BlockTable,
    Located,
    block_of,
    locate_expression,
    locate_statement,
    statement_path,
)
from gymmigrate.edits.plan import Plan

__all__ = ["ApplyError", "apply_plan"]


# -- the one traversal ---------------------------------------------------------------------


class _Applier(cst.CSTTransformer):
    def __init__(self) -> None:
        super().__init__()
        self.enter: set[int] = set()  # nodes on a path to an edit
        self.builds: dict[int, list[Any]] = defaultdict(list)
        self.before: dict[int, list[cst.CSTNode]] = defaultdict(list)
        self.after: dict[int, list[cst.CSTNode]] = defaultdict(list)
        self.removed: set[int] = set()
        self.leading: dict[int, list[cst.EmptyLine]] = defaultdict(list)  # comment lines moved here

    def mark(self, chain: list[cst.CSTNode]) -> None:
        self.enter.update(id(node) for node in chain)

    def on_visit(self, node: cst.CSTNode) -> bool:
        return id(node) in self.enter

    def on_leave(self, original_node: cst.CSTNode, updated_node: cst.CSTNode) -> Any:
        key = id(original_node)
        result: Any = updated_node
        for build in self.builds.get(key, ()):
            result = build(result)
        if key in self.removed:
            result = cst.RemovalSentinel.REMOVE
        before, after = self.before.get(key), self.after.get(key)
        carried = self.leading.get(key)
        if carried and result is not cst.RemovalSentinel.REMOVE:
            if before:
                # Comment lines are carried only to whole statements, never to small ones.
                first = cast("cst.SimpleStatementLine | cst.BaseCompoundStatement", before[0])
                before = [first.with_changes(leading_lines=[*carried, *first.leading_lines]), *before[1:]]
            elif hasattr(result, "leading_lines"):
                result = result.with_changes(leading_lines=[*carried, *result.leading_lines])
        if before or after:
            kept = [] if result is cst.RemovalSentinel.REMOVE else [result]
            result = cst.FlattenSentinel([*(before or ()), *kept, *(after or ())])
        return result


def _new_statements(code: list[Any], small: bool) -> list[cst.CSTNode]:
    """Parse new code for insertion as whole lines, or as small statements on one line.
    An item is source text, a LibCST node, or a function that builds one (so that a rule
    deciding in ``check`` never loads LibCST)."""
    nodes: list[cst.CSTNode] = []
    for item in code:
        node = cst.parse_statement(item) if isinstance(item, str) else item() if callable(item) else item
        if small:
            if isinstance(node, cst.SimpleStatementLine):
                nodes.extend(node.body)
            elif isinstance(node, cst.BaseSmallStatement):
                nodes.append(node)
            else:
                raise ApplyError("a compound statement cannot join a line of simple statements")
        else:
            if isinstance(node, cst.BaseSmallStatement):
                node = cst.SimpleStatementLine(body=[node])
            nodes.append(node)
    return nodes


def apply_plan(module: cst.Module, plan: Plan, window: tuple[int, int] | None = None) -> cst.Module:
    """Return ``module`` with every edit of ``plan`` carried out.

    With ``window=(first, stop)``, ``module`` holds only the top-level statements
    ``first..stop-1`` of the file (``gymmigrate.edits.splice``): only their edits are
    carried out, and paths are counted from ``first``.
    """
    facts = plan.facts
    applier = _Applier()
    located_cache: dict[ast.stmt, Located] = {}
    places: dict[ast.AST, tuple[str, int]] = {}
    candidates: dict = {}  # (statement, kind) -> both sides' candidates
    tables: dict[tuple[int, str], tuple[list[cst.CSTNode], BlockTable]] = {}
    paths: dict[ast.stmt, list[tuple[str, int]]] = {}

    def path_of(statement: ast.stmt) -> list[tuple[str, int]]:
        path = paths.get(statement)
        if path is None:
            path = paths[statement] = statement_path(statement, facts.parents, places)
        return path

    def inside(statement: ast.stmt) -> bool:
        if window is None:
            return True
        return window[0] <= path_of(statement)[0][1] < window[1]

    def locate(statement: ast.stmt) -> Located:
        found = located_cache.get(statement)
        if found is None:
            path = path_of(statement)
            if window is not None:
                if not window[0] <= path[0][1] < window[1]:
                    raise ApplyError("an edit reaches outside the statements re-parsed for it")
                path = [("body", path[0][1] - window[0]), *path[1:]]
            found = located_cache[statement] = locate_statement(module, path, tables)
        return found

    for target, builds in plan.replacements.items():
        statement = facts.statement_of(target)
        if not inside(statement):
            continue
        located = locate(statement)
        applier.mark(located.chain)
        inner: list[cst.CSTNode]
        if target is statement:
            node, inner = located.node, []
        else:
            node, inner = locate_expression(located, statement, target, plan, candidates)
            applier.mark([located.node, *inner])
        applier.mark([node])
        applier.builds[id(node)].extend(builds)

    insertions = {"before": {k: list(v) for k, v in plan.before.items()}, "after": {k: list(v) for k, v in plan.after.items()}}
    if plan.imports:
        anchor, where = _import_anchor(facts.tree)
        if anchor is not None and not inside(anchor):
            pass  # another window holds the anchor
        elif anchor is None:  # an empty module
            module = module.with_changes(
                body=[*module.body, *_new_statements(plan.imports, small=False)], has_trailing_newline=True
            )
        elif where == "after":
            insertions["after"].setdefault(anchor, []).extend(plan.imports)
        else:
            insertions["before"].setdefault(anchor, [])[:0] = plan.imports

    for where, by_statement in insertions.items():
        for statement, code in by_statement.items():
            if not code or not inside(statement):
                continue
            located = locate(statement)
            applier.mark(located.chain)
            holder, whole_line = _holder(located)
            getattr(applier, where)[id(holder)].extend(_new_statements(code, small=not whole_line))
            applier.mark([holder])

    for statement in plan.removed:
        if not inside(statement):
            continue
        located = locate(statement)
        applier.mark(located.chain)
        holder, _ = _holder(located)
        applier.removed.add(id(holder))
        applier.mark([holder])
        if statement in plan.keep_comments:
            _carry_comments(statement, located, holder, plan, locate, applier)

    if not applier.enter:
        return module
    return module.visit(applier)


def _carry_comments(
    statement: ast.stmt, located: Located, holder: cst.CSTNode, plan: Plan, locate: Callable[[ast.stmt], Located], applier: _Applier
) -> None:
    """Move the comment lines above a removed statement to the next statement kept in its block."""
    lines = getattr(holder, "leading_lines", ())
    if not lines or (located.line is not None and holder is not located.line):
        return  # nothing above it, or it shares its line with other statements
    siblings = block_of(statement, plan.facts.parents)
    index = next(i for i, item in enumerate(siblings) if item is statement)
    following = next((item for item in siblings[index + 1 :] if item not in plan.removed), None)
    if following is None:
        return
    target = locate(following)
    if target.line is not None and not isinstance(target.line, cst.SimpleStatementLine):
        return  # a one-line suite holds no comment lines
    owner = target.line if target.line is not None else target.node
    applier.mark([*target.chain, owner])
    applier.leading[id(owner)].extend(lines)


def _holder(located: Located) -> tuple[cst.CSTNode, bool]:
    """The node that takes insertions around a statement, and whether they are whole lines.

    A statement alone on its line gets new lines; one that shares its line (``a; b``)
    or sits in a one-line suite (``if x: a``) gets new small statements on that line.
    """
    if located.line is None:
        return located.node, True
    if isinstance(located.line, cst.SimpleStatementLine) and len(located.line.body) == 1:
        return located.line, True
    return located.node, False


def _import_anchor(tree: ast.Module) -> tuple[ast.stmt | None, str]:
    """Where new top-level imports go: after the last top-level import, else after the
    docstring, else before the first statement."""
    last_import = None
    for statement in tree.body:
        if isinstance(statement, (ast.Import, ast.ImportFrom)):
            last_import = statement
    if last_import is not None:
        return last_import, "after"
    body = tree.body
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) and isinstance(body[0].value.value, str):
        return body[0], "after"
    if body:
        return body[0], "before"
    return None, "after"
