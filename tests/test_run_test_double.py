"""A test double does not make a made env's attribute its own (``fixtures/project_test_double``).

``arcade.screens.LifeCounter`` holds what its factory makes with ``gym.make`` and reads
``.ale`` on it; only a test module passes a double with an ``ale`` of its own. The read
fails on the made env (forwarding is gone), so it is reported (GM604), naming the test's call.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_test_double"
runner = CliRunner()


def _findings(run: Path) -> list[dict]:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code in (0, 1), result.output
    return [{**f, "path": Path(f["path"]).relative_to(run).as_posix()} for f in json.loads(result.stdout)]


def _copy(tmp_path: Path) -> Path:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    return run


def test_a_read_past_a_test_double_is_reported(tmp_path: Path) -> None:
    findings = _findings(_copy(tmp_path))
    found = [f for f in findings if f["path"] == "arcade/screens.py" and f["rule"] == "GM604"]
    assert [(f["line"], f["kind"]) for f in found] == [(18, "flag"), (23, "flag")]
    assert "tests/test_screens.py:22" in found[0]["message"]
    assert ".unwrapped.ale" in found[0]["message"]


def test_the_factorys_concatenated_atari_id_registers_ale_py(tmp_path: Path) -> None:
    findings = _findings(_copy(tmp_path))
    assert [(f["line"], f["kind"]) for f in findings if f["rule"] == "GM106"] == [(5, "auto")]


def test_the_same_double_outside_the_tests_is_no_test_double(tmp_path: Path) -> None:
    run = _copy(tmp_path)
    (run / "tests" / "test_screens.py").rename(run / "demo.py")
    findings = _findings(run)
    assert not [f for f in findings if f["rule"] == "GM604" and "double" in f["message"]]


def test_the_receiver_question_names_the_tests_double(tmp_path: Path) -> None:
    findings = _findings(_copy(tmp_path))
    found = [f for f in findings if f["path"] == "arcade/screens.py" and f["rule"] in ("GM201", "GM301")]
    assert [(f["line"], f["rule"], f["kind"]) for f in found] == [(17, "GM201", "flag"), (22, "GM301", "flag")]
    assert "only tests pass a double" in found[0]["message"]
    assert "tests/test_screens.py:22" in found[0]["message"]
    assert "port that double's reset and step" in found[0]["message"]


def test_the_same_double_outside_the_tests_is_a_plain_mixed_question(tmp_path: Path) -> None:
    run = _copy(tmp_path)
    (run / "tests" / "test_screens.py").rename(run / "demo.py")
    found = [f for f in _findings(run) if f["rule"] == "GM201"]
    assert [f["line"] for f in found] == [17]
    assert "at some sites" in found[0]["message"] and "double" not in found[0]["message"]
