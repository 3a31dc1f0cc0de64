"""Envs handed on from an attribute or from a name of several branches (issue #19).

``fixtures/project_held_arguments/``: ``trainer.py``'s ``Trainer`` holds its constructor's
``test_env`` in ``self.test_env`` and passes it to ``evaluation.evaluate``; ``main.py``
builds it only with ``gym.make(...)`` results. ``main.experiment`` binds ``env`` to
``gym.make(...)`` in one branch and to the run's ``Corridor`` (a ``gym.Env``) in the other,
and a nested def hands it to ``evaluation.rollout``. Both defs were asked about; the run
proves each a Gym env now, and the migrated code runs on Gymnasium.

The near cases stay asked: ``Prober`` is built once with a made env and once with the
project's ``Board`` (``probe``); ``main.tally`` binds a made env in one branch and a
``Board`` in the other (``score``); ``Examiner`` is built only with a made env, but
``loud.py`` derives ``LoudExaminer`` from it and builds that over a ``Board`` (``inspect``).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.fixture_cases import migrated_project


def _migrated(tmp_path: Path) -> tuple[Path, list[tuple[str, int, str]]]:
    return migrated_project(tmp_path, "project_held_arguments")


def test_held_and_branch_bound_envs_are_traced_and_the_near_cases_asked(tmp_path: Path) -> None:
    project, review = _migrated(tmp_path)
    evaluation = (project / "evaluation.py").read_text()
    assert evaluation.count("obs, reward, terminated, truncated, info = env.step(policy(obs))") == 2  # evaluate, rollout
    assert evaluation.count("obs, reward, done, info = env.step(") == 3  # probe, score, inspect
    assert review == [("evaluation.py", 23, "GM201"), ("evaluation.py", 29, "GM201"), ("evaluation.py", 35, "GM201")]


def test_the_migrated_code_runs_on_gymnasium(tmp_path: Path) -> None:
    project, _ = _migrated(tmp_path)
    code = (
        "import main\n"
        "print(len(main.train(2)), main.experiment('cart')(lambda obs: 0) > 0, main.experiment('corridor')(lambda obs: 1))\n"
    )
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["2", "True", "4"]
