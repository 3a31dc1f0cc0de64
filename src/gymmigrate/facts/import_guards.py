"""Which ``try`` statement makes an import optional: ``try: import x / except ImportError: ...``."""

from __future__ import annotations

import ast

from gymmigrate.facts.module import ModuleFacts

_IMPORT_ERRORS = frozenset({"ImportError", "ModuleNotFoundError", "Exception", "BaseException"})


def catches_import_error(handler: ast.ExceptHandler) -> bool:
    if handler.type is None:
        return True
    caught = handler.type.elts if isinstance(handler.type, ast.Tuple) else [handler.type]
    return any(ast.unparse(item) in _IMPORT_ERRORS for item in caught)


def import_error_guard(facts: ModuleFacts, statement: ast.stmt) -> ast.Try | None:
    """The ``try`` whose body (not a handler, ``else`` or ``finally``) holds ``statement`` and
    one of whose handlers catches ImportError, in the same function or class body."""
    child: ast.AST = statement
    for ancestor in facts.ancestors(statement):
        if isinstance(ancestor, ast.Try) and any(child is s for s in ancestor.body):
            if any(catches_import_error(handler) for handler in ancestor.handlers):
                return ancestor
        if isinstance(ancestor, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.Lambda)):
            return None
        child = ancestor
    return None


def in_handler_of(facts: ModuleFacts, node: ast.AST, guard: ast.Try) -> bool:
    """``node`` sits in one of ``guard``'s ``except`` branches (where a name is the fallback's)."""
    handlers = {id(h) for h in guard.handlers}
    return any(id(a) in handlers for a in facts.ancestors(node))
