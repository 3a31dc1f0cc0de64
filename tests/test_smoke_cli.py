"""``gymmigrate smoke`` and ``gymmigrate rewrite --smoke`` end to end: streams, evidence file, exit codes."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

runner = CliRunner()
FIXTURES = Path(__file__).resolve().parent.parent / "fixtures" / "smoke"


def test_gymnasium_is_not_imported_at_start_up() -> None:
    code = "import sys, gymmigrate.cli; assert 'gymnasium' not in sys.modules, 'imported at start-up'"
    subprocess.run([sys.executable, "-c", code], check=True)


def test_smoke_an_env_id_writes_evidence_and_exits_0(tmp_path: Path) -> None:
    evidence = tmp_path / "evidence.json"
    result = runner.invoke(app, ["smoke", "CartPole-v1", "--seed", "4", "--episodes", "2", "--evidence", str(evidence)])
    assert result.exit_code == 0, result.stderr
    assert result.stdout == "", "the summary goes to stderr"
    assert "gymmigrate smoke CartPole-v1 (seed 4)" in result.stderr
    assert "the contract holds" in result.stderr
    data = json.loads(evidence.read_text(encoding="utf-8"))
    assert (data["outcome"], data["exit_code"], data["seed"]) == ("passed", 0, 4)
    assert data["budget"] == {"episodes": 2, "max_steps": 1000, "timeout_seconds": 60.0}
    assert len(data["envs"][0]["episodes"]) == 2


def test_smoke_a_broken_class_exits_1_and_names_the_check() -> None:
    result = runner.invoke(app, ["smoke", f"{FIXTURES / 'envs.py'}:IntFlags", "--no-determinism"])
    assert result.exit_code == 1
    assert "FAIL flags_are_bool: IntFlags.step() returned terminated=0 of type int" in result.stderr
    assert "Traceback" not in result.output


def test_smoke_an_unknown_env_id_exits_2_with_a_message(tmp_path: Path) -> None:
    evidence = tmp_path / "evidence.json"
    result = runner.invoke(app, ["smoke", "CartPoel-v1", "--evidence", str(evidence)])
    assert result.exit_code == 2
    assert "could not run: unknown env id 'CartPoel-v1'" in result.stderr
    assert "Traceback" not in result.output
    assert json.loads(evidence.read_text(encoding="utf-8"))["outcome"] == "not run"


def test_smoke_rejects_a_bad_budget() -> None:
    result = runner.invoke(app, ["smoke", "CartPole-v1", "--episodes", "0"])
    assert result.exit_code == 2


def test_rewrite_smoke_checks_each_rewritten_script(tmp_path: Path) -> None:
    shutil.copy(FIXTURES / "scripts" / "legacy_cartpole.py", tmp_path / "train.py")
    shutil.copy(FIXTURES / "scripts" / "no_env.py", tmp_path / "helpers.py")
    (tmp_path / "broken.py").write_text(
        "import gym\n"
        "\n"
        "env = gym.make('CartPole-v1')\n"
        "obs = env.reset()\n"
        "for t in range(100):\n"
        "    obs, reward, done, info = env.step(env.action_space.sample())\n",
        encoding="utf-8",
    )
    report = tmp_path / "report.json"
    result = runner.invoke(app, ["rewrite", "--smoke", "--report", str(report), str(tmp_path)])
    assert "Smoke (2 files, seed 0)" in result.stderr, result.stderr
    assert f"ok {tmp_path / 'train.py'}: passed" in result.stderr
    assert f"FAIL {tmp_path / 'broken.py'}: 1 check failed: no_step_after_end: step() on CartPole-v1" in result.stderr
    assert "helpers.py" not in result.stderr.split("Smoke")[1], "a file that creates no env is not run"
    assert result.exit_code == 1
    smoked = {Path(record["path"]).name: record for record in json.loads(report.read_text())["smoke"]}
    assert set(smoked) == {"train.py", "broken.py"}
    assert (smoked["train.py"]["outcome"], smoked["train.py"]["exit_code"]) == ("passed", 0)
    assert smoked["broken.py"]["outcome"] == "failed"
    assert "no_step_after_end" in smoked["broken.py"]["summary"]


def test_rewrite_smoke_refuses_diff(tmp_path: Path) -> None:
    shutil.copy(FIXTURES / "scripts" / "legacy_cartpole.py", tmp_path / "train.py")
    result = runner.invoke(app, ["rewrite", "--smoke", "--diff", str(tmp_path)])
    assert result.exit_code == 2
    assert "cannot be combined with --diff" in result.stderr
    assert (tmp_path / "train.py").read_bytes() == (FIXTURES / "scripts" / "legacy_cartpole.py").read_bytes()
