"""The imports family: which files it may fire on, and one file's decision, in order: the
import statements (``statements.py``), unless a fallback or detector guards them
(``guards.py``), then the other GM108 checks, GM107 (``libraries.py``) and the removed
names read through the gym module (``removed.py``)."""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.rules.base import FileContext
from gymmigrate.rules.imports.common import RULES
from gymmigrate.rules.imports.guards import ImportGuards, innermost_guard
from gymmigrate.rules.imports.libraries import GYM_ONLY_LIBRARIES
from gymmigrate.rules.imports.removed import RemovedAttributes
from gymmigrate.rules.imports.rllib import RllibEra
from gymmigrate.rules.imports.statements import ImportStatements
from gymmigrate.rules.repeats import Repeats


class Imports(ImportStatements, ImportGuards, RemovedAttributes, RllibEra):
    RULES = RULES

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        return "gym" in facts.text or "stable_baselines" in facts.text or any(
            library in facts.text for library in GYM_ONLY_LIBRARIES
        )

    def decide(self) -> None:
        self._removed_advice = Repeats()  # GM105: one review item per move and file
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
        self._rllib_era()
        self._removed_module_attributes()
        self._missing_module_attributes()
        self._removed_entry_points()
