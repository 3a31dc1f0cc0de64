"""One file of a run, from bytes on disk (or stdin) to a ``FileResult``: never raises for
bad input.

Files and stdin share one dispatch (``migrate_bytes``): the same safety screen, the same
adapter for notebooks and pages, dependency declarations (``gymmigrate.dependencies``),
the same lint path for ``check``. ``process_file`` adds reading (``migrate_file``) and
the atomic write that never overwrites an edit saved meanwhile (``PendingWrite``, which a
run can also finish later).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, replace
from enum import Enum
from pathlib import Path

from gymmigrate.dependencies import MAX_FILE_BYTES as DEPENDENCY_MAX_BYTES
from gymmigrate.dependencies import (
    DependencyError,
    is_dependency_file,
    may_name_a_moved_package,
    migrate_dependency_file,
    migrate_page_commands,
)
from gymmigrate.engine import (
    LineMap,
    Transformed,
    lint_source,
    transform_source,
    unified_diff,
)
from gymmigrate.findings import Finding
from gymmigrate.options import RewriteOptions
from gymmigrate.safety import MAX_SOURCE_BYTES, Refused, read_source, screen
from gymmigrate.source_text import TransformError, may_hold_gym_code
from gymmigrate.sources import Adapter, adapter_for
from gymmigrate.sources.programs import document_diff, lint_document, transform_document
from gymmigrate.writes import ChangedOnDisk, write_atomically


class Status(str, Enum):
    UNCHANGED = "unchanged"
    CHANGED = "changed"
    SKIPPED = "skipped"  # filtered out before parsing
    ERROR = "error"


@dataclass(frozen=True)
class FileResult:
    path: str
    status: Status
    findings: tuple[Finding, ...] = ()
    error: str | None = None
    diff: str | None = None
    written: bool = False

    @property
    def changed(self) -> bool:
        return self.status is Status.CHANGED


def migrate_bytes(
    source: bytes, shown: str, path: Path | None, options: RewriteOptions, *, lint: bool
) -> tuple[FileResult, Transformed | None]:
    """The one dispatch: screen, then lint or migrate ``source`` by what ``path`` names (a
    dependency declaration, a notebook or page through its adapter, else Python). The
    ``Transformed`` is None where nothing was migrated (skipped, linted, an error)."""
    dependency = path is not None and is_dependency_file(path)
    adapter = adapter_for(path) if path is not None and not dependency else None
    try:
        if not screen(source, may_name_a_moved_package if dependency else may_hold_gym_code):
            return FileResult(shown, Status.SKIPPED), None
        if dependency:
            assert path is not None
            requires = options.project.requires if options.project is not None else frozenset()
            routes = None if options.project is None else options.project.plugin_routes.get(os.path.realpath(path), {})
            rewritten, found = migrate_dependency_file(
                path, source, selection=options.selection, requires=requires, plugins=routes, code_migrated=_code_beside_migrates(path, options)
            )
            transformed = Transformed(original=source, rewritten=rewritten, encoding="utf-8", findings=list(found))
        elif lint:
            if adapter:
                findings, would_change = lint_document(adapter, source, shown, options)
                findings, would_change = _lint_page_commands(adapter, path, source, findings, would_change, options)
            else:
                findings, would_change = lint_source(source, shown, options)
            return FileResult(shown, Status.CHANGED if would_change else Status.UNCHANGED, findings=tuple(findings)), None
        elif adapter:
            transformed = _with_page_commands(adapter, path, transform_document(adapter, source, shown, options), options)
        else:
            transformed = transform_source(source, shown, options)
    except (Refused, TransformError, DependencyError) as exc:
        return FileResult(shown, Status.ERROR, error=str(exc)), None
    except RecursionError:
        return FileResult(shown, Status.ERROR, error="the file is nested too deeply to analyse"), None
    status = Status.CHANGED if transformed.changed else Status.UNCHANGED
    result = FileResult(shown, status, findings=tuple(transformed.findings))
    return result, None if lint else transformed


# The rules that move a program's code to Gymnasium with its ``gym`` pin: its imports, its
# resets and its steps (what GM109's "the code must be migrated with it" asks for).
_CODE_RULES = ("GM101", "GM102", "GM103", "GM201", "GM301")


def _code_beside_migrates(path: Path, options: RewriteOptions) -> bool:
    """The run holds the Python programs of the folder a dependency file declares (its own,
    or the one above a ``requirements/`` folder), leaves none of them as it is, and applies
    the rules that move code to Gymnasium: the file's ``gym`` pin moves with that code. A
    dependency file migrated alone (no program of its folder in the run) keeps its item."""
    project = options.project
    if project is None or (options.selection is not None and not all(options.selection.allows(code) for code in _CODE_RULES)):
        return False
    folder = os.path.dirname(os.path.realpath(path))
    if os.path.basename(folder).lower() == "requirements":
        folder = os.path.dirname(folder)
    beside = [program for program in project.programs if program.startswith(folder + os.sep)]
    return bool(beside) and not any(program in project.blocked for program in beside)


def process_file(
    path: Path,
    options: RewriteOptions,
    *,
    write: bool,
    want_diff: bool,
    display_path: str | None = None,
    lint: bool = False,
) -> FileResult:
    """Read, rewrite, verify and (if asked) write one file. Never raises for bad input.

    ``lint`` (``gymmigrate check``): only decide; the findings and whether the file would
    change come from the plan, with no LibCST tree and no verification run.
    """
    migrated = migrate_file(path, options, want_diff=want_diff, display_path=display_path, lint=lint)
    if isinstance(migrated, PendingWrite):
        return migrated.write() if write else migrated.result
    return migrated


@dataclass(frozen=True)
class PendingWrite:
    """A file migrated in memory that changes: its result so far, and the write that
    finishes it (the bytes read and the bytes that replace them)."""

    path: Path
    result: FileResult  # CHANGED, not written yet
    source: bytes
    rewritten: bytes

    def write(self) -> FileResult:
        """Write the file atomically; an edit saved since it was read wins (an error here)."""
        shown, findings = self.result.path, self.result.findings
        try:
            # ``expected``: an edit saved while this file was being rewritten wins.
            write_atomically(self.path, self.rewritten, expected=self.source)
        except ChangedOnDisk as exc:
            return FileResult(shown, Status.ERROR, findings=findings, error=f"not rewritten: {exc}; left as it is now")
        except OSError as exc:
            return FileResult(shown, Status.ERROR, findings=findings, error=f"cannot write the file: {exc.strerror or exc}")
        return replace(self.result, written=True)


def migrate_file(
    path: Path,
    options: RewriteOptions,
    *,
    want_diff: bool,
    display_path: str | None = None,
    lint: bool = False,
) -> FileResult | PendingWrite:
    """Read and migrate one file in memory: its result, or where it changes, the
    ``PendingWrite`` that would write it. Never raises for bad input."""
    shown = display_path or str(path)
    adapter = adapter_for(path)  # notebooks and documentation pages; None for Python source
    if is_dependency_file(path):
        prefilter, limit = may_name_a_moved_package, DEPENDENCY_MAX_BYTES
    else:
        prefilter, limit = may_hold_gym_code, adapter.max_bytes if adapter else MAX_SOURCE_BYTES
    try:
        source = read_source(path, prefilter, limit=limit)
    except Refused as exc:
        return FileResult(shown, Status.ERROR, error=str(exc))
    except OSError as exc:
        return FileResult(shown, Status.ERROR, error=f"cannot read the file: {exc.strerror or exc}")
    if source is None:
        return FileResult(shown, Status.SKIPPED)
    result, transformed = migrate_bytes(source, shown, path, options, lint=lint)
    if transformed is None or not transformed.changed:
        return result
    diff = None
    if want_diff:
        diff = document_diff(adapter, shown, transformed) if adapter and not is_dependency_file(path) else unified_diff(shown, transformed)
    changed = FileResult(shown, Status.CHANGED, findings=result.findings, diff=diff)
    return PendingWrite(path, changed, source, transformed.rewritten)


def process_stdin(source: bytes, filename: str | None, options: RewriteOptions, *, lint: bool) -> tuple[FileResult, bytes]:
    """One file read from stdin: its result and the bytes to print (rewrite: the file as
    rewritten, or as it was when nothing changed or it could not be processed)."""
    shown = filename or "<stdin>"
    # A notebook, a page or a dependency file, by its name.
    result, transformed = migrate_bytes(source, shown, Path(filename) if filename else None, options, lint=lint)
    return result, transformed.rewritten if transformed is not None else source


# -- pip install lines in pages ----------------------------------------------------------------


def _order(finding: Finding) -> tuple[int, int, int, str]:
    return (finding.cell if finding.cell is not None else -1, finding.line, finding.column, finding.rule)


def _lint_page_commands(
    adapter: Adapter, path: Path | None, source: bytes, findings: list[Finding], would_change: bool, options: RewriteOptions
) -> tuple[list[Finding], bool]:
    """``check`` of a page: its blocks' findings plus those of its ``pip install`` lines."""
    if path is None or adapter.name not in ("markdown", "rst"):
        return findings, would_change
    try:
        result = migrate_page_commands(path, source, selection=options.selection)
    except DependencyError:
        return findings, would_change
    return sorted([*findings, *result.findings], key=_order), would_change or result.rewritten != source


def _with_page_commands(adapter: Adapter, path: Path | None, transformed: Transformed, options: RewriteOptions) -> Transformed:
    """A migrated page with its ``pip install`` lines migrated too. Those edits stay within
    their lines, so every finding's place in the output is still right."""
    if path is None or adapter.name not in ("markdown", "rst"):
        return transformed
    try:
        before = migrate_page_commands(path, transformed.original, selection=options.selection)
        after = migrate_page_commands(path, transformed.rewritten, selection=options.selection)
    except DependencyError:
        return transformed
    if not before.findings:
        return transformed
    rewritten = after.rewritten
    findings = list(before.findings)
    if rewritten != transformed.original:
        line_map = LineMap(transformed.original.decode("utf-8"), rewritten.decode("utf-8"))
        findings = [f.placed(line_map.forward) for f in findings]
    else:
        findings = [replace(f, line_after=None, message_after=None) for f in findings]
    return replace(transformed, rewritten=rewritten, findings=sorted([*transformed.findings, *findings], key=_order))
