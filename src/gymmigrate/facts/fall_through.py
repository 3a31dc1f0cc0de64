"""Whether a def may run off the end of its body, so that a call of it returns ``None``.

A reset whose every path ends in ``return obs`` has a value on each; one that ends on an
``if`` without ``else``, or on a loop that may finish, returns ``None`` on that path too.
Read from the statements alone (CPython ``ast``), conservatively: a statement is taken to
complete unless its own shape says it cannot (``return``, ``raise``, ``while True``
without a ``break`` of its own, an ``if`` whose both arms cannot, a ``try`` whose body and
handlers cannot), so a call that never returns (``sys.exit()``) still counts as one that
completes.
"""

from __future__ import annotations

import ast
from collections.abc import Sequence

from gymmigrate.facts.module import FUNCTIONS, LOOPS


def may_fall_off(statements: Sequence[ast.stmt]) -> bool:
    """Control may run past the last of ``statements`` (an empty block does)."""
    return all(_completes(statement) for statement in statements)


def _completes(statement: ast.stmt) -> bool:
    """Control may go on to the statement after ``statement``."""
    if isinstance(statement, (ast.Return, ast.Raise, ast.Break, ast.Continue)):
        return False
    if isinstance(statement, ast.If):
        return may_fall_off(statement.body) or may_fall_off(statement.orelse)
    if isinstance(statement, ast.While):
        if _always_true(statement.test):
            return _breaks_out(statement)
        return True
    if isinstance(statement, (ast.With, ast.AsyncWith)):
        # A context manager that swallows the exception of a body ending in ``return`` is rare
        # enough, and its case a question for a person anyway.
        return may_fall_off(statement.body)
    if isinstance(statement, _TRIES):
        handled = any(may_fall_off(handler.body) for handler in statement.handlers)  # type: ignore[attr-defined]
        body = may_fall_off(statement.body) and may_fall_off(statement.orelse)  # type: ignore[attr-defined]
        return (body or handled) and may_fall_off(statement.finalbody)  # type: ignore[attr-defined]
    if _MATCH is not None and isinstance(statement, _MATCH):
        cases = statement.cases  # type: ignore[attr-defined]
        exhaustive = any(_irrefutable(case) for case in cases)
        return not exhaustive or any(may_fall_off(case.body) for case in cases)
    return True


def _always_true(test: ast.expr) -> bool:
    return isinstance(test, ast.Constant) and bool(test.value)


def _breaks_out(loop: ast.While) -> bool:
    """A ``break`` of ``loop`` itself (not of a loop inside it, nor of a nested def)."""
    stack: list[ast.AST] = list(loop.body)
    while stack:
        node = stack.pop()
        if isinstance(node, ast.Break):
            return True
        if isinstance(node, (*LOOPS, *FUNCTIONS, ast.ClassDef, ast.Lambda)):
            # A loop inside: its own breaks end it, not ``loop``; its else may still break.
            stack.extend(getattr(node, "orelse", []) if isinstance(node, LOOPS) else [])
            continue
        stack.extend(ast.iter_child_nodes(node))
    return False


def _irrefutable(case: ast.AST) -> bool:
    """``case _:`` or ``case name:`` without a guard: every subject matches it."""
    pattern = case.pattern  # type: ignore[attr-defined]
    return case.guard is None and isinstance(pattern, ast.MatchAs) and pattern.pattern is None  # type: ignore[attr-defined]


_TRIES: tuple[type[ast.AST], ...] = tuple(t for t in (ast.Try, getattr(ast, "TryStar", None)) if t is not None)
_MATCH: type[ast.AST] | None = getattr(ast, "Match", None)
