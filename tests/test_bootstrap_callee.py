"""GM302 follows the callee: what a flag passed to a def is for (facts/bootstrap.py).

``agent.train_model(s, a, r, s2, done)`` says nothing by itself; the def it calls does,
in this module or in another module of the run that never names Gym (an agent's
``calc_loss``). A call that passes no next state is a rollout store, whatever its name.
"""

from __future__ import annotations

import ast
import json
import textwrap
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from gymmigrate.facts.bootstrap import next_state_masks

runner = CliRunner()


def _masks(source: str) -> frozenset[tuple[str, str]]:
    function = ast.parse(textwrap.dedent(source)).body[0]
    assert isinstance(function, ast.FunctionDef)
    return next_state_masks(function)


def test_a_def_that_stores_or_masks_the_next_state_with_the_flag() -> None:
    assert ("done", "next_state") in _masks(
        """
        def append_sample(self, state, action, reward, next_state, done):
            self.memory.append((state, action, reward, next_state, done))
        """
    )
    assert ("done", "new_states") in _masks(
        """
        def calc_loss(self, new_states, hx, done, rewards):
            next_v = 0.0 if done else self.forward(new_states, hx)
            return rewards[-1] + self.gamma * next_v
        """
    )
    assert ("done", "s2") in _masks(
        """
        def target(r, s2, done, gamma=0.9):
            return r + gamma * (1 - done) * value(s2)
        """
    ) or ("done", "s2") in _masks(
        """
        def target(r, s2, done, gamma=0.9):
            y = r + gamma * (1 - done) * value(s2)
            return y
        """
    )


def test_a_flag_that_only_ends_something_or_is_shown_masks_nothing() -> None:
    assert not _masks(
        """
        def log_step(self, state, next_state, done):
            if done:
                return
            print(state, next_state)
        """
    )
    assert not _masks(
        """
        def show(next_state, done):
            print(next_state, done)
        """
    )
    assert not _masks(
        """
        def store_memory(self, state, action, probs, vals, reward, done):
            self.states.append(state)
            self.dones.append(done)
        """
    )


AGENT = '''
import torch as T


class ActorCritic:
    def value(self, states):
        return T.zeros(1)

    def calc_loss(self, new_states, hx, done, rewards, values):
        next_v = T.zeros(1) if done else self.value(new_states)
        values.append(next_v)
        return sum(rewards) + next_v
'''

MEMORY = '''
class Memory:
    def __init__(self):
        self.values, self.rewards, self.dones = [], [], []

    def store_memory(self, state, value, reward, done):
        self.values.append(value)
        self.rewards.append(reward)
        self.dones.append(done)
'''

WORKER = '''
import gym
from agent import ActorCritic
from memory import Memory


def worker(env_id, rollout=20):
    env = gym.make(env_id)
    local_agent = ActorCritic()
    memory = Memory()
    obs = env.reset()
    done, hx, values, rewards = False, None, [], []
    while not done:
        obs_, reward, done, info = env.step(0)
        rewards.append(reward)
        memory.store_memory(obs, 0.0, reward, done)
        obs = obs_
        if len(rewards) % rollout == 0 or done:
            loss = local_agent.calc_loss(obs, hx, done, rewards, values)
'''


def test_a_callee_in_a_module_without_gym_code_decides(tmp_path: Path) -> None:
    project = tmp_path / "project"
    project.mkdir()
    for name, text in {"agent.py": AGENT, "memory.py": MEMORY, "worker.py": WORKER}.items():
        (project / name).write_text(text)
    # another project of the run has its own ``agent`` module: the importer's folder decides
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "agent.py").write_text(AGENT.replace("if done else", "if rewards else"))
    report = tmp_path / "report.json"
    runner.invoke(app, ["check", "--report", str(report), str(tmp_path)])
    data = json.loads(report.read_text())
    found = {
        (f["line"], f["kind"]): f["message"]
        for file in data["files"]
        if file["path"].endswith("worker.py")
        for f in [*file["review"], *file["notes"]]
        if f["rule"] == "GM302"
    }
    # ``obs`` is the next state once ``obs = obs_`` ran: ``calc_loss`` masks it with the flag
    assert "`local_agent.calc_loss`" in found[(19, "assist")]
    # ``memory.store_memory(obs, ...)`` runs before ``obs = obs_``: no next state, a rollout
    assert "without the next state" in found[(16, "flag")]
    # the same file alone cannot see the agent: the call stays a question
    alone = runner.invoke(app, ["check", str(project / "worker.py")])
    assert "calc_loss`, which masks" not in alone.output
