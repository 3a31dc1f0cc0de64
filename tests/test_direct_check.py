"""``gymmigrate check`` read by ``cli.py`` itself (no typer) prints the same bytes and
exits with the same code as the typer application, and leaves everything else to typer.

The cases run twice, once through ``cli.main`` (which takes the direct way where
``check_arguments`` accepts them) and once through the typer application alone; each
way runs every case in one interpreter of its own, with stdout and stderr redirected at
the file descriptors, so the comparison sees exactly the bytes a user would.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from gymmigrate.cli import check_arguments

ROOT = Path(__file__).resolve().parent.parent
FIXTURES = ROOT / "fixtures"

_PROBE = """
import json, os, sys, tempfile
from gymmigrate import cli
way, cases = sys.argv[1], json.loads(sys.argv[2])
answers = []
for arguments in cases:
    sys.argv = ["gymmigrate", *arguments]
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        saved = os.dup(1), os.dup(2)
        os.dup2(out.fileno(), 1)
        os.dup2(err.fileno(), 2)
        try:
            if way == "direct":
                cli.main()
            else:
                cli._print_undecodable_names_as_they_are()  # as main does first
                cli.run_typer()
            code = "returned"
        except SystemExit as stop:
            code = stop.code
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
        out.seek(0)
        err.seek(0)
        answers.append([code, out.read().decode("latin-1"), err.read().decode("latin-1")])
print(json.dumps(answers))
"""


@pytest.fixture(scope="module")
def project(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("project")
    shutil.copy(FIXTURES / "examples" / "legacy_cartpole_dqn.py", root / "train.py")
    shutil.copy(FIXTURES / "examples" / "legacy_frozenlake_qtable.py", root / "qtable.py")
    shutil.copy(FIXTURES / "notebooks" / "multi_cell_loop.ipynb", root / "loop.ipynb")
    (root / "clean.py").write_text("import gymnasium as gym\n\nenv = gym.make('CartPole-v1')\n")
    (root / "broken.py").write_text("import gym\ndef f(:\n")
    (root / "-dash.py").write_text("import gym\n")
    (root / "README.md").write_text("```python\nimport gym\nenv = gym.make('CartPole-v0')\n```\n")
    (root / "a-folder").mkdir()
    bad = root / "badconfig"
    bad.mkdir()
    (bad / "pyproject.toml").write_text('[tool.gymmigrate]\nselect = ["GM99"]\n')
    (bad / "train.py").write_text("import gym\n")
    return root


def answers(cases: list[list[str]], cwd: Path) -> dict[str, list[list[object]]]:
    """[exit code, stdout, stderr] of each case, run each way (both ways at once)."""
    probes = {
        way: subprocess.Popen(
            [sys.executable, "-c", _PROBE, way, json.dumps(cases)], cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE
        )
        for way in ("direct", "typer")
    }
    found = {}
    for way, probe in probes.items():
        out, err = probe.communicate(timeout=300)
        assert probe.returncode == 0, err.decode(errors="replace")
        found[way] = json.loads(out)
    return found


def run(way: str, arguments: list[str], cwd: Path, stdin: bytes = b"") -> tuple[int, bytes, bytes]:
    """One case in a fresh interpreter, as a user runs it."""
    done = subprocess.run(
        [sys.executable, "-c", _MAIN, way, *arguments], cwd=cwd, input=stdin, capture_output=True, timeout=120
    )
    return done.returncode, done.stdout, done.stderr


_MAIN = """
import sys
from gymmigrate import cli
way = sys.argv.pop(1)
sys.argv[0] = "gymmigrate"
if way == "direct":
    cli.main()
else:
    cli._print_undecodable_names_as_they_are()
    cli.run_typer()
"""

# (arguments, taken directly): the direct way must answer exactly as typer does.
CASES = [
    (["check", "train.py"], True),
    (["check", "."], True),
    (["check", ".", "--docs", "-j1"], True),
    (["check", "train.py", "qtable.py", "--output-format", "json"], True),
    (["check", "--output-format=SARIF", "train.py", "loop.ipynb"], True),
    (["check", "train.py", "--output-format", "github", "--jobs=0"], True),
    (["check", "train.py", "--output-format", "yaml"], True),
    (["check", "train.py", "--select", "GM1", "--ignore=GM101", "--select", "GM2,gm3"], True),
    (["check", "train.py", "--extend-ignore", "GM1", "--extend-select=GM101"], True),
    (["check", "train.py", "--select", "XY1"], True),
    (["check", "missing.py", "train.py"], True),
    (["check", "broken.py", "clean.py"], True),
    (["check", "clean.py"], True),
    (["check", "badconfig/train.py"], True),
    (["check", "--", "-dash.py"], True),
    (["check", "train.py", "-"], True),
    (["check", "-j", "x", "-j", "2", "train.py"], True),
    # left to typer: its help, its usage errors, and what it alone judges
    (["check", "--help"], False),
    (["check"], False),
    (["check", "-dash.py"], False),
    (["check", "train.py", "--frobnicate"], False),
    (["check", "train.py", "-j", "-1"], False),
    (["check", "train.py", "--jobs", "two"], False),
    (["check", "train.py", "--report", "a-folder"], False),
    (["check", "train.py", "--report"], False),
    (["check", "train.py", "--docs=yes"], False),
    (["check", "train.py", "--select", "--ignore", "GM1"], False),
    (["--version"], False),
    (["rewrite", "--diff", "train.py"], False),
]


def test_direct_check_answers_as_typer_does(project: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(project)  # where the paths are judged
    assert [arguments for arguments, direct in CASES if (check_arguments(arguments) is not None) is not direct] == []
    cases = [arguments for arguments, _ in CASES]
    found = answers(cases, project)
    direct, typer = found["direct"], found["typer"]
    for arguments, by_cli, by_typer in zip(cases, direct, typer):
        assert by_cli == by_typer, arguments
    code, out, err = direct[0]
    assert code == 1 and "train.py:10:1: GM101 [auto]" in out and "would rewrite 1 of 1 file" in err
    assert direct[10][0] == 2 and "missing.py" in direct[10][2]  # a missing path
    assert direct[9][0] == 2 and "error: unknown rule code or prefix 'XY1'" in direct[9][2]  # a bad --select
    assert direct[17][0] == 0 and "Usage:" in direct[17][1]  # --help, from typer


def test_stdin_and_report_as_typer(project: Path, tmp_path: Path) -> None:
    source = (project / "train.py").read_bytes()
    outcomes = {}
    for way in ("direct", "typer"):
        arguments = ["check", "-", "--stdin-filename", "train.py", "--report", str(tmp_path / f"{way}.json")]
        assert check_arguments(arguments) is not None
        outcomes[way] = run(way, arguments, project, stdin=source)
    assert outcomes["direct"] == outcomes["typer"]
    assert outcomes["direct"][0] == 1 and b"GM101" in outcomes["direct"][1]
    assert (tmp_path / "direct.json").read_bytes() == (tmp_path / "typer.json").read_bytes()


def test_report_written_the_same(project: Path, tmp_path: Path) -> None:
    outcomes = {}
    for way in ("direct", "typer"):
        outcomes[way] = run(way, ["check", ".", "--report", str(tmp_path / f"{way}.json")], project)
    assert outcomes["direct"] == outcomes["typer"]
    assert outcomes["direct"][0] == 2  # broken.py
    assert (tmp_path / "direct.json").read_bytes() == (tmp_path / "typer.json").read_bytes()
    code, _, err = run("direct", ["check", "train.py", "--report", "no-such-folder/report.json"], project)
    assert code == 2 and err.endswith(b"\n") and b"error: cannot write the report" in err


def test_the_arguments_typer_would_pass() -> None:
    assert check_arguments(["check", "a.py"]) == {"paths": ["a.py"]}
    assert check_arguments(["check", "-j4", "a.py", "--docs", "--select", "GM1", "--select=GM2", "--", "--x"]) == {
        "paths": ["a.py", "--x"],
        "jobs": 4,
        "docs": True,
        "select": ["GM1", "GM2"],
    }
    assert check_arguments(["check", "a.py", "--report", "out.json", "--output-format", "json"]) == {
        "paths": ["a.py"],
        "report": Path("out.json"),
        "output_format": "json",
    }
    assert check_arguments(["rewrite", "a.py"]) is None


def test_a_closed_stdout_exits_as_under_typer(project: Path) -> None:
    """``check . | head -c1``: exit 1 and no traceback, as typer answers a closed pipe."""
    answered = {}
    for way in ("direct", "typer"):
        probe = subprocess.Popen(
            [sys.executable, "-c", _MAIN, way, "check", ".", "--output-format", "json"],
            cwd=project,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
        )
        assert probe.stdout is not None and probe.stderr is not None
        probe.stdout.close()
        errors = probe.stderr.read()
        answered[way] = (probe.wait(timeout=120), errors)
    assert answered["direct"] == answered["typer"]
    assert answered["direct"][0] == 1 and b"Traceback" not in answered["direct"][1]
