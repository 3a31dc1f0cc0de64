"""Which rules a run applies: ``--select`` / ``--ignore`` (and their ``extend-`` forms),
by code or prefix, the way ruff reads them.

A selector is a rule code (``GM301``), a prefix of codes (``GM3``, ``PZ``) or ``ALL``.
For each rule the most specific selector that matches it decides (ignore wins a tie);
a rule no selector matches is on when nothing was selected (every rule runs by default).
A deselected rule neither reports nor fixes: ``edits.filtering.filter_plan`` drops its
findings together with their edits, and does the same for findings silenced by a
suppression comment; a selected rule's change that only makes sense beside a left-out one
goes with it, reported as left as it is.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field


class SelectionError(ValueError):
    """A selector names no implemented rule; the message says which."""


@dataclass(frozen=True)
class Selection:
    """The rules a run applies, resolved once from the selectors."""

    allowed: frozenset[str]
    every_rule: bool = field(default=False)

    def allows(self, code: str) -> bool:
        return self.every_rule or code in self.allowed

    @classmethod
    def from_selectors(
        cls,
        select: Sequence[str] | None = None,
        ignore: Sequence[str] = (),
        extend_select: Sequence[str] = (),
        extend_ignore: Sequence[str] = (),
        *,
        codes: Iterable[str],
    ) -> Selection:
        """``codes``: every implemented rule code (``rules.all_rules()``)."""
        codes = sorted(codes)
        chosen = list(select) if select is not None else ["ALL"]
        chosen += list(extend_select)
        ignored = list(ignore) + list(extend_ignore)
        for selector in chosen + ignored:
            check_selector(selector, codes)
        allowed = {code for code in codes if _decides(code, chosen, ignored)}
        return cls(frozenset(allowed), every_rule=allowed == set(codes))


def check_selector(selector: str, codes: Sequence[str]) -> None:
    if selector == "ALL" or any(code.startswith(selector) for code in codes):
        return
    raise SelectionError(f"unknown rule code or prefix {selector!r} (see `gymmigrate rules`)")


def parse_selectors(values: Sequence[str] | None) -> list[str] | None:
    """Command-line values, each possibly a comma-separated list, as selectors."""
    if values is None:
        return None
    return [part.strip().upper() for value in values for part in value.split(",") if part.strip()]


def _decides(code: str, chosen: Sequence[str], ignored: Sequence[str]) -> bool:
    def specificity(selectors: Sequence[str]) -> int:
        lengths = [0 if s == "ALL" else len(s) for s in selectors if s == "ALL" or code.startswith(s)]
        return max(lengths, default=-1)

    selected, deselected = specificity(chosen), specificity(ignored)
    return selected >= 0 and selected > deselected
