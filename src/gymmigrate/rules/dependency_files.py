"""GM109, GM110, SB110, GM111: dependency declarations (requirements files, ``setup.py``,
``setup.cfg``, ``pyproject.toml``, ``environment.yml``, Dockerfiles, ``pip install`` lines
in pages).

These rules are carried out by ``gymmigrate.dependencies`` on files that hold no Python
program, not by a family of the Python engine; they are declared here, with every other
rule, so that ``--select``/``--ignore``, ``gymmigrate rules`` and the docs know them.
"""

from __future__ import annotations

from gymmigrate.findings import FixKind
from gymmigrate.rules.base import Rule, register_rules

GM109 = Rule(
    "GM109",
    "`gym` requirements become `gymnasium`",
    FixKind.ASSIST,
    "`gym[atari]==0.21` -> `gymnasium[atari]>=1.0`; Gym-era packages to their Gymnasium successors",
)
GM110 = Rule(
    "GM110",
    "Gym-only or unreadable requirements",
    FixKind.FLAG,
    "Gym-only packages (Shimmy route), VCS/URL installs and unreadable lines are reported, never rewritten",
    once_per_run=True,
)
SB110 = Rule(
    "SB110",
    "dependency pins of libraries that moved with Gym",
    FixKind.ASSIST,
    "`stable-baselines3<2` -> `>=2.9`; PettingZoo, SuperSuit, Shimmy, MiniGrid to Gymnasium-1.x releases",
)
GM111 = Rule(
    "GM111",
    "`gym.envs` plugin entry points",
    FixKind.ASSIST,
    "Gymnasium loads no plugins: the module an entry point names calls its register function on import; the entry point is reported",
)
DEPENDENCY_RULES = (GM109, GM110, SB110, GM111)
register_rules(*DEPENDENCY_RULES)
