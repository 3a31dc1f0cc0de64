"""A contract the run changes takes its callers with it; one it keeps, they keep (issue #19/#21).

``fixtures/project_kept_step/``: ``BatchEnv(gym.Env)`` steps a list of envs and returns
their results grouped by field (``zip(*per_env)``), a batch no rule migrates (GM504 tells
it in a note); its reset is migrated to ``(obs, {})``. Callers in two other modules used to be
rewritten to five fields (ValueError, and ``terminated or truncated`` on tuples); now the
step unpacks stay as they are, the reset unpacks follow the migrated reset.

``fixtures/rules/PZ105/hands_on_own_flag.py``: a PettingZoo env's ``reset`` lost
``return_info`` but still handed it on to the Gym env it holds (NameError on every reset).

``fixtures/project_render_heirs/``: ``BaseArena.render(mode)`` migrates to
``render_mode``; its subclasses in two other modules have their own ``__init__``: each
takes ``render_mode`` and passes it on, so ``gymnasium.make(id, render_mode="human")`` of
the registered subclass builds (it raised TypeError) and ``render()`` draws (it was a
silent no-op).

``fixtures/project_render_subclass_modes/``: ``SlidingBoardEnv`` in another module asks
``BoardEnv.render(mode)`` for frames with ``self.render(mode="rgb_array")`` (splitting it
made that call a TypeError): ``BoardEnv`` takes render_mode and keeps ``mode`` optional;
``TileEnv.render(mode, zoom)``, whose mode cannot become optional, is kept whole and takes
no render_mode (so its subclass passes none); ``PlainEnv``, whose subclass elsewhere has its
own render(), still migrates, and the subclass inherits its render_mode without an item;
``play.py`` makes an id ``boards/catalog.py`` registers from a JSON file: it gets no
render_mode (it may name ``BigTileEnv``), and its render is a review item.
"""

from __future__ import annotations

import importlib.util
import json
import shutil
import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from tests.fixture_cases import FIXTURES

runner = CliRunner()


def _migrated(tmp_path: Path, name: str) -> tuple[Path, list[dict]]:
    project = tmp_path / name
    shutil.copytree(FIXTURES / name, project)
    report = tmp_path / "report.json"
    result = runner.invoke(app, ["rewrite", "--report", str(report), str(project)])
    assert result.exit_code == 0, result.output
    findings = [dict(f, path=file["path"]) for file in json.loads(report.read_text())["files"] for f in file["review"]]
    return project, findings


def _run(project: Path, code: str) -> list[str]:
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    return run.stdout.splitlines()


def test_callers_of_a_step_the_run_keeps_keep_four_fields_and_run(tmp_path: Path) -> None:
    project, review = _migrated(tmp_path, "project_kept_step")
    algo = (project / "batch" / "algo.py").read_text()
    evaluate = (project / "evaluate.py").read_text()
    assert "obs, reward, done, _ = self.env.step(actions)" in algo
    # The batch keeps its reset with its step (one API of its own): callers in other modules too
    assert "self.obs = self.env.reset()" in algo
    assert "obss, rewards, dones, _ = env.step(" in evaluate and "terminated" not in evaluate
    assert "obss = env.reset()" in evaluate
    penv = (project / "batch" / "penv.py").read_text()
    assert "def reset(self):" in penv and "seed" not in penv
    # the run settles the batch (it keeps its contract, and so do its callers): a note, not a question
    assert not [f for f in review if f["rule"] == "GM504"], review
    report = json.loads((tmp_path / "report.json").read_text())
    notes = [dict(f, path=file["path"]) for file in report["files"] for f in file["notes"]]
    kept = [f for f in notes if f["rule"] == "GM504" and "callers" in f["message"]]
    assert len(kept) == 1 and kept[0]["path"].endswith("penv.py"), notes
    assert not [f for f in review if f["rule"] in ("GM301", "GM302") and not f["path"].endswith("penv.py")], review
    code = (
        "import gymnasium as gym\nfrom batch.algo import Runner\nfrom evaluate import evaluate\n"
        "print(Runner([gym.make('CartPole-v1') for _ in range(2)]).collect(40))\nprint(evaluate(3, 40))"
    )
    finished, evaluated = _run(project, code)
    assert int(finished) >= 1  # always pushing left ends CartPole episodes well within 40 steps
    count, episodes = evaluated.strip("()").split(", ")
    assert count == "3" and int(episodes) >= 3


def test_a_pettingzoo_reset_that_loses_return_info_stops_handing_it_on() -> None:
    path = FIXTURES / "rules" / "PZ105" / "hands_on_own_flag.expected.py"
    spec = importlib.util.spec_from_file_location("hands_on_own_flag", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    env = module.CrossingPZ()
    env.reset(seed=3)  # NameError before: return_info was gone from the signature only
    assert env.agents == ["light"]
    obs, info = env.env.reset(seed=3)
    assert obs.shape == (2,) and info == {"phase": 0}


def test_render_mode_is_threaded_through_subclasses_in_other_modules(tmp_path: Path) -> None:
    project, review = _migrated(tmp_path, "project_render_heirs")
    single = (project / "gym_arenas" / "single.py").read_text()
    hover = (project / "gym_arenas" / "hover.py").read_text()
    assert 'def __init__(self, size=3, gui=False, kind="kin", render_mode=None):' in single
    assert "super().__init__(size=size, gui=gui, render_mode=render_mode)" in single
    assert "super().__init__(size=4, gui=gui, render_mode=render_mode)" in hover
    # ``TeamArena(SingleArena, Scoring)``: two bases of the run, the first one's kind (as class_kind takes it).
    assert "super().__init__(size=players + 1, render_mode=render_mode)" in (project / "gym_arenas" / "team.py").read_text()
    assert 'gym.make("HoverArena-v0", gui=False, render_mode="human")' in (project / "play.py").read_text()
    code = (
        "import play\nplay.show(2)\nfrom gym_arenas.hover import HoverArena\n"
        "env = HoverArena(render_mode='human')\nenv.reset()\nenv.render()\nprint(HoverArena().render())\n"
        "print(play.team())\nimport gymnasium\nteam = gymnasium.make('TeamArena-v0', render_mode='human')\nteam.reset()\nteam.render()"
    )
    lines = _run(project, code)
    # ``team()`` steps once and draws what it stepped: made in human mode, it draws as before
    assert 'gym.make(env_id, render_mode="human")' in (project / "play.py").read_text()
    assert lines[-3:] == ["arena 1 of 3", "10", "arena 0 of 3"]
    lines = lines[:-3]
    assert "arena 1 of 4" in lines and "arena 2 of 4" in lines  # render() draws in the registered subclass
    assert lines[-2:] == ["arena 0 of 4", "None"]  # and without a mode it draws nothing, as Gymnasium's


def test_a_subclass_that_cannot_take_render_mode_is_reported_and_its_make_left(tmp_path: Path) -> None:
    """``super().__init__(**opts)`` cannot be given ``render_mode``: the subclass is reported,
    and the make of its registered id (or of an id that is not a literal) gets no render_mode
    (it would raise TypeError)."""
    project = tmp_path / "heirs"
    shutil.copytree(FIXTURES / "project_render_heirs", project)
    hover = project / "gym_arenas" / "hover.py"
    hover.write_text(hover.read_text().replace("super().__init__(size=4, gui=gui)", "opts = dict(size=4, gui=gui)\n        super().__init__(**opts)"))
    report = tmp_path / "report.json"
    result = runner.invoke(app, ["rewrite", "--report", str(report), str(project)])
    assert result.exit_code == 0, result.output
    assert "render_mode" not in hover.read_text() and "render_mode" not in (project / "play.py").read_text()
    review = [(Path(file["path"]).name, f["rule"], f["message"]) for file in json.loads(report.read_text())["files"] for f in file["review"]]
    assert any(name == "hover.py" and rule == "GM405" for name, rule, _ in review), review
    assert any(name == "play.py" and rule == "GM402" and "HoverArena, registered in this run" in message for name, rule, message in review), review
    lines = _run(project, "import play\nplay.show(1)\nprint('built')")
    assert lines == ["built"]  # the make builds; render() draws nothing until render_mode reaches it


def test_an_inherited_self_attribute_is_decided_like_the_base_class_reads_it(tmp_path: Path) -> None:
    """``AsyncCollector(Collector)`` reads ``self.env``, which ``Collector.__init__`` stores
    (a ``BaseVectorEnv`` of the run: ``reset(id)`` returns stacked observations). Its reset
    was unpacked into ``(obs, info)`` (splitting the batch) while the base's identical reset
    was reported; both sites are now decided on the same values, reported and left."""
    project, review = _migrated(tmp_path, "project_vector_receivers")
    collector = (project / "rollouts" / "collector.py").read_text()
    assert "obs = self.env.reset()" in collector and "obs_reset = self.env.reset(finished)" in collector
    reports = sorted((Path(f["path"]).name, f["line"]) for f in review if f["rule"] == "GM201")
    # one question for the one attribute the base class binds, naming the subclass's read
    assert ("collector.py", 13) in reports and ("collector.py", 22) not in reports, review
    assert any(f["line"] == 13 and "the same question at line 22" in f["message"] for f in review), review
    # venvs.py makes, wraps and subclasses no Gym env (an unused ``import gym``): the envs its
    # thunks make are not followed, so their reset is asked about and left, not guessed
    venvs = (project / "rollouts" / "venvs.py").read_text()
    assert "obs = [self.envs[i].reset() for i in self._ids(id)]" in venvs
    assert ("venvs.py", 15) in reports, review


def test_a_reset_mode_the_flag_never_reached_returns_the_pair_too() -> None:
    """``Junction(single_agent=False)`` (the default) reset through a branch that tested no
    ``return_info``: its callers, migrated to unpack ``(obs, info)``, unpacked the dict of
    observations (ValueError with one agent, its keys with two). Both modes give the pair."""
    path = FIXTURES / "rules" / "GM502" / "untested_mode_return.expected.py"
    spec = importlib.util.spec_from_file_location("untested_mode_return", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert sorted(module.first_observations()) == ["a", "b"]
    obs, info = module.Junction(single_agent=True).reset(seed=1)
    assert obs.shape == (2,) and info == {}


def test_a_subclass_in_a_module_the_env_rules_skip_is_not_counted_as_taking_render_mode(tmp_path: Path) -> None:
    """A module that never says "gym" is not decided by the env-class rules, so its
    subclass's ``__init__`` is not given ``render_mode``: the run must not count it as
    taking one, or a creation of it would get ``render_mode=`` (TypeError)."""
    project = tmp_path / "heirs"
    shutil.copytree(FIXTURES / "project_render_heirs", project)
    (project / "plain").mkdir()
    (project / "plain" / "__init__.py").write_text("from gym_arenas.base import BaseArena\n")
    tiny = project / "plain" / "tiny.py"
    tiny.write_text("from plain import BaseArena as Base\n\n\nclass TinyArena(Base):\n    def __init__(self):\n        super().__init__(size=1)\n")
    play = project / "play.py"
    play.write_text(play.read_text() + "\n\ndef tiny():\n    from plain.tiny import TinyArena\n    arena = TinyArena()\n    arena.reset()\n    arena.render()\n")
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    assert "render_mode" not in tiny.read_text()
    assert "arena = TinyArena()\n" in play.read_text()
    assert _run(project, "import play\nplay.tiny()\nprint('ran')") == ["ran"]


def test_an_env_class_on_an_api_of_its_own_keeps_it_with_its_callers(tmp_path: Path) -> None:
    """``fixtures/project_own_api/``: ``JunctionEnv(gym.Env)`` returns per-agent dicts
    (``flags["__all__"]``) for every junction, and Gymnasium's shapes in its solo mode. Its
    reset used to be paired again (``(obs, {}), {}``) and its driver in another module
    unpacked (obs, info) from the dict and five values from four (ValueError); now the class
    and the driver stay as they are, and the class is one review item."""
    original = (FIXTURES / "project_own_api" / "drive.py").read_text()
    project, review = _migrated(tmp_path, "project_own_api")
    assert (project / "drive.py").read_text() == original
    env = (project / "grid" / "env.py").read_text()
    assert "return views[self.junctions[0]], {}\n" in env and "def reset(self, seed=None, **kwargs):" in env
    assert [(f["rule"], f["path"].endswith("env.py")) for f in review] == [("GM504", True)], review
    (steps,) = _run(project, "from drive import drive\nprint(drive())")
    assert steps == "5"
    (solo,) = _run(project, "from grid.env import JunctionEnv\nenv = JunctionEnv(solo=True)\nprint(env.reset(seed=1), len(env.step(0)))")
    assert solo == "(0, {}) 5"


def test_a_subclass_in_another_module_that_renders_with_a_mode_keeps_its_base_render(tmp_path: Path) -> None:
    project, review = _migrated(tmp_path, "project_render_subclass_modes")
    board = (project / "boards" / "board.py").read_text()
    assert "def render(self, mode=None):" in board and "_render_frame" not in board
    assert "def __init__(self, width=4, render_mode=None):" in board
    sliding = (project / "boards" / "sliding.py").read_text()
    assert 'frame = self.render(mode="rgb_array")' in sliding and "render_mode=render_mode" in sliding
    tiles = (project / "boards" / "tiles.py").read_text()
    assert "def render(self, mode, zoom):" in tiles and "render_mode" not in tiles.replace("render_modes", "")
    assert "render_mode" not in (project / "boards" / "big_tiles.py").read_text()
    plain = (project / "boards" / "plain.py").read_text()
    assert "def render(self):" in plain and 'return self._render_frame(mode="rgb_array"), {}' in plain
    items = sorted((Path(f["path"]).name, f["kind"]) for f in review if f["rule"] == "GM405")
    assert items == [("board.py", "assist"), ("tiles.py", "flag")], review
    assert all("a subclass in another module" in f["message"] for f in review if f["rule"] == "GM405")
    # play.py makes an id boards/catalog.py registers from data: it may be BigTileEnv, which
    # takes no render_mode, so the make is left and the render reported.
    play = (project / "play.py").read_text()
    assert "gym.make(name)" in play and 'env.render(mode="rgb_array")' in play
    asked = [f for f in review if Path(f["path"]).name == "play.py"]
    assert [(f["line"], f["rule"]) for f in asked] == [(11, "GM401")] and "TileEnv" in asked[0]["message"], review
    code = (
        "from boards.sliding import SlidingBoardEnv\nfrom boards.painted import PaintedEnv\n"
        "from boards.big_tiles import BigTileEnv\n"
        "env = SlidingBoardEnv()\nobs, info = env.reset()\nprint(env.step(1)[0].tolist(), env.render())\n"
        "print(SlidingBoardEnv(render_mode='rgb_array').render().tolist())\n"
        "print(PaintedEnv(render_mode='rgb_array').render().tolist())\n"
        "big = BigTileEnv()\nbig.reset()\nprint(big.step(0)[0].shape)"
    )
    assert _run(project, code) == ["[[0, 255, 0, 0, 0, 0]] None", "[[255, 0, 0, 0, 0, 0]]", "[[7, 7]]", "(6, 6)"]


def test_an_own_batch_on_a_wrapper_base_keeps_its_contract_with_its_callers(tmp_path: Path) -> None:
    """``fixtures/project_own_batch_layers/``: ``Stacker`` derives the project's Gym wrapper
    base but is no layer (it holds ``venv``, never runs the base ``__init__``, reads its
    dones one per env): its step and reset, the four-field step in another module and
    ``hasattr`` on it stay; ``Clip``, a real layer on the same base, is migrated."""
    project, _ = _migrated(tmp_path, "project_own_batch_layers")
    wrappers = (project / "stack" / "wrappers.py").read_text()
    train = (project / "train.py").read_text()
    assert "obs, rews, news, infos = self.venv.step(actions)" in wrappers
    assert "obs, reward, terminated, truncated, info = self.env.step(action)" in wrappers
    assert "obs, rews, dones, infos = env.step([1] * env.num_envs)" in train
    assert 'hasattr(env, "horizon")' in train and "has_wrapper_attr" not in train
    assert "RecordConstructorArgs" not in wrappers
    shape, ends = _run(project, "from train import train\nprint(*train(2, 40))")[0].rsplit(" ", 1)
    assert shape == "(2, 8)" and int(ends) >= 1



def test_a_script_gets_render_mode_where_no_id_it_may_make_names_a_class_without_one(tmp_path: Path) -> None:
    """``fixtures/project_unreached_registry/``: ``lib/customs`` registers ``Custom-v0`` for a
    class whose ``__init__`` takes no ``render_mode``. ``tools/run_any.py``, a script, makes an
    id from its command line, imports nothing that runs that registration, and ``customs`` is
    not below its directory (no ``customs:`` prefix reaches it): ``Custom-v0`` does not exist
    in its process, so its make gets the mode its render asks. ``lib/show.py`` is a module
    ``lib/main.py`` imports after ``customs``: its make may build ``CustomEnv``, and is left."""
    project, review = _migrated(tmp_path, "project_unreached_registry")
    assert 'gym.make(env_id, render_mode="human")' in (project / "tools" / "run_any.py").read_text()
    assert "render_mode" not in (project / "lib" / "show.py").read_text()
    assert any(Path(f["path"]).name == "show.py" and f["rule"] == "GM402" and "CustomEnv" in f["message"] for f in review), review


def _edit(path: Path, old: str, new: str) -> None:
    path.write_text(path.read_text().replace(old, new, 1))


def test_a_script_whose_imports_or_ids_may_register_the_class_keeps_its_make(tmp_path: Path) -> None:
    """The same script importing ``customs``, making ``"customs:" + name`` (make imports the
    package first), lying beside the package (a ``customs:`` prefix from the command line
    reaches it), or in a run with a packaging file (an installed package, a ``gym.envs`` entry
    point): the id may name ``CustomEnv``, and the make is left."""
    script = Path("tools") / "run_any.py"
    for name, change in (
        ("imports", lambda p: _edit(p / script, "import gym\n", "import gym\n\nimport customs  # noqa: F401\n")),
        ("prefix", lambda p: _edit(p / script, "gym.make(env_id)", 'gym.make("customs:" + env_id)')),
        ("beside", lambda p: shutil.move(str(p / script), str(p / "lib" / "run_any.py"))),
        ("packaged", lambda p: (p / "setup.py").write_text('from setuptools import setup\n\nsetup(name="customs", packages=["customs"])\n')),
    ):
        project = tmp_path / name
        shutil.copytree(FIXTURES / "project_unreached_registry", project)
        change(project)
        result = runner.invoke(app, ["rewrite", str(project)])
        assert result.exit_code == 0, result.output
        made = project / ("lib" if name == "beside" else "tools") / "run_any.py"
        assert "render_mode" not in made.read_text(), name
