"""Space checks of a module that a script hands a Gym-only package's envs
(``fixtures/project_gym_only_spaces``).

``train.py`` builds a ``multiagent`` env with the factory of ``envs/particles.py`` and hands it
to the learner of ``learners/central.py``, whose ``isinstance(space, Box)`` tests gym's spaces:
its ``from gym.spaces import ...`` stays on gym with one item, as the same import would in the
script. ``tools/shapes.py`` is only re-exported by its package's ``__init__`` next to the
factory, which hands nothing between them: its import moves. ``watch.py`` draws the env the
factory builds: its ``render(mode)`` is the library's own API, so no render_mode is asked.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_gym_only_spaces"
runner = CliRunner()


def test_space_checks_fed_by_a_sibling_factory_keep_gym_spaces(tmp_path: Path) -> None:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code == 1
    findings = json.loads(result.stdout)
    gm103 = sorted((str(Path(f["path"]).relative_to(run)), f["line"], f["tier"]) for f in findings if f["rule"] == "GM103")
    assert gm103 == [("learners/central.py", 1, "review"), ("tools/shapes.py", 1, "note")]
    kept = next(f for f in findings if f["rule"] == "GM103" and f["path"].endswith("central.py"))
    assert kept["kind"] == "flag" and "multiagent" in kept["message"]


def test_renders_of_a_gym_only_env_made_elsewhere_ask_no_render_mode(tmp_path: Path) -> None:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    findings = json.loads(result.stdout)
    renders = [f for f in findings if f["path"].endswith("watch.py") and f["rule"] == "GM401"]
    assert [f["line"] for f in renders] == [6, 7]
    assert all(f["tier"] == "note" and "built on multiagent" in f["message"] for f in renders)
