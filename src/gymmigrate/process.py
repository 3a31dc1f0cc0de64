"""One file of a run, from bytes on disk (or stdin) to a ``FileResult``: never raises for
bad input.

Files and stdin share one dispatch (``migrate_bytes``): the same safety screen, the same
adapter for notebooks and pages, the same lint path for ``check``. ``process_file`` adds
reading and the atomic write that never overwrites an edit saved meanwhile.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum
from pathlib import Path

from gymmigrate.engine import lint_source, transform_source, Transformed, unified_diff
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
    source: bytes, shown: str, adapter: Adapter | None, options: RewriteOptions, *, lint: bool
) -> tuple[FileResult, Transformed | None]:
    """The one dispatch: screen, then lint or migrate ``source`` as Python or through its
    adapter. The ``Transformed`` is None where nothing was migrated (skipped, linted, an
    error)."""
    try:
        if not screen(source, may_hold_gym_code):
            return FileResult(shown, Status.SKIPPED), None
        if lint:
            if adapter:
                findings, would_change = lint_document(adapter, source, shown, options)
            else:
                findings, would_change = lint_source(source, shown, options)
            return FileResult(shown, Status.CHANGED if would_change else Status.UNCHANGED, findings=tuple(findings)), None
        if adapter:
            transformed = transform_document(adapter, source, shown, options)
        else:
            transformed = transform_source(source, shown, options)
    except (Refused, TransformError) as exc:
        return FileResult(shown, Status.ERROR, error=str(exc)), None
    except RecursionError:
        return FileResult(shown, Status.ERROR, error="the file is nested too deeply to analyse"), None
    status = Status.CHANGED if transformed.changed else Status.UNCHANGED
    return FileResult(shown, status, findings=tuple(transformed.findings)), transformed


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
    shown = display_path or str(path)
    adapter = adapter_for(path)  # notebooks and documentation pages; None for Python source
    try:
        source = read_source(path, may_hold_gym_code, limit=adapter.max_bytes if adapter else MAX_SOURCE_BYTES)
    except Refused as exc:
        return FileResult(shown, Status.ERROR, error=str(exc))
    except OSError as exc:
        return FileResult(shown, Status.ERROR, error=f"cannot read the file: {exc.strerror or exc}")
    if source is None:
        return FileResult(shown, Status.SKIPPED)
    result, transformed = migrate_bytes(source, shown, adapter, options, lint=lint)
    if transformed is None or not transformed.changed:
        return result
    diff = None
    if want_diff:
        diff = document_diff(adapter, shown, transformed) if adapter else unified_diff(shown, transformed)
    if write:
        try:
            # ``expected``: an edit saved while this file was being rewritten wins.
            write_atomically(path, transformed.rewritten, expected=source)
        except ChangedOnDisk as exc:
            return FileResult(shown, Status.ERROR, findings=result.findings, error=f"not rewritten: {exc}; left as it is now")
        except OSError as exc:
            return FileResult(shown, Status.ERROR, findings=result.findings, error=f"cannot write the file: {exc.strerror or exc}")
    return FileResult(shown, Status.CHANGED, findings=result.findings, diff=diff, written=write)


def process_stdin(source: bytes, filename: str | None, options: RewriteOptions, *, lint: bool) -> tuple[FileResult, bytes]:
    """One file read from stdin: its result and the bytes to print (rewrite: the file as
    rewritten, or as it was when nothing changed or it could not be processed)."""
    shown = filename or "<stdin>"
    adapter = adapter_for(Path(filename)) if filename else None  # a notebook or a page, by its name
    result, transformed = migrate_bytes(source, shown, adapter, options, lint=lint)
    return result, transformed.rewritten if transformed is not None else source
