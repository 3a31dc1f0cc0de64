"""One dependency file through a run, with the guarantees of a Python file: read with the
same refusals, ``check`` says whether it would change, ``--diff`` shows a unified diff,
the write is atomic and refused if the file changed meanwhile, a second run changes
nothing (``migrate_dependency_file`` checks it). Also the ``pip install`` lines of pages,
added to what the page's Python blocks give.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

from gymmigrate.dependencies import MAX_FILE_BYTES, DependencyError, migrate_dependency_file, migrate_page_commands
from gymmigrate.findings import Finding

if TYPE_CHECKING:
    from gymmigrate.engine import FileResult, Transformed
    from gymmigrate.selection import Selection
    from gymmigrate.sources import Adapter


def _may_matter(source: bytes) -> bool:
    # Every name the mapping acts on or reports holds one of these.
    lowered = source.lower()
    return any(word in lowered for word in (b"gym", b"baselines", b"sb3", b"pettingzoo", b"supersuit", b"shimmy", b"minigrid", b"atari", b"autorom", b"mujoco", b"procgen", b"roboschool", b"nes-py", b"nes_py", b"bullet"))


def process_dependency_file(
    path: Path, shown: str, *, write: bool, want_diff: bool, lint: bool, selection: Selection | None = None
) -> FileResult:
    from gymmigrate.engine import FileResult, Status, Transformed, unified_diff, write_atomically
    from gymmigrate.safety import Refused, read_source, screen
    from gymmigrate.writes import ChangedOnDisk

    try:
        source = read_source(path, _may_matter, limit=MAX_FILE_BYTES)
        if source is None or not screen(source, _may_matter):
            return FileResult(shown, Status.SKIPPED)
        rewritten, findings = migrate_dependency_file(path, source, selection=selection)
    except (Refused, DependencyError) as exc:
        return FileResult(shown, Status.ERROR, error=str(exc))
    except OSError as exc:
        return FileResult(shown, Status.ERROR, error=f"cannot read the file: {exc.strerror or exc}")
    changed = rewritten != source
    if lint or not changed:
        return FileResult(shown, Status.CHANGED if changed else Status.UNCHANGED, findings=tuple(findings))
    diff = unified_diff(shown, Transformed(original=source, rewritten=rewritten, encoding="utf-8")) if want_diff else None
    if write:
        try:
            write_atomically(path, rewritten, expected=source)
        except ChangedOnDisk as exc:
            return FileResult(shown, Status.ERROR, findings=tuple(findings), error=f"not rewritten: {exc}; left as it is now")
        except OSError as exc:
            return FileResult(shown, Status.ERROR, findings=tuple(findings), error=f"cannot write the file: {exc.strerror or exc}")
    return FileResult(shown, Status.CHANGED, findings=tuple(findings), diff=diff, written=write)


def _order(finding: Finding) -> tuple[int, int, int, str]:
    return (finding.cell if finding.cell is not None else -1, finding.line, finding.column, finding.rule)


def lint_page_commands(
    adapter: Adapter, path: Path, source: bytes, findings: list[Finding], would_change: bool, selection: Selection | None = None
) -> tuple[list[Finding], bool]:
    """``check`` of a page: its blocks' findings plus those of its ``pip install`` lines."""
    if adapter.name not in ("markdown", "rst"):
        return findings, would_change
    try:
        result = migrate_page_commands(path, source, selection=selection)
    except DependencyError:
        return findings, would_change
    return sorted([*findings, *result.findings], key=_order), would_change or result.rewritten != source


def with_page_commands(adapter: Adapter, path: Path, transformed: Transformed, selection: Selection | None = None) -> Transformed:
    """A migrated page with its ``pip install`` lines migrated too. Those edits stay within
    their lines, so every finding's place in the output is still right."""
    from gymmigrate.engine import LineMap

    if adapter.name not in ("markdown", "rst"):
        return transformed
    try:
        before = migrate_page_commands(path, transformed.original, selection=selection)
        after = migrate_page_commands(path, transformed.rewritten, selection=selection)
    except DependencyError:
        return transformed
    if not before.findings:
        return transformed
    rewritten = after.rewritten
    findings = list(before.findings)
    if rewritten != transformed.original:
        line_map = LineMap(transformed.original.decode("utf-8"), rewritten.decode("utf-8"))
        findings = [replace(f, line_after=line_map.forward(f.line)) for f in findings]
    else:
        findings = [replace(f, line_after=None) for f in findings]
    return replace(transformed, rewritten=rewritten, findings=sorted([*transformed.findings, *findings], key=_order))
