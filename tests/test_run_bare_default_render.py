"""A bare render() of a made env whose class keeps render(mode=<default>) (issue #19).

``fixtures/project_bare_default_render/``: ``Flat`` (registered as ``Flat-v0``) inherits,
through a package's star re-exports, a ``render(self, mode="window", zoom=1.0)`` that the
run leaves, so it takes no render_mode. ``env.render()`` on ``gym.make("Flat-v0")`` still
draws in the default mode through Gymnasium's wrappers, which call render() with no
arguments: no item. ``env.render("frame")`` on the same make keeps its item.

The kept ``render(mode, zoom)`` itself is reported once at its def: through make's wrappers
no caller can pass it a mode or an option. ``Post``, kept whole too, has a render taking the
mode alone: no item at its def (as before).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.fixture_cases import migrated_project


def test_bare_render_reaching_a_default_mode_needs_no_item_and_a_kept_render_with_options_is_asked_once(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_bare_default_render")
    play = (project / "play.py").read_text()
    assert '    env = gym.make("Flat-v0")\n    env.reset()\n    env.render()\n' in play
    assert ("play.py", 9, "GM402") not in review
    assert ("play.py", 16, "GM401") in review
    assert ("walkers/base.py", 26, "GM405") in review
    assert not [item for item in review if item[0] == "walkers/post.py" and item[2] == "GM405"]
    code = "import play\nprint(play.watch_flat())\n"
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "[('window', 1.0)]"
