"""GM511: an env class an entry point makes that leaves a space unset. Gymnasium's ``make``
raises in its env checker where gym 0.21's Env gave ``None`` (``fixtures/project_unset_spaces``,
``fixtures/rules/GM511``).

In the package, a registered def of one module builds a class of a third module whose base
sets only the action space: asked at that class. A class registered by name that sets both
with its base, and one only an unregistered factory builds, are not.
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

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures"
runner = CliRunner()


@pytest.fixture
def run(tmp_path: Path) -> Path:
    shutil.copytree(FIXTURES / "project_unset_spaces", tmp_path / "run")
    return tmp_path / "run"


def test_the_class_the_registered_factory_builds_is_asked_about(run: Path) -> None:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code in (0, 1), result.output
    findings = [{**f, "path": Path(f["path"]).relative_to(run).as_posix()} for f in json.loads(result.stdout)]
    asked = [(f["path"], f["line"], f["rule"]) for f in findings if f["rule"] == "GM511"]
    assert asked == [("orchard/trees.py", 10, "GM511")]
    assert "`observation_space`" in next(f["message"] for f in findings if f["rule"] == "GM511")


def _make(cwd: Path, setup: str, env_id: str) -> subprocess.CompletedProcess[str]:
    probe = f"{setup}\nimport gymnasium\nenv = gymnasium.make({env_id!r})\nprint(env.reset(seed=0)[0])\n"
    return subprocess.run([sys.executable, "-W", "ignore", "-c", probe], cwd=cwd, capture_output=True, text=True, timeout=120)


def test_what_is_asked_is_what_make_rejects(run: Path) -> None:
    pytest.importorskip("gymnasium")
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code in (0, 1), result.output
    rejected = _make(run, "import orchard", "Orchard-v0")
    assert rejected.returncode != 0
    assert "must specify an observation space" in rejected.stderr
    assert _make(run, "import orchard", "Vineyard-v0").stdout.strip() == "0"


@pytest.mark.parametrize(
    ("case", "env_id", "rejected"),
    [
        ("registered_class", "Kettle-v0", "observation"),
        ("registered_class", "Dryer-v0", "action"),
        ("registered_factory", "Sprinkler-v0", "action"),
        ("spaces_set_in_construction", "Heater-v0", None),
        ("spaces_set_in_construction", "Fan-v0", None),
        ("spaces_set_in_construction", "Lamp-v0", None),
    ],
)
def test_the_single_file_cases_on_gymnasium(tmp_path: Path, case: str, env_id: str, rejected: str | None) -> None:
    pytest.importorskip("gymnasium")
    # the migrated fixture as a module (its ``__main__`` entry points name the running script)
    shutil.copy(FIXTURES / "rules" / "GM511" / f"{case}.expected.py", tmp_path / "case.py")
    script = (tmp_path / "case.py").read_text().replace('"__main__:', '"case:')
    (tmp_path / "case.py").write_text(script)
    done = _make(tmp_path, "import case", env_id)
    if rejected is None:
        assert done.returncode == 0, done.stderr
    else:
        assert done.returncode != 0
        assert f"must specify an {rejected} space" in done.stderr


def _stub_package(root: Path, main: str) -> None:
    (root / "boards" / "envs").mkdir(parents=True)
    (root / "boards" / "__init__.py").write_text(
        "from gym.envs.registration import register\n"
        'register(id="board-v0", entry_point="boards.envs:Board")\n'
        'register(id="board-hard-v0", entry_point="boards.envs:HardBoard")\n'
    )
    (root / "boards" / "envs" / "__init__.py").write_text("from boards.envs.board import Board\nfrom boards.envs.hard import HardBoard\n")
    (root / "boards" / "envs" / "board.py").write_text(
        "import gym\nimport numpy as np\n\n\nclass Board(gym.Env):\n    def __init__(self):\n"
        "        self.action_space = gym.spaces.Discrete(2)\n        self.observation_space = gym.spaces.Box(0, 1, (2,))\n\n"
        "    def reset(self):\n        return np.zeros(2)\n\n    def step(self, action):\n        return np.zeros(2), 0.0, False, {}\n"
    )
    (root / "boards" / "envs" / "hard.py").write_text("import gym\n\n\nclass HardBoard(gym.Env):\n    pass\n")
    (root / "main.py").write_text(main)


@pytest.mark.parametrize(
    ("main", "tier"),
    [
        ('import gym\nimport boards\nenv = gym.make("boards:board-v0")\n', "note"),  # only the sibling is made
        ('import gym\nimport boards\nenv = gym.make("boards:board-hard-v0")\n', "review"),
        ("import sys\nimport gym\nimport boards\nenv = gym.make(sys.argv[1])\n", "review"),  # any id may be made
    ],
)
def test_a_registered_stub_no_make_of_the_run_names_is_a_note(tmp_path: Path, main: str, tier: str) -> None:
    _stub_package(tmp_path, main)
    result = runner.invoke(app, ["check", "--output-format", "json", str(tmp_path)])
    [finding] = [f for f in json.loads(result.stdout) if f["rule"] == "GM511"]
    assert finding["path"].endswith("hard.py") and finding["tier"] == tier, finding


def _plain_module_package(root: Path, child_imports: str, child_init: str) -> None:
    """A package whose registered class lives in a module that imports no Gym package: its
    Env comes from a base of the run (``pond.envs.base``) that derives from gym.Env."""
    (root / "pond" / "envs").mkdir(parents=True)
    (root / "pond" / "__init__.py").write_text('from gym.envs.registration import register\nregister(id="Frog-v0", entry_point="pond.envs:Frog")\n')
    (root / "pond" / "envs" / "__init__.py").write_text("from pond.envs.base import PondBase\nfrom pond.envs.frog import Frog\n")
    (root / "pond" / "envs" / "base.py").write_text("import gym\n\n\nclass PondBase(gym.Env):\n    def __init__(self, depth):\n        self.depth = depth\n")
    (root / "pond" / "envs" / "frog.py").write_text(
        f"{child_imports}import numpy as np\n\nfrom pond.envs import PondBase\n\n\nclass Frog(PondBase):\n    def __init__(self):\n"
        f"        PondBase.__init__(self, depth=3)\n{child_init}\n    def reset(self):\n        return np.zeros(2)\n\n"
        "    def step(self, action):\n        return np.zeros(2), 0.0, False, {}\n"
    )


@pytest.mark.parametrize(
    ("child_imports", "child_init", "asked"),
    [
        ("", "", True),  # nothing of the chain sets a space: make raises
        ("from gym import spaces\n", "        self.action_space = spaces.Discrete(2)\n        self.observation_space = spaces.Box(0, 1, (2,))\n", False),
        ("import gymnasium\n", "", False),  # a module written for Gymnasium: no legacy default to miss
    ],
)
def test_a_class_in_a_module_without_gym_imports_is_asked_through_its_base(tmp_path: Path, child_imports: str, child_init: str, asked: bool) -> None:
    _plain_module_package(tmp_path, child_imports, child_init)
    result = runner.invoke(app, ["check", "--output-format", "json", str(tmp_path)])
    found = [(Path(f["path"]).name, f["line"]) for f in json.loads(result.stdout) if f["rule"] == "GM511"]
    assert found == ([("frog.py", 6 + child_imports.count("\n"))] if asked else [])


_BASE = """import gym


class Field(gym.Env):
    def __init__(self, size=2):
        self.size = size

    def reset(self):
        self.action_space = gym.spaces.Discrete(2)
        self.observation_space = gym.spaces.Discrete(self.size)
        return 0

    def step(self, action):
        return 0, 0.0, True, {}
"""

_SUB = """import gym

from farm.base import Field


class Meadow(Field):
    def __init__(self):
        super().__init__(size=5)


class Paddock(Field):
    def __init__(self):
        self.size = 3
"""

_REGISTER = """import gym

gym.envs.registration.register(id="Field-v0", entry_point="farm.base:Field")
gym.envs.registration.register(id="Meadow-v0", entry_point="farm.sub:Meadow")
gym.envs.registration.register(id="Paddock-v0", entry_point="farm.sub:Paddock")
field = gym.make("Field-v0")
meadow = gym.make("Meadow-v0")
paddock = gym.make("Paddock-v0")
"""


def test_a_subclass_built_through_its_base_is_asked_about_once_at_the_base(tmp_path: Path) -> None:
    # Meadow runs Field's __init__: spaces set there reach it, so Field's item names it and
    # Meadow gets a note. Paddock never runs that __init__: it keeps an item of its own.
    farm = tmp_path / "farm"
    farm.mkdir()
    (farm / "__init__.py").write_text("")
    (farm / "base.py").write_text(_BASE)
    (farm / "sub.py").write_text(_SUB)
    (tmp_path / "main.py").write_text(_REGISTER)
    result = runner.invoke(app, ["check", "--output-format", "json", str(tmp_path)])
    assert result.exit_code in (0, 1), result.output
    found = {(Path(f["path"]).name, f["line"]): f for f in json.loads(result.stdout) if f["rule"] == "GM511"}
    assert sorted((key, f["tier"]) for key, f in found.items()) == [
        (("base.py", 4), "review"),
        (("sub.py", 6), "note"),
        (("sub.py", 11), "review"),
    ]
    assert "`Meadow`" in found[("base.py", 4)]["message"] and "`Paddock`" not in found[("base.py", 4)]["message"]
    assert "`Field` (base.py)" in found[("sub.py", 6)]["message"]
