"""The hooks of .pre-commit-hooks.yaml through the real pre-commit tool (try-repo):
the check hook fails on legacy code, the rewrite hook fixes it."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("pre_commit", reason="pre-commit is not installed (pip install -e '.[test]' brings it)")

ROOT = Path(__file__).resolve().parent.parent
LEGACY = b"import gym\n\nenv = gym.make('CartPole-v1')\nobs = env.reset()\n"


def git(*arguments: str, cwd: Path) -> None:
    subprocess.run(["git", *arguments], cwd=cwd, check=True, capture_output=True)


def pre_commit(*arguments: str, cwd: Path, home: Path) -> subprocess.CompletedProcess[str]:
    environment = {**os.environ, "PRE_COMMIT_HOME": str(home), "PRE_COMMIT_COLOR": "never"}
    environment.pop("PYTHONPATH", None)  # the hook runs from its own environment
    return subprocess.run(
        [sys.executable, "-m", "pre_commit", *arguments], cwd=cwd, env=environment, capture_output=True, text=True,
        timeout=600,
    )


@pytest.mark.skipif(shutil.which("git") is None, reason="git is not installed")
def test_check_hook_fails_and_rewrite_hook_fixes(tmp_path: Path) -> None:
    project, home = tmp_path / "project", tmp_path / "pre-commit-home"
    project.mkdir()
    git("init", "-q", cwd=project)
    (project / "train.py").write_bytes(LEGACY)
    notebook = ROOT / "fixtures" / "notebooks" / "multi_cell_loop.ipynb"
    shutil.copy(notebook, project / "play.ipynb")
    git("add", "train.py", "play.ipynb", cwd=project)

    check = pre_commit("try-repo", str(ROOT), "gymmigrate-check", "--all-files", cwd=project, home=home)
    assert check.returncode == 1, check.stdout + check.stderr
    assert "train.py:1:1: GM101" in check.stdout
    assert "play.ipynb:cell 3:line 1:1: GM101" in check.stdout, "notebooks reach the hooks too"
    assert (project / "train.py").read_bytes() == LEGACY, "the check hook writes nothing"

    rewrite = pre_commit("try-repo", str(ROOT), "gymmigrate", "--all-files", cwd=project, home=home)
    assert rewrite.returncode == 1, "pre-commit fails a hook that modified files"
    assert "files were modified by this hook" in rewrite.stdout
    migrated = (project / "train.py").read_bytes()
    assert migrated.startswith(b"import gymnasium as gym\n")
    assert b"obs, info = env.reset()" in migrated
    assert (project / "play.ipynb").read_bytes() == notebook.with_name("multi_cell_loop.expected.ipynb").read_bytes()

    git("add", "train.py", "play.ipynb", cwd=project)
    again = pre_commit("try-repo", str(ROOT), "gymmigrate-check", "--all-files", cwd=project, home=home)
    assert again.returncode == 0, again.stdout + again.stderr
