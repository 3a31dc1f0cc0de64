"""Env functions handed to worker processes through a pickling holder (issue #19).

``fixtures/project_pipe_workers/``: three small projects with the baselines layout. Each
``main.py`` builds a vec env class of ``utils/vec.py`` over closures it defines; the class
spawns ``Process(target=worker, args=(..., Holder(env_fn)))`` and the worker calls
``env = holder.x()`` (the project's own holder in ``utils/pickling.py``, or baselines'
``CloudpickleWrapper``) and steps and resets it. The run follows the closures into the
worker: where they all make Gym envs the worker is migrated (the vec env's own step and
reset keep four fields); where they all make envs of a Gym-only library still on gym
(``multiagent``), the worker's calls are that library's decision, asked at its import;
where they make both, the worker stays asked about.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from tests.fixture_cases import FIXTURES, migrated_project


def test_closures_making_gym_envs_migrate_the_worker(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_pipe_workers/gym_maker")
    vec = (project / "utils" / "vec.py").read_text()
    assert "ob, reward, terminated, truncated, info = env.step(data)" in vec  # the worker
    assert "remote.send(env.reset()[0])" in vec
    assert "ob, reward, terminated, truncated, info = env.step(action)" in vec  # the in-process batch
    assert "obs, rewards, dones, infos = zip(*" in vec  # the vec env keeps its four fields
    assert "obs, rewards, dones, infos = envs.step([0] * n)" in (project / "main.py").read_text()
    assert not [r for r in review if r[0] == "utils/vec.py"], review
    code = "import main\nprint(main.run(2, 30), main.run(1, 30))"
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["(2,", "4)", "(1,", "4)"]


def _findings(project: Path) -> list[tuple[str, int, str, str]]:
    result = CliRunner().invoke(app, ["check", "--output-format", "json", str(project)])
    assert result.exit_code == 1, result.output
    return [(Path(f["path"]).relative_to(project).as_posix(), f["line"], f["rule"], f["tier"]) for f in json.loads(result.stdout)]


def test_closures_making_gym_only_library_envs_leave_the_worker_to_that_library() -> None:
    project = FIXTURES / "project_pipe_workers" / "particle_maker"
    findings = _findings(project)
    assert [f for f in findings if f[3] == "review"] == [("utils/make_env.py", 5, "GM107", "review"), ("utils/vec.py", 5, "GM107", "review")]
    worker = [f for f in findings if f[0] == "utils/vec.py" and f[2] != "GM107"]
    # the worker's env (14) and the in-process batch's items (63): the library's decision
    assert {(line, rule) for _, line, rule, _ in worker} >= {(14, "GM301"), (63, "GM304")}
    assert all(tier == "note" for *_, tier in worker)


def test_closures_making_gym_and_other_envs_keep_the_worker_asked_about(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_pipe_workers/mixed_makers")
    assert "ob, reward, done, info = env.step(data)" in (project / "utils" / "vec.py").read_text()
    assert ("utils/vec.py", 15, "GM301") in review, review
