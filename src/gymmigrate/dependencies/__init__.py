"""Dependency declarations: the files that say what to install, migrated with the code.

``gym`` becomes ``gymnasium`` (extras mapped), libraries that moved to Gymnasium with it
(Stable-Baselines3, sb3-contrib, PettingZoo, SuperSuit, Shimmy, MiniGrid) get a release
that supports Gymnasium 1.x, ROM helpers become ``ale-py``, and Gym-only packages are
reported with the Shimmy route (``mapping.py``; docs/dependencies.md has the table).

Pure functions, text in and text out: ``migrate_dependency_file(path, source)`` picks the
handler from the file name (``handler_for``), and every byte outside a changed requirement
string is kept (comments, markers, ``--hash`` options, line endings). Rule codes: GM109
(rewritten), GM110 (reported, left), SB110 (pins of libraries that moved with Gym);
``--select``/``--ignore`` apply to them (``selection``).
"""

from __future__ import annotations

import fnmatch
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path, PurePath
from typing import TYPE_CHECKING

from gymmigrate.dependencies.core import apply_edits
from gymmigrate.dependencies.lines import migrate_environment, migrate_requirements, migrate_setup_cfg
from gymmigrate.dependencies.pyproject import PyprojectError, migrate_pyproject
from gymmigrate.dependencies.setup_py import SetupPyError, migrate_setup_py
from gymmigrate.dependencies.shell import migrate_dockerfile, migrate_page
from gymmigrate.engine import LineMap
from gymmigrate.findings import Finding
from gymmigrate.rules.dependency_files import DEPENDENCY_RULES

if TYPE_CHECKING:
    from gymmigrate.selection import Selection

CODES = tuple(rule.code for rule in DEPENDENCY_RULES)

__all__ = ["DependencyError", "DependencyResult", "handler_for", "is_dependency_file", "may_name_a_moved_package", "migrate_dependency_file", "migrate_page_commands"]

# Dependency files are small; a larger one is generated (a lock file) or data.
MAX_FILE_BYTES = 1024 * 1024


class DependencyError(ValueError):
    """The file could not be read as what its name says; the message says why."""


@dataclass(frozen=True)
class DependencyResult:
    rewritten: bytes
    findings: list[Finding]

    def __iter__(self):  # ``rewritten, findings = migrate_dependency_file(...)``
        return iter((self.rewritten, self.findings))


def _requirements(text: str):
    return migrate_requirements(text)


def _environment(text: str):
    return migrate_environment(text)


def _setup_cfg(text: str):
    return migrate_setup_cfg(text)


def _setup_py(text: str):
    try:
        return migrate_setup_py(text)
    except SetupPyError as exc:
        raise DependencyError(str(exc)) from None


def _pyproject(text: str):
    try:
        return migrate_pyproject(text)
    except PyprojectError as exc:
        raise DependencyError(str(exc)) from None


def _dockerfile(text: str):
    return migrate_dockerfile(text)


# File name patterns (matched case-insensitively against the name) -> handler. The first
# match wins. ``requirements/*.txt`` is matched on the folder name below.
HANDLERS: tuple[tuple[str, Callable], ...] = (
    ("requirements*.txt", _requirements),
    ("requirements*.in", _requirements),
    ("constraints*.txt", _requirements),
    ("setup.py", _setup_py),
    ("setup.cfg", _setup_cfg),
    ("pyproject.toml", _pyproject),
    ("environment*.yml", _environment),
    ("environment*.yaml", _environment),
    ("dockerfile", _dockerfile),
    ("dockerfile.*", _dockerfile),
    ("*.dockerfile", _dockerfile),
    ("containerfile", _dockerfile),
)


def handler_for(path: PurePath | str) -> Callable | None:
    path = PurePath(path)
    name = path.name.lower()
    for pattern, handler in HANDLERS:
        if fnmatch.fnmatchcase(name, pattern):
            return handler
    if path.parent.name.lower() == "requirements" and name.endswith((".txt", ".in")):
        return _requirements
    return None


def may_name_a_moved_package(source: bytes) -> bool:
    """The cheap prefilter: every name the mapping acts on or reports holds one of these."""
    lowered = source.lower()
    return any(word in lowered for word in _MOVED_WORDS)


_MOVED_WORDS = (b"gym", b"baselines", b"sb3", b"pettingzoo", b"supersuit", b"shimmy", b"minigrid", b"atari", b"autorom", b"mujoco", b"procgen", b"roboschool", b"nes-py", b"nes_py", b"bullet")


def is_dependency_file(path: PurePath | str) -> bool:
    return handler_for(path) is not None


def _decode(source: bytes) -> tuple[str, bool]:
    bom = source.startswith(b"\xef\xbb\xbf")
    try:
        return source[3 if bom else 0 :].decode("utf-8"), bom
    except UnicodeDecodeError as exc:
        raise DependencyError(f"cannot decode the file as UTF-8 ({exc.reason} at byte {exc.start}); left unchanged") from None


def _run(handler: Callable, source: bytes, selection: Selection | None = None) -> DependencyResult:
    def allowed(code: str) -> bool:
        return selection is None or selection.allows(code)

    text, bom = _decode(source)
    outcome = handler(text)
    # --select/--ignore: a rule left out neither reports nor fixes.
    edits = [edit for edit in outcome.edits if allowed(edit.code)]
    findings = sorted(
        [finding for finding in outcome.findings if allowed(finding.rule)]
        + [companion for edit in edits for companion in edit.companions if allowed(companion.rule)]
    )
    if not edits:
        return DependencyResult(source, findings)
    new_text = apply_edits(text, edits)
    rewritten = (b"\xef\xbb\xbf" if bom else b"") + new_text.encode("utf-8")
    if rewritten == source:
        return DependencyResult(source, findings)
    line_map = LineMap(text, new_text)
    return DependencyResult(rewritten, [replace(f, line_after=line_map.forward(f.line)) for f in findings])


def migrate_dependency_file(path: Path | str, source: bytes, *, selection: Selection | None = None) -> DependencyResult:
    """The migrated bytes of a dependency file and what was changed or must be reviewed.

    Raises DependencyError when the file cannot be read as its kind, or when the rewrite
    would not be stable (a second run would change it again).
    """
    handler = handler_for(path)
    if handler is None:
        raise DependencyError("not a dependency file")
    result = _run(handler, source, selection)
    if result.rewritten != source and _run(handler, result.rewritten, selection).rewritten != result.rewritten:
        raise DependencyError("the dependency rewrite is not stable (a second run would change it again); file left unchanged")
    return result


def migrate_page_commands(path: Path | str, source: bytes, *, selection: Selection | None = None) -> DependencyResult:
    """``pip install`` lines in the shell/console code blocks of a Markdown or RST page."""
    markdown = PurePath(path).suffix.lower() in (".md", ".markdown")
    return _run(lambda text: migrate_page(text, markdown), source, selection)
