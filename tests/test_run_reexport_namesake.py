"""A package whose ``__init__`` re-exports a function named like the submodule that defines
it (``from kit.tools.scale import scale``), that submodule holding no Gym code and so not
being a module of the run (``fixtures/project_reexport_namesake``): following the re-export
used to grow the name at every hop (``scale.scale.scale...``) and never end. The run
finishes and migrates the module that uses Gym.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_reexport_namesake"
SRC = Path(__file__).resolve().parent.parent / "src"


def test_a_reexported_namesake_of_a_submodule_ends_the_run(tmp_path: Path) -> None:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    # A subprocess with a deadline: the failure this guards against is a run that never ends.
    result = subprocess.run(
        [sys.executable, "-m", "gymmigrate", "rewrite", "."],
        cwd=run,
        capture_output=True,
        text=True,
        timeout=120,
        env={"PYTHONPATH": str(SRC), "PATH": "/usr/bin:/bin"},
    )
    assert result.returncode == 0, result.stderr
    text = (run / "kit" / "agent.py").read_text()
    assert "import gymnasium as gym" in text
    assert "obs, info = env.reset()" in text
    assert (run / "kit" / "tools" / "scale.py").read_text() == (FIXTURE / "kit" / "tools" / "scale.py").read_text()
