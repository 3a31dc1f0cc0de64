"""The human summary of a smoke check, on stderr (colour only on a terminal, as rich decides)."""

from __future__ import annotations

import sys
from typing import TextIO

from gymmigrate.smoke.evidence import Evidence, Outcome

_MARKS = {Outcome.PASSED: "[green]ok[/green]  ", Outcome.FAILED: "[red]FAIL[/red]", Outcome.SKIPPED: "[dim]skip[/dim]"}


def print_evidence(evidence: Evidence, stream: TextIO | None = None) -> None:
    from rich.console import Console
    from rich.markup import escape

    console = Console(file=stream or sys.stderr, highlight=False, soft_wrap=True)
    title = f"[bold]gymmigrate smoke[/bold] {escape(evidence.target)} (seed {evidence.seed})"
    if evidence.load_error is not None:
        console.print(f"{title}: [red]could not run[/red]: {escape(evidence.load_error)}")
        return
    console.print(title)
    run = evidence.run
    if run is not None:
        for env in run.envs:
            stack = " > ".join(env.wrappers)
            console.print(
                f"  env {env.index}: {escape(env.env_id or env.env_class)} [dim]({escape(stack)}; "
                f"first reset seed {env.reset_seed} from {env.seed_source})[/dim]"
            )
            for episode in env.episodes:
                console.print(
                    f"    episode {episode.index + 1}: {episode.length} step{'s' if episode.length != 1 else ''}, "
                    f"return {episode.episode_return:g}, "
                    f"{episode.ending.value}"
                )
        if run.error:
            console.print(f"  [red]the run raised[/red] {escape(run.error)}")
    for check in evidence.checks:
        console.print(f"  {_MARKS[check.outcome]} {check.name}: {escape(check.message)}")
    failed = len(evidence.failed_checks)
    if failed:
        verdict = f"[red]{failed} check{'s' if failed != 1 else ''} failed[/red]"
    else:
        verdict = "[green]the contract holds[/green]"
    console.print(f"  {verdict}")


def one_line(evidence: Evidence) -> str:
    """For ``rewrite --smoke``: the outcome of one script in a sentence."""
    if evidence.load_error is not None:
        return f"could not run: {evidence.load_error}"
    failed = evidence.failed_checks
    if not failed:
        episodes = sum(len(env.episodes) for env in evidence.run.envs) if evidence.run else 0
        return f"passed ({len(evidence.checks)} checks, {episodes} episodes)"
    return f"{len(failed)} check{'s' if len(failed) != 1 else ''} failed: " + "; ".join(
        f"{check.name}: {check.message}" for check in failed
    )
