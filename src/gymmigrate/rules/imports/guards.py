"""GM108: gym-or-gymnasium ``try/except ImportError`` fallbacks, ``sys.modules`` hacks and
``gym.__version__`` checks are reported, not rewritten: after the migration one branch
is dead and a person should delete it. An ImportError guard around gym alone is
rewritten and listed for review (GM101)."""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.module import dotted_name
from gymmigrate.rules.imports.common import ImportsBase
from gymmigrate.rules.imports.table import LEGACY_PACKAGES


class ImportGuards(ImportsBase):
    """GM108 (mixed into the family)."""

    def _guards(self) -> dict[ast.Try, str]:
        """How each try statement that imports gym treats a missing package.

        fallback: it tries gym and gymnasium (one branch is dead after the migration);
        detector: an ImportError guard around gym in a file that already uses gymnasium
        (it asks whether *legacy* gym is installed: rewriting it would change the answer);
        guarded: an ImportError guard around gym alone (rewritten, but listed for review).
        """
        packages: dict[ast.Try, set[str]] = {}
        for node in self._imports():
            for ancestor in self.facts.ancestors(node):
                if isinstance(ancestor, (ast.Try, getattr(ast, "TryStar", ast.Try))):
                    packages.setdefault(ancestor, set()).update(_packages(node))  # type: ignore[arg-type]
        guards: dict[ast.Try, str] = {}
        for try_node, imported in packages.items():
            if "gym" not in imported:
                continue
            if "gymnasium" in imported:
                guards[try_node] = "fallback"
                self.report(try_node, "GM108", "gym-or-gymnasium import fallback: keep the gymnasium branch and delete the legacy one")
            elif any(_catches_import_error(handler) for handler in try_node.handlers):
                if self.context.profile.imports_gymnasium:
                    guards[try_node] = "detector"
                    self.report(
                        try_node,
                        "GM108",
                        "this try/except ImportError detects whether legacy gym is installed (the file already uses "
                        "gymnasium): left as it is; delete it if legacy gym support is no longer wanted",
                    )
                else:
                    guards[try_node] = "guarded"
        return guards

    def _record_names(self, node: ast.Import | ast.ImportFrom) -> None:
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] in LEGACY_PACKAGES:
                    self._gym_names.add(alias.asname or alias.name.split(".")[0])

    def _sys_modules_hacks(self) -> None:
        if "sys.modules" not in self.facts.text:
            return
        for node in ast.walk(self.facts.tree):
            if not isinstance(node, ast.Assign):
                continue
            for target in node.targets:
                if isinstance(target, ast.Subscript) and dotted_name(target.value) == "sys.modules":
                    key = target.slice
                    if isinstance(key, ast.Constant) and isinstance(key.value, str):
                        if key.value in ("gym", "gymnasium") or key.value.startswith("gym."):
                            self.report(node, "GM108", "sys.modules hack aliasing gym: remove it once the code uses gymnasium")

    def _version_checks(self) -> None:
        if "__version__" not in self.facts.text:
            return
        for node in ast.walk(self.facts.tree):
            if isinstance(node, ast.Attribute) and node.attr == "__version__":
                if isinstance(node.value, ast.Name) and node.value.id in self._gym_names:
                    self.report(node, "GM108", "gym version check: after the migration one branch is dead; delete the legacy one")


def _packages(node: ast.Import | ast.ImportFrom) -> set[str]:
    if isinstance(node, ast.Import):
        return {alias.name.split(".")[0] for alias in node.names}
    if node.module is not None and not node.level:
        return {node.module.split(".")[0]}
    return set()


def innermost_guard(node: ast.AST, guards: dict[ast.Try, str], facts: ModuleFacts) -> str | None:
    """The guard kind of the nearest enclosing try that is a fallback, detector or guard.

    A fallback or detector anywhere above wins, as the old traversal's depth counters did.
    """
    kinds = [guards[a] for a in facts.ancestors(node) if a in guards]
    if "fallback" in kinds or "detector" in kinds:
        return "fallback"
    return "guarded" if kinds else None


def _catches_import_error(handler: ast.ExceptHandler) -> bool:
    if handler.type is None:
        return True  # a bare except catches it too
    caught = handler.type.elts if isinstance(handler.type, ast.Tuple) else [handler.type]
    names = {dotted_name(item) for item in caught}
    return bool(names & {"ImportError", "ModuleNotFoundError", "Exception", "BaseException"})
