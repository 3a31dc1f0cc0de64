"""The import table: where gym's modules and names are in Gymnasium.

Wrapper modules folded into ``gymnasium.wrappers`` (GM104), names that moved to another
module, modules and names that are gone with what to use instead (GM105), names that
other families rename or report; and the questions asked of it: what ``gym.<rest>``
becomes (``migrated_path``, ``gymnasium_module``), why it cannot move
(``removed_module_hint``, ``removed_name_hint``, ``missing_name_hint``), and in which
submodule a name lives now (``home_of``). ``wrapper_usage/legacy_imports.py`` asks the
same questions."""

from __future__ import annotations

import re

from gymmigrate.rules.gymnasium_api import (
    GYMNASIUM_VERSION,
    has_name,
    module_exists,
    submodules_of,
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
    # an import of it is renamed (RENAMED_NAMES); a read through the module is reported
    ("envs.registration", "load"): "use gymnasium.envs.registration.load_env_creator",
    ("envs.registration", "load_env_plugins"): "plugins are gone: import the env package instead",
    ("envs.registration", "EnvRegistry"): "gymnasium.registry is a plain dict of EnvSpec",
    ("envs.registration", "EnvSpecTree"): "gymnasium.registry is a plain dict of EnvSpec",
    ("wrappers", "EnvCompatibility"): "use Shimmy's GymV21Environment-v0 / GymV26Environment-v0",
    ("wrappers", "StepAPICompatibility"): "use gymnasium.utils.step_api_compatibility",
    ("wrappers", "LazyFrames"): "frame stacks are plain numpy arrays now",
    ("wrappers.monitoring", "video_recorder"): "use gymnasium.wrappers.RecordVideo",
}
# (module under gym, name) pairs that Gymnasium kept under another name with the same
# contract: the import binds the new name to the old one (``from
# gymnasium.envs.registration import load_env_creator as load``), so every use stays.
# ``load_env_creator("pkg.module:Attr")`` imports the module and returns the attribute, as
# gym's ``load`` did.
RENAMED_NAMES = {
    ("envs.registration", "load"): "load_env_creator",
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


def under_gym(module: str) -> str | None:
    """``gym.spaces.box`` -> ``spaces.box``; ``gym`` -> ``""``; None for other modules."""
    if module == "gym":
        return ""
    if module.startswith("gym."):
        return module[4:]
    return None


def migrated_path(rest: str) -> str:
    """``wrappers.time_limit`` -> ``wrappers``; ``wrappers.vector_list_info`` -> ``wrappers.vector``."""
    parts = rest.split(".")
    if len(parts) >= 2 and parts[0] == "wrappers":
        if parts[1] in LEGACY_WRAPPER_MODULES:
            return "wrappers"
        if parts[1] == "vector_list_info":
            return "wrappers.vector"
    return rest


def gymnasium_module(rest: str) -> str:
    """``wrappers.time_limit`` -> ``gymnasium.wrappers``; ``""`` -> ``gymnasium``."""
    moved = migrated_path(rest)
    return "gymnasium" + ("." + moved if moved else "")


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
    if MOVED_NAMES.get((rest.split(".")[-1], name)) or MOVED_NAMES.get(("*", name)) or home_of(migrated_path(rest), name):
        return None
    known = MISSING_NAMES.get((target, name))
    return known or f"`{target}` has no `{name}` in Gymnasium {GYMNASIUM_VERSION}: replace it, or copy what the code needs of it"


def home_of(rest: str, name: str) -> str | None:
    """Where ``name`` lives in Gymnasium 1.4 when ``gymnasium.<rest>`` no longer binds it:
    a helper a legacy wrapper module exported (``gym.wrappers.normalize.RunningMeanStd``)
    is in a submodule now (``gymnasium.wrappers.utils``). None where ``<rest>`` binds it,
    or no submodule does (the import is then reported by the removed-name check)."""
    module = f"gymnasium.{rest}" if rest else "gymnasium"
    if has_name(module, name) or not module_exists(module):
        return None
    homes = sorted(m for m in submodules_of(module) if has_name(m, name))
    return (f"{module}.utils" if f"{module}.utils" in homes else homes[0]) if homes else None
