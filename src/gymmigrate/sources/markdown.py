"""Markdown pages: fenced code blocks (```` ``` ```` or ``~~~``) whose info string names
Python (``python``, ``py``, ``python3``, ``pycon``...). Every other byte is prose or
another language's block and stays as it is. Indented code blocks carry no language and
are left alone.
"""

from __future__ import annotations

import re

from gymmigrate.sources import lines_of
from gymmigrate.sources.pages import (
    MAX_FILE_BYTES,
    PYTHON_LANGUAGES,
    Block,
    Page,
    page_text,
)

__all__ = ["MAX_FILE_BYTES", "read"]

_OPENING = re.compile(r"(?P<indent>[ \t]*)(?P<fence>`{3,}|~{3,})[ \t]*(?P<info>[^\r\n]*?)[ \t]*\r?\n?")


def read(source: bytes, path: str) -> Page:
    text = page_text(source)
    return Page(text, list(_python_blocks(lines_of(text))))


def _python_blocks(lines: list[str]):
    index = 0
    while index < len(lines):
        opening = _OPENING.fullmatch(lines[index])
        if opening is None or (opening["fence"][0] == "`" and "`" in opening["info"]):
            index += 1
            continue
        fence = opening["fence"]
        closing = re.compile(rf"[ \t]*{re.escape(fence[0])}{{{len(fence)},}}[ \t]*\r?\n?")
        end = next((i for i in range(index + 1, len(lines)) if closing.fullmatch(lines[i])), None)
        if end is None:
            return  # an unclosed fence runs to the end of the page: nothing after it is prose
        if _language(opening["info"]) in PYTHON_LANGUAGES and end > index + 1:
            yield Block(first=index + 1, lines=lines[index + 1 : end], indent=opening["indent"])
        index = end + 1


def _language(info: str) -> str:
    """``python``, ``{python}``, ``{.python}``, ``python title="x.py"`` -> ``python``."""
    word = info.strip().strip("{}").split(maxsplit=1)[0] if info.strip().strip("{}") else ""
    return word.lstrip(".").rstrip(",").lower()
