"""Callers of a kept render(mode) ask its question (``fixtures/project_kept_render_callers``).

``boards.py``'s ``BoardEnv.render(mode)`` keeps ``mode`` (GM405) because other modules pass
one. ``agent.py`` renders an instance of it, ``viewer.py`` an env it cannot trace, each in
a mode that is no literal, and ``BoardEnv`` is the one render(mode) either module reaches;
``tools/runner.py`` imports nothing of the run, but its package's ``__init__`` (run first)
imports ``BoardEnv``: all three are the def's decision, named in its item, and no advice
of their own. ``cartpole.py`` renders a ``gym.make`` of a Gymnasium id: its render_mode
goes to that make; ``plain.py`` reaches no env class: GM401 stays for both.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_kept_render_callers"
runner = CliRunner()


def test_callers_of_a_kept_render_are_decided_at_the_def(tmp_path: Path) -> None:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    result = runner.invoke(app, ["rewrite", str(run), "--report", str(tmp_path / "report.json")])
    assert result.exit_code == 0, result.output
    assert "self.env.render(m)" in (run / "agent.py").read_text()
    assert "env.render(mode)" in (run / "viewer.py").read_text()
    report = json.loads((tmp_path / "report.json").read_text())
    findings = {(Path(f["path"]).relative_to(run).as_posix(), f["line"], f["rule"]): f for f in report["findings"] if f["rule"] in ("GM401", "GM405")}
    kept = findings[("boards.py", 14, "GM405")]
    assert kept["tier"] == "review"
    assert "(the same decision at 3 other places: " in kept["message"]
    assert kept["message"].endswith(f"{run / 'agent.py'}:9, {run / 'tools' / 'runner.py'}:5, {run / 'viewer.py'}:7)")
    for name, line in (("agent.py", 9), ("viewer.py", 7), ("tools/runner.py", 5)):
        caller = findings[(name, line, "GM401")]
        assert caller["tier"] == "note"
        assert "pass it as render_mode=" not in caller["message"]
        assert caller["message"].endswith(f"(decided once, at {run / 'boards.py'}:14)")
    assert "instance of `BoardEnv`" in findings[("agent.py", 9, "GM401")]["message"]
    assert "could not be traced" in findings[("viewer.py", 7, "GM401")]["message"]
    for left in (findings[("cartpole.py", 10, "GM401")], findings[("plain.py", 3, "GM401")]):
        assert left["tier"] == "review"
        assert "pass it as render_mode= to gym.make" in left["message"]
