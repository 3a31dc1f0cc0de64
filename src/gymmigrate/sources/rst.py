"""reStructuredText pages: ``.. code-block:: python``, ``.. code:: python``,
``.. sourcecode:: python``, ``.. testcode::`` and ``.. doctest::`` directives, and doctest
blocks (a paragraph that starts with ``>>>``). A directive's options (``:linenos:``) and
everything outside the directive's content stay as they are. Code directives in another
language are skipped whole, so a ``>>>`` inside them is not taken for Python.

Literal blocks (after a paragraph ending in ``::``) carry no language: Sphinx highlights
them as Python when they parse as Python, unless a ``.. highlight::`` directive names
another language. They are taken on the same terms: only if they parse, and a literal
block that does not parse is not reported (it is most likely output or shell).
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

_DIRECTIVE = re.compile(
    r"(?P<indent>[ \t]*)\.\.[ \t]+(?P<name>code-block|code|sourcecode|testcode|doctest|testoutput|literalinclude)"
    r"::(?:[ \t]+(?P<argument>[^\r\n]*?))?[ \t]*\r?\n?"
)
_ALWAYS_PYTHON = frozenset({"testcode", "doctest"})
_HIGHLIGHT = re.compile(r"[ \t]*\.\.[ \t]+highlight::[ \t]*(?P<language>\S*)")
_LITERAL_INTRODUCTION = re.compile(r"[^\r\n]*\S[ \t]*::[ \t]*\r?\n?")
_DEFAULT_LANGUAGES = frozenset({"", "default", "python", "python3", "py", "py3"})


def read(source: bytes, path: str) -> Page:
    text = page_text(source)
    return Page(text, list(_python_blocks(lines_of(text))))


def _indent_of(line: str) -> str:
    return line[: len(line) - len(line.lstrip(" \t"))]


def _python_blocks(lines: list[str]):
    index = 0
    literal_language = ""  # what `.. highlight::` set for literal blocks
    while index < len(lines):
        line = lines[index]
        highlight = _HIGHLIGHT.match(line)
        if highlight is not None:
            literal_language = highlight["language"].lower()
            index += 1
            continue
        if _LITERAL_INTRODUCTION.fullmatch(line) and not line.lstrip(" \t").startswith(".."):
            block, index = _directive_content(lines, index, _indent_of(line))
            if block is not None and literal_language in _DEFAULT_LANGUAGES:
                block.maybe_python = True
                yield block
            continue
        directive = _DIRECTIVE.fullmatch(line)
        if directive is not None:
            block, index = _directive_content(lines, index, directive["indent"])
            language = (directive["argument"] or "").split(maxsplit=1)[0].lower() if directive["argument"] else ""
            if block is not None and (directive["name"] in _ALWAYS_PYTHON or language in PYTHON_LANGUAGES):
                yield block
            continue
        if line.lstrip(" \t").startswith(">>>") and (index == 0 or not lines[index - 1].strip()):
            end = next((i for i in range(index, len(lines)) if not lines[i].strip()), len(lines))
            yield Block(first=index, lines=lines[index:end], indent=_indent_of(line))
            index = end
            continue
        index += 1


def _directive_content(lines: list[str], index: int, indent: str) -> tuple[Block | None, int]:
    """The directive's content (after its options and a blank line), and the next line to read."""
    position = index + 1
    while position < len(lines) and lines[position].strip().startswith(":") and len(_indent_of(lines[position])) > len(indent):
        position += 1  # options
    while position < len(lines) and not lines[position].strip():
        position += 1
    if position >= len(lines) or len(_indent_of(lines[position])) <= len(indent) or not lines[position].startswith(indent):
        return None, index + 1
    content_indent = _indent_of(lines[position])
    end = position
    while end < len(lines) and (not lines[end].strip() or lines[end].startswith(content_indent)):
        end += 1
    while end > position and not lines[end - 1].strip():
        end -= 1  # trailing blank lines belong to the prose
    return Block(first=position, lines=lines[position:end], indent=content_indent), end
