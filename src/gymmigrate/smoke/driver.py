"""Drive an env in this process: seeded episodes with a seeded random policy.

Used for env ids and classes. The driver is itself a loop under observation: it reads
"does this env need a reset?" from the observer's ledger rather than unpacking results,
so it keeps going (and the checks keep collecting evidence) over an env that returns a
four-field step or a bare observation. The first reset gets ``seed``, later resets
none (the env's RNG carries on, as Gymnasium intends), and the action space is seeded
with ``seed`` too, so a run is a function of the seed alone.
"""

from __future__ import annotations

import signal
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING

from gymmigrate.smoke.evidence import RunRecord
from gymmigrate.smoke.probe import Budget, Observatory, SmokeStop, SmokeTimeout
from gymmigrate.smoke.targets import LoadError, describe_exception

if TYPE_CHECKING:  # gymnasium loads only when an env is driven
    import gymnasium


def drive(make_env: Callable[[], gymnasium.Env], seed: int, budget: Budget, timeout: float) -> RunRecord:
    """Run episodes until the budget is spent; raises LoadError if the env cannot be built."""
    observatory = Observatory(seed, budget, inject_seed=False, loop_owner="smoke")
    started = time.perf_counter()
    stopped_by, error = "finished", None
    with observatory.installed():
        try:
            env = make_env()
        except LoadError:
            raise
        except Exception as exc:
            raise LoadError(f"cannot create the env: {describe_exception(exc)}") from None
        try:
            with _deadline(timeout):
                _loop(env, observatory, seed)
        except SmokeStop:
            stopped_by = "budget"
        except SmokeTimeout:
            stopped_by = "timeout"
        except Exception as exc:
            stopped_by, error = "error", describe_exception(exc)
        finally:
            _close(env)
    return observatory.record(stopped_by, error, seconds=time.perf_counter() - started)


def _loop(env: gymnasium.Env, observatory: Observatory, seed: int) -> None:
    action_space = env.action_space
    action_space.seed(seed)
    first = True
    while True:  # ends by SmokeStop once the episode or step budget is spent
        if observatory.needs_reset(env):
            env.reset(seed=seed if first else None)
            first = False
        else:
            env.step(action_space.sample())


def _close(env: gymnasium.Env) -> None:
    try:
        env.close()
    except Exception:  # closing is not part of the contract checked here
        pass


@contextmanager
def _deadline(seconds: float) -> Iterator[None]:
    """Raise SmokeTimeout in this thread after ``seconds`` (only possible on the main thread)."""
    if threading.current_thread() is not threading.main_thread() or not hasattr(signal, "setitimer"):
        yield
        return

    def expire(signum: int, frame: object) -> None:
        raise SmokeTimeout(f"still running after {seconds:g} s")

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
