"""Wrapper rules at runtime: legacy wrappers, rewritten by the whole pipeline, obey Gymnasium.

Each file under ``fixtures/wrappers/`` is a gym 0.21-style wrapper module. It is run
through ``transform_source`` (every pass, in order), loaded as a module, wrapped around
Gymnasium envs (alone and under Gymnasium's own wrappers, which pass ``seed``/``options``
and unpack five values) and stepped for a few episodes. The checks are Gymnasium's
contract: ``reset`` returns ``(obs, info)``, ``step`` returns five values whose flags are
bools. The fixture rules themselves are tested by ``tests/test_rules.py``.
"""

from __future__ import annotations

import types
from collections.abc import Callable
from functools import cache
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.passive_env_checker import (
    env_reset_passive_checker,
    env_step_passive_checker,
)

from gymmigrate.engine import transform_source
from gymmigrate.findings import FixKind

WRAPPER_FIXTURES = Path(__file__).resolve().parent.parent / "fixtures" / "wrappers"
EPISODES = 3
MAX_STEPS_PER_EPISODE = 600


@cache
def migrated_source(name: str) -> str:
    source = (WRAPPER_FIXTURES / name).read_bytes()
    return transform_source(source, name).rewritten.decode()


def load_migrated(name: str) -> types.ModuleType:
    text = migrated_source(name)
    assert "import gym\n" not in text
    module = types.ModuleType(f"migrated_{Path(name).stem}")
    exec(compile(text, name, "exec"), module.__dict__)  # noqa: S102  (our own fixture)
    return module


def check_reset(env: gym.Env, seed: int | None) -> object:
    result = env.reset(seed=seed)
    assert isinstance(result, tuple) and len(result) == 2, f"reset returned {type(result).__name__}"
    obs, info = result
    assert isinstance(info, dict)
    assert np.asarray(obs).shape == env.observation_space.shape
    return obs


def check_step(env: gym.Env, action: object) -> tuple[bool, bool]:
    result = env.step(action)
    assert isinstance(result, tuple) and len(result) == 5, f"step returned {len(result)} values"
    obs, reward, terminated, truncated, info = result
    assert isinstance(terminated, (bool, np.bool_)), type(terminated)
    assert isinstance(truncated, (bool, np.bool_)), type(truncated)
    assert np.isscalar(reward) or np.asarray(reward).shape == ()
    assert isinstance(info, dict)
    assert np.asarray(obs).shape == env.observation_space.shape
    return bool(terminated), bool(truncated)


def run_episodes(env: gym.Env, episodes: int = EPISODES) -> list[int]:
    lengths = []
    env.action_space.seed(0)
    for episode in range(episodes):
        check_reset(env, seed=episode if episode == 0 else None)
        for step in range(1, MAX_STEPS_PER_EPISODE + 1):  # noqa: B007  (the episode's length, read after the loop)
            terminated, truncated = check_step(env, env.action_space.sample())
            if terminated or truncated:
                break
        lengths.append(step)
    env.close()
    return lengths


# (fixture, class, keyword arguments, env id)
CASES: list[tuple[str, str, dict[str, object], str]] = [
    ("obs_normalize.py", "NormalizeObservations", {}, "CartPole-v1"),
    ("obs_normalize.py", "NormalizeObservations", {"clip_obs": 5.0}, "Pendulum-v1"),
    ("reward_scale.py", "ScaleReward", {"scale": 0.5}, "CartPole-v1"),
    ("reward_scale.py", "ScaleReward", {}, "MountainCar-v0"),
    ("step_limit.py", "EpisodeStepLimit", {"max_steps": 7}, "CartPole-v1"),
    ("step_limit.py", "EpisodeStepLimit", {"max_steps": 30}, "Acrobot-v1"),
    ("noop_reset.py", "RandomNoopsOnReset", {"noop_max": 5}, "CartPole-v1"),
    ("noop_reset.py", "FireOnReset", {}, "CartPole-v1"),
    ("frame_skip.py", "RepeatAndMax", {"skip": 3}, "CartPole-v1"),
    ("frame_skip.py", "CastObservation", {}, "Pendulum-v1"),
]

# Gymnasium's own wrappers on top: they call reset(seed=..., options=...) and unpack five values.
OUTER: dict[str, Callable[[gym.Env], gym.Env]] = {
    "alone": lambda env: env,
    "RecordEpisodeStatistics": gym.wrappers.RecordEpisodeStatistics,
    "TimeLimit": lambda env: gym.wrappers.TimeLimit(env, max_episode_steps=20),
}


@pytest.mark.parametrize("outer", OUTER, ids=list(OUTER))
@pytest.mark.parametrize("fixture,cls,kwargs,env_id", CASES, ids=[f"{c[1]}-{c[3]}" for c in CASES])
def test_migrated_wrapper_runs(fixture: str, cls: str, kwargs: dict[str, object], env_id: str, outer: str) -> None:
    module = load_migrated(fixture)
    env = OUTER[outer](getattr(module, cls)(gym.make(env_id), **kwargs))
    lengths = run_episodes(env)
    assert len(lengths) == EPISODES


@pytest.mark.parametrize("fixture,cls,kwargs,env_id", CASES, ids=[f"{c[1]}-{c[3]}" for c in CASES])
def test_migrated_wrapper_passes_gymnasium_checks(fixture: str, cls: str, kwargs: dict[str, object], env_id: str) -> None:
    """Gymnasium's passive checker, applied to the migrated wrapper's own outputs."""
    module = load_migrated(fixture)
    env = getattr(module, cls)(gym.make(env_id), **kwargs)
    env_reset_passive_checker(env, seed=0)
    env.action_space.seed(0)
    env_step_passive_checker(env, env.action_space.sample())


def test_step_limit_ends_episodes_as_truncation() -> None:
    module = load_migrated("step_limit.py")
    env = module.EpisodeStepLimit(gym.make("CartPole-v1"), max_steps=5)
    env.reset(seed=3)
    for _ in range(4):
        terminated, truncated = check_step(env, 0 if _ % 2 else 1)
        assert not (terminated or truncated)
    terminated, truncated = check_step(env, 1)
    assert truncated and not terminated


def test_noop_reset_seeds_reproducibly() -> None:
    module = load_migrated("noop_reset.py")
    first = module.RandomNoopsOnReset(gym.make("CartPole-v1"), noop_max=8)
    second = module.RandomNoopsOnReset(gym.make("CartPole-v1"), noop_max=8)
    np.testing.assert_array_equal(first.reset(seed=11)[0], second.reset(seed=11)[0])


def test_rewrite_reports_review_items() -> None:
    """The changes whose meaning may shift are on the review list, not silent."""
    source = (WRAPPER_FIXTURES / "step_limit.py").read_bytes()
    findings = transform_source(source, "step_limit.py").findings
    kinds = {(f.rule, f.kind) for f in findings}
    assert ("GM602", FixKind.ASSIST) in kinds  # the wrapper's own end condition became truncation
    assert ("GM601", FixKind.ASSIST) in kinds  # reset(self) took seed/options


def test_the_normalize_statistics_of_a_wrapper_are_not_forwarded() -> None:
    """fixtures/rules/GM604/normalize_statistics_not_forwarded: ``self.return_rms`` holds a
    RunningMeanStd, not an env: its ``update``/``var`` stay plain attribute reads, and the
    migrated wrapper steps on Gymnasium 1.4."""
    import runpy
    from pathlib import Path

    import gymnasium

    expected = Path(__file__).resolve().parent.parent / "fixtures" / "rules" / "GM604" / "normalize_statistics_not_forwarded.expected.py"
    assert "get_wrapper_attr" not in expected.read_text()
    namespace = runpy.run_path(str(expected))
    env = namespace["MONormalizeReward"](gymnasium.make("CartPole-v1"), 0)
    env.reset(seed=0)
    assert len(env.step(0)) == 5


def test_a_pytest_fixture_env_is_traced_and_its_tests_pass_on_gymnasium(tmp_path) -> None:
    """fixtures/rules/GM604/pytest_fixture_env: a test's ``env`` parameter is what the
    module's fixture of that name yields (``gym.make``): its reset, step and attributes
    read through the wrappers are migrated, and the migrated tests pass under pytest."""
    import shutil
    import subprocess
    import sys
    from pathlib import Path

    expected = Path(__file__).resolve().parent.parent / "fixtures" / "rules" / "GM604" / "pytest_fixture_env.expected.py"
    shutil.copy(expected, tmp_path / "test_pair_game.py")
    done = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", str(tmp_path)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "2 passed" in done.stdout


# -- GM618: a RecordEpisodeStatistics subclass that computes its own statistics ----------

_STATISTICS = WRAPPER_FIXTURES.parent / "rules" / "GM618" / "own_statistics.py"


def _migrated_statistics(options: object = None) -> types.ModuleType:
    from gymmigrate.options import RewriteOptions

    text = transform_source(_STATISTICS.read_bytes(), str(_STATISTICS), options or RewriteOptions()).rewritten.decode()
    module = types.ModuleType("migrated_own_statistics")
    exec(compile(text, str(_STATISTICS), "exec"), module.__dict__)  # noqa: S102  (our own fixture)
    return module


def _two_rewards(env_id: str) -> gym.Env:
    """A Gymnasium env whose reward is a vector of two (as multi-objective envs return)."""
    return gym.wrappers.TransformReward(gym.make(env_id), lambda r: np.array([r, -2.0 * r], dtype=np.float32))


def test_a_statistics_subclass_runs_on_gymnasium_with_gym_0_26_state() -> None:
    module = _migrated_statistics()
    env = module.VectorRewardStatistics(_two_rewards("CartPole-v1"), reward_dim=2)
    env.action_space.seed(0)
    for episode in range(3):
        env.reset(seed=episode)
        steps, ended = 0, False
        while not ended:
            obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
            steps += 1
            ended = terminated or truncated
        assert isinstance(terminated, bool) and isinstance(truncated, bool)  # one env: the flags, not lists
        stats = info["episode"]
        assert stats["r"].shape == (2,) and stats["r"].tolist() == [float(steps), -2.0 * steps]
        assert stats["l"] == steps and isinstance(stats["l"], np.int32)
        assert isinstance(stats["t"], float) and stats["t"] >= 0
    assert env.episode_count == 3 and len(env.return_queue) == 3 and env.num_envs == 1
    assert env.is_vector_env is False


def test_a_statistics_subclass_without_a_reset_gets_one() -> None:
    module = _migrated_statistics()
    env = module.EpisodeTimer(gym.make("CartPole-v1"))
    env.reset(seed=0)
    env.action_space.seed(0)
    steps, info, ended = 0, {}, False
    while not ended:
        _, _, terminated, truncated, info = env.step(env.action_space.sample())
        steps += 1
        ended = terminated or truncated
    assert info["length"] == steps and info["elapsed"] >= 0
    obs, info = env.reset(seed=1)  # zeroes the per-env lengths again, returns Gymnasium's pair
    assert env.episode_lengths.tolist() == [0] and isinstance(info, dict)


def test_without_gm618_the_statistics_subclass_lacks_gym_0_26_state() -> None:
    from gymmigrate.options import RewriteOptions
    from gymmigrate.rules import all_rules
    from gymmigrate.selection import Selection

    codes = [rule.code for rule in all_rules()]
    options = RewriteOptions(selection=Selection.from_selectors(ignore=["GM618"], codes=codes))
    module = _migrated_statistics(options)
    env = module.VectorRewardStatistics(_two_rewards("CartPole-v1"))
    with pytest.raises(AttributeError, match="num_envs"):
        env.reset(seed=0)


def test_a_statistics_subclass_still_refuses_a_vector_env() -> None:
    """Gymnasium 1.x's single-env base: the vector wrapper is another class (GM708 reports the use)."""
    module = _migrated_statistics()
    envs = gym.vector.SyncVectorEnv([lambda: _two_rewards("CartPole-v1")] * 2)
    with pytest.raises(TypeError, match="Expected env to be a `gymnasium.Env`"):
        module.VectorRewardStatistics(envs)


_RULE_FIXTURES = WRAPPER_FIXTURES.parent / "rules"


def _run_rule_fixture(relative: str) -> dict:
    path = _RULE_FIXTURES / relative
    text = transform_source(path.read_bytes(), str(path)).rewritten.decode()
    assert "import gymnasium as gym\n" in text
    namespace: dict = {}
    exec(compile(text, str(path), "exec"), namespace)  # noqa: S102  (our own fixture)
    return namespace


def test_a_batch_kept_on_its_stacked_step_still_runs_on_gymnasium() -> None:
    """A batch of envs keeps its four stacked fields and its reset's stacked observations (its
    own API, which its callers keep reading); its sub-envs' calls are Gymnasium's, and each
    env's end (terminated or truncated, a time-limit cut included) still resets that env."""
    namespace = _run_rule_fixture("GM504/batched_env_stacked.py")
    fleet = namespace["fleet"]
    frames = fleet.reset()
    assert frames.shape == (3, 4)
    ended = 0
    for _ in range(200):
        frames, gains, ends, _ = fleet.step([0, 1, 0])
        assert frames.shape == (3, 4) and gains.shape == (3,) and ends.shape == (3,)
        ended += int(ends.sum())
    assert ended > 0


def test_a_wrapper_over_a_batch_of_one_keeps_the_batch_shape_on_gymnasium() -> None:
    namespace = _run_rule_fixture("GM602/batched_single_wrapper.py")
    solo = namespace["solo"]
    frame = solo.reset(seed=0)  # the outer Gymnasium wrapper passes seed and options on
    assert frame.shape == (1, 4)
    for _ in range(100):
        frame, gain, end, note = solo.step([1])
        assert frame.shape == (1, 4) and end.shape == (1,) and isinstance(note, list)
    assert solo.finished is not None


def test_elementwise_done_of_a_wrapper_that_reads_batched_flags() -> None:
    """``terminated | truncated``: a bool on one env (the ``isinstance(done, bool)`` test still
    holds), elementwise where arrays come through (``or`` raises there)."""
    namespace = _run_rule_fixture("GM301/batched_flags_elementwise.py")
    env = namespace["EndCounter"](gym.make("CartPole-v1"))
    env.reset(seed=0)
    for _ in range(60):
        *_, terminated, truncated, _ = env.step(0)
        if terminated or truncated:
            env.reset()
    assert env.count >= 1


def test_a_wrapper_forwarding_its_attributes_constructs_once_its_arguments_are_recorded() -> None:
    """GM617 records the arguments of a wrapper with its own ``__getattr__`` after the base
    ``__init__``: recorded first, the mixin's ``hasattr`` check reaches ``__getattr__`` before
    ``self.env`` exists, and that recurses."""
    namespace = _run_rule_fixture("GM617/forwarding_getattr.py")
    tasked, counted = namespace["tasked"], namespace["counted"]
    assert tasked.tasks == 5 and counted.count == 2
    assert tasked.spec.additional_wrappers[-1].kwargs == {"tasks": 5}

    class RecordedFirst(namespace["Tasked"]):
        def __init__(self, env, tasks: int = 3):
            gym.utils.RecordConstructorArgs.__init__(self, tasks=tasks)
            super().__init__(env, tasks)

    with pytest.raises(RecursionError):
        RecordedFirst(gym.make("CartPole-v1"))
