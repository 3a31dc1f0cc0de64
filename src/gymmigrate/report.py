"""Show results: diffs on stdout, the summary and review list on stderr, JSON reports.

stdout carries data (diffs), stderr carries the human summary; colour only on a
terminal (rich decides, and honours NO_COLOR / FORCE_COLOR).
"""

from __future__ import annotations

import os
import re
import sys
from collections import Counter, defaultdict
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, TextIO

from gymmigrate import __version__
from gymmigrate.findings import Finding, Tier, deciding_module
from gymmigrate.formats import findings_json, write_github, write_json, write_sarif
from gymmigrate.process import FileResult, Status
from gymmigrate.rules import all_rules

if TYPE_CHECKING:
    from rich.table import Table


def print_diff(diff: str, stream: TextIO | None = None) -> None:
    stream = stream or sys.stdout
    if not stream.isatty():
        stream.write(diff)
        stream.flush()
        return
    from rich.console import Console
    from rich.text import Text

    console = Console(file=stream, highlight=False, soft_wrap=True)
    for line in diff.splitlines():
        style = None
        if line.startswith(("+++", "---")):
            style = "bold"
        elif line.startswith("+"):
            style = "green"
        elif line.startswith("-"):
            style = "red"
        elif line.startswith("@@"):
            style = "cyan"
        console.print(Text(line, style=style or ""))


def changes_per_rule(results: Sequence[FileResult]) -> Counter[str]:
    """How many rewrites each rule made (review-only findings are not changes)."""
    return Counter(f.rule for r in results for f in r.findings if f.is_change)


def print_findings(results: Sequence[FileResult], stream: TextIO | None = None) -> None:
    """One line per finding, in the compiler style editors and CI annotators read."""
    stream = stream or sys.stdout
    for result in results:
        for finding in result.findings:
            where = location(result.path, finding, finding.line)
            stream.write(f"{where}:{finding.column + 1}: {finding.rule} [{finding.kind.value}] {finding.message}\n")
    stream.flush()


def location(path: str, finding: Finding, line: int) -> str:
    """``path:line``, or ``path:cell N:line L`` in a notebook (N counts every cell from 1,
    as a reader counts them; the JSON report's ``cell`` is the 0-based index)."""
    if finding.cell is None:
        return f"{path}:{line}"
    return f"{path}:cell {finding.cell + 1}:line {line}"


_SAME_IN_FILE = re.compile(r" \(the same question at [^()]*\)$")
# At most this many other places are named in the item that asks a run-wide decision.
_PLACES_NAMED = 5


def decide_once(results: Sequence[FileResult]) -> list[FileResult]:
    """One decision, one review item, across the files of a run too.

    An item of a rule whose decision belongs to the run, not to its file
    (``Rule.once_per_run``: a library with no Gymnasium release, an env id's new version),
    or of a question the run shares (``Finding.question``: where a base class's ``self.env``
    comes from, asked by each module of its subclasses), is asked once: where several files hold the same item (same rule, same message), the
    first file's item stays in the review list and names the other places; the others
    become notes pointing at it, so every place is still listed (``check``, the JSON
    report) and the count of review items counts decisions. Within a file the rules
    already ask each question once (``Plan.ask_once``)."""
    groups: dict[tuple[str, str], list[tuple[int, int]]] = defaultdict(list)
    for r, result in enumerate(results):
        for f, finding in enumerate(result.findings):
            if not finding.needs_review:
                continue
            if finding.question is not None:
                # a question of the run (where `self.env` of a base class of the run comes
                # from): every module of its subclasses asks it, whatever the rule
                groups[("", finding.question)].append((r, f))
            else:
                # the file's own "(the same question at line 43)" does not make it another decision
                groups[(finding.rule, _SAME_IN_FILE.sub("", finding.message))].append((r, f))
    repeated = {key: places for key, places in groups.items() if len({r for r, _ in places}) > 1}
    if not repeated:
        return list(results)  # without loading every rule family (`check` of one file stays lean)
    once = {rule.code for rule in all_rules() if rule.once_per_run}
    findings = [list(result.findings) for result in results]
    for (rule, question), places in repeated.items():
        if rule and rule not in once:
            continue
        # a run's question is asked in the module that decides it (the base class's), if
        # that module asks it; else, like every other decision, in the first file by path
        home = deciding_module(question) if not rule else ""
        places.sort(
            key=lambda place: (
                os.path.realpath(results[place[0]].path) != home,
                results[place[0]].path,
                findings[place[0]][place[1]].cell or 0,
                findings[place[0]][place[1]].line,
            )
        )
        (r0, f0), others = places[0], places[1:]
        # Each place named twice over: in the sources (the message: `check`, the JSON) and in
        # the files as the run leaves them (``message_after``: the review list of a rewrite).
        first = findings[r0][f0]
        here, here_after = location(results[r0].path, first, first.line), _location_as_left(results[r0], first)
        named = [location(results[r].path, findings[r][f], findings[r][f].line) for r, f in others]
        named_after = [_location_as_left(results[r], findings[r][f]) for r, f in others]
        findings[r0][f0] = _with_suffix(first, _other_places(named), _other_places(named_after))
        for r, f in others:
            findings[r][f] = replace(
                _with_suffix(findings[r][f], f" (decided once, at {here})", f" (decided once, at {here_after})"), tier=Tier.NOTE
            )
    return [replace(result, findings=tuple(found)) for result, found in zip(results, findings)]


def _other_places(named: list[str]) -> str:
    more = f" and {len(named) - _PLACES_NAMED} more" if len(named) > _PLACES_NAMED else ""
    where = "place" if len(named) == 1 else "places"
    return f" (the same decision at {len(named)} other {where}: {', '.join(named[:_PLACES_NAMED])}{more})"


def _with_suffix(finding: Finding, suffix: str, suffix_after: str) -> Finding:
    """``finding`` naming other files' places: ``suffix`` in their sources, ``suffix_after``
    in the files as the run leaves them."""
    after = finding.message_after if finding.message_after is not None else finding.message
    return replace(finding, message=finding.message + suffix, message_after=after + suffix_after)


def _location_as_left(result: FileResult, finding: Finding) -> str:
    """Where a person finds ``finding`` once the run is over: in the rewritten file where it
    was written, else in the source (which is then what is on disk)."""
    return location(result.path, finding, finding.line_after if result.written and finding.line_after else finding.line)


def _as_read(result: FileResult, finding: Finding, *, wrote: bool) -> tuple[int, str]:
    """The line and message of a review item in the version of the file a person opens:
    after a rewrite, the file as written (both the item's line and every line its message
    names, of its file and of others: ``Finding.message_after``); else the source."""
    if wrote and (result.written or finding.line_after is None):
        # a file left unchanged reads the same in both versions; its message may still name
        # places in files that were rewritten (``decide_once``)
        line = finding.line_after or finding.line
        return line, finding.message_after if finding.message_after is not None else finding.message
    return finding.line, finding.message


# One line of the summary: pieces of text, each with a rich style ("" for none).
Line = list[tuple[str, str]]


def print_summary(results: Sequence[FileResult], *, wrote: bool, stream: TextIO | None = None) -> None:
    """The closing summary and the review list; rich (colour, the table) only on a
    terminal, plain lines for logs and pipes."""
    stream = stream or sys.stderr
    changed = [r for r in results if r.status is Status.CHANGED]
    errors = [r for r in results if r.status is Status.ERROR]
    review = [(r, f) for r in results for f in r.findings if f.needs_review]
    notes = sum(not f.needs_review for r in results for f in r.findings)
    per_rule = changes_per_rule(results)

    verb = "rewrote" if wrote else "would rewrite"
    head: Line = [("gymmigrate", "bold"), (f" {verb} {len(changed)} of {len(results)} file{'s' if len(results) != 1 else ''}", "")]
    if errors:
        head += [(", ", ""), (f"{len(errors)} could not be processed", "red")]
    lines: list[Line] = []
    if review:
        lines.append([("\n", ""), (f"Review ({len(review)})", "bold yellow"), (": places where a person must decide", "")])
        for result, finding in review:
            line, message = _as_read(result, finding, wrote=wrote)
            tag = "rewritten" if finding.is_change else "not rewritten"
            lines.append([(f"  {location(result.path, finding, line)}: ", ""), (finding.rule, "bold"), (f" ({tag}) {message}", "")])
    if notes:
        lines.append([(f"{notes} note{'s' if notes != 1 else ''} on rewrites already applied (listed by `check` and in --report)", "")])
    for result in errors:
        lines.append([("error", "red"), (f": {result.path}: {result.error or 'unknown error'}", "")])

    if not _is_terminal(stream):
        per_rule_line: list[Line] = []
        if per_rule:
            per_rule_line = [[("Changes per rule: " + ", ".join(f"{rule} x{count}" for rule, count in sorted(per_rule.items())), "")]]
        for pieces in [head, *per_rule_line, *lines]:
            stream.write("".join(text for text, _ in pieces) + "\n")
        stream.flush()
        return
    from rich.console import Console
    from rich.text import Text

    console = Console(file=stream, highlight=False, soft_wrap=True)
    console.print(Text.assemble(*head))
    console.print(summary_table(results, per_rule, len(review), wrote=wrote))
    for pieces in lines:
        console.print(Text.assemble(*pieces))


def summary_table(results: Sequence[FileResult], per_rule: Counter[str], review: int, *, wrote: bool) -> Table:
    """The closing summary as a table, for a person at a terminal (logs keep the one-line form)."""
    from rich.table import Table

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


def _is_terminal(stream: TextIO) -> bool:
    """What rich would decide: a TTY, unless FORCE_COLOR / TTY_COMPATIBLE say otherwise."""
    if os.environ.get("FORCE_COLOR") or os.environ.get("TTY_COMPATIBLE") == "1":
        return True
    isatty = getattr(stream, "isatty", None)
    return bool(isatty and isatty())


def report_json(results: Sequence[FileResult], *, wrote: bool, smoke: Sequence[object] | None = None) -> dict[str, object]:
    files = []
    for result in results:
        if result.status is Status.SKIPPED and not result.findings:
            continue
        files.append(
            {
                "path": result.path,
                "status": result.status.value,
                "written": result.written,
                "error": result.error,
                # Each finding once, in its tier (every record also says "tier").
                "review": [f.to_json() for f in result.findings if f.needs_review],
                "notes": [f.to_json() for f in result.findings if not f.needs_review],
            }
        )
    per_rule = changes_per_rule(results)
    return {
        "tool": "gymmigrate",
        "version": __version__,
        "mode": "rewrite" if wrote else "dry-run",
        "summary": {
            "files_seen": len(results),
            "files_changed": sum(r.status is Status.CHANGED for r in results),
            "files_with_errors": sum(r.status is Status.ERROR for r in results),
            "changes_per_rule": dict(sorted(per_rule.items())),
            "review_items": sum(f.needs_review for r in results for f in r.findings),
            "notes": sum(not f.needs_review for r in results for f in r.findings),
        },
        "files": files,
        # Every finding in the shape of `check --output-format json` (path, every field, fix_available).
        "findings": findings_json(results),
        # Present only with `rewrite --smoke`: one record per rewritten script checked.
        **({"smoke": [outcome.to_json() for outcome in smoke]} if smoke is not None else {}),  # type: ignore[attr-defined]
    }


def write_json_report(
    path: Path, results: Sequence[FileResult], *, wrote: bool, smoke: Sequence[object] | None = None
) -> None:
    import json  # only a run with --report writes one

    path.write_text(json.dumps(report_json(results, wrote=wrote, smoke=smoke), indent=2) + "\n", encoding="utf-8")


def write_findings(output_format: str, results: Sequence[FileResult], stream: TextIO) -> None:
    """``check``'s findings on ``stream`` in ``output_format`` (``formats.FORMATS``)."""
    if output_format == "json":
        write_json(results, stream)
    elif output_format == "sarif":
        write_sarif(results, stream)
    elif output_format == "github":
        write_github(results, stream)
    else:
        print_findings(results, stream)
    stream.flush()
