"""Put the parts together: load the target, run it (three times for determinism), judge, and return the Evidence.

Runs: seed N (the evidence), seed N again (``determinism``) and seed N+1
(``seed_changes_start``). For a script that means three executions, one after the
other (never in parallel: scripts write checkpoints and logs); the second and third
are skipped when the first never got to step an env or hit the timeout.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from gymmigrate.smoke.checks import evaluate
from gymmigrate.smoke.driver import drive
from gymmigrate.smoke.evidence import CheckResult, Evidence, RunRecord
from gymmigrate.smoke.multi_agent import (
    api_test_check,
    drive_pettingzoo,
    pettingzoo_target,
)
from gymmigrate.smoke.probe import Budget
from gymmigrate.smoke.script import run_script
from gymmigrate.smoke.targets import (
    LoadError,
    NothingToCheck,
    Target,
    check_env_id,
    describe_exception,
    instantiate,
    load_class,
    parse_target,
)

if TYPE_CHECKING:  # gymnasium loads only when a target is checked
    import gymnasium

GYMNASIUM_CHECK_ENV = "gymnasium_check_env"


@dataclass(frozen=True)
class SmokeOptions:
    seed: int = 0
    episodes: int = 3
    max_steps: int = 1000
    timeout: float = 60.0
    determinism: bool = True
    script_args: tuple[str, ...] = ()


def run_smoke(target_text: str, options: SmokeOptions | None = None) -> Evidence:
    """Never raises for a bad target: a load failure is Evidence with ``load_error`` set (exit 2)."""
    options = options or SmokeOptions()
    started = time.perf_counter()
    evidence = Evidence(
        target=target_text,
        target_kind="unknown",
        seed=options.seed,
        episodes=options.episodes,
        max_steps=options.max_steps,
        timeout=options.timeout,
        run=None,
    )
    try:
        target = parse_target(target_text)
        evidence = replace(evidence, target_kind=target.kind)
        pre_checks, runs = _run_all(target, options)
    except LoadError as exc:
        return replace(
            evidence,
            load_error=str(exc),
            created_no_env=isinstance(exc, NothingToCheck),
            timings={"seconds": _elapsed(started)},
        )
    run, same_seed, other_seed = runs
    checks = (*pre_checks, *evaluate(run, same_seed, other_seed, options.timeout))
    timings = {"seconds": _elapsed(started)}
    timings.update({f"run_{i + 1}_seconds": round(r.seconds, 3) for i, r in enumerate(runs) if r is not None})
    return replace(evidence, run=replace(run, seconds=0.0), checks=checks, timings=timings)


def _run_all(target: Target, options: SmokeOptions) -> tuple[tuple[CheckResult, ...], tuple]:
    budget = Budget(options.episodes, options.max_steps)
    if options.script_args and target.kind != "script":
        raise LoadError(f"extra arguments {' '.join(options.script_args)!r} are only for a script target")
    if target.kind == "script":
        return (), _repeat(lambda seed: _script_run(target, options, seed), options)
    multi_agent = pettingzoo_target(target)
    if multi_agent is not None:
        return (api_test_check(multi_agent),), _repeat(
            lambda seed: drive_pettingzoo(multi_agent, seed, options.episodes, options.max_steps, options.timeout), options
        )
    if target.kind == "env-id":
        check_env_id(target.location)
        import gymnasium

        def make() -> gymnasium.Env:
            return gymnasium.make(target.location)

        pre_checks: tuple[CheckResult, ...] = ()
    else:
        cls = load_class(target)
        pre_checks = (_gymnasium_check_env(cls),)

        def make() -> gymnasium.Env:
            return instantiate(cls)

    runs = _repeat(lambda seed: drive(make, seed, budget, options.timeout), options)
    return pre_checks, runs


def _repeat(run_once, options: SmokeOptions) -> tuple[RunRecord, RunRecord | None, RunRecord | None]:  # noqa: ANN001
    first = run_once(options.seed)
    if not options.determinism or not first.stepped or first.stopped_by == "timeout":
        return first, None, None
    return first, run_once(options.seed), run_once(options.seed + 1)


def _script_run(target: Target, options: SmokeOptions, seed: int) -> RunRecord:

    return run_script(
        target.location,
        list(options.script_args),
        seed=seed,
        episodes=options.episodes,
        max_steps=options.max_steps,
        timeout=options.timeout,
    )


def _gymnasium_check_env(cls: type[gymnasium.Env]) -> CheckResult:
    """Gymnasium's own checker, on a fresh instance (it resets and steps the env itself)."""
    import warnings

    from gymnasium.utils.env_checker import check_env


    env = instantiate(cls)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            check_env(env, skip_render_check=True)
        except Exception as exc:
            return CheckResult.fail(GYMNASIUM_CHECK_ENV, f"gymnasium's check_env failed: {describe_exception(exc)}")
        finally:
            try:
                env.close()
            except Exception:
                pass
    notes = sorted({_first_line(str(w.message)) for w in caught})
    if notes:
        quoted = "; ".join(notes[:3])
        return CheckResult.ok(GYMNASIUM_CHECK_ENV, f"gymnasium's check_env passed with {len(notes)} warnings: {quoted}")
    return CheckResult.ok(GYMNASIUM_CHECK_ENV, "gymnasium's check_env passed")


def _first_line(text: str) -> str:
    import re

    clean = re.sub(r"\x1b\[[0-9;]*m", "", text).strip()
    return clean.splitlines()[0] if clean else clean


def _elapsed(started: float) -> float:
    return round(time.perf_counter() - started, 3)
