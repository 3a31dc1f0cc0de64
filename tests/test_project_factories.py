"""A def of the run that returns ``make(...)`` results is a Gym env factory in every module
that calls it (``facts/summaries/defs.py`` ``made_factories``, joined in ``facts/project.py``).

``fixtures/project_factories/`` is a ``tools`` package whose ``make_env`` seeds a
``gym.make`` env and returns it, and whose ``make_short`` wraps one in ``TimeLimit``; a
script in ``scripts/`` that never names the library calls them through ``import tools``
(a star import in ``tools/__init__.py``) and reads ``env.x_threshold`` on the result,
which Gymnasium 1.x no longer forwards; later it rebinds the same name to ``LongTrack()``,
an env class of the run (a subclass in another module), whose attributes are its own.
``vendor/tools.py`` is another module called ``tools`` in another folder: the script's
``import tools`` is the package above it.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.project import ProjectFacts
from gymmigrate.facts.summaries import summarize
from tests.fixture_cases import FIXTURES

runner = CliRunner()


def _copy(tmp_path: Path) -> Path:
    target = tmp_path / "project_factories"
    shutil.copytree(FIXTURES / "project_factories", target)
    return target


def _facts(project: Path) -> ProjectFacts:
    summaries = []
    for path in sorted(project.rglob("*.py")):
        summary = summarize(str(path), path.read_text())
        assert summary is not None
        summaries.append(summary)
    return ProjectFacts.join(summaries)


def test_the_factories_are_known_where_they_are_called(tmp_path: Path) -> None:
    project = _copy(tmp_path)
    facts = _facts(project)
    script = facts.view(str(project / "scripts" / "play.py"))
    assert script.call_kind("tools.make_env") is EnvKind.GYM_ENV  # the package next to the script
    assert script.returns_made("tools.make_env") and script.returns_made("tools.make_short")
    assert script.call_kind("tools.describe") is EnvKind.NOT_ENV and not script.returns_made("tools.describe")
    vendor = facts.view(str(project / "vendor" / "x.py"))
    assert vendor.call_kind("tools.make_env") is EnvKind.NOT_ENV  # from its own folder: the other tools
    assert script.makes_bare_env("tools.long.LongTrack") and not script.makes_bare_env("tools.make_env")


def test_the_own_env_class_read_after_a_factory_is_no_question(tmp_path: Path) -> None:
    project = _copy(tmp_path)
    report = tmp_path / "report.json"
    runner.invoke(app, ["check", "--report", str(report), str(project)])
    files = json.loads(report.read_text())["files"]
    found = {(f["line"], f["rule"]) for file in files if file["path"].endswith("play.py") for f in [*file["review"], *file["notes"]]}
    assert (12, "GM604") in found and (13, "GM604") in found  # the make_env result: forwarded
    assert not any(rule == "GM604" and line > 30 for line, rule in found)  # LongTrack's env.size
    assert {(38, "GM201"), (41, "GM301")} <= found


def test_calls_are_rewritten_and_forwarded_reads_go_through_unwrapped(tmp_path: Path) -> None:
    project = _copy(tmp_path)
    vendor = (project / "vendor" / "tools.py").read_bytes()
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    script = (project / "scripts" / "play.py").read_text()
    assert "obs, info = env.reset()" in script
    assert "obs, reward, terminated, truncated, _ = env.step(steps % 2)" in script
    assert "abs(obs[0]) > env.unwrapped.x_threshold" in script and "env.x_threshold" not in script
    assert "_, _, terminated, truncated, _ = env.step(0)" in script  # the TimeLimit-wrapped make
    assert 'found = tools.describe(name)\n    return found.get("id")' in script  # not an env: untouched
    assert "obs, reward, terminated, truncated, info = env.step(1)" in script and "return obs, env.size" in script
    assert (project / "vendor" / "tools.py").read_bytes() == vendor
    again = runner.invoke(app, ["rewrite", str(project)])
    assert again.exit_code == 0 and "rewrote 0 of" in again.output
    # It runs on Gymnasium 1.4: make_env's seed became a seeded reset (GM203), then the
    # script's own reset starts the episode; the TimeLimit ends the short one after 5 steps.
    code = (
        "import gymnasium\nfrom scripts import play\n"
        "env = gymnasium.make('CartPole-v1'); env.reset(seed=7); obs, _ = env.reset(); n = 0\n"
        "while True:\n"
        "    obs, _, term, trunc, _ = env.step(n % 2); n += 1\n"
        "    if term or trunc or abs(obs[0]) > 2.4: break\n"
        "print(play.episode(7) == (n, 2.4), play.short_episode(), play.record('x'), *play.walk_long_track())\n"
    )
    run = subprocess.run([sys.executable, "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["True", "5", "x", "7", "8"]
