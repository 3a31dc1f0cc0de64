"""The smoke check in this process: env ids and classes, each broken env caught by its own check."""

from __future__ import annotations

import re
from pathlib import Path

import gymnasium
import pytest

from gymmigrate.smoke.evidence import (
    EXIT_CHECK_FAILED,
    EXIT_NOT_RUN,
    EXIT_OK,
    Ending,
    Outcome,
)
from gymmigrate.smoke.probe import SmokeStop, SmokeTimeout
from gymmigrate.smoke.runner import SmokeOptions, run_smoke
from gymmigrate.smoke.targets import LoadError, parse_target

ENVS = Path(__file__).resolve().parent.parent / "fixtures" / "smoke" / "envs.py"
ALL_CHECKS = {
    "reset_returns_obs_info",
    "step_returns_five_fields",
    "flags_are_bool",
    "obs_in_space",
    "no_step_after_end",
    "run_completed",
    "episodes_end",
    "determinism",
    "seed_changes_start",
}


def corridor(name: str) -> str:
    return f"{ENVS}:{name}"


def failed(evidence) -> dict[str, str]:  # noqa: ANN001
    return {check.name: check.message for check in evidence.checks if check.outcome is Outcome.FAILED}


def check(evidence, name: str):  # noqa: ANN001, ANN201
    return next(c for c in evidence.checks if c.name == name)


# -- targets -------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "kind", "location", "class_name"),
    [
        pytest.param("CartPole-v1", "env-id", "CartPole-v1", None, id="env id"),
        pytest.param("ALE/Pong-v5", "env-id", "ALE/Pong-v5", None, id="namespaced env id"),
        pytest.param("envs/maze.py:Maze", "class", "envs/maze.py", "Maze", id="class in a file"),
        pytest.param("mypkg.envs:Maze", "class", "mypkg.envs", "Maze", id="class in a module"),
        pytest.param("train.py", "script", "train.py", None, id="script"),
    ],
)
def test_parse_target(text: str, kind: str, location: str, class_name: str | None) -> None:
    target = parse_target(text)
    assert (target.kind, target.location, target.class_name) == (kind, location, class_name)


def test_parse_target_rejects_a_bad_class_part() -> None:
    with pytest.raises(LoadError, match="path/to/file.py:ClassName"):
        parse_target("envs.py:not a name")


# -- a registered env id -------------------------------------------------------------


def test_cartpole_keeps_the_contract_and_the_evidence_says_so() -> None:
    evidence = run_smoke("CartPole-v1")
    assert evidence.exit_code == EXIT_OK, failed(evidence)
    data = evidence.to_json()
    assert {c["name"] for c in data["checks"]} == ALL_CHECKS
    assert data["env_id"] == "CartPole-v1"
    assert data["wrappers"] == ["TimeLimit", "OrderEnforcing", "PassiveEnvChecker", "CartPoleEnv"]
    assert data["seed"] == 0 and data["render_mode"] is None
    assert set(data["versions"]) == {"gymnasium", "numpy", "python", "gymmigrate"}
    assert data["versions"]["gymnasium"] == gymnasium.__version__
    episodes = data["envs"][0]["episodes"]
    assert len(episodes) == 3
    assert all(e["ending"] == "terminated" and e["length"] == e["return"] for e in episodes)
    assert data["counts"]["terminated"] == 3 and data["counts"]["truncated"] == 0
    assert data["envs"][0]["seed_source"] == "smoke" and data["envs"][0]["reset_seed"] == 0


def test_same_seed_same_evidence_apart_from_timings() -> None:
    first = run_smoke("CartPole-v1", SmokeOptions(seed=5)).to_json()
    second = run_smoke("CartPole-v1", SmokeOptions(seed=5)).to_json()
    first.pop("timings"), second.pop("timings")
    assert first == second


def test_another_seed_gives_other_episodes() -> None:
    seed_5 = run_smoke("CartPole-v1", SmokeOptions(seed=5, determinism=False)).run
    seed_6 = run_smoke("CartPole-v1", SmokeOptions(seed=6, determinism=False)).run
    assert seed_5 and seed_6
    assert [e.digest for e in seed_5.envs[0].episodes] != [e.digest for e in seed_6.envs[0].episodes]


def test_truncations_are_counted_apart_from_terminations() -> None:
    evidence = run_smoke("MountainCar-v0", SmokeOptions(episodes=2, determinism=False))
    assert evidence.exit_code == EXIT_OK
    assert evidence.to_json()["counts"]["truncated"] == 2
    assert check(evidence, "episodes_end").message == "2 episodes ended: 0 terminated, 2 truncated, 0 stopped by budget"


def test_step_budget_stops_an_episode_mid_way() -> None:
    evidence = run_smoke("MountainCar-v0", SmokeOptions(max_steps=50, determinism=False))
    episode = evidence.run.envs[0].episodes[0]
    assert (episode.length, episode.ending) == (50, Ending.BUDGET)
    assert check(evidence, "episodes_end").outcome is Outcome.FAILED
    assert "the loop never ended: 50 steps ran" in check(evidence, "episodes_end").message


def test_unknown_env_id_is_a_load_error() -> None:
    evidence = run_smoke("CartPol-v1")
    assert evidence.exit_code == EXIT_NOT_RUN
    assert evidence.load_error.startswith("unknown env id 'CartPol-v1'")
    assert evidence.checks == ()


def test_registered_broken_env_is_caught_under_gymnasiums_own_wrappers() -> None:
    # make() wraps the env in PassiveEnvChecker, which unpacks five values and raises
    # on the old four-field step: the run fails, and the check names the cause.
    gymnasium.register("SmokeFourField-v0", entry_point=f"{_import_fixture().__name__}:FourFieldStep")
    try:
        evidence = run_smoke("SmokeFourField-v0", SmokeOptions(determinism=False))
    finally:
        gymnasium.registry.pop("SmokeFourField-v0")
    problems = failed(evidence)
    assert evidence.exit_code == EXIT_CHECK_FAILED
    assert problems["step_returns_five_fields"].startswith("FourFieldStep.step() returned 4 values")
    assert "ValueError: not enough values to unpack" in problems["run_completed"]


def _import_fixture():  # noqa: ANN202
    import importlib.util
    import sys

    spec = importlib.util.spec_from_file_location("smoke_fixture_envs", ENVS)
    module = importlib.util.module_from_spec(spec)
    sys.modules["smoke_fixture_envs"] = module
    spec.loader.exec_module(module)
    return module


# -- classes ---------------------------------------------------------------------------


def test_a_class_that_keeps_the_contract_passes_gymnasiums_check_env_too() -> None:
    evidence = run_smoke(corridor("Corridor"))
    assert evidence.exit_code == EXIT_OK, failed(evidence)
    assert evidence.checks[0].name == "gymnasium_check_env"
    assert evidence.checks[0].outcome is Outcome.PASSED
    assert evidence.run.envs[0].wrappers == ("Corridor",)


BROKEN = [
    pytest.param(
        "FourFieldStep",
        "step_returns_five_fields",
        r"^FourFieldStep\.step\(\) returned 4 values \(obs, reward, done, info\), the old Gym API",
        id="four-field step",
    ),
    pytest.param(
        "ObsOnlyReset",
        "reset_returns_obs_info",
        r"^ObsOnlyReset\.reset\(\) returned a ndarray \(\[\d\.\]\) instead of \(obs, info\)",
        id="reset returns only obs",
    ),
    pytest.param(
        "IntFlags", "flags_are_bool", r"^IntFlags\.step\(\) returned terminated=0 of type int", id="non-bool flags"
    ),
    pytest.param("OutOfSpace", "obs_in_space", r"outside its observation_space Box\(0\.0, 8\.0", id="obs out of space"),
    pytest.param(
        "Endless",
        "episodes_end",
        r"^the loop never ended: 1000 steps ran and no episode terminated or truncated",
        id="episode never ends",
    ),
    pytest.param("SeedIgnoring", "seed_changes_start", r"ignores the seed passed to reset\(\)", id="seed ignored"),
    pytest.param(
        "Unseedable",
        "determinism",
        r"^two runs with seed 0 (gave different first transitions|diverged in episode)",
        id="not reproducible",
    ),
]


@pytest.mark.parametrize(("name", "check_name", "message"), BROKEN)
def test_each_broken_env_is_caught_by_its_own_check(name: str, check_name: str, message: str) -> None:
    evidence = run_smoke(corridor(name))
    problems = failed(evidence)
    problems.pop("gymnasium_check_env", None)  # gymnasium's checker may also object; ours must name the cause
    assert evidence.exit_code == EXIT_CHECK_FAILED
    assert set(problems) == {check_name}
    assert re.search(message, problems[check_name]), problems[check_name]


def test_gymnasium_check_env_failure_is_a_named_check_not_a_crash() -> None:
    evidence = run_smoke(corridor("ObsOnlyReset"))
    assert evidence.checks[0].name == "gymnasium_check_env"
    assert evidence.checks[0].message.startswith(
        "gymnasium's check_env failed: AssertionError: The result returned by `env.reset()` was not a tuple"
    )


def test_a_deterministic_start_is_reported_not_failed() -> None:
    evidence = run_smoke(corridor("FixedStart"))
    assert evidence.exit_code == EXIT_OK
    message = check(evidence, "seed_changes_start").message
    assert message.startswith("deterministic start: FixedStart begins every episode")


def test_a_slow_env_is_stopped_at_the_timeout() -> None:
    evidence = run_smoke(corridor("Sleepy"), SmokeOptions(timeout=0.5))
    assert evidence.run.stopped_by == "timeout"
    assert failed(evidence)["episodes_end"].startswith("the loop never ended: still running after 0.5 s")


@pytest.mark.parametrize(
    ("target", "message"),
    [
        pytest.param(corridor("Missing"), "has no class 'Missing'", id="missing class"),
        pytest.param(corridor("NotAnEnv"), "is not a gymnasium.Env subclass", id="not an env"),
        pytest.param(
            corridor("NeedsArguments"), "cannot construct NeedsArguments() without arguments", id="needs arguments"
        ),
        pytest.param("no/such/file.py:Env", "no such file: no/such/file.py", id="missing file"),
        pytest.param(
            "no_such_package.envs:Env", "cannot import no_such_package.envs: ModuleNotFoundError", id="missing module"
        ),
    ],
)
def test_a_class_that_cannot_be_loaded_exits_2(target: str, message: str) -> None:
    evidence = run_smoke(target)
    assert evidence.exit_code == EXIT_NOT_RUN
    assert message in evidence.load_error


def test_script_arguments_are_refused_for_an_env_id() -> None:
    evidence = run_smoke("CartPole-v1", SmokeOptions(script_args=("--lr", "3")))
    assert evidence.exit_code == EXIT_NOT_RUN
    assert evidence.load_error == "extra arguments '--lr 3' are only for a script target"


# -- the observer ------------------------------------------------------------------------


def test_the_observer_leaves_classes_as_it_found_them() -> None:
    module = _import_fixture()
    step, reset = module.Corridor.step, module.Corridor.reset
    run_smoke("smoke_fixture_envs:Corridor", SmokeOptions(determinism=False))
    assert module.Corridor.step is step and module.Corridor.reset is reset
    assert gymnasium.spaces.Discrete.seed.__name__ == "seed" and not hasattr(gymnasium.spaces.Dict.seed, "__wrapped__")
    # The construction hook stays, dormant: envs with and without arguments still build.
    assert module.NeedsArguments("maze.txt").map_file == "maze.txt"
    gymnasium.make("CartPole-v1").close()


def test_a_dict_action_space_seeded_by_the_script_is_left_alone() -> None:
    from gymmigrate.smoke.probe import Budget, Observatory

    observatory = Observatory(9, Budget(1, 10), inject_seed=True)
    with observatory.installed():
        env = _import_fixture().Corridor()
        env.action_space = gymnasium.spaces.Dict({"move": gymnasium.spaces.Discrete(2)})
        env.action_space.seed(123)
        expected = gymnasium.spaces.Dict({"move": gymnasium.spaces.Discrete(2)}, seed=123).sample()
        env.reset()
        assert env.action_space.sample() == expected
    assert observatory.ledgers and next(iter(observatory.ledgers.values())).seed_source == "smoke"


def test_budget_and_timeout_cannot_be_swallowed_by_except_exception() -> None:
    assert not issubclass(SmokeStop, Exception) and issubclass(SmokeStop, BaseException)
    assert not issubclass(SmokeTimeout, Exception)
