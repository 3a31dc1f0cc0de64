"""A print-only ``render(self, mode="human")`` of an env class that a factory of the run
builds (``fixtures/project_render_factory_module``).

``agent.py`` gets its env from ``factory.make_env``, whose module imports ``GridEnv`` in
the factory's body, and renders it through an attribute the run cannot trace,
``agent.env.render("human")``; no creation gives a render_mode. ``render`` keeps ``mode`` as
an optional parameter (GM405), so that call still prints instead of raising TypeError.
``BoardEnv``, built by another factory whose callers only render bare, takes the standard
``render(self)``.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.fixture_cases import migrated_project


def test_a_mode_passed_to_an_env_from_a_factory_module_keeps_render_s_mode(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_render_factory_module")
    grid = (project / "grid.py").read_text()
    assert "def render(self, mode=None):" in grid and "mode = self.render_mode" in grid
    board = (project / "board.py").read_text()
    assert "def render(self):" in board and "if self.render_mode is None:" in board
    assert ("grid.py", 22, "GM405") in review
    run = subprocess.run(
        [sys.executable, "-c", "import agent; print(agent.main())"], cwd=project, capture_output=True, text=True, check=False
    )
    assert run.returncode == 0, run.stderr
    assert run.stdout.count("player at") == 3 and run.stdout.rstrip().endswith("ok"), run.stdout
