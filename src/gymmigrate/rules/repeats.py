"""One decision, one review item: the same question repeated in a file is asked once.

Where a file uses a removed name ten times (``error.InvalidFrame``, ``VideoRecorder``),
the decision (what replaces it) is made once; the first use is the review item and the
others are notes that point at it, so the review list stays one item per decision while
every place is still listed (``check``, the JSON report).
"""

from __future__ import annotations

import ast
from collections.abc import Hashable

from gymmigrate.findings import Tier


class Repeats:
    def __init__(self) -> None:
        self._first: dict[Hashable, ast.AST] = {}

    def tier(self, key: Hashable, node: ast.AST, what: str = "decision") -> tuple[Tier | None, str]:
        """(tier, suffix for the message): no tier (the kind decides) for the first node
        asking ``key``, a note saying where it was asked for any later one."""
        first = self._first.setdefault(key, node)
        if first is node:
            return None, ""
        return Tier.NOTE, f" (the same {what} as line {first.lineno})"  # type: ignore[attr-defined]
