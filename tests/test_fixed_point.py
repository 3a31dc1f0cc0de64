"""The fixed point by iteration: a rewrite whose output another round still changes is
applied again and verified, up to a bound; only an oscillation is refused, naming the
rules that kept changing it. The rules here are test-only families registered for one
test each, so the mechanism is exercised whatever the real rules do.

The verifying rounds decide with the run's facts, which describe the other modules as they
were before the run: a decision that leans on another module still being legacy is not
checked against the migrated run by them. The last test migrates a project whose fixed
point depends on that, runs it again, and runs the result on Gymnasium."""

from __future__ import annotations

import ast
import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app
from gymmigrate.engine import MAX_ROUNDS, transform_source
from gymmigrate.findings import FixKind
from gymmigrate.rules import PIPELINE
from gymmigrate.rules.base import _FAMILIES, FamilySpec, Rule, RuleFamily, set_pipeline
from gymmigrate.source_text import TransformError
from tests.fixture_cases import migrated_project


@contextmanager
def registered(family: type[RuleFamily]) -> Iterator[None]:
    if family not in _FAMILIES:  # registered when its class was made; again for a second use
        _FAMILIES.append(family)
    set_pipeline((*PIPELINE, FamilySpec(family.__name__, __name__)))
    try:
        yield
    finally:
        _FAMILIES.remove(family)
        set_pipeline(PIPELINE)


def _counter_family(name: str, step: dict[int, int]) -> type[RuleFamily]:
    """Rewrites ``level = N`` to ``level = step[N]``; a file saying ``import gym`` so it runs."""

    def decide(self: RuleFamily) -> None:
        for node in ast.walk(self.facts.tree):
            if (
                isinstance(node, ast.Assign)
                and isinstance(node.targets[0], ast.Name)
                and node.targets[0].id == "level"
                and isinstance(node.value, ast.Constant)
                and node.value.value in step
            ):
                new = step[node.value.value]
                self.plan.replace(node.value, lambda cst_node, new=new: cst_node.with_changes(value=str(new)))
                self.report(node, "GM998", f"level {node.value.value} -> {new}")

    return type(name, (RuleFamily,), {"RULES": (Rule("GM998", "test", FixKind.AUTO, "test"),), "decide": decide})


def test_a_rewrite_that_needs_a_second_round_settles() -> None:
    family = _counter_family("TwoRounds", {1: 2, 2: 3})
    with registered(family):
        result = transform_source(b"import gymnasium as gym\nlevel = 1\n")
    assert result.rewritten == b"import gymnasium as gym\nlevel = 3\n"
    assert [f.message for f in result.findings if f.rule == "GM998"] == ["level 1 -> 2", "level 2 -> 3"]
    assert all(f.line == 2 and f.line_after == 2 for f in result.findings if f.rule == "GM998")
    with registered(family):
        assert transform_source(result.rewritten).rewritten == result.rewritten  # a fixed point


def test_an_oscillation_is_refused_naming_the_rule() -> None:
    family = _counter_family("SeeSaw", {1: 2, 2: 1})
    with registered(family), pytest.raises(TransformError, match=r"oscillates \(SeeSaw"):
        transform_source(b"import gymnasium as gym\nlevel = 1\n")


def test_a_rewrite_that_never_settles_is_refused_after_the_bound() -> None:
    family = _counter_family("Climb", {n: n + 1 for n in range(1, 20)})
    with registered(family), pytest.raises(TransformError, match=rf"does not settle after {MAX_ROUNDS} rounds \(Climb"):
        transform_source(b"import gymnasium as gym\nlevel = 1\n")


# RecordVideo imports moviepy, an optional dependency this machine does not have: a stand-in
# writes each video's frame count where the video would go.
_RECORD_ON_GYMNASIUM = """
import os, runpy, sys, types

class ImageSequenceClip:
    def __init__(self, frames, fps):
        self.frames = frames

    def write_videofile(self, path, logger=None):
        with open(path, "w") as out:
            out.write(str(len(self.frames)))

for name in ("moviepy", "moviepy.video", "moviepy.video.io", "moviepy.video.io.ImageSequenceClip"):
    sys.modules[name] = types.ModuleType(name)
sys.modules["moviepy.video.io.ImageSequenceClip"].ImageSequenceClip = ImageSequenceClip
sys.path.insert(0, os.getcwd())
runpy.run_path("drive.py", run_name="__main__")
print(sorted((name, open(os.path.join("videos", name)).read()) for name in os.listdir("videos")))
"""


def test_a_recorder_over_a_bare_render_settles_in_one_run_across_modules(tmp_path: Path) -> None:
    # ``fixtures/project_recorder_over_bare_render``: the Monitor that becomes RecordVideo gives
    # the make "rgb_array" in the first run, though a bare render() asks "human" of the same env
    # (it is asked about); the verifying rounds, reading the package as it was, could not see
    # that a second run, reading it migrated, would add the mode.
    project, review = migrated_project(tmp_path, "project_recorder_over_bare_render")
    assert review == [("drive.py", 6, "GM402")]
    drive = (project / "drive.py").read_text()
    assert 'env = gym.make("Track-v0", render_mode="rgb_array")' in drive
    assert 'gym.wrappers.RecordVideo(gym.wrappers.RecordEpisodeStatistics(env), video_folder="videos")' in drive
    again = CliRunner().invoke(app, ["rewrite", str(project)])
    assert again.exit_code == 0, again.output
    assert "rewrote 0 of" in again.output, again.output
    ran = subprocess.run([sys.executable, "-W", "ignore", "-c", _RECORD_ON_GYMNASIUM], cwd=project, capture_output=True, text=True, timeout=120)
    assert ran.returncode == 0, ran.stderr
    # two episodes of three steps, each recorded from its reset: four frames a video
    assert ran.stdout.strip().splitlines()[-1] == "[('rl-video-episode-0.mp4', '4'), ('rl-video-episode-1.mp4', '4')]"
