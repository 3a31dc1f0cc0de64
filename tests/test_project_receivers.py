"""Know the receiver across the run, never guess it (facts/summaries/exports.py, joined in
facts/project.py ``call_kinds``).

``fixtures/project_receivers/`` is a package driven by a script that never says where its
objects come from: ``warehouse.make`` is ``gym.make`` re-exported from ``utils`` through
``__init__``, ``Shelf`` comes in by a star import, ``LongShelf`` derives from it in another
module, ``Game`` holds a ``make`` env in ``self.environment`` (a file whose text never names
the library), and ``helpers`` has a plain ``Environment`` and the project's own
``SubprocVecEnv``: the run rewrites the envs and leaves the helpers. ``fixtures/
project_pettingzoo/`` is a PettingZoo 1.20 parallel env and a driver that never imports
PettingZoo.
"""

from __future__ import annotations

import json
import os
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


def _copy(name: str, tmp_path: Path) -> Path:
    target = tmp_path / name
    shutil.copytree(FIXTURES / name, target)
    return target


def _findings(paths: list[Path], tmp_path: Path) -> list[dict[str, object]]:
    report = tmp_path / "report.json"
    runner.invoke(app, ["check", "--report", str(report), *map(str, paths)])
    data = json.loads(report.read_text())
    return [dict(f, path=file["path"]) for file in data["files"] for f in [*file["review"], *file["notes"]]]


def _run(folder: Path, code: str) -> str:
    run = subprocess.run([sys.executable, "-c", code], cwd=folder, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    return run.stdout


def _join(files: dict[str, str], tmp_path: Path) -> ProjectFacts:
    summaries = []
    for name, text in files.items():
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
        summary = summarize(str(path), text)
        assert summary is not None
        summaries.append(summary)
    return ProjectFacts.join(summaries)


# -- the facts ----------------------------------------------------------------------------


def test_reexports_star_imports_aliases_and_subclasses_are_followed(tmp_path: Path) -> None:
    facts = _join(
        {
            "pkg/__init__.py": "from .utils import make\nfrom .envs import *\n",
            "pkg/utils.py": "import gym\n\nmake = gym.make\n",
            "pkg/envs.py": "import gym\n\n\nclass Grid(gym.Env):\n    pass\n\n\nclass Board:\n    pass\n",
            "pkg/more.py": "from .envs import Grid\n\n\nclass BigGrid(Grid):\n    pass\n",
            "main.py": "import pkg\n",
        },
        tmp_path,
    )
    main = facts.view(str(tmp_path / "main.py"))
    assert main.call_kind("pkg.make") is EnvKind.GYM_ENV
    assert main.library_alias("pkg.make") == "gym.make"
    assert main.call_kind("pkg.Grid") is EnvKind.GYM_ENV  # through the star import
    assert main.call_kind("pkg.more.BigGrid") is EnvKind.GYM_ENV
    assert main.call_kind("pkg.Board") is EnvKind.NOT_ENV
    assert main.call_kind("pkg.Nothing") is EnvKind.UNKNOWN  # a module of the run, a name it lacks
    assert main.call_kind("numpy.zeros") is None  # not the run's


def test_pettingzoo_classes_and_factories_of_the_run(tmp_path: Path) -> None:
    facts = _join(
        {
            "hunt.py": (
                "from pettingzoo import ParallelEnv, AECEnv\nfrom pettingzoo.utils import parallel_to_aec, parallel_wrapper_fn\n\n\n"
                "class Hunt(ParallelEnv):\n    pass\n\n\nclass Tag(AECEnv):\n    pass\n\n\n"
                "def env():\n    return parallel_to_aec(Hunt())\n\n\nparallel_env = parallel_wrapper_fn(env)\n"
            ),
            "drive.py": "import hunt\n",
        },
        tmp_path,
    )
    view = facts.view(str(tmp_path / "drive.py"))
    assert view.call_kind("hunt.Hunt") is EnvKind.PZ_PARALLEL
    assert view.call_kind("hunt.Tag") is EnvKind.PZ_AEC
    assert view.call_kind("hunt.env") is EnvKind.PZ_AEC
    assert view.call_kind("hunt.parallel_env") is EnvKind.PZ_PARALLEL
    assert view.imports_multi_agent(["hunt.Hunt"]) and not view.imports_multi_agent(["hunt.nothing"])


def test_a_reexport_cycle_is_unknown_not_a_hang(tmp_path: Path) -> None:
    facts = _join({"a.py": "from b import make\n", "b.py": "from a import make\n"}, tmp_path)
    assert facts.view(str(tmp_path / "a.py")).call_kind("b.make") is EnvKind.UNKNOWN


# -- the Gym package --------------------------------------------------------------------------


def test_one_rewrite_migrates_the_envs_and_leaves_the_helpers(tmp_path: Path) -> None:
    project = _copy("project_receivers", tmp_path)
    helpers = (project / "warehouse" / "helpers.py").read_bytes()
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    driver = (project / "run_warehouse.py").read_text()
    assert "observation, info = env.reset(seed=seed)" in driver  # warehouse.make
    assert "observation, info = env_0.reset()" in driver  # annotated with a star-imported class
    assert "observation, reward, terminated, truncated, info = shelf.step(1)" in driver  # a subclass elsewhere
    assert "state, reward, done, info = env.step(2)" in driver  # the plain helper: untouched
    assert "observations, rewards, dones, infos = env.step([1, 2])" in driver  # the project's VecEnv
    assert "observations = env.reset()\n" in driver  # ...its reset too
    assert "observation, info = env.reset()\n    return rewards" in driver  # rebound to an env: rewritten
    assert (project / "warehouse" / "helpers.py").read_bytes() == helpers
    again = runner.invoke(app, ["rewrite", str(project)])
    assert again.exit_code == 0 and "rewrote 0 of" in again.output  # the migrated run knows it is done
    game = (project / "warehouse" / "game.py").read_text()
    assert "observation, info = self.environment.reset(seed=seed)" in game
    # What the legacy driver meant, on Gymnasium 1.4: CartPole's episode length from the
    # seed, the shelves' own rules, the helpers' unchanged results.
    out = _run(
        project,
        "import gymnasium\nimport run_warehouse as r\n"
        "def length(seed, action):\n"
        "    env = gymnasium.make('CartPole-v1'); env.reset(seed=seed); n = 0\n"
        "    while True:\n"
        "        n += 1; _, _, term, trunc, _ = env.step(action)\n"
        "        if term or trunc: return n\n"
        "print(r.pole_steps(3) == length(3, 0), r.game_length(5) == length(5, 1))\n"
        "print(r.shelf_return(r.Shelf()), r.long_shelf_steps(), r.helper_counts(), r.stacked_rewards())\n",
    )
    same, values = out.splitlines()
    assert same == "True True"
    assert values == "1.0 8 (2, 2.0, False) ([1.0, 2.0], 4)"


def test_the_game_render_forwarding_is_reported_at_its_make(tmp_path: Path) -> None:
    project = _copy("project_receivers", tmp_path)
    findings = _findings([project], tmp_path)
    renders = [f for f in findings if f["rule"] == "GM402"]
    assert [Path(str(f["path"])).name for f in renders] == ["game.py"]


def test_the_driver_checked_alone_reports_instead_of_guessing(tmp_path: Path) -> None:
    project = _copy("project_receivers", tmp_path)
    alone = _findings([project / "run_warehouse.py"], tmp_path)
    assert alone and all(f["kind"] == "flag" for f in alone)


def test_a_file_whose_text_says_environment_is_not_skipped(tmp_path: Path) -> None:
    project = _copy("project_receivers", tmp_path)
    findings = _findings([project], tmp_path)
    assert {f["rule"] for f in findings if str(f["path"]).endswith("game.py")} >= {"GM201", "GM203", "GM301"}


# -- the PettingZoo package ----------------------------------------------------------------

# The legacy code runs on PettingZoo 1.27 as it is (its env defines seed/reset/step itself)
# once ``gym`` names Gymnasium: what it prints is what the legacy driver meant.
_LEGACY_GYM = (
    "import sys, gymnasium, gymnasium.spaces, gymnasium.utils, gymnasium.utils.seeding\n"
    "sys.modules.update({'gym': gymnasium, 'gym.spaces': gymnasium.spaces, 'gym.utils': gymnasium.utils,"
    " 'gym.utils.seeding': gymnasium.utils.seeding})\n"
)
_PLAY = "import drive\nfor seed in range(6):\n    print(seed, drive.play(seed), drive.play_factory(seed))\n"


def test_the_pettingzoo_driver_is_migrated_and_plays_as_before(tmp_path: Path) -> None:
    project = _copy("project_pettingzoo", tmp_path)
    legacy = _run(project, _LEGACY_GYM + _PLAY)
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    driver = (project / "drive.py").read_text()
    assert "observations, infos = env.reset(seed=seed)" in driver
    assert "observations, rewards, terminations, truncations, infos = env.step(chase(observations))" in driver
    assert "observations, infos = penv.reset(seed=seed)" in driver
    assert ".seed(" not in driver
    assert "import gym\n" not in (project / "hunt_parallel.py").read_text()
    again = runner.invoke(app, ["rewrite", str(project)])
    assert again.exit_code == 0 and "rewrote 0 of" in again.output
    migrated = _run(project, _PLAY)
    assert migrated == legacy and len(migrated.splitlines()) == 6
    checked = _run(
        project,
        "from pettingzoo.test import parallel_api_test\nfrom hunt_parallel import HuntEnv\n"
        "parallel_api_test(HuntEnv(), num_cycles=20); print('ok')",
    )
    assert checked.strip().endswith("ok")


def test_the_aec_driver_of_the_runs_factory_is_migrated_and_takes_its_turns(tmp_path: Path) -> None:
    """``drive_aec.py`` plays the package's ``env()`` (``parallel_to_aec`` of ``HuntEnv``)."""
    project = _copy("project_pettingzoo", tmp_path)
    cycles = _run(
        project,
        _LEGACY_GYM + "from hunt_parallel import HuntEnv\nfor seed in range(6):\n"
        "    e = HuntEnv(max_cycles=4); e.seed(seed); e.reset(); n = 0\n"
        "    while e.agents:\n        e.step({a: 1 for a in e.agents}); n += 1\n    print(n)\n",
    ).split()
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    driver = (project / "drive_aec.py").read_text()
    assert "game.reset(seed=seed)" in driver and ".seed(" not in driver.replace("reset(seed=", "")
    assert "observation, reward, termination, truncation, info = game.last()" in driver
    assert "game.step(None if termination or truncation else 1)" in driver
    turns = _run(project, "import drive_aec\nfor seed in range(6):\n    print(drive_aec.play_turns(seed))\n").split()
    # Two turns a cycle, then each agent steps once more with None once it is done.
    assert [int(t) for t in turns] == [2 * int(n) + 2 for n in cycles]


def test_the_pettingzoo_driver_alone_is_not_touched(tmp_path: Path) -> None:
    project = _copy("project_pettingzoo", tmp_path)
    before = (project / "drive.py").read_bytes()
    result = runner.invoke(app, ["rewrite", str(project / "drive.py")])
    assert result.exit_code == 0, result.output
    assert (project / "drive.py").read_bytes() == before


# -- a notebook: kinds follow the cells in order ------------------------------------------------


def test_a_notebook_vecenv_copy_is_left_and_the_name_rebound_to_make_is_rewritten() -> None:
    from tests.test_notebooks import _notebook, _rewrite

    vec_class = (
        "class SubprocVecEnv(object):\n"
        "    def __init__(self, fns):\n        self.envs = [fn() for fn in fns]\n        self.num_envs = len(self.envs)\n"
        "    def reset(self):\n        return [e.reset() for e in self.envs]\n"
        "    def step_async(self, actions):\n        self.actions = actions\n"
        "    def step_wait(self):\n        return [], [], [], []\n"
    )
    source = _notebook(
        ("code", "import gym\n"),
        ("code", vec_class),
        ("code", "env = SubprocVecEnv([lambda: gym.make('CartPole-v1')])\nobs = env.reset()\n"),
        ("code", "env = gym.make('CartPole-v1')\nobs = env.reset()\nobs, reward, done, info = env.step(0)\n"),
    )
    cells = ["".join(c["source"]) for c in json.loads(_rewrite(source))["cells"]]
    assert "obs = env.reset()\n" in cells[2]  # the project's VecEnv keeps its API
    assert "obs, info = env.reset()" in cells[3]
    assert "obs, reward, terminated, truncated, info = env.step(0)" in cells[3]


def test_an_env_kept_in_its_own_attribute_runs_migrated() -> None:
    """``fixtures/rules/GM201/self_alias_of_env.expected.py`` on Gymnasium 1.4."""
    from gymnasium.utils.env_checker import check_env

    namespace: dict[str, object] = {}
    path = FIXTURES / "rules" / "GM201" / "self_alias_of_env.expected.py"
    exec(compile(path.read_text(), str(path), "exec"), namespace)
    env = namespace["Stacked"]()  # type: ignore[operator]
    env.step(1)
    assert env.restart() == 0 and env.count == 0
    check_env(env, skip_render_check=True)


def test_a_gym_wrapper_class_from_a_star_import_makes_a_gym_env(tmp_path: Path) -> None:
    """``fixtures/project_star_wrappers``: ``WrapPyTorch`` comes in by ``from utils.wrappers
    import *``; the env it wraps (baselines' ``make_atari``) is unknown, but the wrapper is a
    Gym env: its reset is rewritten without a question. A plain class of the same module
    (``Recorder``) proves nothing: its reset is still asked about."""
    project = _copy("project_star_wrappers", tmp_path)
    result = runner.invoke(app, ["check", "--output-format", "json", str(project / "train.py"), str(project / "utils")])
    resets = {f["line"]: f["tier"] for f in json.loads(result.stdout) if f["rule"] == "GM201" and f["path"].endswith("train.py")}
    assert resets == {8: "note", 15: "review"}
# -- a constructor parameter proven by the run's callers ----------------------------------------

_AGENT = """class Agent:
    def __init__(self, env, gamma=0.99):
        self.env = env
        self.gamma = gamma

    def run(self):
        obs = self.env.reset()
        obs, reward, done, info = self.env.step(0)
        return reward
"""


def _agent_steps(project: Path, tmp_path: Path) -> list[tuple[str, str]]:
    return sorted(
        (str(f["rule"]), str(f["kind"]))
        for f in _findings([project], tmp_path)
        if str(f["path"]).endswith("agent.py") and f["rule"] in ("GM201", "GM301")
    )


def test_a_constructor_parameter_is_known_from_the_callers_in_other_modules(tmp_path: Path) -> None:
    project = tmp_path / "run"
    (project / "pkg").mkdir(parents=True)
    (project / "pkg" / "__init__.py").write_text("")
    (project / "pkg" / "agent.py").write_text(_AGENT)
    (project / "main.py").write_text(
        'import gym\nfrom pkg.agent import Agent\n\nenv = gym.make("CartPole-v1")\nAgent(env).run()\n'
        'Agent(gym.make("CartPole-v1"), gamma=0.9).run()\n'
    )
    assert _agent_steps(project, tmp_path) == [("GM201", "auto"), ("GM301", "auto")]
    # A subclass in another module built with a VecEnv: the callers no longer all pass a Gym
    # env, and those calls are not seen from agent.py: reported, not rewritten.
    (project / "pkg" / "special.py").write_text(
        "from pkg.agent import Agent\n\n\nclass Special(Agent):\n    def describe(self):\n        return f'on {self.env}'\n"
    )
    (project / "vec.py").write_text(
        "import gym\nfrom stable_baselines3.common.vec_env import DummyVecEnv\nfrom pkg.special import Special\n\n"
        'Special(DummyVecEnv([lambda: gym.make("CartPole-v1")])).run()\n'
    )
    assert _agent_steps(project, tmp_path) == [("GM201", "flag"), ("GM301", "flag")]


def test_space_checks_stay_on_gym_next_to_a_gym_only_env_package(tmp_path: Path) -> None:
    """``from gym import spaces`` used only by isinstance checks in a module that the script
    importing ``multiagent`` imports: left on gym and reported. An unrelated module of the
    same run that checks its own spaces is migrated."""
    project = tmp_path / "run"
    for folder in ("common", "experiments", "tools"):
        (project / folder).mkdir(parents=True)
    checks = "def head(space):\n    from gym import spaces\n    return isinstance(space, spaces.Box)\n"
    (project / "common" / "distributions.py").write_text(checks)
    (project / "tools" / "inspect_env.py").write_text("import gym\n" + checks)
    (project / "experiments" / "train.py").write_text(
        "import gym\nfrom multiagent.environment import MultiAgentEnv\nfrom common.distributions import head\n"
    )
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    assert "    from gym import spaces\n" in (project / "common" / "distributions.py").read_text()
    assert "    from gymnasium import spaces\n" in (project / "tools" / "inspect_env.py").read_text()
    kept = [f for f in _findings([project], tmp_path) if f["rule"] == "GM102" and f["kind"] == "flag"]
    assert [Path(str(f["path"])).name for f in kept] == ["distributions.py"]


def test_notebook_calls_count_as_call_sites_and_own_helpers_are_left(tmp_path: Path) -> None:
    """A notebook is no module anything imports, but it calls the run's defs: its
    ``gym.make`` env makes ``loops.run_episodes``'s loop certain, and the instance of the
    project's own ``Frames`` (its own reset/step) it hands ``Trainer.fit`` leaves that
    method alone, unasked. A def no one calls is still asked."""
    project = _copy("project_notebook_callers", tmp_path)
    trainer = (project / "trainer.py").read_bytes()
    found = _findings([project], tmp_path)
    review = sorted((Path(str(f["path"])).name, f["line"]) for f in found if f["tier"] == "review")
    assert review == [("loops.py", 17)]
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    loops = (project / "loops.py").read_text()
    assert "        state, info = env.reset()\n" in loops
    assert "state, reward, terminated, truncated, _ = env.step(agent(state))" in loops
    assert "    return env.reset()\n" in loops  # never_called: no caller says what env is
    assert (project / "trainer.py").read_bytes() == trainer
    assert "obs, info = self.env.reset()" in (project / "helpers.py").read_text()


def test_a_holder_built_with_the_runs_own_factory_chain_is_a_gym_env(tmp_path: Path) -> None:
    """``fixtures/project_holders/``: ``Session(build(game_id))`` where ``build`` (a def of the
    caller) returns ``stacks.stack(stacks.make_game(...))`` of another module of the run: every
    construction passes a Gym env, so ``self.game`` is one and its reset/step are rewritten."""
    project = _copy("project_holders", tmp_path)
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    holder = (project / "arcade" / "holder.py").read_text()
    assert "frame, reward, terminated, truncated, info = self.world_env.step(action)" in holder
    assert "return self.world_env.reset()[0]" in holder or "self.world_env.reset()\n" not in holder
    again = runner.invoke(app, ["rewrite", str(project)])
    assert again.exit_code == 0 and "rewrote 0 of" in again.output


def test_a_render_through_the_holders_attribute_is_a_gym_render(tmp_path: Path) -> None:
    """``session.world_env.render()`` in a driver that never names gym, the env made by a
    module of the run that imports legacy gym: a legacy "human" render, asked about where
    its make is (in another module), not missed."""
    project = _copy("project_holders", tmp_path)
    found = [f for f in _findings([project], tmp_path) if str(f["path"]).endswith("play.py")]
    assert [(f["rule"], f["kind"], f["line"]) for f in found] == [("GM402", "flag", 19)]


def test_an_attribute_read_through_the_holders_env_reads_through_the_wrappers(tmp_path: Path) -> None:
    """``session.world_env.lives_left`` where ``session`` is an instance of another module's
    plain holder that every construction of the run hands a Gym env (a wrapper stack): the
    read goes through ``get_wrapper_attr``, as forwarding did, not asked about."""
    project = _copy("project_holders", tmp_path)
    (project / "arcade" / "lives.py").write_text(
        "import gym\nfrom arcade import stacks\nfrom arcade.holder import Session\n\n\ndef lives(game_id):\n"
        "    session = Session(stacks.stack(stacks.make_game(game_id)))\n    session.first()\n"
        "    return session.world_env.lives_left, gym.__version__\n"
    )
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    assert 'session.world_env.get_wrapper_attr("lives_left")' in (project / "arcade" / "lives.py").read_text()


def test_the_env_of_another_modules_holder_is_made_where_its_construction_says(tmp_path: Path) -> None:
    """``coach.env.render()`` with ``coach = Coach(None, gym.make(...))``, ``Coach`` a plain class
    of another module holding its second parameter: the make is the second argument's (the
    first, ``None``, is the model), so it gets ``render_mode="human"``."""
    project = _copy("project_holders", tmp_path)
    (project / "arcade" / "coach.py").write_text(
        "class Coach:\n    def __init__(self, model, env):\n        self.model = model\n        self.env = env\n"
    )
    (project / "arcade" / "watch.py").write_text(
        "import gym\nfrom arcade.coach import Coach\n\ncoach = Coach(None, gym.make(\"CartPole-v1\"))\n"
        "for _ in range(3):\n    coach.env.render()\n"
    )
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    assert 'Coach(None, gym.make("CartPole-v1", render_mode="human"))' in (project / "arcade" / "watch.py").read_text()


def test_a_holder_one_caller_builds_with_a_project_object_is_asked_about(tmp_path: Path) -> None:
    """The same shape, where one construction passes the project's own (non-Gym) board:
    the attribute is not known to be a Gym env, so nothing on it is rewritten."""
    project = _copy("project_holders", tmp_path)
    (project / "arcade" / "board.py").write_text(
        "from arcade import holder\n\n\nclass Board:\n    def reset(self):\n        return 0\n\n    def step(self, action):\n"
        "        return 0, 0.0, True, {}\n\n\ndef new_env():\n    return Board()\n\n\ndef solo():\n"
        "    return holder.Session(new_env()).first()\n"
    )
    before = (project / "arcade" / "holder.py").read_bytes()
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    assert (project / "arcade" / "holder.py").read_bytes() == before


def test_a_class_imported_in_alternative_branches_gets_the_env_in_each(tmp_path: Path) -> None:
    """``fixtures/project_alternatives/``: ``train.py`` imports ``Learner`` from one module
    or the other by a condition, then ``Learner(gym.make(...), ...)``: each binding may be
    the class called, so both ``self.env`` are that env and both loops are rewritten. With a
    VecEnv passed instead, neither is: the same call feeds both."""
    project = _copy("project_alternatives", tmp_path)
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    greedy = (project / "learners" / "greedy.py").read_text()
    assert "obs, info = self.env.reset()" in greedy
    assert "following, reward, terminated, truncated, _ = self.env.step(action)" in greedy
    assert "_, reward, terminated, truncated, _ = self.env.step(" in (project / "learners" / "wander.py").read_text()
    again = runner.invoke(app, ["rewrite", str(project)])
    assert again.exit_code == 0 and "rewrote 0 of" in again.output

    vec = _copy("project_alternatives", tmp_path / "vec")
    script = vec / "train.py"
    script.write_text(
        script.read_text()
        .replace("import gym\n", "import gym\nfrom stable_baselines3.common.vec_env import DummyVecEnv\n")
        .replace('env = gym.make("CartPole-v1")', 'env = DummyVecEnv([lambda: gym.make("CartPole-v1")])')
    )
    learners = {name: (vec / "learners" / name).read_bytes() for name in ("greedy.py", "wander.py")}
    result = runner.invoke(app, ["rewrite", str(vec)])
    assert result.exit_code == 0, result.output
    assert {name: (vec / "learners" / name).read_bytes() for name in learners} == learners


def test_an_instance_of_an_env_class_a_caller_hands_in_is_a_gym_env(tmp_path: Path) -> None:
    """``fixtures/project_class_params/``: ``backtest(env_class=Exchange)`` builds
    ``env_class(quotes)`` and passes it to ``replay`` of another module: every call of
    ``backtest`` hands in the run's gym.Env subclass, so ``replay``'s loop is rewritten, as is
    ``smoke``'s on its own instance. With a plain class of the project handed in by a second
    call, ``replay`` is left alone."""
    project = _copy("project_class_params", tmp_path)
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    replay = (project / "markets" / "replay.py").read_text()
    assert "    obs, info = environment.reset()\n" in replay
    assert "obs, gain, terminated, truncated, _ = environment.step(policy(obs))" in replay
    assert "    obs, gain, terminated, truncated, _ = market.step(1)\n" in (project / "backtest.py").read_text()
    again = runner.invoke(app, ["rewrite", str(project)])
    assert again.exit_code == 0 and "rewrote 0 of" in again.output

    mixed = _copy("project_class_params", tmp_path / "mixed")
    (mixed / "markets" / "ledger.py").write_text(
        "class Ledger:\n    def __init__(self, quotes):\n        self.quotes = quotes\n\n    def reset(self):\n        return 0\n\n"
        "    def step(self, action):\n        return 0, 0.0, True, {}\n"
    )
    script = mixed / "backtest.py"
    script.write_text(
        script.read_text()
        .replace("from markets.replay", "from markets.ledger import Ledger\nfrom markets.replay")
        .replace("    print(backtest(", "    print(backtest(env_class=Ledger, quotes=[1.0]))\n    print(backtest(")
    )
    before = (mixed / "markets" / "replay.py").read_bytes()
    result = runner.invoke(app, ["rewrite", str(mixed)])
    assert result.exit_code == 0, result.output
    assert (mixed / "markets" / "replay.py").read_bytes() == before


def test_an_env_from_a_factory_that_makes_then_wraps_in_two_helpers_is_a_gym_env(tmp_path: Path) -> None:
    """``fixtures/project_wrap_steps/``: ``make_game`` calls ``raw`` (``gym.make``) and then
    ``dress``, which returns its argument, maybe in a Gym wrapper (``env = ScaleReward(env)``
    read back through itself); ``Player(env=make_game(...))`` in another module is that env
    and its seed/reset/step are rewritten. With ``dress`` wrapping in a class of an unknown
    package instead, nothing says what ``self.env`` is: left alone."""
    project = _copy("project_wrap_steps", tmp_path)
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    player = (project / "arcade" / "player.py").read_text()
    assert "frame, info = self.env.reset()" in player
    assert "frame, reward, terminated, truncated, _ = self.env.step(" in player
    again = runner.invoke(app, ["rewrite", str(project)])
    assert again.exit_code == 0 and "rewrote 0 of" in again.output

    plain = _copy("project_wrap_steps", tmp_path / "plain")
    build = plain / "arcade" / "build.py"
    build.write_text(
        build.read_text()
        .replace("import gym\n", "import gym\nfrom tapes import Recorder\n")
        .replace("env = ScaleReward(env)", "env = Recorder(env)")
    )
    before = (plain / "arcade" / "player.py").read_bytes()
    result = runner.invoke(app, ["rewrite", str(plain)])
    assert result.exit_code == 0, result.output
    assert (plain / "arcade" / "player.py").read_bytes() == before


def test_an_env_handed_to_an_instance_call_feeds_the_classes_call_method(tmp_path: Path) -> None:
    """``fixtures/project_callable_objects/``: ``judge = Judge(3)`` is passed to ``session``,
    which calls ``judge(env, ...)`` with a ``gym.make`` env: a call of an instance runs
    ``Judge.__call__`` in another module, whose loop is rewritten. Handed a VecEnv instead, it
    is left alone."""
    project = _copy("project_callable_objects", tmp_path)
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    judge = (project / "judge.py").read_text()
    assert "            seen, info = env.reset()\n" in judge
    assert "seen, reward, terminated, truncated, _ = env.step(pick(seen))" in judge
    again = runner.invoke(app, ["rewrite", str(project)])
    assert again.exit_code == 0 and "rewrote 0 of" in again.output

    vec = _copy("project_callable_objects", tmp_path / "vec")
    script = vec / "session.py"
    script.write_text(
        script.read_text()
        .replace("import gym\n", "import gym\nfrom stable_baselines3.common.vec_env import DummyVecEnv\n")
        .replace('env = gym.make("CartPole-v1")', 'env = DummyVecEnv([lambda: gym.make("CartPole-v1")])')
    )
    before = (vec / "judge.py").read_bytes()
    result = runner.invoke(app, ["rewrite", str(vec)])
    assert result.exit_code == 0, result.output
    assert (vec / "judge.py").read_bytes() == before


def test_a_registered_subclass_of_a_library_env_is_a_gym_env_where_it_is_constructed(tmp_path: Path) -> None:
    """``class Level(CoreEnv)`` of another package's base, registered by the package's
    ``__init__`` as an entry point: constructed directly in a test module, its step is a Gym
    env's (as ``make`` of its id is); a class nobody registers stays a question."""
    files = {
        "pkg/__init__.py": 'import gym\nfrom pkg.levels import Level\n\ngym.register(id="Level-v0", entry_point="pkg.levels:Level")\n',
        "pkg/levels.py": "from arcade_core import CoreEnv\n\n\nclass Level(CoreEnv):\n    pass\n\n\nclass Sandbox(CoreEnv):\n    pass\n",
        "pkg/test_levels.py": (
            "from pkg.levels import Level, Sandbox\n\n"
            "env = Level()\nobs, reward, done, info = env.step(0)\n"
            "box = Sandbox()\nobs, reward, done, info = box.step(0)\n"
        ),
    }
    facts = _join(files, tmp_path)
    assert facts.call_kinds[(str(tmp_path / "pkg/levels.py"), "Level")] is EnvKind.GYM_ENV
    assert facts.call_kinds[(str(tmp_path / "pkg/levels.py"), "Sandbox")] is EnvKind.UNKNOWN
    found = _findings([tmp_path / "pkg"], tmp_path)
    steps = sorted((f["line"], f["kind"]) for f in found if f["rule"] == "GM301" and str(f["path"]).endswith("test_levels.py"))
    assert steps == [(4, "auto"), (6, "flag")]


def test_a_notebook_with_outputs_past_a_modules_size_limit_still_counts_as_a_caller(tmp_path: Path) -> None:
    """A notebook whose file is over 1 MiB only because of its outputs (an image): its code
    cells are a few lines, so its calls still say what the helpers' parameters are. The
    ``gym.make`` env it hands ``play`` makes that loop certain; the project's own ``Pool``
    (its own four-value step) it hands ``collect`` leaves that loop alone, unasked."""
    (tmp_path / "helpers.py").write_text(
        "import numpy as np\n\n\nclass Pool:\n    def __init__(self, n):\n        self.n = n\n\n"
        "    def reset(self):\n        return np.zeros(self.n)\n\n"
        "    def step(self, actions):\n        return np.zeros(self.n), np.zeros(self.n), np.zeros(self.n, bool), {}\n\n\n"
        "def play(env):\n    env.reset()\n    obs, reward, over, _ = env.step(0)\n    return over\n\n\n"
        "def collect(pool):\n    pool.reset()\n    obs, reward, over, _ = pool.step([0] * pool.n)\n    return over\n"
    )
    picture = {"output_type": "display_data", "metadata": {}, "data": {"image/png": "A" * (1536 * 1024)}}
    cells = [
        "import gym\nimport helpers\n\nenv = gym.make('CartPole-v1')\n",
        "helpers.play(env)\n",
        "helpers.collect(helpers.Pool(2))\n",
    ]
    notebook = {
        "cells": [
            {"cell_type": "code", "execution_count": 1, "metadata": {}, "outputs": [picture] if i == 1 else [], "source": s}
            for i, s in enumerate(cells)
        ],
        "metadata": {"kernelspec": {"language": "python", "name": "python3", "display_name": "Python 3"}},
        "nbformat": 4,
        "nbformat_minor": 5,
    }
    (tmp_path / "run.ipynb").write_text(json.dumps(notebook, indent=1))
    assert (tmp_path / "run.ipynb").stat().st_size > 1024 * 1024
    found = _findings([tmp_path], tmp_path)
    assert [f for f in found if f["tier"] == "review" and f["rule"] != "GM302"] == []  # GM302: `return over`
    result = runner.invoke(app, ["rewrite", str(tmp_path)])
    assert result.exit_code == 0, result.output
    helpers = (tmp_path / "helpers.py").read_text()
    assert "obs, reward, terminated, truncated, _ = env.step(0)" in helpers
    assert "obs, reward, over, _ = pool.step([0] * pool.n)" in helpers


def test_a_def_called_through_a_star_import_knows_its_callers(tmp_path: Path) -> None:
    """``fixtures/project_star_callers``: ``train.py`` calls the helpers of ``stats.py``
    through ``from stats import *``. The helper given only a ``gym.make`` env is rewritten
    without a question; the one given only the project's own ``World`` is still asked
    about, as an explicit import would leave it."""
    project = _copy("project_star_callers", tmp_path)
    found = _findings([project], tmp_path)
    stats = sorted((f["line"], f["rule"], f["tier"]) for f in found if str(f["path"]).endswith("stats.py"))
    assert stats == [(4, "GM201", "note"), (7, "GM301", "note"), (16, "GM301", "review")]


def test_a_list_of_envs_handed_to_another_module_gives_its_items_kind(tmp_path: Path) -> None:
    """``fixtures/project_list_items``: ``agent.py`` hands ``collectors.py`` its lists of envs.
    Items of the project's own vector env class (step_async/step_wait) are left with no
    question; items made by ``gym.make`` are Gym envs, and their reset is rewritten."""
    project = _copy("project_list_items", tmp_path)
    found = _findings([project], tmp_path)
    resets = sorted((f["line"], f["tier"]) for f in found if str(f["path"]).endswith("collectors.py") and f["rule"] == "GM201")
    assert resets == [(15, "note")]


def test_a_table_of_creators_of_another_module_settles_what_a_lookup_makes(tmp_path: Path) -> None:
    """``fixtures/project_creator_tables``: ``pool.py`` calls through a closed table of
    ``registry.py`` whose every creator returns a ``make()`` result: its step and reset are
    rewritten, and what it reads through the wrapper stack goes through the stack. A table
    of the project's own env classes (``factory.py``) makes no Gym env: ``learner.py``'s reset
    is left, with no question. A table another module writes into (``extend.py`` fills
    ``plugins.py``'s) settles nothing: ``host.py``'s step stays a question."""
    project = _copy("project_creator_tables", tmp_path)
    found = _findings([project], tmp_path)
    rows = sorted((str(f["path"]).rsplit("/", 1)[1], f["line"], f["rule"], f["tier"]) for f in found if f["rule"] in ("GM201", "GM301", "GM604"))
    assert [r for r in rows if r[0] in ("pool.py", "learner.py", "host.py")] == [
        ("host.py", 9, "GM301", "review"),
        ("pool.py", 9, "GM301", "note"),
        ("pool.py", 11, "GM201", "note"),
        ("pool.py", 15, "GM604", "note"),
        ("pool.py", 16, "GM604", "note"),
        ("pool.py", 20, "GM604", "note"),
    ]
    runner.invoke(app, ["rewrite", str(project)])
    pool = (project / "pool.py").read_text()
    assert 'self.env.has_wrapper_attr("team_size")' in pool
    assert 'self.env.get_wrapper_attr("legal_moves")()' in pool


def test_a_class_handed_to_another_module_makes_what_every_caller_hands_in(tmp_path: Path) -> None:
    """``fixtures/project_passed_classes``: an agent's constructor takes an env class, hands it
    up to ``Agent.__init__`` of another module (which stores it on ``self.env_class``) and
    builds its env with ``self.env_class(...)``. Handed only the project's own env classes
    (through a table of agents, from a table of envs), the agent's reset and step are left with
    no question; handed only Gym env classes, they are rewritten; handed both, they stay a
    question."""
    project = _copy("project_passed_classes", tmp_path)
    found = _findings([project], tmp_path)
    rows = sorted(
        (str(f["path"]).rsplit("/", 1)[1], f["line"], f["rule"], f["tier"])
        for f in found
        if "/agents/" in str(f["path"]) and f["rule"] in ("GM201", "GM301")
    )
    assert rows == [
        ("mixed.py", 12, "GM201", "review"),
        ("mixed.py", 13, "GM301", "note"),
        ("player.py", 12, "GM201", "note"),
        ("player.py", 13, "GM301", "note"),
    ]
    walker = (project / "kit" / "agents" / "walker.py").read_bytes()
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    assert (project / "kit" / "agents" / "walker.py").read_bytes() == walker
    player = (project / "kit" / "agents" / "player.py").read_text()
    assert "obs, info = self.env.reset()" in player
    assert "obs, reward, terminated, truncated, info = self.env.step(0)" in player


def test_a_base_bound_only_by_a_star_import_of_the_run_is_bound_cycles_and_all_kept(tmp_path: Path) -> None:
    """``ProjectFacts.star_bindings``: a class base that only a star import binds stands for
    the name of that module (through its own star imports, a cycle of them followed once);
    a module's ``__all__`` decides what its star import binds."""
    facts = _join(
        {
            "pkg/a.py": "import gym\nfrom .b import *\n\n\nclass A(gym.Env):\n    pass\n",
            "pkg/b.py": "from .a import *\n\n\nclass B(A):\n    pass\n",
            "pkg/c.py": "from .b import *\n\n\nclass C(A):\n    pass\n",
            "pkg/d.py": "import gym\n\n__all__ = ['helper']\n\n\nclass Hidden(gym.Env):\n    pass\n\n\ndef helper():\n    return 1\n",
            "pkg/e.py": "from .d import *\n\n\nclass E(Hidden):\n    pass\n",
        },
        tmp_path,
    )
    root = os.path.realpath(tmp_path / "pkg")
    assert facts.star_bindings == {f"{root}/b.py": {"A": ".a.A"}, f"{root}/c.py": {"A": ".b.A"}}
