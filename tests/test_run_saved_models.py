"""A new env version is a question where the run loads a saved model, in any module.

``fixtures/project_saved_models``: ``tasks/driving.py`` makes a retired CarRacing id and
loads nothing; ``evaluate.py``, with no Gym code of its own, loads saved weights into a
policy and runs it through that task. Without the evaluation script, nothing of the run
loads a model, and the bump stays a note.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_saved_models"
runner = CliRunner()


def _bump(run: Path) -> tuple[str, str, str]:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code == 1
    [bump] = [f for f in json.loads(result.stdout) if f["rule"] == "GM803"]
    assert Path(bump["path"]).relative_to(run).as_posix() == "tasks/driving.py"
    return bump["kind"], bump["tier"], bump["message"]


def test_a_model_loaded_by_another_module_makes_the_bump_a_question(tmp_path: Path) -> None:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    kind, tier, message = _bump(run)
    assert (kind, tier) == ("assist", "review")
    assert "nothing" not in message


def test_a_run_that_loads_nothing_keeps_the_bump_a_note(tmp_path: Path) -> None:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    (run / "evaluate.py").unlink()
    kind, tier, message = _bump(run)
    assert (kind, tier) == ("assist", "note")
    assert message.endswith("nothing in the run loads a saved model")


def test_a_smoke_script_that_loads_nothing_keeps_its_bump_a_note(tmp_path: Path) -> None:
    """``fixtures/project_smoke_bump``: ``evaluate.py`` loads saved weights into the task of
    ``walker.py``, whose bump stays a question. ``smoke.py`` makes its id at the top level of a
    script with no def or class, and loads nothing: no other module can load a model through
    it, so its bump is a note."""
    run = tmp_path / "run"
    shutil.copytree(FIXTURE.parent / "project_smoke_bump", run)
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code == 1
    bumps = {Path(f["path"]).name: (f["kind"], f["tier"], f["message"]) for f in json.loads(result.stdout) if f["rule"] == "GM803"}
    assert bumps["walker.py"][:2] == ("assist", "review")
    kind, tier, message = bumps["smoke.py"]
    assert (kind, tier) == ("assist", "note")
    assert "nothing in this script" in message and "loads a saved model" in message


def test_a_load_that_cannot_reach_the_module_keeps_its_bump_a_note(tmp_path: Path) -> None:
    """``fixtures/project_unreached_bump``: ``evaluate.py`` loads saved weights into the task
    of ``tasks/driving.py``, whose bump stays a question. ``train_walker.py`` defines a def
    that makes the id it is given, trains from scratch and loads nothing, and no module of the
    run imports it: the load is another program's, so its bump is a note."""
    run = tmp_path / "run"
    shutil.copytree(FIXTURE.parent / "project_unreached_bump", run)
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code == 1
    bumps = {Path(f["path"]).name: (f["kind"], f["tier"], f["message"]) for f in json.loads(result.stdout) if f["rule"] == "GM803"}
    assert bumps["driving.py"][:2] == ("assist", "review")
    kind, tier, message = bumps["train_walker.py"]
    assert (kind, tier) == ("assist", "note")
    assert message.endswith("nothing here or in a module that imports this one loads a saved model")


def test_a_load_through_an_import_chain_makes_the_bump_a_question(tmp_path: Path) -> None:
    """The same run where the evaluation script reaches the trainer through another module
    (``evaluate.py`` imports ``runner.py``, which imports ``train_walker.py``): the model may
    be loaded for its envs, so its bump stays a question."""
    run = tmp_path / "run"
    shutil.copytree(FIXTURE.parent / "project_unreached_bump", run)
    (run / "runner.py").write_text("import gym\n\nfrom train_walker import train\n\nSPACE = gym.spaces.Discrete(2)\n")
    evaluate = run / "evaluate.py"
    evaluate.write_text("import runner\n" + evaluate.read_text())
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    bumps = {Path(f["path"]).name: (f["kind"], f["tier"]) for f in json.loads(result.stdout) if f["rule"] == "GM803"}
    assert bumps["train_walker.py"] == ("assist", "review")
