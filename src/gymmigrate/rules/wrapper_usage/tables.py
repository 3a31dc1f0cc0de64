"""What Gymnasium 1.x did to its wrappers: renames, removals, vector versions, own attributes.

Tables from gymnasium 1.4 ``wrappers/__init__.py`` (``_renamed_wrapper``) and
``wrappers/vector/__init__.py``, shared by the renames family (GM608-GM615) and the
forwarding family (GM604-GM606), plus the helpers that read a qualified name as a wrapper.
"""

from __future__ import annotations

from gymmigrate.facts import names as N
from gymmigrate.findings import FixKind

RENAMED = {
    "AutoResetWrapper": "Autoreset",
    "FrameStack": "FrameStackObservation",
    "GrayScaleObservation": "GrayscaleObservation",
    "PixelObservationWrapper": "AddRenderObservation",
    "FilterObservationWrapper": "FilterObservation",
}
EXPERIMENTAL_SPECIAL = {
    "LambdaObservationV0": "TransformObservation",
    "LambdaActionV0": "TransformAction",
    "LambdaRewardV0": "TransformReward",
    "PixelObservationV0": "AddRenderObservation",
    "AutoresetV0": "Autoreset",
    "NormalizeRewardV1": "NormalizeReward",
}
REMOVED = {
    "EnvCompatibility": "use Shimmy's GymV21Environment-v0 / GymV26Environment-v0 to load a legacy env",
    "StepAPICompatibility": "use gymnasium.utils.step_api_compatibility's converters",
    "LazyFrames": "frame stacks are plain numpy arrays now (FrameStackObservation)",
    "VideoRecorder": "use gymnasium.wrappers.RecordVideo or gymnasium.utils.save_video.save_video",
}
VECTOR_WRAPPERS = frozenset(
    {
        "TransformObservation", "FilterObservation", "FlattenObservation", "GrayscaleObservation",
        "ResizeObservation", "ReshapeObservation", "RescaleObservation", "DtypeObservation",
        "NormalizeObservation", "TransformAction", "ClipAction", "RescaleAction", "TransformReward",
        "ClipReward", "NormalizeReward", "RecordEpisodeStatistics", "RecordVideo", "HumanRendering",
        "ArrayConversion", "JaxToNumpy", "JaxToTorch", "NumpyToTorch",
    }
)  # fmt: skip
SINGLE_ENV_WRAPPERS = VECTOR_WRAPPERS | {
    "AtariPreprocessing", "DelayObservation", "FrameStackObservation", "TimeAwareObservation",
    "MaxAndSkipObservation", "AddRenderObservation", "StickyAction", "RepeatAction", "TimeLimit",
    "Autoreset", "PassiveEnvChecker", "OrderEnforcing", "RenderCollection", "AddWhiteNoise", "ObstructView",
}  # fmt: skip

# Defined on gymnasium.Wrapper itself (``dir(gymnasium.Wrapper)``, 1.4): reads never needed forwarding.
# ``seed`` is the seeding rules' business (GM203).
SAFE_ATTRIBUTES = frozenset(
    {
        "env", "unwrapped", "spec", "action_space", "observation_space", "metadata", "render_mode",
        "np_random", "np_random_seed", "reset", "step", "render", "close", "get_wrapper_attr",
        "set_wrapper_attr", "has_wrapper_attr", "class_name", "wrapper_spec", "seed", "reward_range",
    }
)  # fmt: skip
# State and methods of the base envs that legacy code reached through forwarding.
BASE_ENV_ATTRIBUTES = frozenset(
    {
        "state", "x_threshold", "theta_threshold_radians", "gravity", "masscart", "masspole", "length",
        "force_mag", "tau", "max_speed", "max_torque", "goal_position", "goal_velocity", "ale", "lives",
        "get_action_meanings", "get_keys_to_action", "desc", "P", "s", "lastaction", "nS", "nA", "model",
        "data", "sim", "lander", "world", "game", "compute_reward", "goal", "frameskip", "_frameskip",
    }
)  # fmt: skip
# Attributes a gymnasium wrapper class sets itself: reading them on that wrapper is fine.
OWN_ATTRIBUTES = {
    "RecordEpisodeStatistics": {"return_queue", "length_queue", "time_queue", "episode_count", "buffer_length",
                                "episode_returns", "episode_lengths", "episode_start_time", "stats_key"},
    "NormalizeObservation": {"obs_rms", "epsilon", "update_running_mean"},
    "NormalizeReward": {"return_rms", "discounted_reward", "gamma", "epsilon", "update_running_mean"},
    "TimeLimit": {"_max_episode_steps", "_elapsed_steps"},
    "RecordVideo": {"video_folder", "episode_trigger", "step_trigger", "video_length", "name_prefix", "episode_id"},
}  # fmt: skip

# What the layers ``gymnasium.make`` may add (1.4: PassiveEnvChecker, OrderEnforcing,
# TimeLimit, HumanRendering, RenderCollection) have besides ``gymnasium.Wrapper``'s own
# (``SAFE_ATTRIBUTES``), read from ``vars()`` and ``dir()`` of each: ``set_wrapper_attr``
# of one of these names stops at that layer.
MAKE_LAYER_ATTRIBUTES = SAFE_ATTRIBUTES | frozenset(
    {
        "_action_space", "_observation_space", "_metadata", "_cached_spec", "_saved_kwargs", "_np_random",
        "_np_random_seed", "_elapsed_steps", "_max_episode_steps", "_has_reset", "has_reset",
        "_disable_render_order_enforcing", "_previous_data", "checked_data_reuse", "checked_render",
        "checked_reset", "checked_step", "close_called", "ACCEPTED_RENDER_MODES", "_render_frame", "clock",
        "screen_size", "window", "frame_list", "pop_frames", "reset_clean",
    }
)  # fmt: skip

FINAL_INFO_KEYS = ("final_observation", "final_info")


def wrapper_rest(qualified: str) -> str | None:
    """``gymnasium.wrappers.frame_stack.FrameStack`` -> ``FrameStack``; ``experimental.wrappers.X`` -> ``X``."""
    rest = N.strip_gym_prefix(qualified)
    if rest is None:
        return None
    for prefix in ("wrappers.", "experimental.wrappers."):
        if rest.startswith(prefix):
            tail = rest[len(prefix) :]
            if tail.startswith("vector."):
                return None
            return tail.rsplit(".", 1)[-1]
    return None


def wrapper_class_rest(qualified: str) -> str | None:
    """``wrapper_rest`` of a wrapper class only: None for the helpers that live beside the
    wrappers (gym's ``VideoRecorder`` and ``StatsRecorder``, ``LazyFrames``, ``RunningMeanStd``).
    Their constructors take the env too, ``VideoRecorder(env, path)``, but what they return is
    a recorder, not a layer around it: reading its attributes forwards nothing."""
    name = wrapper_rest(qualified)
    if name is None or name in N.GYM_NOT_ENV_CLASSES:
        return None
    modules = (N.strip_gym_prefix(qualified) or "").split(".")[:-1]
    return None if N.GYM_NOT_ENV_MODULES.intersection(modules) else name


def experimental_name(name: str) -> str | None:
    """``ClipActionV0`` -> ``ClipAction``; None for a name that is not an experimental wrapper."""
    if name in EXPERIMENTAL_SPECIAL:
        return EXPERIMENTAL_SPECIAL[name]
    for suffix in ("V0", "V1"):
        if name.endswith(suffix) and name[:1].isupper():
            return name[: -len(suffix)]
    return None


def rename_code(old: str) -> tuple[str, FixKind | None]:
    """The rule a legacy wrapper's rename is reported under, and its fix kind where it is not
    the rule's: Autoreset resets on another step (GM612); AddRenderObservation needs a render
    mode and takes other arguments (GM608, ASSIST)."""
    if old == "AutoResetWrapper":
        return "GM612", None
    if old == "PixelObservationWrapper":
        return "GM608", FixKind.ASSIST
    return "GM608", None


def current_name(name: str) -> str:
    """The 1.x name of a wrapper written under its legacy or experimental name."""
    if name == "Monitor":
        return "RecordVideo"
    return RENAMED.get(name) or experimental_name(name) or name
