"""PZ109, PZ110: where PettingZoo spaces come from, and how envs are made in 1.27.

PZ109: PettingZoo 1.22 builds on ``gymnasium.spaces``; a PettingZoo env whose spaces
come from ``gym`` fails its type checks and ``api_test``. The import itself is rewritten
by the import rules (GM101-GM103, one edit per import); this rule lists each such import
in a PettingZoo file, so the report says why the env needs it.

PZ110: PettingZoo 1.27 deprecates module-level creation (``rps_v2.env()`` warns) in
favour of ``pettingzoo.make("aec", "classic/rps-v2")``. The old form still works on
1.24-1.27, and ``pettingzoo.make`` does not exist before 1.27, so this is a suggestion
(FLAG), made only in files whose PettingZoo code is being migrated in this run: code
already on the current API is left in peace.
"""

from __future__ import annotations

import ast
import re

from gymmigrate.facts import names as N
from gymmigrate.rules.pettingzoo.common import PZ109, PZ110, PettingZooFamily
from gymmigrate.rules.pettingzoo.env_modules import BUMPS, CURRENT, MOVED_FAMILIES

# ``pettingzoo.classic.rps_v2.env`` -> ("classic", "rps", "2", "env")
_MODULE_FACTORY = re.compile(r"^pettingzoo\.(\w+)\.(\w+?)_v(\d+)\.(env|parallel_env)$")


class SpacesAndMake(PettingZooFamily):
    RULES = (PZ109, PZ110)
    after = ("EnvClasses", "AecLoop", "ParallelCalls", "SeedRender", "EnvModules")

    def decide(self) -> None:
        if self.context.profile.imports_pettingzoo:
            self._report_gym_spaces()
        if self.notes.pettingzoo_edited:
            for calls in (self.facts.attribute_calls.get("env", ()), self.facts.attribute_calls.get("parallel_env", ())):
                for call in calls:
                    self._suggest_make(call)

    def _report_gym_spaces(self) -> None:
        for statement in self.facts.import_statements:
            if isinstance(statement, ast.ImportFrom):
                module = statement.module or ""
                spaces = module == "gym.spaces" or module.startswith("gym.spaces.") or (
                    module == "gym" and any(alias.name == "spaces" for alias in statement.names)
                )
            else:
                spaces = any(alias.name == "gym.spaces" or alias.name.startswith("gym.spaces.") for alias in statement.names)
            if spaces and statement.level == 0 if isinstance(statement, ast.ImportFrom) else spaces:
                self.report(statement, "PZ109", "PettingZoo 1.22+ envs use `gymnasium.spaces` (the import moves with GM101-GM103)")
        for attr in self.facts.attributes.get("spaces", ()):
            if any(q == "gym.spaces" for q in self.facts.qualified_names(attr)):
                self.report(attr, "PZ109", "PettingZoo 1.22+ envs use `gymnasium.spaces` (`import gym` moves with GM101)")

    def _suggest_make(self, call: ast.Call) -> None:
        for qualified in self.facts.qualified_names(call.func):
            match = _MODULE_FACTORY.match(qualified)
            if match is None or N.top_package(qualified) != N.PETTINGZOO_PACKAGE:
                continue
            family, name, version, factory = match.groups()
            if f"pettingzoo.{family}" in MOVED_FAMILIES:
                return  # its own package now (PZ111); PettingZoo's registry does not hold it
            bump = BUMPS.get((f"pettingzoo.{family}", name))
            if bump is not None and int(version) == bump.previous:
                version = str(bump.current)  # PZ111 bumps the import
            current = bump.current if bump is not None else CURRENT.get(f"pettingzoo.{family}", {}).get(name)
            if current is not None and int(version) < current:
                # superseded and not bumped (PZ111 asks for a port): 1.27 does not register
                # this version, so the new form would name an env it cannot make
                return
            api = "parallel" if factory == "parallel_env" else "aec"
            self.report(call, "PZ110", f"PettingZoo 1.27 deprecates module-level creation: "
                        f"`pettingzoo.make(\"{api}\", \"{family}/{name}-v{version}\", ...)` is the new form (1.27 only)")
            return
