"""``rewrite`` and ``check`` read code; they never run it, nor import anything from it.

The planted project leaves a marker file for every piece of its code that runs: its own
package, the script's main block, a conftest.py and setup.py, and look-alikes of
modules gymmigrate or the migrated code import (gym, gymnasium, typer, rich, libcst,
numpy), placed where ``python -m gymmigrate`` started in that folder would find them
first if it left the folder on sys.path.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from .cli_process import run_cli

SCRIPT = """import gym
import planted_package
from planted_package import helpers

env = gym.make("CartPole-v1")
obs = env.reset()

if __name__ == "__main__":
    {marker}
"""
# Each file: where it goes, and the name of the marker it leaves when it runs.
PLANTED = {
    "planted_package/__init__.py": "planted_package",
    "planted_package/helpers.py": "planted_helpers",
    "conftest.py": "conftest",
    "setup.py": "setup",
    "gym/__init__.py": "gym",
    "gymnasium/__init__.py": "gymnasium",
    "numpy/__init__.py": "numpy",
    "typer.py": "typer",
    "rich/__init__.py": "rich",
    "libcst/__init__.py": "libcst",
}


def _plant(project: Path) -> Path:
    """The project, with a folder that collects the markers; returns that folder."""
    markers = project / "markers"
    markers.mkdir(parents=True)

    def leave_marker(name: str) -> str:
        return f"open({str(markers / name)!r}, 'w').close()"

    (project / "train.py").write_text(SCRIPT.format(marker=leave_marker("train_main")))
    for relative, name in PLANTED.items():
        path = project / relative
        path.parent.mkdir(exist_ok=True)
        # Mentions gym, so the pre-parse filter reads it like any other file.
        path.write_text(f"import gym\n{leave_marker(name)}\n")
    return markers


@pytest.mark.parametrize("command", [["check", "."], ["rewrite", "."], ["rewrite", "--diff", "train.py"]])
def test_no_code_of_the_project_runs(tmp_path: Path, command: list[str]) -> None:
    project = tmp_path / "project"
    markers = _plant(project)
    completed = run_cli(*command, cwd=project)
    assert "Traceback" not in completed.stderr, completed.stderr
    assert completed.returncode in (0, 1), completed.stderr
    assert sorted(path.name for path in markers.iterdir()) == [], "code of the project ran"
    if command == ["rewrite", "."]:
        assert (project / "train.py").read_bytes().startswith(b"import gymnasium as gym\n"), "the run did its work"
    else:
        assert "train.py" in completed.stdout, "the run looked at the script"
