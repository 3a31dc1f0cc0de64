"""Reset and seeding rules (GM201-GM208, GM704) beyond the fixtures.

Fixtures run without options, so ``--seed`` (GM204) is tested here; so is the runtime
contract: a migrated legacy loop, run against Gymnasium, is reproducible.
"""

from __future__ import annotations

import textwrap

import numpy as np
import pytest

from gymmigrate.engine import transform_source
from gymmigrate.options import RewriteOptions
from tests.fixture_cases import RULE_FIXTURES


def migrate(source: str, seed: int | None = None) -> tuple[str, list[tuple[int, str, str]]]:
    result = transform_source(textwrap.dedent(source).encode(), "case.py", RewriteOptions(seed=seed))
    findings = [(f.line, f.rule, f.kind.value) for f in result.findings]
    return result.rewritten.decode(), findings


def ours(findings: list[tuple[int, str, str]]) -> list[tuple[int, str, str]]:
    return [f for f in findings if f[1].startswith("GM20") or f[1] == "GM704"]


# -- --seed N (GM204) -------------------------------------------------------------------------


def test_cli_seed_seeds_the_first_reset_outside_a_loop() -> None:
    out, findings = migrate(
        """\
        import gym

        env = gym.make("CartPole-v1")
        obs = env.reset()
        for episode in range(10):
            obs = env.reset()
        """,
        seed=7,
    )
    assert "obs, info = env.reset(seed=7)\nfor episode in range(10):\n    obs, info = env.reset()\n" in out
    assert (4, "GM204", "assist") in findings


def test_cli_seed_inserts_a_seeding_reset_before_the_loop() -> None:
    out, findings = migrate(
        """\
        import gym

        env = gym.make("CartPole-v1")
        # training
        for episode in range(10):
            obs = env.reset()
        """,
        seed=7,
    )
    assert 'env = gym.make("CartPole-v1")\nenv.reset(seed=7)\n# training\nfor episode in range(10):\n' in out
    assert out.count("seed=7") == 1
    assert (6, "GM204", "assist") in findings


def test_cli_seed_leaves_envs_the_code_seeds_itself() -> None:
    out, findings = migrate(
        """\
        import gym

        env = gym.make("CartPole-v1")
        env.seed(3)
        for episode in range(10):
            obs = env.reset()

        other = gym.make("CartPole-v1")
        obs, info = other.reset(seed=11)
        """,
        seed=7,
    )
    assert "seed=7" not in out
    assert not [f for f in findings if f[1] == "GM204"]


def test_cli_seed_never_touches_sb3_vec_envs() -> None:
    source = """\
        from stable_baselines3.common.env_util import make_vec_env

        vec_env = make_vec_env("CartPole-v1", n_envs=2)
        obs = vec_env.reset()
        """
    out, findings = migrate(source, seed=7)
    assert out == textwrap.dedent(source)
    assert findings == []


def test_cli_seed_leaves_vector_envs_whose_sub_envs_are_seeded() -> None:
    out, _ = migrate(
        """\
        import gym


        def make_env(seed):
            def thunk():
                env = gym.make("CartPole-v1")
                env.seed(seed)
                return env
            return thunk


        envs = gym.vector.SyncVectorEnv([make_env(i) for i in range(2)])
        obs = envs.reset()
        """,
        seed=7,
    )
    assert "seed=7" not in out
    assert "obs, infos = envs.reset()" in out


def test_without_cli_seed_nothing_is_seeded() -> None:
    out, findings = migrate(
        """\
        import gym

        env = gym.make("CartPole-v1")
        obs = env.reset()
        """
    )
    assert "seed" not in out
    assert not [f for f in findings if f[1] == "GM204"]


# -- runtime: the migrated code is reproducible ------------------------------------------------


def _run(code: str) -> list[np.ndarray]:
    namespace: dict[str, object] = {"__name__": "migrated_fixture"}
    exec(compile(code, "migrated_fixture.py", "exec"), namespace)
    return namespace["first_observations"]  # type: ignore[return-value]


def test_migrated_legacy_loop_is_reproducible_on_gymnasium() -> None:
    pytest.importorskip("gymnasium")
    legacy = (RULE_FIXTURES / "GM204" / "legacy_seed_then_loop.py").read_bytes()
    migrated = transform_source(legacy, "legacy_seed_then_loop.py").rewritten.decode()
    # the seed goes to the first iteration's reset only (GM203), no extra episode before the loop
    assert "obs, info = env.reset(seed=42 if episode == 0 else None)" in migrated
    first_run, second_run = _run(migrated), _run(migrated)
    assert len(first_run) == 3
    # Same seed, same episodes, run after run...
    for a, b in zip(first_run, second_run):
        np.testing.assert_array_equal(a, b)
    # ...and the seed was applied once: the episodes differ from each other (GM204).
    assert not np.array_equal(first_run[0], first_run[1])
    assert not np.array_equal(first_run[1], first_run[2])


def test_cli_seed_makes_an_unseeded_loop_reproducible_on_gymnasium() -> None:
    pytest.importorskip("gymnasium")
    legacy = """\
        import gym

        env = gym.make("CartPole-v1")
        first_observations = []
        for episode in range(2):
            obs = env.reset()
            first_observations.append(obs)
        """
    migrated, _ = migrate(legacy, seed=7)
    first_run, second_run = _run(migrated), _run(migrated)
    np.testing.assert_array_equal(first_run[0], second_run[0])
    np.testing.assert_array_equal(first_run[1], second_run[1])
    assert not np.array_equal(first_run[0], first_run[1])


# -- shapes, names and formatting -------------------------------------------------------------------


def test_legacy_vector_make_is_treated_as_a_gym_vector_env() -> None:
    out, findings = migrate(
        """\
        import gym

        envs = gym.vector.make("CartPole-v1", num_envs=4)
        envs.seed(0)
        obs = envs.reset()
        """
    )
    assert "obs, infos = envs.reset(seed=0)" in out
    assert {(4, "GM208", "auto"), (5, "GM704", "auto")} <= set(findings)


def test_info_name_does_not_hide_the_step_info_an_autoreset_returns() -> None:
    out, _ = migrate(
        """\
        import gym


        class AutoReset(gym.Wrapper):
            def step(self, action):
                obs, reward, done, info = self.env.step(action)
                if done:
                    obs = self.env.reset()
                return obs, reward, done, info
        """
    )
    assert "obs, reset_info = self.env.reset()" in out


def test_merged_seed_keeps_its_comment_and_a_multiline_call() -> None:
    out, _ = migrate(
        """\
        import gym

        env = gym.make("CartPole-v1")
        # one seed for the whole run
        env.seed(5)
        obs = env.reset(
            difficulty=2,
        )
        """
    )
    assert out.endswith(
        '# one seed for the whole run\nobs, info = env.reset(\n    difficulty=2,\n    seed=5,\n)\n'
    )


def test_seed_before_a_counted_loop_seeds_only_its_first_reset() -> None:
    # Merged as a plain seed, the loop's reset would reseed every episode (GM204); a standalone
    # reset before the loop would play an extra episode: the first iteration takes the seed.
    out, findings = migrate(
        """\
        import gym

        env = gym.make("CartPole-v1")
        env.seed(5)
        for episode in range(3):
            obs = env.reset()
        """
    )
    assert "env.seed" not in out
    assert "for episode in range(3):\n    obs, info = env.reset(seed=5 if episode == 0 else None)\n" in out
    assert not [f for f in findings if f[1] == "GM204"]


def test_seed_before_an_uncounted_loop_stays_a_reset_of_its_own() -> None:
    out, findings = migrate(
        """\
        import gym

        env = gym.make("CartPole-v1")
        env.seed(5)
        while True:
            obs = env.reset()
        """
    )
    assert "env.reset(seed=5)\nwhile True:\n    obs, info = env.reset()\n" in out
    assert not [f for f in findings if f[1] == "GM204"]


@pytest.mark.parametrize(
    "line",
    [
        "obs, info = env.reset()",
        "obs = env.reset()[0]",
        "obs, info = env.reset(seed=1)",
        "env.reset(seed=1)",
        "env.action_space.seed(1)",
    ],
)
def test_migrated_lines_stay_as_they_are(line: str) -> None:
    source = f'import gymnasium as gym\n\nenv = gym.make("CartPole-v1")\n{line}\n'
    out, findings = migrate(source)
    assert out == source
    assert ours(findings) == []


def test_single_value_use_of_a_seeded_reset_is_reported_not_rewritten() -> None:
    source = 'import gymnasium as gym\n\nenv = gym.make("CartPole-v1")\nobs = env.reset(seed=1)\n'
    out, findings = migrate(source)
    assert out == source
    assert ours(findings) == [(4, "GM201", "flag")]


def test_inserted_and_merged_lines_keep_crlf_line_endings() -> None:
    source = (
        b'import gym\r\n\r\nenv = gym.make("CartPole-v1")\r\nfor ep in range(3):\r\n    obs = env.reset()\r\n'
        b'other = gym.make("CartPole-v1")\r\nother.seed(1)\r\nobs = other.reset()\r\n'
    )
    out = transform_source(source, "case.py", RewriteOptions(seed=3)).rewritten
    assert b"env.reset(seed=3)\r\nfor ep in range(3):\r\n" in out
    assert out.endswith(b'other = gym.make("CartPole-v1")\r\nobs, info = other.reset(seed=1)\r\n')
    assert b"\n" not in out.replace(b"\r\n", b"")
