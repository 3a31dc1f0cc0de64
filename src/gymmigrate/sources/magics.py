"""IPython syntax in notebook cells: kept byte for byte, never parsed as Python.

A line magic (``%time``), a shell escape (``!pip install``), a help request (``env?``,
``?env``), ``files = !ls`` and ``get_ipython()`` calls are not Python the rules should
read. Each such line is replaced by a placeholder that parses, ``pass  # gymmigrate-magic
N`` at the same indentation, and restored after migration. A cell magic hides its whole
cell (``%%bash``, ``%%writefile``), except those whose body IPython runs as Python
(``%%time``, ``%%timeit``, ``%%capture``, ``%%prun``): only their first line is hidden. Only lines that start a statement are candidates: a
``!`` or ``?`` inside a triple-quoted string or a bracket stays text.
"""

from __future__ import annotations

import re

from gymmigrate.source_text import TransformError
from gymmigrate.sources import lines_of

_PLACEHOLDER = "pass  # gymmigrate-magic {}\n"
_PLACEHOLDER_LINE = re.compile(r"(?P<indent>[ \t]*)pass  # gymmigrate-magic (?P<number>\d+)\r?\n?")
_MAGIC_LINE = re.compile(
    r"""[ \t]*(?:
        [%!?]                                   # %magic, !shell, ?help
      | get_ipython\(\)                         # what IPython itself turns magics into
      | [A-Za-z_][\w.]*\?{1,2}[ \t]*\r?\n?$     # env? / env.step??
      | [A-Za-z_][\w.]*(?:[ \t]*,[ \t]*[A-Za-z_][\w.]*)*[ \t]*=[ \t]*[!%]   # files = !ls
    )""",
    re.VERBOSE,
)


# Cell magics whose body is Python that IPython runs as it is: only their first line is
# hidden, so a `%%time` training loop is migrated like any other cell.
PYTHON_CELL_MAGICS = frozenset({"time", "timeit", "capture", "prun"})
_CELL_MAGIC_NAME = re.compile(r"[ \t\r\n]*%%(\w+)")


def is_cell_magic(code: str) -> bool:
    return code.lstrip(" \t\r\n").startswith("%%")


def _body_is_python(code: str) -> bool:
    match = _CELL_MAGIC_NAME.match(code)
    return match is not None and match[1] in PYTHON_CELL_MAGICS


class Magics:
    """The IPython lines of one notebook, numbered across its cells."""

    def __init__(self) -> None:
        self.hidden: list[str] = []
        self.restored: set[int] = set()
        self.replacements: dict[int, str] = {}  # hidden line -> what it is given back as

    def hidden_number(self, line: str) -> int | None:
        """The number of the hidden line ``line`` stands for, if it is a placeholder."""
        match = _PLACEHOLDER_LINE.fullmatch(line)
        return int(match["number"]) if match is not None else None

    def replace(self, number: int, line: str) -> None:
        """Give hidden line ``number`` back as ``line`` (an install line with new requirements)."""
        self.replacements[number] = line

    def hide(self, code: str) -> str:
        """``code`` with each IPython line (or the whole cell, for a cell magic) replaced."""
        out: list[str] = []
        lines = lines_of(code)
        if is_cell_magic(code):
            if not _body_is_python(code):
                return self._placeholder("", code)
            head = next(i for i, line in enumerate(lines) if line.strip())
            out.extend(lines[:head])  # blank lines: kept, so lines keep their numbers
            out.append(self._placeholder("", lines[head]))
            lines = lines[head + 1 :]
        indent = ""
        for line, magic in _magic_lines(lines):
            if magic == _MAGIC:
                indent = line[: len(line) - len(line.lstrip(" \t"))]
                out.append(self._placeholder(indent, line))
            elif magic == _MAGIC_CONTINUED:
                # ``!apt-get install -y \`` goes on on the next line, which IPython joins to
                # it: hidden as well, at the magic's indentation, one placeholder per line
                out.append(self._placeholder(indent, line))
            else:
                out.append(line)
        return "".join(out)

    def _placeholder(self, indent: str, original: str) -> str:
        self.hidden.append(original)
        return indent + _PLACEHOLDER.format(len(self.hidden) - 1)

    def restore(self, code: str) -> str:
        """Put the hidden lines back; every placeholder must still be there, unchanged."""
        out: list[str] = []
        for line in lines_of(code):
            match = _PLACEHOLDER_LINE.fullmatch(line)
            if match is None:
                out.append(line)
                continue
            number = int(match["number"])
            if number >= len(self.hidden) or number in self.restored:
                raise TransformError("the rewrite changed an IPython magic line; notebook left unchanged")
            self.restored.add(number)
            out.append(self.replacements.get(number, self.hidden[number]))
        return "".join(out)

    def check_all_restored(self, hidden_in: set[int]) -> None:
        if not hidden_in <= self.restored:
            raise TransformError("the rewrite lost an IPython magic line; notebook left unchanged")


_PYTHON, _MAGIC, _MAGIC_CONTINUED = 0, 1, 2


def _magic_lines(lines: list[str]):
    """Each line, and whether it is Python, an IPython line, or a line an IPython line ending
    in a backslash continues onto."""
    continues = False
    for line, starts in _statement_starts(lines):
        if continues:
            kind = _MAGIC_CONTINUED
        elif starts and _MAGIC_LINE.match(line):
            kind = _MAGIC
        else:
            kind = _PYTHON
        continues = kind != _PYTHON and line.rstrip("\r\n").endswith("\\")
        yield line, kind


def _statement_starts(lines: list[str]):
    """Each line, and whether it starts a statement (not inside brackets, a string or a
    backslash continuation). A small scanner: cells are short and this runs only on
    notebooks that mention Gym."""
    depth = 0
    string: str | None = None  # the open quote, while inside a string
    continued = False
    magic_continues = False
    for line in lines:
        starts = depth == 0 and string is None and not continued and not magic_continues
        yield line, starts
        if magic_continues or (starts and _MAGIC_LINE.match(line)):
            # its quotes and brackets are not Python's, nor those of the lines it goes on to
            magic_continues = line.rstrip("\r\n").endswith("\\")
            continue
        continued = False
        i, end = 0, len(line.rstrip("\r\n"))
        while i < end:
            if string is not None:
                if line[i] == "\\":
                    i += 2
                elif line.startswith(string, i):
                    i += len(string)
                    string = None
                else:
                    i += 1
                continue
            char = line[i]
            if char == "#":
                break
            if char in "([{":
                depth += 1
            elif char in ")]}":
                depth = max(depth - 1, 0)
            elif char in "\"'":
                string = line[i : i + 3] if line[i : i + 3] in ('"""', "'''") else char
                i += len(string)
                continue
            elif char == "\\" and i == end - 1:
                continued = True
            i += 1
        if string in ('"', "'"):
            string = None  # a one-quote string cannot span lines
