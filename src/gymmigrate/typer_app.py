"""The typer application: every command's arguments, options and help.

Each command hands its parsed arguments to the function of the same name in
``commands.py`` and exits with the code it returns. ``cli.main`` runs this application
for everything except the plain ``check`` runs it parses itself (see ``cli.py``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Optional

import typer

from gymmigrate import __version__, commands
from gymmigrate.commands import EXIT_OK

app = typer.Typer(
    name="gymmigrate",
    help="Migrate legacy OpenAI Gym code to the Gymnasium 1.x API.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


def _version(value: bool) -> None:
    if value:
        typer.echo(f"gymmigrate {__version__}")
        raise typer.Exit(EXIT_OK)


@app.callback()
def _root(
    version: Annotated[
        bool, typer.Option("--version", callback=_version, is_eager=True, help="Show the version and exit.")
    ] = False,
) -> None:
    """Migrate legacy OpenAI Gym code to the Gymnasium 1.x API."""


PathsArgument = Annotated[
    list[str],
    typer.Argument(help="Files or directories (searched recursively for *.py and *.ipynb).", show_default=False),
]
DocsOption = Annotated[
    bool,
    typer.Option("--docs", help="When searching directories, also take Markdown and reStructuredText pages (*.md, *.rst)."),
]
ReportOption = Annotated[
    Optional[Path],
    typer.Option("--report", help="Write every change and review item as JSON to this file.", dir_okay=False),
]
JobsOption = Annotated[int, typer.Option("--jobs", "-j", min=0, help="Worker processes (0: one per core).")]
_CODES = "rule codes or prefixes (GM301, GM3, GM), repeated or comma-separated"
SelectOption = Annotated[
    Optional[list[str]], typer.Option("--select", help=f"Apply only these {_CODES} (default: every rule).")
]
IgnoreOption = Annotated[Optional[list[str]], typer.Option("--ignore", help=f"Leave out these {_CODES}.")]
ExtendSelectOption = Annotated[
    Optional[list[str]], typer.Option("--extend-select", help=f"Also apply these {_CODES}.")
]
ExtendIgnoreOption = Annotated[
    Optional[list[str]], typer.Option("--extend-ignore", help=f"Also leave out these {_CODES}.")
]
StdinFilenameOption = Annotated[
    Optional[str],
    typer.Option("--stdin-filename", help="With the path -, the file name to show and to look up the configuration from."),
]


@app.command()
def rewrite(
    paths: PathsArgument,
    diff: Annotated[
        bool, typer.Option("--diff", help="Dry run: print a unified diff to stdout and write nothing.")
    ] = False,
    seed: Annotated[
        Optional[int],
        typer.Option("--seed", min=0, help="Seed the first reset of envs that were never seeded."),
    ] = None,
    report: ReportOption = None,
    jobs: JobsOption = 0,
    docs: DocsOption = False,
    smoke: Annotated[
        bool,
        typer.Option(
            "--smoke",
            help="After rewriting, smoke-check (seed --seed or 0) each rewritten script that creates an env.",
        ),
    ] = False,
    select: SelectOption = None,
    ignore: IgnoreOption = None,
    extend_select: ExtendSelectOption = None,
    extend_ignore: ExtendIgnoreOption = None,
    stdin_filename: StdinFilenameOption = None,
) -> None:
    """Rewrite legacy Gym code in place (or show the diff with --diff).

    With the path -, read one file from stdin and write it, rewritten, to stdout.
    """
    raise typer.Exit(
        commands.rewrite(
            paths,
            diff=diff,
            seed=seed,
            report=report,
            jobs=jobs,
            docs=docs,
            smoke=smoke,
            select=select,
            ignore=ignore,
            extend_select=extend_select,
            extend_ignore=extend_ignore,
            stdin_filename=stdin_filename,
        )
    )


@app.command()
def check(
    paths: PathsArgument,
    report: ReportOption = None,
    jobs: JobsOption = 0,
    output_format: Annotated[
        str,
        typer.Option(
            "--output-format",
            help="How findings are printed to stdout: text (path:line:col: RULE \\[kind] message), json, "
            "sarif (SARIF 2.1.0, for code scanning) or github (workflow annotations).",
            case_sensitive=False,
        ),
    ] = "text",
    docs: DocsOption = False,
    select: SelectOption = None,
    ignore: IgnoreOption = None,
    extend_select: ExtendSelectOption = None,
    extend_ignore: ExtendIgnoreOption = None,
    stdin_filename: StdinFilenameOption = None,
) -> None:
    """Lint mode: list every legacy Gym site (what rewrite would change or asks you to review); write nothing.

    Each finding is printed to stdout as `path:line:column: RULE \\[kind] message` (or in
    --output-format). With the path -, check one file read from stdin.
    Exit codes: 0 nothing found, 1 findings, 2 files that could not be processed.
    """
    raise typer.Exit(
        commands.check(
            paths,
            report=report,
            jobs=jobs,
            output_format=output_format,
            docs=docs,
            select=select,
            ignore=ignore,
            extend_select=extend_select,
            extend_ignore=extend_ignore,
            stdin_filename=stdin_filename,
        )
    )


@app.command(name="rules")
def rules_command(
    code: Annotated[
        Optional[str], typer.Argument(help="A rule code (GM301): show its full explanation and example.", show_default=False)
    ] = None,
) -> None:
    """List every rule (code, title, fix kind, summary), or explain one with its before/after example."""
    raise typer.Exit(commands.rules(code))


@app.command(name="smoke")
def smoke_command(
    target: Annotated[
        str,
        typer.Argument(
            help="A registered env id (CartPole-v1), a class (path/to/file.py:ClassName or package.module:ClassName) "
            "or a script (path/to/train.py).",
            show_default=False,
        ),
    ],
    script_args: Annotated[
        Optional[list[str]],
        typer.Argument(help="Arguments passed to the script (put them after --).", show_default=False),
    ] = None,
    seed: Annotated[
        int, typer.Option("--seed", min=0, help="Seed of the runs (a second run repeats it, a third uses seed + 1).")
    ] = 0,
    episodes: Annotated[int, typer.Option("--episodes", min=1, help="Stop once this many episodes have ended.")] = 3,
    max_steps: Annotated[
        int, typer.Option("--max-steps", min=1, help="Stop once this many steps have run (all envs together).")
    ] = 1000,
    timeout: Annotated[
        float, typer.Option("--timeout", min=0.1, help="Stop a run (kill a script) after this many seconds.")
    ] = 60.0,
    evidence_file: Annotated[
        Optional[Path],
        typer.Option("--evidence", help="Write the evidence as JSON to this file.", dir_okay=False),
    ] = None,
    determinism: Annotated[
        bool,
        typer.Option("--determinism/--no-determinism", help="Repeat the run with the same seed and with seed + 1."),
    ] = True,
) -> None:
    """Run a short, bounded, seeded episode loop and check the Gymnasium API contract.

    Exit codes: 0 the contract holds, 1 a check failed, 2 the target could not be loaded or run.
    """
    raise typer.Exit(
        commands.smoke(
            target,
            script_args=script_args,
            seed=seed,
            episodes=episodes,
            max_steps=max_steps,
            timeout=timeout,
            evidence_file=evidence_file,
            determinism=determinism,
        )
    )
