"""A worker process that dies (a segfault in native code, the OOM killer) costs one file.

Workers are made to die with the test-only hook ``GYMMIGRATE_TEST_CRASH_ON`` (see
``gymmigrate.runner._crash_for_tests``), which exits the worker like a crash would.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from gymmigrate import runner
from gymmigrate.options import RewriteOptions
from gymmigrate.process import FileResult, Status
from gymmigrate.runner import WORKER_DIED, run_files

from .cli_process import run_cli

OPTIONS = RewriteOptions()
LEGACY = b'import gym\nenv = gym.make("CartPole-v1")\nobs = env.reset()\n'
MIGRATED = b'import gymnasium as gym\nenv = gym.make("CartPole-v1")\nobs, info = env.reset()\n'


def _crash_tree(root: Path, count: int, crashing: set[int]) -> list[Path]:
    paths = []
    for index in range(count):
        name = f"crash_here_{index:02}.py" if index in crashing else f"script_{index:02}.py"
        path = root / name
        path.write_bytes(LEGACY)
        paths.append(path)
    return paths


def test_a_worker_that_dies_costs_only_its_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    paths = _crash_tree(tmp_path, 24, crashing={5})
    monkeypatch.setenv("GYMMIGRATE_TEST_CRASH_ON", "crash_here")
    results = list(run_files(paths, OPTIONS, write=True, want_diff=False, jobs=2))
    assert [result.path for result in results] == [str(path) for path in paths], "order is kept"
    crashed = results[5]
    assert crashed.status is Status.ERROR and crashed.error == WORKER_DIED
    assert paths[5].read_bytes() == LEGACY
    others = results[:5] + results[6:]
    assert all(path.read_bytes() == MIGRATED for path in paths[:5] + paths[6:])
    assert all(result.status is Status.CHANGED and result.written for result in others)


def test_every_worker_dying_still_ends_with_a_result_per_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    paths = _crash_tree(tmp_path, runner.PARALLEL_THRESHOLD, crashing=set(range(runner.PARALLEL_THRESHOLD)))
    monkeypatch.setenv("GYMMIGRATE_TEST_CRASH_ON", "crash_here")
    results = list(run_files(paths, OPTIONS, write=True, want_diff=False, jobs=2))
    assert [(result.path, result.error) for result in results] == [(str(path), WORKER_DIED) for path in paths]
    assert all(path.read_bytes() == LEGACY for path in paths)


def test_worker_death_through_the_cli_is_exit_two_without_traceback(tmp_path: Path) -> None:
    paths = _crash_tree(tmp_path, 16, crashing={3, 12})
    completed = run_cli("rewrite", "--jobs", "2", str(tmp_path), GYMMIGRATE_TEST_CRASH_ON="crash_here")
    assert completed.returncode == 2
    assert "Traceback" not in completed.stderr
    for index in (3, 12):
        assert f"error: {paths[index]}: {WORKER_DIED}" in completed.stderr
        assert paths[index].read_bytes() == LEGACY
    assert all(path.read_bytes() == MIGRATED for i, path in enumerate(paths) if i not in (3, 12))


def test_a_bug_costs_one_file_in_a_single_process_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    paths = _crash_tree(tmp_path, 3, crashing=set())
    real = runner.process_file

    def buggy(path: Path, *args: object, **kwargs: object) -> FileResult:
        if path == paths[1]:
            raise KeyError("a bug")
        return real(path, *args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(runner, "process_file", buggy)
    results = list(run_files(paths, OPTIONS, write=True, want_diff=False, jobs=1))
    assert [result.status for result in results] == [Status.CHANGED, Status.ERROR, Status.CHANGED]
    assert results[1].error == "internal error: KeyError: 'a bug'"
