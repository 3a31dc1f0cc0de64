"""Gym envs a factory of another module gives as a closure in a tuple (issue #19).

``fixtures/project_factory_closures/``: ``sim/factory.py``'s ``track_factory`` returns
``create, name``, where ``create`` registers an id and returns ``gym.envs.make(name)``;
``board_factory`` returns a closure building the project's own ``Board``.
``sim/experiment.py`` unpacks the first (``create, _ = track_factory(...)``), indexes it
(``track_factory(...)[0]()``) and calls the closure: a make result, whose own attributes
are read through ``get_wrapper_attr`` and whose reset and step take Gymnasium's API. The
board the other closure builds is left as it is.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.fixture_cases import migrated_project


def test_a_closure_of_make_results_is_a_made_env_and_the_own_object_is_left(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_factory_closures")
    experiment = (project / "sim" / "experiment.py").read_text()
    assert 'self.laps = self.env.get_wrapper_attr("distance")' in experiment
    assert "state, info = self.env.reset()" in experiment
    assert "state, reward, terminated, truncated, _ = self.env.step(0)" in experiment
    assert 'self.env.get_wrapper_attr("lap_time")()' in experiment
    assert 'return env.get_wrapper_attr("distance")' in experiment
    assert "board.reset()\n    cells, reward, done, info = board.step(0)\n    return board.size, reward" in experiment
    assert review == [("sim/track.py", 21, "GM504")]  # the env's own step limit, asked as ever


def test_the_migrated_code_runs_on_gymnasium(tmp_path: Path) -> None:
    project, _ = migrated_project(tmp_path, "project_factory_closures")
    code = (
        "from sim.experiment import Experiment, quick, puzzle\n"
        "print(Experiment(3, 0).run(), quick(4, 1), puzzle(2))\n"
    )
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "(3.0, 1.5) 4 (2, 1.0)"
