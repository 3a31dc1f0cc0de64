"""Dependency declarations: the files that say what to install, migrated with the code.

``gym`` becomes ``gymnasium`` (extras mapped), libraries that moved to Gymnasium with it
(Stable-Baselines3, sb3-contrib, PettingZoo, SuperSuit, Shimmy, MiniGrid) get a release
that supports Gymnasium 1.x, ROM helpers become ``ale-py``, and Gym-only packages are
reported with the Shimmy route (``mapping.py``; docs/dependencies.md has the table).

Pure functions, text in and text out: ``migrate_dependency_file(path, source)`` picks the
handler from the file name (``kind_of``; the formats live in ``migrate.py``), and every byte outside a changed requirement
string is kept (comments, markers, ``--hash`` options, line endings). Rule codes: GM109
(rewritten), GM110 (reported, left), SB110 (pins of libraries that moved with Gym);
``--select``/``--ignore`` apply to them (``selection``).
"""

from __future__ import annotations

import fnmatch
import importlib
from pathlib import Path, PurePath
from types import ModuleType
from typing import TYPE_CHECKING

from gymmigrate.rules.dependency_files import DEPENDENCY_RULES

if TYPE_CHECKING:
    from collections.abc import Mapping

    from gymmigrate.dependencies.migrate import DependencyResult
    from gymmigrate.dependencies.plugins import Route
    from gymmigrate.selection import Selection

CODES = tuple(rule.code for rule in DEPENDENCY_RULES)

__all__ = ["DependencyError", "is_dependency_file", "kind_of", "may_name_a_moved_package", "migrate_dependency_file", "migrate_page_commands"]

# Dependency files are small; a larger one is generated (a lock file) or data.
MAX_FILE_BYTES = 1024 * 1024


class DependencyError(ValueError):
    """The file could not be read as what its name says; the message says why."""


# File name patterns (matched case-insensitively against the name) -> the kind of file.
# The first match wins. ``requirements/*.txt`` is matched on the folder name below.
PATTERNS: tuple[tuple[str, str], ...] = (
    ("requirements*.txt", "requirements"),
    ("requirements*.in", "requirements"),
    ("constraints*.txt", "requirements"),
    ("setup.py", "setup.py"),
    ("setup.cfg", "setup.cfg"),
    ("pyproject.toml", "pyproject.toml"),
    ("environment*.yml", "environment.yml"),
    ("environment*.yaml", "environment.yml"),
    ("dockerfile", "dockerfile"),
    ("dockerfile.*", "dockerfile"),
    ("*.dockerfile", "dockerfile"),
    ("containerfile", "dockerfile"),
)


def kind_of(path: PurePath | str) -> str | None:
    """The kind of dependency file ``path`` names, or None."""
    path = PurePath(path)
    name = path.name.lower()
    for pattern, kind in PATTERNS:
        if fnmatch.fnmatchcase(name, pattern):
            return kind
    if path.parent.name.lower() == "requirements" and name.endswith((".txt", ".in")):
        return "requirements"
    return None


def is_dependency_file(path: PurePath | str) -> bool:
    return kind_of(path) is not None


def may_name_a_moved_package(source: bytes) -> bool:
    """The cheap prefilter: every name the mapping acts on or reports holds one of these."""
    lowered = source.lower()
    return any(word in lowered for word in _MOVED_WORDS)


_MOVED_WORDS = (b"gym", b"baselines", b"sb3", b"pettingzoo", b"supersuit", b"shimmy", b"minigrid", b"atari", b"autorom", b"mujoco", b"procgen", b"roboschool", b"nes-py", b"nes_py", b"bullet")


def migrate_dependency_file(
    path: Path | str,
    source: bytes,
    *,
    selection: Selection | None = None,
    requires: frozenset[str] = frozenset(),
    plugins: Mapping[str, Route] | None = None,
    code_migrated: bool = False,
) -> DependencyResult:
    """The migrated bytes of a dependency file and what was changed or must be reviewed.

    Raises DependencyError when the file cannot be read as its kind, or when the rewrite
    would not be stable (a second run would change it again).
    """
    return _formats().migrate_dependency_file(
        path, source, selection=selection, requires=requires, plugins=plugins, code_migrated=code_migrated
    )


def migrate_page_commands(path: Path | str, source: bytes, *, selection: Selection | None = None) -> DependencyResult:
    """``pip install`` lines in the shell/console code blocks of a Markdown or RST page."""
    return _formats().migrate_page_commands(path, source, selection=selection)


def _formats() -> ModuleType:
    # The formats and their parsers load with the first dependency file, as the sources
    # load a notebook's adapter: a run over Python files never pays for them.
    return importlib.import_module("gymmigrate.dependencies.migrate")
