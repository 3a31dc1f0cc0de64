"""Method contracts follow their class (rules/custom_env/hooks.py, render.py), end to end.

``fixtures/project_contracts/`` is a small package: ``CoreEnv`` resets through a hook
(``first_observation``) a subclass in another module overrides, and steps through a hook
(``post_step``) a subclass in the same module overrides; ``BoardEnv`` asks its own
``render`` for a mode, and ``FramedBoardEnv`` overrides that render. ``play.py`` uses
them the legacy way. Before this change the migrated package raised ``ValueError`` (four
values from the override), and ``FramedBoardEnv().snapshot()`` silently skipped the
override (the base's own ``self.render(mode)`` went to a helper of the base's old body);
earlier still, that call raised ``TypeError``. ``project_hooks_elsewhere`` has the step
hook overridden in another module: the override follows the base when its returns can
(facts/step_hooks.py); else nothing of the hook changes, it is reported.
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


def _copy(tmp_path: Path, name: str) -> Path:
    target = tmp_path / name
    shutil.copytree(FIXTURES / name, target)
    return target


def test_hooks_and_render_follow_their_class_and_the_package_runs(tmp_path: Path) -> None:
    project = _copy(tmp_path, "project_contracts")
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    core = (project / "envs" / "core.py").read_text()
    assert 'return obs, 1.0, bool(self.pos >= 3), False, {"bonus": True}' in core  # the override, with its base
    assert "return self.first_observation(), {}" in core  # an overridden reset hook is wrapped, not followed
    assert 'def render(self, mode="human"):' in (project / "envs" / "board.py").read_text()
    code = (
        "import play\nprint(play.play_bonus())\nprint(play.first_noisy())\nprint(play.board_snapshot())\n"
        "print(play.framed_snapshot())\n"
        "from gymnasium.utils.env_checker import check_env\nfrom envs.core import BonusEnv, CoreEnv\n"
        "from envs.noisy import NoisyEnv\nfor cls in (CoreEnv, BonusEnv, NoisyEnv):\n    check_env(cls())\nprint('checked')"
    )
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    bonus, noisy, board, framed, checked = run.stdout.splitlines()
    assert bonus == "(3.0, [3.0], {'bonus': True})"
    assert noisy == "[1.0]" and board == "board at 1" and framed == "[board at 0]" and checked == "checked"


def test_a_hook_overridden_in_another_module_follows_its_base(tmp_path: Path) -> None:
    """The override in ``far.py`` returns a four-value literal: it takes five values with
    the base's hook (an override that cannot is ``project_hooks_reexported_kept``)."""
    project = _copy(tmp_path, "project_hooks_elsewhere")
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    assert "return obs, 0.0, bool(self.pos >= 3), False, {}" in (project / "envs" / "core.py").read_text()
    assert "return obs, 2.0, bool(self.pos >= 5), False, {}" in (project / "envs" / "far.py").read_text()
    code = "from envs.far import FarEnv\nenv = FarEnv()\nprint([env.step(1)[1:4] for _ in range(5)][-1])"
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0 and run.stdout.strip() == "(2.0, True, False)", run.stderr


def test_hooks_and_wrappers_of_a_base_in_another_module(tmp_path: Path) -> None:
    """``project_step_hooks``, the shape of a task library: ``PhaseEnv.step`` (re-exported by
    ``tasks/__init__.py``) runs the ``_step`` that ``HoldTask`` (``class HoldTask(tasks.PhaseEnv)``,
    another module) and its subclass define; ``PhaseEnv.reset`` steps through ``self._top``,
    the env itself or the wrapper that ``PhaseWrapper.__init__`` registers with
    ``self.unwrapped.set_top(self)``; ``BonusWrapper(tasks.PhaseWrapper)`` reads a method of the
    env it wraps. Before: the ``_step`` were renamed ``step`` as gym < 0.9 methods and overrode
    the base's step (``play_hold`` looped for ever), ``self._top.step`` kept four fields (a
    ValueError in every reset), and ``self.env.bonus()`` was left to forwarding that
    Gymnasium 1.x removed (an AttributeError under any wrapper). ``CoinEnv``, a gym 0.7 env of
    the same run, still has its ``_step`` renamed."""
    project = _copy(tmp_path, "project_step_hooks")
    before = (project / "tasks" / "hold.py").read_text()
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    assert (project / "tasks" / "hold.py").read_text() == before
    assert "def step(self, action):" in (project / "tasks" / "coin.py").read_text()
    assert "obs, _, _, _, _ = self._top.step(0)" in (project / "tasks" / "core.py").read_text()
    assert 'self.env.get_wrapper_attr("bonus")()' in (project / "tasks" / "wrappers.py").read_text()
    code = (
        "import play\nprint(play.play_hold(), play.play_bonus(), play.play_coin())\n"
        "from gymnasium.utils.env_checker import check_env\nfrom gymnasium.wrappers import TimeLimit\n"
        "from tasks.hold import HoldTask, LongHoldTask\nfrom tasks.wrappers import BonusWrapper\n"
        "for cls in (HoldTask, LongHoldTask):\n    check_env(cls())\n"
        "env = BonusWrapper(TimeLimit(LongHoldTask(), 10))\nenv.reset(seed=0)\nprint(env.step(0)[1:])"
    )
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.splitlines() == ["(2.0, 3) (2.0, 2) (1.0, True)", "(2.0, False, False, {'phase': 2})"]


def test_an_env_holding_a_gym_env_returns_its_reset_and_step_as_they_are() -> None:
    """``return self.env.reset()`` is (obs, info) once the held env is Gymnasium's: not
    wrapped in a second pair (which also made the rewrite unstable); it gets the seed."""
    import importlib.util

    from gymnasium.utils.env_checker import check_env

    path = FIXTURES / "rules" / "GM501" / "holds_gym_env.expected.py"
    spec = importlib.util.spec_from_file_location("holds_gym_env", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    env = module.HolderEnv()
    obs, info = env.reset(seed=3)
    assert obs.shape == (4,) and isinstance(info, dict)
    assert len(env.step(0)) == 5
    check_env(env, skip_render_check=True)  # deterministic: the seed reaches the held env


def test_a_hook_of_a_reexported_base_is_followed_by_its_overrides_elsewhere(tmp_path: Path) -> None:
    """``project_hooks_reexported``: ``PhaseEnv.step`` returns ``self.post_step(...)``;
    ``class DoubledTask(trials.PhaseEnv)`` (``trials/__init__.py`` re-exports the class of
    ``trials/core.py``) overrides the hook with four values, its subclass returns
    ``super().post_step(...)``. Before: the re-export hid the override, the base's hook
    returned five values and the override four (``not enough values to unpack``). Now every
    override follows the base; ``..._kept``, an override that returns a name, keeps them all
    and reports the base's step."""
    project = _copy(tmp_path, "project_hooks_reexported")
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    assert "return obs, reward, done, False, info" in (project / "trials" / "tasks.py").read_text()
    assert "return super().post_step(obs, reward, done, info)" in (project / "trials" / "tasks.py").read_text()
    code = (
        "from gymnasium.utils.env_checker import check_env\nfrom trials.tasks import DoubledTask, LabelledTask\n"
        "for cls in (DoubledTask, LabelledTask):\n    check_env(cls())\n"
        "env = LabelledTask()\nenv.reset(seed=0)\nprint(env.step(1)[1:])"
    )
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.splitlines() == ["(1.0, False, False, {'label': 'x'})"]

    kept = _copy(tmp_path, "project_hooks_reexported_kept")
    before = (kept / "trials" / "tasks.py").read_text()
    report = tmp_path / "report.json"
    result = runner.invoke(app, ["rewrite", "--report", str(report), str(kept)])
    assert result.exit_code == 0, result.output
    assert "return obs, reward, done, info" in (kept / "trials" / "core.py").read_text()
    assert (kept / "trials" / "tasks.py").read_text() == before
    review = [f for file in json.loads(report.read_text())["files"] for f in file["review"]]
    assert any(f["rule"] == "GM504" and "tasks.py:ClippedTask" in f["message"] for f in review), review


def test_a_hook_only_subclasses_elsewhere_define_follows_the_step(tmp_path: Path) -> None:
    """``OldStyleEnv.step`` only returns ``self._step(...)``, which it does not define; the
    subclass in ``hopper.py`` does: its returns take five values, the base's step is left
    (a note, no question)."""
    project = _copy(tmp_path, "project_hook_absent_in_base")
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    assert "return self._step(*args, **kwargs)" in (project / "envs" / "base.py").read_text()
    assert "1.0, bool(self.height < 0), False, {}" in (project / "envs" / "hopper.py").read_text()
    assert "base.py:12: GM504" not in result.output  # the pass-through asks nothing
    code = (
        "import gymnasium as gym\nfrom envs.hopper import HopEnv\ngym.register('Hop-v0', entry_point=HopEnv)\n"
        "env = gym.make('Hop-v0')\nenv.reset(seed=1)\nprint(env.step(1)[1:4], env.step(0)[1:4], env.step(0)[1:4])"
    )
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0 and run.stdout.strip() == "(1.0, False, False) (1.0, False, False) (1.0, True, False)", run.stderr + run.stdout


def test_a_generator_handed_to_a_class_of_another_module_gets_its_api(tmp_path: Path) -> None:
    """``WalkerEnv.seed`` hands its ``seeding.np_random`` Generator to ``Legs`` (legs.py),
    which never sets np_random itself: its ``randint`` becomes ``integers`` (before, legs.py
    was left and the first reset raised AttributeError)."""
    project = _copy(tmp_path, "project_rng_handed_over")
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    assert "return int(self.np_random.integers(4))" in (project / "envs" / "legs.py").read_text()
    code = (
        "from envs.walker import WalkerEnv\nenv = WalkerEnv()\na = env.reset(seed=3)\nb = env.reset(seed=3)\n"
        "print(a == b, env.step(0)[2:4])"
    )
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0 and run.stdout.strip() == "True (False, False)", run.stderr + run.stdout


def test_a_step_helper_another_module_calls_keeps_its_four_values(tmp_path: Path) -> None:
    """``project_helper_callers``: ``KartEnv.step`` returns ``self.shape(...)``, and
    ``drive.py`` calls ``env.shape(...)`` itself on an instance it asserts is a ``KartEnv``,
    unpacking four values. Before, the helper was widened to five and that unpack raised
    ValueError; now step unpacks the helper's four values and builds the five itself."""
    project = _copy(tmp_path, "project_helper_callers")
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    kart = (project / "envs" / "kart.py").read_text()
    assert "return obs, reward, done, info" in kart and "return obs, reward, terminated, False, info" in kart
    code = "import drive\nprint(drive.drive())"
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "(0.5, False, 0.0)"


def test_a_proxy_of_the_project_is_migrated_with_its_env_or_asked_about(tmp_path: Path) -> None:
    """``project_proxy_holders``: ``StepLogger`` (a plain class, ``super(StepLogger,
    self).__init__()``) forwards reset and step to the env it holds, and its one construction
    passes a ``CarEnv`` the run migrates, through ``env = StepLogger(env)``: it is migrated
    with that env. ``Driver`` holds a ``StepLogger`` in one module and an SB3 VecEnv in
    another: its calls are asked about, not left in silence as a VecEnv's. The run proves
    ``StepLogger`` a Gym env, so ``play.py``, which steps one, is migrated with it."""
    project = _copy(tmp_path, "project_proxy_holders")
    before = (project / "driver.py").read_text()
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    assert "obs, reward, terminated, truncated, info = self.env.step(action)" in (project / "logger.py").read_text()
    assert (project / "driver.py").read_text() == before
    assert "driver.py:13: GM201" in result.output and "a Gym env at some sites and a VecEnv" in result.output
    assert "obs, info = env.reset()" in (project / "play.py").read_text()


_LIBRARY_RUNNER = """from stable_baselines import PPO2
from stable_baselines.common.runners import AbstractEnvRunner


class Runner(AbstractEnvRunner):
    def __init__(self, *, env, model, n_steps):
        super().__init__(env=env, model=model, n_steps=n_steps)


class TunedPPO(PPO2):
    def make_runner(self):
        return Runner(env=self.env, model=self, n_steps=self.n_steps)
"""


def test_a_library_base_init_call_hands_its_vec_env_to_no_class_of_the_run(tmp_path: Path) -> None:
    """``runner.py`` subclasses a library algorithm and runner: the runner's
    ``super().__init__(env=env)`` gets the algorithm's VecEnv and reaches the library's
    ``__init__``. Taken as a call of an unknown owner's ``__init__``, it handed that VecEnv
    to every ``__init__`` of the run, StepLogger's among them, which was then left alone
    without a word: it is migrated with its env, as without the runner."""
    project = _copy(tmp_path, "project_proxy_holders")
    (project / "runner.py").write_text(_LIBRARY_RUNNER)
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    assert "obs, reward, terminated, truncated, info = self.env.step(action)" in (project / "logger.py").read_text()
    assert "driver.py:13: GM201" in result.output and "a Gym env at some sites and a VecEnv" in result.output


def test_a_run_base_init_call_still_hands_its_vec_env_to_that_base(tmp_path: Path) -> None:
    """The same runner on a base of the run (``BaseRunner`` storing ``self.env``): its
    ``super().__init__`` reaches that base, which gets the VecEnv and keeps the legacy
    calls; StepLogger, never handed it, is still migrated."""
    project = _copy(tmp_path, "project_proxy_holders")
    (project / "base_runner.py").write_text(
        "class BaseRunner(object):\n    def __init__(self, *, env, model, n_steps):\n        self.env = env\n\n"
        "    def run(self):\n        obs, reward, done, info = self.env.step(None)\n        return obs\n"
    )
    (project / "runner.py").write_text(
        _LIBRARY_RUNNER.replace("from stable_baselines.common.runners import AbstractEnvRunner", "from base_runner import BaseRunner").replace(
            "Runner(AbstractEnvRunner)", "Runner(BaseRunner)"
        )
    )
    before = (project / "base_runner.py").read_text()
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    assert (project / "base_runner.py").read_text() == before
    assert "base_runner.py" not in result.output  # a VecEnv's step, known: nothing to ask
    assert "obs, reward, terminated, truncated, info = self.env.step(action)" in (project / "logger.py").read_text()


_COURT_MODULE = '''import gym
import numpy as np
from gym.utils import seeding
from scenelib import BaseScene


class {name}(BaseScene):
    def serve(self):
        return self.np_random.randint(2)


class {name}Env(gym.Env):
    def __init__(self):
        self.action_space = gym.spaces.Discrete(2)
        self.observation_space = gym.spaces.Box(0, 1, (2,))
        self.seed()

    def seed(self, seed=None):
        self.np_random, seed = seeding.np_random(seed)
        return [seed]

    def build(self):{pad}
        scene = {name}()
        scene.np_random = self.np_random
        return scene

    def reset(self):
        self.build().serve()
        return np.zeros(2)

    def step(self, action):
        return np.zeros(2), 0.0, False, {{}}
'''


def test_a_class_handed_a_generator_right_after_it_is_built_cites_its_own_module(tmp_path: Path) -> None:
    """Two modules each build their scene (whose unread base might set a RandomState) and
    hand it the env's Generator in the next statement: each randint -> integers is a note
    (the base's value is replaced before any draw) citing the handover of its own module,
    never a line of the other file."""
    (tmp_path / "a.py").write_text(_COURT_MODULE.format(name="Hockey", pad=""))
    (tmp_path / "b.py").write_text(_COURT_MODULE.format(name="Pong", pad="\n        self.built = True"))
    result = runner.invoke(app, ["check", "--output-format", "json", str(tmp_path)])
    findings = [f for f in json.loads(result.stdout) if f["rule"] == "GM505" and "integers" in f["message"]]
    assert sorted((Path(f["path"]).name, f["tier"]) for f in findings) == [("a.py", "note"), ("b.py", "note")], findings
    by_file = {Path(f["path"]).name: f["message"] for f in findings}
    assert "(line 24)" in by_file["a.py"] and "(line 25)" in by_file["b.py"], by_file
