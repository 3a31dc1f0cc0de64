"""An env class whose render(mode) hands its mode to an engine of the project's own
(``fixtures/project_own_render``).

``arena``'s ``MatchEnv.render(mode="human")`` only passes its mode to ``MatchEngine.render``,
and every caller in the run calls ``render()`` bare to switch drawing on: the render stays
as it is, no constructor gets a ``render_mode``, and no bare call is a question. ``court``
has the same shape, but a module asks for frames with ``render(mode="rgb_array")``: that
class is migrated, and its render hands the engine the mode the env is made with.
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

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_own_render"
runner = CliRunner()


@pytest.fixture
def run(tmp_path: Path) -> Path:
    shutil.copytree(FIXTURE, tmp_path / "run")
    return tmp_path / "run"


def test_a_render_handing_its_mode_to_an_own_engine_is_kept_and_asks_nothing(run: Path, tmp_path: Path) -> None:
    before = {name: (run / "arena" / name).read_text() for name in ("engine.py", "play.py")}
    result = runner.invoke(app, ["rewrite", str(run), "--report", str(tmp_path / "report.json")])
    assert result.exit_code == 0, result.output
    match_env = (run / "arena" / "match_env.py").read_text()
    assert 'def render(self, mode="human"):\n        return self._engine.render(mode=mode)' in match_env
    assert "render_mode" not in match_env
    assert (run / "arena" / "engine.py").read_text() == before["engine.py"]
    assert "render_mode" not in (run / "arena" / "play.py").read_text()
    report = json.loads((tmp_path / "report.json").read_text())
    findings = [dict(f, path=Path(file["path"])) for file in report["files"] for f in [*file["review"], *file["notes"]]]
    arena = [f for f in findings if f["path"].parent.name == "arena" and f["rule"] in ("GM401", "GM402", "GM405")]
    assert [(f["path"].name, f["rule"], f["tier"]) for f in arena] == [("match_env.py", "GM405", "note")]
    assert "no render call of the run passes it a mode" in arena[0]["message"]


def test_a_render_asked_for_frames_is_migrated_and_hands_its_engine_the_mode(run: Path) -> None:
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code == 0, result.output
    court_env = (run / "court" / "court_env.py").read_text()
    assert "def render(self):" in court_env
    assert "return self._engine.render(mode=self.render_mode)" in court_env
    assert 'CourtEnv(render_mode="rgb_array")' in (run / "court" / "shots.py").read_text()


def test_the_migrated_packages_switch_drawing_on_and_give_frames(run: Path) -> None:
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code == 0, result.output
    probe = (
        "from arena.play import create, watch\n"
        "env = create(render=True)\nassert env._engine.drawing\n"
        "env = create(timed=True)\nenv.render()\nassert env.unwrapped._engine.drawing\n"  # Gymnasium's Wrapper.render()
        "env = watch()\nassert env.unwrapped._engine.drawing and env.unwrapped._engine.frames == 1\n"
        "from court.shots import frame\nassert frame() == [[0, 0, 0]]\n"
    )
    done = subprocess.run([sys.executable, "-c", probe], cwd=run, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    again = runner.invoke(app, ["rewrite", "--diff", str(run)])
    assert "would rewrite 0 of" in again.output
