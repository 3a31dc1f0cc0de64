"""Parent side of a script smoke check: run the script in a child process and read back what it saw.

The child (``gymmigrate.smoke.bootstrap``) runs in its own session with
``PYTHONHASHSEED`` set to the seed. At the timeout it gets SIGTERM, which unwinds the
script and still writes the observations; if it has not exited a few seconds later,
its whole process group is killed. The child's stdout and stderr are kept in a log
whose tail explains a child that died without leaving observations.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from gymmigrate.smoke.evidence import RunRecord, run_from_json
from gymmigrate.smoke.targets import LoadError, NothingToCheck

GRACE_SECONDS = 3.0
_LOG_TAIL_LINES = 12


def run_script(
    script: str, args: list[str], *, seed: int, episodes: int, max_steps: int, timeout: float
) -> RunRecord:
    if not Path(script).is_file():
        raise LoadError(f"no such script: {script}")
    with tempfile.TemporaryDirectory(prefix="gymmigrate-smoke-") as scratch:
        output = Path(scratch, "observations.json")
        config = Path(scratch, "config.json")
        log = Path(scratch, "output.log")
        config.write_text(
            json.dumps({"seed": seed, "episodes": episodes, "max_steps": max_steps, "output": str(output)}),
            encoding="utf-8",
        )
        command = [sys.executable, "-m", "gymmigrate.smoke.bootstrap", str(config), script, *args]
        environment = {**os.environ, "PYTHONHASHSEED": str(seed), "PYTHONUNBUFFERED": "1"}
        started = time.perf_counter()
        with log.open("wb") as log_file:
            child = subprocess.Popen(
                command,
                stdin=subprocess.DEVNULL,
                stdout=log_file,
                stderr=subprocess.STDOUT,
                env=environment,
                start_new_session=True,
            )
            killed = _wait(child, timeout)
        seconds = time.perf_counter() - started
        if not output.is_file():
            if killed:
                return RunRecord(seed=seed, envs=(), stopped_by="timeout", seconds=seconds)
            raise LoadError(
                f"the script's process died (exit status {child.returncode}) without reporting: "
                + _tail(log)
            )
        run = run_from_json(json.loads(output.read_text(encoding="utf-8")))
    run = _with_seconds(run, seconds)
    if run.calls == 0:
        if run.stopped_by == "error":
            raise LoadError(f"the script crashed before its first step: {run.error}")
        if run.stopped_by == "timeout":
            return run
        if "AsyncVectorEnv" in run.vector_envs:
            raise NothingToCheck(
                "the script's envs ran only inside AsyncVectorEnv worker processes, out of the shim's sight: "
                "smoke-check it with vectorization_mode='sync'"
            )
        raise NothingToCheck("the script ended without resetting or stepping any gymnasium or PettingZoo env: nothing to check")
    return run


def _wait(child: subprocess.Popen, timeout: float) -> bool:
    """Wait for the child; at the timeout ask it to stop, then kill its group. True if killed."""
    try:
        try:
            child.wait(timeout=timeout)
            return False
        except subprocess.TimeoutExpired:
            child.send_signal(signal.SIGTERM)
        try:
            child.wait(timeout=GRACE_SECONDS)
            return False
        except subprocess.TimeoutExpired:
            _kill_group(child)
            child.wait()
            return True
    finally:
        _kill_group(child)  # whatever the script started (workers, servers) goes too


def _kill_group(child: subprocess.Popen) -> None:
    try:
        os.killpg(child.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def _tail(log: Path) -> str:
    lines = log.read_text(encoding="utf-8", errors="replace").strip().splitlines()
    return " | ".join(lines[-_LOG_TAIL_LINES:]) if lines else "it printed nothing"


def _with_seconds(run: RunRecord, seconds: float) -> RunRecord:
    from dataclasses import replace

    return replace(run, seconds=seconds)
