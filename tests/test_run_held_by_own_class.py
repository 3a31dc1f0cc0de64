"""Gym envs held by plain classes of the project's own from their constructor (issue #19).

``fixtures/project_held_by_own_class/``: ``Planner`` stores its constructor's ``task`` and
reads the env's own ``width`` and ``agent_pos``; it is built only by ``PlannerAgent`` from
the env that class holds, and ``run.py`` builds ``PlannerAgent`` only over ``gym.make``
results. Legacy wrappers forwarded those reads; Gymnasium's raise AttributeError, so they
now get past the wrappers, and the migrated code runs.

The near cases: ``Scout`` is built the same way, but ``replay.py`` hands its agent an
unpickled object the run cannot trace: its read is asked, naming the construction that
hands on a Gym env. ``Tracker`` is built only over the project's ``Board``: left as it is.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.fixture_cases import migrated_project


def test_reads_of_a_held_make_result_get_past_the_wrappers(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_held_by_own_class")
    planner = (project / "helpers" / "planner.py").read_text()
    assert 'self.half = task.get_wrapper_attr("width") // 2' in planner
    assert 'x, _ = self.task.get_wrapper_attr("agent_pos")' in planner
    assert "return self.task.agent_pos" in (project / "helpers" / "scout.py").read_text()
    assert "return self.board.agent_pos" in (project / "helpers" / "tracker.py").read_text()
    assert review == [("helpers/scout.py", 9, "GM604")]
    run = subprocess.run(
        [sys.executable, "-W", "ignore", "-c", "import run, board; print(run.main(), board.track())"],
        cwd=project,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["(0,", "True)", "(1,", "2)"]
