"""A factory of the run that hands the env it builds to a helper of its own module, which
wraps it in wrapper classes of another module, gives a Gym env (``fixtures/project_factory_helpers``).

``workshop.build`` imports its env class inside the def and returns ``_finish(env, ...)``;
``client.py``'s reset and step calls, in a def and on ``self.env`` stored in a plain class's
``__init__``, are migrated, and the read of ``env.size`` in the value that rebinds ``env``
(the bare env made just above) asks nothing. ``build_mixed`` returns the stack on one path
and a plain record of the package's on the other: ``audit`` stays a question.
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

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_factory_helpers"
runner = CliRunner()


@pytest.fixture
def run(tmp_path: Path) -> Path:
    shutil.copytree(FIXTURE, tmp_path / "run")
    return tmp_path / "run"


def test_the_factory_stack_is_a_gym_env_and_the_mixed_factory_asked(run: Path) -> None:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code in (0, 1), result.output
    findings = [{**f, "path": Path(f["path"]).relative_to(run).as_posix()} for f in json.loads(result.stdout)]
    client = sorted((f["line"], f["rule"], f["kind"]) for f in findings if f["path"] == "client.py")
    assert client == [(6, "GM201", "auto"), (10, "GM301", "auto"), (22, "GM201", "auto"), (25, "GM301", "auto"), (31, "GM201", "flag")]
    review = [(f["path"], f["line"], f["rule"]) for f in findings if f["tier"] == "review"]
    assert review == [("client.py", 31, "GM201")]


def test_the_migrated_client_runs_on_gymnasium(run: Path) -> None:
    pytest.importorskip("gymnasium")
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code in (0, 1), result.output
    probe = (
        "from client import Station, run\n"
        "print(run(3))\n"
        "station = Station()\n"
        "print(station.begin(), station.advance(1))\n"
    )
    done = subprocess.run([sys.executable, "-c", probe], cwd=run, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    # size 3 > 2 made the clamp strict (the bare env's size was read): 3 rewards of 0.5
    assert done.stdout.split("\n")[:2] == ["(3, 1.5, 3)", "0 (1, 1.0)"]
