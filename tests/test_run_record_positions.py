"""Tables of creators whose records are tuples, called through a position (issue #19).

``fixtures/project_record_positions/``: ``registry.py`` binds ``SCENES`` to a dict whose every
record holds a Gym env class of the run at position 0, so ``SCENES[name][0](size=2)`` in
``play.py`` makes a Gym env (one record shown in the display, one stored at top level):
``run_scene``'s reset and step are rewritten. ``GAMES`` holds the project's own game there:
``run_game``'s reset is left with no question. The near cases stay asked: ``MIXED`` is given
the game by a top-level store, ``LATE`` entries a def stores from its parameters.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.fixture_cases import migrated_project


def test_a_position_of_every_record_settles_what_a_lookup_makes(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_record_positions")
    play = (project / "play.py").read_text()
    assert "    obs, info = env.reset()\n    obs, reward, terminated, truncated, info = env.step(len(obs) % 2)\n" in play
    assert "    env = GAMES[name][0]()\n    obs = env.reset()\n" in play
    assert "    env = MIXED[name][0]()\n    obs = env.reset()\n" in play
    assert "    env = LATE[name][0]()\n    obs = env.reset()\n" in play
    assert review == [("play.py", 19, "GM201"), ("play.py", 25, "GM201")]
    code = "import play\nprint(play.run_scene('walk'), play.run_scene('hill'), play.run_game('board'))\n"
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["1.0", "1.0", "0.0"]
