"""Gym envs a batch class builds from a list of thunks made in another module (issue #19).

``fixtures/project_thunk_batches/``: ``farm/thunks.py``'s ``make_env`` returns a closure
returning ``gym.make(env_id)``; ``farm/train.py`` passes ``[make_env(...) for i in ...]``
to ``farm/batch.py``'s ``Batch``, which holds ``self.envs = [fn() for fn in env_fns]``.
The env's own method and attribute on those items (``env.set_width``, ``self.envs[0].width``)
reached the base env through legacy wrapper forwarding: they go through
``get_wrapper_attr``. ``MixedBatch`` is also fed the project's own counters by another
call: what it holds stays as it is. The batch keeps its own four-value step.
``farm/workers.py``'s ``ProcBatch`` spawns ``worker`` with ``Pickled(env_fn)`` (a holder
storing the thunk on ``x``) for each thunk: ``env = holder.x()`` there is a Gym env too, so
``env.set_width`` goes through ``get_wrapper_attr``; ``CountProcs``, also spawned with the
project's counters, is left.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.fixture_cases import migrated_project


def test_items_built_from_gym_thunks_read_through_the_wrappers(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_thunk_batches")
    batch = (project / "farm" / "batch.py").read_text()
    assert 'env.get_wrapper_attr("set_width")(width)' in batch
    assert 'return self.envs[0].get_wrapper_attr("width")' in batch
    assert "ob, rew, terminated, truncated, info = self.envs[i].step(actions[i])" in batch
    assert "results.append((ob, rew, done, info))" in batch  # the batch's own contract
    assert "item.set_width(width)" in batch  # fed the project's counters too: left
    workers = (project / "farm" / "workers.py").read_text()
    assert 'env.get_wrapper_attr("set_width")(data)' in workers
    assert "ob, reward, terminated, truncated, info = env.step(data)" in workers
    assert "    item.set_width(data)" in workers  # spawned with the project's counters too: left
    assert review == []


def test_the_migrated_code_runs_on_gymnasium(tmp_path: Path) -> None:
    project, _ = migrated_project(tmp_path, "project_thunk_batches")
    code = "from farm.train import run, mixed, run_procs\nprint(run(2), run_procs(2)); mixed()\n"
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "(3, [True, True]) [5.0, 5.0]"
