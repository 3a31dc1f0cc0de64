"""Find the Python files a run should look at.

Directories are searched recursively for ``*.py``, notebooks (``*.ipynb``) and dependency
declarations (``requirements*.txt``, ``pyproject.toml``, ``setup.cfg``, ``environment.yml``,
Dockerfiles: ``gymmigrate.dependencies.is_dependency_file``), and with ``docs`` for
documentation pages (``*.md``, ``*.rst``) too. Tool and dependency folders (VCS,
virtualenvs, site-packages, build output, caches) are skipped, and inside a git work
tree the files git ignores are skipped too; git itself answers that question, so the
rules of nested ``.gitignore`` files, ``info/exclude`` and global excludes all hold.
Files named explicitly are always taken, except the temporary files of an interrupted
run (walking never yields them: they do not end in ``.py``).

Symbolic links met while walking are not followed, whether to files or folders: a
link can point outside the tree, or back into it (a loop). A link named explicitly is
taken, and written through (its target changes, it stays a link). A file reached twice
(named and inside a named folder, or named twice) is processed once. Folders that
cannot be read are reported, not silently left out.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path

from gymmigrate.dependencies import is_dependency_file
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
NOTEBOOK_SUFFIXES = (".ipynb",)
DOCS_SUFFIXES = (".md", ".markdown", ".rst")


def walked_suffixes(docs: bool = False) -> tuple[str, ...]:
    """What walking a folder takes: Python source and notebooks, and pages with ``docs``."""
    return PYTHON_SUFFIXES + NOTEBOOK_SUFFIXES + (DOCS_SUFFIXES if docs else ())


@dataclass(frozen=True)
class Discovery:
    files: list[Path]
    errors: list[tuple[str, str]]  # (path, reason): unusable arguments, folders that cannot be read


def discover(arguments: Iterable[str], *, docs: bool = False) -> Discovery:
    suffixes = walked_suffixes(docs)
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
            for found in _walk(path, errors, suffixes):
                add(found)
        elif is_temporary_name(path.name):
            errors.append((argument, "a temporary file of an interrupted gymmigrate run, not a source"))
        elif path.is_file():
            add(path)
        elif path.is_symlink():
            errors.append((argument, "a broken symbolic link (its target is missing, or the links form a loop)"))
        elif path.exists():
            errors.append((argument, "not a regular file or directory"))
        else:
            errors.append((argument, "no such file or directory"))
    return Discovery(files, errors)


def _skipped(directory: Path) -> bool:
    name = directory.name
    return name in SKIPPED_DIRECTORIES or name.endswith(".egg-info") or _is_virtualenv(directory)


def _is_virtualenv(directory: Path) -> bool:
    """A virtualenv under any name. A folder that cannot be read is not skipped here:
    walking it reports it."""
    try:
        return (directory / "pyvenv.cfg").is_file()
    except OSError:  # pathlib lets EACCES through
        return False


def _walk(root: Path, errors: list[tuple[str, str]], suffixes: tuple[str, ...] = PYTHON_SUFFIXES) -> Iterator[Path]:
    """The files under ``root`` whose names end with ``suffixes``; folders that cannot be read go to ``errors``."""
    listing = _git_visible_files(root)
    if listing is not None:
        tracked, unreadable = listing
        errors.extend(unreadable)
        yield from _git_files(root, tracked, suffixes)
        return

    def unreadable_folder(error: OSError) -> None:
        errors.append((str(error.filename), f"cannot read the folder: {error.strerror or error}"))

    for directory, subdirectories, filenames in os.walk(root, onerror=unreadable_folder):
        base = Path(directory)
        # os.walk does not descend into linked folders; dropping them here also spares a
        # stat through each link in _skipped.
        subdirectories[:] = sorted(d for d in subdirectories if not (base / d).is_symlink() and not _skipped(base / d))
        for filename in sorted(filenames):
            path = base / filename
            if (filename.endswith(suffixes) or is_dependency_file(path)) and not path.is_symlink():
                yield path


def _git_files(root: Path, tracked: list[str], suffixes: tuple[str, ...]) -> Iterator[Path]:
    for relative in sorted(tracked):
        if not relative.endswith(suffixes) and not is_dependency_file(relative):
            continue
        path = root / relative
        parents = path.relative_to(root).parents
        if any(_skipped(root / parent) for parent in parents if str(parent) != "."):
            continue
        # git lists a committed link as a file of its own (it never lists what is under
        # a linked folder); like os.walk above, a link is not followed.
        if path.is_file() and not path.is_symlink():
            yield path


# How git says it could not list a folder (it still exits 0).
_GIT_UNREADABLE = re.compile(r"^warning: could not open directory '(?P<folder>.+?)/?': (?P<reason>.+)$", re.M)


def _git_visible_files(root: Path) -> tuple[list[str], list[tuple[str, str]]] | None:
    """Files under ``root`` that git tracks or would track (not ignored), and the folders
    git could not read; None outside git."""
    import subprocess  # only a folder's walk asks git: ``check FILE`` never loads it

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
    names = [name for name in completed.stdout.decode("utf-8", "surrogateescape").split("\0") if name]
    return names, _git_unreadable_folders(root, completed.stderr.decode("utf-8", "surrogateescape"))


def _git_unreadable_folders(root: Path, warnings: str) -> list[tuple[str, str]]:
    found = list(_GIT_UNREADABLE.finditer(warnings))
    if not found:
        return []
    import subprocess

    # git names these folders from the top of the work tree, not from ``root``.
    top = subprocess.run(
        ["git", "-C", str(root), "rev-parse", "--show-toplevel"], capture_output=True, text=True, check=False
    ).stdout.strip()
    base = Path(top) if top else root
    return [(str(base / match["folder"]), f"cannot read the folder: {match['reason']}") for match in found]
