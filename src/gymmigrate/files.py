"""Find the Python files a run should look at.

Directories are searched recursively for ``*.py``. Tool and dependency folders (VCS,
virtualenvs, site-packages, build output, caches) are skipped, and inside a git work
tree the files git ignores are skipped too; git itself answers that question, so the
rules of nested ``.gitignore`` files, ``info/exclude`` and global excludes all hold.
Files named explicitly are always taken, except the temporary files of an interrupted
run (walking never yields them: they do not end in ``.py``).
"""

from __future__ import annotations

import os
import subprocess
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path

from gymmigrate.writes import is_temporary_name

SKIPPED_DIRECTORIES = frozenset(
    {
        ".git",
        ".hg",
        ".svn",
        ".bzr",
        "__pycache__",
        ".mypy_cache",
        ".pytest_cache",
        ".ruff_cache",
        ".hypothesis",
        ".ipynb_checkpoints",
        ".tox",
        ".nox",
        ".venv",
        "venv",
        ".eggs",
        "site-packages",
        "dist-packages",
        "node_modules",
        "build",
        "dist",
    }
)
PYTHON_SUFFIXES = (".py",)


@dataclass(frozen=True)
class Discovery:
    files: list[Path]
    errors: list[tuple[str, str]]  # (path as given, reason)


def discover(arguments: Iterable[str]) -> Discovery:
    files: list[Path] = []
    errors: list[tuple[str, str]] = []
    seen: set[Path] = set()

    def add(path: Path) -> None:
        key = path.resolve()
        if key not in seen:
            seen.add(key)
            files.append(path)

    for argument in arguments:
        path = Path(argument)
        if path.is_dir():
            for found in _walk(path):
                add(found)
        elif is_temporary_name(path.name):
            errors.append((argument, "a temporary file of an interrupted gymmigrate run, not a source"))
        elif path.is_file():
            add(path)
        elif path.exists():
            errors.append((argument, "not a regular file or directory"))
        else:
            errors.append((argument, "no such file or directory"))
    return Discovery(files, errors)


def _skipped(directory: Path) -> bool:
    name = directory.name
    return (
        name in SKIPPED_DIRECTORIES
        or name.endswith(".egg-info")
        or (directory / "pyvenv.cfg").is_file()  # a virtualenv under any name
    )


def _walk(root: Path) -> Iterator[Path]:
    tracked = _git_visible_files(root)
    if tracked is not None:
        for relative in sorted(tracked):
            if not relative.endswith(PYTHON_SUFFIXES):
                continue
            path = root / relative
            parents = path.relative_to(root).parents
            if any(_skipped(root / parent) for parent in parents if str(parent) != "."):
                continue
            if path.is_file():
                yield path
        return
    for directory, subdirectories, filenames in os.walk(root):
        base = Path(directory)
        subdirectories[:] = sorted(d for d in subdirectories if not _skipped(base / d))
        for filename in sorted(filenames):
            if filename.endswith(PYTHON_SUFFIXES):
                yield base / filename


def _git_visible_files(root: Path) -> list[str] | None:
    """Files under ``root`` that git tracks or would track (not ignored); None outside git."""
    try:
        completed = subprocess.run(
            ["git", "-C", str(root), "ls-files", "-z", "--cached", "--others", "--exclude-standard", "--", "."],
            capture_output=True,
            timeout=60,
            check=False,
        )
    except (OSError, subprocess.TimeoutExpired):
        return None
    if completed.returncode != 0:
        return None
    return [name for name in completed.stdout.decode("utf-8", "surrogateescape").split("\0") if name]
