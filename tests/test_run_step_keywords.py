"""The action passed by the env class's own keyword to a made env's step
(``fixtures/project_step_keywords``, GM606).

``cook.py`` makes ``kitchen:Kitchen-v0``, which ``kitchen/__init__.py`` registers for
``KitchenEnv``, whose ``step(self, action_dict)`` takes the keyword first: on the make result
(a Gymnasium wrapper outermost, ``step(self, action)``) ``step(action_dict=a)`` is a
TypeError, and the action goes by position. ``Pantry-v0``'s class takes ``action`` first and
``action_dict`` second: the keyword is reported, not moved. ``KitchenEnv()`` built directly
has no wrapper: its call is left.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from tests.fixture_cases import FIXTURES


def test_a_made_envs_step_gets_the_action_by_position(tmp_path: Path) -> None:
    project = tmp_path / "project"
    shutil.copytree(FIXTURES / "project_step_keywords", project)
    report = tmp_path / "report.json"
    result = CliRunner().invoke(app, ["rewrite", "--jobs", "1", "--report", str(report), str(project)])
    assert result.exit_code == 0, result.output
    text = (project / "cook.py").read_text()
    assert 'env.step({"chef": 1})' in text  # the made Kitchen-v0
    assert 'env.step(action_dict={"shelf": 2})' in text  # Pantry-v0: action first, action_dict second
    assert text.count('env.step(action_dict={"chef": 1})') == 1  # the class built directly
    files = json.loads(report.read_text())["files"]
    review = [(f["line"], f["rule"]) for file in files if file["path"].endswith("cook.py") for f in file["review"]]
    assert review == [(20, "GM606")]
    notes = [(f["line"], f["rule"]) for file in files if file["path"].endswith("cook.py") for f in file["notes"]]
    assert (11, "GM606") in notes and (26, "GM606") not in notes
