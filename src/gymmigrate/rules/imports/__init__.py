"""Imports: ``gym`` becomes ``gymnasium`` (GM101-GM105, GM107, GM108).

* GM101 ``import gym`` -> ``import gymnasium as gym``; a name the user chose stays.
* GM102 ``from gym import X`` -> ``from gymnasium import X``.
* GM103 dotted submodule paths (``gym.spaces``, ``gym.utils.seeding``...) -> ``gymnasium...``.
* GM104 wrapper modules that Gymnasium 1.0 folded away (``gym.wrappers.time_limit``)
  -> the package root ``gymnasium.wrappers``.
* GM105 removed modules and symbols (GoalEnv, classic_control.rendering, DiscreteEnv,
  robotics, VideoRecorder, EnvCompatibility...) are reported and left as they are.
* GM107 libraries that never moved to Gymnasium (``stable_baselines`` 2.x, the TF-era
  Stable-Baselines, and OpenAI ``baselines``) are reported once per file, at the first
  import: their users move to Stable-Baselines3. Env plugins imported to register ids
  with gym (``pybullet_envs``, ``gym_super_mario_bros``...) are reported with their route
  (Shimmy, a Farama successor, or none): their ids do not resolve under Gymnasium. Their VecEnv code is left alone (``Receivers``: SB3_VEC kind).
* GM108 gym-or-gymnasium ``try/except ImportError`` fallbacks, ``sys.modules`` hacks
  and ``gym.__version__`` checks are reported, not rewritten: after the migration one
  branch is dead and a person should delete it.

Source: Gymnasium migration guide, "Package Import"; gymnasium 1.0 release notes.

Where each part lives:

* ``family.py``: ``Imports``, the family (``may_fire``, ``decide``).
* ``statements.py``: the rewrite of import statements (GM101-GM104; GM105 at an import).
* ``table.py``: the import table (moved wrapper modules and names, removed modules and
  names, names other families rename) and the paths and hints read from it.
* ``libraries.py``: GM107, libraries and env plugins still on Gym, and the imports kept
  on gym because of them.
* ``plugin_modules.py``: whether every env of the module comes from a Gym-only plugin, in
  which case nothing of the module is migrated (GM101's item says why).
* ``guards.py``: GM108, fallbacks, ``sys.modules`` hacks, version checks.
* ``removed.py``: GM105 on removed names read through the gym module.
* ``common.py``: catalog entries and the shared state.

What Gymnasium 1.4 has (modules, names) is ``rules/gymnasium_api.py``.
"""

from gymmigrate.rules.imports.common import RULES
from gymmigrate.rules.imports.family import Imports

__all__ = ["RULES", "Imports"]
