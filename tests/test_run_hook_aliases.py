"""A base env whose gym <= 0.9 hooks (``_seed``, ``_reset``, ``_close``) are published by
class-level aliases under a version test, and subclasses in other modules that call the
base's hook (``ArenaEnv._reset(self)``) or its public reset (``ArenaEnv.reset(self)``)
(``fixtures/project_hook_aliases``), migrated by one run and used on Gymnasium 1.4.

The hooks keep their names (the subclasses call them) and the ``reset`` alias becomes a
reset taking seed and options; each subclass's reset seeds as legacy ``seed(n); reset()``
did and returns one ``(obs, info)`` pair.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_hook_aliases"
runner = CliRunner()

_USE = """
import numpy as np
from gymnasium.utils.env_checker import check_env
from arenas import Runner, Sprinter
from arenas.base import ArenaEnv

for cls in (ArenaEnv, Runner, Sprinter):
    env = cls()
    first, info = env.reset(seed=3)
    again, _ = env.reset(seed=3)
    other, _ = env.reset(seed=4)
    assert isinstance(first, np.ndarray) and first.shape == (3,), (cls, first)
    assert info == {}, (cls, info)
    assert np.array_equal(first, again) and not np.array_equal(first, other), cls
    if cls is not ArenaEnv:
        assert len(env.step(1)) == 5
        check_env(env, skip_render_check=True)
    env.close()
    assert env.closed
print("ok")
"""


def test_aliased_hooks_and_their_subclasses_reset_seeded_on_gymnasium(tmp_path: Path) -> None:
    project = tmp_path / "project"
    shutil.copytree(FIXTURE, project)
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    again = runner.invoke(app, ["rewrite", str(project)])
    assert "rewrote 0 of" in again.output, again.output
    base = (project / "arenas" / "base.py").read_text()
    assert "def _reset(self):" in base and "def reset(self, *, seed=None, options=None):" in base
    assert "close = _close" in base and "seed = _seed" in base
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", _USE], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "ok"
