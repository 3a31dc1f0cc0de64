"""The command line end to end: flags, output streams, exit codes, reports."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate import __version__
from gymmigrate.cli import app

runner = CliRunner()
LEGACY = b"import gym\nfrom gym.spaces import Box\n"
MIGRATED = b"import gymnasium as gym\nfrom gymnasium.spaces import Box\n"


@pytest.fixture
def project(tmp_path: Path) -> Path:
    (tmp_path / "train.py").write_bytes(LEGACY)
    (tmp_path / "clean.py").write_bytes(b"import gymnasium as gym\n")
    (tmp_path / "unrelated.py").write_bytes(b"print('hello')\n")
    return tmp_path


def test_version() -> None:
    result = runner.invoke(app, ["--version"])
    assert result.exit_code == 0
    assert result.stdout.strip() == f"gymmigrate {__version__}"


def test_diff_prints_and_writes_nothing(project: Path) -> None:
    result = runner.invoke(app, ["rewrite", "--diff", str(project)])
    assert result.exit_code == 1
    assert f"--- {project / 'train.py'}" in result.stdout
    assert "-import gym\n-from gym.spaces import Box\n+import gymnasium as gym\n" in result.stdout
    assert "\x1b[" not in result.stdout, "no colour when stdout is not a terminal"
    assert "would rewrite 1 of 3 files" in result.stderr
    assert (project / "train.py").read_bytes() == LEGACY


def test_diff_exit_zero_when_nothing_would_change(project: Path) -> None:
    result = runner.invoke(app, ["rewrite", "--diff", str(project / "clean.py")])
    assert result.exit_code == 0
    assert result.stdout == ""


def test_rewrite_in_place_then_second_run_changes_nothing(project: Path) -> None:
    first = runner.invoke(app, ["rewrite", str(project)])
    assert first.exit_code == 0, first.output
    assert (project / "train.py").read_bytes() == MIGRATED
    assert "rewrote 1 of 3 files" in first.stderr
    assert "GM101 x1" in first.stderr and "GM103 x1" in first.stderr
    assert first.stdout == "", "summaries go to stderr"
    second = runner.invoke(app, ["rewrite", "--diff", str(project)])
    assert second.exit_code == 0
    assert second.stdout == ""


def test_review_items_are_listed_with_position(tmp_path: Path) -> None:
    script = tmp_path / "old.py"
    script.write_text("import gym\nfrom gym import GoalEnv\n")
    result = runner.invoke(app, ["rewrite", str(script)])
    assert result.exit_code == 0
    assert f"{script}:2: GM105 (not rewritten)" in result.stderr


def test_summary_lists_review_items_and_counts_notes(tmp_path: Path) -> None:
    script = tmp_path / "old.py"
    script.write_text("import gym\nfrom gym import GoalEnv\n")
    result = runner.invoke(app, ["rewrite", "--diff", str(script)])
    assert "Review (1)" in result.stderr
    assert "1 note on rewrites already applied" in result.stderr
    assert "GM101" not in result.stderr.split("Review (1)")[1], "a note is not a review item"


def test_json_report(project: Path, tmp_path: Path) -> None:
    report = tmp_path / "report.json"
    (project / "old.py").write_text("import gym\nfrom gym import GoalEnv\n")
    result = runner.invoke(app, ["rewrite", "--diff", "--report", str(report), str(project)])
    assert result.exit_code == 1
    data = json.loads(report.read_text())
    assert data["mode"] == "dry-run"
    assert data["summary"]["files_changed"] == 2
    by_path = {f["path"]: f for f in data["files"]}
    old = by_path[str(project / "old.py")]
    assert old["notes"][0] == {
        "line": 1,
        "column": 0,
        "rule": "GM101",
        "kind": "auto",
        "message": "import gym -> import gymnasium as gym",
        "line_after": 1,
        "end_line": 1,
        "end_column": 10,
        "cell": None,
        "tier": "note",
    }
    assert [(r["line"], r["rule"], r["kind"], r["tier"]) for r in old["review"]] == [(2, "GM105", "flag", "review")]
    assert data["summary"]["review_items"] == 1 and data["summary"]["notes"] >= 1


def test_bad_files_give_exit_two_and_the_rest_still_runs(project: Path) -> None:
    (project / "py2.py").write_bytes(b"import gym\nprint 'hello'\n")
    (project / "latin.py").write_bytes(b"import gym\nx = '\xff'\n")
    result = runner.invoke(app, ["rewrite", str(project), str(project / "missing.py")])
    assert result.exit_code == 2
    assert (project / "train.py").read_bytes() == MIGRATED
    assert "py2.py: syntax error at line 2" in result.stderr and "Python 2" in result.stderr
    assert "port it to Python 3 first" in result.stderr
    assert "latin.py: cannot decode the file" in result.stderr
    assert "missing.py: no such file or directory" in result.stderr
    assert "Traceback" not in result.output


def test_usage_errors_exit_two(project: Path) -> None:
    assert runner.invoke(app, ["rewrite"]).exit_code == 2
    assert runner.invoke(app, ["rewrite", "--seed", "-3", str(project)]).exit_code == 2
    assert runner.invoke(app, ["rewrite", "--no-such-flag", str(project)]).exit_code == 2


def test_unwritable_report_is_an_error(project: Path) -> None:
    result = runner.invoke(app, ["rewrite", "--diff", "--report", str(project / "no" / "dir.json"), str(project)])
    assert result.exit_code == 2
    assert "cannot write the report" in result.stderr


def test_python_dash_m_entry_point(project: Path) -> None:
    completed = subprocess.run(
        [sys.executable, "-m", "gymmigrate", "rewrite", "--diff", str(project / "train.py")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert completed.returncode == 1
    assert "+import gymnasium as gym" in completed.stdout


def test_check_lists_findings_and_writes_nothing(project: Path) -> None:
    result = runner.invoke(app, ["check", str(project)])
    assert result.exit_code == 1
    assert f"{project / 'train.py'}:1:1: GM101 [auto] import gym -> import gymnasium as gym\n" in result.stdout
    assert f"{project / 'train.py'}:2:1: GM103 [auto]" in result.stdout
    assert (project / "train.py").read_bytes() == LEGACY


def test_check_exit_zero_on_migrated_code(project: Path) -> None:
    result = runner.invoke(app, ["check", str(project / "clean.py"), str(project / "unrelated.py")])
    assert result.exit_code == 0
    assert result.stdout == ""


def test_check_exit_two_on_bad_files(project: Path) -> None:
    (project / "broken.py").write_text("import gym\ndef f(:\n")
    result = runner.invoke(app, ["check", str(project)])
    assert result.exit_code == 2
    assert "broken.py: syntax error at line 2" in result.stderr


def test_parallel_run_gives_the_same_results_in_the_same_order(tmp_path: Path) -> None:
    for index in range(40):
        (tmp_path / f"script_{index:02}.py").write_bytes(LEGACY if index % 3 else b"import gymnasium as gym\n")
    serial = runner.invoke(app, ["rewrite", "--diff", "--jobs", "1", str(tmp_path)])
    parallel = runner.invoke(app, ["rewrite", "--diff", "--jobs", "2", str(tmp_path)])
    assert serial.exit_code == parallel.exit_code == 1
    assert serial.stdout == parallel.stdout
    assert serial.stdout.count("+import gymnasium as gym") == 26
    written = runner.invoke(app, ["rewrite", "--jobs", "2", str(tmp_path)])
    assert written.exit_code == 0
    assert all(p.read_bytes().startswith(b"import gymnasium as gym") for p in tmp_path.iterdir())
