"""``gymmigrate rules``: the rule table, and one rule's page with its fixture example."""

from __future__ import annotations

import sys
from typing import TextIO

from gymmigrate import rule_docs
from gymmigrate.rules import all_rules


def _console(stream: TextIO | None):
    from rich.console import Console

    return Console(file=stream or sys.stdout, highlight=False, soft_wrap=stream is None and not sys.stdout.isatty())


def print_rules(stream: TextIO | None = None) -> None:
    from rich.table import Table

    table = Table(title="gymmigrate rules", title_justify="left")
    table.add_column("Code", no_wrap=True, style="bold")
    table.add_column("Title")
    table.add_column("Fix", no_wrap=True)
    table.add_column("Summary")
    for rule in all_rules():
        table.add_row(rule.code, rule.title, rule.kind.value, rule.summary)
    _console(stream).print(table)


def print_rule(code: str, stream: TextIO | None = None) -> bool:
    """Print the rule's page and its example; False when no rule has that code."""
    from rich.markdown import Markdown
    from rich.syntax import Syntax

    rule = next((rule for rule in all_rules() if rule.code == code), None)
    if rule is None:
        return False
    doc = rule_docs.load().get(code)
    console = _console(stream)
    console.print(f"[bold]{rule.code}[/bold]: {rule.title} ({rule.kind.value})")
    console.print(rule.summary + "\n")
    if doc is not None and doc.page:
        console.print(Markdown(doc.page.split("\n", 1)[1] if doc.page.startswith("#") else doc.page))
    if doc is not None and doc.before is not None:
        console.print(f"\n[bold]Example[/bold] ({doc.example}), before:")
        console.print(Syntax(doc.before, "python", theme="ansi_dark", background_color="default"))
        if doc.after is not None:
            console.print("after `gymmigrate rewrite`:")
            console.print(Syntax(doc.after, "python", theme="ansi_dark", background_color="default"))
        else:
            console.print("(reported for review; not rewritten)")
    return True
