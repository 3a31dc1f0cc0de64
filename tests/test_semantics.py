"""Migrated programs compute what the legacy ones computed (RL semantics, not only syntax).

Each legacy program runs against a small stand-in for legacy Gym written here (a
four-value ``step``, a ``TimeLimit`` that ends episodes with ``done=True`` and sets
``info["TimeLimit.truncated"]``), so no old gym is needed; its migration runs against the
installed Gymnasium 1.4 with the same dynamics. The numbers they compute are compared.
"""

from __future__ import annotations

import sys
import textwrap
import types
from typing import Any

import gymnasium
import numpy as np
import pytest

from gymmigrate.engine import transform_source

LIMIT = 6  # steps before the time limit cuts an episode
ENV_ID = "SemanticsWalk-v0"


# -- the same dynamics, legacy and Gymnasium ------------------------------------------------


class _Walk:
    """Walks one cell per step; odd episodes reach the goal (terminal) after 4 steps, even
    ones never do and are cut by the time limit. Rewards depend on the position. Every
    third step loses a life (for the life-loss wrappers); the game is over with no lives."""

    def _start(self) -> np.ndarray:
        self.episode = getattr(self, "episode", -1) + 1
        self.position = 0
        self.lives = 3
        return np.array([0.0])

    def _move(self, action: int) -> tuple[np.ndarray, float, bool, dict[str, Any]]:
        self.position += 1
        if self.position % 3 == 0:
            self.lives -= 1
        goal = 4 if self.episode % 2 else 100
        over = self.position >= goal or self.lives == 0
        reward = float(self.position) * (1.0 + action)
        return np.array([float(self.position)]), reward, over, {"lives": self.lives}


class LegacyWalk(_Walk):
    def reset(self) -> np.ndarray:
        return self._start()

    def step(self, action: int) -> tuple[np.ndarray, float, bool, dict[str, Any]]:
        return self._move(action)


class LegacyTimeLimit:
    """gym 0.21's TimeLimit: ``done=True`` at the limit, and the info key."""

    def __init__(self, env: LegacyWalk, limit: int) -> None:
        self.env, self.limit, self.elapsed = env, limit, 0

    def __getattr__(self, name: str) -> Any:
        return getattr(self.env, name)

    def reset(self, **kwargs: Any) -> np.ndarray:
        self.elapsed = 0
        return self.env.reset(**kwargs)

    def step(self, action: int) -> tuple[np.ndarray, float, bool, dict[str, Any]]:
        obs, reward, done, info = self.env.step(action)
        self.elapsed += 1
        if self.elapsed >= self.limit:
            info["TimeLimit.truncated"] = not done
            done = True
        return obs, reward, done, info


class LegacyWrapper:
    def __init__(self, env: Any) -> None:
        self.env = env

    def __getattr__(self, name: str) -> Any:
        return getattr(self.env, name)

    def step(self, action: int) -> Any:
        return self.env.step(action)

    def reset(self, **kwargs: Any) -> Any:
        return self.env.reset(**kwargs)


def legacy_gym() -> types.ModuleType:
    module = types.ModuleType("gym")
    module.Env = LegacyWalk  # type: ignore[attr-defined]
    module.Wrapper = LegacyWrapper  # type: ignore[attr-defined]
    module.make = lambda env_id: LegacyTimeLimit(LegacyWalk(), LIMIT)  # type: ignore[attr-defined]
    return module


class GymnasiumWalk(_Walk, gymnasium.Env):
    observation_space = gymnasium.spaces.Box(0.0, 100.0, (1,))
    action_space = gymnasium.spaces.Discrete(2)

    def reset(self, *, seed: int | None = None, options: dict | None = None) -> tuple[np.ndarray, dict]:
        super().reset(seed=seed)
        return self._start(), {"lives": 3}

    def step(self, action: int) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        obs, reward, terminated, info = self._move(action)
        return obs, reward, terminated, False, info


if ENV_ID not in gymnasium.registry:
    gymnasium.register(ENV_ID, entry_point=GymnasiumWalk, max_episode_steps=LIMIT, disable_env_checker=True)


# -- running both programs ---------------------------------------------------------------------


def run_legacy(source: str, function: str, monkeypatch: pytest.MonkeyPatch, *args: Any) -> Any:
    with monkeypatch.context() as patch:
        patch.setitem(sys.modules, "gym", legacy_gym())
        namespace: dict[str, Any] = {}
        exec(compile(source, "legacy_program.py", "exec"), namespace)
        return namespace[function](*args)


def migrate(source: str) -> tuple[str, list[tuple[int, str, str, str]]]:
    result = transform_source(source.encode(), "program.py")
    text = result.rewritten.decode()
    assert "import gymnasium as gym" in text and "import gym\n" not in text
    return text, [(f.line, f.rule, f.kind.value, f.tier.value) for f in result.findings]  # type: ignore[union-attr]


def run_migrated(text: str, function: str, *args: Any) -> Any:
    namespace: dict[str, Any] = {}
    exec(compile(text, "migrated_program.py", "exec"), namespace)
    return namespace[function](*args)


# -- GM302: on-policy rollouts keep the episode boundary ---------------------------------------

GAE_ROLLOUT = textwrap.dedent(
    """
    import gym
    import numpy as np


    def advantages(horizon=40, gamma=0.9, lam=0.8):
        env = gym.make("SemanticsWalk-v0")
        obs = env.reset()
        rewards, values, dones = [], [], []
        for t in range(horizon):
            value = 0.5 * float(obs[0]) + 1.0
            obs, reward, done, info = env.step(t % 2)
            rewards.append(reward)
            values.append(value)
            dones.append(done)
            if done:
                obs = env.reset()
        result = np.zeros(horizon)
        last = 0.0
        for t in reversed(range(horizon - 1)):
            next_non_terminal = 1.0 - dones[t]
            delta = rewards[t] + gamma * values[t + 1] * next_non_terminal - values[t]
            last = delta + gamma * lam * next_non_terminal * last
            result[t] = last
        return result
    """
)


def test_on_policy_rollout_keeps_the_legacy_advantages(monkeypatch: pytest.MonkeyPatch) -> None:
    legacy = run_legacy(GAE_ROLLOUT, "advantages", monkeypatch)
    text, findings = migrate(GAE_ROLLOUT)
    assert "dones.append(done)" in text  # the episode boundary, not `terminated`
    assert (15, "GM302", "flag", "review") in findings
    np.testing.assert_allclose(run_migrated(text, "advantages"), legacy)
    # The test tells the two apart: with `terminated` stored, a time-limit cut bootstraps
    # from the first state of the next episode and the advantages change.
    wrong = text.replace("dones.append(done)", "dones.append(terminated)")
    assert not np.allclose(run_migrated(wrong, "advantages"), legacy)


# -- GM302: replay transitions with the next state use `terminated` ----------------------------

REPLAY = textwrap.dedent(
    """
    import gym


    def transitions(steps=30, gamma=0.5):
        env = gym.make("SemanticsWalk-v0")
        state = env.reset()
        memory, targets, cut = [], [], []
        for t in range(steps):
            next_state, reward, done, info = env.step(1)
            memory.append((state, 1, reward, next_state, done))
            targets.append(reward + gamma * (1 - done) * float(next_state[0]))
            cut.append(info.get("TimeLimit.truncated", False))
            state = env.reset() if done else next_state
        return memory, targets, cut
    """
)


def test_replay_transitions_store_terminated_and_bootstrap_at_the_time_limit(monkeypatch: pytest.MonkeyPatch) -> None:
    legacy_memory, legacy_targets, legacy_cut = run_legacy(REPLAY, "transitions", monkeypatch)
    text, findings = migrate(REPLAY)
    assert "memory.append((state, 1, reward, next_state, terminated))" in text
    assert "(1 - terminated)" in text
    assert {(11, "GM302", "assist", "note"), (12, "GM302", "assist", "note")} <= set(findings)
    memory, targets, _ = run_migrated(text, "transitions")
    assert any(legacy_cut), "the time limit must cut an episode in this run"
    for old, new, old_target, new_target, was_cut in zip(legacy_memory, memory, legacy_targets, targets, legacy_cut):
        # the stored flag is the legacy one without time-limit cuts (the migration guide's meaning)
        assert bool(new[4]) == (bool(old[4]) and not was_cut)
        np.testing.assert_allclose(new[3], old[3])
        if not was_cut:
            assert new_target == pytest.approx(old_target)
        else:  # a cut now bootstraps from the next state, as it should
            assert new_target == pytest.approx(old[2] + 0.5 * float(old[3][0]))


# -- GM602: a lost life is a termination -------------------------------------------------------

LIFE_LOSS = textwrap.dedent(
    """
    import gym


    class EndOnLifeLoss(gym.Wrapper):
        def __init__(self, env):
            super().__init__(env)
            self.lives = 0
            self.was_real_done = True

        def step(self, action):
            obs, reward, done, info = self.env.step(action)
            self.was_real_done = done
            lives = info["lives"]
            if lives < self.lives and lives > 0:
                done = True
            self.lives = lives
            return obs, reward, done, info

        def reset(self, **kwargs):
            self.lives = 3
            return self.env.reset(**kwargs)


    def flags(steps=24):
        env = EndOnLifeLoss(gym.make("SemanticsWalk-v0"))
        env.reset()
        seen = []
        for _ in range(steps):
            result = env.step(0)
            seen.append((result[2:-1], env.was_real_done))
            if any(result[2:-1]):
                env.reset()
        return seen
    """
)


def test_life_loss_wrapper_terminates_on_a_lost_life(monkeypatch: pytest.MonkeyPatch) -> None:
    legacy = run_legacy(LIFE_LOSS, "flags", monkeypatch)
    text, findings = migrate(LIFE_LOSS)
    assert "return obs, reward, terminated, truncated, info" in text
    assert (18, "GM602", "assist", "note") in findings
    migrated = run_migrated(text, "flags")
    assert len(migrated) == len(legacy)
    lost_lives = 0
    for ((done,), real_done), ((terminated, truncated), real_over) in zip(legacy, migrated):
        assert (terminated or truncated) == done  # every legacy end is still an end
        assert real_over == real_done  # and the game-over bookkeeping is unchanged
        if done and not real_done:  # a lost life, not a game over
            lost_lives += 1
            assert terminated and not truncated
    assert lost_lives > 0
