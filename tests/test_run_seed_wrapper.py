"""A wrapper class of the project with a seed() of its own (``fixtures/project_seed_wrapper``),
migrated by one ``gymmigrate rewrite`` and run on Gymnasium 1.4 (GM203).

``tasks.py``: ``Alternate(Layer)`` (``Layer`` a ``gym.Wrapper`` of ``base.py``) rolls one of several ``Die`` envs, picked by its own
generator; its seed() seeds every die and that generator, its reset picks a die and resets it
bare. ``two_dice`` is registered as ``TwoDice-v0``. ``play.py``: ``env.seed(seed);
env.reset()`` on ``gym.make(env_id)``, and a plain class seeding made envs. Merged into
``env.reset(seed=seed)``, the seed reached neither the dice nor the picker (two seeded runs
differed); ``env.get_wrapper_attr("seed")(seed)`` calls the seed() gym's forwarding reached.
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


def test_a_wrappers_own_seed_is_still_what_seeds_made_envs(tmp_path: Path) -> None:
    project = tmp_path / "project"
    shutil.copytree(FIXTURES / "project_seed_wrapper", project)
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    again = runner.invoke(app, ["rewrite", str(project)])
    assert "rewrote 0 of" in again.output, again.output
    play = (project / "play.py").read_text()
    assert '    env.get_wrapper_attr("seed")(seed)\n    first, info = env.reset()\n' in play
    assert "env.reset(seed=" not in play
    run = subprocess.run(
        [sys.executable, "-W", "ignore", "-c", "import play; print(play.main())"],
        cwd=project,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["True"]


def test_without_a_seeding_wrapper_the_seed_is_merged_into_the_reset(tmp_path: Path) -> None:
    project = tmp_path / "project"
    shutil.copytree(FIXTURES / "project_seed_wrapper", project)
    tasks = project / "tasks.py"
    text = tasks.read_text()
    start = text.index("class Alternate(")
    end = text.index('register(id="TwoDice-v0"')
    tasks.write_text(text[:start] + text[end:].replace('register(id="TwoDice-v0", entry_point="tasks:two_dice")\n', ""))
    play = project / "play.py"
    play.write_text(play.read_text().replace('("TwoDice-v0", "Die-v0")', '("Die-v0",)'))
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    text = play.read_text()
    assert "first, info = env.reset(seed=seed)" in text
    assert "env.unwrapped.seed(seed)" in text  # the plain class's seed() as before
