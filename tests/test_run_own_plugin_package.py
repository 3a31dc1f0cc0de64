"""A Gym-only plugin's ids made by the plugin's own package: the run is that package.

``make("gfootball:GFootball-...-v0")`` in a project that does not contain gfootball makes
an env of a package with no Gymnasium release, so a module making only such envs stays on
gym with one item (GM101, fixture ``GM107/gfootball_made_by_id``). In gfootball's own
repository the same line is the package testing its own envs, which move to Gymnasium with
it: the module is migrated as any other.
"""

from __future__ import annotations

from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

TEST = """import gym


def test_steps():
    env = gym.make("gfootball:GFootball-academy_empty_goal-SMM-v0")
    env.reset()
    obs, reward, done, info = env.step(env.action_space.sample())
    assert obs is not None
"""


def _write(root: Path, *, own: bool) -> Path:
    tests = root / ("gfootball" if own else "project") / "env"
    tests.mkdir(parents=True)
    (tests.parent / "__init__.py").write_text(
        'import gym\n\ngym.register(id="GFootball-academy_empty_goal-SMM-v0", entry_point="gfootball.env:FootballEnv")\n'
        if own
        else "",
        encoding="utf-8",
    )
    (tests / "__init__.py").write_text("", encoding="utf-8")
    (tests / "gym_test.py").write_text(TEST, encoding="utf-8")
    return tests / "gym_test.py"


def test_the_plugins_own_package_migrates_its_tests(tmp_path: Path) -> None:
    test = _write(tmp_path, own=True)
    result = CliRunner().invoke(app, ["rewrite", str(tmp_path)])
    assert result.exit_code == 0, result.output
    text = test.read_text(encoding="utf-8")
    assert "import gymnasium as gym" in text
    assert "obs, reward, terminated, truncated, info = env.step(" in text


def test_another_project_keeps_a_plugin_only_module_on_gym(tmp_path: Path) -> None:
    test = _write(tmp_path, own=False)
    result = CliRunner().invoke(app, ["rewrite", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert test.read_text(encoding="utf-8") == TEST
    assert "GM101" in result.output and "gfootball" in result.output
