"""What the imports rules share: the catalog entries, and ``ImportsBase``, the state of one
file's decision with the import statements and GM105's one review item per move.
``ImportsBase`` has no ``RULES``: it is not a family of its own."""

from __future__ import annotations

import ast
from collections.abc import Hashable

from gymmigrate.findings import FixKind
from gymmigrate.rules.base import Rule, RuleFamily
from gymmigrate.rules.repeats import Repeats

RULES = (
    Rule("GM101", "import gym", FixKind.AUTO, "`import gym` becomes `import gymnasium as gym`."),
    Rule("GM102", "from gym import X", FixKind.AUTO, "`from gym import X` becomes `from gymnasium import X`."),
    Rule("GM103", "gym submodule paths", FixKind.AUTO, "`gym.spaces`, `gym.utils...` paths move under `gymnasium`."),
    Rule(
        "GM104",
        "moved wrapper modules",
        FixKind.AUTO,
        "`gym.wrappers.<module>` imports come from the package root `gymnasium.wrappers`.",
    ),
    Rule("GM105", "removed modules and symbols", FixKind.FLAG, "Imports of things Gymnasium removed are reported."),
    Rule(
        "GM107",
        "libraries still on Gym",
        FixKind.FLAG,
        "An import of a library with no Gymnasium release (`stable_baselines` 2.x, env plugins that register "
        "with gym only such as `pybullet_envs`) is reported once per file, with its route; an import of RLlib "
        "next to gym asks once per run for ray 2.3+ and its Gymnasium-era MultiAgentEnv API.",
        once_per_run=True,
    ),
    Rule(
        "GM108",
        "version sniffing and import fallbacks",
        FixKind.FLAG,
        "gym-or-gymnasium fallbacks, `sys.modules` hacks and `gym.__version__` checks are reported.",
    ),
)


class ImportsBase(RuleFamily):
    """The state ``Imports.decide`` sets up for one file, and what its parts share."""

    _removed_advice: Repeats  # GM105: one review item per move and file
    _gym_names: set[str]  # the names the file binds to gym (or gymnasium)
    _kept_space_imports: dict[ast.ImportFrom, str]  # imports left on gym for class checks, with their messages

    def _imports(self) -> list[ast.Import | ast.ImportFrom]:
        return self.facts.import_statements

    def _report_removed(self, node: ast.stmt, message: str, advice: str, question: Hashable | None = None) -> None:
        """GM105 once per decision: the first import that needs a given move (say, to
        gymnasium_robotics) is a review item naming the later imports of the file needing
        the same move, which are notes pointing at it (``EditPlan.ask_once``)."""
        # the advice up to its colon names the move (``the mujoco-py envs ... were removed``),
        # whatever module it then names; a removed helper's own question (what replaces it,
        # asked by its uses too) is that move
        if question is None:
            question = self._removed_advice.question(advice.split(": ", 1)[0])
        self.report(node, "GM105", message, question=question)
