"""Spaces, logger, errors, utils (GM902-GM908): the facts the rules rest on, checked
against the installed gymnasium, and rewrites the fixtures do not show."""

from __future__ import annotations

import inspect

import gymnasium
import numpy as np
import pytest
from gymnasium.spaces import Box
from gymnasium.utils.env_checker import check_env

from gymmigrate.engine import transform_source
from gymmigrate.rules.spaces_logger import (
    KEPT_ERRORS,
    KEPT_LEVELS,
    REMOVED_ERRORS,
    REMOVED_LEVELS,
    REMOVED_LOG_FUNCTIONS,
    SET_LEVEL,
)


def test_logger_names() -> None:
    for name in [*REMOVED_LEVELS, *SET_LEVEL, *REMOVED_LOG_FUNCTIONS, "MIN_LEVEL"]:
        assert not hasattr(gymnasium.logger, name), name
    for name in KEPT_LEVELS:
        assert hasattr(gymnasium.logger, name)
    assert gymnasium.logger.ERROR == 40 and gymnasium.logger.WARN == 30
    assert hasattr(gymnasium.logger, "min_level")


def test_error_classes() -> None:
    assert KEPT_ERRORS <= set(dir(gymnasium.error))
    assert not set(REMOVED_ERRORS) & set(dir(gymnasium.error))


def test_box_lists_raise_and_arrays_with_the_box_dtype_do_not() -> None:
    with pytest.raises(ValueError):
        Box([0.0, 0.0], [1.0, 1.0])
    with pytest.raises(ValueError):
        Box(low=[0, 0], high=[1, 1], shape=(2,))
    with pytest.raises(ValueError):
        Box(0, 1, (2,), dtype=None)
    rewritten = Box(np.array([0.0, 0.0], dtype=np.float32), np.array([1.0, 1.0], dtype=np.float32))
    assert rewritten == Box(0.0, 1.0, (2,), dtype=np.float32)


def test_check_env_still_accepts_but_ignores_warn() -> None:
    parameters = inspect.signature(check_env).parameters
    assert list(parameters)[:2] == ["env", "warn"]
    assert parameters["warn"].default is None


def test_space_seed_returns_an_int() -> None:
    assert isinstance(Box(0, 1, (2,)).seed(3), int)


NOOPS = [
    pytest.param(
        "import gymnasium as gym\nimport mylib\nmylib.logger.set_level(10)\nmylib.error.Unregistered\n",
        id="another library's logger and errors",
    ),
    pytest.param(
        "import gymnasium as gym\nfrom mylib.spaces import Box\nb = Box([0, 0], [1, 1])\n",
        id="another library's Box",
    ),
    pytest.param(
        "import gymnasium as gym\nfrom gymnasium.utils.env_checker import check_env\ncheck_env(env, skip_render_check=True)\n",
        id="check_env without warn",
    ),
]


@pytest.mark.parametrize("source", NOOPS)
def test_noops(source: str) -> None:
    result = transform_source(source.encode(), "case.py")
    assert result.rewritten.decode() == source
    assert not [f for f in result.findings if f.rule.startswith("GM9")]


def test_set_level_inside_an_expression_is_reported() -> None:
    source = "import gymnasium as gym\nok = gym.logger.set_level(40) or True\n"
    result = transform_source(source.encode(), "case.py")
    assert result.rewritten.decode() == source
    assert [(f.rule, f.kind.value) for f in result.findings] == [("GM906", "flag")]
