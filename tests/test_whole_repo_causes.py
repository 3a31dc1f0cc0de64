"""Causes the whole-repository benchmark found (benchmarks/whole_repos.py: ma-gym, mo-gym, nasim),
each a fixture package migrated by one ``gymmigrate rewrite`` and run on Gymnasium 1.4.

``fixtures/project_teams/`` is a multi-agent package: its envs keep one space per agent in
a ``list`` subclass and register in the package's ``__init__`` (GM807: Gymnasium's env
checker, which ``make`` runs, rejects such spaces), and its tests reach the env through
pytest-cases ``fixture_ref`` parametrization and write its attributes (GM604).
``fixtures/project_rewards/`` has a vector-reward env and a scalarising wrapper with its
own constructor argument, checked with ``check_env``, which recreates the env from its
spec (GM617), and which draws its slips from Python's global ``random`` (GM510: check_env
tests that a seeded reset makes steps reproducible).
``fixtures/project_batches/`` (SuperSuit's shapes): its tests are parametrized over a list
of wrappers around the package's own env, and its ``VectorEnv`` subclass resets a list of
sub-envs that the package's own obs-only batches are written into, and keeps that
obs-only reset itself (its callers are left on it).
``fixtures/project_statistics/`` (mo-gym's shape): a subclass of gym's
``RecordEpisodeStatistics`` that computes vector-reward statistics in its own ``step`` on
the state gym 0.26's base set (GM618 restores it), re-exported by the package and used on
one env, on each env of the package's vector env, and on the whole vector env (reported:
GM708).
``fixtures/project_agents/`` (NetworkAttackSimulator's shape): an agent module that never
names the library reads an attribute of the env its callers in other modules pass (GM604),
and the package's ``Discrete`` subclass checks its elements with ``isinstance(i, int)``
(GM903). ``fixtures/project_render_factory/`` (its shape too): the tests render with a mode
an env the package's own factory made, and ``render`` keeps ``mode`` for them (GM405).
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from tests.fixture_cases import FIXTURES

runner = CliRunner()


def _migrated(name: str, tmp_path: Path, *extra: str) -> Path:
    project = tmp_path / name
    shutil.copytree(FIXTURES / name, project)
    result = runner.invoke(app, ["rewrite", str(project), *extra])
    assert result.exit_code == 0, result.output
    again = runner.invoke(app, ["rewrite", str(project), *extra])
    assert "rewrote 0 of" in again.output, again.output
    return project


def _run(project: Path, code: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)


_RELAY = """
import gymnasium as gym
import teams

for n in (2, 3):
    env = gym.make("Relay-v0", n_agents=n)
    obs, info = env.reset(seed=0)
    env.set_wrapper_attr("baton", n - 1)
    assert env.unwrapped.baton == n - 1
    assert len(env.action_space.sample()) == n
    obs, rewards, terminated, truncated, info = env.step([1] * n)
    assert all(terminated) and rewards == [1.0] * n, (terminated, rewards)
team = gym.make("TeamCartPole-v0")
obs, info = team.reset(seed=1)
steps, done = 0, [False]
while not all(done):
    obs, rewards, terminated, truncated, info = team.step(team.action_space.sample())
    done = terminated or truncated
    steps += 1
assert len(obs) == 1 and terminated == [True] and truncated is False and steps < 500
solo = gym.make("Solo-v0")
assert "PassiveEnvChecker" in str(solo)
solo.reset(seed=0)
print(solo.step(0)[1])
"""


def test_list_spaces_register_without_the_env_checker_and_the_tests_reach_the_env(tmp_path: Path) -> None:
    project = _migrated("project_teams", tmp_path)
    init = (project / "teams" / "__init__.py").read_text()
    assert init.count("disable_env_checker=True") == 2  # Relay and OneAgent: Solo's Box space keeps its checker
    single = (project / "teams" / "single.py").read_text()
    assert "return [obs], [reward], [terminated or truncated], False, info" in single or "[done], False, info" in single
    tests = (project / "tests" / "test_relay.py").read_text()
    assert 'env.set_wrapper_attr("baton", env.get_wrapper_attr("n_agents") - 1)' in tests
    assert "obs, rewards, terminated, truncated, info = env.step(" in tests
    run = _run(project, _RELAY)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["1.0"]


def test_without_gm807_make_raises_on_the_list_spaces(tmp_path: Path) -> None:
    project = _migrated("project_teams", tmp_path, "--ignore", "GM807")
    run = _run(project, "import gymnasium as gym, teams\ngym.make('Relay-v0')")
    assert run.returncode != 0 and "does not inherit from `gymnasium.spaces.Space`" in run.stderr


_SCALAR = """
import gymnasium as gym
import numpy as np
from gymnasium.utils.env_checker import check_env

import scalar

env = scalar.Weighted(gym.make("TwoGoals-v0"), np.array([1.0, 0.5]))
check_env(env.unwrapped)
check_env(env)
again = gym.make(env.spec)
assert type(again).__name__ == "Weighted" and list(again.weight) == [1.0, 0.5]


def episode(seed):
    again.reset(seed=seed)
    path = []
    for _ in range(20):
        obs, reward, terminated, truncated, info = again.step(1)
        path.append((float(obs[0]), reward, *info["vector_reward"].tolist()))
        if terminated or truncated:
            return path, terminated
    raise AssertionError("TimeLimit(20) did not end the episode")


first, ended = episode(3)
assert episode(3) == (first, ended)  # a seeded reset makes the slips reproducible
print(len(first) >= 5, first[-1][1] in (0.0, 1.0, 0.5))
"""


def test_a_wrapper_with_arguments_is_recreated_from_its_spec(tmp_path: Path) -> None:
    project = _migrated("project_rewards", tmp_path)
    wrappers = (project / "scalar" / "wrappers.py").read_text()
    assert "class Weighted(gym.Wrapper, gym.utils.RecordConstructorArgs):" in wrappers
    assert "gym.utils.RecordConstructorArgs.__init__(self, weight=weight)" in wrappers
    assert "if self.np_random.random() < 0.05:" in (project / "scalar" / "envs.py").read_text()
    run = _run(project, _SCALAR)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["True", "True"]


def test_without_gm617_check_env_cannot_recreate_the_wrapper(tmp_path: Path) -> None:
    project = _migrated("project_rewards", tmp_path, "--ignore", "GM617")
    run = _run(project, _SCALAR)
    assert run.returncode != 0 and "cannot be recreated" in run.stderr


def test_parametrized_envs_are_traced_and_the_run_s_own_batches_are_left(tmp_path: Path) -> None:
    project = _migrated("project_batches", tmp_path)
    test = (project / "checks" / "test_batches.py").read_text()
    assert "obs, info = env.reset(seed=5)" in test  # each parametrized item is the package's env
    concat = (project / "batches" / "concat.py").read_text()
    assert "obs = self.sub_envs[i].reset(seed=seed + i, options=options)" in concat  # SingleBatch's own reset
    assert "[sub_env.reset(seed=None, options=options) for sub_env" in concat
    # ConcatBatches is a vector env whose own reset still returns the rows alone: its
    # callers stay on that contract (reported), not unpacked as a Gymnasium vector reset.
    assert "rows = envs.reset(seed=seed)" in test
    run = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-W", "ignore", "checks"],
        cwd=project, capture_output=True, text=True, timeout=120,
    )
    assert run.returncode == 0, run.stdout + run.stderr
    assert "5 passed" in run.stdout


def _pytest(project: Path, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-W", "ignore", *args],
        cwd=project, capture_output=True, text=True, timeout=120,
    )


def test_a_statistics_subclass_gets_gym_0_26_state_back_and_its_vector_use_is_reported(tmp_path: Path) -> None:
    report = tmp_path / "report.json"
    result = runner.invoke(app, ["check", str(FIXTURES / "project_statistics"), "--report", str(report)])
    assert result.exit_code == 1, result.output  # changes pending, and review items
    project = _migrated("project_statistics", tmp_path)
    wrappers = (project / "mostats" / "wrappers.py").read_text()
    assert 'self.num_envs = getattr(self.env, "num_envs", 1)' in wrappers
    assert "self.t0 = time.perf_counter()" in wrappers
    assert "self.episode_lengths = np.zeros(self.num_envs, dtype=np.int32)" in wrappers
    findings = json.loads(report.read_text())["findings"]
    by_rule = {(Path(f["path"]).name, f["line"], f["rule"], f["kind"]) for f in findings}
    assert ("wrappers.py", 8, "GM618", "assist") in by_rule
    # the whole vector env in a single-env wrapper: Gymnasium 1.x's Wrapper raises; reported
    assert ("test_stats.py", 38, "GM708", "flag") in by_rule
    run = _pytest(project, "checks", "-k", "not the_whole_batch")
    assert run.returncode == 0 and "2 passed" in run.stdout, run.stdout + run.stderr


def test_without_gm618_the_statistics_subclass_fails_on_gymnasium(tmp_path: Path) -> None:
    project = _migrated("project_statistics", tmp_path, "--ignore", "GM618")
    run = _pytest(project, "checks", "-k", "one_env")
    assert run.returncode != 0 and "has no attribute 'num_envs'" in run.stdout, run.stdout


def test_an_agent_module_that_never_names_gym_reads_its_env_through_the_wrappers(tmp_path: Path) -> None:
    """``fixtures/project_agents/`` (NetworkAttackSimulator's shape): ``run_cycler(env)`` in
    a module that never names the library reads ``env.flat`` and steps with ``(act + 1) %
    env.action_space.n``; other modules pass it a ``gym.make`` env and the bare env class.
    The read goes through ``get_wrapper_attr`` (GM604: the run's callers pass only Gym
    envs), and the ``isinstance(index, int)`` check in the package's ``Discrete`` subclass
    accepts the ``np.int64`` that Gymnasium's ``n`` arithmetic gives (GM903)."""
    project = _migrated("project_agents", tmp_path)
    agent = (project / "cyclers" / "agent.py").read_text()
    assert 'if env.get_wrapper_attr("flat"):' in agent
    moves = (project / "cyclers" / "moves.py").read_text()
    assert "isinstance(index, (int, np.integer))" in moves
    run = _pytest(project, "checks")
    assert run.returncode == 0 and "2 passed" in run.stdout, run.stdout + run.stderr


def test_without_gm604_and_gm903_the_agent_fails_on_gymnasium(tmp_path: Path) -> None:
    project = _migrated("project_agents", tmp_path, "--ignore", "GM604,GM903")
    run = _pytest(project, "checks")
    assert "has no attribute 'flat'" in run.stdout and "must be an integer" in run.stdout, run.stdout


def test_render_keeps_its_mode_for_a_package_factory_s_env(tmp_path: Path) -> None:
    """``fixtures/project_render_factory/`` (NetworkAttackSimulator's shape): the tests get
    the env from the package's own factory (``boards.make_board()``, re-exported through two
    ``__init__`` modules) and call ``env.render(mode="text")``; no mode can move to a make
    there, so ``render`` keeps ``mode`` as an optional parameter (GM405)."""
    project = _migrated("project_render_factory", tmp_path)
    board = (project / "boards" / "envs" / "board.py").read_text()
    assert "def render(self, mode=None):" in board and "mode = self.render_mode" in board
    run = _pytest(project, "checks")
    assert run.returncode == 0 and "2 passed" in run.stdout, run.stdout + run.stderr


def test_wrappers_derived_from_a_wrapper_class_of_another_module_read_their_env(tmp_path: Path) -> None:
    """``fixtures/project_wrapper_bases/`` (neurogym's shape): ``ChoiceWrapper(trials.PhaseWrapper)``
    (re-exported from ``trials/core.py``) reads ``self.choices``, which neither it nor its
    bases set, inside ``try/except AttributeError``; ``ScaledWrapper.new_trial`` runs
    ``self.ob = self.ob * 2``, the first read of which gym found on the env. Before: both
    were left, and Gymnasium 1.4 raised in every construction and trial.
    ``get_wrapper_attr`` raises AttributeError too: the refusal of an env without choices
    is kept."""
    project = tmp_path / "project_wrapper_bases"
    shutil.copytree(FIXTURES / "project_wrapper_bases", project)
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    wrappers = (project / "trials" / "wrappers.py").read_text()
    assert 'len(self.get_wrapper_attr("choices"))' in wrappers
    assert 'self.ob = self.get_wrapper_attr("ob") * 2' in wrappers
    code = "import play\nprint(play.choices(), play.refused(), play.scaled())"
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "4 ChoiceWrapper needs an env with choices (16.0, 32.0)"
