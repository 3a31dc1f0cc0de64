"""A name bound to the project's own env class in one branch and to a Gym env in another,
handed to a def (issue #19).

``fixtures/project_branch_own_class/``: ``runner.run`` builds ``walker.Walker`` (an own
``Env(object)`` class, reset and step on the old API) or ``gym.make(name)`` and hands either
to ``play``; ``runner.train`` does the same through two methods of ``Collector`` (``collect``
hands its parameter to ``sample``). The "this file uses only Gym" fallback used to rewrite
those resets and steps, which broke the ``Walker`` path (``ob, info = env.reset()`` split
its observation; the five-name unpack raised). They are now reported once and left.
``rerun``, whose branches build the run's own ``gym.Env`` subclass or a made env, still has
``replay`` migrated with no item, and the migrated code runs on Gymnasium.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.fixture_cases import FIXTURES, migrated_project


def test_own_class_beside_gym_env_is_reported_and_all_gym_branches_migrated(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_branch_own_class")
    runner = (project / "runner.py").read_text()
    assert runner.count("ob, rew, done, _ = env.step(") == 2  # play, Collector.sample: left
    assert runner.count("ob, rew, terminated, truncated, _ = env.step(") == 1  # replay
    assert runner.count("ob, info = env.reset()") == 1
    assert review == [("runner.py", 5, "GM201"), ("runner.py", 39, "GM201")]
    assert (project / "walker.py").read_text() == (FIXTURES / "project_branch_own_class" / "walker.py").read_text()
    code = "import runner\nprint(runner.run('Walker-v0'), runner.train('Walker-v0'), runner.rerun('Corridor-v0'), runner.rerun('CartPole-v1'))\n"
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["0.0", "[0.0,", "0.0]", "1.0", "1.0"]
