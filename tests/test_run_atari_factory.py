"""A factory of the run called from another module (``fixtures/project_atari_factory``).

``arcade_envs.make_game`` makes its env from a parameter id and wraps it, on a flag, in a
wrapper only Atari games fit. What its callers pass settles whether its module needs
``import ale_py`` (GM106); a recorder in a caller names the make it cannot edit (GM407).
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_atari_factory"
runner = CliRunner()


def _findings(run: Path) -> list[dict]:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code in (0, 1), result.output
    return [{**f, "path": Path(f["path"]).relative_to(run).as_posix()} for f in json.loads(result.stdout)]


def _of(findings: list[dict], path: str, rule: str) -> list[tuple[int, str]]:
    return [(f["line"], f["kind"]) for f in findings if f["path"] == path and f["rule"] == rule]


def _copy(tmp_path: Path) -> Path:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    return run


def test_atari_ids_from_every_caller_settle_the_factorys_import(tmp_path: Path) -> None:
    findings = _findings(_copy(tmp_path))
    assert _of(findings, "arcade_envs.py", "GM106") == [(16, "auto")]
    [message] = [f["message"] for f in findings if f["path"] == "arcade_envs.py" and f["rule"] == "GM106"]
    assert "BreakoutNoFrameskip-v4" in message


def test_the_recorder_names_the_make_in_the_other_module(tmp_path: Path) -> None:
    findings = _findings(_copy(tmp_path))
    [found] = [f for f in findings if f["path"] == "record.py" and f["rule"] == "GM407"]
    assert found["kind"] == "flag"
    assert "the make in `make_game` of arcade_envs.py" in found["message"]


def test_the_same_factory_imported_by_name_or_through_its_package(tmp_path: Path) -> None:
    run = _copy(tmp_path)
    text = (run / "record.py").read_text()
    (run / "record.py").write_text(text.replace("import arcade_envs\n", "from arcade_envs import make_game\n").replace("arcade_envs.make_game(", "make_game("))
    findings = _findings(run)
    assert "make_game` of arcade_envs.py" in next(f["message"] for f in findings if f["rule"] == "GM407")
    assert _of(findings, "arcade_envs.py", "GM106") == [(16, "auto")]
    package = tmp_path / "pkg_run"
    (package / "games").mkdir(parents=True)
    (package / "games" / "__init__.py").write_text("")
    shutil.copy(run / "arcade_envs.py", package / "games" / "arcade_envs.py")
    (package / "record.py").write_text(text.replace("import arcade_envs\n", "from games import arcade_envs\n"))
    findings = _findings(package)
    assert "make_game` of games/arcade_envs.py" in next(f["message"] for f in findings if f["rule"] == "GM407")
    assert _of(findings, "games/arcade_envs.py", "GM106") == [(16, "auto")]


def test_no_caller_passing_an_atari_id_needs_no_ale_py(tmp_path: Path) -> None:
    run = _copy(tmp_path)
    (run / "record.py").write_text((run / "record.py").read_text().replace("BreakoutNoFrameskip-v4", "CartPole-v1"))
    before = "import ale_py"
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code == 0, result.output
    assert before not in (run / "arcade_envs.py").read_text()
    assert before not in (run / "record.py").read_text()


def test_a_factory_handed_on_as_a_value_tries_the_registration(tmp_path: Path) -> None:
    """Unknown ids may reach the factory besides Atari ones: the registration is tried, so an
    install without ale-py still makes the other envs (a note, nothing to decide)."""
    run = _copy(tmp_path)
    (run / "record.py").write_text(
        (run / "record.py").read_text().replace("BreakoutNoFrameskip-v4", "CartPole-v1")
        + "\nfrom functools import partial\n\nmake_other = partial(arcade_envs.make_game, press_fire=False)\n"
    )
    findings = _findings(run)
    assert _of(findings, "arcade_envs.py", "GM106") == [(16, "auto")]
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code == 0, result.output
    assert "    try:\n        import ale_py\n" in (run / "arcade_envs.py").read_text()
