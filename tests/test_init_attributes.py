"""What a class's instances certainly hold once constructed, across the modules of a run
(``facts/init_attributes.py``, joined in ``project_classes.join_init_attributes``): the
base ``__init__`` a class hands up to in another module, the helpers ``__init__`` calls on
``self`` as the instance's own class resolves them, and nothing past an early return or a
class with several bases."""

from __future__ import annotations

import json
import os
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from gymmigrate.facts.project import ProjectFacts
from gymmigrate.facts.summaries import summarize

BASE = """import gym


class Track(gym.Env):
    def __init__(self, laps):
        self.laps = laps
        self.reward_range = (-1.0, 1.0)
        self._setup()

    def _setup(self):
        self.limit = 100
"""

ENVS = """import gym

from .base import Track


class Loop(Track):
    def __init__(self):
        super().__init__(3)
        self.closed = True


class Short(Track):
    def _setup(self):
        pass


class Lazy(Track):
    def __init__(self, ready=False):
        if not ready:
            return
        Track.__init__(self, 1)


class Other:
    pass


class Mixed(Track, Other):
    pass
"""

RUN = """import gym

from pkg.envs import Lazy, Loop

loop = Loop()
print(loop.reward_range)
lazy = Lazy()
print(lazy.reward_range)
"""


def _write(tmp_path: Path) -> Path:
    package = tmp_path / "pkg"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "base.py").write_text(BASE)
    (package / "envs.py").write_text(ENVS)
    (tmp_path / "run.py").write_text(RUN)
    return package


def test_bases_and_helpers_of_other_modules_are_followed(tmp_path: Path) -> None:
    package = _write(tmp_path)
    paths = [package / "base.py", package / "envs.py", tmp_path / "run.py"]
    summaries = [s for p in paths if (s := summarize(str(p), p.read_text())) is not None]
    facts = ProjectFacts.join(summaries)
    envs = os.path.realpath(package / "envs.py")

    def held(name: str) -> frozenset[str]:
        return facts.init_attributes.get((envs, name), frozenset()) - {"__init__", "_setup"}

    assert {"laps", "reward_range", "limit", "closed"} <= held("Loop")
    # its own ``_setup`` stores nothing, and is the one the base's ``__init__`` calls
    assert "limit" not in held("Short") and "reward_range" in held("Short")
    assert "reward_range" not in held("Lazy")  # an early return before the base's __init__
    assert "reward_range" not in held("Mixed")  # two bases: which __init__ runs is not followed


def test_a_read_on_a_bare_env_of_another_module_is_a_note_where_its_class_sets_it(tmp_path: Path) -> None:
    _write(tmp_path)
    report = tmp_path / "report.json"
    CliRunner().invoke(app, ["check", "--report", str(report), str(tmp_path)])
    data = json.loads(report.read_text())
    found = {
        (f["line"], tier)
        for file in data["files"]
        if file["path"].endswith("run.py")
        for tier in ("review", "notes")
        for f in file[tier]
        if f["rule"] == "GM507"
    }
    assert found == {(6, "notes"), (8, "review")}
