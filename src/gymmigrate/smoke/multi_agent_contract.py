"""The PettingZoo API contract, checked on what every layer of a script's env returns.

``multi_agent_probe`` calls ``check_call`` after each wrapped ``reset``, ``step`` and
``last``; a violation goes to the Gym observer's ``_charge``, which keeps the first one
of a call chain (the innermost layer where it shows). The check names are the Gym
ones, so a PettingZoo script and a Gym script report alike.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from gymmigrate.smoke.probe import (
    FLAGS_ARE_BOOL,
    OBS_IN_SPACE,
    RESET_SIGNATURE,
    STEP_SIGNATURE,
    _describe,
)

AEC, PARALLEL = "aec", "parallel"
Charge = Callable[[str, str], None]


def check_call(env: Any, name: str, api: str, result: object, charge: Charge) -> None:
    """Check what one call on one layer returned; ``charge(check, message)`` records a violation."""
    layer = type(env).__name__
    if name == "reset" and api == AEC:
        if result is not None:
            charge(
                RESET_SIGNATURE,
                f"{layer}.reset() returned {_describe(result)}: an AEC reset() returns None "
                "(the script reads observations with last())",
            )
    elif name == "reset":
        if not (isinstance(result, tuple) and len(result) == 2 and all(isinstance(r, dict) for r in result)):
            charge(
                RESET_SIGNATURE,
                f"{layer}.reset() returned {_describe(result)} instead of (observations, infos), two dicts: "
                "the PettingZoo API before 1.21 returned the observations alone",
            )
            return
        _check_observations(charge, env, layer, "reset", result[0])
    elif name == "last":
        _check_last(charge, env, layer, result)
    elif api == PARALLEL:
        _check_parallel_step(charge, env, layer, result)


def _check_last(charge: Charge, env: Any, layer: str, result: object) -> None:
    if not (isinstance(result, tuple) and len(result) == 5):
        old = isinstance(result, tuple) and len(result) == 4
        charge(
            STEP_SIGNATURE,
            f"{layer}.last() returned "
            + ("4 values (observation, reward, done, info), the PettingZoo API before 1.21" if old else _describe(result))
            + ": return (observation, reward, termination, truncation, info)",
        )
        return
    observation, _reward, termination, truncation, _info = result
    agent = attribute(env, "agent_selection", None)
    _check_flags(charge, layer, "last()", agent, termination, truncation)
    if observation is not None:
        _check_observations(charge, env, layer, "last", {agent: observation})


def _check_parallel_step(charge: Charge, env: Any, layer: str, result: object) -> None:
    if not (isinstance(result, tuple) and len(result) == 5 and all(isinstance(r, dict) for r in result)):
        old = isinstance(result, tuple) and len(result) == 4
        charge(
            STEP_SIGNATURE,
            f"{layer}.step() returned "
            + ("four dicts (observations, rewards, dones, infos), the PettingZoo API before 1.21" if old else _describe(result))
            + ": return (observations, rewards, terminations, truncations, infos)",
        )
        return
    observations, _rewards, terminations, truncations, _infos = result
    for agent, termination in terminations.items():
        _check_flags(charge, layer, "step()", agent, termination, truncations.get(agent, False))
    _check_observations(charge, env, layer, "step", observations)


def _check_flags(charge: Charge, layer: str, call: str, agent: object, termination: object, truncation: object) -> None:
    for flag_name, flag in (("termination", termination), ("truncation", truncation)):
        if not isinstance(flag, (bool, np.bool_)):
            charge(
                FLAGS_ARE_BOOL,
                f"{layer}.{call} returned {flag_name}={flag!r} of type {type(flag).__name__} for {agent}: "
                "terminations and truncations must be bool",
            )


def _check_observations(charge: Charge, env: Any, layer: str, call: str, observations: object) -> None:
    if not isinstance(observations, dict):
        return
    for agent, observation in observations.items():
        try:
            space = env.observation_space(agent)
        except Exception:  # an agent the env cannot describe: PettingZoo's api_test reports that
            continue
        try:
            inside = bool(space.contains(observation))
        except Exception:
            inside = False
        if not inside:
            charge(
                OBS_IN_SPACE,
                f"{layer}.{call}() returned an observation of {agent} outside observation_space({agent!r}) {space}",
            )
            return


def attribute(env: object, name: str, default: object) -> Any:
    """``getattr`` that never raises: PettingZoo's OrderEnforcingWrapper raises for some names before reset."""
    try:
        return getattr(env, name, default)
    except Exception:
        return default
