"""A plain class around a Gym env (a "duck wrapper": ``self.env`` plus ``__getattr__``)
is migrated with its callers, end to end on Gymnasium 1.4 and ALE: its step returns five
values, a lost life ends the episode as terminated, ``self.env.ale`` reaches the base env
through ``.unwrapped``, and ``reset`` on an instance gives ``(obs, info)``."""

from __future__ import annotations

import types

import pytest

from gymmigrate.engine import transform_source
from tests.fixture_cases import FIXTURES


def _migrated(fixture: str) -> types.ModuleType:
    path = FIXTURES / "rules" / fixture
    result = transform_source(path.read_bytes(), str(path))
    assert result.changed
    module = types.ModuleType(fixture.replace("/", "_")[:-3])
    exec(compile(result.rewritten, str(path), "exec"), module.__dict__)
    return module


def test_a_duck_wrapper_ends_the_episode_on_a_lost_life_as_terminated() -> None:
    pytest.importorskip("ale_py")
    module = _migrated("GM602/duck_wrapper.py")
    env = module.make_env()
    obs, info = env.reset(seed=0)
    assert obs.shape == (210, 160, 3) and isinstance(info, dict)
    lives = env.unwrapped.ale.lives()
    for _ in range(5000):
        result = env.step(1)  # FIRE: the ball is launched, the paddle never moves
        assert len(result) == 5
        _, _, terminated, truncated, _ = result
        if terminated or truncated:
            break
    assert (terminated, truncated) == (True, False)
    assert env.unwrapped.ale.lives() == lives - 1
    env.close()
