"""Gym wrapper classes the run puts only around VecEnvs (``fixtures/project_vec_wrappers``).

gym's Wrapper took any object; Gymnasium's refuses one that is no ``gymnasium.Env``. A
wrapper class every construction of the run hands a VecEnv (in its own module or another,
through a def that wraps its argument) is one review item at the class: its insides and the
calls on its instances stay on the VecEnv's API. So is one the run constructs nowhere whose
own methods take a VecEnv's ``step_wait()`` results apart. Their base class, which another
subclass puts around a Gym env built in another module, migrates as a Gym wrapper.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app
from tests.fixture_cases import FIXTURES

runner = CliRunner()


@pytest.fixture
def run(tmp_path: Path) -> Path:
    shutil.copytree(FIXTURES / "project_vec_wrappers", tmp_path / "run")
    return tmp_path / "run"


def _findings(run: Path) -> list[dict]:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code in (0, 1), result.output
    return [{**f, "path": Path(f["path"]).relative_to(run).as_posix()} for f in json.loads(result.stdout)]


def test_wrappers_around_vec_envs_are_left_and_reported_once(run: Path) -> None:
    review = sorted((f["path"], f["line"], f["rule"]) for f in _findings(run) if f["tier"] == "review")
    assert review == [("wrappers.py", 5, "GM602"), ("wrappers.py", 20, "GM602"), ("wrappers.py", 52, "GM602")]


def test_vec_env_calls_stay_and_the_gym_path_migrates(run: Path) -> None:
    before = {p: (run / p).read_text() for p in ("batches.py", "drive.py", "wrappers.py")}
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code in (0, 1), result.output
    assert (run / "batches.py").read_text() == before["batches.py"]
    drive = (run / "drive.py").read_text()
    # the batch's calls keep the VecEnv's API; the Gym env's migrate
    assert "    obs = venv.reset()\n" in drive and "obs, rews, dones, infos = venv.step(" in drive
    assert "obs, info = env.reset()" in drive and "obs, rew, terminated, truncated, info = env.step(0)" in drive
    wrappers = (run / "wrappers.py").read_text()
    vec_part = before["wrappers.py"].split("class Base")[0].replace("import gym\n", "import gymnasium as gym\n", 1)
    assert wrappers.startswith(vec_part)  # Noisy, Totals and finish() as they were
    assert 'self.env.step_wait()' in wrappers and "get_wrapper_attr" not in wrappers
    assert "def reset(self, *, seed=None, options=None):" in wrappers.split("class Base")[1].split("class Manager")[0]
    assert "obs, rew, terminated, truncated, info = self.env.step(action)" in wrappers.split("class Clip")[1]
