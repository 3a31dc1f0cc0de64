"""Renders of an env another module makes (GM402): ``fixtures/project_render_agents``.

Two agent modules render, under the run script's ``--render`` flag, the env the script makes
and passes them. The mode is chosen at that make now: one decision for the run, asked once
(in the first agent module, naming the other), never silent; the migrated package runs.
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

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_render_agents"
runner = CliRunner()


@pytest.fixture
def run(tmp_path: Path) -> Path:
    shutil.copytree(FIXTURE, tmp_path / "run")
    return tmp_path / "run"


def test_the_render_of_an_env_made_elsewhere_is_one_question_for_the_run(run: Path) -> None:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    renders = [f for f in json.loads(result.stdout) if f["rule"] == "GM402"]
    assert sorted((Path(f["path"]).name, f["line"], f["tier"]) for f in renders) == [
        ("greedy.py", 13, "review"),
        ("random_walk.py", 13, "note"),
    ]
    asked = next(f for f in renders if f["tier"] == "review")
    assert "passed in at ../run.py:20" in asked["message"]
    assert 'render_mode="human" if <self.args.render' in asked["message"]
    assert asked["message"].endswith(f"(the same decision at 1 other place: {run / 'agents' / 'random_walk.py'}:13)")


def test_the_migrated_agents_run_with_rendering_off(run: Path) -> None:
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code in (0, 1), result.output
    for algo in ("greedy", "walk"):
        probe = f"from run import main\nlengths = main(['--algo', {algo!r}])\nassert len(lengths) == 3 and min(lengths) > 0\n"
        done = subprocess.run([sys.executable, "-c", probe], cwd=run, capture_output=True, text=True, timeout=120)
        assert done.returncode == 0, done.stderr


def test_an_env_drawn_by_a_wrapper_of_another_module_is_reported_where_it_is_made(tmp_path: Path) -> None:
    """``fixtures/project_render_wrappers``: ``train.py`` wraps its ``gym.make`` env in the
    package's ``Draw`` (re-exported by ``showing/wrappers/__init__.py``), whose reset/step
    render it: legacy drew each time, an env made without a render_mode draws nothing."""
    project = tmp_path / "wrapped"
    shutil.copytree(FIXTURE.parent / "project_render_wrappers", project)
    result = runner.invoke(app, ["check", "--output-format", "json", str(project)])
    renders = [f for f in json.loads(result.stdout) if f["rule"] == "GM402" and Path(f["path"]).name == "train.py"]
    assert [(f["line"], f["tier"]) for f in renders] == [(10, "review")]
    assert "rendered by `showing.wrappers.Draw` (line 12)" in renders[0]["message"]
