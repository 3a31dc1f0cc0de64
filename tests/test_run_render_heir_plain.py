"""A registered subclass in a module that never names Gym (``fixtures/project_render_heir_plain``).

``market/envs/bonds.py`` derives ``BondsEnv`` from ``LedgerEnv`` of ``market/envs/ledger.py``
and never spells ``gym``: the run still gives it ``render_mode`` and hands it to the base, so
``show.py``'s ``gym.make("Bonds-v0")`` followed by a bare ``render()`` gets
``render_mode="human"`` instead of an item saying the class takes no render_mode.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_render_heir_plain"
runner = CliRunner()


def test_the_make_of_a_heir_that_takes_render_mode_gets_it(tmp_path: Path) -> None:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    result = runner.invoke(app, ["rewrite", str(run), "--report", str(tmp_path / "report.json")])
    assert result.exit_code == 0, result.output
    assert "def __init__(self, days, coupon=0.02, render_mode=None):" in (run / "market" / "envs" / "bonds.py").read_text()
    assert "super().__init__(days, render_mode=render_mode)" in (run / "market" / "envs" / "bonds.py").read_text()
    assert 'gym.make("Bonds-v0", render_mode="human")' in (run / "show.py").read_text()
    report = json.loads((tmp_path / "report.json").read_text())
    text = json.dumps(report)
    assert "takes no render_mode" not in text
