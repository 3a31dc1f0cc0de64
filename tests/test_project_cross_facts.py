"""Facts of one module that another module's rewrite needs, joined across the run.

``fixtures/project_cross_step_counts/``: a subclass's step returns ``truncated=False``; its
base in another module counts no steps (a note), or counts them (a review item).
``fixtures/project_cross_own_api/``: dm_env adapters of one module used in others.
``fixtures/project_cross_render_ctor/``: an env built by a run class in one module and
rendered bare in another.
``fixtures/project_cross_render_holder/``: a holder class whose render() forwards to its env,
rendered from another module.
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


def _copy(name: str, tmp_path: Path) -> Path:
    target = tmp_path / name
    shutil.copytree(FIXTURES / name, target)
    return target


def _review(output: str) -> str:
    return output.partition("Review (")[2]


def test_truncated_false_is_a_note_when_the_base_elsewhere_counts_no_steps(tmp_path: Path) -> None:
    """``Hopper(RobotBase)``: RobotBase (base.py) counts nothing, so the step cannot end on
    a limit of its own; ``Runner(TimedBase)``: TimedBase counts steps, the item stays."""
    project = _copy("project_cross_step_counts", tmp_path)
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    assert "return obs, 1.0, fell, False, {}" in (project / "envs" / "hopper.py").read_text()
    review = _review(result.output)
    assert "hopper.py:10: GM504" not in review
    assert "runner.py:8: GM504" in review


def test_an_own_api_adapter_of_another_module_is_no_gym_env(tmp_path: Path) -> None:
    """``env = adapters.CartAdapter(env)`` and ``Stacker(env)`` (stacking.py, a subclass of
    ``adapters.Adapter(dm_env.Environment)``): TimeStep envs, whatever they hold. Their
    reset/step calls are left with no item; only the import and the adapter's own Gym calls
    change, and stacking.py, which holds no Gym code, is left as it is."""
    project = _copy("project_cross_own_api", tmp_path)
    before = (project / "pkg" / "stacking.py").read_text()
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    test = (project / "pkg" / "adapters_test.py").read_text()
    assert "import gymnasium as gym" in test
    assert "timestep = env.reset()\n" in test and "_ = env.step(0)\n" in test
    assert (project / "pkg" / "stacking.py").read_text() == before
    review = _review(result.output)
    assert "adapters_test.py" not in review and "stacking.py" not in review


def test_an_own_api_adapter_that_forwards_attributes_still_reaches_the_gym_env(tmp_path: Path) -> None:
    """``adapters.CartForwarding`` (a dm_env adapter whose base hands what it lacks to the
    Gym env it holds, ``__getattr__``): ``env.render("rgb_array")`` reaches the Gym env, so
    it is not left as another API's call (a TypeError on Gymnasium): the mode moves to the
    make; the adapter's own reset (a TimeStep) is left."""
    project = _copy("project_cross_own_api", tmp_path)
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    test = (project / "pkg" / "forwarding_test.py").read_text()
    assert 'gym.make("CartPole-v1", render_mode="rgb_array")' in test
    assert "frame = env.render()\n" in test and "    env.reset()\n" in test


def test_a_constructor_of_another_module_gets_the_mode_its_bare_renders_need(tmp_path: Path) -> None:
    """``env = Console(cartridge)`` then ``play(env, n)`` (cli.py), where ``play`` (play.py)
    only calls ``env.render()`` bare: the constructor, whose migrated ``__init__`` takes
    render_mode, gets ``render_mode="human"`` and the render is a note; ``replay`` is also
    given an env built inline, so its constructors are left as they are."""
    project = _copy("project_cross_render_ctor", tmp_path)
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    cli = (project / "arcade" / "cli.py").read_text()
    assert cli.count('render_mode="human"') == 1
    assert '    env = Console(cartridge, render_mode="human")\n    play(env, episodes)' in cli
    assert "replay(Console(cartridge), 3)" in cli
    assert "play.py:7: GM402" not in _review(result.output)
    run = subprocess.run(
        [sys.executable, "-W", "ignore", "-c", "from arcade.cli import main\nprint(main('x', 2) > 0)"],
        cwd=project,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert run.returncode == 0 and run.stdout.strip() == "True", run.stderr + run.stdout


def test_a_holder_render_of_another_module_points_at_its_forward(tmp_path: Path) -> None:
    """``sim.render()`` (run.py) on ``Simulator`` (sim/holder.py, re-exported by the
    package), whose own render() forwards bare to the env it makes: the decision is asked
    at that forward, and the script's call is a note pointing there, not a second question."""
    project = _copy("project_cross_render_holder", tmp_path)
    result = runner.invoke(app, ["check", str(project)])
    review = _review(result.output)
    assert "holder.py:15: GM402" in review
    assert "run.py:7: GM402" not in review
    assert "run.py:7:5: GM402 [flag] not rewritten: `sim.render()` calls `Simulator.render()`" in result.output
    assert "(in sim/holder.py)" in result.output
