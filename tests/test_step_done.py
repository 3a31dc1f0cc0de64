"""Step and done semantics (GM301-GM304, GM703) and removed make() keywords (GM305, GM801).

The fixtures under fixtures/rules/ pin whole files; these tests pin the corner cases
one by one (pyupgrade style: a table of rewrites and a table of no-ops) and then run a
rewritten legacy episode loop against the installed Gymnasium to show that the
rewrite means what the legacy code meant.
"""

from __future__ import annotations

import ast
import json
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from gymmigrate.engine import transform_source


def rewrite(source: str) -> tuple[str, list[tuple[int, str, str]]]:
    result = transform_source(textwrap.dedent(source).encode(), "case.py")
    text = result.rewritten.decode()
    ast.parse(text)
    again = transform_source(result.rewritten, "case.py")
    assert again.rewritten == result.rewritten, "a second run must change nothing"
    return text, sorted((f.line, f.rule, f.kind.value) for f in result.findings)


def body(text: str) -> str:
    """The rewritten text without its import lines (other rules own those)."""
    return "\n".join(line for line in text.splitlines() if not line.startswith(("import ", "from "))).strip()


REWRITES = [
    pytest.param(
        """
        import gymnasium as gym
        env = gym.make("CartPole-v1")
        class Runner:
            def tick(self, a):
                self.obs, r, self.done, info = env.step(a)  # keep me
        """,
        """
        env = gym.make("CartPole-v1")
        class Runner:
            def tick(self, a):
                self.obs, r, terminated, truncated, info = env.step(a)  # keep me
                self.done = terminated or truncated
        """,
        id="attribute done target: always re-joined, comment stays on the step line",
    ),
    pytest.param(
        """
        import gymnasium as gym
        env = gym.make("CartPole-v1")
        [o, r, d, i] = env.step(0)
        if d: print("over")
        """,
        """
        env = gym.make("CartPole-v1")
        [o, r, terminated, truncated, i] = env.step(0)
        d = terminated or truncated
        if d: print("over")
        """,
        id="list target keeps its brackets",
    ),
    pytest.param(
        """
        import gymnasium as gym
        env = gym.make("CartPole-v1")
        o, r, _, i = env.step(0)
        """,
        """
        env = gym.make("CartPole-v1")
        o, r, _, _, i = env.step(0)
        """,
        id="discarded done stays discarded",
    ),
    pytest.param(
        """
        import gymnasium as gym
        env = gym.make("CartPole-v1")
        def run(a):
            o, r, done, i = env.step(a)
            memory.push(o, done)
            o, r, done, i = env.step(a)
            memory.push(o, done)
            return done
        """,
        """
        env = gym.make("CartPole-v1")
        def run(a):
            o, r, terminated, truncated, i = env.step(a)
            memory.push(o, terminated)
            o, r, terminated, truncated, i = env.step(a)
            done = terminated or truncated
            memory.push(o, terminated)
            return done
        """,
        id="each read belongs to the step that dominates it",
    ),
    pytest.param(
        """
        import gymnasium as gym
        env = gym.make("CartPole-v1")
        o, r, done, info = env.step(0)
        if "TimeLimit.truncated" not in info:
            pass
        """,
        """
        env = gym.make("CartPole-v1")
        o, r, terminated, truncated, info = env.step(0)
        if not truncated:
            pass
        """,
        id="key membership is exactly truncated",
    ),
    pytest.param(
        """
        import gymnasium as gym
        env = gym.make("CartPole-v1")
        done = False
        def step_once():
            global done
            o, r, done, i = env.step(0)
        while not done:
            step_once()
        """,
        """
        env = gym.make("CartPole-v1")
        done = False
        def step_once():
            global done
            o, r, terminated, truncated, i = env.step(0)
            done = terminated or truncated
        while not done:
            step_once()
        """,
        id="a global flag is always re-joined (its readers are elsewhere)",
    ),
    pytest.param(
        """
        import gymnasium as gym
        env = gym.make("CartPole-v1")
        def is_over():
            return finished
        finished = False
        while not is_over():
            o, r, finished, i = env.step(0)
        """,
        """
        env = gym.make("CartPole-v1")
        def is_over():
            return finished
        finished = False
        while not is_over():
            o, r, terminated, truncated, i = env.step(0)
            finished = terminated or truncated
        """,
        id="a closure defined earlier still reads the flag",
    ),
    pytest.param(
        """
        import gym
        class Skip(gym.Wrapper):
            def skip(self, action):
                for _ in range(4):
                    obs, reward, done, info = super().step(action)
                    if done:
                        break
                return obs
        """,
        """
        class Skip(gym.Wrapper):
            def skip(self, action):
                for _ in range(4):
                    obs, reward, terminated, truncated, info = super().step(action)
                    done = terminated or truncated
                    if done:
                        break
                return obs
        """,
        id="super().step in a Gym wrapper is a Gym step",
    ),
    pytest.param(
        """
        import gymnasium as gym
        envs = gym.make_vec("CartPole-v1", num_envs=2, vectorization_mode="sync")
        o, r, dones, infos = envs.step([0, 1])
        print(dones)
        """,
        """
        envs = gym.make_vec("CartPole-v1", num_envs=2, vectorization_mode="sync")
        o, r, terminations, truncations, infos = envs.step([0, 1])
        dones = np.logical_or(terminations, truncations)
        print(dones)
        """,
        id="vector flags are joined with logical_or, never `or`",
    ),
    pytest.param(
        """
        import gymnasium as gym
        env = gym.make("CartPole-v1", new_step_api=True, max_episode_steps=50,)
        """,
        """
        env = gym.make("CartPole-v1", max_episode_steps=50,)
        """,
        id="middle keyword removed, trailing comma kept",
    ),
    pytest.param(
        """
        from gymnasium import make
        env = make("CartPole-v1", autoreset=True)
        """,
        """
        env = Autoreset(make("CartPole-v1"))
        """,
        id="autoreset through a bare make imports the wrapper",
    ),
]


@pytest.mark.parametrize(("before", "after"), REWRITES)
def test_rewrites(before: str, after: str) -> None:
    text, _ = rewrite(before)
    assert body(text) == textwrap.dedent(after).strip()


NOOPS = [
    pytest.param(
        """
        import gymnasium as gym
        from stable_baselines3.common.env_util import make_vec_env
        venv = make_vec_env("CartPole-v1", n_envs=2)
        obs, rewards, dones, infos = venv.step([0, 0])
        if infos[0].get("TimeLimit.truncated", False):
            print(1 - dones)
        """,
        id="SB3 VecEnv step and info key stay (SB102, SB104)",
    ),
    pytest.param(
        """
        import gymnasium as gym
        import torch
        model = torch.nn.Linear(2, 2)
        opt = torch.optim.SGD(model.parameters(), lr=0.1)
        opt.step()
        loss, grads, done, extra = model.step(1)
        """,
        id="torch objects are not envs, even unpacked into four names",
    ),
    pytest.param(
        """
        import gymnasium as gym
        env = gym.make("CartPole-v1")
        obs, reward, terminated, truncated, info = env.step(0)
        buffer.add(obs, terminated)
        """,
        id="five targets are already migrated",
    ),
    pytest.param(
        """
        import gymnasium as gym
        env = gym.make("CartPole-v1")
        res = env.step(0)
        print(res[2], res[4])
        """,
        id="indexed results in Gymnasium code are not moved again",
    ),
]


@pytest.mark.parametrize("source", NOOPS)
def test_noops(source: str) -> None:
    result = transform_source(textwrap.dedent(source).encode(), "case.py")
    assert result.rewritten.decode() == textwrap.dedent(source)
    assert not [f for f in result.findings if f.rule in ("GM301", "GM302", "GM303", "GM304", "GM703")]


def test_unknown_receiver_unpacked_into_four_names_is_flagged() -> None:
    text, findings = rewrite(
        """
        import gym
        from stable_baselines3 import PPO

        def rollout(runner, a):
            o, r, done, info = runner.step(a)
            return o
        """
    )
    assert "o, r, done, info = runner.step(a)" in text
    assert (6, "GM301", "flag") in findings


def test_ambiguous_and_non_dominated_reads_are_flagged_not_rewritten() -> None:
    text, findings = rewrite(
        """
        import gymnasium as gym
        env = gym.make("CartPole-v1")
        def run(agent):
            for t in range(10):
                if t:
                    agent.remember(prev_done)
                o, r, done, i = env.step(0)
                agent.observe(done)
                prev_done = done
        """
    )
    assert "agent.observe(done)" in text and "prev_done = done" in text
    assert "done = terminated or truncated" in text
    assert [f for f in findings if f[1] == "GM302"] == [(9, "GM302", "flag"), (10, "GM302", "flag")]


def test_numpy_is_imported_for_the_vector_join() -> None:
    text, _ = rewrite(
        """
        import gymnasium as gym
        envs = gym.make_vec("CartPole-v1", num_envs=2, vectorization_mode="sync")
        o, r, dones, infos = envs.step([0, 1])
        print(dones)
        """
    )
    assert "import numpy as np" in text


# -- runtime: the rewritten legacy loop against the installed Gymnasium -------------------

LEGACY_LOOP = '''
import gym


def play(env_id, seed, max_steps):
    env = gym.make(env_id)
    env.action_space.seed(seed)
    obs = env.reset(seed=seed)
    log = []
    done = False
    steps = 0
    while not done and steps < max_steps:
        obs, reward, done, info = env.step(env.action_space.sample())
        log.append((done, info.get("TimeLimit.truncated", False)))
        steps += 1
    env.close()
    return log
'''


# Run in a fresh interpreter: other tests install process-wide hooks on gymnasium.Env.
REFERENCE = """
import json, sys
import gymnasium


def reference(env_id, seed, max_steps):
    # What the legacy log meant, from Gymnasium's flags: (episode over, cut by the time limit).
    # The logged flag is not a bootstrap mask (no next state is stored): it keeps ``done``.
    env = gymnasium.make(env_id)
    env.action_space.seed(seed)
    env.reset(seed=seed)
    log = []
    for _ in range(max_steps):
        _, _, terminated, truncated, _ = env.step(env.action_space.sample())
        log.append((bool(terminated or truncated), bool(truncated and not terminated)))
        if terminated or truncated:
            break
    env.close()
    return log


env_id, max_steps = sys.argv[1], int(sys.argv[2])
migrated = [[bool(t), bool(cut)] for t, cut in play(env_id, 3, max_steps)]
expected = [list(row) for row in reference(env_id, 3, max_steps)]
print(json.dumps({"migrated": migrated, "expected": expected}))
"""


def run_migrated(code: str, env_id: str, max_steps: int, tmp_path: Path) -> dict[str, list[list[bool]]]:
    script = tmp_path / "migrated_loop.py"
    script.write_text(code + REFERENCE, encoding="utf-8")
    done = subprocess.run(
        [sys.executable, str(script), env_id, str(max_steps)], capture_output=True, text=True, timeout=120, check=False
    )
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize(
    ("env_id", "max_steps", "ends_by"),
    [("CartPole-v1", 500, "terminated"), ("MountainCar-v0", 300, "truncated")],
)
def test_rewritten_legacy_loop_runs_on_gymnasium(env_id: str, max_steps: int, ends_by: str, tmp_path: Path) -> None:
    text, findings = rewrite(LEGACY_LOOP)
    assert "obs, reward, terminated, truncated, info = env.step(" in text
    assert "done = terminated or truncated" in text  # the while test still reads it
    assert {(13, "GM301", "auto"), (14, "GM302", "flag"), (14, "GM303", "assist")} <= set(findings)
    result = run_migrated(text, env_id, max_steps, tmp_path)
    log = result["migrated"]
    assert log == result["expected"]
    last_over, last_timeout = log[-1]
    if ends_by == "terminated":  # CartPole falls over long before its 500-step limit
        assert last_over and not last_timeout
    else:  # random actions never reach the flag: the 200-step TimeLimit cuts the episode
        assert len(log) == 200 and last_timeout and last_over  # over, as the legacy ``done`` said
    assert not any(t for t, _ in log[:-1]) and not any(cut for _, cut in log[:-1])


LEGACY_VECTOR_LOOP = '''
import gym


def count_episode_ends(steps):
    envs = gym.vector.SyncVectorEnv([lambda: gym.make("CartPole-v1") for _ in range(2)])
    envs.action_space.seed(5)
    obs, _ = envs.reset(seed=5)
    ends = 0
    for _ in range(steps):
        obs, rewards, dones, infos = envs.step(envs.action_space.sample())
        ends += int(dones.sum())
    envs.close()
    return ends


print(count_episode_ends(200))
'''


def test_rewritten_vector_loop_joins_arrays_with_numpy(tmp_path: Path) -> None:
    text, findings = rewrite(LEGACY_VECTOR_LOOP)
    assert "dones = np.logical_or(terminations, truncations)" in text
    assert "import numpy as np" in text
    assert (11, "GM703", "auto") in findings
    script = tmp_path / "vector_loop.py"
    script.write_text(text, encoding="utf-8")
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 0, done.stderr
    assert int(done.stdout.strip()) > 0  # random CartPole episodes end well within 200 steps
