"""Gym wrapper classes of another module that hand on what the wrapped env's step and reset
give keep the legacy API around an env kept on it (``fixtures/project_legacy_forward``).

``hold.compat.Legacy`` presents the old API behind a gym version check, so the run leaves it
alone. ``train.py`` wraps it in ``hold.shape.Clip`` (its step and reset return the inner
env's) and ``Nudge`` (an ``ActionWrapper``), imported through the package's star
re-exports, and gets the same chain from ``hold.make.build`` (a factory of another module):
its reset and step calls stay legacy. ``Legacy`` defines seed(): called on it, it is left;
called through the wrappers around it, which forward no ``seed`` in Gymnasium, it becomes
``get_wrapper_attr("seed")(s)``. ``plain.py`` puts ``Clip`` around a plain Gym env: those
calls are migrated.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_legacy_forward"
runner = CliRunner()


@pytest.fixture
def run(tmp_path: Path) -> Path:
    shutil.copytree(FIXTURE, tmp_path / "run")
    return tmp_path / "run"


def test_calls_on_a_forwarding_wrapper_around_the_kept_one_stay(run: Path) -> None:
    before = {p: (run / p).read_text() for p in ("train.py", "plain.py")}
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code in (0, 1), result.output
    expected = before["train.py"].replace("import gym\n", "import gymnasium as gym\n", 1)
    # the seed() of ``Legacy`` inside the chain, which Gymnasium's wrappers do not forward
    expected = expected.replace("env.seed(3)", 'env.get_wrapper_attr("seed")(3)')
    expected = expected.replace("built.seed(7)", 'built.get_wrapper_attr("seed")(7)')
    assert (run / "train.py").read_text() == expected
    assert (run / "hold/make.py").read_text() == (FIXTURE / "hold/make.py").read_text().replace("import gym\n", "import gymnasium as gym\n", 1)
    plain = (run / "plain.py").read_text()
    assert "observation, info = env.reset()" in plain
    assert "terminated, truncated, _ = env.step(" in plain


def test_a_seed_on_the_kept_wrapper_itself_is_left_with_a_note(run: Path) -> None:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code in (0, 1), result.output
    findings = [f for f in json.loads(result.stdout) if Path(f["path"]).name == "train.py" and f["rule"] == "GM203"]
    assert sorted((f["line"], f["tier"]) for f in findings) == [(21, "note"), (24, "note"), (30, "note")]
    assert not (run / "train.py").read_text().count("alone.get_wrapper_attr")


def test_the_migrated_run_plays_on_gymnasium(run: Path) -> None:
    pytest.importorskip("gymnasium")
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code in (0, 1), result.output
    probe = "from train import main\nfrom plain import run\nprint(main(40) + run(20))\n"
    done = subprocess.run([sys.executable, "-c", probe], cwd=run, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert float(done.stdout) > 0


def test_a_gym_mixin_base_keeps_the_wrapper_forwarding(run: Path, tmp_path: Path) -> None:
    """``Clip`` also derived from ``gym.utils.EzPickle`` (Gym's mixin, which defines no step or
    reset) still hands on its env's results: the run decides as it does without the mixin."""
    plain = tmp_path / "plain_run"
    shutil.copytree(FIXTURE, plain)
    shape = run / "hold/shape.py"
    text = shape.read_text()
    assert "class Clip(gym.Wrapper):" in text
    shape.write_text(text.replace("class Clip(gym.Wrapper):", "class Clip(gym.Wrapper, gym.utils.EzPickle):", 1))
    for tree in (run, plain):
        result = runner.invoke(app, ["rewrite", str(tree)])
        assert result.exit_code in (0, 1), result.output
    assert (run / "train.py").read_text() == (plain / "train.py").read_text()
    assert (run / "hold/make.py").read_text() == (plain / "hold/make.py").read_text()
