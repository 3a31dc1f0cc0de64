"""Envs built from a wrapper kept on the legacy API keep legacy calls across the run
(``fixtures/project_legacy_chain``).

``relay.compat.OldFaces`` presents the old API behind a gym version check, so the run leaves
it alone. Its instances reach ``drive.py`` through a star re-export of the package, through an
``if``/``else`` make followed by ``env = OldFaces(env)``, through ``relay.stack.assemble`` (a
factory putting wrapper classes of its own module around it, one on a branch) and through a
parameter fed only with such envs: all of those calls stay legacy, and so do the wrappers of
``relay/stack.py``. ``mixed.py`` feeds one parameter such an env and a plain Gym env: one
review item, nothing rewritten there.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_legacy_chain"
runner = CliRunner()


@pytest.fixture
def run(tmp_path: Path) -> Path:
    shutil.copytree(FIXTURE, tmp_path / "run")
    return tmp_path / "run"


def _findings(run: Path) -> list[dict]:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code in (0, 1), result.output
    return [{**f, "path": Path(f["path"]).relative_to(run).as_posix()} for f in json.loads(result.stdout)]


def test_only_the_imports_change_where_every_feed_is_legacy(run: Path) -> None:
    before = {p: (run / p).read_text() for p in ("drive.py", "relay/stack.py", "mixed.py")}
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code in (0, 1), result.output
    for path, text in before.items():
        assert (run / path).read_text() == text.replace("import gym\n", "import gymnasium as gym\n", 1), path


def test_a_parameter_fed_both_kinds_is_one_question(run: Path) -> None:
    findings = _findings(run)
    review = sorted((f["path"], f["line"], f["rule"]) for f in findings if f["tier"] == "review")
    assert review == [("mixed.py", 10, "GM301"), ("relay/compat.py", 7, "GM108")]
    mixed = next(f for f in findings if f["path"] == "mixed.py" and f["rule"] == "GM301")
    assert "OldFaces" in mixed["message"]
    # the wrappers put around the kept one are left with a note, not asked about
    stack = sorted((f["line"], f["rule"], f["tier"]) for f in findings if f["path"] == "relay/stack.py")
    assert stack == [(1, "GM101", "note"), (15, "GM602", "note"), (22, "GM602", "note")]


def test_the_migrated_run_plays_on_gymnasium(run: Path) -> None:
    pytest.importorskip("gymnasium")
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code in (0, 1), result.output
    probe = "from drive import main\nprint(main(30))\n"
    done = subprocess.run([sys.executable, "-c", probe], cwd=run, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert float(done.stdout) > 0
