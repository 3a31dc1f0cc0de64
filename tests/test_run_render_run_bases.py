"""``render_mode`` for classes whose bases only another module shows to be env classes (issue #19).

``fixtures/project_render_run_bases/``: ``kit.point.Point`` derives ``kit.core.TaskEnv`` and a
mixin, so its own module cannot classify it; the run gives it ``render_mode``, ``WallPoint``
hands it on through ``**kwargs``, and ``gym.make("WallPoint-v0")`` takes
``render_mode="human"`` (it was asked about: "takes no render_mode"). ``kit.reach.Reach``
derives ``ArmBase`` (which takes ``render_mode`` from bases of its own module) and
``TaskEnv`` (which makes it an env class the rules decide): ``ReachXY()`` takes
``render_mode="human"`` (it was asked about: "not a known env factory").

``Lift`` derives ``ArmBase`` alone, which the run follows through ``kit.arm``'s own classes to
``kit.sim.SimEnv``: ``Lift()`` takes ``render_mode="human"`` too (the bare render() beside it
noted). The near case keeps its old behaviour: ``Plotter``'s own ``render(mode)`` stays.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.fixture_cases import migrated_project


def test_render_mode_reaches_classes_of_run_bases_and_the_near_cases_stay(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_render_run_bases")
    play = (project / "play.py").read_text()
    assert 'env = ReachXY(render_mode="human")' in play
    assert 'env = gym.make("WallPoint-v0", render_mode="human")' in play
    assert '    env = Lift(render_mode="human")\n' in play
    point = (project / "kit" / "point.py").read_text()
    assert "def __init__(self, size=4, render_mode=None, **kwargs):" in point
    assert '    def render(self, mode="human"):\n        return mode\n' in point  # Plotter
    assert review == [("play.py", 29, "GM402")]
    code = "import play\nprint(play.watch_reach(2), play.watch_wall(3), play.watch_lift(), play.plot())\n"
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["2", "3", "0.0", "human"]
