"""Odd and hostile inputs: each gets a clear outcome, never a traceback or a lost file.

Binary data named ``.py``, huge files, very long lines, mixed line endings, symbolic
links (loops, links out of the tree, links named on the command line), unreadable
folders, unusual file names, and the same file reached twice.
"""

from __future__ import annotations

import os
import stat
import subprocess
import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app
from gymmigrate.engine import transform_source
from gymmigrate.files import discover
from gymmigrate.options import RewriteOptions
from gymmigrate.process import Status, process_file
from gymmigrate.safety import MAX_SOURCE_BYTES
from gymmigrate.writes import is_temporary_name

from .cli_process import cli_environment, command

OPTIONS = RewriteOptions()
LEGACY = b"import gym\nobs = gym.make('CartPole-v1').reset()\n"
MIGRATED = b"import gymnasium as gym\nobs, info = gym.make('CartPole-v1').reset()\n"
cli = CliRunner()


def _process(path: Path, *, write: bool = True):
    return process_file(path, OPTIONS, write=write, want_diff=False)


# --- content -------------------------------------------------------------------------


def test_binary_file_named_py_is_a_clean_error(tmp_path: Path) -> None:
    blob = tmp_path / "model_gym_weights.py"
    content = b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR import gym \x00\xff\xfe" + bytes(range(256))
    blob.write_bytes(content)
    result = _process(blob)
    assert result.status is Status.ERROR
    assert result.error == "binary file (NUL bytes), not Python source; left unchanged"
    assert blob.read_bytes() == content


def test_utf16_source_is_named_as_such(tmp_path: Path) -> None:
    script = tmp_path / "utf16.py"
    script.write_bytes("import gym\n".encode("utf-16"))
    result = _process(script)
    assert result.status is Status.ERROR and "UTF-16" in (result.error or "")


def test_a_bad_file_does_not_stop_the_others(tmp_path: Path) -> None:
    (tmp_path / "blob.py").write_bytes(b"gym\x00\x01\x02")
    (tmp_path / "train.py").write_bytes(LEGACY)
    result = cli.invoke(app, ["rewrite", str(tmp_path)])
    assert result.exit_code == 2
    assert "blob.py: binary file (NUL bytes)" in result.stderr
    assert (tmp_path / "train.py").read_bytes() == MIGRATED


def test_a_10_mb_file_is_refused_quickly_and_unread(tmp_path: Path) -> None:
    huge = tmp_path / "generated_gym_table.py"
    with huge.open("wb") as handle:
        handle.write(b"import gym\n")
        handle.write(b"x = 1\n" * (10 * 1024 * 1024 // 6))
    (tmp_path / "train.py").write_bytes(LEGACY)
    started = time.monotonic()
    result = cli.invoke(app, ["check", str(tmp_path)])
    elapsed = time.monotonic() - started
    assert result.exit_code == 2
    assert f"{huge}: the file is too large (10.0 MB; the limit for one module is 1 MB); left unchanged" in result.stderr
    assert f"{tmp_path / 'train.py'}:1:1: GM101" in result.stdout, "the other file is still checked"
    assert elapsed < 20, f"refusing a large file must not parse it ({elapsed:.1f}s)"


def test_a_large_file_without_gym_code_is_skipped_not_refused(tmp_path: Path) -> None:
    data = tmp_path / "table.py"
    data.write_bytes(b"x = 1\n" * (MAX_SOURCE_BYTES // 6 + 10))
    assert _process(data).status is Status.SKIPPED


def test_very_long_lines_survive(tmp_path: Path) -> None:
    long_string = b"BLOB = '" + b"ab" * 150_000 + b"'\n"
    long_comment = b"# " + b"gym " * 50_000 + b"\n"
    script = tmp_path / "long.py"
    script.write_bytes(LEGACY + long_string + long_comment)
    result = _process(script)
    assert result.status is Status.CHANGED
    assert script.read_bytes() == MIGRATED + long_string + long_comment


def test_mixed_line_endings_are_kept_line_by_line() -> None:
    source = b"import gym\r\nenv = gym.make('CartPole-v1')\nobs = env.reset()\r\n# end\n"
    expected = b"import gymnasium as gym\r\nenv = gym.make('CartPole-v1')\nobs, info = env.reset()\r\n# end\n"
    assert transform_source(source).rewritten == expected


# --- symbolic links ------------------------------------------------------------------


@pytest.fixture
def linked_tree(tmp_path: Path) -> tuple[Path, Path]:
    """A project whose folder holds links: to a folder and a file outside, a loop, a
    dangling link. Returns (project, outside)."""
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "vendored.py").write_bytes(LEGACY)
    project = tmp_path / "project"
    (project / "pkg").mkdir(parents=True)
    (project / "pkg" / "train.py").write_bytes(LEGACY)
    (project / "linked_folder").symlink_to(outside, target_is_directory=True)
    (project / "linked_file.py").symlink_to(outside / "vendored.py")
    (project / "pkg" / "loop").symlink_to(project, target_is_directory=True)
    (project / "dangling.py").symlink_to(project / "missing.py")
    return project, outside


def test_links_inside_a_walked_folder_are_not_followed(linked_tree: tuple[Path, Path]) -> None:
    project, outside = linked_tree
    assert discover([str(project)]).files == [project / "pkg" / "train.py"]
    result = cli.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    assert (project / "pkg" / "train.py").read_bytes() == MIGRATED
    assert (outside / "vendored.py").read_bytes() == LEGACY, "nothing outside the tree is touched"
    assert (project / "linked_file.py").is_symlink() and (project / "dangling.py").is_symlink()


def test_links_are_not_followed_in_a_git_work_tree_either(linked_tree: tuple[Path, Path]) -> None:
    project, _ = linked_tree
    subprocess.run(["git", "init", "-q", str(project)], check=True)
    assert discover([str(project)]).files == [project / "pkg" / "train.py"]


def test_a_link_named_explicitly_is_written_through(linked_tree: tuple[Path, Path]) -> None:
    project, outside = linked_tree
    link = project / "linked_file.py"
    result = cli.invoke(app, ["rewrite", str(link)])
    assert result.exit_code == 0, result.output
    assert link.is_symlink() and link.resolve() == outside / "vendored.py", "the link stays a link"
    assert (outside / "vendored.py").read_bytes() == MIGRATED
    assert not [p for p in (*project.iterdir(), *outside.iterdir()) if is_temporary_name(p.name)]


def test_a_link_and_its_target_named_together_are_processed_once(linked_tree: tuple[Path, Path]) -> None:
    project, outside = linked_tree
    result = cli.invoke(app, ["rewrite", "--diff", str(project / "linked_file.py"), str(outside / "vendored.py")])
    assert result.exit_code == 1
    assert result.stdout.count("+import gymnasium as gym") == 1


def test_broken_links_and_loops_named_explicitly_are_errors(linked_tree: tuple[Path, Path], tmp_path: Path) -> None:
    project, _ = linked_tree
    first, second = tmp_path / "a.py", tmp_path / "b.py"
    first.symlink_to(second)
    second.symlink_to(first)
    result = cli.invoke(app, ["check", str(project / "dangling.py"), str(first)])
    assert result.exit_code == 2
    assert "Traceback" not in result.output
    for path in (project / "dangling.py", first):
        assert f"{path}: a broken symbolic link (its target is missing, or the links form a loop)" in result.stderr


# --- unreadable folders --------------------------------------------------------------


def test_a_folder_that_cannot_be_listed_is_reported(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # What os.walk meets in a folder without read permission, as root too (root could
    # read it; the real permission case is the next test).
    locked = tmp_path / "locked"
    locked.mkdir()
    (tmp_path / "train.py").write_bytes(LEGACY)
    real_scandir = os.scandir

    def scandir(path: object = ".") -> object:
        if Path(os.fsdecode(path)) == locked:  # type: ignore[arg-type]
            raise PermissionError(13, "Permission denied", str(locked))
        return real_scandir(path)  # type: ignore[arg-type]

    monkeypatch.setattr(os, "scandir", scandir)
    discovery = discover([str(tmp_path)])
    assert discovery.files == [tmp_path / "train.py"]
    assert discovery.errors == [(str(locked), "cannot read the folder: Permission denied")]


@pytest.mark.skipif(os.geteuid() == 0, reason="root can read folders without permission")
@pytest.mark.parametrize("in_git", [False, True], ids=["plain folder", "git work tree"])
def test_unreadable_folder_is_an_error_and_the_rest_runs(tmp_path: Path, in_git: bool) -> None:
    if in_git:
        subprocess.run(["git", "init", "-q", str(tmp_path)], check=True)
    locked = tmp_path / "locked"
    locked.mkdir()
    (locked / "hidden.py").write_bytes(LEGACY)
    (tmp_path / "train.py").write_bytes(LEGACY)
    locked.chmod(0)
    try:
        result = cli.invoke(app, ["rewrite", str(tmp_path)])
    finally:
        locked.chmod(stat.S_IRWXU)
    assert result.exit_code == 2
    assert f"{locked}: cannot read the folder: Permission denied" in result.stderr
    assert (tmp_path / "train.py").read_bytes() == MIGRATED


# --- names and repeats ----------------------------------------------------------------


@pytest.mark.parametrize("in_git", [False, True], ids=["plain folder", "git work tree"])
def test_names_with_spaces_and_non_ascii_characters(tmp_path: Path, in_git: bool) -> None:
    if in_git:
        subprocess.run(["git", "init", "-q", str(tmp_path)], check=True)
    folder = tmp_path / "données d'entraînement"
    folder.mkdir()
    scripts = [folder / "my train script.py", folder / "агент 🤖.py", tmp_path / "日本語.py"]
    for script in scripts:
        script.write_bytes(LEGACY)
    checked = cli.invoke(app, ["check", str(tmp_path)])
    assert checked.exit_code == 1
    for script in scripts:
        assert f"{script}:1:1: GM101 [auto]" in checked.stdout
    rewritten = cli.invoke(app, ["rewrite", str(tmp_path)])
    assert rewritten.exit_code == 0, rewritten.output
    assert all(script.read_bytes() == MIGRATED for script in scripts)


@pytest.mark.skipif(os.uname().sysname == "Darwin", reason="macOS file systems refuse names that are not UTF-8")
def test_a_name_that_is_not_utf8_prints_its_own_bytes(tmp_path: Path) -> None:
    script = Path(os.fsdecode(os.path.join(os.fsencode(tmp_path), b"caf\xe9.py")))
    script.write_bytes(LEGACY)
    # A strict UTF-8 stdout, as under an en_US.UTF-8 locale.
    completed = subprocess.run(
        command("rewrite", "--diff", str(tmp_path)),
        env=cli_environment(PYTHONIOENCODING="utf-8:strict"),
        capture_output=True,
        timeout=120,
        check=False,
    )
    assert completed.returncode == 1, completed.stderr
    assert b"Traceback" not in completed.stderr
    assert b"+++ " + os.fsencode(script) + b"\n" in completed.stdout


def test_a_file_reached_several_ways_is_processed_once(tmp_path: Path) -> None:
    script = tmp_path / "train.py"
    script.write_bytes(LEGACY)
    other = tmp_path / "sub" / "other.py"
    other.parent.mkdir()
    other.write_bytes(LEGACY)
    arguments = [str(tmp_path), str(script), str(script), str(tmp_path / "sub" / ".." / "train.py"), str(other.parent)]
    result = cli.invoke(app, ["rewrite", "--diff", *arguments])
    assert result.exit_code == 1
    assert result.stdout.count(f"+++ {script}\n") == 1 and result.stdout.count(f"+++ {other}\n") == 1
    assert "would rewrite 2 of 2 files" in result.stderr

