"""Where a notebook's cell sources sit in its JSON text, and their new text in its style.

A notebook is edited in place: the ``source`` value of a changed cell is cut out of the
file's text and a new one put in its place, so nothing else is serialized again. This
module finds those values (by character offsets into the text) and writes a new one in
the style of the old: the lines that did not change keep their bytes, indentation and
escapes included.

The text has already been read by ``json.loads``, so it is valid JSON; where an object
repeats a key, the last occurrence is the one ``json.loads`` (and so Jupyter) keeps, and
the one found here.
"""

from __future__ import annotations

import difflib
import json
import re
from collections.abc import Iterator
from dataclasses import dataclass

_WHITESPACE = re.compile(r"[ \t\n\r]*")
_DECODER = json.JSONDecoder()
_ESCAPE = re.compile(r"\\(u[0-9a-fA-F]{4}|.)")


class JSONLayoutError(ValueError):
    """The text is not shaped as the scanner expects (it is valid JSON, so: a bug)."""


@dataclass(frozen=True)
class Span:
    start: int
    end: int  # exclusive


@dataclass(frozen=True)
class _Item:
    """One string of a ``source`` list: the whitespace before it, its literal, and the
    whitespace after it (before the next ``,``, or before ``]`` for the last)."""

    lead: str
    literal: str
    trail: str
    value: str


def cell_source_spans(text: str) -> dict[int, Span]:
    """Cell index -> where the value of that cell's ``source`` is, in the ``cells`` list
    of the top-level object (the last ``cells`` key, the last ``source`` of a cell)."""
    pos = _skip(text, 0)
    cells: Span | None = None
    for key, value in _members(text, pos):
        if key == "cells":
            cells = value
    if cells is None or text[cells.start] != "[":
        raise JSONLayoutError("no top-level `cells` list")
    spans: dict[int, Span] = {}
    for index, cell in enumerate(_elements(text, cells.start)):
        if text[cell.start] != "{":
            continue
        for key, value in _members(text, cell.start):
            if key == "source":
                spans[index] = value
    return spans


def new_source_text(text: str, span: Span, new: str | list[str], *, ensure_ascii: bool) -> str:
    """The JSON text of ``new`` to put at ``span`` (which holds the old source) in ``text``;
    ``ensure_ascii`` as ``escapes_non_ascii(text)`` says."""
    old = text[span.start : span.end]
    if isinstance(new, str):
        return json.dumps(new, ensure_ascii=ensure_ascii)
    items = _items(text, span)
    if not items:
        if not new:
            return old
        lead, close = _fresh_layout(text, span)
        items_text = ",".join(lead + json.dumps(line, ensure_ascii=ensure_ascii) for line in new)
        return f"[{items_text}{close}]"
    if not new:
        return "[]"
    close = items[-1].trail
    pieces: list[tuple[str, str, str]] = []  # lead, literal, whitespace before the comma
    matcher = difflib.SequenceMatcher(a=[item.value for item in items], b=new, autojunk=False)
    for tag, i1, i2, j1, j2 in matcher.get_opcodes():
        if tag == "equal":
            pieces.extend((items[i].lead, items[i].literal, items[i].trail) for i in range(i1, i2))
            continue
        for k, line in enumerate(new[j1:j2]):
            # A new line is indented as the line it replaces (or the one before it).
            model = items[min(i1 + k, i2 - 1)] if i2 > i1 else items[max(i1 - 1, 0)]
            pieces.append((model.lead, json.dumps(line, ensure_ascii=ensure_ascii), ""))
    body = ",".join(lead + literal + (trail if n < len(pieces) - 1 else "") for n, (lead, literal, trail) in enumerate(pieces))
    return f"[{body}{close}]"


def _skip(text: str, pos: int) -> int:
    match = _WHITESPACE.match(text, pos)
    assert match is not None  # the pattern matches the empty string
    return match.end()


def _expect(text: str, pos: int, what: str) -> None:
    if text[pos : pos + 1] != what:
        raise JSONLayoutError(f"expected {what!r} at character {pos}")


def _value(text: str, pos: int) -> Span:
    try:
        _, end = _DECODER.raw_decode(text, pos)
    except json.JSONDecodeError as exc:
        raise JSONLayoutError(str(exc)) from None
    return Span(pos, end)


def _members(text: str, pos: int) -> Iterator[tuple[str, Span]]:
    """The members of the object that starts at ``pos``, in file order, duplicates included."""
    _expect(text, pos, "{")
    pos = _skip(text, pos + 1)
    if text[pos : pos + 1] == "}":
        return
    while True:
        key_span = _value(text, pos)
        key = json.loads(text[key_span.start : key_span.end])
        if not isinstance(key, str):
            raise JSONLayoutError(f"a key that is not a string at character {pos}")
        pos = _skip(text, key_span.end)
        _expect(text, pos, ":")
        value = _value(text, _skip(text, pos + 1))
        yield key, value
        pos = _skip(text, value.end)
        if text[pos : pos + 1] == ",":
            pos = _skip(text, pos + 1)
            continue
        _expect(text, pos, "}")
        return


def _elements(text: str, pos: int) -> Iterator[Span]:
    """The elements of the array that starts at ``pos``."""
    _expect(text, pos, "[")
    pos = _skip(text, pos + 1)
    if text[pos : pos + 1] == "]":
        return
    while True:
        value = _value(text, pos)
        yield value
        pos = _skip(text, value.end)
        if text[pos : pos + 1] == ",":
            pos = _skip(text, pos + 1)
            continue
        _expect(text, pos, "]")
        return


def _items(text: str, span: Span) -> list[_Item]:
    items: list[_Item] = []
    after = span.start + 1  # just past "[" or ","
    for element in _elements(text, span.start):
        literal = text[element.start : element.end]
        value = json.loads(literal)
        if not isinstance(value, str):
            raise JSONLayoutError("a source list holds something that is not a string")
        trail_end = _skip(text, element.end)
        items.append(_Item(text[after : element.start], literal, text[element.end : trail_end], value))
        after = trail_end + 1
    return items


def _fresh_layout(text: str, span: Span) -> tuple[str, str]:
    """Whitespace before each line and before ``]`` for a list that was empty: one indent
    step deeper than the line of its key, as ``json.dumps`` with the file's indent writes."""
    indent_match = re.match(r"[\[{]\r?\n( *)\S", text)
    if indent_match is None:
        return "", ""
    newline = "\r\n" if "\r\n" in text else "\n"
    line_start = text.rfind("\n", 0, span.start) + 1
    key_indent = re.match(r" *", text[line_start:])
    assert key_indent is not None
    return newline + key_indent[0] + indent_match[1], newline + key_indent[0]


def escapes_non_ascii(text: str) -> bool:
    """Whether the file writes non-ASCII characters as ``\\uXXXX`` (Colab may; nbformat
    writes them as they are)."""
    if not text.isascii():
        return False
    return any(match[1][0] == "u" and int(match[1][1:], 16) >= 0x80 for match in _ESCAPE.finditer(text))
