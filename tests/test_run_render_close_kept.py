"""``render(close=True)`` on an env whose class keeps render(close=...) (``fixtures/project_render_close_kept``).

``sims/base.py``'s ``SimEnv.render(mode, close)`` closes only its viewer; the run migrates it
to ``render(self, close=False)``. ``watch.py`` makes ``HoverEnv`` (registered by the run,
deriving ``SimEnv`` in another module) and calls ``render(close=True)``, directly and through
a wrapper: that call means "close the viewer", where ``close()`` would shut the env down, and
Gymnasium's wrappers (make adds some) take no render arguments, so it becomes
``unwrapped.render(close=True)``. The same call on ``CartPole-v1``, whose render takes no
``close``, becomes ``close()``.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_render_close_kept"
runner = CliRunner()


def test_render_close_reaches_the_class_that_keeps_it(tmp_path: Path) -> None:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    result = runner.invoke(app, ["rewrite", str(run), "--report", str(tmp_path / "report.json")])
    assert result.exit_code == 0, result.output
    assert "def render(self, close=False):" in (run / "sims" / "base.py").read_text()
    watch = (run / "watch.py").read_text()
    assert "hover.unwrapped.render(close=True)\n" in watch
    assert "logged.unwrapped.render(close=True)\n" in watch
    assert "pole.close()\n" in watch
    text = json.dumps(json.loads((tmp_path / "report.json").read_text()))
    assert "render(close=True) -> unwrapped.render(close=True)" in text
