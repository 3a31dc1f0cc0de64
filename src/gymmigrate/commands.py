"""What each command does once its arguments are parsed: plain functions that print and
return the exit code, so that the typer application (``typer_app.py``) and the direct
``check`` parser of ``cli.py`` run the very same code.

Heavy modules (libcst, the rules, gymnasium) are imported inside the commands, so each
command loads only what it uses, and gymnasium is only ever imported by ``smoke``.

Exit codes: 0 success; 1 pending changes (``--diff``), findings (``check``) or a failed
smoke check; 2 usage errors and files (or targets) that could not be processed.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

EXIT_OK = 0
EXIT_PENDING = 1
EXIT_ERROR = 2


class CommandError(Exception):
    """Printed as ``error: MESSAGE`` on stderr; the command then exits with ``EXIT_ERROR``."""


def echo_stderr(message: str) -> None:
    """One line on stderr, written as typer's ``echo`` writes it (ANSI codes dropped when
    stderr is not a terminal), so both ways into a command print the same bytes."""
    line = f"{message}\n"
    if "\033[" in line and not sys.stderr.isatty():
        import re

        line = re.sub(r"\033\[[;?0-9]*[a-zA-Z]", "", line)
    sys.stderr.write(line)
    sys.stderr.flush()


def check(
    paths: list[str],
    *,
    report: Path | None = None,
    jobs: int = 0,
    output_format: str = "text",
    docs: bool = False,
    select: list[str] | None = None,
    ignore: list[str] | None = None,
    extend_select: list[str] | None = None,
    extend_ignore: list[str] | None = None,
    stdin_filename: str | None = None,
) -> int:
    """``gymmigrate check``: list every legacy Gym site; write nothing."""
    from gymmigrate.formats import FORMATS
    from gymmigrate.process import Status
    from gymmigrate.report import decide_once, print_summary, write_findings
    from gymmigrate.workflow import Flags, run_groups

    try:
        output_format = output_format.lower()
        if output_format not in FORMATS:
            raise CommandError(f"--output-format must be one of {', '.join(FORMATS)}, not {output_format!r}")
        flags = Flags(select, ignore, extend_select, extend_ignore, docs=docs or None)
        if paths == ["-"]:
            return _stdin(flags, stdin_filename, lint=True, output_format=output_format, report=report)
        results = decide_once(list(run_groups(_groups(paths, flags), write=False, want_diff=False, jobs=jobs, lint=True)))
        write_findings(output_format, results, sys.stdout)
        print_summary(results, wrote=False)
        if report is not None:
            _write_report(report, results, wrote=False)
    except CommandError as exc:
        echo_stderr(f"error: {exc}")
        return EXIT_ERROR
    if any(r.status is Status.ERROR for r in results):
        return EXIT_ERROR
    return EXIT_PENDING if any(r.findings for r in results) else EXIT_OK


def rewrite(
    paths: list[str],
    *,
    diff: bool = False,
    seed: int | None = None,
    report: Path | None = None,
    jobs: int = 0,
    docs: bool = False,
    smoke: bool = False,
    select: list[str] | None = None,
    ignore: list[str] | None = None,
    extend_select: list[str] | None = None,
    extend_ignore: list[str] | None = None,
    stdin_filename: str | None = None,
) -> int:
    """``gymmigrate rewrite``: rewrite in place, or print the diff."""
    if smoke and diff:
        echo_stderr("error: --smoke runs the rewritten files, so it cannot be combined with --diff")
        return EXIT_ERROR
    from gymmigrate.process import Status
    from gymmigrate.report import decide_once, print_diff, print_summary
    from gymmigrate.workflow import Flags, run_groups

    try:
        flags = Flags(select, ignore, extend_select, extend_ignore, seed=seed, docs=docs or None)
        if paths == ["-"]:
            if smoke:
                raise CommandError("--smoke runs the rewritten files, so it cannot be combined with the path - (stdin)")
            return _stdin(flags, stdin_filename, lint=False, diff=diff, report=report)
        groups = _groups(paths, flags)
        seed = next((group.options.seed for group in groups if group.options.seed is not None), seed)
        results = []
        for result in run_groups(
            groups, write=not diff, want_diff=diff, jobs=jobs, lint=False, before_writing=_remove_abandoned_temporaries
        ):
            if result.diff:
                print_diff(result.diff)
            results.append(result)
        results = decide_once(results)
        print_summary(results, wrote=not diff)
        smoked = _smoke_rewritten(results, seed or 0) if smoke else None
        if report is not None:
            _write_report(report, results, wrote=not diff, smoke=smoked)
    except CommandError as exc:
        echo_stderr(f"error: {exc}")
        return EXIT_ERROR
    smoke_failed = any(outcome.outcome == "failed" for outcome in smoked or ())
    if any(r.status is Status.ERROR for r in results):
        return EXIT_ERROR
    if diff and any(r.status is Status.CHANGED for r in results):
        return EXIT_PENDING
    return EXIT_PENDING if smoke_failed else EXIT_OK


def rules(code: str | None = None) -> int:
    """``gymmigrate rules [CODE]``: every rule, or one explained."""
    from gymmigrate.rules_listing import print_rule, print_rules

    if code is None:
        print_rules()
        return EXIT_OK
    if not print_rule(code.upper()):
        echo_stderr(f"error: unknown rule {code!r} (see `gymmigrate rules`)")
        return EXIT_ERROR
    return EXIT_OK


def smoke(
    target: str,
    *,
    script_args: list[str] | None = None,
    seed: int = 0,
    episodes: int = 3,
    max_steps: int = 1000,
    timeout: float = 60.0,
    evidence_file: Path | None = None,
    determinism: bool = True,
) -> int:
    """``gymmigrate smoke TARGET``: a bounded, seeded episode loop against the API contract."""
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
            echo_stderr(f"error: cannot write the evidence {evidence_file}: {exc.strerror or exc}")
            return EXIT_ERROR
    return evidence.exit_code


def _write_report(path: Path, results: list, *, wrote: bool, smoke: list | None = None) -> None:
    from gymmigrate.report import write_json_report

    try:
        write_json_report(path, results, wrote=wrote, smoke=smoke)
    except OSError as exc:
        raise CommandError(f"cannot write the report {path}: {exc.strerror or exc}") from None


def _remove_abandoned_temporaries(files: list[Path]) -> None:
    """A killed run can leave a temporary file next to the file it was writing; this
    run is about to write there, so it tidies up (check and --diff write nothing)."""
    from gymmigrate.writes import remove_abandoned_temporaries

    folders = sorted({Path(os.path.realpath(path)).parent for path in files})
    removed = remove_abandoned_temporaries(folders)
    if removed:
        echo_stderr(f"removed {len(removed)} temporary file(s) left by an interrupted gymmigrate run")


def _groups(paths: list[str], flags: object) -> list:
    """Paths grouped by their [tool.gymmigrate]; a bad configuration or rule code is a usage error."""
    from gymmigrate.config import ConfigError
    from gymmigrate.selection import SelectionError
    from gymmigrate.workflow import group_paths

    if "-" in paths:
        raise CommandError("the path - (stdin) cannot be combined with other paths")
    try:
        return group_paths(paths, flags)  # type: ignore[arg-type]
    except (ConfigError, SelectionError) as exc:
        raise CommandError(str(exc)) from None


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


def _smoke_rewritten(results: list, seed: int) -> list:
    """Smoke-check each written file that creates an env; the outcomes."""
    from gymmigrate.smoke.rewritten import smoke_rewritten

    # Only Python scripts run: a notebook or a documentation page is not a script.
    return smoke_rewritten([r.path for r in results if r.written and r.path.endswith(".py")], seed)
