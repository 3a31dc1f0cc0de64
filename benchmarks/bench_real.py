"""Benchmark: gymmigrate on real published legacy Gym code, as a user runs it.

    python benchmarks/bench_real.py [--repeat N] [--json PATH] [--cache DIR]

Not part of the test suite. The corpus is four published packages, fetched once with
``pip download`` (no install) into ``benchmarks/.cache/`` and unpacked there:
gym 0.17.3 (sdist), sb3-contrib 1.8.0, rl-zoo3 1.8.0 and highway-env 1.5 (wheels).
The *Gym set* is every ``*.py`` file in them whose text matches
``gym|pettingzoo|baselines|envs?\\b`` (any case) and that ``ast.parse`` accepts with
the Python 3.11 grammar; the files it rejects are counted and left out.

Every figure is the wall time of a whole subprocess (interpreter start-up included),
the median of ``--repeat`` runs (default 3) unless said otherwise:

  rewrite ratio     ``gymmigrate rewrite --diff --jobs 1`` over the Gym set, divided by
                    one process doing ``libcst.parse_module(src).code`` on the same
                    files. Target: at most 3.0.
  mixed-tree ratio  ``gymmigrate rewrite --diff`` (default jobs) over a temporary tree
                    holding the Gym set plus as many lines of the standard library's
                    pure-Python modules with no Gym in them, divided by one process
                    parsing the whole tree. Target: at most 0.75 (Gym-free files should
                    cost less than a parse).
  check, 3 slowest  ``gymmigrate check FILE`` for the three slowest files of 200-700
                    lines (every file of the set is timed once, the slowest are timed
                    again). Target: at most 0.5 s each.
  check, slowest    the slowest single ``gymmigrate check FILE`` over the whole set.
                    Target: at most 1.0 s.
  cold start        ``gymmigrate --version`` (median of --startup-runs, default 7),
                    with ``python -c "import libcst"`` shown for reference.
                    Target: at most 150 ms.
  peak RSS          maximum resident set of ``rewrite --diff --jobs 1`` over the Gym
                    set and over half of it (every other file). Target: flat, the full
                    set at most 1.25 times the half.

Also printed, from one ``gymmigrate rewrite --diff --report REPORT.json`` over the Gym
set: files errored, "not stable" refusals, internal errors, review items per 1,000
lines (target: at most 9), review items per rule, duplicate findings (same path, line,
rule and message more than once; target: none) and the notes (explanations of rewrites
already applied) with their share of all findings. A field the report lacks is n/a.

Verdicts apply to wall time. Next to it the table shows CPU time (user + system of the
process and the workers it waited for): wall time is what a user waits, CPU time barely
moves when other work shares the machine. For a single process, wall well above CPU means
a busy machine; with workers (the mixed tree) CPU time adds up all of them.
The load average at start and end is printed too. Processes run with bytecode cached, as
users run (a ``PYTHONDONTWRITEBYTECODE`` of the shell is dropped and the package compiled
once before timing). The engine is measured as installed
(an editable install measures the working tree); if its source changes during the run,
the run says so under "problems". ``--json PATH`` writes every figure, the per-file
``check`` times, the report counts and those facts as JSON.
"""

from __future__ import annotations

import argparse
import ast
import json
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import sysconfig
import tarfile
import tempfile
import threading
import time
import zipfile
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

HERE = Path(__file__).resolve().parent
DEFAULT_CACHE = HERE / ".cache"
REQUIREMENTS = ("gym==0.17.3", "sb3-contrib==1.8.0", "rl-zoo3==1.8.0", "highway-env==1.5")
GYM_PATTERN = re.compile(rb"gym|pettingzoo|baselines|envs?\b", re.IGNORECASE)
CHECK_LINES = (200, 700)

TARGET_REWRITE_RATIO = 3.0
TARGET_MIXED_RATIO = 0.75
TARGET_CHECK_SLOWEST_THREE = 0.5
TARGET_CHECK_ANY = 1.0
TARGET_COLD_START = 0.150
TARGET_RSS_GROWTH = 1.25

# Folder names gymmigrate's discovery skips; renamed in the mixed tree so it sees every file.
DISCOVERY_SKIPS = {"build", "dist", "venv", "site-packages", "dist-packages", "node_modules", "__pycache__"}

PARSE_SCRIPT = """\
import sys
import libcst
with open(sys.argv[1], encoding="utf-8") as listing:
    paths = listing.read().splitlines()
failed = 0
for path in paths:
    with open(path, "rb") as handle:
        source = handle.read()
    try:
        libcst.parse_module(source).code
    except Exception:
        failed += 1
sys.stderr.write(f"parsed {len(paths) - failed} of {len(paths)}\\n")
"""


# --------------------------------------------------------------------------- corpus


def _normalise(name: str) -> str:
    return re.sub(r"[-_.]+", "_", name).lower()


def _archive_key(filename: str) -> tuple[str, str] | None:
    """(normalised name, version) of a wheel or sdist file name."""
    if filename.endswith(".whl"):
        parts = filename[: -len(".whl")].split("-")
        return (_normalise(parts[0]), parts[1]) if len(parts) >= 2 else None
    for suffix in (".tar.gz", ".zip", ".tar.bz2", ".tgz"):
        if filename.endswith(suffix):
            stem = filename[: -len(suffix)]
            if "-" in stem:
                name, version = stem.rsplit("-", 1)
                return _normalise(name), version
    return None


def _find_archive(cache: Path, requirement: str) -> Path | None:
    name, version = requirement.split("==")
    wanted = (_normalise(name), version)
    for path in sorted(cache.iterdir()):
        if path.is_file() and _archive_key(path.name) == wanted:
            return path
    return None


def fetch_corpus(cache: Path) -> dict[str, Path]:
    """Download (once) and unpack (once) each requirement; its unpacked folder by name."""
    cache.mkdir(parents=True, exist_ok=True)
    ignore = cache / ".gitignore"
    if not ignore.exists():
        ignore.write_text("*\n", encoding="utf-8")
    missing = [r for r in REQUIREMENTS if _find_archive(cache, r) is None]
    if missing:
        log(f"downloading {', '.join(missing)} into {cache}")
        command = [sys.executable, "-m", "pip", "download", "--no-deps", "--no-binary", ":none:", "-d", str(cache)]
        completed = subprocess.run(command + missing, capture_output=True, text=True, check=False)
        if completed.returncode != 0:
            sys.exit(f"pip download failed:\n{completed.stdout}\n{completed.stderr}")
    unpacked = {}
    for requirement in REQUIREMENTS:
        archive = _find_archive(cache, requirement)
        if archive is None:
            sys.exit(f"pip download did not leave an archive for {requirement} in {cache}")
        name = _normalise(requirement.split("==")[0])
        target = cache / "src" / name
        done = cache / "src" / f"{name}.unpacked"
        if not (done.is_file() and done.read_text(encoding="utf-8") == archive.name and target.is_dir()):
            shutil.rmtree(target, ignore_errors=True)
            target.mkdir(parents=True)
            _unpack(archive, target)
            done.write_text(archive.name, encoding="utf-8")
        unpacked[name] = target
    return unpacked


def _unpack(archive: Path, target: Path) -> None:
    if archive.name.endswith(".whl") or archive.name.endswith(".zip"):
        with zipfile.ZipFile(archive) as bundle:
            bundle.extractall(target)
        return
    with tarfile.open(archive) as bundle:
        if hasattr(tarfile, "data_filter"):
            bundle.extractall(target, filter="data")
        else:  # an older interpreter: refuse names that would escape the target by hand
            for member in bundle.getmembers():
                if member.name.startswith("/") or ".." in Path(member.name).parts:
                    raise SystemExit(f"unsafe path in {archive.name}: {member.name}")
            bundle.extractall(target)


def line_count(source: bytes) -> int:
    return len(source.splitlines())


def parses_as_311(source: bytes, path: Path) -> bool:
    try:
        ast.parse(source, filename=str(path), feature_version=(3, 11))
    except (SyntaxError, ValueError):
        return False
    return True


@dataclass
class Corpus:
    files: list[Path]
    lines: dict[Path, int]
    excluded: list[Path]  # match the pattern but do not parse as Python 3.11

    @property
    def total_lines(self) -> int:
        return sum(self.lines[p] for p in self.files)


def gym_set(roots: Sequence[Path]) -> Corpus:
    files, lines, excluded = [], {}, []
    for root in roots:
        for path in sorted(root.rglob("*.py")):
            if not path.is_file():
                continue
            source = path.read_bytes()
            if not GYM_PATTERN.search(source):
                continue
            if not parses_as_311(source, path):
                excluded.append(path)
                continue
            files.append(path)
            lines[path] = line_count(source)
    return Corpus(files, lines, excluded)


def stdlib_filler(lines_wanted: int) -> list[tuple[Path, Path]]:
    """(file, path relative to the stdlib) of Gym-free stdlib modules, until the lines add up."""
    stdlib = Path(sysconfig.get_paths()["stdlib"])
    candidates = []
    for path in stdlib.rglob("*.py"):
        relative = path.relative_to(stdlib)
        if any(part in {"site-packages", "dist-packages", "__pycache__", "test", "tests", "idle_test"} for part in relative.parts):
            continue
        candidates.append((len(relative.parts), str(relative), path))
    chosen, total = [], 0
    for _, _, path in sorted(candidates):  # top-level modules first, then packages
        if total >= lines_wanted:
            break
        source = path.read_bytes()
        if GYM_PATTERN.search(source) or not parses_as_311(source, path):
            continue
        chosen.append((path, path.relative_to(stdlib)))
        total += line_count(source)
    return chosen


def _safe_relative(relative: Path) -> Path:
    parts = [f"{part}_" if (part in DISCOVERY_SKIPS or part.startswith(".") or part.endswith(".egg-info")) else part for part in relative.parts[:-1]]
    return Path(*parts, relative.name)


def build_mixed_tree(target: Path, gym: Corpus, cache_src: Path) -> tuple[list[Path], int, int]:
    """Copy the Gym set and the stdlib filler under ``target``; (files, stdlib files, stdlib lines)."""
    copied = []
    for path in gym.files:
        destination = target / "gym" / _safe_relative(path.relative_to(cache_src))
        destination.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(path, destination)
        copied.append(destination)
    filler = stdlib_filler(gym.total_lines)
    filler_lines = 0
    for path, relative in filler:
        destination = target / "stdlib" / _safe_relative(relative)
        destination.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(path, destination)
        copied.append(destination)
        filler_lines += line_count(path.read_bytes())
    return copied, len(filler), filler_lines


# --------------------------------------------------------------------------- running


@dataclass
class Run:
    seconds: float  # wall time
    cpu_seconds: float | None  # user + system time of the child and the children it waited for
    returncode: int | None
    maxrss_bytes: int | None  # of the child and the children it waited for
    stderr: str
    timed_out: bool = False


def log(message: str) -> None:
    elapsed = time.perf_counter() - START
    print(f"[{elapsed:7.1f}s] {message}", file=sys.stderr, flush=True)


def run(command: Sequence[str], timeout: float) -> Run:
    """Run ``command`` with stdout discarded; its wall and CPU time, exit code and peak RSS."""
    with tempfile.TemporaryFile() as errors:
        start = time.perf_counter()
        process = subprocess.Popen(list(command), stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=errors)
        killed = threading.Event()

        def kill() -> None:
            killed.set()
            process.kill()

        timer = threading.Timer(timeout, kill)
        timer.start()
        try:
            if hasattr(os, "wait4"):
                _, status, usage = os.wait4(process.pid, 0)
                seconds = time.perf_counter() - start
                process.returncode = os.waitstatus_to_exitcode(status)
                scale = 1 if sys.platform == "darwin" else 1024  # bytes on macOS, KiB elsewhere
                maxrss = usage.ru_maxrss * scale
                cpu = usage.ru_utime + usage.ru_stime
            else:
                process.wait()
                seconds = time.perf_counter() - start
                maxrss = cpu = None
        finally:
            timer.cancel()
        errors.seek(0)
        text = errors.read().decode("utf-8", "replace")
    return Run(seconds, cpu, process.returncode, maxrss, text, killed.is_set())


def median(values: Sequence[float]) -> float:
    return statistics.median(values)


@dataclass
class Timing:
    """The medians of repeated runs of one command: wall time and CPU time."""

    wall: float
    cpu: float | None

    @classmethod
    def of(cls, runs: Sequence[Run]) -> Timing:
        cpus = [r.cpu_seconds for r in runs if r.cpu_seconds is not None]
        return cls(median([r.seconds for r in runs]), median(cpus) if len(cpus) == len(runs) else None)

    def over(self, other: Timing) -> Timing:
        cpu = self.cpu / other.cpu if self.cpu is not None and other.cpu else None
        return Timing(self.wall / other.wall, cpu)


def warn_if_crashed(label: str, result: Run, expected: Sequence[int] = (0, 1, 2)) -> None:
    if result.timed_out:
        PROBLEMS.append(f"{label}: killed after the time limit")
    elif result.returncode not in expected or "Traceback (most recent call last)" in result.stderr:
        tail = "\n    ".join(result.stderr.strip().splitlines()[-6:])
        PROBLEMS.append(f"{label}: exit code {result.returncode}\n    {tail}")
    else:
        return
    log(f"problem: {PROBLEMS[-1]}")


def package_dir() -> Path | None:
    """The folder of the gymmigrate package this interpreter imports."""
    import importlib.util

    spec = importlib.util.find_spec("gymmigrate")
    if spec is None or not spec.submodule_search_locations:
        return None
    return Path(next(iter(spec.submodule_search_locations)))


def engine_fingerprint() -> str | None:
    """A short hash of the installed gymmigrate package's source (to notice edits mid-run)."""
    import hashlib

    package = package_dir()
    if package is None:
        return None
    digest = hashlib.sha256()
    for path in sorted(package.rglob("*.py")):
        digest.update(str(path.relative_to(package)).encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()[:12]


def source_revision() -> str | None:
    """``git describe --always --dirty`` of the checkout this script sits in, if any."""
    try:
        completed = subprocess.run(
            ["git", "-C", str(HERE), "describe", "--always", "--dirty"], capture_output=True, text=True, timeout=30, check=False
        )
    except (OSError, subprocess.TimeoutExpired):
        return None
    return completed.stdout.strip() or None if completed.returncode == 0 else None


def load_average() -> float | None:
    """The 1-minute load average (other work on the machine skews every figure)."""
    try:
        return os.getloadavg()[0]
    except (AttributeError, OSError):
        return None


def gymmigrate_command() -> list[str]:
    beside = Path(sys.executable).parent / ("gymmigrate.exe" if os.name == "nt" else "gymmigrate")
    if beside.is_file():
        return [str(beside)]
    found = shutil.which("gymmigrate")
    return [found] if found else [sys.executable, "-m", "gymmigrate"]


def parse_command(listing: Path) -> list[str]:
    return [sys.executable, "-c", PARSE_SCRIPT, str(listing)]


def write_listing(path: Path, files: Sequence[Path]) -> Path:
    path.write_text("".join(f"{f}\n" for f in files), encoding="utf-8")
    return path


# --------------------------------------------------------------------------- report


def summarise_report(path: Path, total_lines: int) -> dict[str, object]:
    na: dict[str, object] = {
        "files_errored": None,
        "not_stable": None,
        "internal_errors": None,
        "review_items": None,
        "review_per_1000_lines": None,
        "notes": None,
        "notes_share": None,
        "review_per_rule": {},
        "duplicate_findings": None,
        "duplicate_examples": [],
        "errors": [],
    }
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        PROBLEMS.append(f"report: cannot read {path.name}: {exc}")
        return na
    out = dict(na)
    summary = data.get("summary") if isinstance(data, dict) else None
    files = data.get("files") if isinstance(data, dict) else None
    summary = summary if isinstance(summary, dict) else {}
    files = files if isinstance(files, list) else None

    if files is not None:
        errored = [f for f in files if isinstance(f, dict) and f.get("status") == "error"]
        messages = [str(f.get("error") or "") for f in errored]
        out["files_errored"] = len(errored)
        out["not_stable"] = sum("not stable" in m.lower() for m in messages)
        out["internal_errors"] = sum("internal error" in m.lower() for m in messages)
        out["errors"] = [{"path": f.get("path"), "error": f.get("error")} for f in errored]
    elif isinstance(summary.get("files_with_errors"), int):
        out["files_errored"] = summary["files_with_errors"]

    if isinstance(summary.get("review_items"), int):
        out["review_items"] = summary["review_items"]
    elif files is not None and all(isinstance(f, dict) and isinstance(f.get("review"), list) for f in files):
        out["review_items"] = sum(len(f["review"]) for f in files)
    if isinstance(out["review_items"], int) and total_lines:
        out["review_per_1000_lines"] = out["review_items"] * 1000 / total_lines
    if isinstance(summary.get("notes"), int):
        out["notes"] = summary["notes"]
        if isinstance(out["review_items"], int) and out["notes"] + out["review_items"]:
            out["notes_share"] = out["notes"] / (out["notes"] + out["review_items"])
    if files is not None:
        per_rule = Counter(str(r.get("rule")) for f in files if isinstance(f, dict) for r in f.get("review") or [])
        out["review_per_rule"] = dict(per_rule.most_common())

    if files is not None and all(isinstance(f, dict) and ("changes" in f or "review" in f) for f in files):
        # Reports list each finding once, under "review" or "notes" (by tier). Older ones
        # listed an assist finding under both "changes" and "review": take each identical
        # record there as many times as the longer list has it.
        sites: Counter[tuple[object, ...]] = Counter()
        for entry in files:
            def records(key: str, entry: dict = entry) -> Counter[str]:
                items = entry.get(key) or []
                return Counter(json.dumps(i, sort_keys=True) for i in items if isinstance(i, dict))

            merged = (records("changes") | records("review")) + records("notes")
            for record, count in merged.items():
                finding = json.loads(record)
                site = (entry.get("path"), finding.get("line"), finding.get("rule"), finding.get("message"))
                sites[site] += count
        duplicated = {site: n for site, n in sites.items() if n > 1}
        out["duplicate_findings"] = sum(n - 1 for n in duplicated.values())
        out["duplicate_examples"] = [
            {"path": s[0], "line": s[1], "rule": s[2], "message": s[3], "times": n}
            for s, n in sorted(duplicated.items(), key=lambda item: str(item[0]))[:5]
        ]
    return out


# --------------------------------------------------------------------------- main

START = time.perf_counter()
PROBLEMS: list[str] = []


def verdict(measured: float | None, target: float) -> str:
    if measured is None:
        return "n/a"
    return "ok" if measured <= target else "over"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeat", type=int, default=3, help="runs per timed figure; the median is shown (default 3)")
    parser.add_argument("--startup-runs", type=int, default=7, help="runs of the cold-start figure (default 7)")
    parser.add_argument("--cache", type=Path, default=DEFAULT_CACHE, help="download/unpack folder (default benchmarks/.cache)")
    parser.add_argument("--json", type=Path, metavar="PATH", help="also write the figures as JSON to PATH")
    parser.add_argument("--timeout", type=float, default=3600.0, help="kill any one subprocess after this many seconds")
    args = parser.parse_args()
    repeat = max(1, args.repeat)
    cache = args.cache.resolve()
    tool = gymmigrate_command()
    timeout = args.timeout

    # Users run with bytecode cached: a PYTHONDONTWRITEBYTECODE inherited from the shell
    # would have every timed process compile gymmigrate from source (a second of each
    # `check FILE`). Compile the package once, then let the timed processes read it.
    os.environ.pop("PYTHONDONTWRITEBYTECODE", None)
    package = package_dir()
    if package is not None:
        subprocess.run([sys.executable, "-m", "compileall", "-q", str(package)], capture_output=True, check=False)

    version = subprocess.run(tool + ["--version"], capture_output=True, text=True, check=False)
    if version.returncode != 0:
        sys.exit(f"`{' '.join(tool)} --version` failed:\n{version.stderr}")
    version_text = version.stdout.strip()
    fingerprint_start, revision_start = engine_fingerprint(), source_revision()
    load_start = load_average()

    roots = fetch_corpus(cache)
    gym = gym_set(list(roots.values()))
    if not gym.files:
        sys.exit("the Gym set is empty")
    log(f"Gym set: {len(gym.files)} files, {gym.total_lines} lines, {len(gym.excluded)} excluded")

    with tempfile.TemporaryDirectory(prefix="bench-real-") as scratch_name:
        scratch = Path(scratch_name)
        gym_listing = write_listing(scratch / "gym.txt", gym.files)
        gym_paths = [str(p) for p in gym.files]

        # 4. cold start (first: cheap, and a broken install shows at once)
        run(tool + ["--version"], timeout)
        run([sys.executable, "-c", "import libcst"], timeout)
        start_tool, start_libcst = [], []
        for _ in range(max(1, args.startup_runs)):
            start_tool.append(run(tool + ["--version"], timeout))
            start_libcst.append(run([sys.executable, "-c", "import libcst"], timeout))
        cold_start, import_libcst = Timing.of(start_tool), Timing.of(start_libcst)
        log(f"cold start {cold_start.wall * 1000:.0f} ms (import libcst {import_libcst.wall * 1000:.0f} ms)")

        # 1. + 6. rewrite --jobs 1 over the Gym set (its peak RSS too) against parsing it
        rewrite_runs, parse_runs = [], []
        for index in range(repeat):
            result = run(tool + ["rewrite", "--diff", "--jobs", "1", *gym_paths], timeout)
            warn_if_crashed("rewrite --diff --jobs 1 (Gym set)", result)
            rewrite_runs.append(result)
            parsed = run(parse_command(gym_listing), timeout)
            warn_if_crashed("libcst parse (Gym set)", parsed, expected=(0,))
            parse_runs.append(parsed)
            log(f"rewrite --jobs 1 run {index + 1}/{repeat}: {result.seconds:.1f} s (parse {parsed.seconds:.2f} s)")
        rewrite, parse = Timing.of(rewrite_runs), Timing.of(parse_runs)
        rewrite_ratio = rewrite.over(parse)

        half = gym.files[::2]
        half_run = run(tool + ["rewrite", "--diff", "--jobs", "1", *map(str, half)], timeout)
        warn_if_crashed("rewrite --diff --jobs 1 (half the Gym set)", half_run)
        rss_values = [r.maxrss_bytes for r in rewrite_runs if r.maxrss_bytes is not None]
        rss_full = max(rss_values) if rss_values else None
        rss_half = half_run.maxrss_bytes
        rss_growth = rss_full / rss_half if rss_full and rss_half else None
        log(f"half set: {half_run.seconds:.1f} s")

        # 2. mixed tree, default jobs, against parsing the whole tree
        mixed_root = scratch / "mixed"
        mixed_files, filler_files, filler_lines = build_mixed_tree(mixed_root, gym, cache / "src")
        mixed_listing = write_listing(scratch / "mixed.txt", mixed_files)
        mixed_runs, mixed_parse_runs = [], []
        for index in range(repeat):
            result = run(tool + ["rewrite", "--diff", str(mixed_root)], timeout)
            warn_if_crashed("rewrite --diff (mixed tree)", result)
            mixed_runs.append(result)
            parsed = run(parse_command(mixed_listing), timeout)
            warn_if_crashed("libcst parse (mixed tree)", parsed, expected=(0,))
            mixed_parse_runs.append(parsed)
            log(f"mixed tree run {index + 1}/{repeat}: {result.seconds:.1f} s (parse {parsed.seconds:.2f} s)")
        mixed, mixed_parse = Timing.of(mixed_runs), Timing.of(mixed_parse_runs)
        mixed_ratio = mixed.over(mixed_parse)

        # 5. the JSON report over the Gym set
        report_path = scratch / "report.json"
        report_run = run(tool + ["rewrite", "--diff", "--report", str(report_path), *gym_paths], timeout)
        warn_if_crashed("rewrite --diff --report (Gym set)", report_run)
        report = summarise_report(report_path, gym.total_lines)
        log(f"report run: {report_run.seconds:.1f} s")

        # 3. check, one process per file: every file once, then the slowest again
        once: dict[Path, Run] = {}
        for number, path in enumerate(gym.files, 1):
            result = run(tool + ["check", str(path)], timeout)
            warn_if_crashed(f"check {path.relative_to(cache)}", result)
            once[path] = result
            if number % 25 == 0 or number == len(gym.files):
                log(f"check once: {number}/{len(gym.files)}")
        low, high = CHECK_LINES
        sized = [p for p in gym.files if low <= gym.lines[p] <= high]

        def slowest(paths: list[Path]) -> list[Path]:
            return sorted(paths, key=lambda p: once[p].seconds, reverse=True)[:3]

        top_sized, top_any = slowest(sized), slowest(gym.files)
        again: dict[Path, Timing] = {}
        for path in dict.fromkeys(top_sized + top_any):
            runs = [once[path]] + [run(tool + ["check", str(path)], timeout) for _ in range(repeat - 1)]
            again[path] = Timing.of(runs)
        slowest_three = sorted(((p, again[p]) for p in top_sized), key=lambda item: item[1].wall, reverse=True)
        check_three = slowest_three[0][1] if slowest_three else None
        slowest_any_path = max(top_any, key=lambda p: again[p].wall)
        check_any = again[slowest_any_path]
        log("check: done")

    total_seconds = time.perf_counter() - START
    fingerprint_end, revision_end = engine_fingerprint(), source_revision()
    load_end = load_average()
    if fingerprint_start != fingerprint_end:
        PROBLEMS.append(
            f"the engine's source changed during the run (package hash {fingerprint_start} -> {fingerprint_end}, "
            f"revision {revision_start} -> {revision_end}): the figures mix versions"
        )

    def show(value: float | None, fmt: str) -> str:
        return "n/a" if value is None else fmt.format(value)

    def cpu(timing: Timing | None, fmt: str, scale: float = 1.0) -> str:
        return show(None if timing is None or timing.cpu is None else timing.cpu * scale, fmt)

    mib = 1024 * 1024
    relative = cache / "src"
    rows = [
        ("rewrite ratio (--jobs 1)", f"{rewrite_ratio.wall:.1f}x", cpu(rewrite_ratio, "{:.1f}x"), f"<= {TARGET_REWRITE_RATIO:.1f}x", verdict(rewrite_ratio.wall, TARGET_REWRITE_RATIO)),
        ("  gymmigrate rewrite --diff", f"{rewrite.wall:.2f} s", cpu(rewrite, "{:.2f} s"), "", ""),
        ("  libcst parse", f"{parse.wall:.2f} s", cpu(parse, "{:.2f} s"), "", ""),
        ("mixed-tree ratio (default jobs)", f"{mixed_ratio.wall:.2f}x", cpu(mixed_ratio, "{:.2f}x"), f"<= {TARGET_MIXED_RATIO:.2f}x", verdict(mixed_ratio.wall, TARGET_MIXED_RATIO)),
        ("  gymmigrate rewrite --diff", f"{mixed.wall:.2f} s", cpu(mixed, "{:.2f} s"), "", ""),
        ("  libcst parse", f"{mixed_parse.wall:.2f} s", cpu(mixed_parse, "{:.2f} s"), "", ""),
        (
            f"check, 3 slowest of {low}-{high} lines",
            " / ".join(f"{t.wall:.2f}" for _, t in slowest_three) + " s" if slowest_three else "n/a",
            " / ".join(cpu(t, "{:.2f}") for _, t in slowest_three) + " s" if slowest_three else "n/a",
            f"<= {TARGET_CHECK_SLOWEST_THREE:.1f} s",
            verdict(check_three.wall if check_three else None, TARGET_CHECK_SLOWEST_THREE),
        ),
        ("check, slowest file", f"{check_any.wall:.2f} s", cpu(check_any, "{:.2f} s"), f"<= {TARGET_CHECK_ANY:.1f} s", verdict(check_any.wall, TARGET_CHECK_ANY)),
        ("cold start (--version)", f"{cold_start.wall * 1000:.0f} ms", cpu(cold_start, "{:.0f} ms", 1000), f"<= {TARGET_COLD_START * 1000:.0f} ms", verdict(cold_start.wall, TARGET_COLD_START)),
        ("  python -c 'import libcst'", f"{import_libcst.wall * 1000:.0f} ms", cpu(import_libcst, "{:.0f} ms", 1000), "", ""),
        (
            "peak RSS full / half set",
            f"{show(rss_full and rss_full / mib, '{:.0f}')} / {show(rss_half and rss_half / mib, '{:.0f}')} MiB",
            "",
            f"flat (<= {TARGET_RSS_GROWTH:.2f}x)",
            "n/a" if rss_growth is None else ("flat" if rss_growth <= TARGET_RSS_GROWTH else "grows"),
        ),
    ]
    header = ("figure", "measured", "cpu time", "target", "verdict")
    widths = [max(len(row[i]) for row in [header, *rows]) for i in range(len(header))]
    print()
    print(f"{version_text} (revision {revision_end or 'n/a'}, package hash {fingerprint_end or 'n/a'})")
    print(f"corpus: {', '.join(REQUIREMENTS)}")
    print()
    for name, measured, cpu_text, target, mark in [header, *rows]:
        print(
            f"{name:<{widths[0]}}  {measured:>{widths[1]}}  {cpu_text:>{widths[2]}}  {target:<{widths[3]}}  {mark}".rstrip()
        )
    print("(measured: wall time, the figure the target applies to; cpu time: user + system of the process")
    print(" and its workers added up, less sensitive to other load on the machine)")
    print()
    print(f"Gym set: {len(gym.files)} files, {gym.total_lines} lines; {len(gym.excluded)} excluded (do not parse as Python 3.11)")
    for path in gym.excluded:
        print(f"  excluded: {path.relative_to(cache)}")
    print(f"mixed tree: {len(gym.files)} Gym files + {filler_files} stdlib files ({filler_lines} lines)")
    print(f"check: {len(sized)} files of {low}-{high} lines; slowest (wall, median of {repeat}):")
    for path, timing in slowest_three:
        print(f"  {timing.wall:.2f} s  {path.relative_to(relative)} ({gym.lines[path]} lines)")
    print(f"  slowest overall: {check_any.wall:.2f} s  {slowest_any_path.relative_to(relative)} ({gym.lines[slowest_any_path]} lines)")
    per_thousand = report["review_per_1000_lines"]
    print(
        "report: "
        f"files errored {show(report['files_errored'], '{}')}, "
        f"not stable {show(report['not_stable'], '{}')}, "
        f"internal errors {show(report['internal_errors'], '{}')}, "
        f"review items {show(per_thousand, '{:.1f}')} per 1,000 lines ({show(report['review_items'], '{}')}), "
        f"duplicate findings {show(report['duplicate_findings'], '{}')}, "
        f"notes {show(report['notes'], '{}')} ({show(report['notes_share'], '{:.0%}')} of all findings)"
    )
    if report["review_per_rule"]:
        print("  review items per rule: " + ", ".join(f"{rule} {n}" for rule, n in report["review_per_rule"].items()))  # type: ignore[union-attr]
    for error in report["errors"]:  # type: ignore[union-attr]
        print(f"  error: {error['path']}: {error['error']}")
    for example in report["duplicate_examples"]:  # type: ignore[union-attr]
        print(f"  duplicate x{example['times']}: {example['path']}:{example['line']}: {example['rule']} {example['message']}")
    print(
        f"machine: {os.cpu_count()} cores, Python {platform.python_version()}, load average "
        f"{show(load_start, '{:.1f}')} at start, {show(load_end, '{:.1f}')} at end; {repeat} repeats; took {total_seconds:.0f} s"
    )
    if PROBLEMS:
        print(f"problems ({len(PROBLEMS)}):")
        for problem in PROBLEMS[:20]:
            print(f"  {problem}")

    if args.json:

        def figure(measured: Timing, target: float, **extra: object) -> dict[str, object]:
            return {"measured": measured.wall, "cpu": measured.cpu, "target": target, "verdict": verdict(measured.wall, target), **extra}

        figures = {
            "rewrite_ratio": figure(rewrite_ratio, TARGET_REWRITE_RATIO, gymmigrate=vars(rewrite), parse=vars(parse)),
            "mixed_tree_ratio": figure(mixed_ratio, TARGET_MIXED_RATIO, gymmigrate=vars(mixed), parse=vars(mixed_parse)),
            "check_slowest_three_seconds": {
                "measured": [
                    {"path": str(p.relative_to(relative)), "lines": gym.lines[p], "seconds": t.wall, "cpu": t.cpu}
                    for p, t in slowest_three
                ],
                "target": TARGET_CHECK_SLOWEST_THREE,
                "verdict": verdict(check_three.wall if check_three else None, TARGET_CHECK_SLOWEST_THREE),
            },
            "check_slowest_file_seconds": figure(check_any, TARGET_CHECK_ANY, path=str(slowest_any_path.relative_to(relative))),
            "cold_start_seconds": figure(cold_start, TARGET_COLD_START, import_libcst=vars(import_libcst)),
            "peak_rss_bytes": {"full": rss_full, "half": rss_half, "growth": rss_growth, "target_growth": TARGET_RSS_GROWTH},
        }
        document = {
            "benchmark": "bench_real",
            "figures": figures,
            "corpus": {
                "requirements": list(REQUIREMENTS),
                "gym_files": len(gym.files),
                "gym_lines": gym.total_lines,
                "excluded": [str(p.relative_to(cache)) for p in gym.excluded],
                "mixed_stdlib_files": filler_files,
                "mixed_stdlib_lines": filler_lines,
                "check_sized_files": len(sized),
            },
            "report": report,
            "check_once": {str(p.relative_to(relative)): {"seconds": r.seconds, "cpu": r.cpu_seconds} for p, r in once.items()},
            "engine": {
                "version": version_text,
                "revision_start": revision_start,
                "revision_end": revision_end,
                "package_hash_start": fingerprint_start,
                "package_hash_end": fingerprint_end,
            },
            "environment": {
                "cpus": os.cpu_count(),
                "load_start": load_start,
                "load_end": load_end,
                "python": platform.python_version(),
                "platform": platform.platform(),
                "repeat": repeat,
            },
            "total_seconds": total_seconds,
            "problems": PROBLEMS,
        }
        args.json.write_text(json.dumps(document, indent=2) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
