"""A batch class in one module builds its envs from thunks other modules pass (issue #19).

``fixtures/project_thunks_across/``: ``vec/batch.py`` defines ``Batch(env_fns)`` with
``self.envs = [fn() for fn in env_fns]`` and steps and resets its items; ``train.py``
builds it over thunks it defines, ``evaluate.py`` over ``make_env`` of ``envs/factory.py``.
Each thunk wraps ``gym.make``. The items' step and reset were asked about and left while
the thunks' wrappers were ported (a ValueError at the first step); every construction of
the run is now seen and agrees, so they are ported with them. A construction the run
cannot follow, thunks of the project's own env, or thunks of a module left as it is keep
them asked about.
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


def _migrated(tmp_path: Path, extra: dict[str, str] | None = None) -> tuple[Path, list[tuple[str, int, str]]]:
    project = tmp_path / "project"
    shutil.copytree(FIXTURES / "project_thunks_across", project)
    for name, text in (extra or {}).items():
        path = project / name
        path.write_text(text if name != "envs/factory.py" else text + path.read_text())
    report = tmp_path / "report.json"
    result = runner.invoke(app, ["rewrite", "--report", str(report), str(project)])
    assert result.exit_code == 0, result.output
    review = [(Path(file["path"]).name, f["line"], f["rule"]) for file in json.loads(report.read_text())["files"] for f in file["review"]]
    return project, review


def test_thunks_of_every_module_of_the_run_settle_the_batch_items(tmp_path: Path) -> None:
    project, review = _migrated(tmp_path)
    batch = (project / "vec" / "batch.py").read_text()
    assert "obs, reward, terminated, truncated, info = env.step(action)" in batch
    assert "obs, reset_info = env.reset()" in batch and "env.reset()[0] for env in self.envs" in batch
    assert not [r for r in review if r[0] == "batch.py"], review
    code = "import train, evaluate\nprint(train.run(60))\nprint(len(evaluate.evaluate('CartPole-v1', 3)))"
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["(2,", "4)", "3"]


def test_a_list_the_run_does_not_show_leaves_the_items_asked_about(tmp_path: Path) -> None:
    # (a module the run reads: one that never says gym takes no part in the join)
    extra = {"extra.py": "import gym\n\nfrom vec.batch import Batch\n\n\ndef build(fns):\n    gym.logger.set_level(40)\n    return Batch(fns)\n"}
    project, review = _migrated(tmp_path, extra)
    assert "obs, reward, done, info = env.step(action)" in (project / "vec" / "batch.py").read_text()
    assert ("batch.py", 14, "GM301") in review, review


def test_thunks_of_the_projects_own_env_leave_the_items(tmp_path: Path) -> None:
    board = (
        "import gym\n\nfrom vec.batch import Batch\n\n\nclass Board:\n    action_space = gym.spaces.Discrete(2)\n\n"
        "    def reset(self):\n        return 0\n\n"
        "    def step(self, action):\n        return 0, 0.0, False, {}\n\n\n"
        "def boards(n):\n    return Batch([lambda: Board() for _ in range(n)])\n"
    )
    project, review = _migrated(tmp_path, {"boards.py": board})
    assert "obs, reward, done, info = env.step(action)" in (project / "vec" / "batch.py").read_text()
    assert ("batch.py", 14, "GM301") in review, review


def test_thunks_of_a_module_left_as_it_is_leave_the_items(tmp_path: Path) -> None:
    project, review = _migrated(tmp_path, {"envs/factory.py": "# gymmigrate: skip-file\n"})
    assert "obs, reward, done, info = env.step(action)" in (project / "vec" / "batch.py").read_text()
    assert ("batch.py", 14, "GM301") in review, review


_TRIAL_WRAPPER = (
    "import gym\n\n\nclass Trials(gym.Wrapper):\n    rounds = 2\n    finished = 0\n\n"
    "    def step(self, action):\n        obs, reward, inner_done, info = self.env.step(action)\n"
    "        trial_over = False\n        if inner_done:\n            self.finished += 1\n"
    "            trial_over = self.finished == self.rounds\n"
    "        return obs, reward, trial_over, info\n"
)
_TRIAL_BUILDER = (
    "import gym\n\nfrom vec.batch import Batch\nfrom trials import Trials\n\n\n"
    "def make_env(env_id, seed):\n    def thunk():\n        env = gym.make(env_id)\n        env.seed(seed)\n"
    "        env = Trials(env)\n        return env\n\n    return thunk\n\n\n"
    "def trials(n):\n    return Batch([make_env('CartPole-v1', i) for i in range(n)])\n"
)


def test_thunks_wrapping_in_a_class_of_another_module_settle_the_batch_items(tmp_path: Path) -> None:
    # ``make_env`` of one module wraps ``gym.make`` in a Gym wrapper class another module
    # defines: the join says what that class is, and the batch follows its ported step
    project, review = _migrated(tmp_path, {"trials.py": _TRIAL_WRAPPER, "build.py": _TRIAL_BUILDER})
    assert "obs, reward, terminated, truncated, info = env.step(action)" in (project / "vec" / "batch.py").read_text()
    assert not [r for r in review if r[0] == "batch.py"], review
    code = "import build\nprint(build.trials(2).reset().shape)"
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["(2,", "4)"]


def test_thunks_making_a_plain_class_of_another_module_leave_the_items(tmp_path: Path) -> None:
    # the same factory around the project's own plain class of another module: no Gym env
    board = "class Board:\n    def reset(self):\n        return 0\n\n    def step(self, action):\n        return 0, 0.0, False, {}\n"
    builder = _TRIAL_BUILDER.replace("from trials import Trials", "from board import Board").replace(
        "env = gym.make(env_id)\n        env.seed(seed)\n        env = Trials(env)", "env = Board()"
    )
    project, review = _migrated(tmp_path, {"board.py": board, "build.py": builder})
    assert "obs, reward, done, info = env.step(action)" in (project / "vec" / "batch.py").read_text()
    assert ("batch.py", 14, "GM301") in review, review
