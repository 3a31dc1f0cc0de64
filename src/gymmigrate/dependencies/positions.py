"""Offsets in a dependency file's text as lines and columns.

Its own module so that reading a file's plugin entry points (``plugins.py``, which the
runner loads for every run) does not load the requirement parsers."""

from __future__ import annotations

import re
from bisect import bisect_right


class Positions:
    """Offsets in a text -> 1-based lines and 0-based columns."""

    def __init__(self, text: str) -> None:
        self.starts = [0] + [match.end() for match in re.finditer(r"\n", text)]

    def of(self, offset: int) -> tuple[int, int]:
        index = bisect_right(self.starts, offset) - 1
        return index + 1, offset - self.starts[index]
