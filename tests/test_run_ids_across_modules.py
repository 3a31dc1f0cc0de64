"""An env id literal handed to a def of another module that makes it is renamed at its
call (``fixtures/project_ids_across_modules``).

``kit.pool.EnvPool`` stores its ``env_id`` and makes it; ``train.py`` builds one with
``"Pendulum-v0"`` through the package's re-export. ``kit.checks.CheckBase.check`` hands its
``environment`` on to ``prepare``, which makes it; ``test_box2d.py`` calls the inherited
``self.check(environment="LunarLander-v2")``. Both literals are bumped. ``describe`` only
builds a label: its ``"Pendulum-v0"`` stays.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_ids_across_modules"
runner = CliRunner()


@pytest.fixture
def run(tmp_path: Path) -> Path:
    shutil.copytree(FIXTURE, tmp_path / "run")
    return tmp_path / "run"


def test_ids_passed_to_makers_of_other_modules_are_bumped(run: Path) -> None:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code in (0, 1), result.output
    findings = [{**f, "path": Path(f["path"]).relative_to(run).as_posix()} for f in json.loads(result.stdout)]
    ids = sorted((f["path"], f["line"], f["rule"], f["kind"]) for f in findings if f["rule"].startswith("GM80"))
    assert ids == [("test_box2d.py", 8, "GM803", "assist"), ("train.py", 6, "GM803", "auto")]


def test_only_the_made_literals_change(run: Path) -> None:
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code in (0, 1), result.output
    train = (run / "train.py").read_text()
    assert 'EnvPool("Pendulum-v1", 2)' in train
    assert 'describe("Pendulum-v0")' in train
    tests = (run / "test_box2d.py").read_text()
    assert 'environment="LunarLander-v3"' in tests
    assert 'environment="CartPole-v1"' in tests
