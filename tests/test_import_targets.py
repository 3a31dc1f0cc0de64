"""Every import the rules write exists in the installed Gymnasium 1.4; the rest is reported.

A rewritten ``from gym.envs import atari`` -> ``from gymnasium.envs import atari`` would
raise ImportError where the legacy line worked. The tables the rules rename by are
imported here for real (modules whose optional dependency, Box2D or MuJoCo, is not
installed must still be found), and removed paths must be reported, never renamed.
"""

from __future__ import annotations

import ast
import importlib
import subprocess
import sys

import gymnasium
import pytest

from gymmigrate.engine import transform_source
from gymmigrate.rules import gymnasium_api
from gymmigrate.rules.imports.table import (
    LEGACY_WRAPPER_MODULES,
    MOVED_NAMES,
    migrated_path,
)
from gymmigrate.rules.wrapper_usage import tables
from tests.gymnasium_api_table import installed_modules, table


def test_the_shipped_table_is_the_installed_gymnasium() -> None:
    assert gymnasium.__version__ == gymnasium_api.GYMNASIUM_VERSION
    shipped = {module: gymnasium_api.names_of(module) for module in gymnasium_api.GYMNASIUM_API}
    assert shipped == table(), "regenerate rules/gymnasium_api.py with `python -m tests.gymnasium_api_table`"


def importable(module: str) -> bool:
    """The module is there: it imports, or only an optional dependency of it is missing."""
    try:
        importlib.import_module(module)
    except gymnasium.error.DependencyNotInstalled:
        return module in installed_modules()  # its source file is there
    except ImportError:
        return False
    return True


def rewrite_targets() -> list[str]:
    """Every module path the import tables rewrite to."""
    targets = {"gymnasium." + migrated_path(f"wrappers.{module}") for module in LEGACY_WRAPPER_MODULES}
    targets |= set(MOVED_NAMES.values())
    targets.add("gymnasium." + migrated_path("wrappers.vector_list_info"))
    return sorted(targets)


@pytest.mark.parametrize("module", rewrite_targets())
def test_every_rewritten_module_imports(module: str) -> None:
    assert importable(module)


def test_every_wrapper_name_the_rules_write_exists() -> None:
    import gymnasium.wrappers
    import gymnasium.wrappers.vector

    written = set(tables.RENAMED.values()) | set(tables.EXPERIMENTAL_SPECIAL.values()) | tables.SINGLE_ENV_WRAPPERS
    # ``__all__``: the array-conversion wrappers import their optional dependency lazily
    missing = [name for name in sorted(written) if name not in gymnasium.wrappers.__all__]
    missing += [f"vector.{name}" for name in sorted(tables.VECTOR_WRAPPERS) if name not in gymnasium.wrappers.vector.__all__]
    assert not [name for name in ("TimeLimit", "RecordVideo", "FrameStackObservation") if not hasattr(gymnasium.wrappers, name)]
    assert not missing


def test_the_atari_hint_names_a_working_route() -> None:
    # in a fresh interpreter: other tests swap the process-wide registry
    code = "import gymnasium, ale_py; gymnasium.register_envs(ale_py); assert 'ALE/Pong-v5' in gymnasium.registry"
    subprocess.run([sys.executable, "-c", code], check=True, timeout=60)


# Legacy paths (gym 0.21-0.26) that Gymnasium 1.4 does not have.
REMOVED = [
    ("from gym.envs import atari", "ale_py"),
    ("import gym.envs.atari", "ale_py"),
    ("from gym.envs.atari.environment import AtariEnv", "ale_py"),
    ("from gym.envs import robotics", "gymnasium_robotics"),
    ("from gym.envs.robotics import FetchEnv", "gymnasium_robotics"),
    ("from gym.envs.mujoco.half_cheetah_v3 import HalfCheetahEnv", "half_cheetah_v5"),
    ("import gym.envs.mujoco.hopper", "hopper_v5"),
    ("from gym.envs.mujoco import walker2d_v3", "walker2d_v5"),
    ("from gym.envs.unittest import CubeCrash", "unittest"),
    ("from gym.envs.toy_text.discrete import DiscreteEnv", "DiscreteEnv"),
    ("import gym.utils.closer", "gymnasium.utils.closer"),
    ("from gym.vector.utils.spaces import batch_space", "gymnasium.vector.utils.spaces"),
]


@pytest.mark.parametrize(("line", "advice"), REMOVED)
def test_removed_paths_are_reported_not_renamed(line: str, advice: str) -> None:
    source = f"import gym\n{line}\n"
    result = transform_source(source.encode(), "removed.py")
    assert line in result.rewritten.decode().splitlines(), "the import must stay as it is"
    reported = [f for f in result.findings if f.rule == "GM105" and f.line == 2]
    assert reported and advice in reported[0].message and reported[0].needs_review


KEPT = [
    "import gym.spaces",
    "from gym.envs.mujoco.half_cheetah_v4 import HalfCheetahEnv",
    "from gym.envs.classic_control import CartPoleEnv",
    "from gym.wrappers.time_limit import TimeLimit",
    "from gym.utils import seeding",
    "from gym.envs.registration import register",
    "from gym.envs.box2d.lunar_lander import LunarLander",
    "from gym.vector.utils import batch_space",
]


@pytest.mark.parametrize("line", KEPT)
def test_rewritten_imports_exist_in_gymnasium(line: str) -> None:
    result = transform_source(f"import gym\n{line}\n".encode(), "kept.py")
    statement = ast.parse(result.rewritten.decode()).body[1]
    assert not [f for f in result.findings if f.rule == "GM105"]
    if isinstance(statement, ast.ImportFrom):
        assert statement.module is not None and importable(statement.module)
        module = statement.module
        for alias in statement.names:
            assert gymnasium_api.has_name(module, alias.name), f"{module} has no {alias.name}"
    else:
        assert isinstance(statement, ast.Import)
        assert all(importable(alias.name) for alias in statement.names)


def test_the_gym_only_packages_the_facts_know_are_the_libraries_gm107_reports() -> None:
    from gymmigrate.facts.names import GYM_ONLY_PACKAGES
    from gymmigrate.rules.imports.libraries import (
        GYM_ONLY_LIBRARIES,
        LEGACY_API_CONSUMERS,
    )

    # The libraries that only drive the envs handed to them are reported, but their
    # objects are no envs: the facts leave them out.
    assert LEGACY_API_CONSUMERS <= set(GYM_ONLY_LIBRARIES)
    assert set(GYM_ONLY_LIBRARIES) - LEGACY_API_CONSUMERS == GYM_ONLY_PACKAGES


def test_missing_names_are_missing_and_left_to_families_that_handle_them() -> None:
    """The names the imports rules leave to other families are the ones those families
    rename or report, and every name in these tables really is absent from Gymnasium."""
    from gymmigrate.rules.imports.table import (
        MISSING_NAMES,
        RENAMED_ELSEWHERE,
        USES_REPORTED_ELSEWHERE,
    )
    from gymmigrate.rules.rng import REMOVED_SEEDING
    from gymmigrate.rules.spaces_logger import REMOVED_ERRORS, REMOVED_LOGGER_NAMES

    assert RENAMED_ELSEWHERE["gymnasium.wrappers"] == set(tables.RENAMED) | {"Monitor"}
    assert RENAMED_ELSEWHERE["gymnasium.logger"] == REMOVED_LOGGER_NAMES | {"MIN_LEVEL"}
    assert RENAMED_ELSEWHERE["gymnasium.error"] == set(REMOVED_ERRORS)
    assert USES_REPORTED_ELSEWHERE["gymnasium.utils.seeding"] == REMOVED_SEEDING
    pairs = [(m, n) for m, names in {**RENAMED_ELSEWHERE, **USES_REPORTED_ELSEWHERE}.items() for n in names]
    pairs += list(MISSING_NAMES)
    for module, name in pairs:
        assert not hasattr(importlib.import_module(module), name), f"{module}.{name} exists"


def test_a_name_gymnasium_lacks_is_reported_not_moved() -> None:
    result = transform_source(b"import gym\nfrom gym.utils import reraise, seeding\n", "missing.py")
    assert "from gym.utils import reraise, seeding" in result.rewritten.decode()
    reported = [f for f in result.findings if f.rule == "GM105" and f.line == 2]
    assert reported and "from e" in reported[0].message and reported[0].needs_review
