"""Methods the run removes or renames in one module, called by their old name from another
(``fixtures/project_removed_callers``), migrated by one ``gymmigrate rewrite`` and run on
Gymnasium 1.4 (``facts/project_hooks.py``).

``sims``: ``SimEnv`` has a canonical seed(), and ``ObjectsEnv`` (``objects.py``, below it
through ``ArmEnv`` of ``arm.py``) calls ``self.seed(layout_seed)`` in its constructor. Before,
GM503 deleted the seed() and ``ObjectsEnv()`` raised AttributeError; now it is kept and
reported. ``GridEnv``'s seed() goes: the only call below it (``MazeEnv``) reaches a seed()
of the subclass's own. ``TrackedEnv``'s seed() (a generic class) is kept too: ``ReplayEnv``
names its base parametrized (``TrackedEnv[str]``), which is that base all the same, and
reseeds through the getter on every reset.

``arena``: ``ArenaEnv`` is a gym 0.7 env (``_step``, ``_reset``) the run renames.
``GuardEnv`` keeps a ``_reset`` of its own as a helper of a reset that takes a handicap and
calls ``super(GuardEnv, self)._reset()``; ``RestartEnv`` calls ``self._reset()`` from a
helper. Before, both calls kept the old name and raised AttributeError on Gymnasium; now
they call ``reset`` and take the observation from its pair. ``PlainEnv`` renames its own
``_reset`` like the base, whose super call already followed.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from tests.fixture_cases import FIXTURES

runner = CliRunner()

_PLAY = """
import numpy as np
from sims.objects import ObjectsEnv
from sims.maze import MazeEnv
from arena.guard import GuardEnv
from arena.restart import RestartEnv
from arena.plain import PlainEnv
from sims.replay import ReplayEnv

one, two = ObjectsEnv(), ObjectsEnv()
print(one.colors == two.colors, one.reset(seed=3)[0].shape)
print(MazeEnv().layout, MazeEnv().reset(seed=1)[0] == MazeEnv().reset(seed=1)[0])
guard = GuardEnv()
obs, info = guard.reset(handicap=[1])
print(type(obs).__name__, info, guard.elapsed, guard.step(0)[1:4])
print(RestartEnv().restart().tolist(), PlainEnv().reset(seed=2)[0].tolist())
replay = ReplayEnv()
print(replay.reset()[0].tolist() == replay.reset()[0].tolist())
"""


def test_callers_elsewhere_keep_working_after_their_base_migrates(tmp_path: Path) -> None:
    project = tmp_path / "project"
    shutil.copytree(FIXTURES / "project_removed_callers", project)
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    again = runner.invoke(app, ["rewrite", str(project)])
    assert "rewrote 0 of" in again.output, again.output
    core = (project / "sims" / "core.py").read_text()
    assert core.count("    def seed(self, seed=None):") == 1  # SimEnv's stays, GridEnv's goes
    assert "        self.seed()\n" in core
    assert "seed() kept: `ObjectsEnv` (objects.py)" in result.output
    assert "seed() kept: `ReplayEnv` (replay.py)" in result.output
    assert "ob, _ = super(GuardEnv, self).reset()" in (project / "arena" / "guard.py").read_text()
    assert "ob, _ = self.reset()" in (project / "arena" / "restart.py").read_text()
    assert "        return super().reset(seed=seed)\n" in (project / "arena" / "plain.py").read_text()
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", _PLAY], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.splitlines() == [
        "True (3,)",
        "7 True",
        "ndarray {} 0 (1.0, False, False)",
        "[0.0, 0.0] [0.0, 0.0]",
        "True",
    ]


def test_the_legacy_package_ran_the_same_way(tmp_path: Path) -> None:
    """The same calls on the legacy code, with the hooks and seed() as gym <= 0.9 called them:
    what the migrated package prints is what this one did (seeding aside)."""
    project = tmp_path / "project"
    shutil.copytree(FIXTURES / "project_removed_callers", project)
    shim = tmp_path / "gym"
    shim.mkdir()
    # gym 0.7's Env as far as these classes use it: step/reset call the hooks
    (shim / "__init__.py").write_text(
        "from gymnasium import spaces\n"
        "class Env:\n"
        "    def step(self, action):\n        return self._step(action)\n"
        "    def reset(self):\n        return self._reset()\n"
    )
    (shim / "utils.py").write_text("from gymnasium.utils import seeding\n")
    code = (
        "from sims.objects import ObjectsEnv\nfrom arena.guard import GuardEnv\nfrom arena.restart import RestartEnv\n"
        "one, two = ObjectsEnv(), ObjectsEnv()\nprint(one.colors == two.colors)\n"
        "guard = GuardEnv()\nobs = guard.reset(handicap=[1])\nprint(type(obs).__name__, guard.elapsed, guard.step(0)[1:3])\n"
        "print(RestartEnv().restart().tolist())\n"
    )
    env = {**os.environ, "PYTHONPATH": f"{tmp_path}:{project}"}
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120, env=env)
    assert run.returncode == 0, run.stderr
    assert run.stdout.splitlines() == ["True", "ndarray 0 (1.0, False)", "[0.0, 0.0]"]
