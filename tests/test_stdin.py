"""check - / rewrite -: one file from stdin, result on stdout (editor integration)."""

from __future__ import annotations

import json
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

runner = CliRunner()
LEGACY = b"import gym\nfrom gym.spaces import Box\n"
MIGRATED = b"import gymnasium as gym\nfrom gymnasium.spaces import Box\n"


def test_rewrite_stdin_writes_the_result_to_stdout() -> None:
    result = runner.invoke(app, ["rewrite", "-"], input=LEGACY)
    assert result.exit_code == 0
    assert result.stdout_bytes == MIGRATED


def test_rewrite_stdin_unchanged_and_unrelated_files_come_back_as_they_were() -> None:
    for source in (MIGRATED, b"print('hello')\n"):
        result = runner.invoke(app, ["rewrite", "-"], input=source)
        assert result.exit_code == 0 and result.stdout_bytes == source


def test_rewrite_stdin_diff() -> None:
    result = runner.invoke(app, ["rewrite", "--diff", "-", "--stdin-filename", "train.py"], input=LEGACY)
    assert result.exit_code == 1
    assert "--- a/train.py" in result.stdout and "+import gymnasium as gym" in result.stdout


def test_check_stdin_uses_the_filename_in_findings() -> None:
    result = runner.invoke(app, ["check", "-", "--stdin-filename", "src/train.py"], input=LEGACY)
    assert result.exit_code == 1
    assert result.stdout.startswith("src/train.py:1:1: GM101 [auto]")
    as_json = runner.invoke(app, ["check", "--output-format", "json", "-"], input=LEGACY)
    assert {item["path"] for item in json.loads(as_json.stdout)} == {"<stdin>"}


def test_stdin_filename_finds_the_configuration(tmp_path: Path) -> None:
    (tmp_path / "pyproject.toml").write_text('[tool.gymmigrate]\nignore = ["GM103"]\n')
    result = runner.invoke(app, ["check", "-", "--stdin-filename", str(tmp_path / "new.py")], input=LEGACY)
    assert [line.split()[1] for line in result.stdout.splitlines()] == ["GM101"]


def test_stdin_syntax_error_is_exit_2_and_echoes_the_input() -> None:
    broken = b"import gym\ndef (:\n"
    result = runner.invoke(app, ["rewrite", "-"], input=broken)
    assert result.exit_code == 2
    assert result.stdout_bytes == broken
    assert "syntax error" in result.stderr


def test_stdin_cannot_be_mixed_with_paths(tmp_path: Path) -> None:
    result = runner.invoke(app, ["check", "-", str(tmp_path)])
    assert result.exit_code == 2 and "cannot be combined" in result.stderr


def test_stdin_report_and_smoke(tmp_path: Path) -> None:
    report = tmp_path / "report.json"
    result = runner.invoke(app, ["check", "-", "--report", str(report)], input=LEGACY)
    assert result.exit_code == 1
    assert [f["rule"] for f in json.loads(report.read_text())["findings"]] == ["GM101", "GM103"]
    smoke = runner.invoke(app, ["rewrite", "--smoke", "-"], input=LEGACY)
    assert smoke.exit_code == 2 and "--smoke" in smoke.stderr


def test_stdin_notebook_by_its_filename() -> None:
    notebook = Path(__file__).resolve().parent.parent / "fixtures" / "notebooks" / "multi_cell_loop.ipynb"
    source = notebook.read_bytes()
    result = runner.invoke(app, ["rewrite", "-", "--stdin-filename", "nb.ipynb"], input=source)
    assert result.exit_code == 0, result.stderr
    assert result.stdout_bytes == notebook.with_name("multi_cell_loop.expected.ipynb").read_bytes()
    findings = runner.invoke(app, ["check", "-", "--stdin-filename", "nb.ipynb"], input=source)
    assert findings.stdout.startswith("nb.ipynb:cell ")
