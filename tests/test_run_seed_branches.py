"""A seed() caller whose receiver the join classifies (``fixtures/project_seed_branches``).

``shelf.make_toy`` seeds an env built as one of two classes of other modules of the run, in
two branches: its module alone cannot trace the receiver, the run shows both to be Gym env
classes, so GM203 makes the call ``env.reset(seed=...)``. Counting it as an untraced seed()
caller kept both classes' seed() in the first run and removed them in the second. The near
case, ``drawer.make_thing``, builds a Gym env or a plain class of the project's own: its seed
call stays (asked about), and the Gym env class keeps its seed() for it, on every run.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from tests.fixture_cases import migrated_project


def _sources(project: Path) -> dict[str, bytes]:
    return {path.name: path.read_bytes() for path in sorted(project.glob("*.py"))}


def test_a_seed_call_on_envs_of_the_run_built_in_branches_leaves_no_seed_behind(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_seed_branches")
    shelf = (project / "shelf.py").read_text()
    assert "        env.reset(seed=seed)\n" in shelf and ".seed(" not in shelf.replace("reset(seed=", "")
    for module in ("pebble_env.py", "marble_env.py"):
        text = (project / module).read_text()
        assert "def seed" not in text and "self.seed()" not in text and "seeding" not in text
    # the near case: the call may reach the plain class, stays, and keeps Spinner's seed()
    assert "        env.seed(seed)\n" in (project / "drawer.py").read_text()
    assert "    def seed(self, seed=None):\n" in (project / "spinner_env.py").read_text()
    assert review == [("drawer.py", 9, "GM203"), ("spinner_env.py", 11, "GM503")]

    migrated = _sources(project)
    again = CliRunner().invoke(app, ["rewrite", str(project)])
    assert again.exit_code == 0, again.output
    assert _sources(project) == migrated, "a second run changed the migrated project"

    code = "import shelf, drawer\nprint(shelf.main(), drawer.main())\n"
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["[True,", "True]", "[True,", "True]"]  # every toy seeded alike
