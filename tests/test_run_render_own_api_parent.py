"""A class of the run left whole on an API of its own takes no render_mode, and neither do
its subclasses in other modules (``fixtures/project_render_own_api_parent``).

``arm/pour.py``'s ``PourEnv`` derives the migrated ``ArmEnv`` but its step serves two
callers (four values, or per-agent dicts with ``"__all__"``): it is reported and left as it
is, its ``__init__`` without ``render_mode``. ``arm/tasks.py``'s ``PourLeftEnv`` must then
not pass ``render_mode=`` to it (a TypeError building it), while ``WipeLeftEnv``, whose base
``WipeEnv`` is migrated, still takes it and hands it on.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_render_own_api_parent"
runner = CliRunner()


def test_no_render_mode_is_passed_to_a_base_left_on_its_own_api(tmp_path: Path) -> None:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code == 0, result.output
    pour = (run / "arm" / "pour.py").read_text()
    tasks = (run / "arm" / "tasks.py").read_text()
    assert "def __init__(self, arm, partner):" in pour
    assert 'super().__init__(arm="left", partner=None)\n' in tasks
    # the nearby heir of a migrated base still takes it
    assert "def __init__(self, arm, render_mode=None):" in pour
    assert 'super().__init__(arm="left", render_mode=render_mode)' in tasks
