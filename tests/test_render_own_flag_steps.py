"""A bare render() of an env class of the run whose step() draws only on a flag of its own
(issue #19): made with render_mode="human", that env draws in step() no more than before, so
the item must not call the explicit render() redundant. A class whose step() always renders
keeps that advice. The constructor may be in the module of the class or in another one.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures" / "rules" / "GM402"


def _gm402_messages(path: Path) -> list[str]:
    run = subprocess.run(
        [sys.executable, "-m", "gymmigrate", "check", "--output-format", "json", str(path)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    found = json.loads(run.stdout)
    findings = found["findings"] if isinstance(found, dict) else found
    return [f["message"] for f in findings if f["rule"] == "GM402"]


def test_step_drawing_on_its_own_flag_keeps_the_call_without_calling_it_redundant() -> None:
    (message,) = _gm402_messages(FIXTURES / "own_env_drawing_on_own_flag.py")
    assert "redundant" not in message
    assert "this call is still what draws" in message


def test_step_always_drawing_keeps_the_redundant_advice() -> None:
    (message,) = _gm402_messages(FIXTURES / "own_env_always_drawing_in_step_still_redundant.py")
    assert "draws every step inside step()/reset(), so this call is redundant" in message


def test_class_imported_from_another_module_of_the_run(tmp_path: Path) -> None:
    source = (FIXTURES / "own_env_drawing_on_own_flag.py").read_text()
    head, _, tail = source.partition("\n\nboard = Board()")
    (tmp_path / "pkg").mkdir()
    (tmp_path / "pkg" / "__init__.py").write_text("")
    (tmp_path / "pkg" / "board.py").write_text(head + "\n")
    (tmp_path / "play.py").write_text("import gym\nfrom pkg.board import Board\n\nboard = Board()" + tail)
    (message,) = _gm402_messages(tmp_path)
    assert "redundant" not in message
    assert "this call is still what draws" in message
