"""A run killed at any instant leaves every file whole, and the next run finishes the job.

The test starts a real run and SIGKILLs it, because that is the only honest way to show
that a file is either its old bytes or its complete rewrite at every instant.
"""

from __future__ import annotations

import fcntl
import os
import signal
import subprocess
import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app
from gymmigrate.writes import is_temporary_name, remove_abandoned_temporaries

from .cli_process import run_cli, start_cli

LEGACY = b'import gym\nenv = gym.make("CartPole-v1")\nobs = env.reset()\n'
MIGRATED = b'import gymnasium as gym\nenv = gym.make("CartPole-v1")\nobs, info = env.reset()\n'


def _legacy_tree(root: Path, folders: int, per_folder: int) -> list[Path]:
    paths = []
    for folder in range(folders):
        for index in range(per_folder):
            path = root / f"pkg_{folder}" / f"script_{index:03}.py"
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(LEGACY)
            paths.append(path)
    return paths


def _temporaries(root: Path) -> list[Path]:
    return [path for path in root.rglob("*") if is_temporary_name(path.name)]


def _live_processes_in_session(session: int) -> list[int]:
    """Processes (not zombies) whose session is ``session``, from /proc."""
    live = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue  # it exited meanwhile
        state, sid = fields[0], int(fields[3])
        if sid == session and state != "Z":
            live.append(int(entry.name))
    return live


def _wait_until(condition, timeout: float, interval: float = 0.01) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(interval)
    return condition()


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads process states from /proc")
def test_a_killed_run_leaves_whole_files_and_the_next_run_finishes(tmp_path: Path) -> None:
    tree = tmp_path / "project"
    paths = _legacy_tree(tree, folders=3, per_folder=20)

    def rewritten() -> int:
        return sum(path.read_bytes() == MIGRATED for path in paths)

    quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
    run = start_cli("rewrite", "--jobs", "2", str(tree), start_new_session=True, **quiet)
    try:
        assert _wait_until(lambda: rewritten() >= 5, timeout=60), "the run never got going"
        os.kill(run.pid, signal.SIGKILL)  # only the parent: its workers become orphans
        run.wait()
        # Orphaned workers notice and exit instead of waiting for work forever.
        assert _wait_until(lambda: not _live_processes_in_session(run.pid), timeout=10), "workers outlived the run"
    finally:
        try:
            os.killpg(run.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass

    contents = [path.read_bytes() for path in paths]
    assert all(content in (LEGACY, MIGRATED) for content in contents), "a file was left half-written"
    assert 0 < contents.count(MIGRATED) < len(paths), "the kill should land part way through the run"

    # What a kill between creating the temporary file and the rename leaves (the kill
    # above may or may not have hit that instant), what a live run's file looks like,
    # and names that only look like ours.
    abandoned = paths[0].parent / f".{paths[0].name}.k1ll3d_x.gymmigrate"
    abandoned.write_bytes(MIGRATED[:10])
    in_use = paths[1].parent / f".{paths[1].name}.wr1t1ng_.gymmigrate"
    in_use.write_bytes(MIGRATED[:10])
    not_ours = [tree / ".notes.gymmigrate", tree / ".train.py.UPPER123.gymmigrate", tree / "keep.gymmigrate"]
    for path in not_ours:
        path.write_bytes(b"user data")
    leftovers_before = set(_temporaries(tree)) - {abandoned, in_use}

    with in_use.open("rb") as handle:
        fcntl.flock(handle, fcntl.LOCK_EX)  # as the run writing it would hold it
        second = run_cli("rewrite", str(tree))
    assert second.returncode == 0, second.stderr
    assert "Traceback" not in second.stderr
    assert all(path.read_bytes() == MIGRATED for path in paths)
    assert not abandoned.exists() and not any(path.exists() for path in leftovers_before)
    assert "temporary file(s) left by an interrupted gymmigrate run" in second.stderr
    assert in_use.exists(), "a temporary file another run is writing must be left alone"
    assert all(path.read_bytes() == b"user data" for path in not_ours)


def test_leftover_temporary_files_are_never_sources(tmp_path: Path) -> None:
    (tmp_path / "train.py").write_bytes(LEGACY)
    leftover = tmp_path / ".train.py.a1b2c3d4.gymmigrate"
    leftover.write_bytes(LEGACY)
    result = CliRunner().invoke(app, ["check", str(tmp_path)])
    assert result.exit_code == 1
    assert str(leftover) not in result.stdout
    assert leftover.read_bytes() == LEGACY, "check writes nothing, so it removes nothing"
    named = CliRunner().invoke(app, ["check", str(leftover)])
    assert named.exit_code == 2
    assert "a temporary file of an interrupted gymmigrate run, not a source" in named.stderr


def test_only_abandoned_temporary_files_of_our_own_pattern_are_removed(tmp_path: Path) -> None:
    ours = tmp_path / ".env.py.abc_1234.gymmigrate"
    ours.write_bytes(b"partial")
    folder_named_like_ours = tmp_path / ".x.py.abcdefgh.gymmigrate"
    folder_named_like_ours.mkdir()
    link_named_like_ours = tmp_path / ".y.py.abcdefgh.gymmigrate"
    link_named_like_ours.symlink_to(tmp_path / "elsewhere")
    assert remove_abandoned_temporaries([tmp_path]) == [ours]
    assert folder_named_like_ours.is_dir() and link_named_like_ours.is_symlink()


def test_ctrl_c_stops_a_run_without_tracebacks_or_half_written_files(tmp_path: Path) -> None:
    paths = _legacy_tree(tmp_path, folders=2, per_folder=20)
    # Ctrl-C reaches the whole foreground process group: the run and its workers. (This
    # test's own runner may ignore SIGINT, and children inherit that: restore it.)
    run = start_cli(
        "rewrite",
        "--jobs",
        "2",
        str(tmp_path),
        start_new_session=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    try:
        assert _wait_until(lambda: sum(p.read_bytes() == MIGRATED for p in paths) >= 3, timeout=60)
        os.killpg(run.pid, signal.SIGINT)
        _, stderr = run.communicate(timeout=60)
    finally:
        try:
            os.killpg(run.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    assert run.returncode == 130, "interrupted: neither success (0) nor pending changes (1)"
    assert b"Traceback" not in stderr, stderr.decode(errors="replace")
    assert all(path.read_bytes() in (LEGACY, MIGRATED) for path in paths)
    assert _temporaries(tmp_path) == [], "the run waits for its workers to finish their file"
