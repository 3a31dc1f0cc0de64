"""Attributes of gym's built-in envs that Gymnasium's classes no longer have (GM604).

Legacy code reached some attributes of the envs gym shipped that Gymnasium's versions of
those classes do not define: gym's pyglet viewer and the shapes it drew (gym 0.22
removed ``classic_control.rendering``; Gymnasium's classic control and Box2D envs draw with
pygame), mujoco-py's ``sim`` and viewer (the v4 envs run on the ``mujoco`` bindings), the
toy-text envs' ``DiscreteEnv`` fields. ``.unwrapped.viewer`` raises AttributeError as
``.viewer`` does, so no rewrite of the receiver reaches them: such a read or write is
reported, with what replaces the attribute, and left as it is.

The table is the difference between the classes gym 0.21 registered (``self.x`` stores,
class attributes and methods, with their bases) and the classes Gymnasium 1.4 makes for the
same ids (after GM803's version bump); ``tests/test_builtin_attributes.py`` checks each
entry against the installed Gymnasium. ``seed`` and ``reward_range`` are left to their own
rules. It applies only where the run shows which built-in env a receiver holds: every
creation of it is a ``make`` of an id of one of these envs or a constructor of its class.
Part of ``forwarding.WrapperForwarding``, which asks it before rewriting a read through
make's layers (``make_layers.py``): what no layer has, whichever layer a ``.env`` chain
names, asks nothing of the chain.
"""

from __future__ import annotations

import ast
import re
from typing import TYPE_CHECKING

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.creation import CreationFinder
from gymmigrate.facts.module import dotted_name
from gymmigrate.facts.receivers import Receivers
from gymmigrate.findings import FixKind
from gymmigrate.rules.wrapper_usage.atari_limits import is_make_call, make_ids

if TYPE_CHECKING:
    from gymmigrate.rules.wrapper_usage.self_forwarding import ForwardingFamily

_PYGLET_VIEWER = (
    "gym's pyglet viewer is gone (gym 0.22 removed `gym.envs.classic_control.rendering`): the env draws with pygame in "
    "render(), into its own `screen` and `clock`; make the env with render_mode=\"human\" for a window, or "
    "\"rgb_array\" and show the frames render() returns"
)
_PYGLET_SHAPE = "it was a shape of gym's pyglet drawing, gone with it: render() draws with pygame now"
_MUJOCO_PY_VIEWER = (
    "mujoco-py's viewer is gone: the v4 envs render through `mujoco_renderer` (the camera is the "
    "`default_camera_config` the env is made with)"
)
_MUJOCO_PY_SIM = (
    "mujoco-py's MjSim is gone: the v4 envs hold the mujoco bindings' `model` and `data` (`sim.data.qpos` is "
    "`data.qpos`, `sim.model` is `model`)"
)

_VIEWER = {"viewer": _PYGLET_VIEWER}
_MUJOCO = {
    "viewer": _MUJOCO_PY_VIEWER,
    "_viewers": _MUJOCO_PY_VIEWER,
    "_get_viewer": _MUJOCO_PY_VIEWER,
    "viewer_setup": _MUJOCO_PY_VIEWER,
    "sim": _MUJOCO_PY_SIM,
}
# The v3 locomotion envs' ``done`` property is ``terminated`` in v4.
_MUJOCO_DONE = {**_MUJOCO, "done": "the v4 envs call it `terminated` (the same test of the body's health)"}
_TOY_TEXT = {
    "isd": "it is `initial_state_distrib` now",
    "nS": "the count of states is `observation_space.n`",
    "nA": "the count of actions is `action_space.n`",
}

# Gone from Gymnasium's class, by the class name gym 0.21 gave it (Gymnasium keeps the names).
GONE: dict[str, dict[str, str]] = {
    "CartPoleEnv": {
        **_VIEWER,
        **dict.fromkeys(("axle", "carttrans", "poletrans", "track", "_pole_geom"), _PYGLET_SHAPE),
        "steps_beyond_done": "it is `steps_beyond_terminated` now",
    },
    "MountainCarEnv": {**_VIEWER, **dict.fromkeys(("cartrans", "track"), _PYGLET_SHAPE)},
    "Continuous_MountainCarEnv": {**_VIEWER, **dict.fromkeys(("cartrans", "track"), _PYGLET_SHAPE)},
    "PendulumEnv": {**_VIEWER, **dict.fromkeys(("img", "imgtrans", "pole_transform"), _PYGLET_SHAPE)},
    "AcrobotEnv": _VIEWER,
    "LunarLander": _VIEWER,
    "LunarLanderContinuous": _VIEWER,
    "BipedalWalker": _VIEWER,
    "BipedalWalkerHardcore": _VIEWER,
    "CarRacing": {**_VIEWER, **dict.fromkeys(("transform", "score_label", "render_road", "render_indicators"), _PYGLET_SHAPE)},
    "FrozenLakeEnv": _TOY_TEXT,
    "TaxiEnv": _TOY_TEXT,
    "CliffWalkingEnv": {"isd": _TOY_TEXT["isd"]},
    **dict.fromkeys(
        ("ReacherEnv", "PusherEnv", "InvertedPendulumEnv", "InvertedDoublePendulumEnv", "HalfCheetahEnv", "SwimmerEnv", "HumanoidStandupEnv"),
        _MUJOCO,
    ),
    **dict.fromkeys(("HopperEnv", "Walker2dEnv", "AntEnv"), _MUJOCO_DONE),
    "HumanoidEnv": {
        **_MUJOCO_DONE,
        "contact_cost": "Humanoid-v4 computes no contact cost (Humanoid-v5 has `contact_cost` again, with other changes)",
    },
}

# Methods of gym's AtariEnv that ale-py's, which Gymnasium's Atari ids make, no longer has:
# name -> (the path that replaces it on the env itself, the keywords it adds, how many
# arguments the legacy method took). gym <= 0.19 kept its own AtariEnv on atari-py
# (``gym/envs/atari/atari_env.py``: ``_get_image`` was ``ale.getScreenRGB2()``, ``_get_ram``
# ``to_ram(ale)``, the full state ``cloneSystemState``/``restoreSystemState``); gym 0.20-0.26
# made ale-py 0.7's (``ale_py/gym/environment.py``), which kept ``clone_full_state``; ale-py
# 0.9 removed the system state: ``clone_state(include_rng=True)`` holds the RNG, and
# ``restore_state`` restores whatever the state holds (ale-py 0.12.1 ``ale_py/env.py``).
# ``tests/test_builtin_attributes.py`` checks the table against the installed ale-py.
ATARI_REPLACED: dict[str, tuple[tuple[str, ...], tuple[tuple[str, str], ...], int]] = {
    "_get_image": (("ale", "getScreenRGB"), (), 0),
    "_get_ram": (("ale", "getRAM"), (), 0),
    "clone_full_state": (("clone_state",), (("include_rng", "True"),), 0),
    "restore_full_state": (("restore_state",), (), 1),
}
# What has no exact replacement: ``seed(s)`` reseeded the emulator and reloaded the ROM
# without a reset; ale-py 0.9 seeds only in ``reset(seed=s)`` (``seed_game`` and
# ``load_game``, then ``reset_game``).
ATARI_GONE = {
    "seed": (
        "ale-py's AtariEnv has no seed(): `env.reset(seed=s)` seeds it (it reseeds the emulator and reloads the ROM, "
        "then resets the game); where no reset may run there, `env.unwrapped.seed_game(s)` then "
        "`env.unwrapped.load_game()` is what gym's seed() did"
    ),
}

# The class each built-in id name makes (gym 0.21's registry; the name is the id without
# its version).
_ID_CLASSES = {
    "CartPole": "CartPoleEnv",
    "MountainCar": "MountainCarEnv",
    "MountainCarContinuous": "Continuous_MountainCarEnv",
    "Pendulum": "PendulumEnv",
    "Acrobot": "AcrobotEnv",
    # Gymnasium makes these two with a keyword of the base class (continuous=, hardcore=)
    "LunarLander": "LunarLander",
    "LunarLanderContinuous": "LunarLander",
    "BipedalWalker": "BipedalWalker",
    "BipedalWalkerHardcore": "BipedalWalker",
    "CarRacing": "CarRacing",
    "FrozenLake": "FrozenLakeEnv",
    "FrozenLake8x8": "FrozenLakeEnv",
    "Taxi": "TaxiEnv",
    "CliffWalking": "CliffWalkingEnv",
    **{name: f"{name}Env" for name in (
        "Reacher", "Pusher", "InvertedPendulum", "InvertedDoublePendulum", "HalfCheetah", "Hopper", "Swimmer",
        "Walker2d", "Ant", "Humanoid", "HumanoidStandup",
    )},
}  # fmt: skip
_VERSIONED = re.compile(r"^(?P<name>[A-Za-z0-9]+)-v\d+$")
# Where gym and Gymnasium keep the built-in env classes (after the package name).
_ENV_PACKAGES = ("envs.classic_control.", "envs.box2d.", "envs.toy_text.", "envs.mujoco.")

GONE_NAMES = frozenset(name for attributes in GONE.values() for name in attributes)


def class_of_id(env_id: str) -> str | None:
    """The built-in class ``make(env_id)`` builds (``CarRacing-v0`` -> ``CarRacing``), or None."""
    match = _VERSIONED.match(env_id)
    return _ID_CLASSES.get(match["name"]) if match is not None else None


def gone_from_builtin(family: ForwardingFamily, attr: ast.Attribute) -> bool:
    """``env.env.viewer`` where the run shows ``env`` is made as a built-in env whose
    Gymnasium class has no ``viewer``: no receiver reaches it (``.unwrapped.viewer`` raises
    as well), so the read or write is reported, with what replaces the attribute, and left
    as it is. One question per class and attribute."""
    name = attr.attr
    if name not in GONE_NAMES:
        return False
    if name in family.origins.local_wrapper_attributes():
        return False  # a wrapper class of the run may define it and be the one read
    gone = gone_from(family.facts, family.receivers, attr.value, name)
    if gone is None:
        return False
    classname, replacement = gone
    text = dotted_name(attr) or name
    # whichever layer the receiver names: ``.unwrapped`` is that class too
    effect = "AttributeError on every layer" if isinstance(attr.ctx, ast.Load) else "a write sets what nothing reads"
    family.report(
        attr,
        "GM604",
        f"`{text}`: Gymnasium's {classname} has no `{name}` ({effect}); {replacement}",
        kind=FixKind.FLAG,
        question=("GM604", "gone", classname, name),
    )
    return True


def gone_from(facts: ModuleFacts, receivers: Receivers, receiver: ast.expr, name: str) -> tuple[str, str] | None:
    """``(class, what replaces it)`` where every env ``receiver`` may hold (followed below
    ``.env`` and ``.unwrapped``) is made as one built-in class whose Gymnasium version has
    no ``name``; None where any creation is not shown to be such a class (a parameter, an
    id the run cannot read, a class of the project's own)."""
    base = receiver
    while isinstance(base, ast.Attribute) and base.attr in ("env", "unwrapped"):
        base = base.value
    if isinstance(base, ast.Name) and base.id in ("self", "cls"):
        return None  # an env class's own attribute: the custom env rules decide it

    def builtin(call: ast.Call) -> bool:
        return is_make_call(facts, call) or _constructed_class(facts, call) is not None

    finder = facts.memo(("builtin-class-finder", 0), lambda: CreationFinder(facts, receivers, builtin))
    creation = finder.find(base)
    if not creation.found:
        return None
    classes: set[str | None] = set()
    for call in creation.calls:
        if is_make_call(facts, call):
            ids = make_ids(facts, receivers, call)
            classes.update(class_of_id(i) if i is not None else None for i in ids or [None])
        else:
            classes.add(_constructed_class(facts, call))
    if len(classes) != 1:
        return None
    (classname,) = classes
    if classname is None or name not in GONE.get(classname, {}):
        return None
    return classname, GONE[classname][name]


def _constructed_class(facts: ModuleFacts, call: ast.Call) -> str | None:
    """``CarRacing()`` imported from gym's (or Gymnasium's) env packages: its class name."""
    for qualified in facts.qualified_names(call.func):
        rest = N.strip_gym_prefix(qualified) or ""
        last = rest.rsplit(".", 1)[-1]
        if rest.startswith(_ENV_PACKAGES) and last in GONE:
            return last
    return None
