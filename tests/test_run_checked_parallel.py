"""A def that checks its parameter is a PettingZoo parallel env (``assert isinstance(team,
ParallelEnv)``) before handing it to a class a package re-exports
(``fixtures/project_checked_parallel``): the class's ``self.team`` is that parallel env,
whatever the def's callers are thought to pass, and its reset becomes the (obs, infos)
pair of PettingZoo 1.23+ though the class's module imports no PettingZoo.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_checked_parallel"
runner = CliRunner()


def _adapter_findings(run: Path) -> list[tuple[int, str, str]]:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code == 1
    return sorted((f["line"], f["rule"], f["kind"]) for f in json.loads(result.stdout) if Path(f["path"]).name == "adapter.py")


def test_a_checked_parallel_env_handed_to_a_reexported_class_is_migrated(tmp_path: Path) -> None:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    assert (12, "PZ105", "auto") in _adapter_findings(run)
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code == 0, result.output
    text = (run / "squads" / "adapter.py").read_text()
    assert "obs, infos = self.team.reset(seed=seed, options=options)" in text
    second = runner.invoke(app, ["rewrite", "--diff", str(run / "squads")])
    assert "adapter.py" not in second.stdout  # idempotent


def test_a_caller_said_to_pass_a_vecenv_does_not_outweigh_the_check(tmp_path: Path) -> None:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    # ``make_vec_env(...)`` is a VecEnv, which would leave every call on ``team`` alone
    (run / "run_vec.py").write_text(
        "from stable_baselines3.common.env_util import make_vec_env\n\nfrom squads.convert import squad_vec_env\n\n\n"
        "def main():\n    squad_vec_env(make_vec_env('CartPole-v1'))\n"
    )
    assert (12, "PZ105", "auto") in _adapter_findings(run)


def test_without_the_check_or_a_traced_caller_no_pettingzoo_rule_fires(tmp_path: Path) -> None:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    (run / "run_squads.py").unlink()
    convert = run / "squads" / "convert.py"
    convert.write_text(convert.read_text().replace("    assert isinstance(team, ParallelEnv), \"a parallel env is needed\"\n", ""))
    assert all(not rule.startswith("PZ") for _, rule, _ in _adapter_findings(run))
