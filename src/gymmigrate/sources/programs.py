"""Migrate the programs of a ``Document`` with the engine, and place findings in the file.

The segments of one program (a notebook's code cells, a page's blocks, the examples of a
``>>>`` session) are joined into one Python text with a boundary comment line between
them, so the rules see one module: an env made in cell 2 and stepped in cell 5 is the same
env. After migration the text is split at the same comments; if any boundary moved or
vanished the file is refused rather than guessed at.
"""

from __future__ import annotations

import difflib
import re
from bisect import bisect_right
from dataclasses import replace

from gymmigrate.engine import Transformed, lint_source, transform_source, unified_diff
from gymmigrate.findings import NAMED_LINES, Finding
from gymmigrate.options import RewriteOptions
from gymmigrate.source_text import TransformError, may_hold_gym_code
from gymmigrate.sources import Adapter, Document, Location, Segment, lines_of

_BOUNDARY = "# gymmigrate: segment boundary {}\n"
_BOUNDARY_PREFIX = "# gymmigrate: segment boundary"
_BOUNDARY_LINE = re.compile(r"# gymmigrate: segment boundary (\d+)\r?\n?")


def join(codes: list[str]) -> tuple[str, list[int]]:
    """One program text, and the 1-based program line where each segment starts."""
    parts: list[str] = []
    starts: list[int] = []
    line = 1
    for index, code in enumerate(codes):
        if index:
            parts.append(_BOUNDARY.format(index))
            line += 1
        starts.append(line)
        parts.append(code)
        line += code.count("\n")
    return "".join(parts), starts


def split(code: str, count: int, original: str | None = None) -> list[str]:
    """The segments of a migrated program, or TransformError if a boundary moved.

    A boundary comment is part of the statement below it, so it goes when a rule removes
    that statement (`from gym.wrappers import X` opening a cell). With ``original``, such a
    boundary is put back where the removed lines were, found by aligning the two texts.
    """
    lines = lines_of(code)
    numbers = [_boundary_number(line) for line in lines]
    present = [number for number in numbers if number is not None]
    if original is not None and present != list(range(1, count)) and present == sorted(set(present)):
        lines = _restore_lost_boundaries(lines, lines_of(original), set(present))
        numbers = [_boundary_number(line) for line in lines]
    pieces: list[list[str]] = [[]]
    for line, number in zip(lines, numbers):
        if number is None:
            pieces[-1].append(line)
        elif number == len(pieces):
            pieces.append([])
        else:
            raise TransformError("the rewrite moved a cell or block boundary; file left unchanged")
    if len(pieces) != count:
        raise TransformError(f"the rewrite left {len(pieces)} cells or blocks where there were {count}; file left unchanged")
    return ["".join(piece) for piece in pieces]


def _boundary_number(line: str) -> int | None:
    match = _BOUNDARY_LINE.fullmatch(line) if line.startswith(_BOUNDARY_PREFIX) else None
    return int(match[1]) if match else None


def _restore_lost_boundaries(after: list[str], before: list[str], present: set[int]) -> list[str]:
    """``after`` with each boundary of ``before`` it lost put back at the matching place."""
    lost: dict[int, list[str]] = {}  # index in ``after`` -> boundary lines to put before it
    matcher = difflib.SequenceMatcher(None, before, after, autojunk=False)
    for tag, i1, i2, j1, j2 in matcher.get_opcodes():
        if tag == "equal":
            continue
        for i in range(i1, i2):
            number = _boundary_number(before[i])
            if number is not None and number not in present:
                lost.setdefault(j1 + min(i - i1, j2 - j1), []).append(before[i])
    out: list[str] = []
    for index, line in enumerate(after):
        out.extend(lost.get(index, ()))
        out.append(line)
    out.extend(lost.get(len(after), ()))
    return out


def migrate(
    document: Document, source: bytes, path: str, options: RewriteOptions, *, lint: bool
) -> tuple[list[Finding], bool, bytes]:
    """The findings (placed in the file), whether the file changes, and its new bytes
    (``source`` itself in lint mode or when nothing changes)."""
    findings: list[Finding] = list(document.notes)
    new_codes: list[list[str]] = []
    placed: list[tuple[int, Finding, list[int], list[int]]] = []  # program, finding, starts before and after
    would_change = document.changes_outside_code
    for index, program in enumerate(document.programs):
        codes = [segment.code for segment in program]
        new_codes.append(codes)
        code, starts = join(codes)
        if _BOUNDARY_PREFIX in "".join(codes):
            raise TransformError("the code holds gymmigrate's own boundary comment; file left unchanged")
        data = code.encode("utf-8", "surrogatepass")  # a lone surrogate from JSON: the engine reports it
        if not may_hold_gym_code(data):
            continue
        try:
            if lint:
                found, changes = lint_source(data, path, options)
                would_change |= changes
                findings.extend(_placed(f, starts, program) for f in found)
                continue
            transformed = transform_source(data, path, options)
        except TransformError as exc:
            raise TransformError(_in_file_terms(str(exc), starts, _origins(program))) from None
        after_starts = starts
        if transformed.changed:
            new_codes[index] = split(transformed.rewritten.decode(transformed.encoding), len(program), code)
            _, after_starts = join(new_codes[index])
        placed.extend((index, f, starts, after_starts) for f in transformed.findings)
    if lint:
        if would_change:
            document.check_writable()
        return sorted(findings, key=_order), would_change, source
    rewritten, segment_starts_after = document.rebuild(new_codes)
    for index, finding, starts, after_starts in placed:
        moved = _placed(finding, starts, document.programs[index])
        if rewritten != source:
            # A program left as it was still moves when an earlier block of the page grew.
            line_after = finding.line_after if finding.line_after is not None else finding.line
            where = _locate(line_after, after_starts, segment_starts_after[index])
            # the lines its message names, like its own, in the rewritten file's terms
            message_after = finding.message_after if finding.message_after is not None else finding.message
            moved = replace(
                moved, line_after=where.line, message_after=_in_file_terms(message_after, after_starts, segment_starts_after[index])
            )
        else:
            moved = replace(moved, line_after=None, message_after=None)
        findings.append(moved)
    return sorted(findings, key=_order), rewritten != source, rewritten


def _in_file_terms(message: str, starts: list[int], origins: list[Location]) -> str:
    """An engine message names lines of the joined program ("line 48", "lines 10, 12");
    name the file's instead (a notebook's "cell 3 line 4"), where its segments start at
    ``origins``."""

    def where(match: re.Match[str]) -> str:
        locations = [_locate(int(number), starts, origins) for number in match[1].split(", ")]
        if all(location.cell is None for location in locations):
            word = "line" if len(locations) == 1 else "lines"
            return f"{word} {', '.join(str(location.line) for location in locations)}"
        return ", ".join(
            f"line {location.line}" if location.cell is None else f"cell {location.cell + 1} line {location.line}"
            for location in locations
        )

    return NAMED_LINES.sub(where, message)


def _order(finding: Finding) -> tuple[int, int, int, str]:
    return (finding.cell if finding.cell is not None else -1, finding.line, finding.column, finding.rule)


def _origins(program: list[Segment]) -> list[Location]:
    return [segment.start for segment in program]


def _placed(finding: Finding, starts: list[int], program: list[Segment]) -> Finding:
    origins = _origins(program)
    where = _locate(finding.line, starts, origins)
    end_line = finding.end_line
    if end_line is not None:
        end_line = _locate(end_line, starts, origins).line
    message = _in_file_terms(finding.message, starts, origins)
    return replace(finding, line=where.line, cell=where.cell, end_line=end_line, message=message)


def _locate(line: int, starts: list[int], origins: list[Location]) -> Location:
    """Program line -> file location: the segment holding it, then the line within."""
    index = max(bisect_right(starts, line) - 1, 0)
    return origins[index].plus(line - starts[index])


def transform_document(adapter: Adapter, source: bytes, path: str, options: RewriteOptions) -> Transformed:
    """``transform_source`` for a file that holds programs: the new bytes, findings placed."""
    findings, _, rewritten = migrate(adapter.read(source, path), source, path, options, lint=False)
    return Transformed(original=source, rewritten=rewritten, encoding="utf-8", findings=findings)


def lint_document(adapter: Adapter, source: bytes, path: str, options: RewriteOptions) -> tuple[list[Finding], bool]:
    """``lint_source`` for a file that holds programs."""
    findings, would_change, _ = migrate(adapter.read(source, path), source, path, options, lint=True)
    return findings, would_change


def document_diff(adapter: Adapter, path: str, transformed: Transformed) -> str:
    """A unified diff of what a person reads: a page's text, a notebook's code cells."""
    before = adapter.read(transformed.original, path).code_view()
    after = adapter.read(transformed.rewritten, path).code_view()
    label = f"{path} (code cells)" if adapter.name == "notebook" else path
    return unified_diff(label, Transformed(original=before.encode("utf-8"), rewritten=after.encode("utf-8"), encoding="utf-8"))
