"""The imports family: which files it may fire on, and one file's decision, in order: the
import statements (``statements.py``), unless a fallback or detector guards them
(``guards.py``), then the other GM108 checks, GM107 (``libraries.py``) and the removed
names read through the gym module (``removed.py``), and Gym code run from strings
(``code_strings.py``)."""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.findings import FixKind, gym_only_question
from gymmigrate.rules.base import FileContext
from gymmigrate.rules.imports.code_strings import CodeStrings
from gymmigrate.rules.imports.common import RULES
from gymmigrate.rules.imports.guards import ImportGuards, innermost_guard
from gymmigrate.rules.imports.libraries import GYM_ONLY_LIBRARIES, GYM_ONLY_MODULES
from gymmigrate.rules.imports.plugin_modules import first_gym_import, plugin_only_module
from gymmigrate.rules.imports.removed import RemovedAttributes
from gymmigrate.rules.imports.rllib import RllibEra
from gymmigrate.rules.imports.statements import ImportStatements
from gymmigrate.rules.repeats import Repeats


class Imports(ImportStatements, ImportGuards, RemovedAttributes, RllibEra, CodeStrings):
    RULES = RULES
    decides_the_module = True

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        return "gym" in facts.text or "stable_baselines" in facts.text or any(
            library in facts.text for library in (*GYM_ONLY_LIBRARIES, *GYM_ONLY_MODULES)
        )

    def decide(self) -> None:
        plugins = plugin_only_module(self.facts, self.receivers)
        if plugins:
            self._keep_module_on_gym(plugins)
            return
        self._removed_advice = Repeats("GM105")  # GM105: one review item per move and file
        self._gym_names = set()
        self._kept_space_imports = self._space_checks_of_gym_only_envs()
        guards = self._guards()
        for node in self._imports():
            guard = innermost_guard(node, guards, self.facts)
            if guard in ("fallback", "detector"):
                self._record_names(node)
            elif isinstance(node, ast.Import):
                self._import(node, guarded=guard == "guarded")
            else:
                self._import_from(node)
        self._sys_modules_hacks()
        self._version_checks()
        self._gym_only_libraries()
        self._gym_envs_handed_to_gym_only()
        self._gym_only_classes_and_entry_points()
        self._rllib_era()
        self._removed_module_attributes()
        self._missing_module_attributes()
        self._removed_entry_points()
        self._code_strings()

    def _keep_module_on_gym(self, plugins: tuple[str, ...]) -> None:
        """Every env of the module is one of ``plugins``' (``plugin_modules.py``): nothing of
        it is migrated, and one item at its gym import says why, with the route; the plugins'
        own imports (GM107) are notes pointing there. Its question is the plugin's, which
        other modules of the run ask at their imports of it."""
        self.notes.module_kept_for = plugins[0]
        node = first_gym_import(self.facts)
        asked_at: dict[str, int] = {}
        if node is not None:
            asked_at = dict.fromkeys(plugins, node.lineno)
            named = " and ".join(f"`{p}`" for p in plugins)
            which = "which register their" if len(plugins) > 1 else "which registers its"
            routes = "; ".join(GYM_ONLY_LIBRARIES[p] for p in plugins)
            self.report(
                node,
                "GM101",
                f"left on gym with the rest of this module: every env it makes comes from {named}, {which} ids "
                "with gym only (Gymnasium's make does not find them), and those envs keep gym's API, so no part of the "
                f"module is migrated; keep it on gym with {named}, or port the module and {named} together: {routes}",
                FixKind.FLAG,
                question=gym_only_question(N.gym_only_stack(plugins[0])),
            )
        self._gym_only_libraries(asked_at)
