"""Run the engine over many files, on every core when it pays off.

Each file is independent and ``process_file`` returns a small picklable ``FileResult``,
so worker processes can do the work; results come back in the order the files were
given so diffs and summaries are stable from run to run.

A worker process can die under a file: a crash in native code (LibCST's parser is
native), or the kernel's out-of-memory killer. ``concurrent.futures`` cannot survive
that: a dead worker fails every unfinished task with ``BrokenProcessPool``, including
results already sent but not yet read, so it cannot tell which file was the cause nor
keep the others' results. So this module keeps its own small pool: each worker has one
file at a time and its own pipe, the parent waits on the pipes and on the processes
together, and a worker that dies costs exactly the file it held. A fresh worker takes
its place and the run goes on.
"""

from __future__ import annotations

import os
import re
import time
from collections import deque
from collections.abc import Callable, Generator, Iterable, Iterator, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, overload

from gymmigrate.dependencies import kind_of
from gymmigrate.dependencies.plugins import PluginEntry, plugin_entries
from gymmigrate.facts.creator_tables import writes_into_import
from gymmigrate.facts.module_summary import ModuleSummary
from gymmigrate.facts.project import ProjectFacts
from gymmigrate.facts.summaries import summarize, summarize_masks
from gymmigrate.findings import Finding, FixKind
from gymmigrate.options import RewriteOptions
from gymmigrate.process import (
    FileResult,
    PendingWrite,
    Status,
    migrate_file,
    process_file,
)
from gymmigrate.safety import MAX_SOURCE_BYTES, Refused, read_source, screen
from gymmigrate.source_text import TransformError, decode, may_hold_gym_code
from gymmigrate.sources import adapter_for
from gymmigrate.sources.programs import join as join_segments

if TYPE_CHECKING:
    from multiprocessing.connection import Connection
    from multiprocessing.process import BaseProcess

# The finding an importer of a module the run leaves as it is gets (like GM001, a
# finding of the run itself, not a rule of the table).
BLOCKED_BY_MODULE = "GM002"

# The files of a run that hold a Python program of their own: modules and notebooks.
PROGRAM_SUFFIXES = (".py", ".pyw", ".ipynb")

# Below this many files a pool costs more (worker start-up, imports) than it saves.
PARALLEL_THRESHOLD = 16

WORKER_DIED = "the worker process died while processing this file (a crash in native code, or killed by the system)"

# How often an orphaned worker checks whether the run that started it is gone.
_PARENT_POLL_SECONDS = 0.2


def default_jobs() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


def run_files(
    paths: Sequence[Path],
    options: RewriteOptions,
    *,
    write: bool,
    want_diff: bool,
    jobs: int | None = None,
    lint: bool = False,
) -> Iterator[FileResult]:
    jobs = default_jobs() if jobs is None or jobs <= 0 else jobs
    workers = jobs if jobs > 1 and len(paths) >= PARALLEL_THRESHOLD else 1
    project: ProjectFacts | None
    results: Iterator[FileResult]
    if options.project is None and len(paths) > 1:
        # One cheap pass over every module (on the workers too), joined once.
        pool = (lambda python: _run_parallel(python, _Summarize(), workers)) if workers > 1 else None  # noqa: E731
        summaries = run_summaries(list(paths), pool)
        project = _run_facts(summaries, paths)
        if project.star_bindings:
            summaries, project = _with_star_bindings(summaries, paths, project.star_bindings)
        if lint:
            results = _computed(list(paths), _Task(replace(options, project=project), write, want_diff, True), workers)
        else:
            project, results = _providers_first(paths, summaries, project, options, write, want_diff, workers)
    else:
        project, results = options.project, _computed(list(paths), _Task(options, write, want_diff, lint), workers)
    if project is None or not project.blocked:
        yield from results
        return
    for result in results:
        yield _with_blocked_note(result, project)


@overload
def _computed(paths: list[Path], task: _Task, workers: int) -> Generator[FileResult, None, None]: ...
@overload
def _computed(paths: list[Path], task: _Migrate, workers: int) -> Generator[FileResult | PendingWrite, None, None]: ...
def _computed(paths: list[Path], task: _Task | _Migrate, workers: int) -> Generator[FileResult | PendingWrite, None, None]:
    """``task`` over ``paths``, in order: here, or on ``workers`` processes."""
    return (task(path) for path in paths) if workers == 1 else _run_parallel(paths, task, workers)


def run_summaries(paths: list[Path], summaries: Callable[[list[Path]], Iterable[object]] | None = None) -> list[ModuleSummary]:
    """One summary per Python module of the run (none for a single file: nothing to join).

    ``summaries`` maps ``summarize_path`` over the paths (the worker pool); by default it
    runs here, one file after the other.
    """
    if len(paths) < 2:
        return []
    # Documents: their code is not importable by the run. Notebooks are not importable
    # either, but they call the run's modules (``rl_utils.train(env, agent)`` with a
    # ``gym.make`` env): their calls count as call sites (``ProjectFacts.join`` keeps them
    # out of the module names).
    python = [path for path in paths if Path(path).suffix in PROGRAM_SUFFIXES]
    found = summaries(python) if summaries is not None else map(summarize_path, python)
    return [summary for summary in found if isinstance(summary, ModuleSummary)]


def _providers_first(
    paths: Sequence[Path],
    summaries: list[ModuleSummary],
    project: ProjectFacts,
    options: RewriteOptions,
    write: bool,
    want_diff: bool,
    workers: int,
) -> tuple[ProjectFacts, Iterator[FileResult]]:
    """The run's final facts and every file's result, migrating first the modules whose
    env classes other modules import (the providers).

    A provider that is refused (an error, an unstable rewrite) is marked blocked and the
    run joined again without its classes, so that no importer passes ``render_mode=`` to
    them, unpacks their ``reset`` or drops their ``seed()`` as if they had migrated; then
    every file runs with those facts. Where none is refused, which is the rule, each file
    is migrated once: with ``--diff`` the others run on the same workers meanwhile, and a
    provider's result is the run's own; a written run migrates the providers in memory,
    writes nothing before all of them are known to migrate, then writes each in its turn
    (``PendingWrite``) while the others are migrated and written.
    """
    run_options = replace(options, project=project)
    providers = set(project.importers) - set(project.blocked)
    first = [path for path in paths if os.path.realpath(path) in providers]
    rest = [path for path in paths if os.path.realpath(path) not in providers]
    stream: Generator[FileResult, None, None] | None = None
    migrated: list[FileResult | PendingWrite]
    if write:
        migrated = list(_computed(first, _Migrate(run_options, want_diff), workers)) if first else []
    else:
        stream = _computed(first + rest, _Task(run_options, False, want_diff), workers)
        migrated = [next(stream) for _ in first]
    refused = {
        os.path.realpath(path): _result_of(answer).error or "it could not be migrated"
        for path, answer in zip(first, migrated)
        if _result_of(answer).status is Status.ERROR
    }
    if refused:
        if stream is not None:
            stream.close()  # computed with the facts the refusal changes
        project = _run_facts(summaries, paths, blocked={**project.blocked, **refused})
        return project, _computed(list(paths), _Task(replace(options, project=project), write, want_diff), workers)
    if stream is None:
        stream = _computed(rest, _Task(run_options, write, want_diff), workers)
    done = dict(zip(first, migrated))
    return project, (_finished(done[path]) if path in done else next(stream) for path in paths)


def _result_of(answer: FileResult | PendingWrite) -> FileResult:
    return answer.result if isinstance(answer, PendingWrite) else answer


def _finished(answer: FileResult | PendingWrite) -> FileResult:
    return answer.write() if isinstance(answer, PendingWrite) else answer


def _with_star_bindings(
    summaries: list[ModuleSummary], paths: Sequence[Path], bindings: dict[str, dict[str, str]]
) -> tuple[list[ModuleSummary], ProjectFacts]:
    """The summaries and facts of a run in which some module derives a class that only a
    star import of another module of the run binds (``ProjectFacts.star_bindings``): that
    module summarized again with the name bound, so its class is the run's class it names
    (a Gym env when that one is), and the run joined once more."""
    again = [_summary_with(summary, bindings[summary.path]) if summary.path in bindings else summary for summary in summaries]
    return again, _run_facts(again, paths)


def _summary_with(summary: ModuleSummary, bindings: dict[str, str]) -> ModuleSummary:
    if Path(summary.path).suffix != ".py":
        return summary  # a notebook: no module of the run imports it
    try:
        source = read_source(Path(summary.path), _may_matter_to_the_run)
        if source is None:
            return summary
        text, _ = decode(source)
    except (OSError, Refused, TransformError):
        return summary
    return summarize(summary.path, text, bindings) or summary


def _run_facts(summaries: list[ModuleSummary], paths: Sequence[Path], blocked: dict[str, str] | None = None) -> ProjectFacts:
    """The run's joined facts, with its entry points resolved and its programs listed."""
    project = _with_plugins(ProjectFacts.join(summaries, blocked=blocked), summaries, paths)
    project.programs = frozenset(
        os.path.realpath(path) for path in paths if Path(path).suffix in PROGRAM_SUFFIXES and kind_of(path) is None  # not setup.py
    )
    return project


def _with_plugins(project: ProjectFacts, summaries: list[ModuleSummary], paths: Sequence[Path]) -> ProjectFacts:
    """The run's facts with its ``gym.envs`` entry points resolved (GM111): each names a
    function of a module; where that module is migrated in this run and defines it, the
    module calls it on import, and the dependency file says so; else it says why not."""
    plugin_files = [path for path in paths if kind_of(path) in ("setup.py", "setup.cfg", "pyproject.toml")]
    project.plugin_calls, project.plugin_routes = {}, {}
    if not plugin_files:
        return project
    python = {os.path.realpath(path) for path in paths if Path(path).suffix in (".py", ".pyw")}
    by_path = {os.path.realpath(summary.path): summary for summary in summaries}
    for path in plugin_files:
        try:
            text = Path(path).read_bytes().decode("utf-8-sig")
        except (OSError, UnicodeDecodeError):
            continue
        kind = kind_of(path)
        assert kind is not None
        routes = project.plugin_routes.setdefault(os.path.realpath(path), {})
        for entry in plugin_entries(kind, text):
            target, reason = _plugin_module(Path(os.path.realpath(path)).parent, entry, python, by_path, project)
            if target is None:
                routes[entry.target] = (None, reason)
                continue
            calls = project.plugin_calls.setdefault(target, ())
            if (entry.attr, entry.namespace) not in calls:
                project.plugin_calls[target] = (*calls, (entry.attr, entry.namespace))
            routes[entry.target] = (os.path.relpath(target, os.path.dirname(os.path.realpath(path))), "")
    return project


def _plugin_module(
    base: Path, entry: PluginEntry, python: set[str], by_path: dict[str, ModuleSummary], project: ProjectFacts
) -> tuple[str | None, str]:
    """The module of the run that will call ``entry``'s function, or None and why not."""
    if not entry.attr or "." in entry.attr:
        return None, "it names no top-level function of a module"
    parts = entry.module.split(".")
    if parts[-1] == "__init__":
        parts.pop()
    candidates = [root.joinpath(*parts).with_suffix(".py") for root in (base, base / "src")] if parts else []
    candidates += [root.joinpath(*parts, "__init__.py") for root in (base, base / "src")]
    found = next((os.path.realpath(candidate) for candidate in candidates if candidate.is_file()), None)
    if found is None:
        return None, f"no module `{entry.module}` beside this file"
    shown = os.path.relpath(found, base)
    if found not in python:
        return None, f"`{shown}` is not part of this run"
    if found in project.blocked:
        return None, f"`{shown}` is left as it is: {project.blocked[found]}"
    summary = by_path.get(found)
    try:
        migrated = screen(read_source(Path(found), may_hold_gym_code) or b"", may_hold_gym_code)
    except (OSError, Refused):
        migrated = False
    if summary is None or not migrated:
        return None, f"the run does not migrate `{shown}`: it holds no Gym code"
    if entry.attr not in summary.exports:
        return None, f"`{shown}` defines no top-level `{entry.attr}`"
    return found, ""


def _with_blocked_note(result: FileResult, project: ProjectFacts) -> FileResult:
    """An importer of a blocked module says which module held it back (GM002)."""
    path = os.path.realpath(result.path)
    notes = tuple(
        Finding(
            1,
            0,
            BLOCKED_BY_MODULE,
            FixKind.FLAG,
            f"`{os.path.relpath(blocked, os.path.dirname(path))}` is left as it is ({reason}): this module's uses of its "
            "classes (render_mode=, reset and step results, seed()) were not migrated and are reported; "
            "migrate both together",
        )
        for blocked, reason in sorted(project.blocked.items())
        if path in project.importers.get(blocked, ())
    )
    return replace(result, findings=(*notes, *result.findings)) if notes else result


def summarize_path(path: Path) -> ModuleSummary | None:
    """The summary of the module at ``path``, read and screened as its own run will."""
    try:
        # The same screening as the file's own run: never parse what it refuses. A package's
        # ``__init__`` and a star import are read whatever they say: they re-export names
        # (``from .utils import make``) the rest of the run calls.
        relevant = _may_reexport if Path(path).name == "__init__.py" else _may_matter_to_the_run
        notebook = adapter_for(Path(path)) if Path(path).suffix == ".ipynb" else None
        # A notebook's file size is mostly its outputs (images, logs): it is read up to its own
        # run's limit, and only its code cells count against a module's (in _notebook_summary).
        source = read_source(Path(path), relevant, limit=notebook.max_bytes) if notebook else read_source(Path(path), relevant)
        if source is None:
            return None
        if notebook is not None:
            return _notebook_summary(path, source)
        if not screen(source, relevant):
            tests = (_may_mask_bootstrapping, _may_define_plain_root, writes_into_import, _may_load_saved_state)
            if not any(screen(source, test) for test in tests):
                return None
            # no Gym code, but maybe the agent whose ``learn`` masks bootstrapping (GM302), the
            # project's own interface its env adapters derive (``class Environment(ABC)``), a
            # write into a table of creators another module holds (``creator_tables.py``), or
            # an evaluation script loading a saved model into the run's tasks (GM803)
            return summarize_masks(str(path), decode(source)[0])
        text, _ = decode(source)
    except (OSError, Refused, TransformError):
        return None
    return summarize(str(path), text)


def _notebook_summary(path: Path, source: bytes) -> ModuleSummary | None:
    """The summary of a notebook's code cells as the one program its own run migrates."""
    # Through its adapter, loaded on first use: the notebook reader needs json, which a run
    # without notebooks (and ``check`` of one file) never loads.
    adapter = adapter_for(Path(path))
    if adapter is None:
        return None
    try:
        programs = adapter.read(source, str(path)).programs
    except Exception:  # noqa: BLE001  (the notebook's own run reports why; it just adds no facts)
        return None
    if not programs:
        return None
    text, _ = join_segments([segment.code for segment in programs[0]])
    if len(text.encode("utf-8")) > MAX_SOURCE_BYTES:  # its code alone is past a module's limit
        return None
    return summarize(str(path), text)


# A def with a parameter named like a done flag (``def learn(self, s, r, s_, done)``): the only
# defs ``facts/bootstrap.py`` can find masks in. Most Gym-free modules (a stdlib module that
# says "done" in a comment) fail this before any parse.
_FLAG_PARAMETER = re.compile(rb"def\s+\w+\s*\((?:[^()]|\([^()]*\))*?\b\w*(?:done|terminal)\w*\b")


def _may_mask_bootstrapping(source: bytes) -> bool:
    """An agent's ``learn(..., done)`` that masks with its flag, or a memory's record class
    with a done field (``Transition = namedtuple(..., "done")``): facts for the run (GM302)."""
    if b"done" not in source and b"terminal" not in source:
        return False
    return _FLAG_PARAMETER.search(source) is not None or _RECORD_CLASS.search(source) is not None


_RECORD_CLASS = re.compile(rb"namedtuple|NamedTuple|@dataclass")

# ``class Environment(ABC):`` / ``(object)`` / ``(metaclass=ABCMeta)`` at the top level
_PLAIN_ROOT = re.compile(rb"^class\s+\w+\s*\((?:object|ABC|abc\.ABC|metaclass=(?:abc\.)?ABCMeta)\)\s*:", re.MULTILINE)


# What ``summaries.defs.loads_saved_state`` looks for, as text: the parse decides.
_LOAD_CALL = re.compile(rb"\.load\(|load_state_dict|load_weights|load_model|from_pretrained|restore\(|load_from_checkpoint")


def _may_load_saved_state(source: bytes) -> bool:
    return _LOAD_CALL.search(source) is not None


def _may_define_plain_root(source: bytes) -> bool:
    """A top-level class deriving only ``object`` or ``abc.ABC`` (``plain_roots``)."""
    return b"class" in source and _PLAIN_ROOT.search(source) is not None


def _may_reexport(source: bytes) -> bool:
    return may_hold_gym_code(source) or b"import" in source


def _may_matter_to_the_run(source: bytes) -> bool:
    return may_hold_gym_code(source) or b"import *" in source


@dataclass(frozen=True)
class _Summarize:
    """``summarize_path`` for the workers: a module's summary, or False
    (never None: the pool reads a missing answer as a dead worker)."""

    def __call__(self, path: Path) -> object:
        try:
            return summarize_path(path) or False
        except Exception:  # noqa: BLE001  (the file's own run reports what is wrong with it)
            return False


@dataclass(frozen=True)
class _Task:
    """``process_file`` with the run's settings; picklable, so workers receive it."""

    options: RewriteOptions
    write: bool
    want_diff: bool
    lint: bool = False

    def __call__(self, path: Path) -> FileResult:
        try:
            return process_file(path, self.options, write=self.write, want_diff=self.want_diff, lint=self.lint)
        except Exception as exc:  # a bug must cost this file, not the run
            return _internal_error(path, exc)


@dataclass(frozen=True)
class _Migrate:
    """``migrate_file`` for the workers: the file migrated in memory, a ``PendingWrite``
    where it changes, for the run to write later."""

    options: RewriteOptions
    want_diff: bool

    def __call__(self, path: Path) -> FileResult | PendingWrite:
        try:
            return migrate_file(path, self.options, want_diff=self.want_diff)
        except Exception as exc:  # a bug must cost this file, not the run
            return _internal_error(path, exc)


def _internal_error(path: Path, exc: Exception) -> FileResult:
    return FileResult(str(path), Status.ERROR, error=f"internal error: {type(exc).__name__}: {exc}")


@overload
def _run_parallel(paths: list[Path], task: _Task, jobs: int) -> Generator[FileResult, None, None]: ...
@overload
def _run_parallel(paths: list[Path], task: _Migrate, jobs: int) -> Generator[FileResult | PendingWrite, None, None]: ...
@overload
def _run_parallel(paths: list[Path], task: _Summarize, jobs: int) -> Generator[object, None, None]: ...
def _run_parallel(paths: list[Path], task: _Task | _Migrate | _Summarize, jobs: int) -> Generator[object, None, None]:
    """Every file's result, in order, however many workers die on the way."""
    pool = _Pool(task, min(jobs, len(paths)))
    order = _InOrder()
    waiting = deque(range(len(paths)))
    try:
        while waiting or pool.busy():
            for worker in pool.idle():
                if not waiting:
                    break
                index = waiting.popleft()
                if not pool.assign(worker, index, paths[index]):
                    waiting.appendleft(index)  # that worker was gone already; a fresh one will take it
            for index, result in pool.collect(paths):
                yield from order.add(index, result)
    finally:
        pool.close()


class _InOrder:
    """Results arrive by index in any order; release them in index order, as soon as possible."""

    def __init__(self) -> None:
        self._waiting: dict[int, FileResult] = {}
        self._next = 0

    def add(self, index: int, result: FileResult) -> Iterator[FileResult]:
        self._waiting[index] = result
        while self._next in self._waiting:
            yield self._waiting.pop(self._next)
            self._next += 1


@dataclass
class _Worker:
    process: BaseProcess
    connection: Connection  # the parent's end of the worker's pipe
    index: int | None = None  # the file it holds, if any


class _Pool:
    """Worker processes that each hold at most one file, and are replaced when they die."""

    def __init__(self, task: _Task | _Migrate | _Summarize, size: int) -> None:
        # multiprocessing loads only for a pool: a run of one file (a pre-commit hook) never pays for it.
        import multiprocessing

        self._task = task
        self._context = multiprocessing.get_context()
        self._workers = [self._start() for _ in range(size)]

    def _start(self) -> _Worker:
        parent_end, child_end = self._context.Pipe()
        process = self._context.Process(target=_serve, args=(child_end, self._task), daemon=True)
        process.start()
        child_end.close()
        return _Worker(process, parent_end)

    def busy(self) -> list[_Worker]:
        return [worker for worker in self._workers if worker.index is not None]

    def idle(self) -> list[_Worker]:
        return [worker for worker in self._workers if worker.index is None]

    def assign(self, worker: _Worker, index: int, path: Path) -> bool:
        """Hand ``path`` to an idle worker; False (and the worker replaced) if it is gone."""
        try:
            worker.connection.send(path)
        except OSError:
            self._replace(worker)
            return False
        worker.index = index
        return True

    def collect(self, paths: list[Path]) -> list[tuple[int, FileResult]]:
        """Wait until some busy worker answers or dies; the results (or deaths) so far."""
        from multiprocessing.connection import wait

        busy = self.busy()
        ready = set(wait([w.connection for w in busy] + [w.process.sentinel for w in busy]))
        finished = []
        for worker in busy:
            if worker.connection in ready or worker.process.sentinel in ready:
                assert worker.index is not None
                finished.append((worker.index, self._receive(worker, paths[worker.index])))
        return finished

    def _receive(self, worker: _Worker, path: Path) -> FileResult:
        result: FileResult | None = None
        try:
            if worker.connection.poll():
                result = worker.connection.recv()
        except Exception:  # EOF or a message cut short: the worker died while answering
            result = None
        worker.index = None
        if result is None or not worker.process.is_alive():
            self._replace(worker)
        return result if result is not None else FileResult(str(path), Status.ERROR, error=WORKER_DIED)

    def _replace(self, worker: _Worker) -> None:
        _stop(worker)
        self._workers[self._workers.index(worker)] = self._start()

    def close(self) -> None:
        """Let every worker finish the file it holds, then stop it."""
        for worker in self._workers:
            try:
                worker.connection.send(None)
            except OSError:
                pass  # gone already
        for worker in self._workers:
            _stop(worker)


def _stop(worker: _Worker) -> None:
    """Wait for ``worker`` to exit. An answer nobody will use is read and dropped: a
    worker blocked on a full pipe could not exit."""
    while worker.process.is_alive():
        try:
            if worker.connection.poll(0.1):
                worker.connection.recv()
        except Exception:  # EOF, or an answer cut short: it is exiting
            break
    worker.process.join()
    worker.connection.close()


# --- in the worker processes ---------------------------------------------------------

def _serve(connection: Connection, task: _Task | _Migrate | _Summarize) -> None:
    """A worker: process the files the parent sends, one at a time, until it sends None."""
    # Ctrl-C reaches the whole process group: the parent stops the run, after letting
    # each worker finish its file; a worker that raised KeyboardInterrupt too would
    # leave a traceback per process.
    import signal  # only workers need these: a run of one file never loads them
    import threading

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    threading.Thread(target=_exit_when_orphaned, args=(os.getppid(),), daemon=True).start()
    try:
        while (path := connection.recv()) is not None:
            _crash_for_tests(path)
            result = task(path)
            try:
                connection.send(result)
            except OSError:
                raise
            except Exception as exc:  # the result would not pickle: this file's error
                connection.send(_internal_error(path, exc))
    except (EOFError, OSError):
        pass  # the parent is gone: there is no one to answer


def _exit_when_orphaned(parent: int) -> None:
    """A killed run must not leave workers behind (they would wait for work forever).

    The rewrite of the current file is dropped mid-way at worst: writes are atomic, and
    the next run removes the temporary file and redoes the file.
    """
    while os.getppid() == parent:
        time.sleep(_PARENT_POLL_SECONDS)
    os._exit(1)


def _crash_for_tests(path: Path) -> None:
    """Test-only hook: die like a segfault on files whose path contains
    ``GYMMIGRATE_TEST_CRASH_ON``. The tests set it; nothing else should."""
    marker = os.environ.get("GYMMIGRATE_TEST_CRASH_ON")
    if marker and marker in str(path):
        os._exit(139)
