"""[tool.gymmigrate] in pyproject.toml: discovery by walking up, precedence, errors."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app
from gymmigrate.config import ConfigError, find_config

runner = CliRunner()
LOOP = b'import gym\n\nenv = gym.make("CartPole-v1")\nobs = env.reset()\nobs, reward, done, info = env.step(0)\n'


def project(tmp_path: Path, table: str) -> Path:
    (tmp_path / "pyproject.toml").write_text(f"[project]\nname = 'x'\n\n[tool.gymmigrate]\n{table}\n")
    package = tmp_path / "pkg" / "deep"
    package.mkdir(parents=True)
    (package / "loop.py").write_bytes(LOOP)
    return package / "loop.py"


def rules_of(stdout: str) -> set[str]:
    return {line.split()[1] for line in stdout.splitlines()}


def test_found_by_walking_up_from_the_path(tmp_path: Path) -> None:
    path = project(tmp_path, 'select = ["GM3"]\nseed = 7\ndocs = true')
    config = find_config(path)
    assert config.path == tmp_path / "pyproject.toml"
    assert (config.select, config.seed, config.docs) == (("GM3",), 7, True)


def test_a_pyproject_without_the_table_is_passed_over(tmp_path: Path) -> None:
    path = project(tmp_path, 'ignore = ["GM1"]')
    (path.parent / "pyproject.toml").write_text("[project]\nname = 'inner'\n")
    assert find_config(path).path == tmp_path / "pyproject.toml"


def test_select_from_config_and_flags_win(tmp_path: Path) -> None:
    path = project(tmp_path, 'select = ["GM3"]')
    assert rules_of(runner.invoke(app, ["check", str(path)]).stdout) == {"GM301"}
    flagged = runner.invoke(app, ["check", "--select", "GM1", str(path)])
    assert rules_of(flagged.stdout) == {"GM101"}


def test_extend_ignore_adds_up_from_file_and_flags(tmp_path: Path) -> None:
    path = project(tmp_path, 'extend-ignore = ["GM1"]')
    result = runner.invoke(app, ["check", "--extend-ignore", "GM3", str(path)])
    assert rules_of(result.stdout) == {"GM201"}


def test_seed_default_from_config(tmp_path: Path) -> None:
    path = project(tmp_path, "seed = 3")
    assert runner.invoke(app, ["rewrite", str(path)]).exit_code == 0
    assert b"env.reset(seed=3)" in path.read_bytes()


def test_exclude_globs_skip_walked_files_but_not_named_ones(tmp_path: Path) -> None:
    path = project(tmp_path, 'exclude = ["pkg/deep/*"]\nextend-exclude = ["other.py"]')
    (tmp_path / "other.py").write_bytes(LOOP)
    (tmp_path / "kept.py").write_bytes(LOOP)
    walked = runner.invoke(app, ["check", str(tmp_path)])
    assert "kept.py" in walked.stdout
    assert "loop.py" not in walked.stdout and "other.py" not in walked.stdout
    named = runner.invoke(app, ["check", str(path)])
    assert "loop.py" in named.stdout


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ('selekt = ["GM3"]', "selekt: unknown key"),
        ('select = "GM3"', "select: must be a list of strings"),
        ("seed = -1", "seed: must be a non-negative integer"),
        ('docs = "yes"', "docs: must be true or false"),
        ('select = ["GM999"]', "select: unknown rule code or prefix 'GM999'"),
        ('extend-ignore = ["XY"]', "extend-ignore: unknown rule code or prefix 'XY'"),
    ],
)
def test_bad_configuration_is_a_usage_error_naming_key_and_file(tmp_path: Path, table: str, message: str) -> None:
    path = project(tmp_path, table)
    result = runner.invoke(app, ["check", str(path)])
    assert result.exit_code == 2
    assert message in result.stderr
    assert str(tmp_path / "pyproject.toml") in result.stderr


def test_invalid_toml_is_reported(tmp_path: Path) -> None:
    (tmp_path / "pyproject.toml").write_text("[tool.gymmigrate\n")
    with pytest.raises(ConfigError, match="not valid TOML"):
        find_config(tmp_path / "sub" / "x.py")


def test_docs_from_config_takes_pages_when_walking(tmp_path: Path) -> None:
    project(tmp_path, "docs = true")
    (tmp_path / "guide.md").write_text("# Guide\n\n```python\nimport gym\n```\n")
    assert "guide.md:4:1: GM101" in runner.invoke(app, ["check", str(tmp_path)]).stdout
    (tmp_path / "pyproject.toml").write_text("[tool.gymmigrate]\ndocs = false\n")
    assert "guide.md" not in runner.invoke(app, ["check", str(tmp_path)]).stdout
    assert "guide.md" in runner.invoke(app, ["check", "--docs", str(tmp_path)]).stdout
