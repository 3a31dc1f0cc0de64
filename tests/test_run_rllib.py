"""RLlib's multi-agent envs across a run (issue #19).

``fixtures/project_rllib/``: ``envs/grid.py`` derives ``GridEnv`` from RLlib's
``MultiAgentEnv``; ``envs/orchard.py`` subclasses it; ``envs/creator.py`` returns thunks
building those subclasses (``get_env_creator``), or one of them in one branch and a Gym env
in the other (``get_mixed_creator``); ``envs/pistons.py`` holds RLlib's
``ParallelPettingZooEnv`` in ``Pistons`` and a constructor argument in ``Holder``, and
``envs/shared.py`` steps what each base holds; ``scripts/rollout.py`` steps an ``Orchard``
it makes, what ``get_env_creator(...)(cfg)`` gives a constructor, and what
``get_mixed_creator(...)(cfg)`` gives one. RLlib's envs keep their per-agent dict API, so
the calls on them are left with no question; the mixed factory and the argument no caller
shows stay asked about. The ray release the gym-era RLlib code needs is asked once in the
run, at the first module importing RLlib next to gym.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from tests.fixture_cases import FIXTURES

runner = CliRunner()


def _migrated(tmp_path: Path) -> tuple[Path, dict[str, list[dict]]]:
    project = tmp_path / "project"
    shutil.copytree(FIXTURES / "project_rllib", project)
    report = tmp_path / "report.json"
    result = runner.invoke(app, ["rewrite", "--report", str(report), str(project)])
    assert result.exit_code == 0, result.output
    files = json.loads(report.read_text())["files"]
    tiers = {"review": [], "notes": []}
    for file in files:
        for tier in tiers:
            tiers[tier] += [{**f, "path": Path(file["path"]).relative_to(project).as_posix()} for f in file.get(tier, [])]
    return project, tiers


def _at(items: list[dict], path: str) -> list[tuple[int, str]]:
    return sorted((f["line"], f["rule"]) for f in items if f["path"] == path)


def test_rllib_envs_made_anywhere_in_the_run_are_left_with_no_question(tmp_path: Path) -> None:
    project, tiers = _migrated(tmp_path)
    rollout = (project / "scripts" / "rollout.py").read_text()
    assert rollout.count("obs, rewards, dones, infos = self.") == 3
    # ``Controller`` (an ``Orchard``, two modules below ``MultiAgentEnv``) and ``Driver``
    # (fed by the factory's thunks) ask nothing; ``Mixed`` still does
    assert _at(tiers["review"], "scripts/rollout.py") == [(34, "GM301")]
    assert _at(tiers["notes"], "scripts/rollout.py") == [(1, "GM101")]
    # ``SharedPistons`` steps what ``Pistons`` stores and steps in another module
    shared = [f for f in tiers["review"] + tiers["notes"] if f["path"] == "envs/shared.py"]
    assert [f["line"] for f in shared] == [13], shared
    # ``Pistons`` drives RLlib's PettingZoo wrapper; ``Holder`` an argument no caller shows
    assert [(line, rule) for line, rule in _at(tiers["review"], "envs/pistons.py")] == [(25, "GM301")]


def test_the_ray_release_is_asked_once_in_the_run(tmp_path: Path) -> None:
    _, tiers = _migrated(tmp_path)
    asked = [(f["path"], f["line"]) for f in tiers["review"] if f["rule"] == "GM107"]
    pointed = [(f["path"], f["line"]) for f in tiers["notes"] if f["rule"] == "GM107"]
    assert asked == [("envs/grid.py", 2)]
    assert pointed == [("envs/pistons.py", 3)]
    # a module importing gym alone (creator.py, rollout.py) has no ray question
    assert not [f for f in tiers["review"] + tiers["notes"] if f["rule"] == "GM107" and f["path"].startswith(("envs/creator", "scripts/"))]
