"""GM807: a factory registered as an entry point that returns the project's own proxy, no
gymnasium.Env (issue #19).

``fixtures/project_factory_entry/``: ``lab.registry.flat_board`` returns ``Flatten``, whose
bases end in ``Saved``, a plain class of a module with no Gym code: ``gymnasium.make`` raises
TypeError on it before any env checker, and the registration is reported. ``plain_board``
(a ``gym.Env``) and ``either_board`` (the proxy only when asked, the env by default) are left.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from tests.fixture_cases import FIXTURES, migrated_project


def test_only_the_factory_returning_the_proxy_is_reported() -> None:
    root = FIXTURES / "project_factory_entry"
    result = CliRunner().invoke(app, ["check", "--output-format", "json", str(root)])
    assert result.exit_code in (0, 1), result.output
    findings = [f for f in json.loads(result.stdout) if f["rule"] == "GM807"]
    assert [(Path(f["path"]).relative_to(root).as_posix(), f["line"], f["kind"]) for f in findings] == [("lab/registry.py", 25, "flag")]
    assert "`flat_board` returns a `Flatten`" in findings[0]["message"] and "`Saved` of `lab.saved`" in findings[0]["message"]


def test_make_rejects_the_proxy_and_builds_the_env(tmp_path: Path) -> None:
    project, _ = migrated_project(tmp_path, "project_factory_entry")
    probe = (
        "import gymnasium, lab.registry\n"
        "gymnasium.make('PlainBoard-v0').reset(seed=0)\n"
        "try:\n"
        "    gymnasium.make('FlatBoard-v0')\n"
        "except TypeError as error:\n"
        "    assert 'must inherit from the gymnasium.Env class' in str(error)\n"
        "else:\n"
        "    raise AssertionError('made')\n"
    )
    done = subprocess.run([sys.executable, "-W", "ignore", "-c", probe], cwd=project, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
