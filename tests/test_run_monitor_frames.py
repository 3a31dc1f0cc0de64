"""A legacy Monitor over an env that gives no frames is its statistics alone (issue #19).

``fixtures/project_monitor_frames/``: ``Window-v0`` builds a class whose metadata, inherited
from a base of another module, declares the "human" render mode only. Legacy Monitor
switched its video recorder off for it, so its rewrite is ``RecordEpisodeStatistics(env)``,
the make gets no ``render_mode`` (RecordVideo would need "rgb_array", which the env cannot
give), and the Monitor's own ``_flush`` stays a review item, not a ``get_wrapper_attr`` that
fails. The near case, ``Canvas-v0``, declares "rgb_array" and keeps the RecordVideo rewrite.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.fixture_cases import migrated_project


def test_monitor_over_a_window_only_env_keeps_its_statistics_alone(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_monitor_frames")
    window = (project / "train_window.py").read_text()
    assert 'env = gym.make("Window-v0")\n' in window
    assert "env = gym.wrappers.RecordEpisodeStatistics(env)\n" in window
    assert "env._flush(force=True)\n" in window
    canvas = (project / "train_canvas.py").read_text()
    assert 'env = gym.make("Canvas-v0", render_mode="rgb_array")\n' in canvas
    assert 'env = gym.wrappers.RecordVideo(gym.wrappers.RecordEpisodeStatistics(env), video_folder="/tmp/canvas-runs")\n' in canvas
    # The canvas script steps its RecordVideo and never closes it: the recording episode's
    # video is saved only by close() now (legacy Monitor saved it at exit), which it asks.
    assert review == [("train_canvas.py", 6, "GM611"), ("train_window.py", 9, "GM604")]
    # the migrated script runs up to the Monitor method it is asked about
    code = window.replace("env._flush(force=True)\n", "print(env.get_wrapper_attr('episode_count'))\n")
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["1"]
