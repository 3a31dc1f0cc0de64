"""An env whose reset steps the wrapper around it (``fixtures/project_wrapper_steps``), migrated
by one ``gymmigrate rewrite`` and run on Gymnasium 1.4 (GM808).

``trials/core.py``: ``Staged.reset`` takes its first observation from
``self.outermost.step(...)``, which ``Layer.__init__`` sets to itself with
``self.unwrapped.hand_to(self)``; ``trials/tasks.py`` subclasses it; ``trials/catalog.py``
registers the tasks it discovers at import time through its own ``register(id, **kwargs)``
helper, and one of them by a literal entry point. With ``gymnasium.make`` the env checker
sits between the layers and the env and raises TypeError on the layer's step inside its own
reset; both registrations now turn the checker off, the helper in a way that keeps a
caller's own ``disable_env_checker``.
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
import trials
from trials.layers import Doubled

for env_id in ("Count-v0", "Count-v1"):
    env = Doubled(gym.make(env_id))
    assert "PassiveEnvChecker" not in str(env), env
    obs, info = env.reset(seed=0)
    assert obs[0] > 0 and obs[0] % 2 == 0, obs  # the first observation went through the layer
    obs, reward, terminated, truncated, info = env.step(1)
    assert reward == 1.0 and truncated is False and info["stage"] * 2 == obs[0], (obs, info)
checked = gym.make("Count-v0", disable_env_checker=False)
assert "PassiveEnvChecker" in str(checked)  # a caller's own choice is kept
print("ok")
"""


def _migrated(tmp_path: Path, *extra: str) -> Path:
    project = tmp_path / "project"
    shutil.copytree(FIXTURES / "project_wrapper_steps", project)
    result = runner.invoke(app, ["rewrite", str(project), *extra])
    assert result.exit_code == 0, result.output
    again = runner.invoke(app, ["rewrite", str(project), *extra])
    assert "rewrote 0 of" in again.output, again.output
    return project


def _run(project: Path, code: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)


def test_an_env_stepping_its_wrapper_in_reset_registers_without_the_checker(tmp_path: Path) -> None:
    project = _migrated(tmp_path)
    catalog = (project / "trials" / "catalog.py").read_text()
    assert 'register(id=id, **{"disable_env_checker": True, **kwargs})' in catalog
    assert 'kwargs={"limit": 3}, disable_env_checker=True)' in catalog
    run = _run(project, _RUN)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["ok"]


def test_without_gm808_the_checker_raises_in_reset(tmp_path: Path) -> None:
    project = _migrated(tmp_path, "--ignore", "GM808")
    run = _run(project, "import gymnasium as gym, trials\nfrom trials.layers import Doubled\nDoubled(gym.make('Count-v1')).reset(seed=0)")
    assert run.returncode != 0 and "cannot unpack non-iterable NoneType object" in run.stderr
