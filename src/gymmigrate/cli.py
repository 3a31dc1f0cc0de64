"""Command line: argument parsing and exit codes only.

Heavy modules (libcst, the rules, gymnasium) are imported inside the commands, so
``gymmigrate --version`` and ``--help`` start fast and gymnasium is only ever imported
by ``smoke``.

Exit codes: 0 success; 1 pending changes (``--diff``), findings (``check``) or a failed
smoke check; 2 usage errors and files (or targets) that could not be processed.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Annotated, NoReturn, Optional

import typer

from gymmigrate import __version__

app = typer.Typer(
    name="gymmigrate",
    help="Migrate legacy OpenAI Gym code to the Gymnasium 1.x API.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)

EXIT_OK = 0
EXIT_PENDING = 1
EXIT_ERROR = 2


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
    if smoke and diff:
        typer.echo("error: --smoke runs the rewritten files, so it cannot be combined with --diff", err=True)
        raise typer.Exit(EXIT_ERROR)
    from gymmigrate.process import Status
    from gymmigrate.report import print_diff, print_summary
    from gymmigrate.workflow import Flags, run_groups

    flags = Flags(select, ignore, extend_select, extend_ignore, seed=seed, docs=docs or None)
    if paths == ["-"]:
        if smoke:
            _usage_error("--smoke runs the rewritten files, so it cannot be combined with the path - (stdin)")
        raise typer.Exit(_stdin(flags, stdin_filename, lint=False, diff=diff, report=report))
    groups = _groups(paths, flags)
    seed = next((group.options.seed for group in groups if group.options.seed is not None), seed)
    results = []
    for result in run_groups(
        groups, write=not diff, want_diff=diff, jobs=jobs, lint=False, before_writing=_remove_abandoned_temporaries
    ):
        if result.diff:
            print_diff(result.diff)
        results.append(result)
    print_summary(results, wrote=not diff)
    smoked = _smoke_rewritten(results, seed or 0) if smoke else None
    if report is not None:
        _write_report(report, results, wrote=not diff, smoke=smoked)
    smoke_failed = any(outcome.outcome == "failed" for outcome in smoked or ())
    if any(r.status is Status.ERROR for r in results):
        raise typer.Exit(EXIT_ERROR)
    if diff and any(r.status is Status.CHANGED for r in results):
        raise typer.Exit(EXIT_PENDING)
    raise typer.Exit(EXIT_PENDING if smoke_failed else EXIT_OK)


def _write_report(path: Path, results: list, *, wrote: bool, smoke: list | None = None) -> None:
    from gymmigrate.report import write_json_report

    try:
        write_json_report(path, results, wrote=wrote, smoke=smoke)
    except OSError as exc:
        typer.echo(f"error: cannot write the report {path}: {exc.strerror or exc}", err=True)
        raise typer.Exit(EXIT_ERROR) from None


def _remove_abandoned_temporaries(files: list[Path]) -> None:
    """A killed run can leave a temporary file next to the file it was writing; this
    run is about to write there, so it tidies up (check and --diff write nothing)."""
    from gymmigrate.writes import remove_abandoned_temporaries

    folders = sorted({Path(os.path.realpath(path)).parent for path in files})
    removed = remove_abandoned_temporaries(folders)
    if removed:
        typer.echo(f"removed {len(removed)} temporary file(s) left by an interrupted gymmigrate run", err=True)


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
    from gymmigrate.formats import FORMATS
    from gymmigrate.process import Status
    from gymmigrate.report import print_summary, write_findings
    from gymmigrate.workflow import Flags, run_groups

    output_format = output_format.lower()
    if output_format not in FORMATS:
        typer.echo(f"error: --output-format must be one of {', '.join(FORMATS)}, not {output_format!r}", err=True)
        raise typer.Exit(EXIT_ERROR)
    flags = Flags(select, ignore, extend_select, extend_ignore, docs=docs or None)
    if paths == ["-"]:
        raise typer.Exit(_stdin(flags, stdin_filename, lint=True, output_format=output_format, report=report))
    results = list(run_groups(_groups(paths, flags), write=False, want_diff=False, jobs=jobs, lint=True))
    write_findings(output_format, results, sys.stdout)
    print_summary(results, wrote=False)
    if report is not None:
        _write_report(report, results, wrote=False)
    if any(r.status is Status.ERROR for r in results):
        raise typer.Exit(EXIT_ERROR)
    raise typer.Exit(EXIT_PENDING if any(r.findings for r in results) else EXIT_OK)


def _groups(paths: list[str], flags: object) -> list:
    """Paths grouped by their [tool.gymmigrate]; a bad configuration or rule code is a usage error."""
    from gymmigrate.config import ConfigError
    from gymmigrate.selection import SelectionError
    from gymmigrate.workflow import group_paths

    if "-" in paths:
        _usage_error("the path - (stdin) cannot be combined with other paths")
    try:
        return group_paths(paths, flags)  # type: ignore[arg-type]
    except (ConfigError, SelectionError) as exc:
        _usage_error(str(exc))


def _usage_error(message: str) -> NoReturn:
    typer.echo(f"error: {message}", err=True)
    raise typer.Exit(EXIT_ERROR)


def _stdin(
    flags: object,
    filename: str | None,
    *,
    lint: bool,
    diff: bool = False,
    output_format: str = "text",
    report: Path | None = None,
) -> int:
    """check - / rewrite -: one file from stdin, the result (or findings) on stdout."""
    from gymmigrate.engine import Transformed, unified_diff
    from gymmigrate.process import Status, process_stdin
    from gymmigrate.report import print_summary, write_findings
    from gymmigrate.source_text import decode

    group = _groups([filename or "."], flags)[0]
    source = sys.stdin.buffer.read()
    result, output = process_stdin(source, filename, group.options, lint=lint)
    if lint:
        write_findings(output_format, [result], sys.stdout)
    elif diff:
        if output != source:
            sys.stdout.write(unified_diff(result.path, Transformed(source, output, decode(source)[1])))
    else:
        sys.stdout.buffer.write(output)
    sys.stdout.flush()
    print_summary([result], wrote=False)
    if report is not None:
        _write_report(report, [result], wrote=False)
    if result.status is Status.ERROR:
        return EXIT_ERROR
    if lint:
        return EXIT_PENDING if result.findings else EXIT_OK
    return EXIT_PENDING if diff and result.status is Status.CHANGED else EXIT_OK


@app.command(name="rules")
def rules_command(
    code: Annotated[
        Optional[str], typer.Argument(help="A rule code (GM301): show its full explanation and example.", show_default=False)
    ] = None,
) -> None:
    """List every rule (code, title, fix kind, summary), or explain one with its before/after example."""
    from gymmigrate.rules_listing import print_rule, print_rules

    if code is None:
        print_rules()
        raise typer.Exit(EXIT_OK)
    if not print_rule(code.upper()):
        _usage_error(f"unknown rule {code!r} (see `gymmigrate rules`)")
    raise typer.Exit(EXIT_OK)


def _smoke_rewritten(results: list, seed: int) -> list:
    """Smoke-check each written file that creates an env; True if any failed or could not run."""
    from gymmigrate.smoke.rewritten import smoke_rewritten

    # Only Python scripts run: a notebook or a documentation page is not a script.
    return smoke_rewritten([r.path for r in results if r.written and r.path.endswith(".py")], seed)


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
    from gymmigrate.smoke.runner import SmokeOptions, run_smoke
    from gymmigrate.smoke.summary import print_evidence

    options = SmokeOptions(
        seed=seed,
        episodes=episodes,
        max_steps=max_steps,
        timeout=timeout,
        determinism=determinism,
        script_args=tuple(script_args or ()),
    )
    evidence = run_smoke(target, options)
    print_evidence(evidence)
    if evidence_file is not None:
        try:
            evidence.write(evidence_file)
        except OSError as exc:
            typer.echo(f"error: cannot write the evidence {evidence_file}: {exc.strerror or exc}", err=True)
            raise typer.Exit(EXIT_ERROR) from None
    raise typer.Exit(evidence.exit_code)


def main() -> None:
    _print_undecodable_names_as_they_are()
    app()


def _print_undecodable_names_as_they_are() -> None:
    """A file name that is not valid UTF-8 reaches Python with lone surrogates (PEP 383).
    Where stdout is strict (a UTF-8 locale), printing its diff header or finding would
    raise; surrogateescape writes the name's original bytes back, as ls and git do."""
    for stream in (sys.stdout, sys.stderr):
        if getattr(stream, "errors", None) == "strict" and hasattr(stream, "reconfigure"):
            stream.reconfigure(errors="surrogateescape")


if __name__ == "__main__":
    main()
