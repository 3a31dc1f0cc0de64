"""A Gym wrapper of the project's own protocol used across modules: ``fixtures/project_own_records``.

``sim/records.py``'s ``Sampler`` steps with the project's ``Sample`` record and resets to the
bare observation, so its own reset keeps returning the observation. ``sim/loops.py``'s
``rollout`` is given one by every caller of the run (``train.py``): its reset and step
calls keep that protocol (no unpacked reset, no question on ``sample.reward``). ``peek`` is
given a ``Sampler`` and a plain Gym env: its reset is reported, not rewritten. The migrated
run works on Gymnasium 1.4.
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

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_own_records"
runner = CliRunner()


@pytest.fixture
def run(tmp_path: Path) -> Path:
    shutil.copytree(FIXTURE, tmp_path / "run")
    return tmp_path / "run"


def test_callers_given_the_wrapper_keep_its_protocol(run: Path) -> None:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    findings = [f for f in json.loads(result.stdout) if Path(f["path"]).name == "loops.py"]
    rows = sorted((f["line"], f["rule"], f["tier"]) for f in findings)
    assert rows == [(1, "GM101", "note"), (21, "GM201", "review")]
    peek = next(f for f in findings if f["rule"] == "GM201")
    assert "a Sampler (whose step and reset keep their own contract)" in peek["message"]


def test_the_migrated_run_rolls_out(run: Path) -> None:
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code in (0, 1), result.output
    loops = (run / "sim" / "loops.py").read_text()
    assert "observations = [sampler.reset()]" in loops
    assert "return source.reset()" in loops
    records = (run / "sim" / "records.py").read_text()
    assert "def reset(self, *, seed=None, options=None):" in records
    probe = (
        "import numpy as np\n"
        "from train import train\n"
        "observations, total = train(40)\n"
        "assert all(isinstance(o, np.ndarray) and o.shape == (4,) for o in observations), observations[:2]\n"
        "print(total)\n"
    )
    done = subprocess.run([sys.executable, "-c", probe], cwd=run, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert float(done.stdout) == 40.0
