"""A custom env's reset that returns nothing (rules/custom_env/reset_none.py), across a run.

Gymnasium's reset must return ``(obs, info)``: the item at such a reset is a note only
where the run proves nothing unpacks it, the class built in its own module and each
instance only asked for attributes, its reset called for its effect; another module
importing the class's module, a wrapper around an instance, or a read of what reset
returns keeps it a review item.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app

runner = CliRunner()

ENV = '''import gym
import numpy as np


class Pendulum2(gym.Env):
    def __init__(self):
        self.observation_space = gym.spaces.Box(-1.0, 1.0, (2,), np.float32)
        self.action_space = gym.spaces.Box(-1.0, 1.0, (1,), np.float32)

    def reset(self):
        self.theta = 0.0

    def step(self, action):
        self.theta += float(action[0])
        return np.array([np.cos(self.theta), np.sin(self.theta)], np.float32), 0.0, abs(self.theta) > 3.0, {}


if __name__ == "__main__":
    env = Pendulum2()
{use}
'''
DIRECT = "    env.reset()\n    obs, reward, done, info = env.step(env.action_space.sample())\n"
OTHER = 'import gym\n\nenv = gym.make("CartPole-v1")\nenv.reset()\n'


def _reset_item(tmp_path: Path, use: str, other: str = OTHER) -> dict[str, object]:
    (tmp_path / "pendulum2.py").write_text(ENV.replace("{use}", use))
    (tmp_path / "train.py").write_text(other)
    result = runner.invoke(app, ["check", "--output-format", "json", str(tmp_path)])
    found = [
        f
        for f in json.loads(result.stdout)
        if Path(f["path"]).name == "pendulum2.py" and f["rule"] == "GM501" and "returns nothing" in f["message"]
    ]
    assert len(found) == 1, found
    return found[0]


def test_a_class_the_run_uses_only_directly_gets_a_note(tmp_path: Path) -> None:
    item = _reset_item(tmp_path, DIRECT)
    assert item["line"] == 10
    assert item["tier"] == "note"
    assert "the run uses `Pendulum2` only directly" in str(item["message"])


@pytest.mark.parametrize(
    ("use", "other"),
    [
        pytest.param(DIRECT, "import gym\nfrom pendulum2 import Pendulum2\n\nenv = Pendulum2()\n", id="imported elsewhere"),
        pytest.param("    env = gym.wrappers.TimeLimit(env, 100)\n    env.reset()\n", OTHER, id="wrapped"),
        pytest.param("    first = env.reset()\n", OTHER, id="reset result read"),
    ],
)
def test_any_other_use_keeps_the_review_item(tmp_path: Path, use: str, other: str) -> None:
    item = _reset_item(tmp_path, use, other)
    assert item["tier"] == "review"
    assert "only directly" not in str(item["message"])


BASE = '''import gym


class Scene(gym.Env):
    def __init__(self, size=3):
        self.size = size

    def reset(self):
        self.t = 0

    def step(self, action):
        raise NotImplementedError
'''
TASK = '''import gym
import numpy as np

from scene import Scene


class Reach(Scene):
    observation_space = gym.spaces.Box(-1.0, 1.0, (3,))

    def reset(self):
        super().reset()
        return np.zeros(self.size)
{more}
'''
RESETLESS = '''

class Push(Scene):
    def step(self, action):
        return np.zeros(self.size), 0.0, False, {}
'''


def _base_item(tmp_path: Path, more: str = "", other: str = OTHER) -> dict[str, object]:
    (tmp_path / "scene.py").write_text(BASE)
    (tmp_path / "tasks.py").write_text(TASK.replace("{more}", more))
    (tmp_path / "train.py").write_text(other)
    result = runner.invoke(app, ["check", "--output-format", "json", str(tmp_path)])
    found = [
        f
        for f in json.loads(result.stdout)
        if Path(f["path"]).name == "scene.py" and f["rule"] == "GM501" and "returns nothing" in f["message"]
    ]
    assert len(found) == 1, found
    return found[0]


def test_a_base_only_its_overriding_subclasses_reset_gets_a_note(tmp_path: Path) -> None:
    item = _base_item(tmp_path)
    assert item["tier"] == "note"
    assert "every subclass of it overrides reset (Reach)" in str(item["message"])


@pytest.mark.parametrize(
    ("more", "other"),
    [
        pytest.param(RESETLESS, OTHER, id="a subclass inherits the reset"),
        pytest.param("", "from scene import Scene\n\nenv = Scene()\nenv.reset()\n", id="the base built itself"),
    ],
)
def test_a_base_reached_another_way_keeps_the_review_item(tmp_path: Path, more: str, other: str) -> None:
    item = _base_item(tmp_path, more, other)
    assert item["tier"] == "review"
    assert "overrides reset" not in str(item["message"])


MIDDLE = '''

class Camera(Scene):
    """No reset of its own: only a base again, for subclasses of another module."""

    def __init__(self, size=3):
        super().__init__(size)
        self.zoom = 1

    def look(self):
        return self.size
'''
# built elsewhere only as the base of ``super().__init__(...)``: that builds a Reach
SUPER_INIT = """
    def __init__(self):
        super().__init__(size=3)
"""


def _middle_item(tmp_path: Path, other: str) -> dict[str, object]:
    (tmp_path / "scene.py").write_text(BASE + MIDDLE)
    (tmp_path / "tasks.py").write_text(TASK.replace("{more}", SUPER_INIT).replace("Scene", "Camera"))
    (tmp_path / "train.py").write_text(other)
    result = runner.invoke(app, ["check", "--output-format", "json", str(tmp_path)])
    found = [f for f in json.loads(result.stdout) if f["path"].endswith("scene.py") and f["rule"] == "GM501" and "returns nothing" in f["message"]]
    assert len(found) == 1, found
    return found[0]


def test_a_base_under_a_resetless_base_only_gets_a_note(tmp_path: Path) -> None:
    # Scene <- Camera (no reset, never built) <- Reach (another module, overrides reset):
    # Scene's reset runs only under Reach's ``super().reset()``.
    item = _middle_item(tmp_path, OTHER)
    assert item["tier"] == "note"
    assert "every subclass of it overrides reset (Reach)" in str(item["message"])


def test_a_built_resetless_middle_base_keeps_the_review_item(tmp_path: Path) -> None:
    # Camera built itself: its instances run Scene's reset, whose None a wrapper unpacks.
    item = _middle_item(tmp_path, "from scene import Camera\n\nenv = Camera()\nenv.reset()\n")
    assert item["tier"] == "review"
    assert "overrides reset" not in str(item["message"])
