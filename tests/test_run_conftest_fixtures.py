"""pytest fixtures of a conftest.py are the values of the tests' parameters of their names
(``fixtures/project_conftest_fixtures``): the tests below the conftest take a Gym env class's
instance and a Gym wrapper of the run over one, by parameter name and through
``request.getfixturevalue``; a test that parametrizes the name itself, and a script beside
the tests' directory, are not given them.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_conftest_fixtures"
runner = CliRunner()


def _migrated(tmp_path: Path) -> Path:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code in (0, 1), result.output
    return run


def test_fixture_parameters_are_the_fixtures_values(tmp_path: Path) -> None:
    text = (_migrated(tmp_path) / "tests" / "unit" / "test_tank.py").read_text()
    assert "def test_reset(tank):\n    obs, info = tank.reset()" in text
    assert "obs, info = wide_tank.reset()" in text  # ``@pytest.fixture(name="wide_tank")``
    assert "obs, reward, terminated, truncated, info = wide_tank.step(0)" in text
    assert "    env = request.getfixturevalue(name)\n    obs, info = env.reset()" in text


def test_reads_through_a_fixtures_wrapper(tmp_path: Path) -> None:
    text = (_migrated(tmp_path) / "tests" / "unit" / "test_tank.py").read_text()
    assert 'assert env.get_wrapper_attr("level") == 0' in text  # a bare env or the wrapper
    assert 'assert gauged.has_wrapper_attr("level")' in text
    assert 'assert gauged.get_wrapper_attr("level") == 0' in text
    # the wrapper's own attribute needs no forwarding
    assert 'assert hasattr(gauged, "last_raw")' in text
    assert "assert gauged.last_raw is not None" in text


def test_names_the_fixture_does_not_reach(tmp_path: Path) -> None:
    run = _migrated(tmp_path)
    text = (run / "tests" / "unit" / "test_tank.py").read_text()
    assert "def test_tank_parametrized_here(tank):\n    obs = tank.reset()" in text
    assert (run / "scripts" / "drive.py").read_text() == (FIXTURE / "scripts" / "drive.py").read_text()
