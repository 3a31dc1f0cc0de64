"""``gymmigrate rewrite --smoke``: smoke-check the scripts a rewrite just wrote.

Only files that can create an env are run (their text calls ``make(`` or defines a
class deriving from an ``...Env``); a file that, when run, still creates no env (a
module of helpers, an env class with no ``__main__`` block) is reported as skipped and
does not count against the run. A failed check or a script that cannot run does: the
rewrite is not verified, so the command exits 1.
"""

from __future__ import annotations

import re
import sys
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import TextIO

from gymmigrate.smoke.runner import SmokeOptions, run_smoke
from gymmigrate.smoke.summary import one_line

_CREATES_ENV = re.compile(r"\bmake(?:_vec)?\s*\(|^\s*class\s+\w+\s*\([^)]*Env\b", re.MULTILINE)


def may_create_env(source: str) -> bool:
    return _CREATES_ENV.search(source) is not None


@dataclass(frozen=True)
class SmokeOutcome:
    """One rewritten file's smoke check, for the summary and the JSON report."""

    path: str
    outcome: str  # "passed", "failed" or "skipped" (running it created no env)
    exit_code: int
    summary: str

    def to_json(self) -> dict[str, object]:
        return asdict(self)


def smoke_rewritten(paths: list[str], seed: int, stream: TextIO | None = None) -> list[SmokeOutcome]:
    """Run the script smoke check on each file that may create an env."""
    from rich.console import Console
    from rich.markup import escape

    console = Console(file=stream or sys.stderr, highlight=False, soft_wrap=True)
    candidates = [path for path in paths if _reads_as_env_code(path)]
    if not candidates:
        console.print("\n[bold]Smoke[/bold]: no rewritten file creates an env")
        return []
    console.print(f"\n[bold]Smoke[/bold] ({len(candidates)} file{'s' if len(candidates) != 1 else ''}, seed {seed})")
    outcomes = []
    for path in candidates:
        evidence = run_smoke(path, SmokeOptions(seed=seed))
        if evidence.created_no_env:
            console.print(f"  {escape(path)}: [dim]skipped: running it created no env[/dim]")
            outcomes.append(SmokeOutcome(path, "skipped", evidence.exit_code, "running it created no env"))
            continue
        passed = evidence.exit_code == 0
        mark = "[green]ok[/green]" if passed else "[red]FAIL[/red]"
        console.print(f"  {mark} {escape(path)}: {escape(one_line(evidence))}")
        outcomes.append(SmokeOutcome(path, "passed" if passed else "failed", evidence.exit_code, one_line(evidence)))
    return outcomes


def _reads_as_env_code(path: str) -> bool:
    try:
        return may_create_env(Path(path).read_text(encoding="utf-8", errors="replace"))
    except OSError:
        return False
