"""A base's ``reset`` that warms up with ``self.step(...)``, beside subclasses in other
modules with steps of their own API (``fixtures/project_warmup_steps``), migrated by one
``gymmigrate rewrite`` and run on Gymnasium 1.4.

``road/``: every subclass whose step stays on four values replaces ``reset`` (directly, or
first in the MRO) and never runs the base's, so the warm-up unpack takes five values with
the base's migrated step. Before, it kept four and every reset with warm-up steps raised
``ValueError``. ``ring/``: a subclass's reset calls up into the warm-up, which then runs
its own four-value step: the unpack stays.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from tests.fixture_cases import FIXTURES

runner = CliRunner()

_RUN = """
import warnings
warnings.simplefilter("ignore")
from road.base import Road

env = Road(warmup=3)
observation, info = env.reset(seed=0)
print(env.t, observation.tolist(), info)
"""


def test_warmup_unpack_moves_with_the_steps_that_run_it(tmp_path: Path) -> None:
    project = tmp_path / "project"
    shutil.copytree(FIXTURES / "project_warmup_steps", project)
    before = {p: (project / p).read_text() for p in ("road/convoy.py", "ring/pair.py")}
    checked = runner.invoke(app, ["check", "--output-format", "json", str(project)])
    kept = [(Path(f["path"]).relative_to(project).as_posix(), f["line"], f["rule"]) for f in json.loads(checked.stdout) if f["tier"] == "review" and "self.step()" in f["message"]]
    assert kept == [("ring/base.py", 18, "GM504")], kept  # the unpack left on four values is asked about
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    again = runner.invoke(app, ["rewrite", str(project)])
    assert "rewrote 0 of" in again.output, again.output
    assert "observation, _, _, _, _ = self.step(action=None)" in (project / "road" / "base.py").read_text()
    assert "observation, _, _, _ = self.step(action=None)" in (project / "ring" / "base.py").read_text()
    assert {p: (project / p).read_text() for p in before} == before  # the own-API classes stay
    run = subprocess.run([sys.executable, "-c", _RUN], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.splitlines() == ["3 [0.0, 0.0] {}"]
