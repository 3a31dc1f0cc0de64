"""Odd and hostile inputs: each gets a clear outcome, never a traceback or a lost file.

Binary data named ``.py``, huge files, very long lines, mixed line endings.
"""

from __future__ import annotations

import time
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from gymmigrate.engine import Status, process_file, transform_source
from gymmigrate.rules.base import RewriteOptions
from gymmigrate.safety import MAX_SOURCE_BYTES

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
