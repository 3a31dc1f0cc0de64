"""The script observer for PettingZoo: watch every ``AECEnv`` and ``ParallelEnv`` a script drives.

It works beside the Gym ``Observatory`` (probe.py) and reports into it: the same
ledgers (one per unwrapped env, so the env indexes and seeds N+i are shared with Gym
envs), the same call stack, budget, contract check names and violations. Only
``agent_counts`` is new: per agent, episodes that ended for it by termination and by
truncation, counted apart, as the PettingZoo target driver (multi_agent.py) records.

PettingZoo is never imported here. ``install()`` puts an import watch on
``pettingzoo.utils.env``, the module that defines ``AECEnv`` and ``ParallelEnv``; when
the script imports PettingZoo, the two classes get a construction hook (as
``gymnasium.Env`` does in probe.py), and the first instance of each class has the
``reset``, ``step`` and (AEC) ``last`` defined anywhere in its MRO wrapped. A Gym-only
script pays one string comparison per import.

As for Gym, every layer (PettingZoo's ``OrderEnforcingWrapper``, ``BaseWrapper``s,
``aec_to_parallel_wrapper`` and the env they wrap) has its results checked
(multi_agent_contract.py), a violation charged to the innermost layer where it shows; the outermost call, the one the script
made, keeps the episode ledger. An AEC episode ends when ``env.agents`` is empty after
a step (what ends ``agent_iter``), a parallel one when ``env.agents`` is empty after
``step``; it counts as terminated when any agent terminated in it.
"""

from __future__ import annotations

import functools
import hashlib
import inspect
import os
import sys
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from importlib.machinery import ModuleSpec
from types import ModuleType
from typing import Any

from gymmigrate.smoke.evidence import Ending, EnvRecord
from gymmigrate.smoke.multi_agent_contract import AEC, PARALLEL, attribute, check_call
from gymmigrate.smoke.probe import (
    NO_STEP_AFTER_END,
    OBS_IN_SPACE,
    Observatory,
    SmokeStop,
    _accepts_seed,
    _as_float,
    _as_int,
    _construction_hook,
    _Episode,
    _fingerprint,
    _Ledger,
    _render_mode,
    _truthy,
)

_ENV_MODULE = "pettingzoo.utils.env"
_PROBED = "__gymmigrate_agents_probe__"
_OLD_DONES = ("dones", "_was_done_step", "_dones_step_first", "terminations", "truncations")

# PettingZoo's AECEnv and ParallelEnv once the script imported them; the observer that
# the construction hooks report to (None outside a script smoke run).
_CLASSES: dict[str, type] = {}
_ACTIVE: MultiAgentObserver | None = None


@dataclass
class _AgentLedger(_Ledger):
    api: str = AEC
    agent_counts: dict[str, dict[str, int]] = field(default_factory=dict)
    ended_agents: dict[str, str] = field(default_factory=dict)  # in the episode in progress

    def to_record(self, open_ending: Ending) -> EnvRecord:
        counts = {agent: dict(self.agent_counts[agent]) for agent in sorted(self.agent_counts)}
        return replace(super().to_record(open_ending), agent_counts=counts)


class MultiAgentObserver:
    def __init__(self, observatory: Observatory) -> None:
        self.observatory = observatory
        self.last_root: tuple[str, str] | None = None  # (api, method) of the script's latest call
        self._last_root_call = 0  # the Gym observer's call count at that call
        self._watch: _ImportWatch | None = None
        self._patched: list[tuple[type, str, object]] = []

    def install(self) -> None:
        global _ACTIVE
        _ACTIVE = self
        module = sys.modules.get(_ENV_MODULE)
        if module is not None:
            _hook_classes(module)
        else:
            self._watch = _ImportWatch()
            sys.meta_path.insert(0, self._watch)

    def uninstall(self) -> None:
        global _ACTIVE
        if _ACTIVE is self:
            _ACTIVE = None
        if self._watch in sys.meta_path:
            sys.meta_path.remove(self._watch)
        for owner, name, original in reversed(self._patched):
            setattr(owner, name, original)
        self._patched.clear()

    def crash_hint(self, exc: BaseException) -> str:
        """Why a script crashed on a PettingZoo env, when it is the pre-1.21 API."""
        if isinstance(exc, AttributeError) and exc.name in _OLD_DONES and _api_of(type(exc.obj)) is not None:
            return (
                "; PettingZoo 1.21 split dones into terminations and truncations (and _was_done_step into "
                "_was_dead_step): run gymmigrate rewrite on it first"
            )
        if self.last_root is None or self._last_root_call != self.observatory.calls:
            return ""  # another env call came after the last PettingZoo one
        api, method = self.last_root
        if isinstance(exc, ValueError) and "too many values to unpack (expected 4" in str(exc):
            if method == "last":
                return (
                    "; the loop unpacks last() into the four values of PettingZoo before 1.21 (observation, "
                    "reward, done, info), it returns (observation, reward, termination, truncation, info) now: "
                    "run gymmigrate rewrite on it first"
                )
            if method == "step" and api == PARALLEL:
                return (
                    "; the loop unpacks a parallel step() into the four dicts of PettingZoo before 1.21, it "
                    "returns (observations, rewards, terminations, truncations, infos) now: run gymmigrate rewrite on it first"
                )
        return ""

    # -- instrumenting ----------------------------------------------------------------

    def _instrument(self, cls: type) -> None:
        for owner in cls.__mro__:
            api = _api_of(owner)
            if api is None:
                continue
            for name in ("reset", "step", "last") if api == AEC else ("reset", "step"):
                original = owner.__dict__.get(name)
                if not inspect.isfunction(original) or getattr(original, _PROBED, False):
                    continue
                setattr(owner, name, self._probe(original, name, api))
                self._patched.append((owner, name, original))

    def _probe(self, method: Any, name: str, api: str) -> Any:
        observer = self

        @functools.wraps(method)
        def probe(env: object, *args: object, **kwargs: object) -> object:
            return observer._call(env, method, name, api, args, kwargs)

        setattr(probe, _PROBED, True)
        return probe

    # -- one call ---------------------------------------------------------------------

    def _call(self, env: Any, method: Any, name: str, api: str, args: tuple, kwargs: dict) -> object:
        watch = self.observatory
        if os.getpid() != watch.pid or id(env) in watch._stack:
            return method(env, *args, **kwargs)  # a forked worker, or super().step() on the same env
        ledger = None
        if not watch._stack:  # the script's own call: it drives the ledger
            if watch.stop_reason is not None:
                raise SmokeStop(watch.stop_reason)
            watch.calls += 1
            watch._chain_charged = set()
            self.last_root, self._last_root_call = (api, name), watch.calls
            ledger = self._ledger_for(env, api)
            if name == "reset":
                args, kwargs = self._seed_first_reset(ledger, env, method, args, kwargs)
            elif name == "step":
                self._check_order(ledger)
        watch._stack.append(id(env))
        try:
            result = method(env, *args, **kwargs)
        finally:
            watch._stack.pop()
        check_call(env, name, api, result, watch._charge)
        if ledger is not None:
            if name == "reset":
                self._after_reset(ledger, result)
            elif name == "last":
                self._after_last(ledger, result)
            else:
                self._after_step(ledger, env, args[0] if args else next(iter(kwargs.values()), None), result)
        return result

    def _ledger_for(self, env: Any, api: str) -> _AgentLedger:
        base = attribute(env, "unwrapped", env)
        ledger = self.observatory.ledgers.get(id(base))
        if ledger is None:
            metadata = attribute(base, "metadata", None)
            ledger = _AgentLedger(
                index=len(self.observatory.ledgers),
                env_id=metadata.get("name") if isinstance(metadata, dict) else None,
                env_class=type(base).__name__,
                wrappers=_wrapper_stack(env),
                render_mode=_render_mode(env),
                base=base,
                api=api,
            )
            self.observatory.ledgers[id(base)] = ledger
        return ledger  # type: ignore[return-value]

    def _seed_first_reset(self, ledger: _AgentLedger, env: Any, method: Any, args: tuple, kwargs: dict) -> tuple[tuple, dict]:
        if ledger.resets > 0:
            return args, kwargs
        watch = self.observatory
        smoke_seed = watch.seed + ledger.index
        # Scripts sample env.action_space(agent): a space nobody seeded draws from OS entropy.
        for offset, agent in enumerate(attribute(env, "possible_agents", None) or ()):
            for space_name in ("action_space", "observation_space"):
                try:
                    space = getattr(env, space_name)(agent)
                except Exception:
                    continue
                watch._seed_space_if_unseeded(space, smoke_seed + offset)
        seed = kwargs.get("seed", args[0] if args else None)
        if seed is not None:
            ledger.reset_seed, ledger.seed_source = _as_int(seed), watch.loop_owner
        elif watch.inject_seed and _accepts_seed(method):
            ledger.reset_seed, ledger.seed_source = smoke_seed, "smoke"
            if args:
                args = (smoke_seed, *args[1:])
            else:
                kwargs = {**kwargs, "seed": smoke_seed}
        return args, kwargs

    def _check_order(self, ledger: _AgentLedger) -> None:
        name = ledger.env_id or ledger.env_class
        if ledger.current is None:
            self.observatory._violation(NO_STEP_AFTER_END, f"step() on {name} was called before the first reset()")
        elif ledger.current.ending is not None:
            self.observatory._violation(
                NO_STEP_AFTER_END,
                f"step() on {name} was called after episode {ledger.current.index + 1} ended (every agent done "
                f"at step {ledger.current.ended_at_step}) without reset() in between",
            )
        else:
            return
        self.observatory._chain_charged.add(OBS_IN_SPACE)  # results after the end are undefined

    # -- the episode ledger -----------------------------------------------------------

    def _after_reset(self, ledger: _AgentLedger, result: object) -> None:
        ledger.resets += 1
        if ledger.current is not None and ledger.current.ending is None and ledger.current.length > 0:
            ledger.episodes.append(ledger.current.close(Ending.RESET))
        ledger.ended_agents = {}
        ledger.current = _Episode(index=len(ledger.episodes), start="", hasher=None)
        if ledger.api == PARALLEL:  # an AEC episode starts at its first last()
            _begin(ledger.current, result[0] if isinstance(result, tuple) and len(result) == 2 else result)

    def _after_last(self, ledger: _AgentLedger, result: object) -> None:
        episode = ledger.current
        if episode is None or episode.ending is not None:
            return
        values = result if isinstance(result, tuple) else (result,)
        if not episode.start:
            _begin(episode, values[0])
        if len(values) >= 4:
            episode.episode_return += _as_float(values[1])
        for value in values[:-1] if len(values) >= 4 else values:  # infos may hold anything
            _fingerprint(value, episode.hasher)

    def _after_step(self, ledger: _AgentLedger, env: Any, action: object, result: object) -> None:
        watch = self.observatory
        watch.total_steps += 1
        ledger.steps += 1
        episode = ledger.current
        if episode is None or episode.ending is not None:
            ledger.steps_after_end += 1
        else:
            if not episode.start:
                _begin(episode, None)
            episode.length += 1
            _fingerprint(action, episode.hasher)
            if ledger.api == PARALLEL:
                terminations, truncations = self._read_parallel_step(episode, result)
            else:
                terminations = attribute(env, "terminations", None) or attribute(env, "dones", None)
                truncations = attribute(env, "truncations", None)
            if ledger.first_transition is None:
                ledger.first_transition = episode.hasher.copy().hexdigest()
            _note_endings(ledger, terminations, truncations)
            if not attribute(env, "agents", True):
                episode.ended_at_step = episode.length
                ended = ledger.ended_agents.values()
                ending = Ending.TRUNCATED if "truncated" in ended and "terminated" not in ended else Ending.TERMINATED
                ledger.episodes.append(episode.close(ending))
                watch.episodes_ended += 1
        if watch.episodes_ended >= watch.budget.episodes:
            watch.stop_reason = f"{watch.episodes_ended} episodes ran"
        elif watch.total_steps >= watch.budget.max_steps:
            watch.stop_reason = f"{watch.total_steps} steps ran"

    @staticmethod
    def _read_parallel_step(episode: _Episode, result: object) -> tuple[object, object]:
        if not isinstance(result, tuple) or len(result) not in (4, 5):
            return None, None
        rewards = result[1]
        if isinstance(rewards, dict):
            episode.episode_return += sum(_as_float(reward) for reward in rewards.values())
        for value in result[:-1]:
            _fingerprint(value, episode.hasher)
        return (result[2], result[3]) if len(result) == 5 else (result[2], None)  # four dicts: dones

# -- hooks --------------------------------------------------------------------------


class _ImportWatch:
    """A meta path finder that lets PettingZoo's env module load, then hooks its two classes."""

    def find_spec(self, fullname: str, path: Sequence[str] | None, target: ModuleType | None = None) -> ModuleSpec | None:
        if fullname != _ENV_MODULE:
            return None
        for finder in sys.meta_path:
            if finder is self or not hasattr(finder, "find_spec"):
                continue
            spec = finder.find_spec(fullname, path, target)
            if spec is not None:
                break
        else:
            return None
        exec_module = getattr(spec.loader, "exec_module", None)
        if exec_module is not None:

            def exec_and_hook(module: object) -> None:
                exec_module(module)
                _hook_classes(module)

            _monkeypatch(spec.loader, "exec_module", exec_and_hook)  # this spec's own loader instance
        return spec


def _hook_classes(module: object) -> None:
    """Hook ``__new__`` of AECEnv and ParallelEnv once per process (it stays: see probe.py)."""
    for api, class_name in ((AEC, "AECEnv"), (PARALLEL, "ParallelEnv")):
        base = getattr(module, class_name, None)
        if not isinstance(base, type):
            continue
        _CLASSES[api] = base
        if "__new__" not in base.__dict__:
            _monkeypatch(base, "__new__", staticmethod(_construction_hook(base, _on_new_env)))


def _monkeypatch(owner: object, name: str, value: object) -> None:
    """``owner.name = value`` where ``name`` is a method (a plain assignment would not type-check)."""
    setattr(owner, name, value)


def _on_new_env(env: object) -> None:
    if _ACTIVE is not None:
        _ACTIVE._instrument(type(env))


def _api_of(owner: object) -> str | None:
    for api in (AEC, PARALLEL):
        base = _CLASSES.get(api)
        if base is not None and isinstance(owner, type) and issubclass(owner, base):
            return api
    return None


# -- helpers ------------------------------------------------------------------------


def _begin(episode: _Episode, observation: object) -> None:
    episode.hasher = hashlib.sha256()
    _fingerprint(observation, episode.hasher)
    episode.start = episode.hasher.hexdigest()


def _note_endings(ledger: _AgentLedger, terminations: object, truncations: object) -> None:
    """Count each agent once per episode, by termination or (only if not terminated) truncation."""
    for flags, how in ((terminations, "terminated"), (truncations, "truncated")):
        if not isinstance(flags, dict):
            continue
        for agent, flag in flags.items():
            name = str(agent)
            if name in ledger.ended_agents or not _truthy(flag):
                continue
            ledger.ended_agents[name] = how
            ledger.agent_counts.setdefault(name, {"terminated": 0, "truncated": 0})[how] += 1


def _wrapper_stack(env: object) -> tuple[str, ...]:
    """Outermost first: PettingZoo wrappers keep the inner env in ``env`` (``aec_env`` for aec_to_parallel)."""
    names = [type(env).__name__]
    while len(names) < 50:
        own = getattr(env, "__dict__", {})
        inner = own.get("env", own.get("aec_env"))
        if inner is None or _api_of(type(inner)) is None:
            break
        env = inner
        names.append(type(env).__name__)
    return tuple(names)

