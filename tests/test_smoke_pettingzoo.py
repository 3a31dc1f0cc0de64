"""``gymmigrate smoke`` on PettingZoo targets, through the CLI: seeded AEC and parallel episodes,
PettingZoo's own API test first, per-agent terminations and truncations counted apart."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app

pytest.importorskip("pettingzoo")

runner = CliRunner()
RULE_FIXTURES = Path(__file__).resolve().parent.parent / "fixtures" / "rules"


def smoke(tmp_path: Path, *args: str) -> tuple[int, dict, str]:
    evidence = tmp_path / "evidence.json"
    result = runner.invoke(app, ["smoke", *args, "--evidence", str(evidence)])
    data = json.loads(evidence.read_text(encoding="utf-8")) if evidence.exists() else {}
    return result.exit_code, data, result.stderr


def checks(data: dict) -> dict[str, str]:
    return {check["name"]: check["outcome"] for check in data["checks"]}


def test_aec_module_target_counts_truncations_per_agent(tmp_path: Path) -> None:
    code, data, stderr = smoke(tmp_path, "pettingzoo.classic.rps_v2", "--seed", "3", "--episodes", "2")
    assert code == 0, stderr
    assert "PettingZoo's api_test passed" in stderr
    env = data["envs"][0]
    assert env["reset_seed"] == 3 and env["seed_source"] == "smoke"
    assert env["agent_counts"] == {
        "player_0": {"terminated": 0, "truncated": 2},
        "player_1": {"terminated": 0, "truncated": 2},
    }
    assert data["counts"]["truncated"] == 2 and data["counts"]["terminated"] == 0
    assert checks(data)["determinism"] == "passed"


def test_aec_factory_target_counts_terminations(tmp_path: Path) -> None:
    code, data, stderr = smoke(tmp_path, "pettingzoo.classic.tictactoe_v3:env", "--episodes", "2")
    assert code == 0, stderr
    counts = data["envs"][0]["agent_counts"]
    assert set(counts) == {"player_1", "player_2"}
    assert all(c == {"terminated": 2, "truncated": 0} for c in counts.values())  # games end, none is cut short
    assert data["counts"]["terminated"] == 2


def test_parallel_factory_target(tmp_path: Path) -> None:
    code, data, stderr = smoke(tmp_path, "pettingzoo.classic.rps_v2:parallel_env", "--episodes", "2")
    assert code == 0, stderr
    assert "parallel_api_test passed" in stderr
    assert data["envs"][0]["agent_counts"]["player_0"] == {"terminated": 0, "truncated": 2}


def test_rewritten_custom_parallel_env_passes_and_the_legacy_one_fails(tmp_path: Path) -> None:
    migrated = tmp_path / "migrated_env.py"
    migrated.write_bytes((RULE_FIXTURES / "PZ108/custom_parallel_env.expected.py").read_bytes())
    code, data, stderr = smoke(tmp_path, f"{migrated}:parallel_env", "--episodes", "2")
    assert code == 0, stderr
    assert data["envs"][0]["agent_counts"]["player_0"] == {"terminated": 0, "truncated": 2}  # ten rounds: a step limit

    # The 1.20 API on top of Gymnasium spaces: imports fine, breaks the 1.27 contract.
    legacy = tmp_path / "legacy_env.py"
    legacy.write_text((RULE_FIXTURES / "PZ108/custom_parallel_env.py").read_text().replace("from gym.", "from gymnasium."))
    code, data, stderr = smoke(tmp_path, f"{legacy}:parallel_env", "--episodes", "2")
    assert code == 1
    outcomes = checks(data)
    assert outcomes["pettingzoo_api_test"] == "failed"
    assert outcomes["reset_returns_obs_info"] == "failed"
    assert "FAIL run_completed" in stderr


def test_gym_targets_keep_their_record(tmp_path: Path) -> None:
    code, data, stderr = smoke(tmp_path, "CartPole-v1", "--episodes", "1", "--no-determinism")
    assert code == 0, stderr
    assert "agent_counts" not in data["envs"][0]
    assert "pettingzoo_api_test" not in checks(data)


# -- scripts: the child observes PettingZoo's AECEnv and ParallelEnv -------------------

SCRIPTS = Path(__file__).resolve().parent.parent / "fixtures" / "smoke" / "scripts"


def migrated(tmp_path: Path, name: str) -> Path:
    """A 1.20-style script fixture after `gymmigrate rewrite`."""
    script = tmp_path / name
    script.write_bytes((SCRIPTS / name).read_bytes())
    result = runner.invoke(app, ["rewrite", str(script)])
    assert result.exit_code == 0, result.output
    return script


def test_migrated_aec_script_passes_with_per_agent_counts(tmp_path: Path) -> None:
    script = migrated(tmp_path, "pettingzoo_legacy_aec.py")
    assert "termination, truncation, info = env.last()" in script.read_text()
    code, data, stderr = smoke(tmp_path, str(script), "--seed", "5")
    assert code == 0, stderr
    assert data["target_kind"] == "script"
    env = data["envs"][0]
    assert (env["env_id"], env["env_class"], env["reset_seed"], env["seed_source"]) == ("tictactoe_v3", "raw_env", 5, "smoke")
    assert env["wrappers"][0] == "OrderEnforcingWrapper" and env["wrappers"][-1] == "raw_env"
    assert [episode["ending"] for episode in env["episodes"]] == ["terminated", "terminated"]  # the script plays two games
    assert env["agent_counts"] == {
        "player_1": {"terminated": 2, "truncated": 0},
        "player_2": {"terminated": 2, "truncated": 0},
    }
    assert data["run"]["stopped_by"] == "finished"  # two games, under the default budget of three episodes
    outcomes = checks(data)
    assert outcomes["determinism"] == "passed" and outcomes["step_returns_five_fields"] == "passed"
    assert "every last() returned (observation, reward, termination, truncation, info)" in stderr


def test_migrated_parallel_script_passes_and_counts_truncations(tmp_path: Path) -> None:
    script = migrated(tmp_path, "pettingzoo_legacy_parallel.py")
    code, data, stderr = smoke(tmp_path, str(script))
    assert code == 0, stderr
    env = data["envs"][0]
    assert env["env_id"] == "rps_v2" and env["wrappers"][0] == "aec_to_parallel_wrapper"
    assert env["agent_counts"] == {  # rps ends every game by truncation, after 15 rounds
        "player_0": {"terminated": 0, "truncated": 1},
        "player_1": {"terminated": 0, "truncated": 1},
    }
    assert env["steps"] == 15 and data["counts"]["truncated"] == 1
    assert all(outcome != "failed" for outcome in checks(data).values())


def test_the_budget_stops_a_pettingzoo_script(tmp_path: Path) -> None:
    script = tmp_path / "many_games.py"
    script.write_text(
        "from pettingzoo.classic import rps_v2\n"
        "env = rps_v2.parallel_env()\n"
        "for game in range(1000):\n"
        "    env.reset(seed=game)\n"
        "    while env.agents:\n"
        "        env.step({agent: env.action_space(agent).sample() for agent in env.agents})\n"
    )
    code, data, stderr = smoke(tmp_path, str(script), "--episodes", "2", "--no-determinism")
    assert code == 0, stderr
    assert data["run"]["stopped_by"] == "budget" and data["envs"][0]["seed_source"] == "script"
    assert data["envs"][0]["agent_counts"]["player_0"] == {"terminated": 0, "truncated": 2}
    code, data, stderr = smoke(tmp_path, str(script), "--max-steps", "20", "--no-determinism")
    assert data["run"]["steps"] == 20 and data["counts"]["stopped by budget"] == 1


@pytest.mark.parametrize(
    ("name", "unpacked"),
    [("pettingzoo_legacy_aec.py", "unpacks last() into the four values"), ("pettingzoo_legacy_parallel.py", "unpacks a parallel step() into the four dicts")],
)
def test_legacy_loops_fail_run_completed_with_the_reason(tmp_path: Path, name: str, unpacked: str) -> None:
    code, data, stderr = smoke(tmp_path, str(SCRIPTS / name), "--no-determinism")
    assert code == 1
    failed = {check["name"]: check["message"] for check in data["checks"] if check["outcome"] == "failed"}
    assert set(failed) == {"run_completed"}
    assert "ValueError: too many values to unpack (expected 4" in failed["run_completed"]
    assert f"{name}:8)" in failed["run_completed"]  # the line of the script, not of PettingZoo
    assert unpacked in failed["run_completed"] and "run gymmigrate rewrite on it first" in failed["run_completed"]


def test_a_legacy_env_with_a_four_value_last_fails_the_step_contract(tmp_path: Path) -> None:
    code, data, stderr = smoke(tmp_path, str(SCRIPTS / "pettingzoo_legacy_env.py"))
    assert code == 1
    failed = {check["name"]: check["message"] for check in data["checks"] if check["outcome"] == "failed"}
    assert set(failed) == {"step_returns_five_fields"}
    assert failed["step_returns_five_fields"].startswith(
        "CountdownEnv.last() returned 4 values (observation, reward, done, info), the PettingZoo API before 1.21"
    )
    env = data["envs"][0]
    assert (env["env_id"], env["wrappers"]) == ("countdown_v0", ["CountdownEnv"])
    assert env["agent_counts"] == {"a": {"terminated": 1, "truncated": 0}, "b": {"terminated": 1, "truncated": 0}}


def test_a_gym_only_script_is_unchanged_and_never_imports_pettingzoo(tmp_path: Path) -> None:
    seen = tmp_path / "modules.json"
    script = tmp_path / "gym_loop.py"
    script.write_text(
        (SCRIPTS / "unseeded_loop.py").read_text()
        + f"\nimport json, sys\nopen({str(seen)!r}, 'w').write(json.dumps([m for m in sys.modules if m.startswith('pettingzoo')]))\n"
    )
    code, data, stderr = smoke(tmp_path, str(script), "--episodes", "10", "--no-determinism")
    assert code == 0, stderr
    assert json.loads(seen.read_text()) == []
    assert "agent_counts" not in data["envs"][0]
    assert {c["name"]: c["message"] for c in data["checks"]}["step_returns_five_fields"] == (
        "every step() returned (obs, reward, terminated, truncated, info)"
    )


def test_reading_the_old_dones_names_the_split(tmp_path: Path) -> None:
    script = tmp_path / "reads_dones.py"
    script.write_text(
        "from pettingzoo.classic import rps_v2\n"
        "env = rps_v2.env()\n"
        "env.reset()\n"
        "for agent in env.agent_iter():\n"
        "    if env.dones[agent]:\n"
        "        break\n"
        "    env.step(env.action_space(agent).sample())\n"
    )
    code, data, stderr = smoke(tmp_path, str(script), "--no-determinism")
    assert code == 1
    failed = {check["name"]: check["message"] for check in data["checks"] if check["outcome"] == "failed"}
    assert set(failed) == {"run_completed"}
    assert "'dones'" in failed["run_completed"] and "reads_dones.py:5)" in failed["run_completed"]
    assert "PettingZoo 1.21 split dones into terminations and truncations" in failed["run_completed"]
