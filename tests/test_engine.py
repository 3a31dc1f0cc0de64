"""The file engine: byte fidelity, verification, safe writes, position mapping, discovery."""

from __future__ import annotations

import os
import stat
import subprocess
from pathlib import Path

import pytest

from gymmigrate.engine import LineMap, transform_source
from gymmigrate.files import discover
from gymmigrate.options import RewriteOptions
from gymmigrate.process import Status, process_file
from gymmigrate.source_text import TransformError

OPTIONS = RewriteOptions()


def test_crlf_survives_a_rewrite() -> None:
    source = b"import gym\r\n# keep me\r\nx = gym.spaces.Discrete(2)\r\n"
    result = transform_source(source)
    assert result.rewritten == b"import gymnasium as gym\r\n# keep me\r\nx = gym.spaces.Discrete(2)\r\n"


def test_latin1_cookie_and_bytes_survive() -> None:
    source = b"# -*- coding: latin-1 -*-\nimport gym\nname = '\xe9t\xe9'\n"
    result = transform_source(source)
    assert result.rewritten == b"# -*- coding: latin-1 -*-\nimport gymnasium as gym\nname = '\xe9t\xe9'\n"


def test_bom_survives() -> None:
    source = b"\xef\xbb\xbfimport gym\n"
    assert transform_source(source).rewritten == b"\xef\xbb\xbfimport gymnasium as gym\n"


def test_no_trailing_newline_and_odd_formatting_survive() -> None:
    source = b"import   gym  # odd spacing\nenv=gym.make( 'CartPole-v1' )"
    assert transform_source(source).rewritten == b"import   gymnasium as gym  # odd spacing\nenv=gym.make( 'CartPole-v1' )"


def test_untouched_source_is_identical() -> None:
    source = b"import numpy as np\r\n\r\nclass Environment:  # not gym\r\n    pass\r\n"
    result = transform_source(source)
    assert result.rewritten == source
    assert not result.changed


def test_syntax_error_is_reported() -> None:
    with pytest.raises(TransformError, match=r"syntax error at line 2"):
        transform_source(b"import gym\nenv = = gym.make('x')\n")


def test_python2_is_named() -> None:
    with pytest.raises(TransformError, match="Python 2"):
        transform_source(b"import gym\nprint 'episode', 3\n")


def test_undecodable_bytes_are_reported() -> None:
    with pytest.raises(TransformError, match="cannot decode"):
        transform_source(b"import gym\nname = '\xff\xfe'\n")


def test_positions_map_back_to_the_original_after_lines_are_inserted() -> None:
    before = "a\nb\nc\nd\n"
    after = "a\nb\ninserted\nc\nd\n"
    line_map = LineMap(before, after)
    assert [line_map.forward(n) for n in (1, 2, 3, 4)] == [1, 2, 4, 5]
    assert [line_map.backward(n) for n in (1, 2, 4, 5)] == [1, 2, 3, 4]
    assert line_map.backward(3) in (2, 3)


def test_a_line_of_a_replaced_run_maps_to_the_line_that_reads_like_it() -> None:
    """A step unpacked anew gains `done = terminated or truncated` below it, and the reset
    after it changes too: difflib sees one replaced run of two lines becoming three. The
    reset is the third line of that run, not the second."""
    before = "while not done:\n    obs, reward, done, info = env.step(a)\nobs = env.reset()\nend()\n"
    after = (
        "while not done:\n    obs, reward, terminated, truncated, info = env.step(a)\n"
        "    done = terminated or truncated\nobs, info = env.reset()\nend()\n"
    )
    line_map = LineMap(before, after)
    assert [line_map.forward(n) for n in (1, 2, 3, 4)] == [1, 2, 4, 5]
    assert [line_map.backward(n) for n in (1, 2, 4, 5)] == [1, 2, 3, 4]
    assert line_map.backward(3) in (2, 3), "an added line maps next to where it was added"


def test_process_file_writes_atomically_and_keeps_the_mode(tmp_path: Path) -> None:
    script = tmp_path / "train.py"
    script.write_bytes(b"#!/usr/bin/env python\nimport gym\n")
    script.chmod(0o751)
    result = process_file(script, OPTIONS, write=True, want_diff=False)
    assert result.status is Status.CHANGED and result.written
    assert script.read_bytes() == b"#!/usr/bin/env python\nimport gymnasium as gym\n"
    assert stat.S_IMODE(script.stat().st_mode) == 0o751
    assert [p.name for p in tmp_path.iterdir()] == ["train.py"], "no temporary file is left behind"


def test_process_file_leaves_a_bad_file_alone(tmp_path: Path) -> None:
    bad = tmp_path / "bad.py"
    content = b"import gym\ndef broken(:\n"
    bad.write_bytes(content)
    result = process_file(bad, OPTIONS, write=True, want_diff=False)
    assert result.status is Status.ERROR and "syntax error" in (result.error or "")
    assert bad.read_bytes() == content


def test_files_without_gym_code_are_skipped_before_parsing(tmp_path: Path) -> None:
    plain = tmp_path / "plain.py"
    plain.write_bytes(b"def broken(:\n")  # would be a syntax error if parsed
    assert process_file(plain, OPTIONS, write=True, want_diff=False).status is Status.SKIPPED


def test_discovery_skips_tool_folders_and_virtualenvs(tmp_path: Path) -> None:
    for relative in [
        "pkg/train.py",
        "pkg/notes.txt",
        ".git/hooks/x.py",
        "build/lib/x.py",
        "site-packages/x.py",
        "myenv/lib/x.py",
        "pkg/__pycache__/x.py",
        "envs/custom_env.py",  # a folder named envs is user code
    ]:
        path = tmp_path / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("import gym\n")
    (tmp_path / "myenv" / "pyvenv.cfg").write_text("home = /usr\n")
    found = sorted(p.relative_to(tmp_path).as_posix() for p in discover([str(tmp_path)]).files)
    assert found == ["envs/custom_env.py", "pkg/train.py"]


def test_discovery_honours_gitignore(tmp_path: Path) -> None:
    subprocess.run(["git", "init", "-q", str(tmp_path)], check=True)
    (tmp_path / ".gitignore").write_text("generated/\nscratch_*.py\n")
    for relative in ["src/train.py", "generated/out.py", "scratch_1.py"]:
        path = tmp_path / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("import gym\n")
    found = sorted(p.relative_to(tmp_path).as_posix() for p in discover([str(tmp_path)]).files)
    assert found == ["src/train.py"]


def test_discovery_takes_explicit_files_and_reports_missing(tmp_path: Path) -> None:
    script = tmp_path / "script.py"
    script.write_text("import gym\n")
    result = discover([str(script), str(script), str(tmp_path / "missing.py")])
    assert result.files == [script]
    assert result.errors == [(str(tmp_path / "missing.py"), "no such file or directory")]


@pytest.mark.skipif(os.geteuid() == 0, reason="root can read files without permission")
def test_unreadable_file_is_an_error(tmp_path: Path) -> None:
    locked = tmp_path / "locked.py"
    locked.write_text("import gym\n")
    locked.chmod(0)
    assert process_file(locked, OPTIONS, write=False, want_diff=False).status is Status.ERROR


def test_pathological_nesting_is_an_error_not_a_crash(tmp_path: Path) -> None:
    # LibCST's native parser segfaults on this; CPython's parser rejects it first.
    deep = tmp_path / "deep.py"
    deep.write_text("import gym\nx = " + "(" * 5000 + "1" + ")" * 5000 + "\n")
    result = process_file(deep, OPTIONS, write=True, want_diff=False)
    assert result.status is Status.ERROR
    assert "too many nested parentheses" in (result.error or "")


@pytest.mark.parametrize(
    "source",
    [
        pytest.param(b"import gym\renv = gym.make('CartPole-v1')\robs = env.reset()\r", id="cr-only line endings"),
        pytest.param(b"import gym\n\x0cenv = gym.make('CartPole-v1')\n", id="form feed"),
    ],
)
def test_files_libcst_cannot_reproduce_are_left_alone(source: bytes) -> None:
    with pytest.raises(TransformError, match="cannot be reproduced byte for byte"):
        transform_source(source)


def test_null_bytes_are_reported() -> None:
    with pytest.raises(TransformError, match="null bytes"):
        transform_source(b"import gym\nx = '\x00'\n")


def test_tabs_survive() -> None:
    source = b"import gym\nif True:\n\tenv = gym.make('CartPole-v1')\n\tobs = env.reset()\n"
    result = transform_source(source)
    assert result.rewritten == b"import gymnasium as gym\nif True:\n\tenv = gym.make('CartPole-v1')\n\tobs, info = env.reset()\n"
