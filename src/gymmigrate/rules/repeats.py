"""One decision, one review item: the same question repeated in a file is asked once.

Where a file uses a removed name ten times (``error.InvalidFrame``, ``VideoRecorder``),
the decision (what replaces it) is made once. Each use is reported with the same
question key (``Repeats.question``); the plan's ``ask_once`` then keeps the first use as
the review item, naming every other line, and turns the others into notes pointing at
it, so the review list stays one item per decision, every place of it is named by that
item, and every place is still listed (``check``, the JSON report).
"""

from __future__ import annotations

import ast
from collections.abc import Hashable


class Repeats:
    def __init__(self, what: str) -> None:
        self._what = what  # the decision's kind, apart from other families' questions
        self._first: dict[Hashable, ast.AST] = {}

    def question(self, key: Hashable) -> Hashable:
        """The question every node asking ``key`` is reported with."""
        return ("asked once", self._what, key)

    def first(self, key: Hashable, node: ast.AST) -> bool:
        """``node`` is the first reported asking ``key`` (what is said once, at it)."""
        return self._first.setdefault(key, node) is node
