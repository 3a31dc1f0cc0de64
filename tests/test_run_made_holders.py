"""A chain of ``.env`` below a make result that a plain class of another module keeps (issue #19).

``fixtures/project_made_holders/``: ``holder.Holder`` stores ``self.env = gym.make(name)``;
``adapter.Adapter`` is handed a ``Holder`` by every construction of the run
(``factory.create_env``) and keeps ``env.env.env``: on the gym its code was written for, the
env under make's TimeLimit, to which the reads below it went. On Gymnasium that layer is
``OrderEnforcing``, which forwards nothing, so the chain becomes ``env.env.unwrapped``.
``adapter.Loose`` is handed a ``holder.Rewrapped``, which may keep a wrapper of the caller's
own: it is left as it is.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.fixture_cases import migrated_project


def test_the_chain_below_the_kept_make_is_its_unwrapped_env(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_made_holders")
    adapter = (project / "adapter.py").read_text()
    assert "self.raw = env.env.unwrapped\n" in adapter
    assert "self.env = env.env\n" in adapter  # the make result itself stays
    assert "self.raw = env.env.env\n" in adapter  # Loose: the holder may keep a wrapper of its own
    assert review == []


def test_the_migrated_adapter_reaches_the_env_on_gymnasium(tmp_path: Path) -> None:
    project, _ = migrated_project(tmp_path, "project_made_holders")
    code = (
        "import factory\n"
        "env, dim = factory.create_env('CartPole-v1')\n"
        "assert type(env.raw).__name__ == 'CartPoleEnv', type(env.raw)\n"
        "assert dim == 4 and env.threshold() == 2.4\n"
    )
    done = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
