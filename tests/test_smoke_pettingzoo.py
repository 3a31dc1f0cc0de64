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
    assert data["envs"][0]["agent_counts"]["player_0"] == {"terminated": 2, "truncated": 0}

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
