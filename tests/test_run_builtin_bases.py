"""Subclasses of env classes the run does not define: one of Gymnasium's own envs with an
``__init__`` of its own (GM405), and a mujoco-py scene whose API other modules read (GM508)
(``fixtures/project_builtin_bases``).

``LightCart(CartPoleEnv)`` takes ``render_mode`` and hands it to ``CartPoleEnv.__init__``, so the
make of its registered id in another module gets ``render_mode="human"`` for its render loop
(before, the id counted as registered without render_mode and the render stayed a question).
The scene's one GM508 item names the places outside any MujocoEnv class that read the
mujoco-py API in the modules its imports connect it to (``Player`` is handed the scene by
``Match``); an MjSim's own (``sim.model``) is mujoco-py itself, and a tool that imports nothing
of the arena is another project: neither is named.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures"
runner = CliRunner()


@pytest.fixture
def run(tmp_path: Path) -> Path:
    shutil.copytree(FIXTURES / "project_builtin_bases", tmp_path / "run")
    return tmp_path / "run"


def _findings(run: Path) -> list[dict]:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code in (0, 1), result.output
    return [{**f, "path": Path(f["path"]).relative_to(run).as_posix()} for f in json.loads(result.stdout)]


def test_the_registered_subclass_takes_render_mode_and_its_make_gets_it(run: Path) -> None:
    found = _findings(run)
    [subclass] = [f for f in found if f["path"] == "carts/light.py" and f["rule"] == "GM405"]
    assert subclass["line"] == 5 and "`CartPoleEnv`" in subclass["message"]
    [make] = [f for f in found if f["path"] == "watch_cart.py" and f["rule"] == "GM402"]
    assert make["kind"] == "assist" and 'added render_mode="human"' in make["message"]


def test_the_migrated_subclass_is_made_with_a_render_mode(run: Path) -> None:
    pytest.importorskip("gymnasium")
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code in (0, 1), result.output
    probe = "import gymnasium, carts\nenv = gymnasium.make('LightCart-v0', render_mode='rgb_array')\nprint(env.unwrapped.render_mode)\n"
    done = subprocess.run([sys.executable, "-W", "ignore", "-c", probe], cwd=run, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "rgb_array"


def test_the_scene_item_names_the_mujoco_py_reads_outside_its_class(run: Path) -> None:
    [scene] = [f for f in _findings(run) if f["rule"] == "GM508"]
    assert (scene["path"], scene["line"]) == ("arena/scene.py", 6)
    assert "match.py:12 and 2 more lines, player.py:9)" in scene["message"]
    assert "replay.py" not in scene["message"]  # a module of another project of the run
