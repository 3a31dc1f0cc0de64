"""``gymmigrate check FILE`` on real files, as a ratio to ``import libcst``.

    python benchmarks/bench_check.py [--repeat N] [--slowest] [--file PATH ...] [--cache DIR]

A pre-commit hook runs ``check`` once per commit, so its whole-process time is what a
user waits for. Each figure is the median, over ``--repeat`` rounds, of ``check FILE``
divided by the ``python -c "import libcst"`` of the same round (start-up included in
both; each round runs the libcst import and then each file's check, alternately). The
files, from the benchmark's Gym set (``bench_real.py``: gym 0.17.3, sb3-contrib 1.8.0,
rl-zoo3 1.8.0, highway-env 1.5): rl-zoo3's ``exp_manager.py`` (895 lines, the heaviest
analysis when issue #17 was measured) and gym's ``box2d/bipedal_walker.py``; with
``--slowest`` also the file whose analysis takes longest now, timed in process. Target
at most 0.8 on each. Bytecode is compiled first and the children may write it, as an installed
package runs.
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
# The files of issue #17's figure: the heaviest analysis, and an env module of the kind a
# hook checks most.
NAMED = (("rl_zoo3", "exp_manager.py"), ("box2d", "bipedal_walker.py"))


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
    parser.add_argument("--repeat", type=int, default=11, help="rounds timed (default 11)")
    parser.add_argument("--file", type=Path, action="append", help="time this file (repeatable) instead of the Gym set's two")
    parser.add_argument("--slowest", action="store_true", help="also time the file whose analysis is slowest now")
    parser.add_argument("--cache", type=Path, default=DEFAULT_CACHE, help="download/unpack folder (default benchmarks/.cache)")
    args = parser.parse_args()
    os.environ.pop("PYTHONDONTWRITEBYTECODE", None)  # users run with bytecode cached
    import gymmigrate

    compileall.compile_dir(str(Path(gymmigrate.__file__).parent), quiet=1)
    tool = gymmigrate_command()
    libcst = [sys.executable, "-c", "import libcst"]
    run(libcst, 60)  # its bytecode too
    if args.file:
        files = list(args.file)
    else:
        gym = gym_set(list(fetch_corpus(args.cache.resolve()).values()))
        files = [path for named in NAMED for path in gym.files if path.parts[-2:] == named]
        if args.slowest:
            slowest = _slowest_to_check(gym.files)
            files += [slowest] if slowest not in files else []
    for path in files:
        run(tool + ["check", str(path)], 60)  # the rules' bytecode
    wall: dict[Path, list[float]] = {path: [] for path in files}
    cpu: dict[Path, list[float]] = {path: [] for path in files}
    for _ in range(max(1, args.repeat)):
        parse = run(libcst, 60)
        for path in files:
            check = run(tool + ["check", str(path)], 60)
            wall[path].append(check.seconds / parse.seconds)
            if check.cpu_seconds and parse.cpu_seconds:
                cpu[path].append(check.cpu_seconds / parse.cpu_seconds)
    met = True
    for path in files:
        ratio = statistics.median(wall[path])
        met = met and ratio <= TARGET_RATIO
        print(f"file: {path}")
        print(f"  check FILE / import libcst, wall: {ratio:.2f} (min {min(wall[path]):.2f}, max {max(wall[path]):.2f}; target <= {TARGET_RATIO})")
        if cpu[path]:
            print(f"  check FILE / import libcst, cpu:  {statistics.median(cpu[path]):.2f}")
    print("load average (1, 5, 15 min):", " ".join(f"{load:.2f}" for load in os.getloadavg()))
    print("verdict:", "met" if met else "NOT met")


if __name__ == "__main__":
    main()
