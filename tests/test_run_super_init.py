"""A base class's ``self.env`` set from what its subclasses in other modules hand up with
``super().__init__(...)`` (``fixtures/project_super_init``).

``train.py`` picks the agent class by a conditional expression among two classes a
package re-exports, and passes the envs its factory makes; each subclass's ``__init__``
hands them up to ``agents/base.py``, whose resets and steps are then certain. A subclass
elsewhere that hands up ``*envs`` (what reaches the base is not seen) keeps the base's
question.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_super_init"
runner = CliRunner()


def _base_findings(run: Path) -> list[dict]:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code == 1
    return [f for f in json.loads(result.stdout) if Path(f["path"]).name == "base.py"]


def test_super_init_of_chosen_reexported_subclasses_is_traced(tmp_path: Path) -> None:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    found = _base_findings(run)
    assert sorted((f["line"], f["rule"], f["kind"]) for f in found) == [
        (9, "GM203", "assist"), (12, "GM201", "auto"), (15, "GM301", "auto")
    ]


def test_a_subclass_handing_up_unseen_arguments_keeps_the_question(tmp_path: Path) -> None:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    (run / "agents" / "noisy.py").write_text(
        "from .base import Agent\n\n\nclass NoisyAgent(Agent):\n"
        "    def __init__(self, *envs, sigma=0.1):\n        super().__init__(*envs)\n        self.sigma = sigma\n"
    )
    found = _base_findings(run)
    assert {f["kind"] for f in found} == {"flag"}
    assert any(f["tier"] == "review" and f["line"] == 9 for f in found)
