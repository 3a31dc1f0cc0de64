"""An env subclass in another module than its base adds its own end to the base's step (issue #19).

``fixtures/project_task_ends/``: ``ArenaEnv`` (``arena/core.py``) ends its episodes on a
step limit; ``Reach`` and ``Survive`` (``arena/tasks.py``, a module that never names Gym)
call ``super().step(action)`` and set ``done = True`` when the task is solved or lost.
Their returns used to come out as ``done, False`` (or not at all): the base's step limit
was returned as a termination. Now their own ends set ``terminated`` and they return the
base's ``terminated, truncated``, as a subclass in the base's own module does. ``Lab`` (``arena/lab.py``) takes its step from
a package the run does not hold: its return is reported, not guessed.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from tests.fixture_cases import FIXTURES

runner = CliRunner()


def _migrated(tmp_path: Path) -> tuple[Path, list[dict]]:
    project = tmp_path / "project_task_ends"
    shutil.copytree(FIXTURES / "project_task_ends", project)
    report = tmp_path / "report.json"
    result = runner.invoke(app, ["rewrite", "--report", str(report), str(project)])
    assert result.exit_code == 0, result.output
    findings = [dict(f, path=file["path"]) for file in json.loads(report.read_text())["files"] for f in file["review"]]
    return project, findings


def test_a_subclass_in_another_module_keeps_the_base_truncation(tmp_path: Path) -> None:
    project, review = _migrated(tmp_path)
    tasks = (project / "arena" / "tasks.py").read_text()
    assert tasks.count("return obs, reward, terminated, truncated, info") == 2, tasks
    assert "terminated = True" in tasks and "bool(done)" not in tasks, tasks
    code = (
        "from arena.tasks import Reach, Survive\n"
        "def run(env, action):\n"
        "    env.reset(seed=0)\n"
        "    while True:\n"
        "        _, _, terminated, truncated, _ = env.step(action)\n"
        "        if terminated or truncated:\n"
        "            return terminated, truncated\n"
        "print(run(Reach(), 1), run(Reach(), 0), run(Survive(), 0), run(Survive(max_steps=2), 0))\n"
    )
    done = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    # solved: terminated; the base's step limit: truncated (it was terminated); lost: terminated
    assert done.stdout.strip() == "(True, False) (False, True) (True, False) (False, True)"
    unknown = [f for f in review if f["path"].endswith("lab.py")]
    assert [f["rule"] for f in unknown] == ["GM504"] and "no env class this run holds" in unknown[0]["message"], review
    assert "return obs, reward, done, info" in (project / "arena" / "lab.py").read_text()
