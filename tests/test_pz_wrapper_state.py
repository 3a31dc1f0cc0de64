"""PZ112 at run time: PettingZoo 1.21-style wrappers that assign what the wrapper bases
used to copy from the env, rewritten, behave on PettingZoo 1.27 as they did on 1.21.

Up to 1.24.2, ``BaseWrapper.reset``/``step`` copied the env's ``rewards`` (and
``agent_selection``, ``terminations``, ... ) onto the wrapper, and
``BaseParallelWrapper.reset``/``step`` its ``agents``; since 1.24.3 they are forwarded only
while the wrapper has no attribute of its own. Each test runs the fixture as written (only
its import spelling fixed, so it loads) and as rewritten, against the installed PettingZoo.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app

pytest.importorskip("pettingzoo")
with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)  # module-level creation warns on 1.27
    from pettingzoo.classic import rps_v2
from pettingzoo.test import parallel_api_test  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent / "fixtures"
FIXTURES = ROOT / "rules" / "PZ112"
# rock for player_0, paper for player_1: player_1 wins every round
MOVES = {"player_0": 0, "player_1": 1}


def _namespace(name: str) -> dict:
    source = (FIXTURES / name).read_text()
    source = source.replace("import BaseParallelWraper\n", "import BaseParallelWrapper as BaseParallelWraper\n")
    namespace: dict = {"__name__": name}
    exec(compile(source, name, "exec"), namespace)
    return namespace


@pytest.fixture(autouse=True)
def quiet_deprecations():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        yield


def _scaled_rewards(name: str) -> list[tuple[dict, dict]]:
    """Two seeded games of rock-paper-scissors through ``ScaleRewards(env, 10)``: after each
    step, the wrapper's rewards next to ten times the env's."""
    env = _namespace(name)["ScaleRewards"](rps_v2.env(max_cycles=3), 10)
    seen = []
    for episode in range(2):
        env.reset(seed=episode)
        for agent in env.agent_iter():
            _, _, termination, truncation, _ = env.last()
            env.step(None if termination or truncation else MOVES[agent])
            seen.append((dict(env.rewards), {a: 10 * r for a, r in env.env.rewards.items()}))
    return seen


def test_scaled_rewards_follow_the_env_once_migrated() -> None:
    legacy = _scaled_rewards("reward_scaling_wrapper.py")
    # On 1.27 the wrapper keeps the dict it made at reset (all zeros) and rescales it.
    assert all(not any(wrapper.values()) for wrapper, _ in legacy)
    migrated = _scaled_rewards("reward_scaling_wrapper.expected.py")
    assert all(wrapper == scaled for wrapper, scaled in migrated)
    assert any(wrapper.get("player_1") == 10 for wrapper, _ in migrated)
    assert any(wrapper.get("player_0") == -10 for wrapper, _ in migrated)


def _episodes(name: str) -> tuple[list[list[str]], int]:
    env = _namespace(name)["CountSteps"](rps_v2.parallel_env(max_cycles=3))
    agents_at_reset = []
    for episode in range(2):
        env.reset(seed=episode)
        agents_at_reset.append(list(env.agents))
        while env.agents:
            env.step({agent: MOVES[agent] for agent in env.agents})
    return agents_at_reset, env.steps


def test_a_parallel_wrappers_agents_are_the_envs_after_reset_once_migrated() -> None:
    # On 1.27 the second episode starts with the empty list the first one ended with.
    assert _episodes("parallel_agents_copy.py") == ([["player_0", "player_1"], []], 3)
    assert _episodes("parallel_agents_copy.expected.py") == ([["player_0", "player_1"]] * 2, 6)
    migrated = _namespace("parallel_agents_copy.expected.py")["CountSteps"]
    parallel_api_test(migrated(rps_v2.parallel_env(max_cycles=5)), num_cycles=10)


_PLAY = """
import warnings
warnings.simplefilter("ignore", DeprecationWarning)
from pettingzoo.classic import rps_v2
from rewards import NegateRewards, ScaleRewards
for wrapper in (ScaleRewards(rps_v2.env(max_cycles=2), 10), NegateRewards(rps_v2.env(max_cycles=2))):
    for episode in range(2):
        wrapper.reset(seed=episode)
        for agent in wrapper.agent_iter():
            _, _, termination, truncation, _ = wrapper.last()
            wrapper.step(None if termination or truncation else {"player_0": 0, "player_1": 1}[agent])
            print(sorted(wrapper.rewards.items()))
"""


def test_wrappers_over_a_base_of_another_module_get_the_copy(tmp_path: Path) -> None:
    """``fixtures/project_pz_wrappers``: ``rewards.py`` derives from the project's
    ``base.py``, which re-exports PettingZoo's ``OrderEnforcingWrapper``; the run follows it."""
    project = tmp_path / "project"
    shutil.copytree(ROOT / "project_pz_wrappers", project)
    legacy = subprocess.run([sys.executable, "-c", _PLAY], cwd=project, capture_output=True, text=True, timeout=120)
    assert legacy.returncode == 0, legacy.stderr
    assert "[('player_0', -10), ('player_1', 10)]" not in legacy.stdout.splitlines()  # its stale dict, rescaled
    runner = CliRunner()
    alone = runner.invoke(app, ["rewrite", str(project / "rewards.py")])
    assert alone.exit_code == 0 and "rewrote 0 of 1" in alone.output  # the base is not known alone
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    text = (project / "rewards.py").read_text()
    assert text.count("        super().step(action)\n        self.rewards = self.env.rewards\n") == 2
    assert text.count("    def reset(self, seed=None, options=None):\n") == 2
    assert "rewrote 0 of" in runner.invoke(app, ["rewrite", str(project)]).output
    run = subprocess.run([sys.executable, "-c", _PLAY], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    assert "[('player_0', -10), ('player_1', 10)]" in lines
    assert "[('player_0', 1), ('player_1', -1)]" in lines
