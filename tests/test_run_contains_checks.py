"""GM910: a float32 ``Box`` (no dtype) with float64 bounds on an env whose observations are
float64, whose ``contains()`` another module of the run asks (``fixtures/project_contains_checks``,
``fixtures/rules/GM910``).

gym <= 0.20's ``Box.contains`` compared shape and bounds; Gymnasium's also checks that the
value's dtype casts to the Box's. Reported at each such Box, naming the calls; a Box whose
env's observations are float32 (``Lamp``) and the action space are not.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures"
runner = CliRunner()


@pytest.fixture
def run(tmp_path: Path) -> Path:
    shutil.copytree(FIXTURES / "project_contains_checks", tmp_path / "run")
    return tmp_path / "run"


def _findings(run: Path, rule: str) -> list[dict]:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code in (0, 1), result.output
    return [{**f, "path": Path(f["path"]).relative_to(run).as_posix()} for f in json.loads(result.stdout) if f["rule"] == rule]


def test_each_box_another_module_checks_float64_observations_against_is_asked_about(run: Path) -> None:
    found = _findings(run, "GM910")
    assert [(f["path"], f["line"]) for f in found] == [("gripper/arm.py", 9), ("gripper/arm.py", 13)]
    tip, observation = found
    assert "`TIP`" in tip["message"] and "tests/test_arm.py:8" in tip["message"]
    assert "`observation_space`" in observation["message"] and "tests/test_arm.py:7" in observation["message"]


def test_what_is_asked_is_what_contains_refuses(run: Path) -> None:
    pytest.importorskip("gymnasium")
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code in (0, 1), result.output
    probe = (
        "from gripper.arm import Gripper, Lamp\n"
        "g, l = Gripper(), Lamp()\n"
        "obs, _ = g.reset()\n"
        "print(g.observation_space.contains(obs), Gripper.TIP.contains(obs[:3]), l.observation_space.contains(l.reset()[0]))\n"
    )
    done = subprocess.run([sys.executable, "-W", "ignore", "-c", probe], cwd=run, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["False", "False", "True"]
