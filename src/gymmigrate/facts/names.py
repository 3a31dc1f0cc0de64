"""Qualified-name tables: which library objects create which kind of environment.

Kept apart from the classifier so the tables can be read (and extended) without
reading the logic that applies them.
"""

from __future__ import annotations

GYM_PACKAGES = ("gym", "gymnasium")

# Names under gym/gymnasium (without the package prefix) whose call returns one env.
GYM_ENV_FACTORIES = frozenset({"make", "envs.make", "envs.registration.make", "envs.registration.registry.make"})

# Prefixes under gym/gymnasium whose class constructors return one (wrapped) env.
GYM_ENV_CLASS_PREFIXES = ("wrappers.", "envs.")
# Classes under those prefixes that are not envs: viewers, recorders, specs, frame
# buffers. ``self.viewer = rendering.Viewer(...)`` is drawing state, not a wrapped env.
GYM_NOT_ENV_MODULES = frozenset(
    {"rendering", "mujoco_rendering", "registration", "monitoring", "video_recorder", "stats_recorder", "car_dynamics", "utils"}
)
GYM_NOT_ENV_CLASSES = frozenset(
    {
        "Viewer",
        "SimpleImageViewer",
        "EnvSpec",
        "LazyFrames",
        "VideoRecorder",
        "StatsRecorder",
        "Car",
        "ContactDetector",
        "FrictionDetector",
        "RunningMeanStd",  # the normalize wrappers' statistics (gym.wrappers.normalize, gymnasium.wrappers.utils)
    }
)

# Gym's own env classes are named ``...Env`` (``CartPoleEnv``, ``MujocoEnv``, ``AtariEnv``)
# but for the Box2D ones, which subclasses extend as often (``class Racer(CarRacing)``).
GYM_BOX2D_ENV_CLASSES = frozenset({"CarRacing", "BipedalWalker", "BipedalWalkerHardcore", "LunarLander", "LunarLanderContinuous"})


def is_builtin_env_class_path(rest: str) -> bool:
    """``envs.classic_control.CartPoleEnv``, ``envs.box2d.car_racing.CarRacing`` (a path
    with gym's prefix stripped): one of Gym's own env classes."""
    if not rest.startswith("envs."):
        return False
    last = rest.rsplit(".", 1)[-1]
    return last[:1].isupper() and (last.endswith("Env") or last in GYM_BOX2D_ENV_CLASSES)


# Gymnasium 1.4's own env classes whose ``__init__`` takes ``render_mode`` (checked in its
# sources), by the modules that hold them, gym's prefix stripped: a subclass's own
# ``__init__`` must take it and hand it on, or ``gymnasium.make(id, render_mode=...)`` raises
# TypeError. ``LunarLanderContinuous`` and ``BipedalWalkerHardcore`` refuse to be built
# directly; the MuJoCo classes take it through ``**kwargs`` beside a constructor the mujoco-py
# classes did not have (GM508).
_RENDER_MODE_ENV_MODULES = {
    "envs.classic_control": ("AcrobotEnv", "CartPoleEnv", "Continuous_MountainCarEnv", "MountainCarEnv", "PendulumEnv"),
    "envs.toy_text": ("BlackjackEnv", "CliffWalkingEnv", "FrozenLakeEnv", "TaxiEnv"),
    "envs.box2d": ("BipedalWalker", "CarRacing", "LunarLander"),
}
_RENDER_MODE_ENV_FILES = {
    "AcrobotEnv": "acrobot",
    "CartPoleEnv": "cartpole",
    "Continuous_MountainCarEnv": "continuous_mountain_car",
    "MountainCarEnv": "mountain_car",
    "PendulumEnv": "pendulum",
    "BlackjackEnv": "blackjack",
    "CliffWalkingEnv": "cliffwalking",
    "FrozenLakeEnv": "frozen_lake",
    "TaxiEnv": "taxi",
    "BipedalWalker": "bipedal_walker",
    "CarRacing": "car_racing",
    "LunarLander": "lunar_lander",
}
RENDER_MODE_ENV_CLASSES = frozenset(
    path
    for package, classes in _RENDER_MODE_ENV_MODULES.items()
    for name in classes
    for path in (f"{package}.{name}", f"{package}.{_RENDER_MODE_ENV_FILES[name]}.{name}")
)


# Gym env base classes Gymnasium no longer has, whose subclasses must be ported onto
# ``gymnasium.Env`` (GM105 says so): once ported, such a class derives from Gym's Env
# alone, so nothing of the old base reads or sets a render mode for it.
PORTED_TO_ENV_BASES = frozenset({"envs.toy_text.discrete.DiscreteEnv"})


def takes_render_mode_builtin(qualified: str) -> bool:
    """``gym.envs.classic_control.cartpole.CartPoleEnv``: one of Gymnasium's own env classes
    whose ``__init__`` takes ``render_mode`` (``RENDER_MODE_ENV_CLASSES``)."""
    rest = strip_gym_prefix(qualified)
    return rest is not None and rest in RENDER_MODE_ENV_CLASSES


GYM_ENV_BASE_CLASSES = frozenset(
    {
        "Env",
        "core.Env",
        "Wrapper",
        "core.Wrapper",
        "ObservationWrapper",
        "core.ObservationWrapper",
        "ActionWrapper",
        "core.ActionWrapper",
        "RewardWrapper",
        "core.RewardWrapper",
        "GoalEnv",
        "core.GoalEnv",
    }
)
GYM_WRAPPER_BASE_CLASSES = frozenset(
    name for name in GYM_ENV_BASE_CLASSES if "Wrapper" in name
)

# Gym's mixin classes (paths under gym/gymnasium, prefix stripped): a Gym env or wrapper class
# may add them to its bases without changing what it is. They define no env attribute and no
# step or reset (EzPickle only __getstate__/__setstate__, RecordConstructorArgs only the record
# of its constructor's arguments), and the migration itself adds RecordConstructorArgs to a
# wrapper taking arguments (rules/wrappers/constructor_args.py), so a second run must decide
# about the class as the first did. EzPickle is in gym/utils/ezpickle.py (legacy gym and
# Gymnasium), RecordConstructorArgs in gymnasium/utils/record_constructor.py (Gymnasium only;
# gymnasium.core imports it too); gym.utils and gymnasium.utils export both they have.
GYM_MIXIN_CLASSES = frozenset(
    {
        "utils.EzPickle",
        "utils.ezpickle.EzPickle",
        "utils.RecordConstructorArgs",
        "utils.record_constructor.RecordConstructorArgs",
        "core.RecordConstructorArgs",
    }
)

GYM_VEC_FACTORIES = frozenset(
    {
        "vector.make",
        "make_vec",
        "vector.SyncVectorEnv",
        "vector.AsyncVectorEnv",
        "vector.sync_vector_env.SyncVectorEnv",
        "vector.async_vector_env.AsyncVectorEnv",
        "experimental.vector.SyncVectorEnv",
        "experimental.vector.AsyncVectorEnv",
    }
)
GYM_VEC_PREFIXES = ("wrappers.vector.",)

# minigrid 3.2.0 minigrid/wrappers.py: its classes (gym_minigrid 1.x had the same names).
MINIGRID_WRAPPERS = frozenset(
    {
        "ActionBonus",
        "DictObservationSpaceWrapper",
        "DirectionObsWrapper",
        "FlatObsWrapper",
        "FullyObsWrapper",
        "ImgObsWrapper",
        "NoDeath",
        "OneHotPartialObsWrapper",
        "PositionBonus",
        "RGBImgObsWrapper",
        "RGBImgPartialObsWrapper",
        "ReseedWrapper",
        "StochasticActionWrapper",
        "SymbolicObsWrapper",
        "ViewSizeWrapper",
    }
)

# Modules of Gym env libraries whose classes (named here) are Gym wrappers: called on a
# Gym env they give one (the gym-era name and its Gymnasium successor alike).
GYM_LIBRARY_WRAPPERS: dict[str, frozenset[str]] = {
    "gym_minigrid.wrappers": MINIGRID_WRAPPERS,
    "minigrid.wrappers": MINIGRID_WRAPPERS,
}

# Top-level packages with no Gymnasium release: GM107 reports their imports with a route
# (``rules/imports/libraries.py`` GYM_ONLY_LIBRARIES), and an object they make is decided by that port.
GYM_ONLY_PACKAGES = frozenset(
    {
        "akro",
        "atari_py",
        "baselines",
        "colabgymrender",
        "d4rl",
        "dm2gym",
        "dm_control2gym",
        "dmc2gym",
        "gfootball",
        "gym_super_mario_bros",
        "gym_ignition",
        "gym_tetris",
        "gym_unity",
        "marl_baselines3",
        "mujoco_py",
        "multiagent",
        "nes_py",
        "ppaquette_gym_doom",
        "ppaquette_gym_super_mario",
        "procgen",
        "ptan",
        "pybullet_envs",
        "pybulletgym",
        "retro",
        "retro_contest",
        "roboschool",
        "safety_gym",
        "slimevolleygym",
        "stable_baselines",
        "universe",
    }
)

# Gym-only packages that come as one stack: a game package and the emulator library its
# envs are built on. Their imports and the envs they make ask one decision (port the stack:
# Shimmy, or its Gymnasium successor), keyed by the library under the stack.
GYM_ONLY_STACKS = {
    "gym_super_mario_bros": "nes_py",
    "gym_tetris": "nes_py",
    "retro_contest": "retro",
}


def gym_only_stack(package: str) -> str:
    """The stack a Gym-only package belongs to (``gym_super_mario_bros`` -> ``nes_py``)."""
    return GYM_ONLY_STACKS.get(package, package)

# Every VecEnv family: Stable-Baselines3, stable_baselines 2.x (TF) and OpenAI baselines
# share the VecEnv API. Four-field step, obs-only reset and seed() are their API and must
# never be rewritten (kind SB3_VEC, which stands for all of them).
SB3_VEC_PREFIXES = (
    "stable_baselines3.common.vec_env.",
    "sb3_contrib.common.vec_env.",
    "stable_baselines.common.vec_env.",
    "baselines.common.vec_env.",
    "baselines.common.vec_env",
)
SB3_VEC_FACTORIES = frozenset(
    {
        "stable_baselines3.common.env_util.make_vec_env",
        "stable_baselines3.common.env_util.make_atari_env",
        "stable_baselines3.common.cmd_util.make_vec_env",
        "stable_baselines3.common.cmd_util.make_atari_env",
        "stable_baselines.common.cmd_util.make_vec_env",
        "stable_baselines.common.cmd_util.make_atari_env",
        "stable_baselines.common.make_vec_env",
        "baselines.common.cmd_util.make_vec_env",
    }
)
SB3_PACKAGES = ("stable_baselines3", "sb3_contrib", "stable_baselines", "baselines")
# The libraries' pickling holders that carry an env function to a worker process
# (``Process(target=worker, args=(..., CloudpickleWrapper(env_fn)))``): the attribute the
# worker reads it from (``env_fn_wrapper.x()``) and the constructor parameter (name,
# position) it is stored from unchanged.
PICKLING_HOLDERS: dict[str, tuple[str, str, int]] = {
    "baselines.common.vec_env.CloudpickleWrapper": ("x", "x", 0),
    "baselines.common.vec_env.vec_env.CloudpickleWrapper": ("x", "x", 0),
    "baselines.common.vec_env.subproc_vec_env.CloudpickleWrapper": ("x", "x", 0),
    "stable_baselines.common.vec_env.CloudpickleWrapper": ("var", "var", 0),
    "stable_baselines.common.vec_env.base_vec_env.CloudpickleWrapper": ("var", "var", 0),
    "stable_baselines3.common.vec_env.CloudpickleWrapper": ("var", "var", 0),
    "stable_baselines3.common.vec_env.base_vec_env.CloudpickleWrapper": ("var", "var", 0),
}
# Stable-Baselines3 2.x single-env wrappers subclass ``gymnasium.Wrapper``: what they wrap
# and return is a Gym env (``env = NoopResetEnv(gym.make(...))``; ``Monitor(env)``).
SB3_ENV_WRAPPER_PREFIXES = ("stable_baselines3.common.atari_wrappers.",)
SB3_ENV_WRAPPERS = frozenset({"stable_baselines3.common.monitor.Monitor"})
SB3_MODEL_CLASSES = frozenset({"HER", "RecurrentPPO", "MaskablePPO", "QRDQN", "TQC", "TRPO", "ARS"})
# Bases of an algorithm or a rollout runner of those libraries (``class MySAC(SAC)``,
# ``class Runner(AbstractEnvRunner)``): the library's ``__init__`` stores ``self.env``, a
# VecEnv of its own (or SB2's single-env ``_UnvecWrapper``, same legacy API), and a
# runner's ``self.model``, the algorithm. Upper-case names (``PPO2``, ``DDPG``) and
# ``SB3_MODEL_CLASSES`` are algorithms too.
SB_ALGORITHM_BASE_SUFFIXES = ("Algorithm", "RLModel")
SB_RUNNER_BASE_SUFFIX = "Runner"
SB3_CALLBACK_BASES = frozenset(
    {
        "stable_baselines3.common.callbacks.BaseCallback",
        "stable_baselines3.common.callbacks.EventCallback",
    }
)

PETTINGZOO_PACKAGE = "pettingzoo"
# SuperSuit wraps PettingZoo (and Gymnasium) envs; its ``*vec_env*`` functions make VecEnvs.
SUPERSUIT_PACKAGE = "supersuit"
PZ_PARALLEL_SUFFIXES = (".parallel_env",)
PZ_AEC_SUFFIXES = (".env", ".raw_env")
# The conversions, with their names before PettingZoo 1.15 (``to_parallel``, the wrapper
# classes ``to_parallel_wrapper`` / ``from_parallel_wrapper``) and the wrapper classes the
# functions build, which some code calls directly.
PZ_PARALLEL_FACTORIES = frozenset(
    {
        "pettingzoo.utils.conversions.aec_to_parallel",
        "pettingzoo.utils.aec_to_parallel",
        "pettingzoo.utils.conversions.to_parallel",
        "pettingzoo.utils.to_parallel",
        "pettingzoo.utils.conversions.aec_to_parallel_wrapper",
        "pettingzoo.utils.conversions.to_parallel_wrapper",
    }
)
PZ_AEC_FACTORIES = frozenset(
    {
        "pettingzoo.utils.conversions.parallel_to_aec",
        "pettingzoo.utils.parallel_to_aec",
        "pettingzoo.utils.conversions.from_parallel",
        "pettingzoo.utils.from_parallel",
        "pettingzoo.utils.conversions.parallel_to_aec_wrapper",
        "pettingzoo.utils.conversions.from_parallel_wrapper",
    }
)
PZ_AEC_BASES = frozenset(
    {
        "pettingzoo.AECEnv",
        "pettingzoo.utils.env.AECEnv",
        "pettingzoo.utils.AECEnv",
        # PettingZoo's wrapper bases: a user wrapper is an env of the same API.
        "pettingzoo.utils.BaseWrapper",
        "pettingzoo.utils.wrappers.BaseWrapper",
        "pettingzoo.utils.wrappers.base.BaseWrapper",
        # ...and the AEC wrappers PettingZoo builds on it (``utils`` re-exports them all).
        *(
            f"pettingzoo.utils.{where}{name}"
            for name, module in (
                ("OrderEnforcingWrapper", "order_enforcing"),
                ("AssertOutOfBoundsWrapper", "assert_out_of_bounds"),
                ("ClipOutOfBoundsWrapper", "clip_out_of_bounds"),
                ("TerminateIllegalWrapper", "terminate_illegal"),
                ("CaptureStdoutWrapper", "capture_stdout"),
            )
            for where in ("", "wrappers.", f"wrappers.{module}.")
        ),
    }
)
PZ_PARALLEL_BASES = frozenset(
    {
        "pettingzoo.ParallelEnv",
        "pettingzoo.utils.env.ParallelEnv",
        "pettingzoo.utils.ParallelEnv",
        "pettingzoo.utils.BaseParallelWrapper",
        "pettingzoo.utils.wrappers.BaseParallelWrapper",
        "pettingzoo.utils.wrappers.base_parallel.BaseParallelWrapper",
        "pettingzoo.utils.wrappers.BaseParallelWraper",  # the 1.20 spelling
        "pettingzoo.utils.BaseParallelWraper",
        "pettingzoo.utils.wrappers.base_parallel.BaseParallelWraper",
    }
)
# PettingZoo env families that left for their own package: old module -> (new package,
# whether PZ111 rewrites their imports: MAgent2's layout was not checked, so it only reports).
PZ_MOVED_FAMILIES: dict[str, tuple[str, bool]] = {
    "pettingzoo.mpe": ("mpe2", True),
    "pettingzoo.magent": ("magent2", False),
}
PZ_MOVED_PACKAGES = frozenset(new for new, _ in PZ_MOVED_FAMILIES.values())
# In a subclass of these, ``self.env`` is the wrapped PettingZoo env (the base stores it).
PZ_WRAPPER_BASES = frozenset(name for name in PZ_AEC_BASES | PZ_PARALLEL_BASES if "Wrap" in name)

# Libraries whose objects are never environments (their .step() is an optimiser or
# scheduler step).
# Every render mode Gym's and Gymnasium's own envs and wrappers have known (gym 0.25's
# "single_*" and the "*_list" collections included; "state_pixels" is CarRacing's): a
# render called with another literal mode is no sign of a Gym env by itself.
GYM_RENDER_MODES = frozenset(
    {
        "human",
        "rgb_array",
        "ansi",
        "depth_array",
        "state_pixels",
        "rgb_array_list",
        "ansi_list",
        "depth_array_list",
        "state_pixels_list",
        "single_rgb_array",
        "single_depth_array",
        "single_state_pixels",
    }
)

# Libraries whose environments have an API of their own (tf_agents' PyEnvironment: reset and
# step return a TimeStep): what they make, and a class deriving one of their classes, is
# left alone, with no question asked. rllab's envs (its ``GymEnv`` adapter around a gym id,
# ``normalize(...)``) take rllab's API, which never moved to Gymnasium: reset gives the
# observation, step a ``Step`` record, their spaces ``flatten``; so do those of the
# TensorFlow port its repository ships as ``sandbox.rocky.tf`` (``TfEnv``), a package named
# by its module path because its top-level name says nothing.
OWN_ENV_API_PACKAGES = ("tf_agents", "dm_env", "rllab")
OWN_ENV_API_MODULES = ("sandbox.rocky.tf.envs",)

# The same for single classes of a library whose other classes may be Gym's (RLlib's atari
# wrappers are Gym wrappers): RLlib's ``MultiAgentEnv`` and its wrappers around PettingZoo,
# Unity and grouped agents take and return per-agent dicts (``dones["__all__"]``), with gym
# (ray < 2.3: reset gives the obs dict, step four dicts) or with Gymnasium (ray >= 2.3: reset
# gives (obs, infos) dicts, step five, ``terminateds``/``truncateds``). Which one follows the
# ray release, not Gym's API: a call on one of them is never rewritten as a Gym env's
# (``rules/imports/rllib.py`` asks the ray decision). ``ray.rllib.env`` re-exports them all;
# before ray 1.4 the wrappers sat in ``ray.rllib.env`` itself, not in ``env.wrappers``.
OWN_ENV_API_CLASSES = frozenset(
    {
        "ray.rllib.MultiAgentEnv",
        "ray.rllib.env.MultiAgentEnv",
        "ray.rllib.env.multi_agent_env.MultiAgentEnv",
        *(
            f"ray.rllib.env.{where}{name}"
            for name, module in (
                ("PettingZooEnv", "pettingzoo_env"),
                ("ParallelPettingZooEnv", "pettingzoo_env"),
                ("GroupAgentsWrapper", "group_agents_wrapper"),
                ("Unity3DEnv", "unity3d_env"),
            )
            for where in ("", f"{module}.", f"wrappers.{module}.")
        ),
    }
)


def has_own_env_api(qualified: str) -> bool:
    """``qualified`` is a class (or callable) of a library whose envs have an API of their
    own (``OWN_ENV_API_PACKAGES``, ``OWN_ENV_API_CLASSES``)."""
    return (
        top_package(qualified) in OWN_ENV_API_PACKAGES
        or qualified in OWN_ENV_API_CLASSES
        or qualified.startswith(tuple(module + "." for module in OWN_ENV_API_MODULES))
    )

NOT_ENV_PACKAGES = (
    *OWN_ENV_API_PACKAGES,
    "torch",
    "tensorflow",
    "keras",
    "jax",
    "optax",
    "flax",
    "numpy",
    "scipy",
    "sklearn",
    "pandas",
    "transformers",
)


def strip_gym_prefix(qualified: str) -> str | None:
    """``gym.wrappers.TimeLimit`` -> ``wrappers.TimeLimit``; None if not under gym/gymnasium."""
    for package in GYM_PACKAGES:
        if qualified == package:
            return ""
        if qualified.startswith(package + "."):
            return qualified[len(package) + 1 :]
    return None


def is_wrapper_class_path(rest: str) -> bool:
    """``wrappers.TimeLimit`` (a path under gym/gymnasium, prefix stripped) names a single-env
    wrapper class; the helpers that live beside the wrappers (``wrappers.monitoring.stats_recorder.
    StatsRecorder``, ``wrappers.utils.RunningMeanStd``) and the vector wrappers do not."""
    if not rest.startswith("wrappers.") or rest.startswith("wrappers.vector."):
        return False
    *modules, last = rest.split(".")
    return last not in GYM_NOT_ENV_CLASSES and not GYM_NOT_ENV_MODULES.intersection(modules)


def top_package(qualified: str) -> str:
    return qualified.split(".", 1)[0]


def is_library(qualified: str) -> bool:
    """Gym, Stable-Baselines, PettingZoo, numpy...: never a module of the run."""
    package = top_package(qualified)
    return (
        strip_gym_prefix(qualified) is not None
        or package in SB3_PACKAGES
        or package == PETTINGZOO_PACKAGE
        or package in NOT_ENV_PACKAGES
        or package in ("typing", "collections", "functools", "os", "sys", "math", "random", "time", "logging")
    )
