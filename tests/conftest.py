"""Session set-up shared by every test module."""

from __future__ import annotations

import compileall
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "src" / "gymmigrate"


def pytest_sessionstart(session: object) -> None:
    # Many tests run gymmigrate in a subprocess, as a user does. Where PYTHONDONTWRITEBYTECODE
    # is set (CI machines often set it), no process writes bytecode, so each of those runs
    # compiled the whole package again (about 0.35 s a run); compiled once here, they read it,
    # as a user's installed package is read.
    compileall.compile_dir(PACKAGE, quiet=1)
