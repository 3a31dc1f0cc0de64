"""GM111: ``gym.envs`` plugin entry points, and what a package's own test suite needs after
``gymmigrate rewrite .`` (the whole-repository benchmark's first failures), end to end.

``fixtures/project_plugins/`` is a small gym 0.25 package: ``setup.py`` registers its env
ids through a ``gym.envs`` entry point (gym called ``register_tile_envs`` on ``import
gym``), a test module subclasses one of its env classes with ``reset(**kwargs)`` / ``step``
overrides that call the base env's, and a wrapper reads the env's attributes and methods on
``self`` (``Wrapper.__getattr__`` forwarded them). Before this change the migrated suite
failed on every count: no id existed (Gymnasium loads no plugins), the subclass's hooks
kept the legacy API (its base, an env class of another module, was not recognised), and
``self.frame`` raised ``AttributeError``.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from gymmigrate.dependencies.plugins import plugin_entries
from tests.fixture_cases import FIXTURES

runner = CliRunner()


def _copy(tmp_path: Path, name: str) -> Path:
    target = tmp_path / name
    shutil.copytree(FIXTURES / name, target)
    return target


def _review(report: Path) -> list[dict]:
    return [f for file in json.loads(report.read_text())["files"] for f in file["review"] + file["notes"]]


def test_the_migrated_package_registers_its_envs_and_passes_its_own_tests(tmp_path: Path) -> None:
    project = _copy(tmp_path, "project_plugins")
    report = tmp_path / "report.json"
    result = runner.invoke(app, ["rewrite", "--report", str(report), str(project)])
    assert result.exit_code == 0, result.output
    init = (project / "tilegrid" / "__init__.py").read_text()
    assert init.endswith('entry_point="tilegrid.rooms:TrapRoom")\n\n\nregister_tile_envs()\n')
    setup = (project / "setup.py").read_text()
    assert '"gym.envs": ["__root__ = tilegrid.__init__:register_tile_envs"]' in setup  # reported, left for gym
    found = _review(report)
    assert any(f["rule"] == "GM111" and f["kind"] == "assist" and "`tilegrid/__init__.py`" in f["message"] for f in found), found
    run = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-W", "ignore", "checks"],
        cwd=project,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert run.returncode == 0, run.stdout + run.stderr
    assert "6 passed" in run.stdout
    again = runner.invoke(app, ["rewrite", "--diff", str(project)])
    assert "would rewrite 0 of" in again.output


def test_a_subclass_that_forwards_reset_keywords_keeps_its_signature(tmp_path: Path) -> None:
    project = _copy(tmp_path, "project_plugins")
    assert runner.invoke(app, ["rewrite", str(project)]).exit_code == 0
    checks = (project / "checks" / "test_rooms.py").read_text()
    # seed and options still reach the base env through **kwargs (no keyword-only seed takes them)
    assert "    def reset(self, **kwargs):\n        obs, info = super().reset(**kwargs)" in checks
    assert "obs, reward, terminated, truncated, info = super().step(action)" in checks


def test_an_entry_point_whose_module_is_not_in_the_run_is_reported(tmp_path: Path) -> None:
    project = _copy(tmp_path, "project_plugins")
    (project / "tilegrid" / "__init__.py").unlink()
    report = tmp_path / "report.json"
    assert runner.invoke(app, ["rewrite", "--report", str(report), str(project)]).exit_code == 0
    found = [f for f in _review(report) if f["rule"] == "GM111"]
    assert len(found) == 1 and found[0]["kind"] == "flag" and "no module `tilegrid.__init__`" in found[0]["message"]


def test_a_named_plugin_registers_in_its_namespace(tmp_path: Path) -> None:
    project = _copy(tmp_path, "project_plugins")
    setup = project / "setup.py"
    setup.write_text(setup.read_text().replace("__root__ = ", "tiles = "))
    assert runner.invoke(app, ["rewrite", str(project)]).exit_code == 0
    init = (project / "tilegrid" / "__init__.py").read_text()
    assert "from gymnasium.envs.registration import namespace" in init
    assert init.endswith("\n\n\nwith namespace('tiles'):\n    register_tile_envs()\n")
    code = "import gymnasium, tilegrid\nprint(gymnasium.make('tiles/TileGrid-4-v0').reset(seed=0)[0])"
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() in ("{'pos': 0}", "{'pos': 1}")


def test_setup_py_alone_reports_the_entry_point(tmp_path: Path) -> None:
    project = _copy(tmp_path, "project_plugins")
    result = runner.invoke(app, ["rewrite", "--diff", str(project / "setup.py")])
    assert "GM111" in result.output and "migrated without the package" in result.output


def test_entry_points_are_read_from_every_declaration_format() -> None:
    setup_py = 'setup(entry_points={"gym.envs": "[gym.envs]\\n"})\n'
    assert plugin_entries("setup.py", setup_py) == []
    text = 'setup(entry_points={"gym.envs": ["Grids = grids.envs:register [extra]", "bad entry"]})\n'
    (entry,) = plugin_entries("setup.py", text)
    assert (entry.name, entry.module, entry.attr, entry.namespace, entry.line) == ("Grids", "grids.envs", "register", "Grids", 1)
    ini = 'setup(entry_points="""\n[gym.envs]\n__root__ = grids:register\n""")\n'
    assert [e.target for e in plugin_entries("setup.py", ini)] == ["grids:register"]
    poetry = '[tool.poetry.plugins."gym.envs"]\n"__root__" = "grids:register"\n'
    assert [(e.target, e.namespace) for e in plugin_entries("pyproject.toml", poetry)] == [("grids:register", None)]
    assert plugin_entries("setup.py", "setup(entry_points={'gym.envs': [") == []  # does not parse: nothing
