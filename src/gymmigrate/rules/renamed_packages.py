"""GM112: env packages that were renamed when they moved to Gymnasium.

``gym_minigrid`` (gym 0.21-0.26) became ``minigrid`` (MiniGrid 2.x/3.x on Gymnasium). A
file that keeps ``import gym_minigrid`` next to ``import gymnasium`` fails at import, or,
with the old package still installed, registers the MiniGrid ids with gym only, so
``gymnasium.make("MiniGrid-...")`` raises NameNotFound. ``import minigrid`` registers them
with Gymnasium (its ``__init__`` calls ``register_minigrid_envs()``).

Rewritten where the new package is known to hold the same thing: a side-effect
``import gym_minigrid`` (the name not used otherwise) and ``from gym_minigrid.wrappers
import ...`` of wrappers ``minigrid.wrappers`` still defines. The rest moved
(``gym_minigrid.minigrid`` was split into ``minigrid.core.*`` and ``minigrid.minigrid_env``,
and ``MiniGridEnv`` now takes a ``mission_space``): reported once per file, with where the
names live now. The tables were read from the minigrid 3.2.0 wheel.
"""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.edits.syntax import dotted_node
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.module import walk
from gymmigrate.facts.names import MINIGRID_WRAPPERS
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext, Rule, RuleFamily

LEGACY, CURRENT = "gym_minigrid", "minigrid"

# Where gym_minigrid.minigrid's names live in minigrid 3.2.0.
MOVED_NAMES = {
    "MiniGridEnv": "minigrid.minigrid_env",
    "Grid": "minigrid.core.grid",
    "MissionSpace": "minigrid.core.mission",
    "Actions": "minigrid.core.actions",
    **{
        name: "minigrid.core.world_object"
        for name in ("WorldObj", "Goal", "Floor", "Lava", "Wall", "Door", "Key", "Ball", "Box")
    },
    **{
        name: "minigrid.core.constants"
        for name in (
            "COLORS",
            "COLOR_NAMES",
            "COLOR_TO_IDX",
            "IDX_TO_COLOR",
            "OBJECT_TO_IDX",
            "IDX_TO_OBJECT",
            "STATE_TO_IDX",
            "DIR_TO_VEC",
            "TILE_PIXELS",
        )
    },
}


class RenamedEnvPackages(RuleFamily):
    RULES = (
        Rule(
            "GM112",
            "renamed env packages",
            FixKind.AUTO,
            "`import gym_minigrid` becomes `import minigrid` (which registers the MiniGrid ids with Gymnasium); "
            "moved modules are reported with where their names live now.",
        ),
    )

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        return LEGACY in facts.text

    def decide(self) -> None:
        project = self.receivers.project
        if project is not None and project.has_module(LEGACY):
            return  # the run is the gym-era package itself: its own imports stay
        moved: list[ast.stmt] = []
        for node in self.facts.import_statements:
            if isinstance(node, ast.Import):
                if any(_under_legacy(alias.name) for alias in node.names):
                    if not self._side_effect_import(node):
                        moved.append(node)
            elif node.module and not node.level and _under_legacy(node.module):
                if not self._wrappers_import(node):
                    moved.append(node)
        if moved:
            self.report(moved[0], "GM112", self._moved_message(moved), FixKind.FLAG)

    def _side_effect_import(self, node: ast.Import) -> bool:
        """``import gym_minigrid`` whose name the file never reads: ``import minigrid``."""
        if len(node.names) != 1:
            return False
        alias = node.names[0]
        if alias.name != LEGACY or alias.asname is not None or self._name_read(LEGACY):
            return False
        self.plan.replace(node, lambda import_node: _renamed(import_node))
        self.report(
            node,
            "GM112",
            "import gym_minigrid -> import minigrid: the package was renamed, and `import minigrid` registers the "
            "MiniGrid ids with Gymnasium",
        )
        return True

    def _wrappers_import(self, node: ast.ImportFrom) -> bool:
        if node.module != f"{LEGACY}.wrappers" or any(alias.name not in MINIGRID_WRAPPERS for alias in node.names):
            return False
        self.plan.replace(node, lambda from_node: from_node.with_changes(module=dotted_node(f"{CURRENT}.wrappers")))
        self.report(node, "GM112", "gym_minigrid.wrappers -> minigrid.wrappers: the package was renamed")
        return True

    def _name_read(self, name: str) -> bool:
        return any(isinstance(node, ast.Name) and node.id == name for node in walk(self.facts.tree))

    def _moved_message(self, moved: list[ast.stmt]) -> str:
        names = sorted(
            {
                alias.name
                for node in moved
                if isinstance(node, ast.ImportFrom)
                for alias in node.names
                if alias.name in MOVED_NAMES
            }
        )
        homes = "; ".join(f"`{name}` is in `{MOVED_NAMES[name]}`" for name in names)
        return (
            "`gym_minigrid` is the gym-era package, renamed `minigrid` for Gymnasium, and its modules moved "
            "(`gym_minigrid.minigrid` was split into `minigrid.minigrid_env` and `minigrid.core.*`; `MiniGridEnv` "
            "takes a `mission_space`): import from `minigrid`"
            + (f" ({homes})" if homes else "")
            + ", and declare `minigrid>=3.0`"
        )


def _under_legacy(module: str) -> bool:
    return module == LEGACY or module.startswith(LEGACY + ".")


def _renamed(node: cst.Import) -> cst.Import:
    alias = node.names[0]
    return node.with_changes(names=[alias.with_changes(name=cst.Name(CURRENT))])
