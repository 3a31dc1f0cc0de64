"""Facts across the files of one run (facts/project.py), end to end.

``fixtures/project/`` is a small package: ``agents/qagent.py`` steps an env it receives
as a parameter, ``train.py`` passes it ``gym.make(...)`` and builds the package's own
gym 0.9-style ``envs/corridor.py`` env and renders it with a mode, ``envs/drawn.py`` draws with gym's removed ``rendering.Viewer``.
One ``gymmigrate rewrite`` of the folder migrates it whole; the files checked alone keep
their cautious answer.
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
from gymmigrate.facts.project import ProjectFacts
from gymmigrate.facts.receivers import EnvKind
from gymmigrate.facts.summaries import summarize
from tests.fixture_cases import FIXTURES

PROJECT = FIXTURES / "project"
runner = CliRunner()


@pytest.fixture()
def project(tmp_path: Path) -> Path:
    target = tmp_path / "project"
    shutil.copytree(PROJECT, target)
    return target


def _findings(folder: Path, tmp_path: Path, *paths: str) -> list[dict[str, object]]:
    report = tmp_path / "report.json"
    runner.invoke(app, ["check", "--report", str(report), *(str(folder / p) for p in paths)])
    data = json.loads(report.read_text())
    return [dict(f, path=file["path"]) for file in data["files"] for f in [*file["review"], *file["notes"]]]


def test_one_rewrite_of_the_folder_migrates_the_package_and_it_trains(project: Path) -> None:
    result = runner.invoke(app, ["rewrite", str(project)])
    assert result.exit_code == 0, result.output
    agent = (project / "agents" / "qagent.py").read_text()
    assert "state, info = env.reset()" in agent
    assert "next_state, reward, terminated, truncated, info = env.step(action)" in agent
    assert 'CorridorEnv(render_mode="ansi")' in (project / "train.py").read_text()
    code = (
        "import train; print(train.train(episodes=1)); print(train.show_corridor())\n"
        "from gymnasium.utils.env_checker import check_env\nfrom envs.corridor import CorridorEnv\n"
        "check_env(CorridorEnv(render_mode='ansi'), skip_render_check=True); print('checked')"
    )
    run = subprocess.run([sys.executable, "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    lengths, frames, checked = run.stdout.splitlines()
    assert len(eval(lengths)) == 1 and eval(frames) == ["@....", ".@..."] and checked == "checked"


def test_the_agent_module_checked_alone_stays_cautious(project: Path, tmp_path: Path) -> None:
    alone = _findings(project, tmp_path, "agents/qagent.py")
    # The one question (GM201) also names the done read that chooses bootstrapping (GM302).
    assert {f["rule"] for f in alone} == {"GM201", "GM301", "GM302"}
    assert all(f["kind"] == "flag" for f in alone)
    together = _findings(project, tmp_path, ".")
    in_agent = [f for f in together if str(f["path"]).endswith("qagent.py")]
    # ``0.0 if done else gamma * max(q[next_state])``: a bootstrap the flag chooses (GM302)
    assert {(f["rule"], f["kind"]) for f in in_agent} == {("GM201", "auto"), ("GM301", "auto"), ("GM302", "assist")}


def test_a_viewer_gets_no_wrapper_attribute_finding(project: Path, tmp_path: Path) -> None:
    findings = _findings(project, tmp_path, ".")
    assert not [f for f in findings if f["rule"] in ("GM604", "GM606") and str(f["path"]).endswith("drawn.py")]


def test_a_vecenv_passed_through_an_unknown_owner_keeps_the_method_guarded(tmp_path: Path) -> None:
    agent = tmp_path / "agent.py"
    agent.write_text("class Agent:\n    def fit(self, env):\n        obs = env.reset()\n        return obs\n")
    gym_caller = tmp_path / "train.py"
    gym_caller.write_text("import gym\nfrom agent import Agent\n\nAgent().fit(gym.make('CartPole-v1'))\n")
    vec_caller = tmp_path / "vec.py"
    vec_caller.write_text(
        "from stable_baselines3.common.vec_env import DummyVecEnv\nimport gym\n\n"
        "def run(trainer):\n    trainer.fit(DummyVecEnv([lambda: gym.make('CartPole-v1')]))\n"
    )
    summaries = [summarize(str(p), p.read_text()) for p in (agent, gym_caller, vec_caller)]
    facts = ProjectFacts.join([s for s in summaries if s is not None])
    kinds = facts.view(str(agent)).param_kinds("Agent.fit", "env")
    assert EnvKind.GYM_ENV in kinds and EnvKind.SB3_VEC in kinds
    result = runner.invoke(app, ["rewrite", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert "obs = env.reset()" in agent.read_text()


def test_an_env_class_of_another_module_passed_to_a_function_is_a_gym_env(tmp_path: Path) -> None:
    (tmp_path / "grid.py").write_text(
        "import gym\n\n\nclass GridEnv(gym.Env):\n    def step(self, action):\n        return 0, 0.0, True, {}\n"
    )
    (tmp_path / "runner.py").write_text("def run(env):\n    obs, reward, done, info = env.step(0)\n    return done\n")
    (tmp_path / "main.py").write_text("from grid import GridEnv\nfrom runner import run\n\nrun(GridEnv())\n")
    result = runner.invoke(app, ["rewrite", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert "obs, reward, terminated, truncated, info = env.step(0)" in (tmp_path / "runner.py").read_text()


def test_run_facts_reach_the_worker_processes(project: Path) -> None:
    for index in range(16):  # enough files for the worker pool
        (project / f"filler_{index:02}.py").write_text("import gym\n\nENV_ID = 'CartPole-v1'\n")
    result = runner.invoke(app, ["rewrite", "--jobs", "2", str(project)])
    assert result.exit_code == 0, result.output
    assert "state, info = env.reset()" in (project / "agents" / "qagent.py").read_text()


def test_an_env_passed_on_through_a_parameter_keeps_its_kind(tmp_path: Path) -> None:
    """``lander.py`` defines ``demo(env)``; ``test_lander.py`` passes its own parameter on."""
    (tmp_path / "lander.py").write_text(
        "import gym\n\n\nclass Lander(gym.Env):\n    pass\n\n\n"
        "def demo(env):\n    obs = env.reset()\n    return obs\n\n\ndemo(Lander())\n"
    )
    (tmp_path / "test_lander.py").write_text(
        "from lander import Lander, demo\n\n\ndef check(env):\n    return demo(env)\n\n\ncheck(Lander())\n"
    )
    summaries = [summarize(str(p), p.read_text()) for p in sorted(tmp_path.glob("*.py"))]
    facts = ProjectFacts.join([s for s in summaries if s is not None])
    assert facts.view(str(tmp_path / "lander.py")).param_kinds("demo", "env") == [EnvKind.GYM_ENV]
    findings = _findings(tmp_path, tmp_path, ".")
    assert [(f["rule"], f["kind"]) for f in findings if f["rule"] == "GM201"] == [("GM201", "auto")]


def _run_main(folder: Path, module: str) -> object:
    code = f"import {module}; print({module}.main())"
    done = subprocess.run([sys.executable, "-c", code], cwd=folder, capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    return done.stdout.strip()


def test_seed_is_kept_while_another_module_of_the_run_may_call_it(tmp_path: Path) -> None:
    """``seed_all(envs)`` in train.py seeds objects it cannot trace, and imports Dice: the
    class keeps seed() (reported), so the migrated run raises no AttributeError."""
    folder = tmp_path / "dice"
    shutil.copytree(FIXTURES / "project_seed", folder)
    (folder / "play.py").unlink()
    result = runner.invoke(app, ["rewrite", str(folder)])
    assert result.exit_code == 0, result.output
    assert "def seed(self, seed=None):" in (folder / "envs.py").read_text()
    assert "seed() kept: another module of this run" in result.stderr
    first, second = eval(_run_main(folder, "train"))  # noqa: S307  (two seeded observations)
    assert first == second, "both dice were seeded with 3"


def test_a_projects_own_seed_method_seeds_made_envs_through_unwrapped(tmp_path: Path) -> None:
    """``Batch.seed()`` (a plain class's, not Gym's hook) seeds ``gym.make("Coin-v0")`` envs:
    Coin keeps its seed() for that call, which reaches it through ``.unwrapped`` (Gymnasium's
    wrappers have no seed); the id is registered for Coin, so it is certain (a note)."""
    folder = tmp_path / "coins"
    shutil.copytree(FIXTURES / "project_seed_made", folder)
    result = runner.invoke(app, ["rewrite", str(folder)])
    assert result.exit_code == 0, result.output
    assert "def seed(self, seed=None):" in (folder / "tasks.py").read_text()
    assert "env.unwrapped.seed(seed + i)" in (folder / "batch.py").read_text()
    assert "batch.py:14: GM203" not in result.stderr  # a note, not a question
    assert _run_main(folder, "batch") == "True"
    migrated = {path.name: path.read_bytes() for path in folder.glob("*.py")}
    assert runner.invoke(app, ["rewrite", str(folder)]).exit_code == 0
    assert {path.name: path.read_bytes() for path in folder.glob("*.py")} == migrated


def test_a_projects_own_seed_method_on_envs_of_any_id_is_rewritten_for_review(tmp_path: Path) -> None:
    """The same with an id the run cannot see (a parameter): rewritten, and the GM203 item
    stays (an env of another package seeds through reset(seed=...))."""
    folder = tmp_path / "coins"
    shutil.copytree(FIXTURES / "project_seed_made", folder)
    batch = folder / "batch.py"
    batch.write_text(
        batch.read_text()
        .replace("def __init__(self, size):", "def __init__(self, size, env_id):")
        .replace('gym.make("Coin-v0")', "gym.make(env_id)")
        .replace("Batch(3)", 'Batch(3, "Coin-v0")')
    )
    result = runner.invoke(app, ["rewrite", str(folder)])
    assert result.exit_code == 0, result.output
    assert "env.unwrapped.seed(seed + i)" in batch.read_text()
    assert "batch.py:14: GM203 (rewritten)" in result.stderr
    assert _run_main(folder, "batch") == "True"


def test_a_projects_own_seed_method_reseeds_its_made_envs_by_reset(tmp_path: Path) -> None:
    """``Batch.seed()`` of a plain class the project calls itself, over envs it makes, with no
    env class of the run keeping a seed(): each ``env.seed(s)`` becomes ``env.reset(seed=s)``
    (asked once: it also resets), and the migrated batch flips the same coins after the same
    seed, as legacy did."""
    folder = tmp_path / "coins"
    shutil.copytree(FIXTURES / "project_seed_made", folder)
    (folder / "tasks.py").unlink()
    batch = folder / "batch.py"
    batch.write_text(batch.read_text().replace("import tasks  # noqa: F401  (registers Coin-v0)\n", "").replace("Coin-v0", "CartPole-v1"))
    result = runner.invoke(app, ["rewrite", str(folder)])
    assert result.exit_code == 0, result.output
    assert "env.reset(seed=seed + i)" in batch.read_text()
    assert "this also resets `env`" in result.stderr
    code = (
        "import numpy as np, batch\nb = batch.Batch(3)\nb.seed(5)\nx = b.flips()\nb.seed(5)\n"
        "print(all(np.array_equal(p, q) for p, q in zip(x, b.flips())))"
    )
    done = subprocess.run([sys.executable, "-c", code], cwd=folder, capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "True"


def test_seed_goes_when_every_caller_in_the_run_is_migrated(tmp_path: Path) -> None:
    folder = tmp_path / "dice"
    shutil.copytree(FIXTURES / "project_seed", folder)
    (folder / "train.py").unlink()
    result = runner.invoke(app, ["rewrite", str(folder)])
    assert result.exit_code == 0, result.output
    assert "def seed" not in (folder / "envs.py").read_text()
    assert "env.reset(seed=3)" in (folder / "play.py").read_text()
    assert _run_main(folder, "play") == _run_main(folder, "play")


def test_render_mode_is_kept_while_another_module_of_the_run_may_pass_one(tmp_path: Path) -> None:
    """record.py renders objects it cannot trace with a mode and imports GridEnv: the class
    keeps an optional mode (``render(self, mode=None)``, else self.render_mode), and takes
    render_mode beside it, so show.py's ``GridEnv()`` is a creation site its render's mode
    moves to (it was an item asking for that by hand)."""
    folder = tmp_path / "grid"
    shutil.copytree(FIXTURES / "project_render", folder)
    result = runner.invoke(app, ["rewrite", str(folder)])
    assert result.exit_code == 0, result.output
    assert "def render(self, mode=None):" in (folder / "envs.py").read_text()
    show = (folder / "show.py").read_text()
    assert 'GridEnv(render_mode="rgb_array")' in show and "env.render().shape" in show
    assert "render_mode=" not in (folder / "record.py").read_text()
    assert _run_main(folder, "record") == "[(4, 4, 3), (4, 4, 3)]"
    assert _run_main(folder, "show") == "(4, 4, 3)"


def test_an_env_class_keeping_an_optional_mode_is_a_creation_site_across_modules(tmp_path: Path) -> None:
    """overhead.py renders an env it cannot trace with a mode and imports the package whose
    ``__init__`` re-exports TrackSim, LaneEnv (a subclass handing ``**kwargs`` on) and FixedSim.
    TrackSim keeps ``mode`` optional and takes render_mode, so drive.py's ``LaneEnv(...)``
    calls are creation sites: the bare render's "human" and the frame's "rgb_array" move there.
    FixedSim's ``render(mode, scale)`` cannot keep an optional mode: its construction gets none."""
    folder = tmp_path / "tracks"
    shutil.copytree(FIXTURES / "project_render_own_class", folder)
    result = runner.invoke(app, ["rewrite", str(folder)])
    assert result.exit_code == 0, result.output
    assert "def render(self, mode=None):" in (folder / "tracks" / "base.py").read_text()
    drive = (folder / "drive.py").read_text()
    assert 'LaneEnv(length=3, render_mode="human")' in drive
    assert 'LaneEnv(length=2, render_mode="rgb_array")' in drive and "frame = snap.render()" in drive
    assert "fixed = FixedSim()" in drive and 'fixed.render("rgb_array", 2)' in drive
    assert "def render(self, mode, scale):" in (folder / "tracks" / "fixed.py").read_text()
    assert _run_main(folder, "drive").splitlines() == ["lane at 1", "lane at 2", "((2, 2, 3), 'rgb_array x2')"]
    shown = subprocess.run(
        [sys.executable, "-c", "import overhead, tracks\ne = tracks.LaneEnv(length=2)\ne.reset()\nprint(overhead.show(e))"],
        cwd=folder, capture_output=True, text=True, check=False,
    )
    assert shown.stdout.strip() == "overhead 0", shown.stderr


def test_render_mode_moves_to_the_creation_site_when_every_caller_is_traced(tmp_path: Path) -> None:
    folder = tmp_path / "grid"
    shutil.copytree(FIXTURES / "project_render", folder)
    (folder / "record.py").unlink()
    result = runner.invoke(app, ["rewrite", str(folder)])
    assert result.exit_code == 0, result.output
    assert 'GridEnv(render_mode="rgb_array")' in (folder / "show.py").read_text()
    assert "def render(self):" in (folder / "envs.py").read_text()
    assert _run_main(folder, "show") == "(4, 4, 3)"


def test_a_module_left_as_it_is_keeps_its_importers_on_its_api(tmp_path: Path) -> None:
    """envs.py says skip-file: play.py must not be rewritten as if PairEnv had migrated
    (no render_mode= for a class that does not take it, no (obs, info) from its reset,
    its seed() kept), says so (GM002), and the pair still runs on Gymnasium 1.4."""
    folder = tmp_path / "pair"
    shutil.copytree(FIXTURES / "project_blocked", folder)
    legacy = _run_main(folder, "play")
    result = runner.invoke(app, ["rewrite", str(folder)])
    assert result.exit_code in (0, 1), result.output
    assert (folder / "envs.py").read_bytes() == (FIXTURES / "project_blocked" / "envs.py").read_bytes()
    assert (folder / "play.py").read_bytes() == (FIXTURES / "project_blocked" / "play.py").read_bytes()
    assert "GM002" in result.output and "envs.py" in result.output
    assert _run_main(folder, "play") == legacy


def test_a_refused_env_module_blocks_what_its_importers_would_assume(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The same when envs.py is refused (here: its rewrite fails): play.py is not migrated
    against the PairEnv it would have become."""
    from gymmigrate import process
    from gymmigrate.options import RewriteOptions
    from gymmigrate.process import Status
    from gymmigrate.runner import run_files
    from gymmigrate.source_text import TransformError

    folder = tmp_path / "pair"
    shutil.copytree(FIXTURES / "project_blocked", folder)
    envs = folder / "envs.py"
    envs.write_text(envs.read_text().replace("# gymmigrate: skip-file\n", "import gym  # legacy\n"))
    real = process.transform_source

    def refuse_envs(source: bytes, path: str = "<string>", options: RewriteOptions | None = None):
        if path.endswith("envs.py"):
            raise TransformError("the rewrite is not stable (a second run would change it again); file left unchanged")
        return real(source, path, options)

    monkeypatch.setattr(process, "transform_source", refuse_envs)
    results = {Path(r.path).name: r for r in run_files([envs, folder / "play.py"], RewriteOptions(), write=True, want_diff=False, jobs=1)}
    assert results["envs.py"].status is Status.ERROR
    assert results["play.py"].status is Status.UNCHANGED
    assert [f.rule for f in results["play.py"].findings if f.rule == "GM002"] == ["GM002"]
    assert "not stable" in next(f.message for f in results["play.py"].findings if f.rule == "GM002")


def test_a_seed_caller_the_run_rewrites_does_not_keep_seed_and_a_second_run_changes_nothing(tmp_path: Path) -> None:
    """worker.py seeds an env it cannot trace, in a file that makes Gym envs: GM203 makes
    that call reset(seed=3) in this run, so it is no seed() caller left. Counting it kept
    Dice.seed() in the first run and removed it in the second."""
    folder = tmp_path / "dice"
    shutil.copytree(FIXTURES / "project_seed_rewritten", folder)
    result = runner.invoke(app, ["rewrite", str(folder)])
    assert result.exit_code == 0, result.output
    assert "def seed" not in (folder / "envs.py").read_text()
    assert "env.reset(seed=3)" in (folder / "worker.py").read_text()
    migrated = {path.name: path.read_bytes() for path in folder.glob("*.py")}
    again = runner.invoke(app, ["rewrite", str(folder)])
    assert again.exit_code == 0, again.output
    assert {path.name: path.read_bytes() for path in folder.glob("*.py")} == migrated
    assert _run_main(folder, "worker") == _run_main(folder, "worker")


def _rewrite_twice(folder: Path) -> dict[str, bytes]:
    """One run, then a second that must change nothing; the files after the first."""
    result = runner.invoke(app, ["rewrite", str(folder)])
    assert result.exit_code == 0, result.output
    migrated = {path.name: path.read_bytes() for path in folder.glob("*.py")}
    again = runner.invoke(app, ["rewrite", str(folder)])
    assert again.exit_code == 0, again.output
    assert {path.name: path.read_bytes() for path in folder.glob("*.py")} == migrated
    return migrated


def test_a_seed_call_before_the_name_is_rewrapped_is_the_one_the_run_rewrites(tmp_path: Path) -> None:
    """worker.py seeds ``env = Dice()`` and only then rebinds ``env`` to a library wrapper:
    the seed call gets the Dice, and GM203 makes it reset(seed=...). Counting the name's
    every binding made it an untraced seed() caller, kept Dice.seed() in the first run and
    removed it in the second."""
    folder = tmp_path / "dice"
    shutil.copytree(FIXTURES / "project_seed_rewrapped", folder)
    migrated = _rewrite_twice(folder)
    assert b"def seed" not in migrated["envs.py"]
    assert b"env.reset(seed=seed)" in migrated["worker.py"]


def test_a_seed_call_after_an_untraced_rewrap_still_keeps_seed(tmp_path: Path) -> None:
    """The same names, but the seed call comes after ``env = wrap(env)`` with a callable
    the run cannot see into: it may reach Dice.seed(), so the class keeps it, in both runs."""
    folder = tmp_path / "dice"
    shutil.copytree(FIXTURES / "project_seed_rewrapped", folder)
    worker = folder / "worker.py"
    worker.write_text(
        worker.read_text()
        .replace("def make_env(seed, log_dir):", "def make_env(seed, wrap):")
        .replace("        env.seed(seed)\n        env = Monitor(env, log_dir)\n", "        env = wrap(env)\n        env.seed(seed)\n")
        .replace("        return env\n", "        return Monitor(env)\n")
    )
    assert "env = wrap(env)\n        env.seed(seed)" in worker.read_text()
    migrated = _rewrite_twice(folder)
    assert b"def seed(self, seed=None):" in migrated["envs.py"]
    assert b"env.seed(seed)" in migrated["worker.py"]


def test_render_mode_is_kept_while_a_gym_env_of_another_module_is_rendered_with_a_mode_left(tmp_path: Path) -> None:
    """snap.py renders a Gym env (a parameter annotated ``gym.Env``) with a mode that is no
    literal: the rendering rules cannot move it and leave the call passing it, so GridEnv,
    which snap.py imports, keeps an optional mode and the call still works after the run."""
    folder = tmp_path / "grid"
    shutil.copytree(FIXTURES / "project_render", folder)
    (folder / "record.py").unlink()
    (folder / "snap.py").write_text(
        "import gym\n\nfrom envs import GridEnv\n\n\ndef snapshot(env: gym.Env, mode):\n    return env.render(mode=mode)\n\n\n"
        "def main():\n    env = GridEnv()\n    env.reset()\n    return snapshot(env, \"rgb_array\").shape\n"
    )
    result = runner.invoke(app, ["rewrite", str(folder)])
    assert result.exit_code == 0, result.output
    assert "def render(self, mode=None):" in (folder / "envs.py").read_text()
    assert _run_main(folder, "snap") == "(4, 4, 3)"
    assert _run_main(folder, "show") == "(4, 4, 3)"


def test_a_test_parametrized_over_another_modules_spec_list_makes_envs_in_the_render_mode(tmp_path: Path) -> None:
    """``@pytest.mark.parametrize("spec", SPECS)`` with SPECS imported from a module of the
    run that binds it to registry specs: ``spec.make()`` is a creation site, and a mode that
    loops with the make moves to it."""
    (tmp_path / "specs.py").write_text(
        "import gym\n\nSPECS = [s for s in gym.envs.registry.values() if s.id == \"FrozenLake-v1\"]\n"
    )
    (tmp_path / "check.py").write_text(
        "import pytest\n\nfrom specs import SPECS\n\n\n@pytest.mark.parametrize(\"spec\", SPECS)\ndef test_modes(spec):\n"
        "    shots = []\n    for mode in (\"ansi\", \"rgb_array\"):\n        env = spec.make()\n        env.reset()\n"
        "        shots.append(env.render(mode=mode))\n    return shots\n\n\n"
        "def main():\n    text, frame = test_modes(SPECS[0])\n    return type(text).__name__, frame.ndim\n"
    )
    result = runner.invoke(app, ["rewrite", str(tmp_path)])
    assert result.exit_code == 0, result.output
    migrated = (tmp_path / "check.py").read_text()
    assert "env = spec.make(render_mode=mode)" in migrated and "env.render()" in migrated
    assert _run_main(tmp_path, "check") == "('str', 3)"


def test_a_bare_render_in_a_module_without_gym_is_reported_when_the_run_proves_the_env(tmp_path: Path) -> None:
    """rollout.py never names gym, but steps the env train.py makes the legacy way: its bare
    render() needs render_mode="human" at that make, which is in another module (GM402)."""
    folder = tmp_path / "rollout"
    shutil.copytree(FIXTURES / "project_render_elsewhere", folder)
    result = runner.invoke(app, ["check", str(folder)])
    assert "rollout.py:11:13: GM402 [flag]" in result.output, result.output
    result = runner.invoke(app, ["rewrite", str(folder)])
    assert result.exit_code == 0, result.output
    assert "state, reward, terminated, truncated, _ = env.step(" in (folder / "rollout.py").read_text()
    assert "env.render()" in (folder / "rollout.py").read_text()
    float(_run_main(folder, "train"))  # runs on Gymnasium 1.4 and prints the return


def test_a_helper_of_the_run_that_only_wraps_leads_the_recorder_to_the_make(tmp_path: Path) -> None:
    """``env = shape(env)`` with ``shape`` in another module returning its argument in Gym
    wrappers: the env was made by the ``gym.make`` before it, which gets the recorder's mode."""
    folder = tmp_path / "wrap"
    shutil.copytree(FIXTURES / "project_wrap_helper", folder)
    result = runner.invoke(app, ["rewrite", str(folder)])
    assert result.exit_code == 0, result.output
    assert 'gym.make("CartPole-v1", render_mode="rgb_array")' in (folder / "film.py").read_text()
    assert "Review" not in result.output, result.output


def test_reads_through_a_helper_of_the_run_that_wraps_its_argument(tmp_path: Path) -> None:
    """``self.env = dressing.dress(env=gym.make(id))``, by keyword or position, with ``dress``
    in another module returning its argument in Gym wrappers: a wrapper stack, so a read of
    what a layer defines goes through get_wrapper_attr; a def that returns something else
    settles nothing."""
    folder = tmp_path / "wrapped"
    shutil.copytree(FIXTURES / "project_wrapped_reads", folder)
    result = runner.invoke(app, ["rewrite", str(folder)])
    assert result.exit_code == 0, result.output
    lines = (folder / "task.py").read_text().splitlines()
    assert lines[10].strip() == 'return self.env.get_wrapper_attr("kept")'
    assert lines[18].strip() == 'return self.env.get_wrapper_attr("kept")'
    assert lines[26].strip() == "return self.env.kept"
