"""GM107 for the RL libraries that drive envs with gym's API: keras-rl's modules are matched
by their own names only, so a package of the run called ``rl`` (which Python imports in
place of keras-rl) asks nothing, while the same import without it is keras-rl's item."""

from __future__ import annotations

import json
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

runner = CliRunner()
TRAIN = 'import gym\nfrom rl.agents import Learner\n\nenv = gym.make("CartPole-v1")\nLearner().fit(env)\n'


def _items(run: Path) -> list[tuple[str, int, str]]:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code in (0, 1), result.output
    return sorted((Path(f["path"]).name, f["line"], f["rule"]) for f in json.loads(result.stdout) if f["rule"] == "GM107")


def test_a_package_of_the_run_named_rl_is_not_keras_rl(tmp_path: Path) -> None:
    (tmp_path / "rl").mkdir()
    (tmp_path / "rl" / "__init__.py").write_text("")
    (tmp_path / "rl" / "agents.py").write_text("class Learner:\n    def fit(self, env):\n        return env\n")
    (tmp_path / "train.py").write_text(TRAIN)
    assert _items(tmp_path) == []


def test_without_it_the_import_is_keras_rl(tmp_path: Path) -> None:
    (tmp_path / "train.py").write_text(TRAIN)
    assert _items(tmp_path) == [("train.py", 2, "GM107")]
