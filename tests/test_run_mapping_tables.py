"""Tables of env classes built by a mapping constructor (issue #19).

``fixtures/project_mapping_tables/``: ``registry.py`` binds ``TASK_ENVS`` to
``OrderedDict((("reach", Reach), ("push", Push)))`` and ``GAMES`` to ``dict(board=Board)``:
as closed as a dict display, so a lookup called in ``play.py`` makes what every class of the
table makes. ``run_task``'s reset and step are rewritten (Gym env classes of the run);
``run_game``'s are left with no question (the project's own game). The near case stays
asked: ``LOADED`` copies what a call returns, whose entries the run does not see.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.fixture_cases import migrated_project


def test_mapping_constructor_tables_settle_what_a_lookup_makes(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_mapping_tables")
    play = (project / "play.py").read_text()
    assert "    obs, info = env.reset()\n    total = 0.0" in play
    assert "obs, reward, terminated, truncated, info = env.step(len(obs) % 2)" in play
    assert "    env = GAMES[name]()\n    obs = env.reset()\n" in play
    assert "    env = LOADED[name]()\n    obs = env.reset()\n" in play
    assert review == [("play.py", 24, "GM201")]
    code = "import play\nprint(play.run_task('reach'), play.run_task('push'), play.run_game('board'))\n"
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["1.0", "1.0", "0.0"]
