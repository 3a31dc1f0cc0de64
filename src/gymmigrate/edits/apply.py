"""Carry out a ``Plan`` on the LibCST tree of the same source, in one traversal.

Edits are addressed by ``ast`` nodes. Statements are found in the LibCST tree by
their place in the block structure (``body[3]`` of the ``orelse`` of ``body[1]``...),
which both trees share; an expression is found inside its statement as the n-th node
of its type in source order, and its text is checked against the ``ast`` node's before
anything is changed. No position metadata is needed, and the traversal only enters
the statements that hold an edit, so applying costs little more than printing.
"""

from __future__ import annotations

import ast
import re
from collections import defaultdict
from collections.abc import Callable
from typing import Any

import libcst as cst

from gymmigrate.edits.plan import Plan


class ApplyError(Exception):
    """An edit could not be placed (a rule bug); the file is left unchanged."""


# -- statements ---------------------------------------------------------------------------

_STATEMENT_FIELDS = ("body", "orelse", "finalbody", "handlers", "cases")


def statement_path(
    statement: ast.stmt, parents: dict[ast.AST, ast.AST], places: dict[ast.AST, tuple[str, int]] | None = None
) -> list[tuple[str, int]]:
    """``[(field, index), ...]`` from the module down to ``statement``.

    Except handlers and match cases are not statements: their step is
    ``("handlers", i)`` / ``("cases", i)`` followed by ``("body", j)``. ``places`` caches
    every child's place in its parent, so each block is enumerated once per file however
    many edits it holds.
    """
    places = {} if places is None else places
    path: list[tuple[str, int]] = []
    node: ast.AST = statement
    while node in parents:
        parent = parents[node]
        place = places.get(node)
        if place is None:
            for name in _STATEMENT_FIELDS:
                items = getattr(parent, name, None)
                if isinstance(items, list):
                    for index, item in enumerate(items):
                        places[item] = (name, index)
            place = places.get(node)
            if place is None:
                raise ApplyError(f"cannot place a {type(node).__name__} inside a {type(parent).__name__}")
        path.append(place)
        node = parent
    path.reverse()
    return path


def _suite_items(owner: cst.CSTNode, field: str) -> tuple[list[cst.CSTNode], list[cst.CSTNode]]:
    """The LibCST nodes between ``owner`` and the statements of ``owner.<field>``, and those statements."""
    if isinstance(owner, cst.Module):
        return [], list(owner.body)
    if field == "body":
        suite = owner.body  # type: ignore[attr-defined]
        return [suite], list(suite.body)
    if field == "orelse":
        orelse = owner.orelse  # type: ignore[attr-defined]
        if isinstance(orelse, cst.If):  # ``elif``: ast says ``orelse=[If]``
            return [], [orelse]
        return [orelse, orelse.body], list(orelse.body.body)
    if field == "finalbody":
        final = owner.finalbody  # type: ignore[attr-defined]
        return [final, final.body], list(final.body.body)
    raise ApplyError(f"no statements under {type(owner).__name__}.{field}")


class _Located:
    """Where an ast statement sits in the LibCST tree."""

    def __init__(self, chain: list[cst.CSTNode], node: cst.CSTNode, line: cst.CSTNode | None) -> None:
        self.chain = chain  # LibCST ancestors, from the module down, excluding ``node``
        self.node = node  # the compound statement or the small statement
        self.line = line  # the SimpleStatementLine / SimpleStatementSuite holding a small one


# One entry per ast statement of a block: (the LibCST statement or small statement, the
# line or suite holding a small one, or None for a compound statement).
_BlockTable = list[tuple[cst.CSTNode, "cst.CSTNode | None"]]


def _block_table(items: list[cst.CSTNode], holder: cst.CSTNode) -> _BlockTable:
    table: _BlockTable = []
    for item in items:
        if isinstance(item, (cst.SimpleStatementLine, cst.SimpleStatementSuite)):
            table.extend((small, item) for small in item.body)
        elif isinstance(item, cst.BaseSmallStatement):  # inside a SimpleStatementSuite
            table.append((item, holder))
        else:
            table.append((item, None))
    return table


def locate_statement(
    module: cst.Module,
    path: list[tuple[str, int]],
    tables: dict[tuple[int, str], tuple[list[cst.CSTNode], _BlockTable]] | None = None,
) -> _Located:
    """Follow ``path`` down the LibCST tree; ``tables`` caches each block's statements."""
    tables = {} if tables is None else tables
    chain: list[cst.CSTNode] = [module]
    owner: cst.CSTNode = module
    for step, (field, index) in enumerate(path):
        last = step == len(path) - 1
        if field in ("handlers", "cases"):
            owner = getattr(owner, field)[index]
            chain.append(owner)
            continue
        key = (id(owner), field)
        cached = tables.get(key)
        if cached is None:
            between, items = _suite_items(owner, field)
            cached = tables[key] = (between, _block_table(items, between[-1] if between else owner))
        between, table = cached
        chain.extend(between)
        if index >= len(table):
            raise ApplyError("statement structure differs between ast and LibCST")
        node, line = table[index]
        if line is not None:
            if not last:
                raise ApplyError("a simple statement cannot contain statements")
            if isinstance(line, cst.SimpleStatementLine):
                chain.append(line)
            return _Located(chain, node, line)
        if last:
            return _Located(chain, node, None)
        chain.append(node)
        owner = node
    raise ApplyError("empty statement path")


# -- expressions inside a statement -------------------------------------------------------

_SIMPLE_TYPES: dict[type, tuple[type, ...]] = {
    ast.Call: (cst.Call,),
    ast.Attribute: (cst.Attribute,),
    ast.Subscript: (cst.Subscript,),
    ast.Name: (cst.Name,),
    ast.Tuple: (cst.Tuple,),
    ast.List: (cst.List,),
    ast.Dict: (cst.Dict,),
    ast.Set: (cst.Set,),
    ast.Lambda: (cst.Lambda,),
    ast.IfExp: (cst.IfExp,),
    ast.NamedExpr: (cst.NamedExpr,),
    ast.Compare: (cst.Comparison,),
    ast.BinOp: (cst.BinaryOperation,),
    ast.UnaryOp: (cst.UnaryOperation,),
    ast.ListComp: (cst.ListComp,),
    ast.SetComp: (cst.SetComp,),
    ast.DictComp: (cst.DictComp,),
    ast.GeneratorExp: (cst.GeneratorExp,),
    ast.JoinedStr: (cst.FormattedString,),
    ast.Await: (cst.Await,),
}
_KEYWORD_CONSTANTS = frozenset({"None", "True", "False"})


def _ast_kind(node: ast.AST) -> str:
    if isinstance(node, ast.Constant):
        if isinstance(node.value, str) or isinstance(node.value, bytes):
            return "string"
        if node.value is None or isinstance(node.value, bool):
            return "keyword-constant"
        if node.value is Ellipsis:
            return "ellipsis"
        return "number"
    if type(node) in _SIMPLE_TYPES:
        return type(node).__name__
    raise ApplyError(f"rules cannot address a {type(node).__name__} node directly")


def _ast_candidates(statement: ast.stmt, kind: str, parents: dict[ast.AST, ast.AST]) -> list[ast.AST]:
    """Nodes of ``kind`` in ``statement``, not in nested statements, in source order."""
    found = []
    stack: list[ast.AST] = [statement]
    while stack:
        node = stack.pop()
        if node is not statement and isinstance(node, ast.stmt):
            continue
        if isinstance(node, (ast.expr,)) and _matches_ast_kind(node, kind, parents):
            found.append(node)
        stack.extend(ast.iter_child_nodes(node))
    found.sort(key=lambda n: (n.lineno, n.col_offset, -(n.end_lineno or 0), -(n.end_col_offset or 0)))  # type: ignore[attr-defined]
    return found


def _matches_ast_kind(node: ast.AST, kind: str, parents: dict[ast.AST, ast.AST]) -> bool:
    if isinstance(node, ast.Constant):
        if isinstance(parents.get(node), ast.JoinedStr):
            return False  # literal parts of an f-string are not strings in LibCST
        return _ast_kind(node) == kind
    return type(node).__name__ == kind


def _cst_matches(node: cst.CSTNode, kind: str) -> bool:
    if kind == "string":
        return isinstance(node, (cst.SimpleString, cst.ConcatenatedString))
    if kind == "number":
        return isinstance(node, (cst.Integer, cst.Float, cst.Imaginary))
    if kind == "keyword-constant":
        return isinstance(node, cst.Name) and node.value in _KEYWORD_CONSTANTS
    if kind == "ellipsis":
        return isinstance(node, cst.Ellipsis)
    if kind == "Name":
        return isinstance(node, cst.Name) and node.value not in _KEYWORD_CONSTANTS
    return isinstance(node, _SIMPLE_TYPES[getattr(ast, kind)])


class _Candidates(cst.CSTVisitor):
    """LibCST nodes of one kind in a statement, in source order, with their ancestors."""

    def __init__(self, kind: str, root: cst.CSTNode) -> None:
        super().__init__()
        self.kind = kind
        self.root = root
        self.found: list[tuple[cst.CSTNode, list[cst.CSTNode]]] = []
        self.stack: list[cst.CSTNode] = []
        self._skip: set[int] = set()

    def on_visit(self, node: cst.CSTNode) -> bool:
        if id(node) in self._skip:
            return False
        if node is not self.root and isinstance(node, (cst.BaseSuite,)):
            return False  # nested statements are addressed on their own
        if isinstance(node, cst.ConcatenatedString) and self.kind == "string":
            self.found.append((node, list(self.stack)))
            return False  # its parts are one ast string
        self._exclude_non_expression_names(node)
        if _cst_matches(node, self.kind):
            self.found.append((node, list(self.stack)))
        self.stack.append(node)
        return True

    def on_leave(self, original_node: cst.CSTNode) -> None:
        if self.stack and self.stack[-1] is original_node:
            self.stack.pop()

    def _exclude_non_expression_names(self, node: cst.CSTNode) -> None:
        # Names that ast does not represent as ``ast.Name``: attribute and keyword names,
        # def/class/parameter names, ``except ... as e``, global/nonlocal.
        skip: list[cst.CSTNode | None] = []
        if isinstance(node, cst.Attribute):
            skip.append(node.attr)
        elif isinstance(node, cst.Arg):
            skip.append(node.keyword)
        elif isinstance(node, (cst.FunctionDef, cst.ClassDef)):
            skip.append(node.name)
        elif isinstance(node, cst.Param):
            skip.append(node.name)
        elif isinstance(node, cst.ExceptHandler) and node.name is not None:
            skip.append(node.name)
        elif isinstance(node, (cst.Global, cst.Nonlocal)):
            skip.extend(item.name for item in node.names)
        elif isinstance(node, (cst.Import, cst.ImportFrom)):
            skip.append(node)
        elif isinstance(node, (cst.MatchAs, cst.MatchStar)):
            skip.append(node.name)
        elif isinstance(node, cst.MatchMappingElement):
            pass
        for item in skip:
            if item is not None:
                self._skip.add(id(item))


def _normal(text: str) -> str:
    return re.sub(r"\s+", "", text)


def _unparenthesized(text: str) -> str:
    """``((a, b))`` -> ``a,b``: whitespace dropped, enclosing parentheses peeled while they
    really enclose the whole text (not ``(a)+(b)``)."""
    text = _normal(text)
    while text.startswith("(") and text.endswith(")") and _encloses(text):
        text = text[1:-1]
    return text


def _encloses(text: str) -> bool:
    depth = 0
    for index, char in enumerate(text):
        depth += char == "("
        depth -= char == ")"
        if depth == 0 and index < len(text) - 1:
            return False
    return True


def locate_expression(
    located: _Located, statement: ast.stmt, target: ast.AST, plan: Plan, cache: dict | None = None
) -> tuple[cst.CSTNode, list[cst.CSTNode]]:
    """The LibCST node for ``target`` inside ``statement``, and its ancestors below it.

    ``cache`` keeps both sides' candidates per (statement, kind), so many edits in one
    large statement scan it once.
    """
    kind = _ast_kind(target)
    cache = {} if cache is None else cache
    key = (statement, kind)
    if key not in cache:
        candidates = _ast_candidates(statement, kind, plan.facts.parents)
        visitor = _Candidates(kind, located.node)
        located.node.visit(visitor)
        if len(visitor.found) != len(candidates):
            raise ApplyError(f"{len(candidates)} ast {kind} nodes but {len(visitor.found)} in LibCST")
        cache[key] = ({id(node): i for i, node in enumerate(candidates)}, visitor.found)
    order, found = cache[key]
    index = order.get(id(target))
    if index is None:
        raise ApplyError(f"{type(target).__name__} is not inside its statement")
    node, ancestors = found[index]
    expected = plan.facts.segment(target)
    actual = cst.Module(body=[]).code_for_node(node)
    # ast includes a tuple's own parentheses in its span, LibCST keeps them in lpar/rpar:
    # compare without any enclosing parentheses on either side.
    if expected and _unparenthesized(actual) != _unparenthesized(expected):
        raise ApplyError(f"expected {expected!r} at line {target.lineno}, found {actual!r}")  # type: ignore[attr-defined]
    return node, ancestors


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
                first = before[0]
                before = [first.with_changes(leading_lines=[*carried, *first.leading_lines]), *before[1:]]
            elif hasattr(result, "leading_lines"):
                result = result.with_changes(leading_lines=[*carried, *result.leading_lines])
        if before or after:
            kept = [] if result is cst.RemovalSentinel.REMOVE else [result]
            result = cst.FlattenSentinel([*(before or ()), *kept, *(after or ())])
        return result


def _new_statements(code: list[Any], small: bool) -> list[cst.CSTNode]:
    """Parse new code for insertion as whole lines, or as small statements on one line."""
    nodes: list[cst.CSTNode] = []
    for item in code:
        node = cst.parse_statement(item) if isinstance(item, str) else item
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


def apply_plan(module: cst.Module, plan: Plan) -> cst.Module:
    """Return ``module`` with every edit of ``plan`` carried out."""
    facts = plan.facts
    applier = _Applier()
    located_cache: dict[ast.stmt, _Located] = {}
    places: dict[ast.AST, tuple[str, int]] = {}
    candidates: dict = {}  # (statement, kind) -> both sides' candidates
    tables: dict[tuple[int, str], tuple[list[cst.CSTNode], _BlockTable]] = {}

    def locate(statement: ast.stmt) -> _Located:
        found = located_cache.get(statement)
        if found is None:
            path = statement_path(statement, facts.parents, places)
            found = located_cache[statement] = locate_statement(module, path, tables)
        return found

    for target, builds in plan.replacements.items():
        statement = facts.statement_of(target)
        located = locate(statement)
        applier.mark(located.chain)
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
        if anchor is None:  # an empty module
            module = module.with_changes(
                body=[*module.body, *_new_statements(plan.imports, small=False)], has_trailing_newline=True
            )
        elif where == "after":
            insertions["after"].setdefault(anchor, []).extend(plan.imports)
        else:
            insertions["before"].setdefault(anchor, [])[:0] = plan.imports

    for where, by_statement in insertions.items():
        for statement, code in by_statement.items():
            if not code:
                continue
            located = locate(statement)
            applier.mark(located.chain)
            holder, whole_line = _holder(located)
            getattr(applier, where)[id(holder)].extend(_new_statements(code, small=not whole_line))
            applier.mark([holder])

    for statement in plan.removed:
        located = locate(statement)
        applier.mark(located.chain)
        holder, _ = _holder(located)
        applier.removed.add(id(holder))
        applier.mark([holder])
        if statement in plan.keep_comments:
            _carry_comments(statement, located, holder, plan, locate, applier)

    if not applier.enter:
        return module
    return module.visit(applier)  # type: ignore[return-value]


def _carry_comments(
    statement: ast.stmt, located: _Located, holder: cst.CSTNode, plan: Plan, locate: Callable[[ast.stmt], _Located], applier: _Applier
) -> None:
    """Move the comment lines above a removed statement to the next statement kept in its block."""
    lines = getattr(holder, "leading_lines", ())
    if not lines or (located.line is not None and holder is not located.line):
        return  # nothing above it, or it shares its line with other statements
    siblings = _block_of(statement, plan.facts.parents)
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


def _block_of(statement: ast.stmt, parents: dict[ast.AST, ast.AST]) -> list[ast.stmt]:
    parent = parents[statement]
    for name in _STATEMENT_FIELDS:
        items = getattr(parent, name, None)
        if isinstance(items, list) and any(item is statement for item in items):
            return items
    raise ApplyError(f"cannot find the block of a {type(statement).__name__}")


def _holder(located: _Located) -> tuple[cst.CSTNode, bool]:
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
