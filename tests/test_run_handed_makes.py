"""A frame mode asked in one module of an env another module makes (issue #19).

``fixtures/project_handed_makes/``: ``main.record`` makes an env, hands it to ``Trainer``
(which never draws it) and to ``Player``, whose ``frames`` calls
``self.env.render(mode="rgb_array")``; ``main.still`` hands a make straight to
``snapshot``, which calls ``env.render("rgb_array")``. Gymnasium fixes the mode at the make,
so both makes take ``render_mode="rgb_array"`` and the renders lose their mode: no item.

``Trainer`` has a static method, whose first parameter is no instance. The near cases keep
their items: ``Clipper`` is also built on an env the run cannot trace, ``show`` renders in
"human" (a human-mode env draws inside every step), ``Framer`` is built on an env that
``main.peek`` also reaches through the instance's attribute, and ``Snapper`` hands its
instance (and so the env it holds) to a list.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from tests.fixture_cases import migrated_project

runner = CliRunner()


def _migrated(tmp_path: Path) -> tuple[Path, list[tuple[str, int, str]]]:
    return migrated_project(tmp_path, "project_handed_makes")


def test_the_mode_moves_to_the_makes_of_another_module(tmp_path: Path) -> None:
    project, review = _migrated(tmp_path)
    main = (project / "main.py").read_text()
    assert 'env = gym.make("CartPole-v1", render_mode="rgb_array")' in main
    assert 'snapshot(gym.make("MountainCar-v0", render_mode="rgb_array"))' in main
    assert main.count("render_mode=") == 2  # Clipper's, show's, Framer's and Snapper's makes get none
    player = (project / "player.py").read_text()
    assert "shots.append(self.env.render())" in player and 'return env.render()\n' in player
    assert review == [
        ("main.py", 32, "GM401"),  # peek's own render of Framer's env
        ("player.py", 30, "GM401"),
        ("player.py", 35, "GM401"),
        ("player.py", 44, "GM401"),
        ("player.py", 57, "GM401"),
    ]
    again = runner.invoke(app, ["rewrite", "--diff", str(project)])
    assert "would rewrite 0 of" in again.output, again.output


def test_the_migrated_renders_return_frames_on_gymnasium(tmp_path: Path) -> None:
    project, _ = _migrated(tmp_path)
    code = "import main\nshots = main.record(3)\nprint(len(shots), shots[0].shape, main.still().shape)\n"
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split("\n")[0] == "3 (400, 600, 3) (400, 600, 3)"
