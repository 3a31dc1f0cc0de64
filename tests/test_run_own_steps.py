"""Steps that other steps of the project call (``fixtures/project_own_steps``), migrated by
one ``gymmigrate rewrite`` and run on Gymnasium 1.4.

``arm/base.py``: ``ArmEnv.step`` returns the observation alone, a helper the tasks of
``arm/tasks/`` build their steps on; ``ArmEnv`` derives from ``CoreEnv`` of ``arm/core.py``
through a class of its own module. Before: the tasks were not known to be env classes
(their base's module could not tell what ``JointBase`` was), so they kept four values
beside a migrated reset, and the helper was asked to return five values by hand, which
would have broken every task. ``sim/``: a base that defines no step unpacks
``self.step(...)``, a subclass hands its base's step result on, and a plain class hands on
the step of the env it makes; every one of them was an item or left on four values.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from tests.fixture_cases import FIXTURES

runner = CliRunner()

_RUN = """
import warnings
warnings.simplefilter("ignore")
import gymnasium as gym
import numpy as np
from gymnasium.utils.env_checker import check_env
import arm.registry
from arm.tasks.hold import HoldTask
from arm.tasks.push import PushTask
from sim.block import BlockEnv
from sim.goal import TargetBlock
from sim.runner import Runner

for env_id in ("ArmPush-v0", "ArmHold-v0"):
    env = gym.make(env_id)
    env.reset(seed=0)
    steps = [env.step(np.ones(2, np.float32)) for _ in range(5)]
    print(env_id, steps[0][1], steps[-1][2:4])
for cls in (PushTask, HoldTask, BlockEnv, TargetBlock):
    check_env(cls())
print(BlockEnv().rollout(4), TargetBlock().reset(seed=1)[0].tolist())
gym.register("Block-v0", entry_point="sim.block:BlockEnv", max_episode_steps=7)
print(Runner("Block-v0").episode_length())
"""


def test_helper_steps_and_the_steps_built_on_them_run_on_gymnasium(tmp_path: Path) -> None:
    project = tmp_path / "project"
    shutil.copytree(FIXTURES / "project_own_steps", project)
    checked = runner.invoke(app, ["check", "--output-format", "json", str(project)])
    review = [f for f in json.loads(checked.stdout) if f["tier"] == "review"]
    assert review == [], review
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    again = runner.invoke(app, ["rewrite", str(project)])
    assert "rewrote 0 of" in again.output, again.output
    assert "return self._observe()" in (project / "arm" / "base.py").read_text()  # the helper keeps its return
    assert "return ob, reward, False, False, info" in (project / "arm" / "tasks" / "push.py").read_text()
    assert "return ob, 1.0, False, False, {}" in (project / "arm" / "tasks" / "hold.py").read_text()
    base = (project / "sim" / "base.py").read_text()
    assert "_reward, terminated, truncated, _info = self.step(" in base and "_o, r, terminated, truncated, _ = self.step(" in base
    goal = (project / "sim" / "goal.py").read_text()
    assert "def reset(self, *, seed=None, options=None):" in goal and "        return results\n" in goal
    assert "_o, _r, terminated, truncated, _ = self.step(" in (project / "sim" / "runner.py").read_text()
    run = subprocess.run([sys.executable, "-c", _RUN], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.splitlines() == [
        "ArmPush-v0 -4.0 (False, True)",
        "ArmHold-v0 1.0 (False, True)",
        "4.0 [0.0, 0.0, 0.0]",
        "7",
    ]
