"""The one reading of an import name's leading dots (facts/import_roots.py), which every
relative lookup of the run's modules goes through."""

from __future__ import annotations

import pytest

from gymmigrate.facts.import_roots import import_parts


@pytest.mark.parametrize(
    ("qualified", "expected"),
    [
        pytest.param("pkg.envs.Task", (0, ["pkg", "envs", "Task"]), id="absolute name"),
        pytest.param(".core.BaseEnv", (1, ["core", "BaseEnv"]), id="from .core import BaseEnv"),
        pytest.param(".Task", (1, ["Task"]), id="from . import Task"),
        pytest.param("..utils.make_env", (2, ["utils", "make_env"]), id="two levels up"),
        pytest.param(".", (1, []), id="from . import *: the package itself, no empty name"),
        pytest.param("...", (3, []), id="from ... import *"),
        pytest.param("utils", (0, ["utils"]), id="bare module"),
    ],
)
def test_an_import_name_splits_into_its_level_and_dotted_names(qualified: str, expected: tuple[int, list[str]]) -> None:
    assert import_parts(qualified) == expected
