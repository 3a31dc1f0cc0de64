"""Atari ids and envs through the project's own helpers, in a run of several modules.

``fixtures/project_atari_helpers``: ``games/factory.py`` makes an env from a parameter id
and asserts it is a ``NoFrameskip`` game; its other helpers return their argument in the
module's Gym wrappers. The scripts hand the factory an Atari id as a literal, through a
name rebound from another id, and build the env over separate assignments.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_atari_helpers"
runner = CliRunner()


@pytest.fixture(scope="module")
def findings(tmp_path_factory: pytest.TempPathFactory) -> list[dict]:
    run = tmp_path_factory.mktemp("atari") / "run"
    shutil.copytree(FIXTURE, run)
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code == 1
    return [{**f, "path": Path(f["path"]).relative_to(run).as_posix()} for f in json.loads(result.stdout)]


def _of(findings: list[dict], path: str, rule: str) -> list[tuple[int, str]]:
    return [(f["line"], f["kind"]) for f in findings if f["path"] == path and f["rule"] == rule]


def test_the_factory_that_asserts_an_atari_game_registers_ale_py(findings: list[dict]) -> None:
    assert _of(findings, "games/factory.py", "GM106") == [(16, "auto")]


def test_a_literal_handed_to_the_factory_from_a_file_without_gym_is_reported(findings: list[dict]) -> None:
    assert _of(findings, "play_literal.py", "GM106") == [(3, "flag")]


def test_an_id_rebound_before_the_factory_call_is_the_one_that_reaches_it(findings: list[dict]) -> None:
    assert _of(findings, "play_rebound.py", "GM106") == [(8, "auto")]


def test_an_env_rebound_through_the_projects_wrapping_helpers_stays_a_gym_env(findings: list[dict]) -> None:
    assert _of(findings, "play_chain.py", "GM201") == [(7, "auto")]
    assert _of(findings, "play_chain.py", "GM301") == [(8, "auto")]


def test_a_helper_that_may_return_something_else_is_not_followed() -> None:
    from gymmigrate.engine import lint_source

    source = b"""import gym

def maybe(env, other):
    if other is not None:
        return other
    return env

env = gym.make("CartPole-v1")
env = maybe(env, object())
obs = env.reset()
"""
    found, _ = lint_source(source, "maybe.py")
    assert [(f.rule, f.kind.value) for f in found if f.rule == "GM201"] != [("GM201", "auto")]


def test_an_id_read_off_an_object_handed_to_another_modules_atari_wrapper_registers_ale_py(findings: list[dict]) -> None:
    # ``game = settings.game; env = gym.make(game); env = arcade_stack(env)``: the wrapper of
    # games/lives.py asserts the Atari action meanings, so the make needs ale_py whatever id
    assert _of(findings, "setup_from_config.py", "GM106") == [(8, "auto")]
