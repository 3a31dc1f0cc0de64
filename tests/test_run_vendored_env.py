"""GM807: an env class built on a copy of another gym that the package carries
(``fixtures/project_vendored_env``): its bases end in a plain class of the run, so it is no
gymnasium.Env and ``gymnasium.make`` rejects it before any env checker runs. The
registration is reported with that reason and left as it is; a ``gym.Env`` whose space is a
``list`` subclass is still registered with the checker off.
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
    shutil.copytree(FIXTURES / "project_vendored_env", tmp_path / "run")
    return tmp_path / "run"


def test_the_registration_is_reported_with_its_reason(run: Path) -> None:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code in (0, 1), result.output
    findings = [{**f, "path": Path(f["path"]).relative_to(run).as_posix()} for f in json.loads(result.stdout)]
    asked = sorted((f["path"], f["line"], f["rule"], f["kind"]) for f in findings if f["rule"] == "GM807")
    assert asked == [("lab/__init__.py", 3, "GM807", "flag"), ("lab/__init__.py", 4, "GM807", "assist")]
    message = next(f["message"] for f in findings if f["line"] == 3 and f["rule"] == "GM807")
    assert "`Env` of `lab.oldgym.core`" in message and "disable_env_checker does not help" in message


def test_only_the_gym_env_gets_the_checker_off(run: Path) -> None:
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code in (0, 1), result.output
    text = (run / "lab" / "__init__.py").read_text()
    assert 'register(id="Hop-v0", entry_point="lab.hop:Hop", max_episode_steps=20)\n' in text
    assert 'entry_point="lab.relay:Relay", disable_env_checker=True)' in text


def test_make_rejects_the_class_for_the_reason_given(run: Path) -> None:
    pytest.importorskip("gymnasium")
    runner.invoke(app, ["rewrite", str(run)])
    probe = "import gymnasium, lab\ngymnasium.make('Hop-v0', disable_env_checker=True)\n"
    made = subprocess.run([sys.executable, "-W", "ignore", "-c", probe], cwd=run, capture_output=True, text=True, timeout=120)
    assert made.returncode != 0 and "must inherit from the gymnasium.Env class" in made.stderr
