"""Issue #19 on Gymnasium 1.4: receivers proven through constructor arguments, and a next
state masked by ``None`` (the PyTorch DQN tutorial's terminal transition).

The legacy programs run against the stand-in legacy Gym of ``test_semantics`` (a four-value
``step`` and a ``TimeLimit`` that ends episodes with ``done=True``); their migrations run
against the installed Gymnasium with the same dynamics.
"""

from __future__ import annotations

import importlib.util
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from tests.test_semantics import migrate, run_legacy, run_migrated

# -- an agent class that receives its env through its constructor -----------------------------

AGENTS = textwrap.dedent(
    """
    import gym


    class Agent:
        def __init__(self, env):
            self.env = env

        def episode(self):
            state = self.env.reset()
            total, steps = 0.0, 0
            while True:
                state, reward, done, _ = self.env.step(1)
                total += reward
                steps += 1
                if done:
                    return total, steps

        def evaluate(self):
            plain = self.env
            self.env = Passing(self.env)
            result = self.episode()
            self.env = plain
            return result


    class Passing(gym.Wrapper):
        pass


    class Learner(Agent):
        def __init__(self, env, lr):
            super().__init__(env)
            self.lr = lr

        def first_reward(self):
            self.env.reset()
            _, reward, done, _ = self.env.step(0)
            return reward


    def run():
        env = gym.make("SemanticsWalk-v0")
        agent = Agent(env)
        learner = Learner(gym.make("SemanticsWalk-v0"), lr=0.1)
        return [agent.episode(), agent.episode(), agent.evaluate(), learner.first_reward()]
    """
)


def test_constructor_argument_receivers_are_rewritten_and_run(monkeypatch: pytest.MonkeyPatch) -> None:
    legacy = run_legacy(AGENTS, "run", monkeypatch)
    text, findings = migrate(AGENTS)
    # proven through the constructor calls (the save/restore of self.env and the subclass's
    # super().__init__ included): rewritten as certain, no "could not trace" review item
    assert "state, info = self.env.reset()" in text
    assert "state, reward, terminated, truncated, _ = self.env.step(1)" in text
    assert "_, reward, terminated, truncated, _ = self.env.step(0)" in text
    assert not [f for f in findings if f[1] in ("GM201", "GM301") and f[2] != "auto"]
    assert run_migrated(text, "run") == legacy  # the same episodes, a time-limit cut included


# -- ``next_state = None`` on a terminal transition ---------------------------------------------

NONE_MASK = textwrap.dedent(
    """
    import gym


    def transitions(steps=30):
        env = gym.make("SemanticsWalk-v0")
        state = env.reset()
        memory, cut = [], []
        for t in range(steps):
            observation, reward, done, info = env.step(1)
            if done:
                next_state = None
            else:
                next_state = observation
            memory.append((state, reward, next_state))
            cut.append(info.get("TimeLimit.truncated", False))
            state = env.reset() if done else observation
        return memory, cut
    """
)


def test_next_state_masked_by_none_keeps_truncated_next_states(monkeypatch: pytest.MonkeyPatch) -> None:
    legacy_memory, legacy_cut = run_legacy(NONE_MASK, "transitions", monkeypatch)
    text, findings = migrate(NONE_MASK)
    assert "if terminated:\n            next_state = None" in text
    assert (11, "GM302", "assist", "note") in findings
    memory, _ = run_migrated(text, "transitions")
    assert any(legacy_cut), "the time limit must cut an episode in this run"
    assert any(old[2] is None and not was_cut for old, was_cut in zip(legacy_memory, legacy_cut)), "and the goal end one"
    for old, new, was_cut in zip(legacy_memory, memory, legacy_cut):
        if was_cut:
            # legacy stored no next state at the cut (no bootstrapping); now it keeps it
            assert old[2] is None and new[2] is not None
        else:
            assert (new[2] is None) == (old[2] is None)
        assert new[1] == old[1]


# -- an Atari id reaching make through an argparse default or a parameter default -----------------

ATARI_LAUNCHER = textwrap.dedent(
    """
    import argparse

    import gym

    DEFAULT_ENV_NAME = "PongNoFrameskip-v4"


    def make_env(env_id="BreakoutNoFrameskip-v4"):
        return gym.make(env_id)


    def run(argv):
        parser = argparse.ArgumentParser()
        parser.add_argument("--env", default=DEFAULT_ENV_NAME)
        args = parser.parse_args(argv)
        return [make_env(args.env), make_env()]
    """
)


def test_atari_ids_through_defaults_are_registered_before_make(tmp_path: Path) -> None:
    if importlib.util.find_spec("ale_py") is None:
        pytest.skip("ale_py is not installed")
    text, findings = migrate(ATARI_LAUNCHER)
    assert "import ale_py\n\ngym.register_envs(ale_py)" in text
    assert any(f[1] == "GM106" for f in findings)
    # A fresh interpreter: the registration happens when ale_py is first imported.
    driver = "envs = run([])\nprint([env.spec.id for env in envs])\nfor env in envs:\n    env.reset(seed=0)\n"
    (tmp_path / "migrated.py").write_text(text + "\n\n" + driver)
    run = subprocess.run([sys.executable, "migrated.py"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "['PongNoFrameskip-v4', 'BreakoutNoFrameskip-v4']"
    legacy = (tmp_path / "legacy.py")
    legacy.write_text(text.replace("import ale_py\n\ngym.register_envs(ale_py)\n", "") + "\n\n" + driver)
    unregistered = subprocess.run([sys.executable, "legacy.py"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert unregistered.returncode != 0 and "NameNotFound" in unregistered.stderr  # what the rewrite prevents


# -- class checks on the spaces of a Gym-only package's envs -------------------------------------

SPACE_CHECKS = textwrap.dedent(
    """
    import gym
    from gym import spaces
    from multiagent.environment import MultiAgentEnv


    def head_for(space):
        if isinstance(space, spaces.Box):
            return "gaussian"
        if isinstance(space, spaces.Discrete):
            return "categorical"
        return "unknown"


    def heads():
        return [head_for(space) for space in MultiAgentEnv().action_space]
    """
)

# Stand-ins: a Gym-only package whose env builds the space classes of (a minimal) legacy gym.
STAND_IN_GYM = "from gym import spaces\n"
STAND_IN_SPACES = "class Box:\n    pass\n\n\nclass Discrete:\n    pass\n"
STAND_IN_MULTIAGENT = (
    "from gym import spaces\n\n\nclass MultiAgentEnv:\n    def __init__(self):\n"
    "        self.action_space = [spaces.Box(), spaces.Discrete()]\n"
)


def test_space_checks_on_a_gym_only_packages_envs_keep_their_answers(tmp_path: Path) -> None:
    (tmp_path / "gym").mkdir()
    (tmp_path / "gym" / "__init__.py").write_text(STAND_IN_GYM)
    (tmp_path / "gym" / "spaces.py").write_text(STAND_IN_SPACES)
    (tmp_path / "multiagent").mkdir()
    (tmp_path / "multiagent" / "__init__.py").write_text("")
    (tmp_path / "multiagent" / "environment.py").write_text(STAND_IN_MULTIAGENT)
    text, findings = migrate(SPACE_CHECKS)
    assert "\nfrom gym import spaces\n" in text  # left on gym, and said why
    assert (3, "GM102", "flag", "review") in findings

    def heads(program: str) -> str:
        (tmp_path / "program.py").write_text(program + "\nprint(heads())\n")
        run = subprocess.run([sys.executable, "program.py"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
        assert run.returncode == 0, run.stderr
        return run.stdout.strip()

    legacy = heads(SPACE_CHECKS)
    assert legacy == "['gaussian', 'categorical']"
    assert heads(text) == legacy  # migrated: Gymnasium for the rest, the checks still answer
    # What the plain rewrite of the import would have done: every check False, silently.
    assert heads(text.replace("\nfrom gym import spaces\n", "\nfrom gymnasium import spaces\n")) == "['unknown', 'unknown']"
