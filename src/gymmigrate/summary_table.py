"""The closing summary as a table, for a person at a terminal (logs keep the one-line form)."""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence

from rich.table import Table

from gymmigrate.process import FileResult, Status


def summary_table(results: Sequence[FileResult], per_rule: Counter[str], review: int, *, wrote: bool) -> Table:
    table = Table(show_header=False, box=None, padding=(0, 2))
    table.add_column(style="bold")
    table.add_column(justify="right")
    statuses = Counter(result.status for result in results)
    table.add_row("Scanned", str(len(results)))
    table.add_row("Skipped (no Gym code)", str(statuses[Status.SKIPPED]))
    table.add_row("Changed" if wrote else "Would change", str(statuses[Status.CHANGED]))
    table.add_row("Failed", str(statuses[Status.ERROR]))
    table.add_row("Review items", str(review))
    for rule, count in sorted(per_rule.items()):
        table.add_row(f"  {rule}", f"x{count}")
    return table
