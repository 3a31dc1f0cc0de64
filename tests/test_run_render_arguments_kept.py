"""render() with the env class's own arguments on a make result (``fixtures/project_render_arguments_kept``).

``boards/board.py``'s ``BoardEnv.render(snapshot_dir, pause)`` takes no mode, so the run
leaves it as it is. ``play.py`` makes it (``Board-v0``, registered by the run) and calls
``render(snapshot_dir=..., pause=...)``: Gymnasium's wrappers (make adds some) take no
render arguments, so the call reaches the class's own render through ``unwrapped``. A
keyword that render lacks, and the same keyword on ``CartPole-v1`` (whose render takes
none), stay as they are and are reported.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_render_arguments_kept"
runner = CliRunner()


def test_render_arguments_reach_the_class_that_takes_them(tmp_path: Path) -> None:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    result = runner.invoke(app, ["rewrite", str(run), "--report", str(tmp_path / "report.json")])
    assert result.exit_code == 0, result.output
    assert "def render(self, snapshot_dir=None, pause=True):" in (run / "boards" / "board.py").read_text()
    play = (run / "play.py").read_text()
    assert 'board.unwrapped.render(snapshot_dir="shots", pause=False)\n' in play
    assert "board.render(zoom=2)\n" in play
    assert 'pole.render(snapshot_dir="shots")\n' in play
    report = json.loads((tmp_path / "report.json").read_text())
    items = {(r["line"], r["rule"], r["kind"]) for f in report["files"] for r in f["review"] if f["path"].endswith("play.py")}
    assert items == {(7, "GM401", "assist"), (10, "GM401", "flag"), (15, "GM401", "flag")}
