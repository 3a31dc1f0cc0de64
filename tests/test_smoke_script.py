"""Scripts under the shim: each run is a child process, so these keep budgets small."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from gymmigrate.engine import transform_source
from gymmigrate.smoke.evidence import (
    EXIT_CHECK_FAILED,
    EXIT_NOT_RUN,
    EXIT_OK,
    Ending,
    Outcome,
)
from gymmigrate.smoke.runner import SmokeOptions, run_smoke

SCRIPTS = Path(__file__).resolve().parent.parent / "fixtures" / "smoke" / "scripts"
ONCE = SmokeOptions(determinism=False)


def script(name: str) -> str:
    return str(SCRIPTS / name)


def failed(evidence) -> dict[str, str]:  # noqa: ANN001
    return {check.name: check.message for check in evidence.checks if check.outcome is Outcome.FAILED}


def check(evidence, name: str):  # noqa: ANN001, ANN201
    return next(c for c in evidence.checks if c.name == name)


def test_an_unseeded_script_gets_the_seed_and_is_reproducible() -> None:
    evidence = run_smoke(script("unseeded_loop.py"))
    assert evidence.exit_code == EXIT_OK, failed(evidence)
    env = evidence.run.envs[0]
    assert (env.env_id, env.reset_seed, env.seed_source) == ("CartPole-v1", 0, "smoke")
    assert env.wrappers == ("TimeLimit", "OrderEnforcing", "PassiveEnvChecker", "CartPoleEnv")
    assert evidence.run.stopped_by == "budget" and len(env.episodes) == 3
    assert check(evidence, "determinism").message == (
        "two runs with seed 0 gave identical first transitions and 3 identical episodes"
    )
    assert check(evidence, "seed_changes_start").message == "seed 1 gives a different first observation than seed 0"


def test_a_script_that_seeds_itself_is_reported_as_such() -> None:
    evidence = run_smoke(script("good_loop.py"), SmokeOptions(seed=3))
    assert evidence.exit_code == EXIT_OK, failed(evidence)
    assert evidence.run.envs[0].seed_source == "script"
    seeded = check(evidence, "seed_changes_start")
    assert seeded.outcome is Outcome.SKIPPED and "reset(seed=7)" in seeded.message


def test_stepping_past_the_end_is_caught() -> None:
    evidence = run_smoke(script("step_past_end.py"), ONCE)
    assert evidence.exit_code == EXIT_CHECK_FAILED
    assert set(failed(evidence)) == {"no_step_after_end"}
    assert re.match(
        r"step\(\) on CartPole-v1 was called after episode 1 ended \(terminated at step \d+\) without reset\(\) "
        r"in between \(\d+ times\)",
        failed(evidence)["no_step_after_end"],
    )


def test_a_four_field_loop_over_a_directly_built_env_is_caught() -> None:
    evidence = run_smoke(script("four_field_loop.py"), ONCE)
    assert set(failed(evidence)) == {"step_returns_five_fields"}
    assert evidence.run.envs[0].wrappers == ("FourFieldStep",)


def test_a_loop_that_never_ends_is_stopped_by_the_step_budget() -> None:
    evidence = run_smoke(script("endless_loop.py"), SmokeOptions(max_steps=200, determinism=False))
    assert evidence.exit_code == EXIT_CHECK_FAILED
    assert failed(evidence) == {
        "episodes_end": "the loop never ended: 200 steps ran and no episode terminated or truncated "
        "(0 terminated, 0 truncated, 1 stopped by budget)"
    }
    assert evidence.run.envs[0].episodes[0].ending is Ending.BUDGET


def test_a_loop_that_hangs_is_stopped_at_the_timeout() -> None:
    evidence = run_smoke(script("hangs.py"), SmokeOptions(timeout=3.0))
    assert evidence.exit_code == EXIT_CHECK_FAILED
    message = failed(evidence)["episodes_end"]
    assert message.startswith("the loop never ended: still running after 3 s, with 3 steps"), message
    assert check(evidence, "determinism").message == "not checked: the first run hit the timeout, so it was not repeated"


def test_the_budget_stops_a_loop_that_swallows_exceptions() -> None:
    evidence = run_smoke(script("swallows_errors.py"), ONCE)
    assert evidence.exit_code == EXIT_OK, failed(evidence)
    assert evidence.run.stopped_by == "budget"


@pytest.mark.parametrize(
    ("name", "message"),
    [
        pytest.param(
            "crash_before_step.py",
            "the script crashed before its first step: FileNotFoundError: [Errno 2] No such file or directory: "
            "'no-such-config.json' (at ",
            id="crash before the first step",
        ),
        pytest.param(
            "legacy_cartpole.py",
            "the script crashed before its first step: ModuleNotFoundError: No module named 'gym' "
            "(this is legacy Gym code: run gymmigrate rewrite on it first)",
            id="unmigrated script",
        ),
        pytest.param(
            "no_env.py",
            "the script ended without resetting or stepping any gymnasium or PettingZoo env: nothing to check",
            id="no env",
        ),
        pytest.param("missing.py", "no such script: ", id="missing script"),
    ],
)
def test_a_script_that_cannot_run_exits_2(name: str, message: str) -> None:
    evidence = run_smoke(script(name))
    assert evidence.exit_code == EXIT_NOT_RUN
    assert evidence.load_error.startswith(message), evidence.load_error


def test_a_crash_after_the_first_step_is_a_failed_check(tmp_path: Path) -> None:
    crashing = tmp_path / "crash_mid.py"
    crashing.write_text(
        "import gymnasium as gym\n"
        "env = gym.make('CartPole-v1')\n"
        "env.reset(seed=0)\n"
        "env.step(0)\n"
        "raise RuntimeError('replay buffer full')\n",
        encoding="utf-8",
    )
    evidence = run_smoke(str(crashing), ONCE)
    assert evidence.exit_code == EXIT_CHECK_FAILED
    assert failed(evidence)["run_completed"] == (
        f"the run raised RuntimeError: replay buffer full (at {crashing}:5)"
    )


def test_script_arguments_reach_the_script(tmp_path: Path) -> None:
    with_args = tmp_path / "with_args.py"
    with_args.write_text(
        "import sys\n"
        "import gymnasium as gym\n"
        "assert sys.argv[1:] == ['--env', 'MountainCar-v0'], sys.argv\n"
        "env = gym.make(sys.argv[2])\n"
        "env.reset()\n"
        "env.step(0)\n",
        encoding="utf-8",
    )
    evidence = run_smoke(str(with_args), SmokeOptions(determinism=False, script_args=("--env", "MountainCar-v0")))
    assert evidence.run is not None and evidence.run.envs[0].env_id == "MountainCar-v0"


def test_a_rewritten_legacy_script_passes_the_smoke_check(tmp_path: Path) -> None:
    legacy = (SCRIPTS / "legacy_cartpole.py").read_bytes()
    rewritten = transform_source(legacy, "legacy_cartpole.py").rewritten.decode()
    target = tmp_path / "train.py"
    target.write_text(rewritten, encoding="utf-8")
    evidence = run_smoke(str(target))
    assert evidence.exit_code == EXIT_OK, (rewritten, evidence.load_error, failed(evidence))
    assert evidence.run.envs[0].env_id == "CartPole-v1"
    assert check(evidence, "determinism").passed


def test_make_vec_sub_envs_are_each_observed(tmp_path: Path) -> None:
    vectorised = tmp_path / "vec.py"
    vectorised.write_text(
        "import gymnasium as gym\n"
        "envs = gym.make_vec('CartPole-v1', num_envs=2, vectorization_mode='sync')\n"
        "obs, info = envs.reset(seed=1)\n"
        "for _ in range(300):\n"
        "    obs, reward, terminated, truncated, info = envs.step(envs.action_space.sample())\n",
        encoding="utf-8",
    )
    evidence = run_smoke(str(vectorised))
    assert evidence.exit_code == EXIT_OK, failed(evidence)
    assert [(env.env_id, env.reset_seed) for env in evidence.run.envs] == [("CartPole-v1", 1), ("CartPole-v1", 2)]
    assert evidence.run.vector_envs == ("SyncVectorEnv",)
    assert check(evidence, "determinism").passed, "the batched action space is seeded too"


def test_async_vector_workers_are_out_of_sight_and_said_so(tmp_path: Path) -> None:
    vectorised = tmp_path / "async_vec.py"
    vectorised.write_text(
        "import gymnasium as gym\n"
        "if __name__ == '__main__':\n"
        "    envs = gym.make_vec('CartPole-v1', num_envs=2, vectorization_mode='async')\n"
        "    envs.reset(seed=1)\n"
        "    envs.step(envs.action_space.sample())\n"
        "    envs.close()\n",
        encoding="utf-8",
    )
    evidence = run_smoke(str(vectorised))
    assert evidence.exit_code == EXIT_NOT_RUN
    assert "AsyncVectorEnv worker processes" in evidence.load_error
