"""Find the LibCST counterpart of an ``ast`` node, without position metadata.

Statements are found by their place in the block structure (``body[3]`` of the
``orelse`` of ``body[1]``...), which both trees share. An expression is found inside
its statement as the n-th node of its kind in source order, and its text is checked
against the ``ast`` node's, so an edit is never placed on the wrong node: it fails with
``ApplyError`` instead. Each block and each statement's candidates are indexed once.
"""

from __future__ import annotations

import ast
import re
from typing import TYPE_CHECKING

import libcst as cst

if TYPE_CHECKING:
    from collections.abc import Callable

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


class Located:
    """Where an ast statement sits in the LibCST tree."""

    def __init__(self, chain: list[cst.CSTNode], node: cst.CSTNode, line: cst.CSTNode | None) -> None:
        self.chain = chain  # LibCST ancestors, from the module down, excluding ``node``
        self.node = node  # the compound statement or the small statement
        self.line = line  # the SimpleStatementLine / SimpleStatementSuite holding a small one


# One entry per ast statement of a block: (the LibCST statement or small statement, the
# line or suite holding a small one, or None for a compound statement).
BlockTable = list[tuple[cst.CSTNode, "cst.CSTNode | None"]]


def _block_table(items: list[cst.CSTNode], holder: cst.CSTNode) -> BlockTable:
    table: BlockTable = []
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
    tables: dict[tuple[int, str], tuple[list[cst.CSTNode], BlockTable]] | None = None,
) -> Located:
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
            return Located(chain, node, line)
        if last:
            return Located(chain, node, None)
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


def _ast_candidates(statement: ast.stmt, kind: str, parents: dict[ast.AST, ast.AST], segment: Callable[[ast.AST], str]) -> list[ast.expr]:
    """Nodes of ``kind`` in ``statement``, not in nested statements, in source order."""
    found: list[ast.expr] = []
    stack: list[ast.AST] = [statement]
    while stack:
        node = stack.pop()
        if node is not statement and isinstance(node, ast.stmt):
            continue
        if isinstance(node, (ast.expr,)) and _matches_ast_kind(node, kind, parents, segment):
            found.append(node)
        stack.extend(ast.iter_child_nodes(node))
    found.sort(key=lambda n: (n.lineno, n.col_offset, -(n.end_lineno or 0), -(n.end_col_offset or 0)))
    return found


def _matches_ast_kind(node: ast.AST, kind: str, parents: dict[ast.AST, ast.AST], segment: Callable[[ast.AST], str]) -> bool:
    if isinstance(node, ast.Constant):
        if isinstance(parents.get(node), ast.JoinedStr):
            return False  # literal parts of an f-string are not strings in LibCST
        return _ast_kind(node) == kind
    if isinstance(node, ast.Tuple) and _bare_subscript_tuple(node, parents, segment):
        return False  # ``a[0, 0]``: LibCST holds the elements as subscript elements, no Tuple
    return type(node).__name__ == kind


def _bare_subscript_tuple(node: ast.Tuple, parents: dict[ast.AST, ast.AST], segment: Callable[[ast.AST], str]) -> bool:
    """A subscript's tuple written without parentheses (``a[0, 0]``, ``a[(0), 1]``): LibCST
    keeps ``a[(0, 0)]`` a Tuple, but not these."""
    parent = parents.get(node)
    if not (isinstance(parent, ast.Subscript) and parent.slice is node):
        return False
    text = _normal(segment(node))
    return not (text.startswith("(") and _encloses(text))


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
        if node is not self.root and isinstance(node, (cst.BaseSuite, cst.If)):
            # Nested statements are addressed on their own; an ``elif`` is a nested ``If``
            # in LibCST's ``orelse`` (no suite in between), and its own statement in ast.
            return False
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
    located: Located, statement: ast.stmt, target: ast.AST, plan: Plan, cache: dict | None = None
) -> tuple[cst.CSTNode, list[cst.CSTNode]]:
    """The LibCST node for ``target`` inside ``statement``, and its ancestors below it.

    ``cache`` keeps both sides' candidates per (statement, kind), so many edits in one
    large statement scan it once.
    """
    kind = _ast_kind(target)
    cache = {} if cache is None else cache
    key = (statement, kind)
    if key not in cache:
        candidates = _ast_candidates(statement, kind, plan.facts.parents, plan.facts.segment)
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


def block_of(statement: ast.stmt, parents: dict[ast.AST, ast.AST]) -> list[ast.stmt]:
    parent = parents[statement]
    for name in _STATEMENT_FIELDS:
        items = getattr(parent, name, None)
        if isinstance(items, list) and any(item is statement for item in items):
            return items
    raise ApplyError(f"cannot find the block of a {type(statement).__name__}")
