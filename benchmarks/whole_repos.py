"""Benchmark: whole repositories, migrated in one command, judged by their own test suites.

    python benchmarks/whole_repos.py [--repos NAME,...] [--stages legacy,human,gymmigrate]
                                     [--cache DIR] [--sources DIR] [--mirrors DIR]
                                     [--timeout SECONDS] [--json PATH]

Not part of the test suite. For each repository below it lays out three trees and runs the
repository's own pytest suite on each, every tree in a fresh virtual environment:

  legacy      the last commit before the project's own Gymnasium port, installed with the
              legacy gym of its era (``legacy_pre``: old gym releases do not build on Python
              3.11 with today's setuptools, so they are built with ``setuptools<66``,
              ``wheel<0.40`` and ``--no-build-isolation``; the constraints in
              ``legacy_constraints`` keep the rest of the era, e.g. ``numpy<1.24``: gym 0.26
              uses ``np.bool8``, deprecated in 1.24; these first installs take
              ``--ignore-requires-python``: PettingZoo 1.21, the last on gym, declares
              ``<3.11`` yet runs on it).
  human       the project's own port (the commit that moved it to Gymnasium), where one
              exists, installed against Gymnasium 1.4 (``gymnasium==1.4.0`` as a constraint).
  gymmigrate  a copy of the legacy tree after ``gymmigrate rewrite .`` over the WHOLE tree
              (package, tests, examples, setup.py / pyproject.toml / requirements), installed
              against Gymnasium 1.4 in a venv where gymmigrate itself is installed from the
              checkout this script runs from.

Each tree is installed as its dependency files declare (``pip install TREE[EXTRAS]``); the
table says whether that worked. When it does not, the package is installed with
``--no-deps`` and the repository's ``fallback`` requirements instead, so its tests still
run (the table marks that ``fallback``). Then ``python -m pytest`` runs from the tree with
``--timeout`` (pytest-timeout) and a JUnit XML report, from which every test's outcome is
read. Printed per repository: declared install yes/no, passed/failed/errors/skipped per
stage, and every test that passed on legacy but not after gymmigrate (its first error line;
the full log is kept next to the tree).

Sources (pinned below; nothing is ever committed to this repository):
  ma-gym      github.com/koulanurag/ma-gym         legacy 877ed64 (0.0.14, gym<=0.20; it
              never moved to Gymnasium: no human port)
  minigrid    github.com/Farama-Foundation/Minigrid legacy f2a30bd1 (MiniGrid 1.2.1, gym 0.26)
              human 4c409330 "migrate to gymnasium (#239)"
  gym-minigrid  the same repository at v1.1.0 = 14bd9030 (gym_minigrid 1.1.0, gym 0.25:
              one done flag, reset(return_info=...); its port went through gym 0.26 first,
              so there is no human port of this tree to Gymnasium)
  mo-gym      github.com/Farama-Foundation/MO-Gymnasium legacy f66ecd97 (mo-gym 0.3.0,
              gym 0.26) human 48e3b520 "Replace gym for gymnasium (#16)"
  supersuit   github.com/Farama-Foundation/SuperSuit legacy f35fd124 (3.6.0, gym 0.26,
              PettingZoo 1.21) human 3707553f "gym -> gymnasium and pettingzoo bump"
  rware       github.com/semitable/robotic-warehouse legacy e4b4d542 (1.0.3, gym==0.21)
              human ecfde864, the last commit of its port (pull request #30, from bbec2db
              "update RWARE environment for gymnasium integration")
  lbforaging  github.com/semitable/lb-foraging legacy cf7a012f (1.1.1, gym==0.21) human
              147df639, the last commit of its port (pull request #29: 0828c10 moved the
              package, 0b405f4 its tests)
  nasim       github.com/Jjschwartz/NetworkAttackSimulator legacy 269d0589 (0.10.1,
              gym>=0.25: built on gym 0.25.2, its step already returns five values) human
              dc471917 "v0.11.0 release" (the move to Gymnasium)
  neurogym    github.com/neurogym/neurogym          legacy 52d642fb (0.0.2, gym>=0.20,<0.25:
              run on 0.24.1, the newest its CI tested) human 4577e2fc, the merge of pull
              request #5 that finished its port (76e3a501, #9, replaced the imports only);
              the port moved the suite from neurogym/tests to tests (``human_tests``)

How the trees are obtained, first match wins:
  --sources DIR   already laid-out trees: DIR/NAME/legacy and DIR/NAME/human.
  --mirrors DIR   bare git clones: DIR/OWNER+NAME/repo, DIR/OWNER+NAME or DIR/NAME.git;
                  the pinned commits are laid out with ``git archive COMMIT | tar -x``.
  otherwise       ``git clone --bare https://github.com/OWNER/NAME`` into CACHE/mirrors.
Trees, venvs and logs live under --cache (default /work/cache/repos), outside the
repository. A venv is reused while its stage, its requirements and the tree's dependency
files are unchanged; the package itself (and gymmigrate) is reinstalled on every run, and
the gymmigrate tree is copied and rewritten afresh on every run.
"""

from __future__ import annotations

import argparse
import dataclasses
import hashlib
import json
import os
import shutil
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
GYMNASIUM = "gymnasium==1.4.0"
LEGACY_BUILD = ["setuptools<66", "wheel<0.40"]
DEP_FILES = ("setup.py", "setup.cfg", "pyproject.toml", "requirements.txt", "test_requirements.txt")


@dataclasses.dataclass(frozen=True)
class Repo:
    name: str
    github: str  # OWNER/NAME
    legacy: str  # full commit
    human: str | None  # full commit of the project's own Gymnasium port
    extras: str  # extras to install with the package ("" for none)
    tests: tuple[str, ...]  # pytest arguments (paths), relative to the tree
    legacy_pre: tuple[str, ...]  # built first, without build isolation (old gym)
    legacy_constraints: tuple[str, ...]
    legacy_fallback: tuple[str, ...]
    new_fallback: tuple[str, ...]  # for the human port and gymmigrate's tree
    new_constraints: tuple[str, ...] = (GYMNASIUM,)
    also: tuple[str, ...] = ()  # optional extras the tests need, installed in every stage
    # every stage's suite runs on a virtual X display (``xvfb-run -a``): for tests that open
    # a window, which abort the interpreter (and the whole suite) without a display
    display: bool = False
    # the human port's test paths, when the port moved the tests (None: the same as ``tests``)
    human_tests: tuple[str, ...] | None = None


REPOS = (
    Repo(
        name="ma-gym",
        github="koulanurag/ma-gym",
        legacy="877ed64f72195d9531560c5f29a83755763b7174",
        human=None,
        extras="test",
        tests=("tests",),
        legacy_pre=("gym==0.20.0",),
        legacy_constraints=("numpy<1.24", "pytest<8"),
        legacy_fallback=("gym==0.20.0", "scipy", "numpy<1.24", "pyglet<=1.5.27", "pillow", "six",
                         "pytest<8", "pytest_cases"),
        new_fallback=(GYMNASIUM, "scipy", "numpy", "pyglet<=1.5.27", "pillow", "six",
                      "pytest<8", "pytest_cases"),
    ),
    Repo(
        name="minigrid",
        github="Farama-Foundation/Minigrid",
        legacy="f2a30bd1b28058fde0db723aa271b595af439548",
        human="4c409330dfe8625fcbca97f76e8b0575a18907c1",
        extras="testing",
        tests=("tests",),
        legacy_pre=("gym==0.26.2",),
        legacy_constraints=("numpy<1.24",),
        legacy_fallback=("gym==0.26.2", "numpy<1.24", "matplotlib", "pytest<8"),
        new_fallback=(GYMNASIUM, "numpy", "matplotlib", "pytest<8"),
    ),
    Repo(
        name="gym-minigrid",  # the same project a step earlier: gym 0.25, one done flag
        github="Farama-Foundation/Minigrid",
        legacy="14bd9030d7f9cf691d58e7a0929bc98f9a40172f",
        human=None,
        extras="testing",
        tests=("tests",),
        legacy_pre=("gym==0.25.2",),
        legacy_constraints=("numpy<1.24",),
        legacy_fallback=("gym==0.25.2", "numpy<1.24", "matplotlib", "pytest<8"),
        new_fallback=(GYMNASIUM, "numpy", "matplotlib", "pytest<8"),
    ),
    Repo(
        name="mo-gym",
        github="Farama-Foundation/MO-Gymnasium",
        legacy="f66ecd97cb30c255b502001b614eff9767872b8d",
        human="48e3b52014a63acb36ba095e3419d33af7fceba6",
        # [mujoco] as each tree declares it, for the half-cheetah and hopper tests (the
        # migrated and human trees add imageio, which Gymnasium 1.x's MuJoCo renderer
        # imports); one MuJoCo for every stage
        extras="testing,mujoco",
        tests=("tests",),
        legacy_pre=("gym==0.26.2",),
        legacy_constraints=("numpy<1.24", "mujoco==2.3.7"),
        legacy_fallback=("gym==0.26.2", "numpy<1.24", "pygame", "scipy", "pymoo", "mujoco", "pytest<8"),
        new_fallback=(GYMNASIUM, "numpy", "pygame", "scipy", "pymoo", "mujoco", "imageio", "pytest<8"),
        new_constraints=(GYMNASIUM, "mujoco==2.3.7"),
        # Gymnasium 1.x's check_env re-makes an env in each of its render modes and resets
        # it: MuJoCo's "human" mode opens a glfw window, and glfw aborts the interpreter
        # without a display (MUJOCO_GL=egl/osmesa only serve the off-screen modes)
        display=True,
    ),
    Repo(
        name="supersuit",
        github="Farama-Foundation/SuperSuit",
        legacy="f35fd124ca364562a676a62c28b23d0695edd955",
        human="3707553f3aa22e51577c346961705ca8b97f6b8d",
        extras="",
        tests=("test",),
        # PettingZoo 1.21's [butterfly] extra pins pygame 2.1.0, which has no 3.11 wheel
        legacy_pre=("gym==0.26.2", "pettingzoo==1.21.0", "pygame", "pymunk"),
        legacy_constraints=("numpy<1.24", "pettingzoo==1.21.0"),
        legacy_fallback=("gym==0.26.2", "numpy<1.24", "pettingzoo==1.21.0", "tinyscaler",
                         "pygame", "pymunk", "opencv-python-headless", "pytest<8"),
        # mpe2: where PettingZoo 1.27's MPE envs live (the migration imports them from there)
        new_fallback=(GYMNASIUM, "numpy", "pettingzoo[butterfly]==1.27.*", "mpe2", "tinyscaler", "pygame",
                      "pymunk", "opencv-python-headless", "pytest<8"),
    ),
    Repo(
        name="rware",
        github="semitable/robotic-warehouse",
        legacy="e4b4d542c221ccc38b999bed11ddf66c3b8e4359",
        human="ecfde8649f6acd2f1d320ba3614a9583d68cd0aa",
        extras="test",
        tests=("tests",),
        legacy_pre=("gym==0.21.0",),
        legacy_constraints=("numpy<1.24", "pytest<8"),
        legacy_fallback=("gym==0.21.0", "numpy<1.24", "pyglet<2", "networkx", "pytest<8"),
        new_fallback=(GYMNASIUM, "numpy", "pyglet<2", "networkx", "pytest<8"),
        # @pytest.mark.parametrize("time_limit,", [1, 100, 200]): pytest 8 reads the trailing
        # comma as a tuple of names and refuses the module; the legacy stage has pytest<8
        new_constraints=(GYMNASIUM, "pytest<8"),
    ),
    Repo(
        name="lbforaging",
        github="semitable/lb-foraging",
        legacy="cf7a012f3a54dea0dc6ce86d264a28b2b01d0a0c",
        human="147df6399fedeb23b4ed5735b411cb5b38cb9b60",
        extras="test",
        tests=("tests",),
        legacy_pre=("gym==0.21.0",),
        legacy_constraints=("numpy<1.24", "pytest<8"),
        legacy_fallback=("gym==0.21.0", "numpy<1.24", "pyglet<2", "six", "pytest<8"),
        new_fallback=(GYMNASIUM, "numpy", "pyglet<2", "six", "pytest<8"),
    ),
    Repo(
        name="nasim",
        github="Jjschwartz/NetworkAttackSimulator",
        legacy="269d0589db64bb5b80a6390dbffd0453f652c4aa",
        human="dc471917ebbb91d8e22749342c36952e5603c2cc",
        extras="test",
        tests=("test",),
        legacy_pre=("gym==0.25.2",),
        legacy_constraints=("numpy<1.24", "pytest<8"),
        legacy_fallback=("gym==0.25.2", "numpy<1.24", "networkx", "matplotlib", "pyyaml", "prettytable", "pytest<8"),
        new_fallback=(GYMNASIUM, "numpy", "networkx", "matplotlib", "pyyaml", "prettytable", "pytest<8"),
    ),
    Repo(
        name="neurogym",
        github="neurogym/neurogym",
        legacy="52d642fba4d9401c1b5dd29063f5a14526000ef2",
        human="4577e2fc7cd4a1345fa1dd391240bb0fb8ad406c",
        extras="",
        # its whole suite, which steps every registered env; the port moved it to tests/
        tests=("neurogym/tests",),
        human_tests=("tests",),
        # gym>=0.20.0,<0.25 as declared: pip's choice is 0.24.1, the newest of its CI matrix
        legacy_pre=("gym==0.24.1",),
        legacy_constraints=("numpy<1.24", "pytest<8"),
        legacy_fallback=("gym==0.24.1", "numpy<1.24", "matplotlib", "pytest<8"),
        new_fallback=(GYMNASIUM, "numpy", "matplotlib", "pytest<8"),
    ),
)

TEST_TOOLS = ("pytest-timeout",)


def log(msg: str) -> None:
    print(f"[{time.strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


def run(cmd, cwd=None, logf: Path | None = None, timeout: float | None = None, env=None) -> int:
    """Run CMD; append its output to LOGF; return the exit code (124 on time-out)."""
    cmd = [str(c) for c in cmd]
    try:
        proc = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              timeout=timeout, env=env)
        rc, text = proc.returncode, proc.stdout.decode(errors="replace")
    except subprocess.TimeoutExpired as exc:
        rc = 124
        text = (exc.stdout or b"").decode(errors="replace") + f"\n!! timed out after {timeout} s\n"
    if logf:
        # pip's notes about index locations it cannot read are noise here
        kept = [line for line in text.splitlines(keepends=True)
                if "is ignored: it is neither a file nor a directory" not in line]
        with open(logf, "a") as out:
            out.write(f"\n$ {' '.join(cmd)}  (cwd={cwd})\n{''.join(kept)}")
    return rc


# --- sources ---------------------------------------------------------------------------

def find_mirror(repo: Repo, mirrors: Path | None, cache: Path) -> Path:
    owner, name = repo.github.split("/")
    candidates = []
    if mirrors:
        candidates += [mirrors / f"{owner}+{name}" / "repo", mirrors / f"{owner}+{name}",
                       mirrors / f"{name}.git"]
    local = cache / "mirrors" / f"{owner}+{name}.git"
    candidates.append(local)
    for c in candidates:
        if (c / "HEAD").is_file():
            return c
    log(f"cloning {repo.github} into {local}")
    local.parent.mkdir(parents=True, exist_ok=True)
    subprocess.run(["git", "clone", "--bare", "--quiet", f"https://github.com/{repo.github}",
                    str(local)], check=True)
    return local


def lay_out(repo: Repo, commit: str, dest: Path, mirrors: Path | None, cache: Path) -> None:
    if (dest / ".laid-out").read_text().strip() == commit if (dest / ".laid-out").is_file() else False:
        return
    shutil.rmtree(dest, ignore_errors=True)
    dest.mkdir(parents=True)
    git_dir = find_mirror(repo, mirrors, cache)
    # a mirror may lack its largest blobs (images, media): lay out every file it has
    listing = subprocess.run(["git", f"--git-dir={git_dir}", "ls-tree", "-r", "-z", commit],
                             check=True, capture_output=True).stdout.split(b"\0")
    entries = [e.split(b"\t", 1) for e in listing if e]
    check = subprocess.run(["git", f"--git-dir={git_dir}", "cat-file", "--batch-check"],
                           input=b"".join(meta.split()[2] + b"\n" for meta, _ in entries),
                           check=True, capture_output=True).stdout.split(b"\n")
    paths = [path.decode() for (meta, path), ok in zip(entries, check) if not ok.endswith(b"missing")]
    missing = len(entries) - len(paths)
    if missing:
        log(f"{repo.name}: {missing} file(s) of {commit[:8]} absent from the mirror, left out")
    archive = subprocess.run(["git", f"--git-dir={git_dir}", "archive", commit, "--", *paths],
                             check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(dest)], input=archive, check=True)
    (dest / ".laid-out").write_text(commit + "\n")


def source_tree(repo: Repo, stage: str, args) -> Path | None:
    """The pristine tree of STAGE ('legacy' or 'human'), or None when there is none."""
    if args.sources:
        tree = args.sources / repo.name / stage
        return tree if tree.is_dir() else None
    commit = repo.legacy if stage == "legacy" else repo.human
    if commit is None:
        return None
    tree = args.cache / "trees" / repo.name / stage
    lay_out(repo, commit, tree, args.mirrors, args.cache)
    return tree


# --- venvs -----------------------------------------------------------------------------

def venv_key(repo: Repo, stage: str, tree: Path) -> str:
    h = hashlib.sha256()
    if stage == "legacy":
        reqs = (repo.legacy_pre, repo.legacy_constraints, repo.legacy_fallback, LEGACY_BUILD)
    else:
        reqs = (repo.new_constraints, repo.new_fallback)
    h.update(repr((stage, repo.extras, repo.also, reqs, TEST_TOOLS)).encode())
    for name in DEP_FILES:
        p = tree / name
        if p.is_file():
            h.update(name.encode() + b"\0" + p.read_bytes())
    return h.hexdigest()[:12]


def prepare_venv(repo: Repo, stage: str, tree: Path, args, logf: Path) -> tuple[Path, dict]:
    """A venv with TREE's dependencies; returns it and the install facts."""
    key = venv_key(repo, stage, tree)
    venv = args.cache / "venvs" / f"{repo.name}-{stage}-{key}"
    py = venv / "bin" / "python"
    pip = [py, "-m", "pip", "--disable-pip-version-check"]
    ready = venv / ".ready.json"
    legacy = stage == "legacy"
    if ready.is_file():
        facts = json.loads(ready.read_text())
    else:
        shutil.rmtree(venv, ignore_errors=True)
        log(f"{repo.name}/{stage}: creating venv {venv.name}")
        subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
        constraints = venv / "constraints.txt"
        constraints.write_text("\n".join(repo.legacy_constraints if legacy else repo.new_constraints) + "\n")
        if legacy:
            run(pip + ["install", "-q", *LEGACY_BUILD], logf=logf)
            rc = run(pip + ["install", "-q", "--no-build-isolation", "--ignore-requires-python",
                            "-c", constraints, *repo.legacy_pre], logf=logf)
            if rc:
                log(f"{repo.name}/{stage}: legacy gym ({' '.join(repo.legacy_pre)}) did not install")
        else:
            run(pip + ["install", "-q", "-c", constraints, GYMNASIUM], logf=logf)
        if stage == "gymmigrate":
            # gymmigrate's own dependencies; the package itself is reinstalled each run
            run(pip + ["install", "-q", "-c", constraints, str(ROOT)], logf=logf)
        target = f"{tree}[{repo.extras}]" if repo.extras else str(tree)
        log(f"{repo.name}/{stage}: pip install {target} (as declared)")
        declared = run(pip + ["install", "-q", "-c", constraints, target], logf=logf,
                       timeout=1800) == 0
        fallback = False
        if not declared:
            reqs = repo.legacy_fallback if legacy else repo.new_fallback
            log(f"{repo.name}/{stage}: declared install failed; fallback: {' '.join(reqs)}")
            era = ["--ignore-requires-python"] if legacy else []
            fallback = run(pip + ["install", "-q", *era, "-c", constraints, *reqs], logf=logf,
                           timeout=1800) == 0
        if repo.also:
            run(pip + ["install", "-q", "-c", constraints, *repo.also], logf=logf)
        run(pip + ["install", "-q", "-c", constraints, *TEST_TOOLS], logf=logf)
        if run([py, "-c", "import pytest"], logf=logf):
            run(pip + ["install", "-q", "pytest<8"], logf=logf)
        facts = {"declared": declared, "fallback": fallback}
        ready.write_text(json.dumps(facts))
    # the package under test, always afresh (no deps: those are settled above)
    run(pip + ["install", "-q", "--no-deps", "--force-reinstall", str(tree)], logf=logf)
    if stage == "gymmigrate":
        run(pip + ["install", "-q", "--no-deps", "--force-reinstall", str(ROOT)], logf=logf)
    facts["versions"] = subprocess.run(
        [py, "-c", "import importlib.metadata as m\n"
         "for d in ('gym','gymnasium','pettingzoo','numpy','pytest'):\n"
         "    try: print(d, m.version(d))\n"
         "    except Exception: pass"],
        capture_output=True, text=True).stdout.split("\n")
    facts["versions"] = [v for v in facts["versions"] if v]
    return venv, facts


# --- tests -----------------------------------------------------------------------------

def read_junit(path: Path) -> dict[str, tuple[str, str]]:
    """test id -> (outcome, first line of its message)."""
    out: dict[str, tuple[str, str]] = {}
    if not path.is_file():
        return out
    for case in ET.parse(path).getroot().iter("testcase"):
        tid = f"{case.get('classname', '')}::{case.get('name', '')}"
        outcome, msg = "passed", ""
        for child in case:
            if child.tag in ("failure", "error", "skipped"):
                outcome = {"failure": "failed", "error": "error", "skipped": "skipped"}[child.tag]
                e_lines = [ln[1:].strip() for ln in (child.text or "").splitlines()
                           if ln.startswith("E ")]
                msg = (e_lines[0] if e_lines else
                       (child.get("message") or "").strip().split("\n")[0])[:200]
                break
        if tid in out and out[tid][0] != "passed":
            continue  # an error in teardown after a failure: keep the first
        out[tid] = (outcome, msg)
    return out


def run_tests(repo: Repo, stage: str, tree: Path, venv: Path, args, logf: Path) -> dict:
    junit = logf.parent / f"{stage}-junit.xml"
    junit.unlink(missing_ok=True)
    env = dict(os.environ, SDL_VIDEODRIVER="dummy", SDL_AUDIODRIVER="dummy", MPLBACKEND="Agg",
               PYTHONDONTWRITEBYTECODE="1")
    env.pop("PYTHONPATH", None)
    display = repo.display and shutil.which("xvfb-run") is not None
    if repo.display and not display:
        log(f"{repo.name}/{stage}: no xvfb-run: tests that open a window abort without a display")
    cmd = [*(["xvfb-run", "-a"] if display else []), venv / "bin" / "python", "-m", "pytest", "-p", "no:cacheprovider", "-q", "-rfE",
           "--tb=short", "--continue-on-collection-errors", f"--timeout={args.timeout}", f"--junitxml={junit}",
           *(repo.human_tests if stage == "human" and repo.human_tests else repo.tests)]
    log(f"{repo.name}/{stage}: pytest")
    t0 = time.monotonic()
    rc = run(cmd, cwd=tree, logf=logf, timeout=args.suite_timeout, env=env)
    cases = read_junit(junit)
    counts = {k: sum(1 for o, _ in cases.values() if o == k)
              for k in ("passed", "failed", "error", "skipped")}
    return {"rc": rc, "seconds": round(time.monotonic() - t0, 1), "counts": counts, "cases": cases,
            "virtual_display": display}


def migrate(repo: Repo, legacy_tree: Path, dest: Path, venv: Path, logf: Path) -> dict:
    shutil.rmtree(dest, ignore_errors=True)
    shutil.copytree(legacy_tree, dest, symlinks=True)
    report = logf.parent / "gymmigrate-report.json"
    t0 = time.monotonic()
    out = logf.parent / "gymmigrate-rewrite.log"
    out.write_text("")
    rc = run([venv / "bin" / "gymmigrate", "rewrite", ".", "--report", report], cwd=dest,
             logf=out)
    text = out.read_text()
    with open(logf, "a") as f:
        f.write(text)
    errors = [line.strip() for line in text.splitlines() if line.startswith("error:")]
    changed = subprocess.run(["diff", "-rq", str(legacy_tree), str(dest)],
                             capture_output=True, text=True).stdout.count("\n")
    subprocess.run(f"diff -ru {legacy_tree} {dest} > {logf.parent / 'gymmigrate.diff'}",
                   shell=True)
    return {"rc": rc, "seconds": round(time.monotonic() - t0, 1), "files_changed": changed,
            "errors": errors}


# --- driver ----------------------------------------------------------------------------

def bench_repo(repo: Repo, args) -> dict:
    result: dict = {"repo": repo.name, "github": repo.github, "legacy_commit": repo.legacy,
                    "human_commit": repo.human, "stages": {}}
    logs = args.cache / "runs" / repo.name
    logs.mkdir(parents=True, exist_ok=True)
    legacy_tree = source_tree(repo, "legacy", args)
    if legacy_tree is None:
        result["error"] = "no legacy tree"
        return result
    for stage in args.stages:
        logf = logs / f"{stage}.log"
        logf.write_text("")
        if stage == "gymmigrate":
            tree = args.cache / "trees" / repo.name / "gymmigrate"
            # the venv needs gymmigrate before the tree exists: key it on the migrated
            # dependency files by migrating first with this checkout's code (PYTHONPATH:
            # the interpreter's own gymmigrate may be another checkout's editable install)
            shutil.rmtree(tree, ignore_errors=True)
            shutil.copytree(legacy_tree, tree, symlinks=True)
            rc = run([sys.executable, "-m", "gymmigrate", "rewrite", "."], cwd=tree, logf=logf,
                     env=dict(os.environ, PYTHONPATH=str(ROOT / "src")))
            if rc not in (0, 1):  # 1: review items left; anything else: the migration did not run
                # without it the venv would install the legacy dependency files and the
                # figures would measure legacy code: stop this stage, loudly
                log(f"{repo.name}/{stage}: the first migration failed (exit {rc}, see {logf}): "
                    "run this script with the interpreter gymmigrate's dependencies are installed in")
                result["stages"][stage] = {"error": f"first migration failed (exit {rc})", "log": str(logf)}
                continue
            venv, facts = prepare_venv(repo, stage, tree, args, logf)
            facts["migration"] = migrate(repo, legacy_tree, tree, venv, logf)
        else:
            tree = legacy_tree if stage == "legacy" else source_tree(repo, "human", args)
            if tree is None:
                result["stages"][stage] = None
                continue
            venv, facts = prepare_venv(repo, stage, tree, args, logf)
        facts.update(run_tests(repo, stage, tree, venv, args, logf))
        facts["log"] = str(logf)
        result["stages"][stage] = facts
    legacy = result["stages"].get("legacy")
    migrated = result["stages"].get("gymmigrate")
    if legacy and migrated and "cases" in legacy and "cases" in migrated:
        # errors of tests (or whole modules, when collecting fails) legacy never had
        result["new_errors"] = {
            tid: v for tid, v in migrated["cases"].items()
            if tid not in legacy["cases"] and v[0] in ("failed", "error")}
        result["regressions"] = {
            tid: migrated["cases"].get(tid, ("missing", "not collected"))
            for tid, (o, _) in legacy["cases"].items()
            if o == "passed" and migrated["cases"].get(tid, ("missing",))[0] != "passed"}
    return result


def print_table(results: list[dict], stages: list[str]) -> None:
    print()
    print(f"{'repository':<13} {'stage':<11} {'deps':<9} {'passed':>6} {'failed':>6} "
          f"{'errors':>6} {'skipped':>7} {'time':>7}  versions")
    for r in results:
        for stage in stages:
            s = r["stages"].get(stage)
            if s is None:
                print(f"{r['repo']:<13} {stage:<11} {'-':<9} {'(no tree)':>6}")
                continue
            if "error" in s:
                print(f"{r['repo']:<13} {stage:<11} {'-':<9} ERROR: {s['error']} ({s['log']})")
                continue
            deps = "yes" if s["declared"] else ("fallback" if s["fallback"] else "NO")
            c = s["counts"]
            print(f"{r['repo']:<13} {stage:<11} {deps:<9} {c['passed']:>6} {c['failed']:>6} "
                  f"{c['error']:>6} {c['skipped']:>7} {s['seconds']:>6}s  "
                  f"{', '.join(s.get('versions', []))}")
        m = (r["stages"].get("gymmigrate") or {}).get("migration")
        if m:
            print(f"  {r['repo']}: gymmigrate rewrite exit {m['rc']}, {m['files_changed']} file(s) "
                  f"changed in {m['seconds']} s, {len(m['errors'])} error(s)")
            for line in m["errors"]:
                print(f"    {line}")
        if r.get("new_errors"):
            print(f"  {r['repo']}: {len(r['new_errors'])} error(s) after gymmigrate that legacy "
                  f"did not have (collection errors show as a module name)")
            groups = {}
            for tid, (o, msg) in sorted(r["new_errors"].items()):
                groups.setdefault((o, msg[:160]), []).append(tid.lstrip(":"))
            for (o, msg), tids in sorted(groups.items(), key=lambda g: -len(g[1])):
                more = f" (+{len(tids) - 3} more)" if len(tids) > 3 else ""
                print(f"    {len(tids):>3} x {o}: {msg}")
                print(f"          {', '.join(tids[:3])}{more}")
        if "regressions" in r:
            reg = r["regressions"]
            print(f"  {r['repo']}: {len(reg)} test(s) passed on legacy but not after gymmigrate")
            groups: dict[tuple[str, str], list[str]] = {}
            for tid, (o, msg) in sorted(reg.items()):
                groups.setdefault((o, msg), []).append(tid)
            for (o, msg), tids in sorted(groups.items(), key=lambda g: -len(g[1])):
                more = f" (+{len(tids) - 3} more)" if len(tids) > 3 else ""
                print(f"    {len(tids):>3} x {o}: {msg}")
                print(f"          {', '.join(tids[:3])}{more}")
        print()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repos", default=",".join(r.name for r in REPOS))  # names as in REPOS
    ap.add_argument("--stages", default="legacy,human,gymmigrate")
    ap.add_argument("--cache", type=Path, default=Path("/work/cache/repos"))
    ap.add_argument("--sources", type=Path, default=None)
    ap.add_argument("--mirrors", type=Path, default=None)
    ap.add_argument("--timeout", type=int, default=120, help="per test (pytest-timeout)")
    ap.add_argument("--suite-timeout", type=int, default=1800, help="per test suite")
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args(argv)
    args.cache = args.cache.resolve()
    args.stages = [s for s in args.stages.split(",") if s]
    names = args.repos.split(",")
    unknown = set(names) - {r.name for r in REPOS}
    if unknown:
        ap.error(f"unknown repositories: {', '.join(sorted(unknown))}")
    results = [bench_repo(r, args) for r in REPOS if r.name in names]
    print_table(results, args.stages)
    if args.json:
        args.json.write_text(json.dumps(results, indent=1, default=list))
    return 0


if __name__ == "__main__":
    sys.exit(main())
