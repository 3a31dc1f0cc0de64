"""A module whose every env comes from a Gym-only plugin stays on gym, as the run sees it
(``rules/imports/plugin_modules.py``): an id the run registers itself is a Gymnasium env
once the run is migrated, so a module making it is migrated too; a literal id that neither
Gymnasium nor the run has is the imported plugin's."""

from __future__ import annotations

from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

runner = CliRunner()

_SOURCES = {
    "envs/__init__.py": 'import gym\n\ngym.register(id="Maze-v0", entry_point="envs.maze:Maze")\n',
    "envs/maze.py": (
        "import gym\nfrom gym import spaces\n\n\nclass Maze(gym.Env):\n    def __init__(self):\n"
        "        self.observation_space = spaces.Discrete(4)\n        self.action_space = spaces.Discrete(2)\n"
    ),
    # the run registers this id: its env is the run's own, migrated with it
    "own.py": 'import d4rl\nimport gym\n\nimport envs\n\nenv = gym.make("Maze-v0")\nobs = env.reset()\n',
    # the plugin's dataset id
    "offline.py": 'import d4rl\nimport gym\n\nenv = gym.make("maze2d-umaze-v1")\nobs = env.reset()\n',
    # neither Gymnasium's nor the run's: the imported plugin registered it
    "other.py": 'import d4rl\nimport gym\n\nenv = gym.make("sorter-random-v0")\nobs = env.reset()\n',
}


def test_plugin_modules_in_a_run(tmp_path: Path) -> None:
    for name, text in _SOURCES.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(text)
    result = runner.invoke(app, ["rewrite", "--jobs", "1", str(tmp_path)])
    assert result.exit_code in (0, 1), result.output
    assert (tmp_path / "own.py").read_text().startswith("import d4rl\nimport gymnasium as gym\n")
    assert "obs, info = env.reset()" in (tmp_path / "own.py").read_text()
    assert (tmp_path / "offline.py").read_text() == _SOURCES["offline.py"]
    assert (tmp_path / "other.py").read_text() == _SOURCES["other.py"]
    assert "offline.py:2: GM101 (not rewritten) left on gym with the rest of this module" in result.output
