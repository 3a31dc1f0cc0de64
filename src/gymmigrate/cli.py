"""Command line entry point (``gymmigrate``, ``python -m gymmigrate``).

A pre-commit hook runs ``gymmigrate check FILES...`` on every commit, so a check's whole
process is what its user waits for, and importing typer alone takes about a third as long
as importing LibCST. ``main`` therefore reads a plain ``check`` itself
(``check_arguments``): its paths and options, spelled ``--option value``,
``--option=value``, ``-j N`` or ``-jN``, with ``--`` before paths that begin with a dash;
it then calls ``commands.check`` exactly as the typer command does. Everything else
(other commands, ``--help``, ``--version``, an option or spelling it does not know, a
value typer would refuse) goes to the typer application (``typer_app.py``), which parses
and reports usage errors as it always has. ``tests/test_direct_check.py`` runs both ways
on the same arguments and compares stdout, stderr and exit codes byte for byte.

Exit codes are ``commands.py``'s: 0 success, 1 pending changes or findings, 2 errors.
"""

from __future__ import annotations

import errno
import gc
import os
import stat
import sys
from pathlib import Path
from typing import IO, TYPE_CHECKING

if TYPE_CHECKING:
    import typer

# check's options, by how they are given; the names are commands.check's keywords.
_VALUE_OPTIONS = {
    "--report": "report",
    "--jobs": "jobs",
    "-j": "jobs",
    "--output-format": "output_format",
    "--stdin-filename": "stdin_filename",
}
_LIST_OPTIONS = {"--select": "select", "--ignore": "ignore", "--extend-select": "extend_select", "--extend-ignore": "extend_ignore"}
_FLAG_OPTIONS = {"--docs": "docs"}

# typer's answer to an interrupted command (Ctrl-C), which it prints nothing for.
EXIT_INTERRUPTED = 130


def main() -> None:
    _collect_garbage_less_often()
    _print_undecodable_names_as_they_are()
    arguments = check_arguments(sys.argv[1:])
    if arguments is None:
        run_typer()
    else:
        sys.exit(check_directly(arguments))


# A run allocates millions of small objects (ast and LibCST nodes, facts) that live until
# their file is done; with CPython's default first-generation threshold (700) the cycle
# collector ran so often that it took about a tenth of a run's CPU (1.3 s of 10 s over the
# benchmark's Gym set). Collecting every 20,000 allocations took that down by about 10% for
# about 10 MiB more peak memory, flat in the size of the run. Worker processes are forked
# and inherit it.
GC_THRESHOLDS = (20_000, 50, 100)


def _collect_garbage_less_often() -> None:
    gc.set_threshold(*GC_THRESHOLDS)


def run_typer() -> None:
    """The typer application, as ``main`` runs it for everything it does not read itself."""
    from gymmigrate.typer_app import app

    app()


def check_arguments(argv: list[str]) -> dict[str, object] | None:
    """``commands.check``'s keyword arguments for ``argv`` (what follows ``gymmigrate``),
    or None where typer must parse it: not a ``check``, or a ``check`` that typer could
    answer with help or a usage error. Where options repeat, the last one counts, as in typer."""
    if argv[:1] != ["check"] or os.name == "nt" or _completion_asked():
        return None  # on Windows typer expands wildcards in arguments itself
    paths: list[str] = []
    values: dict[str, str] = {}
    lists: dict[str, list[str]] = {}
    flags: dict[str, bool] = {}
    rest = iter(argv[1:])
    for argument in rest:
        if argument == "--":
            paths.extend(rest)
            break
        if argument == "-" or not argument.startswith("-"):
            paths.append(argument)
            continue
        if argument in _FLAG_OPTIONS:
            flags[_FLAG_OPTIONS[argument]] = True
            continue
        if argument.startswith("--"):
            option, given, value = argument.partition("=")
        else:  # a short option takes the rest of its argument as its value: -j4
            option, value = argument[:2], argument[2:]
            given = value
        name = _VALUE_OPTIONS.get(option) or _LIST_OPTIONS.get(option)
        if name is None:
            return None
        if not given:
            following = next(rest, None)
            if following is None or following.startswith("-"):
                return None  # a missing value, or one that looks like an option: typer's to judge
            value = following
        if option in _LIST_OPTIONS:
            lists.setdefault(name, []).append(value)
        else:
            values[name] = value
    if not paths:
        return None
    arguments: dict[str, object] = {"paths": paths, **flags, **lists}
    if "output_format" in values:
        arguments["output_format"] = values["output_format"]
    if "stdin_filename" in values:
        arguments["stdin_filename"] = values["stdin_filename"]
    if "jobs" in values:
        try:
            jobs = int(values["jobs"])  # as typer converts it, then checks --jobs >= 0
        except ValueError:
            return None
        if jobs < 0:
            return None
        arguments["jobs"] = jobs
    if "report" in values:
        if not _typer_takes_report(values["report"]):
            return None
        arguments["report"] = Path(values["report"])
    return arguments


def _typer_takes_report(path: str) -> bool:
    """typer's check of ``--report`` (``dir_okay=False``): an existing path must be a
    readable non-directory."""
    try:
        found = os.stat(path)
    except OSError:
        return True
    return not stat.S_ISDIR(found.st_mode) and os.access(path, os.R_OK)


def _completion_asked() -> bool:
    """typer answers shell completion requests (``_GYMMIGRATE_COMPLETE=...``) itself."""
    return any(name.startswith("_") and name.endswith("_COMPLETE") for name in os.environ)


def check_directly(arguments: dict[str, object]) -> int:
    """``commands.check`` with what typer does around a command: an interrupt exits 130,
    a closed stdout (``| head``) exits 1 without a traceback."""
    from gymmigrate.commands import check

    try:
        return check(**arguments)  # type: ignore[arg-type]
    except KeyboardInterrupt:
        return EXIT_INTERRUPTED
    except OSError as exc:
        if exc.errno != errno.EPIPE:
            raise
        sys.stdout = _FlushIgnoringClosedPipe(sys.stdout)
        sys.stderr = _FlushIgnoringClosedPipe(sys.stderr)
        return 1


class _FlushIgnoringClosedPipe:
    """A stream whose reader has gone: flushing at exit must not print a traceback."""

    def __init__(self, stream: IO[str]) -> None:
        self._stream = stream

    def flush(self) -> None:
        try:
            self._stream.flush()
        except OSError as exc:
            if exc.errno != errno.EPIPE:
                raise

    def __getattr__(self, name: str) -> object:
        return getattr(self._stream, name)


def __getattr__(name: str) -> typer.Typer:
    """``gymmigrate.cli.app``: the typer application, which loads typer when first asked for."""
    if name == "app":
        from gymmigrate.typer_app import app

        return app
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _print_undecodable_names_as_they_are() -> None:
    """A file name that is not valid UTF-8 reaches Python with lone surrogates (PEP 383).
    Where stdout is strict (a UTF-8 locale), printing its diff header or finding would
    raise; surrogateescape writes the name's original bytes back, as ls and git do."""
    for stream in (sys.stdout, sys.stderr):
        if getattr(stream, "errors", None) == "strict" and hasattr(stream, "reconfigure"):
            stream.reconfigure(errors="surrogateescape")


if __name__ == "__main__":
    main()
