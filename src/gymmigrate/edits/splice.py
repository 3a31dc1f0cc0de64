"""Apply a plan by re-parsing only the top-level statements that change.

Parsing a file with LibCST and printing it again is most of what a rewrite costs, yet
the edits of a typical file sit in a few top-level statements (the imports, a class, the
training loop). Here each run of touched top-level statements is cut out of the text
as whole lines, parsed as a small module, edited with ``apply_plan`` and printed; the
text between runs is kept as it is, character for character.

The result must be exactly what editing the whole module would give, so this mode is
only used where that is certain, and ``splice_plan`` returns None otherwise (the engine
then edits the whole module):

- an insertion before, or the removal of, a top-level statement that follows a compound
  statement or none: LibCST attaches the comment and blank lines above a statement to
  it (after a simple statement, the cut starts there to take them along);
- an insertion after a top-level compound statement: its block's trailing comment lines
  (LibCST's footer) are outside the cut too;
- new imports with no import or docstring to follow;
- a cut whose default indentation or newline (LibCST detects both from the text it
  parses) differs from the whole file's, since new blocks and lines take those defaults.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Callable

import libcst as cst

from gymmigrate.edits.apply import _import_anchor, apply_plan
from gymmigrate.edits.plan import Plan

_NEWLINE = re.compile(r"\r\n?|\n")  # as LibCST finds a module's default newline
_LIBCST_FALLBACK_INDENT = "    "
_COMPOUND: tuple[type[ast.stmt], ...] = (
    ast.FunctionDef,
    ast.AsyncFunctionDef,
    ast.ClassDef,
    ast.If,
    ast.For,
    ast.AsyncFor,
    ast.While,
    ast.With,
    ast.AsyncWith,
    ast.Try,
    ast.Match,
)
if hasattr(ast, "TryStar"):  # Python 3.11+
    _COMPOUND = (*_COMPOUND, ast.TryStar)


def splice_plan(text: str, plan: Plan, parse: Callable[[str], cst.Module]) -> str | None:
    """The rewritten text, or None when only editing the whole module is certain to be exact."""
    facts = plan.facts
    body = facts.tree.body
    touched = _touched(plan)
    if touched is None or not touched:
        return None
    runs = _runs(sorted(touched), body)
    newline_match = _NEWLINE.search(text)
    newline = newline_match.group(0) if newline_match else "\n"
    indent = _default_indent(facts.tree, facts.lines)
    if indent is None:
        return None
    pieces: list[str] = []
    position = 0
    for first, stop in runs:
        start = facts.line_start(_first_line(body[first]))
        end = facts.line_start(body[stop - 1].end_lineno + 1)  # type: ignore[operator]
        module = parse(text[start:end])
        if module.default_indent != indent or module.default_newline != newline:
            return None
        pieces += [text[position:start], apply_plan(module, plan, window=(first, stop)).code]
        position = end
    pieces.append(text[position:])
    return "".join(pieces)


def _touched(plan: Plan) -> set[int] | None:
    """Indexes of the top-level statements holding an edit; None if the whole module is needed."""
    facts = plan.facts
    tree = facts.tree
    index_of = {id(statement): i for i, statement in enumerate(tree.body)}

    def top(node: ast.AST) -> int:
        while True:
            parent = facts.parents.get(node)
            if parent is tree or parent is None:
                return index_of[id(node)]
            node = parent

    touched = {top(target) for target in plan.replacements}
    for statement in (*plan.before, *plan.removed):
        index = top(statement)
        if facts.parents.get(statement) is tree:
            # The lines above a top-level statement are its own in LibCST: cut from the
            # end of a simple statement before it, so they are inside the cut too.
            if index == 0 or isinstance(tree.body[index - 1], _COMPOUND):
                return None
            touched.add(index - 1)
            if statement in plan.keep_comments:  # its comment lines move to the next statement kept
                following = index + 1
                while following < len(tree.body) and tree.body[following] in plan.removed:
                    following += 1
                touched.update(range(index, min(following + 1, len(tree.body))))
        touched.add(index)
    for statement in plan.after:
        if facts.parents.get(statement) is tree and isinstance(statement, _COMPOUND):
            return None
        touched.add(top(statement))
    if plan.imports:
        anchor, where = _import_anchor(tree)
        if anchor is None or where != "after" or isinstance(anchor, _COMPOUND):
            return None
        touched.add(index_of[id(anchor)])
    return touched


def _first_line(statement: ast.stmt) -> int:
    decorators = getattr(statement, "decorator_list", None)
    return min([statement.lineno, *(d.lineno for d in decorators)]) if decorators else statement.lineno


def _runs(touched: list[int], body: list[ast.stmt]) -> list[tuple[int, int]]:
    """``(first, stop)`` ranges of top-level statements to cut out, as whole lines: a
    statement sharing a line with a neighbour (``a; b``) takes the neighbour along, and
    runs that meet are joined."""
    runs: list[tuple[int, int]] = []
    for index in touched:
        first, stop = index, index + 1
        while first > 0 and body[first - 1].end_lineno == _first_line(body[first]):
            first -= 1
        while stop < len(body) and _first_line(body[stop]) == body[stop - 1].end_lineno:
            stop += 1
        if runs and first <= runs[-1][1]:
            runs[-1] = (runs[-1][0], max(runs[-1][1], stop))
        else:
            runs.append((first, stop))
    return runs


def _default_indent(tree: ast.Module, lines: list[str]) -> str | None:
    """The whole file's default indentation as LibCST detects it: the first indented
    block's indentation. Only top-level statements need looking at: a block nested
    deeper sits inside an indented top-level block, which comes first."""
    for statement in tree.body:
        if isinstance(statement, _COMPOUND):
            found = _first_indented_suite(statement, lines)
            if found is not None:
                return found or None
    return _LIBCST_FALLBACK_INDENT


def _first_indented_suite(statement: ast.stmt, lines: list[str]) -> str | None:
    """The leading whitespace of ``statement``'s first suite that starts on its own line;
    None if every suite is on its header's line; "" if unsure."""
    for suite in _suites(statement, lines):
        first = suite[0]
        line = lines[first.lineno - 1] if first.lineno <= len(lines) else ""
        before = line.encode("utf-8")[: first.col_offset].decode("utf-8", "replace")
        if before and not before.strip(" \t"):
            return before
        if before.strip():  # on its header's line (``if x: y``): no INDENT token
            continue
        return ""  # at column 0 after a header: not Python we understand
    return None


def _suites(statement: ast.stmt, lines: list[str]) -> list[list[ast.stmt]]:
    """The statement's blocks in source order (an ``elif`` chain's blocks included)."""
    if isinstance(statement, ast.If):
        suites = [statement.body]
        orelse = statement.orelse
        if len(orelse) == 1 and isinstance(orelse[0], ast.If) and _is_elif(orelse[0], lines):
            return suites + _suites(orelse[0], lines)
        return suites + ([orelse] if orelse else [])
    if isinstance(statement, (ast.Try, *((ast.TryStar,) if hasattr(ast, "TryStar") else ()))):
        suites = [statement.body, *(handler.body for handler in statement.handlers)]  # type: ignore[attr-defined]
        return [s for s in (*suites, statement.orelse, statement.finalbody) if s]  # type: ignore[attr-defined]
    if isinstance(statement, ast.Match):
        return [case.body for case in statement.cases]
    suites = [statement.body]  # type: ignore[attr-defined]
    rest = getattr(statement, "orelse", None)
    return suites + ([rest] if rest else [])


def _is_elif(statement: ast.If, lines: list[str]) -> bool:
    line = lines[statement.lineno - 1] if statement.lineno <= len(lines) else ""
    return line.lstrip().startswith("elif")
