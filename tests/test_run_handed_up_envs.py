"""Envs a base of another module holds from the parameter a subclass hands up (issue #19).

``fixtures/project_handed_up_envs/``: ``flat.Flat`` hands its ``inner`` up to
``holder.Holder.__init__`` (``super().__init__``, the first of its two bases), which stores it
on ``self._inner`` and returns it from the ``inner`` property; ``main.py`` builds ``Flat`` only
over Gym envs (``gym.make(...)`` results, and ``LongCorridor``, its own subclass of the run's
``Corridor``), so its step and reset on ``self.inner`` are rewritten and its own four-field
contract kept. ``scaled.Scaled`` hands its ``env`` up to ``proxy.Proxy``,
a Gym env whose step and reset are the held env's (a wrapper written by hand): nothing
builds ``Scaled``, and the env it holds is still a Gym env, so its calls are rewritten with
no question (they were asked, and its step unpacked four values).

The near cases: ``Logged`` is built only over the project's own ``Board`` (left, no
question); nothing builds ``Unbuilt``, whose ``Holder`` is no Gym env (its step stays asked).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.fixture_cases import migrated_project


def test_handed_up_attributes_are_traced_and_the_near_cases_kept(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_handed_up_envs")
    flat = (project / "flat.py").read_text()
    assert "        obs, info = self.inner.reset()\n        return list(obs)\n" in flat
    assert "obs, reward, terminated, truncated, info = self.inner.step(action)\n        done = terminated or truncated\n        return list(obs), reward, done, info" in flat
    assert flat.count("obs, reward, done, info = self.inner.step(action)") == 2  # Logged, Unbuilt
    scaled = (project / "scaled.py").read_text()
    assert "obs, info = self._wrapped_env.reset()\n        return obs * self._scale, info" in scaled
    assert "return obs * self._scale, reward, terminated, truncated, info" in scaled
    assert review == [("flat.py", 35, "GM301")]


def test_the_migrated_code_runs_on_gymnasium(tmp_path: Path) -> None:
    project, _ = migrated_project(tmp_path, "project_handed_up_envs")
    code = (
        "import gymnasium, main, scaled\n"
        "env = scaled.Scaled(gymnasium.make('CartPole-v1'))\n"
        "obs, info = env.reset(seed=0)\n"
        "print(main.play_flat(3), main.play_logged(), len(env.step(0)), main.walk()[1])\n"
    )
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["3.0", "[1.0]", "5", "False"]
