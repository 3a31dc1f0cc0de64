"""Gym envs that a factory's thunks or a base class of another module make (issue #19).

``fixtures/project_gym_factories/``: ``envs/creators.py``'s ``get_env_creator`` returns a
thunk bound in two branches, each returning a made env (one inside ``TimeLimit``);
``get_mixed_creator`` returns a made env in one branch and the project's own ``Board`` in
the other. ``scripts/rollout.py`` steps what calling the factory's thunk gives, directly and
through a constructor argument. ``envs/runner.py``'s ``Runner`` stores ``gym.make(...)`` in
``self.env`` and steps it; ``scripts/runners.py``'s ``FastRunner`` and ``scripts/deep.py``'s
``DeepRunner`` (a subclass of it) never store ``self.env`` and step it; ``OwnRunner`` stores
a constructor argument of its own there, and ``OwnTail`` derives it. ``Holder`` stores a
made env it never steps, and ``scripts/players.py``'s ``Player`` steps it; ``Watcher``
resets what ``Keeper`` stores from a constructor argument. What the run proves
made by ``gym.make`` is migrated and runs on Gymnasium; the mixed factory, the class that
stores its own env (and its subclass) and the subclass of a holder of an argument stay asked
about.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.fixture_cases import migrated_project


def _migrated(tmp_path: Path) -> tuple[Path, list[tuple[str, int, str]]]:
    return migrated_project(tmp_path, "project_gym_factories")


def test_what_the_run_proves_made_is_migrated_and_the_rest_asked(tmp_path: Path) -> None:
    project, review = _migrated(tmp_path)
    rollout = (project / "scripts" / "rollout.py").read_text()
    assert rollout.count("reward, terminated, truncated, info = ") == 2  # ``rollout`` and ``Driver``
    assert "obs, reward, done, info = env.step(1)" in rollout  # ``mixed``: a Board in one branch
    runners = (project / "scripts" / "runners.py").read_text()
    assert "obs, reward, terminated, truncated, info = self.env.step(self.env.action_space.sample())" in runners
    assert "obs, reward, done, info = self.env.step(0)" in runners  # ``OwnRunner`` stores its own
    deep = (project / "scripts" / "deep.py").read_text()
    assert "obs, reward, terminated, truncated, info = self.env.step(0)" in deep
    assert "obs, reward, done, info = self.env.step(1)" in deep  # ``OwnTail`` holds OwnRunner's
    players = (project / "scripts" / "players.py").read_text()
    assert "obs, reward, terminated, truncated, info = self.env.step(self.actions - 1)" in players
    assert review == [("scripts/players.py", 16, "GM201"), ("scripts/rollout.py", 35, "GM201"), ("scripts/runners.py", 20, "GM201")]


def test_the_migrated_code_runs_on_gymnasium(tmp_path: Path) -> None:
    project, _ = _migrated(tmp_path)
    code = (
        "from scripts.rollout import rollout, drive\n"
        "from scripts.runners import FastRunner\n"
        "from scripts.deep import DeepRunner\n"
        "from scripts.players import Player\n"
        "print(rollout('cart', 30) > 0, rollout('car', 30) < 0)\n"
        "print(drive('cart', 5).shape)\n"
        "print(FastRunner('CartPole-v1').run(30).shape, FastRunner('CartPole-v1').warm_up().shape)\n"
        "print(DeepRunner('MountainCar-v0').again().shape, Player('CartPole-v1').play(10).shape)\n"
    )
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split("\n")[:4] == ["True True", "(4,)", "(4,) (4,)", "(2,) (4,)"]
