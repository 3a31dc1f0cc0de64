"""A forwarding class no code of the run builds asks nothing (``fixtures/project_unbuilt_duck_wrapper``).

``sim/wrappers.py`` holds three plain classes shaped as Gym wrappers (they hold an env, offer
its spaces and keep its legacy step and reset). ``Keyed`` is built nowhere in the run: no env
reaches it, so it stays as it is with a note. ``Scaled`` is built around an env the run
cannot trace and ``Tagged`` is handed on as a value: both keep their review item. Checked
alone, the module cannot know who builds ``Keyed``: its item stays.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_unbuilt_duck_wrapper"
runner = CliRunner()


def _gm602(*paths: Path) -> dict[int, tuple[str, str]]:
    result = runner.invoke(app, ["check", "--output-format", "json", *map(str, paths)])
    assert result.exit_code in (0, 1), result.output
    return {f["line"]: (f["tier"], f["message"]) for f in json.loads(result.stdout) if f["rule"] == "GM602"}


def _copy(tmp_path: Path) -> Path:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    return run


def test_a_class_built_nowhere_in_the_run_is_a_note(tmp_path: Path) -> None:
    found = _gm602(_copy(tmp_path))
    assert found[8][0] == "note"
    assert "no code of this run builds it" in found[8][1]


def test_classes_built_or_handed_on_keep_their_item(tmp_path: Path) -> None:
    found = _gm602(_copy(tmp_path))
    assert {line: tier for line, (tier, _) in found.items() if line != 8} == {29: "review", 50: "review"}


def test_a_module_checked_alone_keeps_the_item(tmp_path: Path) -> None:
    found = _gm602(_copy(tmp_path) / "sim" / "wrappers.py")
    assert found[8][0] == "review"
