"""Writing a rewrite back: never over an edit made meanwhile, and keeping the file's owner.

A file edited or deleted while gymmigrate works on it is never overwritten or recreated.
The edit is made between the read and the write by wrapping ``transform_source``: the
moment a person would save in an editor while a long run is busy with the file.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate import process
from gymmigrate.cli import app
from gymmigrate.options import RewriteOptions
from gymmigrate.process import Status, process_file
from gymmigrate.writes import is_temporary_name

OPTIONS = RewriteOptions()
LEGACY = b'import gym\nenv = gym.make("CartPole-v1")\nobs = env.reset()\n'
MIGRATED = b'import gymnasium as gym\nenv = gym.make("CartPole-v1")\nobs, info = env.reset()\n'
EDITED = b'import gym\nenv = gym.make("CartPole-v1")\nobs = env.reset()\nprint("saved in the editor")\n'


def _edit_during_transform(monkeypatch: pytest.MonkeyPatch, edit) -> None:
    """The user saves (or deletes) the file while gymmigrate is computing its rewrite."""
    real = process.transform_source

    def transform_then_edit(source: bytes, path: str = "<string>", options: RewriteOptions | None = None):
        result = real(source, path, options)
        edit()
        return result

    monkeypatch.setattr(process, "transform_source", transform_then_edit)


def test_a_file_edited_during_the_run_is_not_overwritten(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    script = tmp_path / "train.py"
    script.write_bytes(LEGACY)
    _edit_during_transform(monkeypatch, lambda: script.write_bytes(EDITED))
    result = process_file(script, OPTIONS, write=True, want_diff=False)
    assert result.status is Status.ERROR and not result.written
    assert result.error == "not rewritten: it changed while gymmigrate ran; left as it is now"
    assert script.read_bytes() == EDITED
    assert not [path for path in tmp_path.iterdir() if is_temporary_name(path.name)]


def test_a_file_deleted_during_the_run_is_not_recreated(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    script = tmp_path / "train.py"
    script.write_bytes(LEGACY)
    _edit_during_transform(monkeypatch, script.unlink)
    result = process_file(script, OPTIONS, write=True, want_diff=False)
    assert result.status is Status.ERROR
    assert "deleted while gymmigrate ran" in (result.error or "")
    assert list(tmp_path.iterdir()) == []


def test_an_edit_during_the_run_is_reported_with_exit_two(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    script = tmp_path / "train.py"
    other = tmp_path / "other.py"
    script.write_bytes(LEGACY)
    other.write_bytes(LEGACY)
    edits = iter([lambda: None, lambda: script.write_bytes(EDITED)])  # other.py first, then train.py
    _edit_during_transform(monkeypatch, lambda: next(edits)())
    result = CliRunner().invoke(app, ["rewrite", str(other), str(script)])
    assert result.exit_code == 2
    assert f"{script}: not rewritten: it changed while gymmigrate ran" in result.stderr.replace("\n", " ")
    assert script.read_bytes() == EDITED and other.read_bytes() == MIGRATED


@pytest.mark.skipif(os.geteuid() != 0, reason="only root can give a file to another user")
def test_ownership_is_kept_when_root_rewrites_a_users_file(tmp_path: Path) -> None:
    script = tmp_path / "train.py"
    script.write_bytes(LEGACY)
    os.chown(script, 65534, 65534)
    assert process_file(script, OPTIONS, write=True, want_diff=False).written
    assert (script.stat().st_uid, script.stat().st_gid) == (65534, 65534)

