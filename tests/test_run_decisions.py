"""One decision, one review item across the files of a run (``report.decide_once``).

``fixtures/project_decisions``: three scripts that load a saved policy bump the same env id and import the same
Gym-only library. Each decision is one review item, in the first file by path, naming
the other places; those are notes pointing at it. Another id whose bump is the same
change (the same version step of the catalog) joins it; a decision only one file makes
stays its own item, and ``check`` still exits 1 (findings) with every place listed.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_decisions"
runner = CliRunner()


@pytest.fixture
def run(tmp_path: Path) -> Path:
    shutil.copytree(FIXTURE, tmp_path / "run")
    return tmp_path / "run"


def _review(findings: list[dict]) -> list[tuple[str, int, str]]:
    return sorted((Path(f["path"]).name, f["line"], f["rule"]) for f in findings if f["tier"] == "review")


def test_check_asks_each_run_wide_decision_once_and_lists_every_place(run: Path) -> None:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code == 1
    findings = json.loads(result.stdout)
    assert _review(findings) == [("evaluate.py", 7, "GM803"), ("evaluate.py", 12, "GM803"), ("test.py", 5, "GM107")]
    hopper = [f for f in findings if f["rule"] == "GM803" and "Hopper-v2" in f["message"]]
    assert len(hopper) == 3  # every place is still listed
    first = next(f for f in hopper if f["tier"] == "review")
    assert first["message"].endswith(
        f"(the same question at line 13) (the same decision at 2 other places: {run / 'scripts' / 'test.py'}:8, "
        f"{run / 'scripts' / 'train.py'}:8)"
    )
    for note in (f for f in hopper if f["tier"] == "note"):
        assert note["message"].endswith(f"(decided once, at {run / 'scripts' / 'evaluate.py'}:7)")
    # Walker2d-v2 takes Hopper-v2's version step (the same change): it joins that decision;
    # LunarLander-v2's change is another one, asked at line 12 on its own
    walker = next(f for f in findings if f["rule"] == "GM803" and "Walker2d-v2" in f["message"])
    assert (walker["line"], walker["tier"]) == (13, "note") and walker["message"].endswith("(asked once, at line 7)")
    roboschool = [f for f in findings if f["rule"] == "GM107"]
    assert [f["tier"] for f in sorted(roboschool, key=lambda f: f["path"])] == ["review", "note"]


def test_the_report_counts_decisions(run: Path, tmp_path: Path) -> None:
    report = tmp_path / "report.json"
    result = runner.invoke(app, ["rewrite", "--diff", "--report", str(report), str(run)])
    assert result.exit_code == 1
    data = json.loads(report.read_text())
    assert data["summary"]["review_items"] == 3
    assert sum(len(f["review"]) for f in data["files"]) == 3
    assert "Review (3)" in result.stderr


def test_a_decision_of_one_file_is_not_grouped(run: Path) -> None:
    """Checked alone, each script asks its own questions: nothing is grouped away."""
    result = runner.invoke(app, ["check", "--output-format", "json", str(run / "scripts" / "train.py")])
    assert _review(json.loads(result.stdout)) == [("train.py", 5, "GM107"), ("train.py", 8, "GM803")]


# -- a question the modules of a run share ---------------------------------------------

POLICIES = Path(__file__).resolve().parent.parent / "fixtures" / "project_policy_bases"


def test_a_base_class_attribute_is_one_question_for_its_subclasses_modules(tmp_path: Path) -> None:
    """``fixtures/project_policy_bases``: where ``Policy``'s ``self.env`` comes from is asked once
    (in the base's module), however many modules of subclasses step it; a subclass that binds
    ``self.env`` itself asks its own question."""
    run = tmp_path / "run"
    shutil.copytree(POLICIES, run)
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code == 1
    findings = json.loads(result.stdout)
    assert _review(findings) == [("base.py", 12, "GM201"), ("reinforce.py", 26, "GM201")]
    first = next(f for f in findings if f["tier"] == "review" and f["path"].endswith("base.py"))
    assert first["message"].endswith(
        f"(the same decision at 3 other places: {run / 'policies' / 'actor.py'}:8, {run / 'policies' / 'dqn.py'}:8, "
        f"{run / 'policies' / 'reinforce.py'}:13)"
    )  # asked in the base's module, though actor.py comes first by path
    pointed = [f for f in findings if f["message"].endswith(f"(decided once, at {run / 'policies' / 'base.py'}:12)")]
    assert sorted((Path(f["path"]).name, f["line"], f["tier"]) for f in pointed) == [
        ("actor.py", 8, "note"),
        ("dqn.py", 8, "note"),
        ("reinforce.py", 13, "note"),
    ]
    assert all("question" not in f for f in findings)  # the key is internal


def test_a_subclass_module_checked_alone_asks_its_own_question(tmp_path: Path) -> None:
    run = tmp_path / "run"
    shutil.copytree(POLICIES, run)
    result = runner.invoke(app, ["check", "--output-format", "json", str(run / "policies" / "dqn.py")])
    assert _review(json.loads(result.stdout)) == [("dqn.py", 8, "GM201")]


# -- parameters the run feeds the same env ---------------------------------------------

FED = Path(__file__).resolve().parent.parent / "fixtures" / "project_fed_params"


def test_defs_fed_the_same_variable_ask_one_question() -> None:
    """``fixtures/project_fed_params``: ``main.py`` hands one untraceable env to two scorers of
    ``scoring.py``: whether it is a Gym env is asked once, at the first; a scorer fed another
    variable asks its own question."""
    result = runner.invoke(app, ["check", "--output-format", "json", str(FED)])
    findings = json.loads(result.stdout)
    assert _review(findings) == [("scoring.py", 2, "GM201"), ("scoring.py", 14, "GM201")]
    first = next(f for f in findings if f["tier"] == "review" and f["line"] == 2)
    assert first["message"].endswith("(the same question at lines 3, 8, 9)")
    pointed = sorted(f["line"] for f in findings if f["message"].endswith("(asked once, at line 2)"))
    assert pointed == [3, 8, 9]


def test_defs_checked_without_their_callers_ask_each_their_own_question() -> None:
    result = runner.invoke(app, ["check", "--output-format", "json", str(FED / "scoring.py")])
    assert _review(json.loads(result.stdout)) == [("scoring.py", 2, "GM201"), ("scoring.py", 8, "GM201"), ("scoring.py", 14, "GM201")]
