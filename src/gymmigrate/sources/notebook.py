"""Jupyter notebooks (``.ipynb``): the code cells, in order, are one program.

Everything else in the file is kept: markdown cells, outputs, execution counts,
metadata, key order and the JSON layout. Only the ``source`` of a cell whose code changed
is replaced, in the form it had (a list of lines or one string), and it is replaced in
the JSON text itself: the file is never serialized again, so every byte outside the
changed ``source`` values stays as it was, whatever wrote it (Jupyter's indent 1,
Colab's indent 2, a line indented by hand, duplicate keys from a merge, CRLF). Inside a
changed ``source`` list, the lines that did not change keep their bytes too (their
indentation and escapes); a new line takes the indentation of the line it replaces.
Where keys repeat, the last one counts, as for ``json.loads`` and Jupyter.

Findings carry ``cell``, the 0-based index in the notebook's ``cells`` (markdown cells
count), and ``line`` within that cell.

A code cell that does not parse (an exercise placeholder such as ``<YOUR CODE>``, code
left half-written) is reported as GM001 with its cell and left byte for byte; the other
code cells are still migrated, as one program without it.
"""

from __future__ import annotations

import ast
import json
import re
from dataclasses import replace
from typing import Any

from gymmigrate.dependencies.core import apply_edits
from gymmigrate.dependencies.mapping import (
    GYM_PACKAGE,
    MIGRATE_WITH_IT,
    only_describes_gym_pin,
)
from gymmigrate.dependencies.shell import migrate_dockerfile
from gymmigrate.findings import Finding, FixKind, Tier
from gymmigrate.source_text import TransformError, may_hold_gym_code
from gymmigrate.sources import Location, Segment, lines_of
from gymmigrate.sources.json_text import (
    JSONLayoutError,
    Span,
    cell_source_spans,
    escapes_non_ascii,
    new_source_text,
)
from gymmigrate.sources.magics import Magics
from gymmigrate.sources.unparsed import UnparsedCode, classify_unparsed

# Outputs (plots, videos) make notebooks large; the code in them is what costs time.
MAX_FILE_BYTES = 64 * 1024 * 1024

UNPARSED_CELL = "GM001"  # the rule of a documentation block that does not parse


def read(source: bytes, path: str) -> Notebook:
    return Notebook(source)


class Notebook:
    def __init__(self, source: bytes) -> None:
        self.source = source
        try:
            self.text = source.decode("utf-8")
            self.data = json.loads(self.text)
        except (UnicodeDecodeError, ValueError) as exc:
            raise TransformError(f"not a readable notebook (invalid JSON: {exc}); left unchanged") from None
        cells = self.data.get("cells") if isinstance(self.data, dict) else None
        if not isinstance(cells, list):
            raise TransformError("not a notebook in nbformat 4 (no top-level `cells` list); left unchanged")
        self.cells: list[dict[str, Any]] = cells
        self.notes: list[Finding] = []
        self.magics = Magics()
        segments: list[Segment] = []
        self._hidden_ranges: dict[int, range] = {}
        if _is_python(self.data):
            for index, cell in enumerate(cells):
                if not isinstance(cell, dict) or cell.get("cell_type") != "code":
                    continue
                first_hidden = len(self.magics.hidden)
                code = self.magics.hide(_with_final_newline(_cell_text(cell)))
                self._hidden_ranges[index] = range(first_hidden, len(self.magics.hidden))
                segments.append(Segment(code, Location(1, index)))
        # Gym in the outputs or the markdown only: nothing to migrate, whatever the cells hold.
        if not may_hold_gym_code("".join(segment.code for segment in segments).encode("utf-8")):
            segments = []
        # Cells whose install lines (``!pip install gym==0.24``) get new requirements: rebuilt
        # even when their Python is left as it is.
        self.install_cells: set[int] = set()
        if segments:
            self._plan_install_lines(segments)
        # A cell that does not parse (an exercise's `<YOUR CODE>`, half-written code) is
        # reported and left byte for byte; the other cells are still one program.
        parsed = []
        for segment in segments:
            problem = _parse_problem(segment.code)
            if problem is None:
                parsed.append(segment)
                continue
            line, detail = problem
            cell_index = segment.start.cell
            finding = unparsed_cell_finding(segment.code, line, detail, cell_index)
            if cell_index in self.install_cells:
                # its install lines stay as they are with the rest of it: no note may say
                # they changed, and the old requirement left in it is to be moved by hand
                self.install_cells.discard(cell_index)
                self.notes = [note for note in self.notes if note.cell != cell_index]
                finding = replace(
                    finding,
                    message=f"{finding.message}; its install line, which names gym's packages, is left as well: update it by hand",
                    tier=None,
                )
            self.notes.append(finding)
        self.changes_outside_code = bool(self.install_cells)
        self.programs = [parsed] if parsed else []

    def _plan_install_lines(self, segments: list[Segment]) -> None:
        """``!pip install gym==0.24`` (``%pip install ...``): an IPython line, never parsed as
        Python, whose requirements move like a requirements file's (GM109, and the companions'
        rules): the hidden line is given back with them when the cell is rebuilt."""
        for segment in segments:
            index = segment.start.cell
            assert index is not None
            for number, line in enumerate(lines_of(segment.code), start=1):
                hidden = self.magics.hidden_number(line)
                if hidden is None or not _INSTALL_LINE.match(self.magics.hidden[hidden]):
                    continue
                original = self.magics.hidden[hidden]
                ending = original[len(original.rstrip("\r\n")) :] or "\n"
                outcome = migrate_dockerfile(original.rstrip("\r\n") + "\n")
                if not outcome.edits:
                    continue
                new_line = apply_edits(original.rstrip("\r\n") + "\n", outcome.edits).rstrip("\n")
                self.magics.replace(hidden, new_line + (ending if original.endswith(("\n", "\r")) else ""))
                self.install_cells.add(index)
                for note in outcome.findings:
                    note = replace(note, line=number, column=note.column, end_line=None, end_column=None, cell=index)
                    if note.rule == GYM_PACKAGE and note.kind is FixKind.ASSIST and only_describes_gym_pin(note.message):
                        # the notebook's own code is migrated in the same run: nothing to decide
                        note = replace(note, tier=Tier.NOTE, message=note.message.replace(MIGRATE_WITH_IT, NOTEBOOK_MIGRATED))
                    self.notes.append(note)

    def rebuild(self, codes: list[list[str]]) -> tuple[bytes, list[list[Location]]]:
        changed: dict[int, str] = {}
        for program, new_codes in zip(self.programs, codes):
            for segment, new_code in zip(program, new_codes):
                if new_code == segment.code:
                    continue
                index = segment.start.cell
                assert index is not None
                text = self.magics.restore(new_code)
                changed[index] = text
        for program in self.programs:
            for segment in program:
                index = segment.start.cell
                if index in self.install_cells and index not in changed:
                    changed[index] = self.magics.restore(segment.code)  # only its install lines change
        for index, text in list(changed.items()):
            if not _cell_text(self.cells[index]).endswith("\n"):
                changed[index] = text.removesuffix("\n")  # nbformat stores the last line without one
        self.magics.check_all_restored({n for index in changed for n in self._hidden_ranges[index]})
        starts = [[segment.start for segment in program] for program in self.programs]
        if not changed:
            return self.source, starts
        spans = self._source_spans()
        ensure_ascii = escapes_non_ascii(self.text)
        pieces: list[str] = []
        done = 0
        for index in sorted(changed):
            cell = self.cells[index]
            new_source: str | list[str] = changed[index]
            if isinstance(cell.get("source"), list):
                new_source = changed[index].splitlines(keepends=True)
            span = spans.get(index)
            if span is None:
                raise TransformError(f"cell {index + 1} has no `source` in the notebook's JSON; left unchanged")
            pieces += [self.text[done : span.start], new_source_text(self.text, span, new_source, ensure_ascii=ensure_ascii)]
            done = span.end
            cell["source"] = new_source
        pieces.append(self.text[done:])
        rewritten = "".join(pieces)
        _check_sources(rewritten, self.cells)
        return rewritten.encode("utf-8"), starts

    def check_writable(self) -> None:
        self._source_spans()

    def _source_spans(self) -> dict[int, Span]:
        try:
            return cell_source_spans(self.text)
        except JSONLayoutError as exc:
            raise TransformError(f"the cells' sources could not be located in the notebook's JSON ({exc}); left unchanged") from None

    def code_view(self) -> str:
        """The code cells as one text, each under a ``# cell N`` line (1-based, every cell
        counted), for a diff a person can read instead of escaped JSON."""
        parts = []
        for index, cell in enumerate(self.cells):
            if isinstance(cell, dict) and cell.get("cell_type") == "code":
                parts.append(f"# cell {index + 1}\n{_with_final_newline(_cell_text(cell))}")
        return "".join(parts)


NOTEBOOK_MIGRATED = "this notebook's code is migrated with it in the same run (imports, reset/step API)"
_INSTALL_LINE = re.compile(r"[ \t]*[!%][ \t]*(?:python3? -m )?pip3?[ \t]+install\b")



def unparsed_cell_finding(code: str, line: int, detail: str, cell: int | None) -> Finding:
    """GM001 for a cell that does not parse. Its tier follows the code the cell holds (a
    token scan: comments and docstrings do not count), not the words in it: an exercise
    cell with no Gym call is a note; one that resets, steps or renders an env, makes one
    or unpacks ``done`` is to be ported by hand; one that masks a value with ``done``
    (``1 - done``) asks GM302's question, which the run cannot ask inside it."""
    # (a notebook with no Gym code at all has no cells to migrate: this one is in a Gym program)
    what = classify_unparsed(code)
    left = f"this code cell does not parse ({detail}); left as it is, the other cells are migrated without it"
    if what is UnparsedCode.NO_GYM:
        message, tier = f"{left}; it holds no Gym call", Tier.NOTE
    elif what is UnparsedCode.DONE_MASK:
        message, tier = (
            f"{left}: it masks a value with a done flag (`1 - done`); once it runs, that flag must be `terminated` "
            "(GM302): an episode cut by a time limit is no terminal state, so its next-state value still counts; "
            "store terminated where the transitions are recorded",
            None,
        )
    else:
        message, tier = f"{left}: it holds Gym calls, check it by hand", None
    return Finding(line=line, column=0, rule=UNPARSED_CELL, kind=FixKind.FLAG, message=message, cell=cell, tier=tier)

def _is_python(data: dict[str, Any]) -> bool:
    metadata = data.get("metadata")
    if not isinstance(metadata, dict):
        metadata = {}
    for key, field in (("kernelspec", "language"), ("language_info", "name")):
        info = metadata.get(key)
        if isinstance(info, dict) and isinstance(info.get(field), str):
            return info[field].lower().startswith("python")
    return True  # nbformat's default kernel is Python


def _cell_text(cell: dict[str, Any]) -> str:
    source = cell.get("source", "")
    if isinstance(source, list) and all(isinstance(part, str) for part in source):
        text = "".join(source)
    elif isinstance(source, str):
        text = source
    else:
        raise TransformError("a cell's source is neither text nor a list of lines; notebook left unchanged")
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:  # a lone surrogate escaped in the JSON
        raise TransformError("a cell holds text that is not valid Unicode; notebook left unchanged") from None
    return text


def _with_final_newline(text: str) -> str:
    return text if not text or text.endswith("\n") else text + "\n"


def _parse_problem(code: str) -> tuple[int, str] | None:
    """None if the cell's code parses, else the line (1-based, within the cell) and why not."""
    try:
        ast.parse(code)
    except SyntaxError as exc:
        line = exc.lineno or 1
        return line, f"line {line}: {exc.msg}"
    except (ValueError, RecursionError, MemoryError) as exc:
        return 1, f"cannot be parsed: {type(exc).__name__}"
    return None


def _check_sources(rewritten: str, cells: list[Any]) -> None:
    """The edited text must read back (as Jupyter reads it) with exactly the new sources."""
    try:
        data = json.loads(rewritten)
        ok = [_source_of(cell) for cell in data["cells"]] == [_source_of(cell) for cell in cells]
    except (ValueError, KeyError, TypeError):
        ok = False
    if not ok:
        raise TransformError("the notebook's JSON could not be edited in place; left unchanged")


def _source_of(cell: Any) -> Any:
    return cell.get("source") if isinstance(cell, dict) else None
