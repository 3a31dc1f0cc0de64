"""The observer: watch every ``gymnasium.Env`` the loop drives, call by call.

Installing the observer patches ``gymnasium.Env.__new__``; the first time a class is
instantiated, the ``reset`` and ``step`` defined anywhere in its MRO are wrapped in a
probe. That one hook sees envs built by ``gymnasium.make``, by ``make_vec`` (its sync
sub-envs are made through ``make``), and by user code calling ``MyEnv()`` directly,
wrappers included, without touching the user's objects.

Each call is seen at two levels:

- every layer (the env and each wrapper) has its return value checked against the
  Gymnasium contract, and a violation is charged to the innermost layer where it shows
  (an outer wrapper passing the same bad tuple on is not charged again);
- the outermost call (the one the user's loop made) drives the episode ledger: start,
  length, return, why it ended, steps taken after the end without a reset, and the
  step/episode budget.

The observer never changes what a call returns and never swallows an exception, so the
user's loop behaves as it would without it. Two things are added on purpose: the first
reset of an env that the code did not seed gets ``seed=`` from ``--seed`` (recorded as
``seed_source: "smoke"``) when ``inject_seed`` is on, and once the budget is spent the
next call raises ``SmokeStop``, a BaseException so a loop's ``except Exception`` cannot
swallow it.
"""

from __future__ import annotations

import functools
import hashlib
import inspect
import os
import re
import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from gymmigrate.smoke.evidence import Ending, EnvRecord, EpisodeRecord, RunRecord

# Check names shared with checks.py.
RESET_SIGNATURE = "reset_returns_obs_info"
STEP_SIGNATURE = "step_returns_five_fields"
FLAGS_ARE_BOOL = "flags_are_bool"
OBS_IN_SPACE = "obs_in_space"
NO_STEP_AFTER_END = "no_step_after_end"
CONTRACT_CHECKS = (RESET_SIGNATURE, STEP_SIGNATURE, FLAGS_ARE_BOOL, OBS_IN_SPACE, NO_STEP_AFTER_END)

_PROBED = "__gymmigrate_probe__"
_MAX_WARNINGS = 20
_ANSI = re.compile(r"\x1b\[[0-9;]*m")


class SmokeStop(BaseException):
    """The step or episode budget is spent: unwind the user's loop."""


class SmokeTimeout(BaseException):
    """The wall-clock budget is spent: unwind the user's loop."""


@dataclass(frozen=True)
class Budget:
    episodes: int
    max_steps: int


@dataclass
class _Episode:
    index: int
    start: str
    hasher: Any
    length: int = 0
    episode_return: float = 0.0
    ending: Ending | None = None
    ended_at_step: int = 0

    def close(self, ending: Ending) -> EpisodeRecord:
        self.ending = ending
        return EpisodeRecord(
            index=self.index,
            length=self.length,
            episode_return=self.episode_return,
            ending=ending,
            start=self.start,
            digest=self.hasher.hexdigest(),
        )


@dataclass
class _Ledger:
    """The loop-level history of one env (keyed by its unwrapped base env)."""

    index: int
    env_id: str | None
    env_class: str
    wrappers: tuple[str, ...]
    render_mode: str | None
    base: object  # kept alive so its id() cannot be reused by another env
    reset_seed: int | None = None
    seed_source: str = "none"
    resets: int = 0
    steps: int = 0
    steps_after_end: int = 0
    first_transition: str | None = None
    episodes: list[EpisodeRecord] = field(default_factory=list)
    current: _Episode | None = None

    @property
    def needs_reset(self) -> bool:
        return self.current is None or self.current.ending is not None

    def to_record(self, open_ending: Ending) -> EnvRecord:
        episodes = list(self.episodes)
        if self.current is not None and self.current.ending is None and self.current.length > 0:
            episodes.append(self.current.close(open_ending))
        return EnvRecord(
            index=self.index,
            env_id=self.env_id,
            env_class=self.env_class,
            wrappers=self.wrappers,
            render_mode=self.render_mode,
            reset_seed=self.reset_seed,
            seed_source=self.seed_source,
            steps=self.steps,
            episodes=tuple(episodes),
            first_transition=self.first_transition,
        )


class Observatory:
    """Holds everything observed while installed; ``record()`` turns it into a RunRecord."""

    def __init__(self, seed: int, budget: Budget, *, inject_seed: bool, loop_owner: str = "script") -> None:
        self.seed = seed
        self.budget = budget
        self.inject_seed = inject_seed
        self.loop_owner = loop_owner  # who passes the seeds the loop gives reset(): "script" or "smoke"
        self.pid = os.getpid()
        self.ledgers: dict[int, _Ledger] = {}
        self.violations: dict[str, list] = {}  # name -> [first message, count]
        self.warnings: list[str] = []
        self.calls = 0  # loop-level reset/step calls attempted
        self.total_steps = 0
        self.episodes_ended = 0
        self.stop_reason: str | None = None
        self._stack: list[int] = []  # ids of the envs whose reset/step is running
        self._chain_charged: set[str] = set()  # checks already charged in this call chain
        self._patched: list[tuple[type, str, object]] = []
        self._env_class: type | None = None
        self._vectors: list[object] = []  # vector envs whose spaces still need the seed
        self.vector_envs: list[str] = []  # class names, for the evidence
        self._seeded_spaces: set[int] = set()  # ids of spaces someone called .seed() on

    # -- installing ---------------------------------------------------------------

    @contextmanager
    def installed(self) -> Iterator[Observatory]:
        self.install()
        try:
            yield self
        finally:
            self.uninstall()

    def install(self) -> None:
        global _ACTIVE
        import gymnasium

        self._env_class = gymnasium.Env
        _install_construction_hooks(gymnasium)
        _ACTIVE = self

        # Which spaces did the code seed itself? Space.np_random is not None once anyone
        # looked at it (batch_space copies it from entropy), so ask Space.seed instead.
        for space_class in _subclasses(gymnasium.spaces.Space):
            original_seed = space_class.__dict__.get("seed")
            if inspect.isfunction(original_seed):
                self._patch(space_class, "seed", self._seed_probe(original_seed), original_seed)
        self._saved_showwarning = warnings.showwarning
        warnings.showwarning = self._record_warning

    def uninstall(self) -> None:
        global _ACTIVE
        if _ACTIVE is self:
            _ACTIVE = None
        for owner, name, original in reversed(self._patched):
            setattr(owner, name, original)
        self._patched.clear()
        warnings.showwarning = self._saved_showwarning

    def _constructed_vector(self, vector: object) -> None:
        # A VectorEnv is not an Env: its sub-envs are observed one by one, but its own
        # batched action space (what the loop samples from) still needs the seed.
        self.vector_envs.append(type(vector).__name__)
        self._vectors.append(vector)

    def _seed_probe(self, original_seed: Callable) -> Callable:
        observatory = self

        @functools.wraps(original_seed)
        def observed_seed(space: object, *args: object, **kwargs: object) -> object:
            observatory._seeded_spaces.add(id(space))
            return original_seed(space, *args, **kwargs)

        return observed_seed

    def _instrument(self, cls: type) -> None:
        env_class = self._env_class
        if env_class is None:  # only called while installed, which sets it
            return
        for owner in cls.__mro__:
            if not (isinstance(owner, type) and issubclass(owner, env_class)):
                continue
            for name in ("reset", "step"):
                original = owner.__dict__.get(name)
                if not inspect.isfunction(original) or getattr(original, _PROBED, False):
                    continue
                self._patch(owner, name, self._probe(original, name), original)

    def _patch(self, owner: type, name: str, replacement: Callable, original: Callable) -> None:
        """Put ``replacement`` in the class for ``original``; ``uninstall`` puts it back."""
        setattr(owner, name, replacement)
        self._patched.append((owner, name, original))

    def _probe(self, method: Callable, kind: str) -> Callable:
        observatory = self

        @functools.wraps(method)
        def probe(env: object, *args: object, **kwargs: object) -> object:
            return observatory._call(env, method, kind, args, kwargs)

        setattr(probe, _PROBED, True)
        return probe

    def _record_warning(self, message, category, filename, lineno, file=None, line=None) -> None:  # noqa: ANN001
        text = f"{category.__name__}: {_ANSI.sub('', str(message)).strip()}"
        if text not in self.warnings and len(self.warnings) < _MAX_WARNINGS:
            self.warnings.append(text)

    # -- one call -----------------------------------------------------------------

    def _call(self, env: object, method: Callable, kind: str, args: tuple, kwargs: dict) -> object:
        if os.getpid() != self.pid or id(env) in self._stack:
            # A forked worker (async vector env), or a super().step() call on the same env.
            return method(env, *args, **kwargs)
        root = not self._stack
        ledger = None
        if root:
            if self.stop_reason is not None:
                raise SmokeStop(self.stop_reason)
            self.calls += 1
            self._chain_charged = set()
            ledger = self._ledger_for(env)
            if kind == "reset":
                kwargs = self._seed_first_reset(ledger, env, method, args, kwargs)
            else:
                self._check_order(ledger, env)
        self._stack.append(id(env))
        try:
            result = method(env, *args, **kwargs)
        finally:
            self._stack.pop()
        self._check_contract(env, kind, result)
        if ledger is not None:
            if kind == "reset":
                self._after_reset(ledger, result)
            else:
                self._after_step(ledger, result)
        return result

    def _ledger_for(self, env: object) -> _Ledger:
        base = _unwrapped(env)
        ledger = self.ledgers.get(id(base))
        if ledger is None:
            spec = getattr(base, "spec", None)
            ledger = _Ledger(
                index=len(self.ledgers),
                env_id=getattr(spec, "id", None),
                env_class=type(base).__name__,
                wrappers=_wrapper_stack(env),
                render_mode=_render_mode(env),
                base=base,
            )
            self.ledgers[id(base)] = ledger
        return ledger

    def _seed_first_reset(self, ledger: _Ledger, env: object, method: Callable, args: tuple, kwargs: dict) -> dict:
        if ledger.resets > 0:
            return kwargs
        smoke_seed = self.seed + ledger.index
        self._seed_vector_spaces()
        # A loop that samples actions from a space it never seeded is not reproducible:
        # Space.np_random is drawn from OS entropy. Seed such spaces from --seed.
        for space_name in ("action_space", "observation_space"):
            self._seed_space_if_unseeded(getattr(env, space_name, None), smoke_seed)
        seed = kwargs.get("seed")
        if seed is not None:
            ledger.reset_seed, ledger.seed_source = _as_int(seed), self.loop_owner
        elif self.inject_seed and _accepts_seed(method):
            ledger.reset_seed, ledger.seed_source = smoke_seed, "smoke"
            kwargs = {**kwargs, "seed": smoke_seed}
        return kwargs

    def _seed_vector_spaces(self) -> None:
        for vector in self._vectors:
            for space_name in ("action_space", "observation_space", "single_action_space", "single_observation_space"):
                self._seed_space_if_unseeded(getattr(vector, space_name, None), self.seed)
        self._vectors.clear()

    def _seed_space_if_unseeded(self, space: object, seed: int) -> None:
        if space is None or id(space) in self._seeded_spaces or not hasattr(space, "seed"):
            return
        try:
            space.seed(seed)
        except Exception:  # a custom space with its own seed(): leave it as the code made it
            pass

    def _check_order(self, ledger: _Ledger, env: object) -> None:
        name = ledger.env_id or ledger.env_class
        if ledger.current is None:
            self._violation(NO_STEP_AFTER_END, f"step() on {name} was called before the first reset()")
        elif ledger.current.ending is not None:
            ending = ledger.current.ending.value
            self._violation(
                NO_STEP_AFTER_END,
                f"step() on {name} was called after episode {ledger.current.index + 1} ended "
                f"({ending} at step {ledger.current.ended_at_step}) without reset() in between",
            )
        else:
            return
        # What an env returns after its end is undefined (CartPole drifts out of its
        # bounds): do not charge those observations to obs_in_space as well.
        self._chain_charged.add(OBS_IN_SPACE)

    def _after_reset(self, ledger: _Ledger, result: object) -> None:
        ledger.resets += 1
        if ledger.current is not None and ledger.current.ending is None and ledger.current.length > 0:
            ledger.episodes.append(ledger.current.close(Ending.RESET))
        obs = result[0] if isinstance(result, tuple) and len(result) == 2 else result
        hasher = hashlib.sha256()
        _fingerprint(obs, hasher)
        start = hasher.hexdigest()
        ledger.current = _Episode(index=len(ledger.episodes), start=start, hasher=hasher)

    def _after_step(self, ledger: _Ledger, result: object) -> None:
        self.total_steps += 1
        ledger.steps += 1
        obs, reward, terminated, truncated = _read_step(result)
        episode = ledger.current
        if episode is None or episode.ending is not None:
            ledger.steps_after_end += 1
        else:
            episode.length += 1
            episode.episode_return += _as_float(reward)
            step_hash = hashlib.sha256()
            for value in (obs, reward, terminated, truncated):
                _fingerprint(value, step_hash)
                _fingerprint(value, episode.hasher)
            if ledger.first_transition is None:
                ledger.first_transition = hashlib.sha256(
                    (episode.start + step_hash.hexdigest()).encode()
                ).hexdigest()
            if terminated or truncated:
                episode.ended_at_step = episode.length
                ledger.episodes.append(episode.close(Ending.TERMINATED if terminated else Ending.TRUNCATED))
                self.episodes_ended += 1
        if self.episodes_ended >= self.budget.episodes:
            self.stop_reason = f"{self.episodes_ended} episodes ran"
        elif self.total_steps >= self.budget.max_steps:
            self.stop_reason = f"{self.total_steps} steps ran"

    # -- the contract, at every layer ----------------------------------------------

    def _check_contract(self, env: object, kind: str, result: object) -> None:
        name = type(env).__name__
        if kind == "reset":
            self._check_reset(env, name, result)
        else:
            self._check_step(env, name, result)

    def _check_reset(self, env: object, name: str, result: object) -> None:
        if not (isinstance(result, tuple) and len(result) == 2):
            self._charge(
                RESET_SIGNATURE,
                f"{name}.reset() returned {_describe(result)} instead of (obs, info): "
                "the old Gym API returned the observation alone; return (obs, {}) instead",
            )
            return
        obs, info = result
        if not isinstance(info, dict):
            self._charge(RESET_SIGNATURE, f"{name}.reset() returned info of type {type(info).__name__}, not a dict")
        self._check_obs(env, name, "reset", obs)

    def _check_step(self, env: object, name: str, result: object) -> None:
        if not (isinstance(result, tuple) and len(result) == 5):
            if isinstance(result, tuple) and len(result) == 4:
                message = (
                    f"{name}.step() returned 4 values (obs, reward, done, info), the old Gym API: "
                    "return (obs, reward, terminated, truncated, info)"
                )
            else:
                message = (
                    f"{name}.step() returned {_describe(result)} instead of "
                    "(obs, reward, terminated, truncated, info)"
                )
            self._charge(STEP_SIGNATURE, message)
            return
        obs, _reward, terminated, truncated, info = result
        for flag_name, flag in (("terminated", terminated), ("truncated", truncated)):
            if not isinstance(flag, (bool, np.bool_)):
                self._charge(
                    FLAGS_ARE_BOOL,
                    f"{name}.step() returned {flag_name}={flag!r} of type {type(flag).__name__}: "
                    "terminated and truncated must be bool",
                )
        if not isinstance(info, dict):
            self._charge(STEP_SIGNATURE, f"{name}.step() returned info of type {type(info).__name__}, not a dict")
        self._check_obs(env, name, "step", obs)

    def _check_obs(self, env: object, name: str, kind: str, obs: object) -> None:
        try:
            space = getattr(env, "observation_space", None)
        except Exception:  # a broken space property is the env's problem, reported elsewhere
            return
        if space is None or not hasattr(space, "contains"):
            return
        try:
            inside = bool(space.contains(obs))
        except Exception:
            inside = False
        if not inside:
            self._charge(
                OBS_IN_SPACE,
                f"{name}.{kind}() returned an observation outside its observation_space {space}: {_short(obs)}",
            )

    def _charge(self, check: str, message: str) -> None:
        """A contract violation, charged once per call chain (to the innermost layer)."""
        if check in self._chain_charged:
            return
        self._chain_charged.add(check)
        self._violation(check, message)

    def _violation(self, check: str, message: str) -> None:
        entry = self.violations.setdefault(check, [message, 0])
        entry[1] += 1

    # -- results ------------------------------------------------------------------

    def needs_reset(self, env: object) -> bool:
        ledger = self.ledgers.get(id(_unwrapped(env)))
        return ledger is None or ledger.needs_reset

    def record(self, stopped_by: str, error: str | None = None, seconds: float = 0.0) -> RunRecord:
        open_ending = Ending.BUDGET if stopped_by == "budget" else Ending.INTERRUPTED
        return RunRecord(
            seed=self.seed,
            envs=tuple(ledger.to_record(open_ending) for ledger in self.ledgers.values()),
            stopped_by=stopped_by,
            error=error,
            warnings=tuple(self.warnings),
            violations=tuple((name, message, count) for name, (message, count) in self.violations.items()),
            steps=self.total_steps,
            calls=self.calls,
            vector_envs=tuple(self.vector_envs),
            steps_after_end=sum(ledger.steps_after_end for ledger in self.ledgers.values()),
            seconds=seconds,
        )


# -- construction hooks ----------------------------------------------------------------

# The observatory that construction hooks report to; None outside a smoke run.
_ACTIVE: Observatory | None = None


def _install_construction_hooks(gymnasium: Any) -> None:
    """Hook ``Env.__new__`` and ``VectorEnv.__new__`` once per process.

    The hooks stay for the life of the process and do nothing while no observatory is
    active: CPython does not give a class its original ``__new__`` slot back when the
    attribute is deleted again, so uninstalling would break later instantiations.
    """
    for base, on_new in ((gymnasium.Env, _on_new_env), (gymnasium.vector.VectorEnv, _on_new_vector)):
        if "__new__" not in base.__dict__:
            base.__new__ = staticmethod(_construction_hook(base, on_new))


def _construction_hook(base: type[Any], on_new: Callable[[object], None]) -> Callable[..., object]:
    def observed_new(cls: type[object], *args: object, **kwargs: object) -> object:
        following = super(base, cls).__new__  # what __new__ would have been without the hook
        instance = following(cls) if following is object.__new__ else following(cls, *args, **kwargs)
        on_new(instance)
        return instance

    return observed_new


def _subclasses(cls: type) -> list[type]:
    found: list[type] = [cls]
    pending: list[type] = [cls]
    sub: type
    while pending:
        for sub in pending.pop().__subclasses__():
            if sub not in found:
                found.append(sub)
                pending.append(sub)
    return found


def _on_new_env(env: object) -> None:
    if _ACTIVE is not None:
        _ACTIVE._instrument(type(env))


def _on_new_vector(vector: object) -> None:
    if _ACTIVE is not None:
        _ACTIVE._constructed_vector(vector)


# -- helpers ---------------------------------------------------------------------


def _unwrapped(env: object) -> object:
    seen = 0
    while hasattr(env, "env") and seen < 100 and _is_wrapper(env):
        env = env.env
        seen += 1
    return env


def _is_wrapper(env: object) -> bool:
    import gymnasium

    return isinstance(env, gymnasium.Wrapper)


def _wrapper_stack(env: object) -> tuple[str, ...]:
    names = [type(env).__name__]
    while _is_wrapper(env) and len(names) < 100:
        env = env.env  # type: ignore[attr-defined]
        names.append(type(env).__name__)
    return tuple(names)


def _render_mode(env: object) -> str | None:
    try:
        mode = getattr(env, "render_mode", None)
    except Exception:
        return None
    return mode if isinstance(mode, str) else None


def _accepts_seed(method: Callable) -> bool:
    try:
        parameters = inspect.signature(method).parameters
    except (TypeError, ValueError):
        return False
    return "seed" in parameters or any(p.kind is inspect.Parameter.VAR_KEYWORD for p in parameters.values())


def _read_step(result: object) -> tuple[object, object, bool, bool]:
    """Read a step result leniently, so the ledger still follows a loop over a broken env."""
    if isinstance(result, tuple) and len(result) == 5:
        obs, reward, terminated, truncated, _info = result
        return obs, reward, _truthy(terminated), _truthy(truncated)
    if isinstance(result, tuple) and len(result) == 4:
        obs, reward, done, info = result
        cut_by_time_limit = isinstance(info, dict) and bool(info.get("TimeLimit.truncated", False))
        return obs, reward, _truthy(done) and not cut_by_time_limit, _truthy(done) and cut_by_time_limit
    return result, 0.0, False, False


def _truthy(value: object) -> bool:
    try:
        return bool(value)
    except Exception:  # an array flag: ambiguous truth value
        return False


def _as_float(value: object) -> float:
    try:
        return float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return 0.0


def _as_int(value: object) -> int | None:
    try:
        return int(value)  # type: ignore[call-overload]
    except (TypeError, ValueError):
        return None


def _fingerprint(value: object, hasher: Any) -> None:
    """Feed a value into a hash so that equal values always hash alike, across processes."""
    if isinstance(value, (bool, np.bool_)):
        hasher.update(b"b1" if value else b"b0")
    elif isinstance(value, (int, np.integer)):
        hasher.update(b"i" + str(int(value)).encode())
    elif isinstance(value, (float, np.floating)):
        hasher.update(b"f" + float(value).hex().encode())
    elif isinstance(value, np.ndarray):
        array = np.ascontiguousarray(value)
        if array.dtype == object:
            hasher.update(b"O")
            for item in array.ravel():
                _fingerprint(item, hasher)
        else:
            hasher.update(f"a{array.dtype.str}{array.shape}".encode() + array.tobytes())
    elif isinstance(value, dict):
        hasher.update(b"d")
        for key in sorted(value, key=str):
            hasher.update(str(key).encode())
            _fingerprint(value[key], hasher)
    elif isinstance(value, (tuple, list)):
        hasher.update(b"t%d" % len(value))
        for item in value:
            _fingerprint(item, hasher)
    elif value is None:
        hasher.update(b"n")
    elif isinstance(value, (str, bytes)):
        hasher.update(b"s" + (value.encode() if isinstance(value, str) else value))
    elif hasattr(value, "__array__"):
        _fingerprint(np.asarray(value), hasher)
    else:
        hasher.update(b"r" + type(value).__qualname__.encode())


def _describe(value: object) -> str:
    if isinstance(value, tuple):
        return f"a tuple of {len(value)} values"
    return f"a {type(value).__name__} ({_short(value)})"


def _short(value: object, limit: int = 80) -> str:
    try:
        text = np.array2string(value, threshold=8) if isinstance(value, np.ndarray) else repr(value)
    except Exception:
        text = f"<{type(value).__name__}>"
    text = " ".join(text.split())
    return text if len(text) <= limit else text[: limit - 3] + "..."
