"""Rendering keeps its schedule, executed: the migrated scripts run against Gymnasium.

``gymnasium.make`` is wrapped to record the render mode each env is made with (a
"human" env would open a window, so the wrapper makes it without one and records it).
"""

from __future__ import annotations

import sys

import gymnasium
import pytest

from gymmigrate.engine import transform_source
from tests.fixture_cases import RULE_FIXTURES


@pytest.fixture
def made_modes(monkeypatch) -> list[object]:
    modes: list[object] = []
    real_make = gymnasium.make

    def make(env_id, **kwargs):
        modes.append(kwargs.pop("render_mode", None))
        return real_make(env_id, **kwargs)

    monkeypatch.setattr(gymnasium, "make", make)
    return modes


def run_migrated(rule: str, case: str, monkeypatch, argv: list[str] | None = None) -> dict[str, object]:
    path = RULE_FIXTURES / rule / f"{case}.py"
    rewritten = transform_source(path.read_bytes(), str(path)).rewritten
    monkeypatch.setattr(sys, "argv", ["script", *(argv or [])])
    namespace: dict[str, object] = {"__name__": f"migrated_{case}"}
    exec(compile(rewritten, str(path), "exec"), namespace)  # noqa: S102 (our own fixture)
    return namespace


def test_only_worker_zero_renders(made_modes, monkeypatch) -> None:
    module = run_migrated("GM402", "render_in_worker_zero", monkeypatch)
    module["worker"](1, steps=5)
    module["worker"](0, steps=5)
    assert made_modes == [None, "human"], "worker 1 draws nothing, worker 0 draws as before"


def test_render_behind_a_flag_keeps_the_flag(made_modes, monkeypatch) -> None:
    run_migrated("GM401", "render_behind_flag", monkeypatch)
    run_migrated("GM401", "render_behind_flag", monkeypatch, ["--render"])
    assert made_modes == [None, "human"]


def test_render_on_a_step_schedule_is_not_made_human(made_modes, monkeypatch) -> None:
    with pytest.warns(UserWarning, match="render_mode"):  # Gymnasium: render() without a mode
        run_migrated("GM402", "render_on_step_schedule", monkeypatch)
    assert made_modes == [None], "the make is left as it was and the site is reported"


def test_render_in_an_else_branch_gets_the_negated_condition(made_modes, monkeypatch) -> None:
    module = run_migrated("GM402", "render_in_else_branch", monkeypatch)
    module["run"](True, episodes=1)
    module["run_or"](True)
    assert made_modes == [None, None], "quiet / skip_render: nothing draws, as before"
    with pytest.warns(UserWarning):  # the stand-in make drops "human"; render() then warns
        module["run"](False, episodes=1)
        module["run_or"](False)
    assert made_modes[2:] == ["human", "human"]


def test_render_mode_on_a_step_schedule_loses_its_mode_but_no_human_mode(made_modes, monkeypatch) -> None:
    with pytest.warns(UserWarning, match="render_mode"):  # render() without a mode: no TypeError
        run_migrated("GM401", "render_mode_on_step_schedule", monkeypatch)
    assert made_modes == [None]


def test_a_mode_from_a_loop_or_a_parameter_moves_to_the_make(monkeypatch) -> None:
    """``for mode in modes: env = make(...); env.render(mode=mode)``: each env is made in the
    loop's mode, so render() gives what render(mode=mode) gave; the same for a parameter."""
    module = run_migrated("GM401", "mode_from_loop", monkeypatch)
    frame, text = module["frames"]("FrozenLake-v1")
    assert frame.shape[2] == 3 and isinstance(text, str) and "S" in text
    assert isinstance(module["frame"]("FrozenLake-v1", mode="ansi"), str)
    assert module["frame"]("FrozenLake-v1").ndim == 3


def test_an_env_spec_of_the_registry_makes_its_env_in_the_render_mode(monkeypatch) -> None:
    """``spec.make()`` on one of the registry's specs (a loop over it, or a test parametrized
    over a list of them) is a creation site: the mode moves there and render() gives frames."""
    module = run_migrated("GM401", "spec_make", monkeypatch)
    shots = module["frames"]()
    assert len(shots) == 1 and shots[0].ndim == 3
    for spec in module["SPECS"]:
        module["test_frame"](spec)
