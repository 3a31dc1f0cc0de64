"""A helper step reached through a class that only hands it on and a package ``__init__``
that star-imports the base module (``fixtures/project_star_helper``), checked as one run.

``SimBase.step`` returns one flag, ``Scaled.step`` hands it on under a changed action, and
``sim/walk.py`` derives from ``Scaled`` and ``Clocked`` as ``sim`` re-exports them. The
overrides' ``failed = super().step(a)`` is a bool, no step result: no GM304 item. ``Walk``
and its bases count nothing, so its truncated=False is a note; ``Clocked`` counts ticks
against a horizon, so ``TimedWalk`` keeps its item. ``SimBase`` keeps its reset on its own
return, which stays asked about at its step.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from tests.fixture_cases import FIXTURES

runner = CliRunner()


def test_flag_of_a_helper_step_is_no_step_result(tmp_path: Path) -> None:
    project = tmp_path / "project"
    shutil.copytree(FIXTURES / "project_star_helper", project)
    checked = runner.invoke(app, ["check", "--output-format", "json", str(project)])
    findings = json.loads(checked.stdout)
    review = sorted((Path(f["path"]).name, f["line"], f["rule"]) for f in findings if f["tier"] == "review")
    assert review == [("base.py", 24, "GM504"), ("walk.py", 23, "GM504")], review
    notes = {(Path(f["path"]).name, f["line"], f["rule"]) for f in findings if f["tier"] == "note"}
    assert ("walk.py", 14, "GM504") in notes
