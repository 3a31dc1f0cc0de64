"""Where Python programs live besides ``.py`` files: one adapter per kind of file.

An adapter reads a file's bytes into a ``Document``: the Python program(s) it holds, each
a list of ``Segment``s (a notebook cell, a documentation block, one ``>>>`` example) with
the place each came from, and a way to rebuild the file from the migrated segments,
leaving every other byte as it was. The engine's ``transform_source`` / ``lint_source``
stay the only code that migrates Python; ``programs.migrate`` runs them over a document.

Adding a format is adding a module with a ``read(source, path) -> Document`` function and
a line in ``_ADAPTERS``.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

from gymmigrate.findings import Finding


@dataclass(frozen=True)
class Location:
    """A line of the file: 1-based, within ``cell`` (0-based index) for notebooks."""

    line: int
    cell: int | None = None

    def plus(self, lines: int) -> Location:
        return Location(self.line + lines, self.cell)


@dataclass(frozen=True)
class Segment:
    """A piece of one program: its Python text (each line ends with a newline) and where
    its first line is in the file; line ``k`` of the text is ``start.plus(k - 1)``."""

    code: str
    start: Location


def lines_of(text: str) -> list[str]:
    """The lines of a text, each with its line ending. Only ``\n`` ends a line (``\r\n``
    included): ``str.splitlines`` would also split at form feeds and U+2028 in prose."""
    lines = text.split("\n")
    return [line + "\n" for line in lines[:-1]] + ([lines[-1]] if lines[-1] else [])


class Document(Protocol):
    programs: list[list[Segment]]
    notes: list[Finding]  # things the adapter found itself (a doc block that does not parse)
    # The adapter changes the file outside the programs too (a notebook's install lines).
    changes_outside_code: bool

    def rebuild(self, codes: list[list[str]]) -> tuple[bytes, list[list[Location]]]:
        """The file with each segment's code replaced, and where each segment now starts."""
        ...

    def check_writable(self) -> None:
        """Raise TransformError if a rewrite could not be written (what ``check`` reports
        when the file would change, so that it agrees with ``rewrite``)."""
        ...

    def code_view(self) -> str:
        """The text a diff of this file shows (the file itself, or a notebook's code cells)."""
        ...


@dataclass(frozen=True)
class Adapter:
    name: str
    read: Callable[[bytes, str], Document]
    max_bytes: int  # a larger file is refused unread (notebooks carry their outputs)


def adapter_for(path: Path) -> Adapter | None:
    """The adapter for ``path``'s kind, or None for Python source, which takes the
    engine's own path unchanged (a ``.py`` file is its own single program)."""
    module_name = _ADAPTERS.get(path.suffix.lower())
    if module_name is None:
        return None
    module = importlib.import_module(f"gymmigrate.sources.{module_name}")
    return Adapter(module_name, module.read, module.MAX_FILE_BYTES)


_ADAPTERS = {".ipynb": "notebook", ".md": "markdown", ".markdown": "markdown", ".rst": "rst"}
