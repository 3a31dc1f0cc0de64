"""Run the engine over many files, on every core when it pays off.

Each file is independent and ``process_file`` returns a small picklable
``FileResult``, so a process pool can do the work; results come back in the order
the files were given so diffs and summaries are stable from run to run.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor
from functools import partial
from pathlib import Path

from gymmigrate.engine import FileResult, process_file
from gymmigrate.rules.base import RewriteOptions

# Below this many files a pool costs more (worker start-up, imports) than it saves.
PARALLEL_THRESHOLD = 16


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
) -> Iterator[FileResult]:
    work = partial(process_file, options=options, write=write, want_diff=want_diff)
    jobs = default_jobs() if jobs is None or jobs <= 0 else jobs
    if jobs == 1 or len(paths) < PARALLEL_THRESHOLD:
        for path in paths:
            yield work(path)
        return
    chunk = max(1, len(paths) // (jobs * 8))
    with ProcessPoolExecutor(max_workers=jobs) as pool:
        yield from pool.map(work, paths, chunksize=chunk)
