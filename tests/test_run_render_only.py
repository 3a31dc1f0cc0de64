"""Env classes of the run whose drawing is their render() alone, made with ``gym.make``
(``fixtures/project_render_only``).

``Tiles`` draws only in render(): made with ``render_mode="human"`` it still draws only
where render() is called, so a render after the episode loop needs no schedule kept and asks
nothing, and no note calls a render of it redundant. ``Ticker`` renders in its step(): the
render after its loop stays a question.
"""

from __future__ import annotations

import json
from pathlib import Path

from tests.fixture_cases import migrated_project


def test_a_render_of_an_env_drawing_only_in_render_is_a_note_that_keeps_the_call(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_render_only")
    assert [(path, line, rule) for path, line, rule in review if path == "play.py"] == [("play.py", 22, "GM402")]
    play = (project / "play.py").read_text()
    assert play.count('gym.make("Tiles-v0", render_mode="human")') == 3
    assert 'gym.make("Ticker-v0")\n' in play
    notes = [
        f["message"]
        for file in json.loads((tmp_path / "report.json").read_text())["files"]
        if file["path"].endswith("play.py")
        for f in file.get("notes", ())
        if f["rule"] in ("GM401", "GM402")
    ]
    assert len(notes) == 3
    assert all("still what draws" in note and "redundant" not in note for note in notes)
