"""A record class of another module of the run (GM302): ``fixtures/project_records``.

``agents/memory.py`` (no Gym code) defines ``Transition = namedtuple(...)``; ``agents/dqn.py``
stores each step's ``done`` in one beside the next observation and masks its TD target with
the stored flag, so the flag becomes ``terminated``, as for a record class of its own module.
A plain class of the run (``agents/logbook.py``'s ``Entry``) is no record: its ``done`` stays
a question. The migrated package runs on Gymnasium 1.4.
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

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_records"
runner = CliRunner()


@pytest.fixture
def run(tmp_path: Path) -> Path:
    shutil.copytree(FIXTURE, tmp_path / "run")
    return tmp_path / "run"


def test_a_done_stored_in_a_record_of_another_module_is_terminated(run: Path) -> None:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    findings = json.loads(result.stdout)
    gm302 = {(Path(f["path"]).name, f["line"]): f for f in findings if f["rule"] == "GM302"}
    assert gm302[("dqn.py", 27)]["tier"] == "note"
    assert "masks bootstrapping from the next state" in gm302[("dqn.py", 27)]["message"]
    assert gm302[("logbook.py", 18)]["tier"] == "review"  # a plain class: no record


def test_the_module_checked_alone_still_asks(run: Path) -> None:
    """Without the run, the imported name is unknown: the flag is asked about, not guessed."""
    result = runner.invoke(app, ["check", "--output-format", "json", str(run / "agents" / "dqn.py")])
    gm302 = [f for f in json.loads(result.stdout) if f["rule"] == "GM302"]
    assert [(f["line"], f["tier"]) for f in gm302] == [(27, "review")]


def test_the_migrated_package_stores_terminated_and_runs(run: Path) -> None:
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code in (0, 1), result.output
    migrated = (run / "agents" / "dqn.py").read_text()
    assert "agent.memory.push(Transition(obs, action, reward, next_obs, terminated))" in migrated
    assert (run / "agents" / "memory.py").read_bytes() == (FIXTURE / "agents" / "memory.py").read_bytes()
    probe = (
        "import numpy as np\n"
        "from agents.dqn import run\n"
        "agent = run(3)\n"
        "flags = [t.done for t in agent.memory.items]\n"
        "assert flags[-1] is True or flags[-1] == True, flags[-3:]\n"  # CartPole ends by termination here
        "print(len(flags))\n"
    )
    done = subprocess.run([sys.executable, "-c", probe], cwd=run, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert int(done.stdout) > 3
