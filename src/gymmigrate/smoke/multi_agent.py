"""``gymmigrate smoke`` on PettingZoo targets: seeded AEC and parallel episodes.

A target is a PettingZoo env module (``pettingzoo.classic.rps_v2``: its ``env()``), one
of its factories or a class (``pettingzoo.classic.rps_v2:parallel_env``,
``path/to/env.py:raw_env``, any ``AECEnv`` / ``ParallelEnv`` subclass or a function that
returns one). PettingZoo's own conformance test (``api_test`` / ``parallel_api_test``)
runs first on a fresh instance; then the driver plays seeded episodes: the first reset
gets the seed, every agent's action space is seeded from it, and actions respect an
``action_mask`` where the observation carries one.

The evidence has the Gym record's shape (one env record, its episodes, the same named
checks, charged by this driver instead of the Gym observer), plus ``agent_counts``: for
each agent, how many episodes ended for it by termination and how many by truncation,
counted apart. An episode counts as terminated when any agent terminated in it, as
truncated when agents only were truncated.

Only this module (and the tests) import PettingZoo, and only when a target needs it.
"""

from __future__ import annotations

import hashlib
import importlib
import io
import time
import warnings
from collections.abc import Callable
from contextlib import redirect_stdout
from dataclasses import dataclass, field
from typing import Any

from gymmigrate.smoke.driver import _deadline
from gymmigrate.smoke.evidence import (
    CheckResult,
    Ending,
    EnvRecord,
    EpisodeRecord,
    RunRecord,
)
from gymmigrate.smoke.probe import (
    FLAGS_ARE_BOOL,
    OBS_IN_SPACE,
    RESET_SIGNATURE,
    STEP_SIGNATURE,
    SmokeTimeout,
)
from gymmigrate.smoke.targets import (
    LoadError,
    Target,
    _import_file,
    _import_module,
    describe_exception,
)

PETTINGZOO_API_TEST = "pettingzoo_api_test"
AEC, PARALLEL = "aec", "parallel"


@dataclass(frozen=True)
class MultiAgentTarget:
    make: Callable[[], Any]
    api: str  # AEC or PARALLEL
    label: str


def pettingzoo_target(target: Target) -> MultiAgentTarget | None:
    """The PettingZoo env ``target`` names, or None when it is not one (a Gym target).

    Never imports PettingZoo for a target that does not name it: a class target is
    loaded first and PettingZoo is asked only when the module already imported it.
    """
    if target.kind == "env-id":
        if "." not in target.location or "-v" in target.location:
            return None  # ``CartPole-v1``: a Gym id
        try:
            module = importlib.import_module(target.location)
        except ImportError:
            return None
        factory = getattr(module, "env", None)
        return MultiAgentTarget(factory, AEC, target.location) if callable(factory) else None
    if target.kind != "class":
        return None
    if not _names_pettingzoo(target.location):
        return None
    module = _import_file(target.location) if target.location.endswith(".py") else _import_module(target.location)
    made = getattr(module, target.class_name or "", None)
    if made is None:
        raise LoadError(f"{target.location} has no attribute {target.class_name!r}")
    try:
        from pettingzoo import AECEnv, ParallelEnv
    except ImportError:
        return None
    label = f"{target.location}:{target.class_name}"
    if isinstance(made, type):
        if issubclass(made, ParallelEnv):
            return MultiAgentTarget(made, PARALLEL, label)
        if issubclass(made, AECEnv):
            return MultiAgentTarget(made, AEC, label)
        return None
    if callable(made):
        try:
            sample = made()
        except Exception as exc:
            raise LoadError(f"cannot call {label}() without arguments: {describe_exception(exc)}") from None
        _close(sample)
        if isinstance(sample, ParallelEnv):
            return MultiAgentTarget(made, PARALLEL, label)
        if isinstance(sample, AECEnv):
            return MultiAgentTarget(made, AEC, label)
    return None


def _names_pettingzoo(location: str) -> bool:
    """A class target is worth asking PettingZoo about if its module or file mentions it."""
    if location.startswith("pettingzoo."):
        return True
    if location.endswith(".py"):
        try:
            with open(location, encoding="utf-8", errors="replace") as handle:
                return "pettingzoo" in handle.read()
        except OSError:
            return False
    return False


def api_test_check(target: MultiAgentTarget) -> CheckResult:
    """PettingZoo's conformance test on a fresh instance (its report goes nowhere: stdout is data)."""
    from pettingzoo.test import api_test, parallel_api_test

    env = _construct(target)
    test = "parallel_api_test" if target.api == PARALLEL else "api_test"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            with redirect_stdout(io.StringIO()):
                if target.api == PARALLEL:
                    parallel_api_test(env, num_cycles=100)
                else:
                    api_test(env, num_cycles=100)
        except Exception as exc:
            return CheckResult.fail(PETTINGZOO_API_TEST, f"PettingZoo's {test} failed: {describe_exception(exc)}")
        finally:
            _close(env)
    notes = sorted({str(w.message).strip().splitlines()[0] for w in caught if str(w.message).strip()})
    if notes:
        return CheckResult.ok(PETTINGZOO_API_TEST, f"PettingZoo's {test} passed with {len(notes)} warnings: {'; '.join(notes[:3])}")
    return CheckResult.ok(PETTINGZOO_API_TEST, f"PettingZoo's {test} passed")


# -- driving ----------------------------------------------------------------------------


class _BudgetSpent(Exception):
    pass


@dataclass
class _Tally:
    """What one run observed, charged as it goes."""

    seed: int
    episodes_wanted: int
    max_steps: int
    steps: int = 0
    calls: int = 0
    episodes: list[EpisodeRecord] = field(default_factory=list)
    agent_counts: dict[str, dict[str, int]] = field(default_factory=dict)
    violations: dict[str, tuple[str, int]] = field(default_factory=dict)
    first_transition: str | None = None
    # the episode in progress
    hasher: Any = None
    start: str = ""
    length: int = 0
    episode_return: float = 0.0
    ended: dict[str, str] = field(default_factory=dict)  # agent -> "terminated" / "truncated"

    def charge(self, check: str, message: str) -> None:
        first, count = self.violations.get(check, (message, 0))
        self.violations[check] = (first, count + 1)

    def begin(self, observation: object) -> None:
        self.start = _digest(observation)
        self.hasher = hashlib.sha256(self.start.encode())
        self.length, self.episode_return, self.ended = 0, 0.0, {}

    def transition(self, *parts: object) -> None:
        self.hasher.update(_digest(parts).encode())
        if self.first_transition is None:
            self.first_transition = self.hasher.hexdigest()

    def step_taken(self) -> None:
        self.steps += 1
        self.length += 1
        if self.steps >= self.max_steps:
            raise _BudgetSpent

    def agent_ended(self, agent: object, terminated: bool, truncated: bool) -> None:
        name = str(agent)
        if name in self.ended or not (terminated or truncated):
            return
        how = "terminated" if terminated else "truncated"
        self.ended[name] = how
        self.agent_counts.setdefault(name, {"terminated": 0, "truncated": 0})[how] += 1

    def close(self, ending: Ending | None = None) -> None:
        if self.hasher is None:
            return
        if ending is None:
            ending = Ending.TERMINATED if "terminated" in self.ended.values() else Ending.TRUNCATED
        self.episodes.append(
            EpisodeRecord(len(self.episodes), self.length, self.episode_return, ending, self.start, self.hasher.hexdigest())
        )
        self.hasher = None
        if len(self.episodes) >= self.episodes_wanted:
            raise _BudgetSpent


def drive_pettingzoo(target: MultiAgentTarget, seed: int, episodes: int, max_steps: int, timeout: float) -> RunRecord:
    tally = _Tally(seed, episodes, max_steps)
    env = _construct(target)
    started = time.perf_counter()
    stopped_by, error = "finished", None
    try:
        with _deadline(timeout):
            _seed_action_spaces(env, seed)
            first = True
            while True:
                if target.api == PARALLEL:
                    _parallel_episode(env, tally, seed if first else None)
                else:
                    _aec_episode(env, tally, seed if first else None)
                first = False
    except _BudgetSpent:
        stopped_by = "budget"
        tally.close(Ending.BUDGET) if tally.hasher is not None else None
    except SmokeTimeout:
        stopped_by = "timeout"
        tally.close(Ending.INTERRUPTED) if tally.hasher is not None else None
    except Exception as exc:
        stopped_by, error = "error", describe_exception(exc)
    finally:
        _close(env)
    record = EnvRecord(
        index=0,
        env_id=target.label,
        env_class=type(getattr(env, "unwrapped", env)).__name__,
        wrappers=_wrappers(env),
        render_mode=getattr(env, "render_mode", None),
        reset_seed=seed,
        seed_source="smoke",
        steps=tally.steps,
        episodes=tuple(tally.episodes),
        first_transition=tally.first_transition,
        agent_counts={agent: dict(counts) for agent, counts in sorted(tally.agent_counts.items())},
    )
    return RunRecord(
        seed=seed,
        envs=(record,),
        stopped_by=stopped_by,
        error=error,
        violations=tuple((name, message, count) for name, (message, count) in tally.violations.items()),
        steps=tally.steps,
        calls=tally.calls,
        seconds=time.perf_counter() - started,
    )


def _reset(env: Any, tally: _Tally, seed: int | None) -> object:
    try:
        return env.reset(seed=seed)
    except TypeError as exc:
        if "seed" in str(exc):  # a pre-1.23 ``reset(self)``
            tally.charge(RESET_SIGNATURE, f"reset() does not take seed=: {describe_exception(exc)}")
        raise
    finally:
        tally.calls += 1


def _aec_episode(env: Any, tally: _Tally, seed: int | None) -> None:
    returned = _reset(env, tally, seed)
    if returned is not None:
        tally.charge(RESET_SIGNATURE, f"an AEC reset() returned {type(returned).__name__}, not None")
    tally.begin(env.observe(env.agent_selection) if env.agents else None)
    for agent in env.agent_iter():
        result = env.last()
        if not (isinstance(result, tuple) and len(result) == 5):
            tally.charge(STEP_SIGNATURE, "last() did not return (observation, reward, termination, truncation, info)")
            raise RuntimeError("last() does not return five values")
        observation, reward, terminated, truncated, info = result
        _check_agent(env, tally, agent, observation, terminated, truncated)
        tally.episode_return += float(reward)
        tally.agent_ended(agent, bool(terminated), bool(truncated))
        action = None if terminated or truncated else _sample(env.action_space(agent), observation)
        tally.transition(agent, observation, reward, terminated, truncated, action)
        env.step(action)
        tally.calls += 1
        tally.step_taken()
    tally.close()


def _parallel_episode(env: Any, tally: _Tally, seed: int | None) -> None:
    returned = _reset(env, tally, seed)
    if not (isinstance(returned, tuple) and len(returned) == 2 and all(isinstance(r, dict) for r in returned)):
        tally.charge(RESET_SIGNATURE, "a parallel reset() did not return (observations, infos)")
        raise RuntimeError("reset() does not return (observations, infos)")
    observations, _ = returned
    tally.begin(observations)
    while env.agents:
        actions = {agent: _sample(env.action_space(agent), observations.get(agent)) for agent in env.agents}
        result = env.step(actions)
        tally.calls += 1
        if not (isinstance(result, tuple) and len(result) == 5):
            tally.charge(STEP_SIGNATURE, "a parallel step() did not return five dicts")
            raise RuntimeError("step() does not return five dicts")
        observations, rewards, terminations, truncations, _ = result
        for agent in list(terminations):
            terminated, truncated = terminations[agent], truncations.get(agent, False)
            _check_agent(env, tally, agent, observations.get(agent), terminated, truncated)
            tally.agent_ended(agent, bool(terminated), bool(truncated))
        tally.episode_return += float(sum(rewards.values()))
        tally.transition(actions, observations, rewards, terminations, truncations)
        tally.step_taken()
    tally.close()


def _check_agent(env: Any, tally: _Tally, agent: object, observation: object, terminated: object, truncated: object) -> None:
    import numpy as np

    if not all(isinstance(flag, (bool, np.bool_)) for flag in (terminated, truncated)):
        tally.charge(FLAGS_ARE_BOOL, f"termination/truncation of {agent} were {type(terminated).__name__}/{type(truncated).__name__}")
    if observation is not None and not env.observation_space(agent).contains(observation):
        tally.charge(OBS_IN_SPACE, f"an observation of {agent} lay outside observation_space({agent!r})")


def _sample(space: Any, observation: object) -> object:
    import numpy as np

    mask = observation.get("action_mask") if isinstance(observation, dict) else None
    if mask is not None and hasattr(space, "n"):
        return space.sample(mask=np.asarray(mask, dtype=np.int8))
    return space.sample()


def _seed_action_spaces(env: Any, seed: int) -> None:
    for offset, agent in enumerate(getattr(env, "possible_agents", ())):
        env.action_space(agent).seed(seed + offset)


def _construct(target: MultiAgentTarget) -> Any:
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)  # module-level creation (1.27), see PZ110
            return target.make()
    except Exception as exc:
        raise LoadError(f"cannot create {target.label}: {describe_exception(exc)}") from None


def _wrappers(env: Any) -> tuple[str, ...]:
    stack, seen = [], 0
    while env is not None and seen < 50:
        stack.append(type(env).__name__)
        env = getattr(env, "env", None)
        seen += 1
    return tuple(stack)


def _close(env: Any) -> None:
    try:
        env.close()
    except Exception:
        pass


def _digest(value: object) -> str:
    return hashlib.sha256(_canonical(value).encode()).hexdigest()


def _canonical(value: object) -> str:
    """Text that two equal observations, rewards or actions share (arrays by their bytes)."""
    if isinstance(value, dict):
        return "{" + ",".join(f"{k!s}:{_canonical(v)}" for k, v in sorted(value.items(), key=lambda kv: str(kv[0]))) + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ",".join(_canonical(v) for v in value) + "]"
    tobytes = getattr(value, "tobytes", None)
    if callable(tobytes):
        return f"{getattr(value, 'dtype', '')}{getattr(value, 'shape', '')}:{tobytes().hex()}"
    return repr(value)
