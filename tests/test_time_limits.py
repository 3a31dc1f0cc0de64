"""A done that is a step or time limit becomes ``truncated`` (facts/limits.py), end to end.

Each shape is migrated and run on Gymnasium 1.4 / PettingZoo 1.27: the episode the limit
ends is truncated, not terminated.

* a helper's dict key (``self._dones()["__all__"]``) in a custom env (GM504);
* a PettingZoo AEC env whose ``dones`` come from the simulation it holds (PZ108);
* a base env whose ``_compute_done`` its subclasses in other modules of the run
  override with the limit (GM504 through the run's class hierarchy); a goal override
  among them makes it a report that names the limit's line instead;
* a step count kept in a named entry of a dict the env holds (``self.board["moves"]``);
* a subclass's limit folded into a flag the base's step reads through a helper's returned
  tuple and arguments: named in a report, not settled as a class that counts nothing.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import types
import warnings
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app
from gymmigrate.engine import transform_source
from tests.fixture_cases import FIXTURES

runner = CliRunner()


def _migrated(fixture: str) -> types.ModuleType:
    path = FIXTURES / "rules" / fixture
    result = transform_source(path.read_bytes(), str(path))
    assert result.changed
    module = types.ModuleType(fixture.replace("/", "_")[:-3])
    exec(compile(result.rewritten, str(path), "exec"), module.__dict__)
    return module


def test_a_limit_in_a_helpers_dict_key_ends_the_episode_truncated() -> None:
    from gymnasium.utils.env_checker import check_env

    module = _migrated("GM504/limit_in_done_helper.py")
    env = module.CorridorSim(max_steps=3)
    env.reset(seed=0)
    endings = []
    for _ in range(10):
        _, _, terminated, truncated, _ = env.step(1)
        endings.append((terminated, truncated))
        if terminated or truncated:
            break
    assert endings == [(False, False)] * 3 + [(False, True)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        check_env(module.CorridorSim(), skip_render_check=True)


def test_a_step_count_kept_in_a_dict_entry_ends_the_episode_truncated() -> None:
    module = _migrated("GM504/keyed_entry_counts_steps.py")
    env = module.Maze()
    env.reset(seed=0)
    endings = []
    for _ in range(40):
        _, _, terminated, truncated, _ = env.step(1)
        endings.append((terminated, truncated))
        if terminated or truncated:
            break
    assert endings == [(False, False)] * 30 + [(False, True)]


def test_a_pettingzoo_limit_from_the_held_simulation_goes_to_truncations() -> None:
    pytest.importorskip("pettingzoo")
    module = _migrated("PZ108/limit_through_inner_sim.py")
    env = module.TrafficAEC()
    env.reset(seed=0)
    ended = {}
    for agent in env.agent_iter(max_iter=50):
        _, _, termination, truncation, _ = env.last()
        if termination or truncation:
            ended[agent] = (termination, truncation)
            env.step(None)
        else:
            env.step(0)
    assert ended == {"a": (False, True), "b": (False, True)}


def _copy(tmp_path: Path) -> Path:
    target = tmp_path / "project_time_limits"
    shutil.copytree(FIXTURES / "project_time_limits", target)
    return target


def test_subclasses_limit_across_the_run_is_returned_as_truncated(tmp_path: Path) -> None:
    project = _copy(tmp_path)
    report = tmp_path / "report.json"
    result = runner.invoke(app, ["rewrite", "--report", str(report), str(project)])
    assert result.exit_code == 0, result.output
    base = (project / "drones" / "base.py").read_text()
    assert "return obs, 1.0, False, done, {}" in base
    items = [f for file in json.loads(report.read_text())["files"] for f in file["review"]]
    messages = [f["message"] for f in items if f["rule"] == "GM504"]
    assert len(messages) == 1 and "hover.py:16" in messages[0] and "CAPTURE_FREQ" not in messages[0]
    code = (
        "from drones.hover import HoverSim\nfrom drones.idle import IdleSim\n"
        "env = HoverSim()\nenv.reset(seed=0)\nends = []\n"
        "for _ in range(20):\n    o, r, te, tr, i = env.step(0)\n    ends.append((te, tr))\n    if te or tr: break\n"
        "print(len(ends), ends[-1])\n"
        "idle = IdleSim()\nidle.reset()\nprint(idle.step(0)[2:4])\n"
    )
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split("\n")[:2] == ["6 (False, True)", "(False, False)"]


def test_a_goal_override_in_the_run_makes_it_a_report_naming_the_limit(tmp_path: Path) -> None:
    project = _copy(tmp_path)
    (project / "drones" / "reach.py").write_text(
        "from gym import spaces\n\nfrom drones.base import BaseSim\n\n\n"
        "class ReachSim(BaseSim):\n    def __init__(self):\n        super().__init__()\n"
        "        self.action_space = spaces.Discrete(2)\n\n"
        "    def _compute_done(self):\n        return self.step_counter >= 2 and self.frames[-1] > 0\n"
    )
    report = tmp_path / "report.json"
    result = runner.invoke(app, ["rewrite", "--report", str(report), str(project)])
    assert result.exit_code == 0, result.output
    base = (project / "drones" / "base.py").read_text()
    assert "return obs, 1.0, terminated, False, {}" in base  # not the limit's alone: kept, reported
    items = [f for file in json.loads(report.read_text())["files"] for f in file["review"]]
    messages = [f["message"] for f in items if f["rule"] == "GM504"]
    assert len(messages) == 1 and "hover.py:16" in messages[0] and "among its causes" in messages[0]


def test_a_subclasses_limit_through_the_bases_helpers_is_named_not_settled(tmp_path: Path) -> None:
    """``fixtures/project_limit_through_arguments``: the base's step unpacks a flag from
    ``self.score(infos, dones)`` and hands it to ``self.per_agent(dones, game_over)``; the
    subclass in another module folds its time limit into the flag ``score`` returns. One item
    names that limit at the base's return, never the note that the class counts nothing."""
    target = tmp_path / "project_limit_through_arguments"
    shutil.copytree(FIXTURES / "project_limit_through_arguments", target)
    report = tmp_path / "report.json"
    result = runner.invoke(app, ["rewrite", "--report", str(report), str(target)])
    assert result.exit_code == 0, result.output
    assert "return obs, tuple(rewards), terminated, False, tuple(infos)" in (target / "arena" / "base.py").read_text()
    findings = [f for file in json.loads(report.read_text())["files"] for f in file["review"] + file["notes"]]
    messages = [(f["tier"], f["message"]) for f in findings if f["rule"] == "GM504"]
    assert len(messages) == 1 and messages[0][0] == "review"
    assert "timed.py:17" in messages[0][1] and "among its causes" in messages[0][1]


def test_a_subclass_folding_only_the_tasks_end_keeps_the_note(tmp_path: Path) -> None:
    """The same base with a subclass whose ``score`` folds only an end of the task: nothing
    the run follows counts steps, so the base's step keeps its note."""
    target = tmp_path / "project_limit_through_arguments"
    shutil.copytree(FIXTURES / "project_limit_through_arguments", target)
    (target / "arena" / "timed.py").write_text(
        "from gym import spaces\n\nfrom arena.base import Arena\n\n\n"
        "class RingArena(Arena):\n    def __init__(self, agents=2):\n        super().__init__(agents)\n"
        "        self.action_space = spaces.Tuple([spaces.Discrete(2)] * agents)\n\n"
        "    def score(self, infos, dones):\n        out = any(info.get('out') for info in infos)\n"
        "        return [0.0] * self.agents, out or any(dones)\n"
    )
    report = tmp_path / "report.json"
    result = runner.invoke(app, ["rewrite", "--report", str(report), str(target)])
    assert result.exit_code == 0, result.output
    findings = [f for file in json.loads(report.read_text())["files"] for f in file["review"] + file["notes"]]
    messages = [(f["tier"], f["message"]) for f in findings if f["rule"] == "GM504"]
    assert len(messages) == 1 and messages[0][0] == "note" and "counts nothing" in messages[0][1]


_STEP = "class E:\n    def step(self, a):\n        self.n += 1\n{body}\n        return obs, 0.0, done, {{}}\n{helpers}"


@pytest.mark.parametrize(
    ("body", "helpers", "cause"),
    [
        ("        done = self.t % self.FREQ == 0", "", "termination"),  # a period, not a limit
        ("        done = self.n >= self.budget", "", "truncation"),  # a count step advances
        ("        done = self.pos >= self.goal or self.n > 9", "", "mixed"),
        ("        done = not self.t > 5", "", "unknown"),
        ("        done = self._over()", "    def _over(self):\n        if self.t < self.T:\n            return False\n        else:\n            return True\n", "truncation"),
        ("        done = self._over()", "    def _over(self):\n        if self.hit:\n            return True\n        return False\n", "termination"),
        ("        d = self._dones()\n        done = d['__all__']", "    def _dones(self):\n        d = {a: False for a in self.agents}\n        d['__all__'] = True if self.t > 3 else False\n        return d\n", "truncation"),
        ("        done = self.flag", "    def reset(self):\n        self.flag = False\n    def tick(self):\n        if self.steps >= self.max_steps:\n            self.flag = True\n", "truncation"),
        # The end of the env's data is a terminal state, whatever the bound is called ...
        ("        done = self.n >= self.max_steps", "    def __init__(self, data):\n        self.max_steps = len(data) - 1\n", "termination"),
        ("        done = self.t == self.max_step", "    def __init__(self, a):\n        self.max_step = a.shape[0] - 1\n", "termination"),
        ("        done = self.t >= len(self.df.index.unique()) - 1", "", "termination"),
        # ... but not a budget: a parameter, one store of anything else, a length against a budget.
        ("        done = self.n >= self.max_steps", "    def __init__(self, data, max_steps):\n        self.max_steps = max_steps\n", "truncation"),
        ("        done = self.n >= self.max_steps", "    def __init__(self, data):\n        self.max_steps = len(data)\n    def resize(self, k):\n        self.max_steps = k\n", "truncation"),
        ("        done = len(self.history) >= self.max_steps", "", "truncation"),
        # A named entry of a dict the env holds counts as an attribute does; a number index does not.
        ("        self.board['moves'] += 1\n        done = self.board['moves'] > 30", "", "truncation"),
        ("        self.cart[0] += 1\n        done = self.cart[0] > 30", "", "termination"),
        # Helpers followed with their arguments, the tuples they return, per-agent copies of a flag.
        ("        done = self._over(self.n)", "    def _over(self, steps):\n        return steps >= self.max_steps\n", "truncation"),
        ("        done = self._over(self.hit)", "    def _over(self, hit):\n        return hit or self.n > 9\n", "mixed"),
        ("        score, done = self._score()", "    def _score(self):\n        return 1.0, self.t > self.T\n", "truncation"),
        ("        done = tuple(self.n > 9 for _ in range(2))", "", "unknown"),
        ("        done = False\n        done = done or self.n > 9", "", "truncation"),
    ],
)
def test_done_causes(body: str, helpers: str, cause: str) -> None:
    import ast

    from gymmigrate.facts.limits import DoneTracer
    from gymmigrate.facts.module import ModuleFacts

    text = _STEP.format(body=body, helpers=helpers)
    facts = ModuleFacts(ast.parse(text), text)
    classdef = facts.classes["E"]
    step = next(m for m in classdef.body if isinstance(m, ast.FunctionDef) and m.name == "step")
    done = step.body[-1].value.elts[2]
    assert DoneTracer(facts, classdef).trace(done).cause.value == cause


def test_an_env_that_hands_an_inner_step_on_keeps_its_truncations_and_seeds() -> None:
    """``fixtures/rules/GM504/inner_step_flags_passed_on.py``: Pendulum's time limit ends the
    episode as a truncation through every layer, and ``reset(seed=...)`` reaches the inner
    env through ``**kwargs`` (the same seed gives the same first observation)."""
    module = _migrated("GM504/inner_step_flags_passed_on.py")
    env = module.make()
    first, _ = env.reset(seed=3)
    again, _ = module.make().reset(seed=3)
    assert first.shape == (2,) and (first == again).all()
    steps = 0
    while True:
        steps += 1
        _, _, terminated, truncated, _ = env.step(env.action_space.sample())
        if terminated or truncated:
            break
    assert (steps, terminated, truncated) == (200, False, True)
