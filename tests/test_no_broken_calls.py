"""No broken calls, executed: a rewrite that changes or removes a method leaves every
caller in the file matching it.

Each fixture is migrated by the engine and the result is run against Gymnasium 1.x:
a helper that needs arguments is not called without them, a forwarding render to inner
envs no longer hands them a mode, and a ``seed()`` that an untraced ``env.seed(3)`` may
still call is kept (while one whose callers are all migrated goes).
"""

from __future__ import annotations

import sys
import types

import gymnasium
import pytest

from gymmigrate.engine import transform_source
from tests.fixture_cases import RULE_FIXTURES


def migrated_module(rule: str, case: str, monkeypatch: pytest.MonkeyPatch) -> dict[str, object]:
    path = RULE_FIXTURES / rule / f"{case}.py"
    result = transform_source(path.read_bytes(), str(path))
    # A stand-in for a library the fixture imports only to make the file "not Gym-only".
    monkeypatch.setitem(sys.modules, "stable_baselines3", types.SimpleNamespace(PPO=object))
    namespace: dict[str, object] = {"__name__": f"migrated_{case}"}
    exec(compile(result.rewritten, str(path), "exec"), namespace)  # noqa: S102 (our own fixture)
    return namespace


def test_reset_does_not_call_an_info_helper_without_its_arguments(monkeypatch) -> None:
    module = migrated_module("GM501", "info_helper_with_arguments", monkeypatch)
    env = module["MultiAgentEnv"]()
    obs, info = env.reset(seed=0)
    assert len(obs) == 2 and info == {}
    obs, reward, terminated, truncated, infos = env.step(0)
    assert infos == [{"agent": 0}, {"agent": 1}]


def test_forwarding_render_no_longer_passes_a_mode_to_the_inner_envs(monkeypatch) -> None:
    module = migrated_module("GM405", "forwarding_render", monkeypatch)
    env = module["Many"](render_mode="rgb_array")
    env.reset(seed=0)
    frames = env.render()
    # Before the fix the mode reached the inner render as `close` and nothing was drawn
    # (or, on an inner Gymnasium env, render() raised TypeError).
    assert frames == [None, None], "the inner envs were made without a render mode, so they draw nothing"
    env.envs = [module["Inner"](render_mode="rgb_array") for _ in range(2)]
    assert [frame.shape for frame in env.render()] == [(4, 4, 3), (4, 4, 3)]


def test_seed_kept_while_an_untraced_caller_may_use_it(monkeypatch) -> None:
    module = migrated_module("GM503", "seed_kept_for_untraced_caller", monkeypatch)
    dice = [module["Dice"](), module["Dice"]()]
    module["seed_all"](dice)  # `env.seed(3)` on instances of the class: no AttributeError
    first, _ = dice[0].reset()
    second, _ = dice[1].reset()
    assert first == second, "both were seeded with 3"
    assert isinstance(module["main"](), int)
    assert issubclass(module["Dice"], gymnasium.Env)


def test_seed_removed_when_its_caller_is_migrated(monkeypatch) -> None:
    module = migrated_module("GM503", "seed_caller_in_file_migrated", monkeypatch)
    assert not hasattr(module["Dice"], "seed")
    assert module["main"]() == module["main"](), "main() seeds through reset(seed=3)"


def test_render_keeps_its_mode_while_an_untraced_caller_passes_one(monkeypatch) -> None:
    module = migrated_module("GM405", "render_kept_for_untraced_caller", monkeypatch)
    picture = module["main"]()  # `env.render(mode="rgb_array")` on a GridEnv: no TypeError
    assert picture.shape == (4, 4, 3)
    env = module["GridEnv"]()  # made without a render_mode: a mode passed still wins
    assert [frame.shape for frame in module["frames"](env)] == [(4, 4, 3), (4, 4, 3)]
    assert isinstance(env, gymnasium.Env)
    obs, info = env.reset(seed=0)
    assert obs == 0 and info == {}
    assert env.render() is None, "no mode passed, no render_mode: draws nothing (Gymnasium's convention)"
    # Gymnasium's wrappers call render() without arguments: the env's own mode is used.
    gymnasium.register(id="GridKeepsMode-v0", entry_point=module["GridEnv"])
    try:
        wrapped = gymnasium.make("GridKeepsMode-v0", render_mode="rgb_array")
        wrapped.reset(seed=0)
        assert wrapped.render().shape == (4, 4, 3)
    finally:
        gymnasium.registry.pop("GridKeepsMode-v0")


def test_seed_kept_while_a_subclass_calls_it(monkeypatch) -> None:
    module = migrated_module("GM503", "seed_kept_for_subclass_call", monkeypatch)
    child = module["Child"]()  # its __init__ calls self.seed(7), inherited from Base
    obs, info = child.reset()
    assert 0 <= obs < 6 and info == {}


def test_render_migrates_beside_a_render_that_draws_into_an_array(monkeypatch) -> None:
    """``obj.render(canvas)`` with ``canvas = np.zeros(...)`` is no Gym render call: the env
    class's render(mode) migrates, and the tile still draws."""
    module = migrated_module("GM405", "render_beside_array_draws", monkeypatch)
    env = module["Board"](render_mode="rgb_array")
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (2, 2, 3) and frame[0, 0, 0] == 255
    assert module["Board"]().render() is None, "no render_mode: draws nothing (Gymnasium's convention)"
    gymnasium.register(id="BoardBesideArrayDraws-v0", entry_point=module["Board"])
    try:
        made = gymnasium.make("BoardBesideArrayDraws-v0", render_mode="rgb_array")
        made.reset(seed=0)
        made.step(1)
        assert made.render().shape == (2, 2, 3)
    finally:
        gymnasium.registry.pop("BoardBesideArrayDraws-v0")
