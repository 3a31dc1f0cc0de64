"""A class deriving a Gym env class of the run that only a star import binds (issue #19).

``fixtures/project_star_bases/``: ``arena.walls`` does ``from .core import *`` and derives
``WalledArena`` from ``core.Arena``: the run binds the name as the import would, so the
subclass migrates with its base (a legacy ``reset`` under a migrated base raised on
``reset(seed=)``, its four-value ``_move`` broke the base's five-value ``step``). The near
case: ``arena.tiles`` star-imports a plain ``Board`` and then a module whose ``__all__``
leaves its own Gym ``Board`` out: ``TileBoard`` derives the plain one and stays as it is.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.fixture_cases import FIXTURES, migrated_project


def test_a_subclass_of_a_star_imported_env_class_migrates_with_its_base(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_star_bases")
    walls = (project / "arena" / "walls.py").read_text()
    assert "    def reset(self, *, seed=None, options=None):\n" in walls
    assert "self.np_random.integers(3)" in walls
    assert "return self.cell.copy(), {}" in walls
    assert "return self.cell.copy(), 0.5, bool(self.cell[1] >= 10.0), False, {}" in walls
    # the base's own reset is not the subclass's: Env's reset seeds np_random, as with a named import
    assert "        gymnasium.Env.reset(self, seed=seed)\n" in walls
    assert review == []
    tiles = FIXTURES / "project_star_bases" / "arena" / "tiles.py"
    assert (project / "arena" / "tiles.py").read_text() == tiles.read_text()
    code = (
        "from arena.walls import WalledArena\n"
        "from arena.tiles import TileBoard\n"
        "env = WalledArena()\n"
        "obs, info = env.reset(seed=1)\n"
        "obs, reward, terminated, truncated, info = env.step(0)\n"
        "print(reward, terminated, truncated, TileBoard().reset())\n"
        "print(bool((WalledArena().reset(seed=5)[0] == WalledArena().reset(seed=5)[0]).all()))\n"
    )
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["0.5", "False", "False", "1", "True"]
