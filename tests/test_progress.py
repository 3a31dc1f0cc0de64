"""The progress bar and the summary table appear on a terminal (driven through a
pseudo-terminal), and nothing extra reaches a pipe."""

from __future__ import annotations

import os
import pty
import select
import subprocess
from pathlib import Path

import pytest

from tests.cli_process import cli_environment, command

LEGACY = b"import gym\nfrom gym.spaces import Box\n"


@pytest.fixture
def many_files(tmp_path: Path) -> Path:
    for index in range(12):
        (tmp_path / f"train_{index:02}.py").write_bytes(LEGACY)
    (tmp_path / "unrelated.py").write_bytes(b"print('hello')\n")
    return tmp_path


def run_with_terminal_stderr(*arguments: str, cwd: Path) -> tuple[int, bytes, bytes]:
    """Run the CLI with stderr on a pseudo-terminal, stdout on a pipe."""
    controller, terminal = pty.openpty()
    environment = cli_environment(COLUMNS="120", TERM="xterm")
    environment.pop("NO_COLOR", None)
    process = subprocess.Popen(command(*arguments), stdout=subprocess.PIPE, stderr=terminal, env=environment, cwd=cwd)
    os.close(terminal)
    seen = b""
    while True:
        ready, _, _ = select.select([controller], [], [], 60)
        if not ready:
            process.kill()
            break
        try:
            chunk = os.read(controller, 65536)
        except OSError:  # the child closed the terminal
            break
        if not chunk:
            break
        seen += chunk
    stdout = process.stdout.read() if process.stdout else b""
    os.close(controller)
    return process.wait(timeout=60), stdout, seen


def test_progress_and_summary_table_on_a_terminal(many_files: Path) -> None:
    code, stdout, stderr = run_with_terminal_stderr("check", "-j", "1", ".", cwd=many_files)
    assert code == 1
    text = stderr.decode("utf-8", "replace")
    assert "13/13" in text, "files done / total"
    assert "0:00:0" in text, "elapsed time"
    assert "unrelated.py" in text, "the file just done (the last one, at the end)"
    for label in ("Scanned", "Skipped (no Gym code)", "Would change", "Failed", "Review items", "GM101"):
        assert label in text
    assert b"\x1b[" not in stdout and b"13/13" not in stdout, "stdout stays data"


def test_nothing_extra_when_stderr_is_not_a_terminal(many_files: Path) -> None:
    completed = subprocess.run(command("check", "-j", "1", str(many_files)), capture_output=True, env=cli_environment())
    assert completed.returncode == 1
    assert b"13/13" not in completed.stderr and b"\x1b[" not in completed.stderr
    assert b"Scanned" not in completed.stderr
    assert b"would rewrite 12 of 13 files" in completed.stderr


def test_diffs_stay_on_stdout_while_the_bar_runs(many_files: Path) -> None:
    code, stdout, stderr = run_with_terminal_stderr("rewrite", "--diff", "-j", "1", ".", cwd=many_files)
    assert code == 1
    assert stdout.count(b"+import gymnasium as gym\n") == 12
    assert b"+import gymnasium" not in stderr
