"""One decision per parameter, none where the run's only caller passes another library's env
(``fixtures/project_pairs_star_caller``).

``bench/rollouts.py`` names no env library; ``bench/run.py`` reaches its defs through a star
import. ``rollout``'s only caller passes the env of each ``(name, env)`` pair of a list it
fills with rllab envs (``normalize(GymEnv(name))``: rllab's own API, never Gymnasium's): its
reset, step, renders and ``render(close=True)`` ask nothing. ``evaluate``'s caller passes a
parameter the run cannot trace: its reset, step, render and close ask one question, at the
reset. ``score`` is given a ``gym.make`` env and is migrated.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_pairs_star_caller"
runner = CliRunner()


def _findings(run: Path) -> list[dict]:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code in (0, 1), result.output
    return [{**f, "path": Path(f["path"]).relative_to(run).as_posix()} for f in json.loads(result.stdout)]


def _copy(tmp_path: Path) -> Path:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    return run


def _in(findings: list[dict], first: int, last: int) -> list[tuple[int, str, str, str]]:
    return [
        (f["line"], f["rule"], f["kind"], f["tier"])
        for f in findings
        if f["path"] == "bench/rollouts.py" and first <= f["line"] <= last
    ]


def test_another_librarys_env_from_a_list_of_pairs_asks_nothing(tmp_path: Path) -> None:
    assert _in(_findings(_copy(tmp_path)), 6, 17) == []


def test_an_untraced_parameter_asks_one_question(tmp_path: Path) -> None:
    found = _in(_findings(_copy(tmp_path)), 20, 28)
    assert found == [
        (23, "GM201", "flag", "review"),
        (24, "GM301", "flag", "note"),
        (26, "GM401", "flag", "note"),
        (27, "GM406", "flag", "note"),
    ]


def test_a_gym_env_passed_is_migrated(tmp_path: Path) -> None:
    assert _in(_findings(_copy(tmp_path)), 31, 34) == [(32, "GM201", "auto", "note"), (33, "GM301", "auto", "note")]


def test_a_list_handed_elsewhere_shows_no_items(tmp_path: Path) -> None:
    run = _copy(tmp_path)
    script = run / "bench" / "run.py"
    script.write_text(script.read_text().replace("for name, env in pairs:\n    rollout", "refill(pairs)\nfor name, env in pairs:\n    rollout", 1))
    found = _in(_findings(run), 6, 17)
    assert [(line, rule, tier) for line, rule, _, tier in found if tier == "review"] == [(8, "GM201", "review")]
