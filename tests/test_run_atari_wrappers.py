"""Atari envs known only through a wrapper of another module, and a search for gym's
Monitor by name in a module that names no wrapper module, in a run of several modules.

``fixtures/project_atari_wrappers`` (its README says what each module is).
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_atari_wrappers"
runner = CliRunner()


@pytest.fixture(scope="module")
def migrated(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[dict]]:
    run = tmp_path_factory.mktemp("atari_wrappers") / "run"
    shutil.copytree(FIXTURE, run)
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code == 1
    found = [{**f, "path": Path(f["path"]).relative_to(run).as_posix()} for f in json.loads(result.stdout)]
    assert runner.invoke(app, ["rewrite", str(run)]).exit_code == 0
    return run, found


def _of(findings: list[dict], path: str, rule: str) -> list[tuple[int, str]]:
    return [(f["line"], f["kind"]) for f in findings if f["path"] == path and f["rule"] == rule]


def test_an_env_handed_to_another_modules_atari_wrapper_registers_ale_py(migrated: tuple[Path, list[dict]]) -> None:
    run, findings = migrated
    assert _of(findings, "build.py", "GM106") == [(6, "auto")]
    text = (run / "build.py").read_text()
    assert "import ale_py" in text and "gym.register_envs(ale_py)" in text


def test_a_wrapper_of_another_module_without_atari_signs_adds_nothing(migrated: tuple[Path, list[dict]]) -> None:
    run, findings = migrated
    assert _of(findings, "plain.py", "GM106") == []
    assert "ale_py" not in (run / "plain.py").read_text()


def test_a_search_for_a_wrapper_named_monitor_is_asked(migrated: tuple[Path, list[dict]]) -> None:
    _, findings = migrated
    assert _of(findings, "report.py", "GM611") == [(6, "flag")]
