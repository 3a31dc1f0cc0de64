"""A constructor parameter fed only by a factory of another module that returns a made env
is a Gym env (``fixtures/project_factory_chain``).

``kit.envs.prepared`` makes the env, seeds it and returns what ``kit.wrap.decorate`` (a def of a
third module) puts around it; ``run.main`` hands it to ``Trainer``, whose reset and step calls
are migrated. ``kit.envs.either`` returns a made env on one path and a plain object on the
other: ``Probe`` stays a question.
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

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_factory_chain"
runner = CliRunner()


@pytest.fixture
def run(tmp_path: Path) -> Path:
    shutil.copytree(FIXTURE, tmp_path / "run")
    return tmp_path / "run"


def test_the_agent_fed_by_the_factory_is_migrated_and_the_mixed_one_asked(run: Path) -> None:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code in (0, 1), result.output
    findings = [{**f, "path": Path(f["path"]).relative_to(run).as_posix()} for f in json.loads(result.stdout)]
    trainer = sorted((f["line"], f["rule"], f["kind"]) for f in findings if f["path"] == "trainer.py")
    assert trainer == [(7, "GM201", "auto"), (9, "GM301", "auto"), (11, "GM201", "auto")]
    review = [(f["path"], f["line"], f["rule"]) for f in findings if f["tier"] == "review"]
    assert review == [("probe.py", 6, "GM201")]


def test_the_migrated_trainer_runs_on_gymnasium(run: Path) -> None:
    pytest.importorskip("gymnasium")
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code in (0, 1), result.output
    probe = "from kit.envs import prepared\nfrom run import main\nprint(main(prepared('CartPole-v1', 7), 50).shape)\n"
    done = subprocess.run([sys.executable, "-c", probe], cwd=run, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "(4,)"
