"""Review items and notes, end to end through the CLI: each finding once, in its tier."""

from __future__ import annotations

import json
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from gymmigrate.findings import Finding, FixKind, Tier

runner = CliRunner()

# One move (to gymnasium_robotics) asked at its first import, a render_mode=None added
# to __init__ (a note) and a step whose truncated=False is exact (a note).
SCRIPT = '''import gym
from gym.envs.robotics.fetch_env import FetchEnv
from gym.envs.robotics import rotations


class Walk(gym.Env):
    def __init__(self):
        self.x = 0

    def render(self, mode="human"):
        return self.x

    def step(self, action):
        self.x += action
        return self.x, 0.0, abs(self.x) > 3, {}
'''


def test_tier_follows_the_kind_unless_the_rule_says_otherwise() -> None:
    assert Finding(1, 0, "GM101", FixKind.AUTO, "m").tier is Tier.NOTE
    assert Finding(1, 0, "GM105", FixKind.FLAG, "m").needs_review
    assert not Finding(1, 0, "GM405", FixKind.ASSIST, "m", tier=Tier.NOTE).needs_review
    assert Finding(1, 0, "GM405", FixKind.ASSIST, "m", tier=Tier.NOTE).to_json()["tier"] == "note"


def test_report_lists_each_finding_once_with_its_tier(tmp_path: Path) -> None:
    script = tmp_path / "walk.py"
    script.write_text(SCRIPT)
    report = tmp_path / "report.json"
    result = runner.invoke(app, ["rewrite", "--diff", "--report", str(report), str(script)])
    data = json.loads(report.read_text())
    (entry,) = data["files"]
    assert "changes" not in entry, "a finding is listed once, under its tier"
    review = [(r["line"], r["rule"]) for r in entry["review"]]
    assert review == [(2, "GM105")], "one move, one review item"
    assert all(r["tier"] == "review" for r in entry["review"])
    assert all(r["tier"] == "note" for r in entry["notes"])
    notes = {(r["line"], r["rule"]) for r in entry["notes"]}
    assert {(3, "GM105"), (7, "GM405"), (10, "GM405"), (15, "GM504")} <= notes
    assert data["summary"]["review_items"] == 1
    assert data["summary"]["notes"] == len(entry["notes"])
    # The text summary lists the one review item and counts the notes.
    assert "Review (1)" in result.stderr
    assert f"{len(entry['notes'])} notes on rewrites already applied" in result.stderr


def test_check_still_lists_every_place(tmp_path: Path) -> None:
    script = tmp_path / "walk.py"
    script.write_text(SCRIPT)
    result = runner.invoke(app, ["check", str(script)])
    assert f"{script}:3:1: GM105" in result.stdout, "the note about the second robotics import is listed"
