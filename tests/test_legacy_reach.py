"""Legacy code the rules now reach: local env classes as creation sites, the last step's
info read after its loop. Each case is migrated and then run against Gymnasium."""

from __future__ import annotations

import textwrap

import numpy as np

from gymmigrate.engine import transform_source


def _run(legacy: str) -> dict[str, object]:
    migrated = transform_source(textwrap.dedent(legacy).encode(), "legacy.py").rewritten.decode()
    assert "import gymnasium" in migrated
    namespace: dict[str, object] = {"__name__": "migrated"}
    exec(compile(migrated, "<migrated>", "exec"), namespace)
    return namespace


def test_local_env_class_gets_the_render_mode_of_its_render_calls() -> None:
    namespace = _run(
        '''
        import gym
        import numpy as np


        class Painter(gym.Env):
            metadata = {"render.modes": ["rgb_array"]}

            def __init__(self, size=8):
                self.size = size
                self.observation_space = gym.spaces.Discrete(size)
                self.action_space = gym.spaces.Discrete(2)
                self.x = 0

            def reset(self):
                self.x = 0
                return self.x

            def step(self, action):
                self.x = min(self.x + int(action), self.size - 1)
                return self.x, 0.0, self.x == self.size - 1, {}

            def render(self, mode="human"):
                frame = np.zeros((self.size, self.size, 3), dtype=np.uint8)
                frame[:, self.x] = 255
                if mode == "rgb_array":
                    return frame


        env = Painter(size=6)
        env.reset()
        frames = []
        done = False
        while not done:
            _, _, done, _ = env.step(1)
            frames.append(env.render(mode="rgb_array"))
        '''
    )
    frames = namespace["frames"]
    assert len(frames) == 5 and all(isinstance(f, np.ndarray) and f.shape == (6, 6, 3) for f in frames)  # type: ignore[arg-type]


def test_time_limit_read_after_the_loop_sees_the_last_step() -> None:
    namespace = _run(
        '''
        import gym

        env = gym.make("CartPole-v1", max_episode_steps=3)
        obs = env.reset(seed=0)
        done = False
        while not done:
            obs, reward, done, info = env.step(0 if obs[2] > 0 else 1)
        cut = info.get("TimeLimit.truncated", False)
        '''
    )
    assert namespace["cut"] is True
