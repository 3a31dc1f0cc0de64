"""VecEnv guards, executed: a stable_baselines 2.x loop keeps its four-field step and runs.

The script is rewritten by the engine, then run in a child process against a fake,
minimal ``stable_baselines.common.vec_env`` (obs-only ``reset()``, four-value ``step()``)
that wraps real Gymnasium CartPole envs. If the migration unpacked ``reset()`` or made
``step()`` five-field, the script would fail.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

from gymmigrate.engine import transform_source
from gymmigrate.facts.profile import FileProfile

FAKE_VEC_ENV = '''
import numpy as np


class VecEnv:
    def step(self, actions):
        self.step_async(actions)
        return self.step_wait()


class DummyVecEnv(VecEnv):
    """The stable_baselines 2.x API over Gymnasium envs: reset() -> obs, step() -> 4 values."""

    def __init__(self, env_fns):
        self.envs = [fn() for fn in env_fns]
        self.num_envs = len(self.envs)
        self.action_space = self.envs[0].action_space
        self.observation_space = self.envs[0].observation_space
        self._actions = None

    def reset(self):
        return np.stack([env.reset()[0] for env in self.envs])

    def step_async(self, actions):
        self._actions = actions

    def step_wait(self):
        obs, rewards, dones, infos = [], [], [], []
        for env, action in zip(self.envs, self._actions):
            ob, reward, terminated, truncated, info = env.step(int(action))
            done = terminated or truncated
            if done:
                info = dict(info, terminal_observation=ob)
                ob, _ = env.reset()
            obs.append(ob)
            rewards.append(reward)
            dones.append(done)
            infos.append(info)
        return np.stack(obs), np.array(rewards), np.array(dones), infos

    def close(self):
        for env in self.envs:
            env.close()


class VecEnvWrapper(VecEnv):
    def __init__(self, venv):
        self.venv = venv
        self.num_envs = venv.num_envs
        self.action_space = venv.action_space
        self.observation_space = venv.observation_space

    def step_async(self, actions):
        self.venv.step_async(actions)

    def close(self):
        self.venv.close()
'''

SCRIPT = '''\
import gym
import numpy as np
from stable_baselines.common.vec_env import DummyVecEnv, VecEnvWrapper


class HalveRewards(VecEnvWrapper):
    def reset(self):
        return self.venv.reset()

    def step_wait(self):
        obs, rewards, dones, infos = self.venv.step_wait()
        return obs, rewards * 0.5, dones, infos


env = DummyVecEnv([lambda: gym.make("CartPole-v1") for _ in range(2)])
obs = env.reset()
assert obs.shape == (2, 4), obs
episodes = 0
for _ in range(300):
    actions = np.array([env.action_space.sample() for _ in range(2)])
    obs, rewards, dones, infos = env.step(actions)
    episodes += int(np.sum(dones))
assert episodes > 0

wrapped = HalveRewards(env)
obs = wrapped.reset()
obs, rewards, dones, infos = wrapped.step(np.array([0, 1]))
assert rewards.tolist() == [0.5, 0.5], rewards
wrapped.close()
print("four-field loop ok", episodes)
'''


def _fake_stable_baselines(root: Path) -> None:
    package = root / "stable_baselines" / "common" / "vec_env"
    package.mkdir(parents=True)
    (root / "stable_baselines" / "__init__.py").write_text("", encoding="utf-8")
    (root / "stable_baselines" / "common" / "__init__.py").write_text("", encoding="utf-8")
    (package / "__init__.py").write_text(textwrap.dedent(FAKE_VEC_ENV), encoding="utf-8")


def test_a_stable_baselines2_loop_is_kept_and_runs_on_gymnasium(tmp_path: Path) -> None:
    _fake_stable_baselines(tmp_path)
    result = transform_source(SCRIPT.encode(), "train.py")
    rewritten = result.rewritten.decode()
    # Only the import changes; the VecEnv code (reset, step, the local wrapper) stays.
    assert rewritten == SCRIPT.replace("import gym\n", "import gymnasium as gym\n", 1)
    assert sorted((f.line, f.rule) for f in result.findings) == [(1, "GM101"), (3, "GM107")]

    script = tmp_path / "train.py"
    script.write_text(rewritten, encoding="utf-8")
    env = dict(os.environ, PYTHONPATH=str(tmp_path))
    completed = subprocess.run(
        [sys.executable, str(script)], cwd=tmp_path, env=env, capture_output=True, text=True, timeout=120
    )
    assert completed.returncode == 0, completed.stderr
    assert "four-field loop ok" in completed.stdout


def test_every_vecenv_library_means_the_file_is_not_gym_only() -> None:
    for line in (
        "from stable_baselines.common.vec_env import DummyVecEnv",
        "import stable_baselines",
        "from stable_baselines3.common.vec_env import DummyVecEnv",
        "from baselines.common.vec_env import SubprocVecEnv",
        "from sb3_contrib import RecurrentPPO",
    ):
        profile = FileProfile.from_source(f"import gym\n{line}\n")
        assert not profile.gym_only, line
    assert FileProfile.from_source("import gym\nimport numpy as np\n").gym_only
