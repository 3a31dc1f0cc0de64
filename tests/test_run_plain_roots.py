"""A project's seed() over a Gym env, in a class whose base is the project's own interface in
another module (GM203): ``fixtures/project_plain_roots``.

``tasks/interface.py`` (no Gym code) defines ``class Task(ABC)``; ``GymTask(Task)`` in
``tasks/gym_tasks.py`` seeds the env it makes in its seed(), which only the project calls:
``self.world.seed(s)`` becomes ``self.world.reset(seed=s)`` (asked once: a mid-episode seed()
now restarts the episode). ``RemoteGymTask`` derives a class of the run whose base is another
package's, which may call seed() as a hook: still asked, not rewritten.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_plain_roots"
runner = CliRunner()


@pytest.fixture
def run(tmp_path: Path) -> Path:
    shutil.copytree(FIXTURE, tmp_path / "run")
    return tmp_path / "run"


def _gm203(target: Path) -> dict[int, dict]:
    result = runner.invoke(app, ["check", "--output-format", "json", str(target)])
    return {f["line"]: f for f in json.loads(result.stdout) if f["rule"] == "GM203"}


def test_a_seed_method_of_a_class_of_the_projects_own_interface_is_rewritten(run: Path) -> None:
    found = _gm203(run)
    assert found[12]["kind"] == "assist"
    assert "`self.world.reset(seed=s)` in `GymTask.seed()`" in found[12]["message"]
    assert found[20]["kind"] == "flag"  # a base deriving another package's class: still asked
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code in (0, 1), result.output
    migrated = (run / "tasks" / "gym_tasks.py").read_text()
    assert migrated.count("self.world.reset(seed=seed)") == 1
    assert migrated.count("self.world.seed(seed)") == 1
    assert (run / "tasks" / "interface.py").read_bytes() == (FIXTURE / "tasks" / "interface.py").read_bytes()


def test_the_module_checked_alone_still_asks(run: Path) -> None:
    """Without the run, the imported base is unknown: the seed() is asked about, not rewritten."""
    found = _gm203(run / "tasks" / "gym_tasks.py")
    assert {line: f["kind"] for line, f in found.items()} == {12: "flag", 20: "flag"}
