"""``gymmigrate check FILE`` on the slowest real file, as a ratio to ``import libcst``.

    python benchmarks/bench_check.py [--repeat N] [--file PATH] [--cache DIR]

A pre-commit hook runs ``check`` once per commit, so its whole-process time is what a
user waits for. The figure is the median, over ``--repeat`` pairs run alternately, of
``check FILE`` divided by ``python -c "import libcst"`` (start-up included in both), on
the file of the benchmark's Gym set (``bench_real.py``: gym 0.17.3, sb3-contrib 1.8.0,
rl-zoo3 1.8.0, highway-env 1.5) whose analysis takes longest; target at most 0.8.
Bytecode is compiled first and the children may write it, as an installed package runs.
"""

from __future__ import annotations

import argparse
import compileall
import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_real import (  # noqa: E402
    DEFAULT_CACHE,
    fetch_corpus,
    gym_set,
    gymmigrate_command,
    log,
    run,
)

TARGET_RATIO = 0.8


def _slowest_to_check(files: list[Path]) -> Path:
    """The file whose analysis takes longest, timed in this process (median of three), so
    machine noise in a process's start-up cannot pick it: every process imports the same."""
    from gymmigrate.engine import lint_source
    from gymmigrate.source_text import TransformError

    times = {}
    for path in files:
        source = path.read_bytes()
        runs = []
        for _ in range(3):
            start = time.perf_counter()
            try:
                lint_source(source, str(path))
            except TransformError:
                break
            runs.append(time.perf_counter() - start)
        if runs:
            times[path] = statistics.median(runs)
    log(f"analysis timed in process on {len(times)} files")
    return max(times, key=lambda path: times[path])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeat", type=int, default=11, help="alternating pairs timed (default 11)")
    parser.add_argument("--file", type=Path, help="time this file instead of finding the slowest of the Gym set")
    parser.add_argument("--cache", type=Path, default=DEFAULT_CACHE, help="download/unpack folder (default benchmarks/.cache)")
    args = parser.parse_args()
    os.environ.pop("PYTHONDONTWRITEBYTECODE", None)  # users run with bytecode cached
    import gymmigrate

    compileall.compile_dir(str(Path(gymmigrate.__file__).parent), quiet=1)
    tool = gymmigrate_command()
    libcst = [sys.executable, "-c", "import libcst"]
    run(libcst, 60)  # its bytecode too
    if args.file is not None:
        slowest = args.file
    else:
        gym = gym_set(list(fetch_corpus(args.cache.resolve()).values()))
        slowest = _slowest_to_check(gym.files)
    wall, cpu = [], []
    for _ in range(max(1, args.repeat)):
        check, parse = run(tool + ["check", str(slowest)], 60), run(libcst, 60)
        wall.append(check.seconds / parse.seconds)
        if check.cpu_seconds and parse.cpu_seconds:
            cpu.append(check.cpu_seconds / parse.cpu_seconds)
    ratio = statistics.median(wall)
    print(f"file: {slowest}")
    print(f"check FILE / import libcst, wall: {ratio:.2f} (min {min(wall):.2f}, max {max(wall):.2f}; target <= {TARGET_RATIO})")
    if cpu:
        print(f"check FILE / import libcst, cpu:  {statistics.median(cpu):.2f}")
    print("verdict:", "met" if ratio <= TARGET_RATIO else "NOT met")


if __name__ == "__main__":
    main()
