"""The named checks: each turns what the runs observed into one CheckResult.

The per-call contract checks (reset/step shapes, bool flags, observations in the space,
no step after the end) were charged by the observer while the loop ran; here they
become results. ``run_completed`` and ``episodes_end`` read how the run stopped;
``determinism`` and ``seed_changes_start`` compare a second run with the same seed
and a third with ``seed + 1``.
"""

from __future__ import annotations

from gymmigrate.smoke.evidence import CheckResult, Ending, EnvRecord, RunRecord
from gymmigrate.smoke.probe import (
    FLAGS_ARE_BOOL,
    NO_STEP_AFTER_END,
    OBS_IN_SPACE,
    RESET_SIGNATURE,
    STEP_SIGNATURE,
)

RUN_COMPLETED = "run_completed"
EPISODES_END = "episodes_end"
DETERMINISM = "determinism"
SEED_CHANGES_START = "seed_changes_start"

_PASSED_MESSAGES = {
    RESET_SIGNATURE: "every reset() returned (obs, info) with a dict info",
    STEP_SIGNATURE: "every step() returned (obs, reward, terminated, truncated, info)",
    FLAGS_ARE_BOOL: "terminated and truncated were always bool",
    OBS_IN_SPACE: "every observation lay in the observation space",
    NO_STEP_AFTER_END: "the loop reset every env before stepping it again after an episode ended",
}
# The same checks on PettingZoo envs (their records carry agent_counts).
_PASSED_MESSAGES_AGENTS = {
    RESET_SIGNATURE: "every reset() returned None (AEC) or (observations, infos) (parallel)",
    STEP_SIGNATURE: "every last() returned (observation, reward, termination, truncation, info) and every "
    "parallel step() five dicts",
    FLAGS_ARE_BOOL: "terminations and truncations were always bool",
}


def evaluate(
    run: RunRecord, same_seed: RunRecord | None, other_seed: RunRecord | None, timeout: float
) -> tuple[CheckResult, ...]:
    repeatable = determinism(run, same_seed)
    if repeatable.passed:
        changed = seed_changes_start(run, other_seed)
    else:  # when one seed already gives two outcomes, comparing two seeds says nothing
        changed = CheckResult.skip(SEED_CHANGES_START, "not checked: two runs with the same seed already differ")
    return (*contract_checks(run), run_completed(run), episodes_end(run, timeout), repeatable, changed)


def contract_checks(run: RunRecord) -> tuple[CheckResult, ...]:
    charged = {name: (message, count) for name, message, count in run.violations}
    multi_agent = [env.agent_counts is not None for env in run.envs]
    results = []
    for name, passed_message in _PASSED_MESSAGES.items():
        if any(multi_agent) and name in _PASSED_MESSAGES_AGENTS:
            agents_message = _PASSED_MESSAGES_AGENTS[name]
            passed_message = agents_message if all(multi_agent) else f"Gym envs: {passed_message}; PettingZoo envs: {agents_message}"
        if name in charged:
            message, count = charged[name]
            results.append(CheckResult.fail(name, message + (f" ({count} times)" if count > 1 else "")))
        else:
            results.append(CheckResult.ok(name, passed_message))
    return tuple(results)


def run_completed(run: RunRecord) -> CheckResult:
    if run.stopped_by == "error":
        return CheckResult.fail(RUN_COMPLETED, f"the run raised {run.error}")
    if run.stopped_by == "timeout":
        return CheckResult.skip(RUN_COMPLETED, "the run was stopped at the timeout (see episodes_end)")
    how = "stopped cleanly when the budget was spent" if run.stopped_by == "budget" else "ran to its end"
    return CheckResult.ok(RUN_COMPLETED, f"the run {how} without raising")


def episodes_end(run: RunRecord, timeout: float) -> CheckResult:
    counts = _counts(run.envs)
    ended = counts[Ending.TERMINATED] + counts[Ending.TRUNCATED]
    tally = (
        f"{counts[Ending.TERMINATED]} terminated, {counts[Ending.TRUNCATED]} truncated, "
        f"{counts[Ending.BUDGET]} stopped by budget"
    )
    if run.stopped_by == "timeout":
        return CheckResult.fail(
            EPISODES_END,
            f"the loop never ended: still running after {timeout:g} s, with {run.steps} steps and "
            f"{ended} episodes ended ({tally})",
        )
    if run.steps and ended == 0 and run.stopped_by == "budget":
        return CheckResult.fail(
            EPISODES_END,
            f"the loop never ended: {run.steps} steps ran and no episode terminated or truncated ({tally})",
        )
    if ended == 0:
        return CheckResult.skip(EPISODES_END, f"no episode ended before the run stopped ({tally})")
    return CheckResult.ok(EPISODES_END, f"{ended} episode{'s' if ended != 1 else ''} ended: {tally}")


def determinism(run: RunRecord, again: RunRecord | None) -> CheckResult:
    if again is None:
        return CheckResult.skip(DETERMINISM, f"not checked: {_why_no_rerun(run)}")
    if not (run.stepped and again.stepped):
        return CheckResult.skip(DETERMINISM, "not checked: a run took no step")
    for first, second in zip(run.envs, again.envs):
        if first.first_transition != second.first_transition:
            return CheckResult.fail(
                DETERMINISM,
                f"two runs with seed {run.seed} gave different first transitions for env {first.index} "
                f"({_name(first)}): the env or the loop draws from an RNG that the seed does not reach "
                "(an env should draw from self.np_random, which reset(seed=...) seeds)",
            )
        for episode, replay in zip(first.episodes, second.episodes):
            if episode.digest != replay.digest or episode.ending != replay.ending:
                return CheckResult.fail(
                    DETERMINISM,
                    f"two runs with seed {run.seed} diverged in episode {episode.index + 1} of env "
                    f"{first.index} ({_name(first)}; {episode.length} and {replay.length} steps, ending "
                    f"{episode.ending.value} and {replay.ending.value}): the env or the loop draws from an RNG "
                    "that the seed does not reach",
                )
    if len(run.envs) != len(again.envs):
        return CheckResult.fail(
            DETERMINISM, f"two runs with seed {run.seed} drove {len(run.envs)} and {len(again.envs)} envs"
        )
    episodes = sum(len(env.episodes) for env in run.envs)
    return CheckResult.ok(
        DETERMINISM, f"two runs with seed {run.seed} gave identical first transitions and {episodes} identical episodes"
    )


def seed_changes_start(run: RunRecord, other: RunRecord | None) -> CheckResult:
    if other is None:
        return CheckResult.skip(SEED_CHANGES_START, f"not checked: {_why_no_rerun(run)}")
    if not (run.envs and other.envs and run.envs[0].episodes and other.envs[0].episodes):
        return CheckResult.skip(SEED_CHANGES_START, "not checked: a run finished no episode")
    env, changed = run.envs[0], other.envs[0]
    start, changed_start = env.episodes[0].start, changed.episodes[0].start
    if env.seed_source == "script":
        return CheckResult.skip(
            SEED_CHANGES_START,
            f"not checked: the script seeds {_name(env)} itself (reset(seed={env.reset_seed})), "
            "so --seed cannot change its episodes",
        )
    if start != changed_start:
        return CheckResult.ok(
            SEED_CHANGES_START, f"seed {other.seed} gives a different first observation than seed {run.seed}"
        )
    if all(episode.start == start for episode in env.episodes):
        return CheckResult.ok(
            SEED_CHANGES_START,
            f"deterministic start: {_name(env)} begins every episode from the same observation, "
            "so the seed cannot change it",
        )
    return CheckResult.fail(
        SEED_CHANGES_START,
        f"seeds {run.seed} and {other.seed} give the same first observation although later resets vary: "
        f"{_name(env)} ignores the seed passed to reset() (seed self.np_random with super().reset(seed=seed))",
    )


def _why_no_rerun(run: RunRecord) -> str:
    if run.stopped_by == "timeout":
        return "the first run hit the timeout, so it was not repeated"
    if not run.stepped:
        return "the first run took no step, so it was not repeated"
    return "the run was not repeated (--no-determinism)"


def _counts(envs: tuple[EnvRecord, ...]) -> dict[Ending, int]:
    counts = {ending: 0 for ending in Ending}
    for env in envs:
        for episode in env.episodes:
            counts[episode.ending] += 1
    return counts


def _name(env: EnvRecord) -> str:
    return env.env_id or env.env_class
