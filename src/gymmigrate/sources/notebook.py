"""Jupyter notebooks (``.ipynb``): the code cells, in order, are one program.

Everything else in the file is kept: markdown cells, outputs, execution counts,
metadata, key order and the JSON layout. Only the ``source`` of a cell whose code changed
is replaced, in the form it had (a list of lines or one string). The notebook is written
again with ``json.dumps`` using the layout read from the file (indent, ``ensure_ascii``,
final newline: nbformat writes indent 1, non-ASCII as is and a final newline); before
writing, the unmodified notebook is serialized the same way and must reproduce the file
byte for byte, otherwise the notebook is refused rather than reformatted.

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
from collections.abc import Callable
from functools import partial
from itertools import product
from typing import Any

from gymmigrate.findings import Finding, FixKind
from gymmigrate.source_text import TransformError, may_hold_gym_code
from gymmigrate.sources import Location, Segment
from gymmigrate.sources.magics import Magics

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
        # A cell that does not parse (an exercise's `<YOUR CODE>`, half-written code) is
        # reported and left byte for byte; the other cells are still one program.
        parsed = []
        for segment in segments:
            problem = _parse_problem(segment.code)
            if problem is None:
                parsed.append(segment)
                continue
            line, detail = problem
            self.notes.append(
                Finding(
                    line=line,
                    column=0,
                    rule=UNPARSED_CELL,
                    kind=FixKind.FLAG,
                    message=f"this code cell does not parse ({detail}); left as it is, the other cells are "
                    "migrated without it: check it by hand",
                    cell=segment.start.cell,
                )
            )
        self.programs = [parsed] if parsed else []

    def rebuild(self, codes: list[list[str]]) -> tuple[bytes, list[list[Location]]]:
        changed: dict[int, str] = {}
        for program, new_codes in zip(self.programs, codes):
            for segment, new_code in zip(program, new_codes):
                if new_code == segment.code:
                    continue
                index = segment.start.cell
                assert index is not None
                text = self.magics.restore(new_code)
                if not _cell_text(self.cells[index]).endswith("\n"):
                    text = text.removesuffix("\n")  # nbformat stores the last line without one
                changed[index] = text
        self.magics.check_all_restored({n for index in changed for n in self._hidden_ranges[index]})
        starts = [[segment.start for segment in program] for program in self.programs]
        if not changed:
            return self.source, starts
        dump = _layout_of(self.text, self.data)
        for index, text in changed.items():
            cell = self.cells[index]
            cell["source"] = text.splitlines(keepends=True) if isinstance(cell.get("source"), list) else text
        return dump(self.data).encode("utf-8"), starts

    def check_writable(self) -> None:
        _layout_of(self.text, self.data)

    def code_view(self) -> str:
        """The code cells as one text, each under a ``# cell N`` line (1-based, every cell
        counted), for a diff a person can read instead of escaped JSON."""
        parts = []
        for index, cell in enumerate(self.cells):
            if isinstance(cell, dict) and cell.get("cell_type") == "code":
                parts.append(f"# cell {index + 1}\n{_with_final_newline(_cell_text(cell))}")
        return "".join(parts)


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


def _layout_of(text: str, data: Any) -> Callable[[Any], str]:
    """A serializer that writes this file's JSON layout, checked on the file as it is.

    nbformat (Jupyter, VS Code) writes indent 1, ``ensure_ascii=False`` and a final
    newline; Colab indent 2. A notebook saved on Windows (or checked out with
    ``core.autocrlf``) has CRLF line ends: JSON strings hold no raw line break, so every
    ``\n`` of the dump is a line end to write as the file does. The first candidate that
    reproduces ``text`` exactly wins.
    """
    newline = "\r\n" if "\r\n" in text else "\n"
    indent_match = re.match(r"[\[{]\r?\n( *)\S", text)
    indent = len(indent_match[1]) if indent_match else None
    final_newline = newline if text.endswith(newline) else ""
    for ensure_ascii, separators in product((False, True), ((",", ": "), (", ", ": "), (",", ":"))):
        dump = partial(json.dumps, indent=indent, ensure_ascii=ensure_ascii, separators=separators)
        if newline != "\n":
            dump = partial(_with_line_ends, dump, newline)
        if dump(data) + final_newline == text:
            return partial(_ending_with, dump, final_newline)
    raise TransformError(
        "the notebook's JSON layout cannot be reproduced (not written by Jupyter/nbformat?);"
        " left unchanged rather than reformatted"
    )


def _with_line_ends(dump: Callable[[Any], str], newline: str, value: Any) -> str:
    return dump(value).replace("\n", newline)


def _ending_with(dump: Callable[[Any], str], final_newline: str, value: Any) -> str:
    return dump(value) + final_newline
