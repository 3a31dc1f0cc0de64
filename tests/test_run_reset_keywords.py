"""An env whose reset takes keywords of its own that the project's wrappers pass down
(``fixtures/project_reset_keywords``), migrated by one ``gymmigrate rewrite`` and run on
Gymnasium 1.4 (GM207).

``chain/core.py``: ``Task.reset(..., step_fn=None, quiet=False)`` takes its first
observation from ``step_fn``, which ``Layer`` and ``Scaled`` set to their own ``self.step``
and hand down with ``self.env.reset(step_fn=...)``; ``chain/use.py`` passes ``quiet=``.
Gymnasium's wrappers take only ``seed`` and ``options``: the keywords now travel in
``options`` at every site, and ``step_fn``'s result unpacks five values.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from tests.fixture_cases import FIXTURES

runner = CliRunner()

_RUN = """
import gymnasium as gym
from chain.core import Layer, Scaled, Task
from chain.use import first

ob, quiet = first()
assert ob[0] == 10.0, ob  # the first observation went through Scaled's step
gym.register("Chain-v0", entry_point="chain.core:Task", disable_env_checker=True)
for env in (Layer(Scaled(gym.make("Chain-v0"))), gym.wrappers.TimeLimit(Layer(Scaled(Task())), 5)):
    obs, info = env.reset(seed=0)
    assert obs[0] == 10.0, obs
obs, info = Layer(Scaled(Task())).reset(options={"quiet": True})
print("ok")
"""


def test_reset_keywords_travel_in_options_down_the_wrappers(tmp_path: Path) -> None:
    project = tmp_path / "project"
    shutil.copytree(FIXTURES / "project_reset_keywords", project)
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    again = runner.invoke(app, ["rewrite", str(project)])
    assert "rewrote 0 of" in again.output, again.output
    core = (project / "chain" / "core.py").read_text()
    assert 'return self.env.reset(seed=seed, options={**(options or {}), "step_fn": step_fn})' in core
    assert "ob, _, _, _, _ = step_fn(" in core
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", _RUN], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["ok"]


def test_blocked_contract_names_its_places_relative_to_the_reporting_module(tmp_path: Path) -> None:
    # A positional pass elsewhere in the run blocks the move: the env's reset gets one item
    # naming that place, as a path relative to the module (not the checkout's location).
    project = tmp_path / "project"
    shutil.copytree(FIXTURES / "project_reset_keywords", project)
    (project / "chain" / "extra").mkdir()
    (project / "chain" / "extra" / "blocker.py").write_text(
        "import gym\n\n\nclass Other(gym.Env):\n    def reset(self, step_fn):\n        return 0\n"
    )
    result = runner.invoke(app, ["check", str(project)])
    places = [line.split("cannot be rewritten:")[1] for line in result.output.splitlines() if "cannot be rewritten:" in line]
    assert places, result.output
    assert all(str(tmp_path) not in shown for shown in places), places
    assert any("extra/blocker.py:5 (`step_fn=`)" in shown for shown in places), places


def test_blocked_contract_names_the_calls_that_pass_the_keywords(tmp_path: Path) -> None:
    # The env's reset item names where the run passes its keywords (the calls a person
    # changes, in this module and others), not only the place that blocked the move.
    project = tmp_path / "project"
    shutil.copytree(FIXTURES / "project_reset_keywords", project)
    (project / "chain" / "extra").mkdir()
    (project / "chain" / "extra" / "blocker.py").write_text(
        "import gym\n\n\nclass Other(gym.Env):\n    def reset(self, step_fn):\n        return 0\n"
    )
    result = runner.invoke(app, ["check", str(project)])
    item = next(line for line in result.output.splitlines() if "core.py:16:" in line and "cannot be rewritten:" in line)
    callers = item.split("to this reset (at ")[1].split(")")[0]
    assert callers == "line 32, line 39, use.py:9", item
    # the blocker's own reset is named as its parameter, not as a place of the run
    other = next(line for line in result.output.splitlines() if "blocker.py:5:" in line and "cannot be rewritten:" in line)
    assert "this reset's own `step_fn` parameter" in other, other
_RUN_SUBCLASS = """
from arm.use import firsts, grip, track

hard, moved = firsts()
assert hard[0] == 5.0 and moved[0] == 6.0, (hard, moved)
assert grip() == 2.0
assert track()[0] == 5.0

print("ok")
"""


def test_keywords_of_a_subclass_env_whose_base_is_imported_travel_in_options(tmp_path: Path) -> None:
    # ``ReachEnv(BaseSim)`` with ``BaseSim`` imported: its module alone cannot tell it is a
    # Gym env, the run can; every keyword a caller passes down the wrappers moves, not only
    # those the base's reset takes. ``BigGripper`` (no env) keeps its own keywords.
    project = tmp_path / "project"
    shutil.copytree(FIXTURES / "project_reset_keywords_subclass", project)
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    again = runner.invoke(app, ["rewrite", str(project)])
    assert "rewrote 0 of" in again.output, again.output
    reach = (project / "arm" / "reach.py").read_text()
    assert 'random_pose = (options or {}).get("random_pose", random_pose)' in reach
    use = (project / "arm" / "use.py").read_text()
    assert 'env.reset(options={"random_pose": True})' in use
    assert "gripper.reset(force=2.0)" in use
    assert "def reset(self, wide=False, force=1.0):" in (project / "arm" / "bigger.py").read_text()
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", _RUN_SUBCLASS], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["ok"]


def test_direct_parent_reset_up_a_base_of_another_module_is_no_wrapper_call(tmp_path: Path) -> None:
    # ``TrackEnv(CameraSim)``, ``CameraSim`` imported and without a reset of its own: its
    # ``super().reset(hard=...)`` reaches ``BaseSim.reset``, which keeps ``hard``; no wrapper
    # is in between, so no item. A keyword no reset up the chain takes is still asked about.
    project = tmp_path / "project"
    shutil.copytree(FIXTURES / "project_reset_keywords_subclass", project)
    result = runner.invoke(app, ["check", str(project)])
    assert not [line for line in result.output.splitlines() if "track.py" in line and "GM207 [flag]" in line], result.output
    track = project / "arm" / "track.py"
    track.write_text(track.read_text().replace("super().reset(hard=hard)", "super().reset(hard=hard, slow=slow)"))
    result = runner.invoke(app, ["check", str(project)])
    flagged = [line for line in result.output.splitlines() if "track.py:6" in line and "GM207 [flag]" in line]
    assert flagged and "`slow=`" in flagged[0], result.output
