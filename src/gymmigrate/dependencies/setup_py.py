"""``setup.py``: the requirement strings passed to ``setup(...)``.

CPython's ``ast`` finds the ``install_requires``, ``tests_require``, ``setup_requires``
and ``extras_require`` keywords of a ``setup()`` / ``setuptools.setup()`` call, their list,
tuple or dict literals, and a module-level name bound once to such a literal
(``install_requires=REQUIRES``). Only the characters between a string constant's quotes
change, and only when the literal is written as its value (no escapes, no implicit
concatenation, no f-string); a requirement built any other way is reported.
"""

from __future__ import annotations

import ast
import warnings

from gymmigrate.dependencies import mapping
from gymmigrate.dependencies.core import (
    Outcome,
    Positions,
    Site,
    finding,
    line_span,
    migrate_sites,
)
from gymmigrate.dependencies.mapping import GYM_ONLY, Note
from gymmigrate.findings import FixKind

_KEYWORDS = frozenset({"install_requires", "tests_require", "setup_requires", "extras_require"})


class SetupPyError(ValueError):
    pass


def migrate_setup_py(text: str) -> Outcome:
    try:
        with warnings.catch_warnings():  # invalid escapes in the project's code are not ours to report
            warnings.simplefilter("ignore")
            tree = ast.parse(text)
    except (SyntaxError, ValueError, RecursionError, MemoryError) as exc:
        raise SetupPyError(f"setup.py does not parse: {exc}") from None
    positions = Positions(text)
    line_starts = positions.starts
    assigned = _module_assignments(tree)
    sites: list[Site] = []
    findings = []
    for node in ast.walk(tree):
        if not (isinstance(node, ast.Call) and _is_setup(node.func)):
            continue
        for keyword in node.keywords:
            if keyword.arg not in _KEYWORDS:
                continue
            for group, constant in _strings(keyword.value, assigned, keyword.arg == "extras_require", keyword.arg):
                span = _literal_span(text, line_starts, constant)
                if span is None:
                    start = _offset(text, line_starts, constant.lineno, constant.col_offset)
                    end = _offset(text, line_starts, constant.end_lineno or constant.lineno, constant.end_col_offset or 0)
                    if mapping.mentions_gym(text[start:end]):
                        note = Note(GYM_ONLY, FixKind.FLAG, "this requirement is not a plain string literal; left as it is: check it by hand")
                        findings.append(finding(positions, start, end, note))
                    continue
                sites.append(Site(span[0], span[1], removal=line_span(text, span[0], span[1]), group=group))
    outcome = migrate_sites(text, sites, positions)
    outcome.findings.extend(findings)
    return outcome


def _is_setup(func: ast.expr) -> bool:
    return (isinstance(func, ast.Name) and func.id == "setup") or (isinstance(func, ast.Attribute) and func.attr == "setup")


def _module_assignments(tree: ast.Module) -> dict[str, ast.expr]:
    """Names bound exactly once at module level, to their value."""
    seen: dict[str, ast.expr | None] = {}
    for statement in tree.body:
        if isinstance(statement, ast.Assign) and len(statement.targets) == 1 and isinstance(statement.targets[0], ast.Name):
            name = statement.targets[0].id
            seen[name] = None if name in seen else statement.value
        elif isinstance(statement, ast.AnnAssign) and isinstance(statement.target, ast.Name) and statement.value is not None:
            name = statement.target.id
            seen[name] = None if name in seen else statement.value
    return {name: value for name, value in seen.items() if value is not None}


def _strings(value: ast.expr, assigned: dict[str, ast.expr], extras: bool, group: object, depth: int = 0) -> list[tuple[object, ast.expr]]:
    """The elements of the requirement list(s) ``value`` stands for, each with its group
    (the keyword, or the keyword and the extra's position)."""
    if depth > 3:
        return []
    if isinstance(value, ast.Name) and value.id in assigned:
        return _strings(assigned[value.id], assigned, extras, group, depth + 1)
    if extras and isinstance(value, ast.Dict):
        return [
            item
            for index, element in enumerate(value.values)
            for item in _strings(element, assigned, False, (group, index), depth + 1)
        ]
    if isinstance(value, (ast.List, ast.Tuple)):
        return [(group, element) for element in value.elts]
    if isinstance(value, ast.BinOp) and isinstance(value.op, ast.Add):
        return _strings(value.left, assigned, extras, group, depth + 1) + _strings(value.right, assigned, extras, group, depth + 1)
    return []


def _offset(text: str, line_starts: list[int], line: int, utf8_column: int) -> int:
    start = line_starts[line - 1]
    newline = text.find("\n", start)
    line_text = text[start : len(text) if newline < 0 else newline]
    return start + len(line_text.encode("utf-8")[:utf8_column].decode("utf-8", "replace"))


def _literal_span(text: str, line_starts: list[int], node: ast.expr) -> tuple[int, int] | None:
    """The span between the quotes of a plain one-line string literal whose text is its value."""
    if not (isinstance(node, ast.Constant) and isinstance(node.value, str)) or node.end_lineno != node.lineno:
        return None
    start = _offset(text, line_starts, node.lineno, node.col_offset)
    end = _offset(text, line_starts, node.lineno, node.end_col_offset or 0)
    literal = text[start:end]
    prefix = len(literal) - len(literal.lstrip("rRuU"))
    body = literal[prefix:]
    if len(body) < 2 or body[0] not in "\"'" or body[-1] != body[0] or body.startswith(('"""', "'''")):
        return None
    if body[1:-1] != node.value or "\\" in body:
        return None
    return start + prefix + 1, end - 1
