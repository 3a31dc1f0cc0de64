"""Run ``python -m gymmigrate`` as a separate process, on the code under test.

The child gets this checkout's ``src`` first on PYTHONPATH explicitly: an inherited
relative entry would stop pointing here once the child runs in another folder, and an
installed copy of gymmigrate would be tested instead.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import gymmigrate

SRC = Path(gymmigrate.__file__).resolve().parent.parent


def cli_environment(**extra: str) -> dict[str, str]:
    environment = dict(os.environ)
    environment["PYTHONPATH"] = os.pathsep.join([str(SRC), environment.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    environment.pop("GYMMIGRATE_TEST_CRASH_ON", None)
    environment.update(extra)
    return environment


def command(*arguments: str) -> list[str]:
    return [sys.executable, "-m", "gymmigrate", *arguments]


def run_cli(
    *arguments: str, cwd: Path | None = None, timeout: float = 120, **extra: str
) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        command(*arguments),
        cwd=cwd,
        env=cli_environment(**extra),
        capture_output=True,
        text=True,
        errors="surrogateescape",
        timeout=timeout,
        check=False,
    )


def start_cli(*arguments: str, **options: Any) -> subprocess.Popen[bytes]:
    return subprocess.Popen(command(*arguments), env=cli_environment(), **options)
