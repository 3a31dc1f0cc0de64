"""What ``check`` and ``rewrite`` do around the runner: settings from flags and
``[tool.gymmigrate]``, excluded files, and the progress bar.

Paths are grouped by the configuration that applies to them (the nearest
``pyproject.toml`` with a ``[tool.gymmigrate]`` table); each group runs with its own
options, flags winning over the file.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import IO, TYPE_CHECKING

from gymmigrate.config import Config, find_config, forget_configs
from gymmigrate.files import discover
from gymmigrate.options import RewriteOptions
from gymmigrate.process import FileResult, Status
from gymmigrate.rules import all_rules
from gymmigrate.runner import run_files
from gymmigrate.selection import Selection, parse_selectors

if TYPE_CHECKING:  # rich loads only where a progress bar is drawn
    from rich.progress import Progress as RichProgress
    from rich.progress import TaskID

STDIN = "-"


@dataclass(frozen=True)
class Flags:
    """The command line's say; None (or empty) where it said nothing."""

    select: list[str] | None = None
    ignore: list[str] | None = None
    extend_select: list[str] | None = None
    extend_ignore: list[str] | None = None
    seed: int | None = None
    docs: bool | None = None

    def options(self, config: Config) -> RewriteOptions:
        """Flags win over the file; ``extend-*`` from both add up. Raises SelectionError."""
        select = parse_selectors(self.select)
        ignore = parse_selectors(self.ignore)
        selectors = (
            select if select is not None else config.select,
            ignore if ignore is not None else config.ignore,
            [*config.extend_select, *(parse_selectors(self.extend_select) or [])],
            [*config.extend_ignore, *(parse_selectors(self.extend_ignore) or [])],
        )
        seed = self.seed if self.seed is not None else config.seed
        if selectors[0] is None and not any(selectors[1:]):
            # Every rule: no need to load every family to learn their codes.
            return RewriteOptions(seed=seed)
        selection = Selection.from_selectors(*selectors, codes=[rule.code for rule in all_rules()])
        return RewriteOptions(seed=seed, selection=None if selection.every_rule else selection)


@dataclass
class Group:
    arguments: list[str]
    config: Config
    options: RewriteOptions
    docs: bool = False  # also take Markdown/RST pages when walking folders (--docs, config `docs`)


def group_paths(paths: Sequence[str], flags: Flags) -> list[Group]:
    """Arguments by the configuration that applies to them, in the order first seen.
    Raises ConfigError or SelectionError."""
    forget_configs()  # a file edited since the last run in this process (tests, editors) is read again
    groups: dict[Path | None, Group] = {}
    for argument in paths:
        config = find_config(Path(argument))
        group = groups.get(config.path)
        if group is None:
            docs = flags.docs if flags.docs is not None else config.docs
            group = groups[config.path] = Group([], config, flags.options(config), docs)
        group.arguments.append(argument)
    return list(groups.values())


def run_groups(
    groups: list[Group],
    *,
    write: bool,
    want_diff: bool,
    jobs: int,
    lint: bool,
    before_writing: Callable[[list[Path]], None] | None = None,
) -> Iterator[FileResult]:
    """Every file's result (group by group, in order), then one error per bad argument;
    a progress bar on stderr while it runs when stderr is a terminal. ``before_writing``
    gets every file of a run that writes, before the first is processed."""
    planned = []
    errors: list[tuple[str, str]] = []
    for group in groups:
        discovery = discover(group.arguments, docs=group.docs)
        # realpath, not resolve(): a link loop named on the command line is discover's to report.
        named = {os.path.realpath(argument) for argument in group.arguments}
        files = [f for f in discovery.files if os.path.realpath(f) in named or not group.config.excludes(f)]
        planned.append((group, files))
        errors.extend(discovery.errors)
    if write and before_writing is not None:
        before_writing([file for _, files in planned for file in files])
    total = sum(len(files) for _, files in planned)
    with Progress(total) as progress:
        for group, files in planned:
            for result in run_files(files, group.options, write=write, want_diff=want_diff, jobs=jobs, lint=lint):
                progress.advance(result.path)
                yield result
    for path, reason in errors:
        yield FileResult(path, Status.ERROR, error=reason)


class Progress:
    """files done / total, the file just finished and the time so far, on stderr; only
    when stderr is a terminal (a log or a pipe gets nothing extra)."""

    def __init__(self, total: int, stream: IO[str] | None = None) -> None:
        self._stream = stream or sys.stderr
        self._total = total
        self._bar: RichProgress | None = None
        self._task: TaskID | None = None

    def __enter__(self) -> Progress:
        if self._total and getattr(self._stream, "isatty", lambda: False)():
            from rich.console import Console
            from rich.progress import (
                BarColumn,
                MofNCompleteColumn,
                TextColumn,
                TimeElapsedColumn,
            )
            from rich.progress import Progress as RichProgress

            bar = self._bar = RichProgress(
                TextColumn("[bold]gymmigrate[/bold]"),
                BarColumn(),
                MofNCompleteColumn(),
                TimeElapsedColumn(),
                TextColumn("{task.fields[current]}", markup=False),
                console=Console(file=self._stream),
                transient=True,
                # Diffs and findings go to the real stdout, never through the bar's console.
                redirect_stdout=False,
                redirect_stderr=False,
            )
            bar.start()
            self._task = bar.add_task("files", total=self._total, current="")
        return self

    def advance(self, path: str) -> None:
        if self._bar is not None and self._task is not None:  # both set together
            self._bar.update(self._task, advance=1, current=path)

    def __exit__(self, *exc: object) -> None:
        if self._bar is not None:
            self._bar.stop()
