"""Which gym imports the imports rules (GM101-GM105) leave as they are.

This family decides on the original source, where every wrapper is still imported from
``gym``; the imports rules will move most of those imports to ``gymnasium`` in the same
run, but leave alone (and report) an import that names something removed, and the
imports inside a gym-or-gymnasium fallback. A wrapper reached through such a legacy
import is not migrated here either: a person must first split the import.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.module import walk
from gymmigrate.facts.profile import FileProfile
from gymmigrate.rules.imports.table import (
    LEGACY_WRAPPER_MODULES,
    REMOVED_MODULES,
    REMOVED_NAMES,
    migrated_path,
    removed_module_hint,
    removed_name_hint,
    under_gym,
)

__all__ = ["LegacyImports", "import_move", "migrated_path", "removed_import", "under_gym"]


class LegacyImports:
    """Answers "will this import still say ``gym`` after the imports rules?" for one module."""

    def __init__(self, facts: ModuleFacts, profile: FileProfile) -> None:
        self.facts = facts
        self.profile = profile
        self._guards: dict[ast.Try, bool] = {}

    def stays_legacy(self, statement: ast.Import | ast.ImportFrom) -> bool:
        if self._in_fallback(statement):
            return True
        if isinstance(statement, ast.ImportFrom):
            if statement.level or statement.module is None:
                return False
            rest = under_gym(statement.module)
            if rest is None:
                return False
            return (removed_module_hint(rest) is not None) or any(
                removed_name_hint(rest, alias.name) is not None for alias in statement.names
            )
        return any(removed_module_hint(under_gym(alias.name) or "") is not None for alias in statement.names if under_gym(alias.name))

    def binds_legacy(self, expr: ast.AST) -> bool:
        """``expr``'s root name is bound by a gym import that stays as it is."""
        while isinstance(expr, ast.Attribute):
            expr = expr.value
        if not isinstance(expr, ast.Name):
            return False
        for binding in self.facts.bindings_of(expr):
            if isinstance(binding, ast.alias):
                statement = self.facts.parent(binding)
                if isinstance(statement, (ast.Import, ast.ImportFrom)) and self.stays_legacy(statement):
                    return True
        return False

    def _in_fallback(self, statement: ast.stmt) -> bool:
        for ancestor in self.facts.ancestors(statement):
            if isinstance(ancestor, ast.Try) and self._is_guard(ancestor):
                return True
        return False

    def _is_guard(self, node: ast.Try) -> bool:
        """A gym-or-gymnasium fallback, or a "is legacy gym installed?" detector in a gymnasium file."""
        if node not in self._guards:
            packages: set[str] = set()
            for inner in walk(node):
                if isinstance(inner, ast.Import):
                    packages.update(alias.name.split(".")[0] for alias in inner.names)
                elif isinstance(inner, ast.ImportFrom) and inner.module and not inner.level:
                    packages.add(inner.module.split(".")[0])
            guard = False
            if "gym" in packages:
                if "gymnasium" in packages:
                    guard = True
                elif self.profile.imports_gymnasium:
                    guard = any(_catches_import_error(handler) for handler in node.handlers)
            self._guards[node] = guard
        return self._guards[node]


def _catches_import_error(handler: ast.ExceptHandler) -> bool:
    if handler.type is None:
        return True
    caught = handler.type.elts if isinstance(handler.type, ast.Tuple) else [handler.type]
    names = {ast.unparse(item) for item in caught}
    return bool(names & {"ImportError", "ModuleNotFoundError", "Exception", "BaseException"})


def import_move(statement: ast.ImportFrom) -> tuple[str, str] | None:
    """The finding the imports rules give for moving this ``from gym... import`` (code, message).

    When every name of such an import goes away here (its wrappers became
    ``gymnasium.wrappers.vector.X``), the statement is removed before the imports rules
    could report it; this family reports the move in their words instead. The plan keeps
    one finding where an imports family reports the same.
    """
    if statement.level or statement.module is None:
        return None
    module = statement.module
    rest = under_gym(module)
    if rest is None:
        if not (module.startswith("gymnasium.wrappers.") and module[19:] in LEGACY_WRAPPER_MODULES):
            return None
        rest = module[len("gymnasium.") :]
    new_rest = migrated_path(rest)
    new_module = "gymnasium" + ("." + new_rest if new_rest else "")
    if new_module == module:
        return None
    code = "GM102" if rest == "" else "GM104" if new_rest != rest else "GM103"
    return code, f"from {module} import ... -> from {new_module} import ..."


def removed_import(statement: ast.ImportFrom) -> str | None:
    """The GM105 message the imports rules give for a ``from gym... import`` they leave alone.

    ``from gym.wrappers.monitor import Monitor`` is rewritten here (GM611) before the
    imports rules would see it; this family reports their finding in their words (the
    plan keeps one where an imports family reports the same).
    """
    if statement.level or statement.module is None:
        return None
    rest = under_gym(statement.module)
    if rest is None:
        return None
    for removed, why in REMOVED_MODULES.items():
        if rest == removed or rest.startswith(removed + "."):
            return f"`{statement.module}` was removed: {why}"
    for alias in statement.names:
        hint = REMOVED_NAMES.get((rest, alias.name))
        if hint:
            return f"`{alias.name}` was removed: {hint}"
    return None
