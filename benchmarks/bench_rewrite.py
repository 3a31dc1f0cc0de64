"""Benchmark: gymmigrate against bare LibCST parsing, as ratios.

    python benchmarks/bench_rewrite.py [--repeat N]

Three figures, each a ratio to the cheapest thing that could do the job:
  * rewrite  : transform_source (every pass, verification, idempotence re-run) over the
               legacy fixtures, divided by libcst.parse_module over the same files;
  * monorepo : process_file (pre-parse filter, then the above) over the fixtures plus
               the standard library's pure-Python modules (code with no Gym in it),
               divided by parsing all of them;
  * start-up : `gymmigrate --version` wall time, divided by `python -c "import libcst"`.
Ratios, not seconds, so the numbers mean the same on a slower machine.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import sysconfig
import time
from pathlib import Path

import libcst as cst

from gymmigrate.engine import transform_source
from gymmigrate.options import RewriteOptions
from gymmigrate.process import process_file
from gymmigrate.source_text import TransformError

ROOT = Path(__file__).resolve().parent.parent


def legacy_corpus() -> list[Path]:
    files = [p for p in (ROOT / "fixtures").rglob("*.py") if not p.name.endswith(".expected.py")]
    return sorted(files)


def stdlib_corpus(limit: int = 400) -> list[Path]:
    stdlib = Path(sysconfig.get_paths()["stdlib"])
    files = [p for p in sorted(stdlib.glob("*.py"))][:limit]
    return files


def timed(function, repeat: int) -> float:
    samples = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        samples.append(time.perf_counter() - start)
    return statistics.median(samples)


def parse_all(sources: list[bytes]) -> None:
    for source in sources:
        try:
            cst.parse_module(source)
        except Exception:
            pass


def rewrite_all(sources: list[bytes]) -> None:
    for source in sources:
        try:
            transform_source(source, "<bench>", RewriteOptions())
        except TransformError:
            pass


def process_all(paths: list[Path]) -> None:
    for path in paths:
        process_file(path, RewriteOptions(), write=False, want_diff=False)


def wall(command: list[str], repeat: int) -> float:
    return timed(lambda: subprocess.run(command, capture_output=True, check=False), repeat)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()

    legacy = legacy_corpus()
    legacy_sources = [p.read_bytes() for p in legacy]
    stdlib = stdlib_corpus()
    mixed = legacy + stdlib
    mixed_sources = [p.read_bytes() for p in mixed]
    rewrite_all(legacy_sources)  # warm imports and caches

    parse_legacy = timed(lambda: parse_all(legacy_sources), args.repeat)
    rewrite_legacy = timed(lambda: rewrite_all(legacy_sources), args.repeat)
    parse_mixed = timed(lambda: parse_all(mixed_sources), args.repeat)
    process_mixed = timed(lambda: process_all(mixed), args.repeat)
    start_baseline = wall([sys.executable, "-c", "import libcst"], args.repeat + 2)
    start_cli = wall([sys.executable, "-m", "gymmigrate", "--version"], args.repeat + 2)

    rows = [
        ("rewrite", f"{len(legacy)} legacy files", rewrite_legacy, parse_legacy),
        ("monorepo", f"{len(legacy)} legacy + {len(stdlib)} stdlib files", process_mixed, parse_mixed),
        ("start-up", "gymmigrate --version", start_cli, start_baseline),
    ]
    print(f"{'figure':<10} {'corpus':<36} {'gymmigrate':>11} {'baseline':>10} {'ratio':>7}")
    for name, corpus, ours, baseline in rows:
        print(f"{name:<10} {corpus:<36} {ours:>10.3f}s {baseline:>9.3f}s {ours / baseline:>6.2f}x")


if __name__ == "__main__":
    main()
