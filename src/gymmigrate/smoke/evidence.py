"""The evidence a smoke check leaves behind: frozen records that become one JSON file.

The JSON is the artifact a reviewer re-runs: everything in it is a function of the
target, the seed and the budget, except the ``timings`` block, so two runs with the
same seed produce identical files once ``timings`` is dropped.
"""

from __future__ import annotations

import json
import platform
from dataclasses import asdict, dataclass, field
from enum import Enum
from importlib import metadata
from pathlib import Path

from gymmigrate import __version__

EXIT_OK = 0
EXIT_CHECK_FAILED = 1
EXIT_NOT_RUN = 2


class Outcome(str, Enum):
    PASSED = "passed"
    FAILED = "failed"
    SKIPPED = "skipped"  # the check could not apply (say, no second run to compare with)


class Ending(str, Enum):
    """Why an episode stopped."""

    TERMINATED = "terminated"
    TRUNCATED = "truncated"
    BUDGET = "stopped by budget"  # --episodes / --max-steps reached mid-episode
    INTERRUPTED = "interrupted"  # the run crashed, timed out or returned mid-episode
    RESET = "reset before the end"  # the loop called reset() mid-episode


@dataclass(frozen=True)
class CheckResult:
    name: str
    outcome: Outcome
    message: str

    @property
    def passed(self) -> bool:
        return self.outcome is not Outcome.FAILED

    @classmethod
    def ok(cls, name: str, message: str) -> CheckResult:
        return cls(name, Outcome.PASSED, message)

    @classmethod
    def fail(cls, name: str, message: str) -> CheckResult:
        return cls(name, Outcome.FAILED, message)

    @classmethod
    def skip(cls, name: str, message: str) -> CheckResult:
        return cls(name, Outcome.SKIPPED, message)


@dataclass(frozen=True)
class EpisodeRecord:
    index: int
    length: int
    episode_return: float
    ending: Ending
    start: str  # sha256 of the first observation
    digest: str  # sha256 of the first observation and every transition: compare runs with it

    def to_json(self) -> dict[str, object]:
        return {
            "index": self.index,
            "length": self.length,
            "return": self.episode_return,
            "ending": self.ending.value,
            "start": self.start,
            "digest": self.digest,
        }


@dataclass(frozen=True)
class EnvRecord:
    """One env the loop drove (a vector env's sub-envs each get a record)."""

    index: int
    env_id: str | None
    env_class: str
    wrappers: tuple[str, ...]  # outermost first, ending with the env class
    render_mode: str | None
    reset_seed: int | None  # the seed of the first reset
    seed_source: str  # "script": the code passed it; "smoke": the shim supplied it; "none"
    steps: int
    episodes: tuple[EpisodeRecord, ...]
    first_transition: str | None  # digest of the first reset and first step
    # PettingZoo envs: per agent, episodes that ended for it by termination and by truncation.
    agent_counts: dict[str, dict[str, int]] | None = None

    def counts(self) -> dict[str, int]:
        return _count_endings(self.episodes)

    def to_json(self) -> dict[str, object]:
        return {
            "index": self.index,
            "env_id": self.env_id,
            "env_class": self.env_class,
            "wrappers": list(self.wrappers),
            "render_mode": self.render_mode,
            "reset_seed": self.reset_seed,
            "seed_source": self.seed_source,
            "steps": self.steps,
            "counts": self.counts(),
            "first_transition": self.first_transition,
            "episodes": [episode.to_json() for episode in self.episodes],
        } | ({"agent_counts": self.agent_counts} if self.agent_counts is not None else {})


@dataclass(frozen=True)
class RunRecord:
    """What one run (one drive of the episodes, or one script execution) observed."""

    seed: int
    envs: tuple[EnvRecord, ...]
    stopped_by: str  # "finished" | "budget" | "error" | "timeout"
    error: str | None = None  # one sentence: exception type, message and place
    warnings: tuple[str, ...] = ()
    violations: tuple[tuple[str, str, int], ...] = ()  # (check name, first message, count)
    steps: int = 0
    calls: int = 0  # reset/step calls the loop made (0: it never got to drive an env)
    steps_after_end: int = 0
    vector_envs: tuple[str, ...] = ()  # vector env classes the code built
    seconds: float = 0.0

    @property
    def stepped(self) -> bool:
        return self.steps > 0


@dataclass(frozen=True)
class Evidence:
    target: str
    target_kind: str  # "env-id" | "class" | "script"
    seed: int
    episodes: int
    max_steps: int
    timeout: float
    run: RunRecord | None
    checks: tuple[CheckResult, ...] = ()
    load_error: str | None = None
    created_no_env: bool = False  # a script that ran to its end without driving an env
    timings: dict[str, float] = field(default_factory=dict)

    @property
    def exit_code(self) -> int:
        if self.load_error is not None:
            return EXIT_NOT_RUN
        return EXIT_OK if all(check.passed for check in self.checks) else EXIT_CHECK_FAILED

    @property
    def failed_checks(self) -> tuple[CheckResult, ...]:
        return tuple(check for check in self.checks if not check.passed)

    def to_json(self) -> dict[str, object]:
        envs = self.run.envs if self.run else ()
        first = envs[0] if envs else None
        return {
            "tool": "gymmigrate smoke",
            "target": self.target,
            "target_kind": self.target_kind,
            "env_id": first.env_id if first else None,
            "wrappers": list(first.wrappers) if first else [],
            "render_mode": first.render_mode if first else None,
            "seed": self.seed,
            "budget": {"episodes": self.episodes, "max_steps": self.max_steps, "timeout_seconds": self.timeout},
            "versions": library_versions(),
            "outcome": _OUTCOME_NAMES[self.exit_code],
            "exit_code": self.exit_code,
            "load_error": self.load_error,
            "run": None
            if self.run is None
            else {
                "stopped_by": self.run.stopped_by,
                "error": self.run.error,
                "steps": self.run.steps,
                "steps_after_end": self.run.steps_after_end,
                "vector_envs": list(self.run.vector_envs),
                "warnings": list(self.run.warnings),
            },
            "counts": _count_endings(tuple(episode for env in envs for episode in env.episodes)),
            "envs": [env.to_json() for env in envs],
            "checks": [
                {"name": check.name, "outcome": check.outcome.value, "message": check.message} for check in self.checks
            ],
            "timings": self.timings,
        }

    def write(self, path: Path) -> None:
        path.write_text(json.dumps(self.to_json(), indent=2) + "\n", encoding="utf-8")


_OUTCOME_NAMES = {EXIT_OK: "passed", EXIT_CHECK_FAILED: "failed", EXIT_NOT_RUN: "not run"}


def _count_endings(episodes: tuple[EpisodeRecord, ...]) -> dict[str, int]:
    counts = {ending.value: 0 for ending in Ending}
    for episode in episodes:
        counts[episode.ending.value] += 1
    return counts


def library_versions() -> dict[str, str]:
    return {
        "gymnasium": _installed("gymnasium"),
        "numpy": _installed("numpy"),
        "python": platform.python_version(),
        "gymmigrate": __version__,
    }


def _installed(distribution: str) -> str:
    try:
        return metadata.version(distribution)
    except metadata.PackageNotFoundError:
        return "not installed"


def records_to_json(run: RunRecord) -> dict[str, object]:
    """A run as plain JSON: how the script child hands its observations to the parent."""
    return asdict(run)


def run_from_json(data: dict) -> RunRecord:
    envs = tuple(
        EnvRecord(
            **{
                **env,
                "wrappers": tuple(env["wrappers"]),
                "episodes": tuple(
                    EpisodeRecord(**{**episode, "ending": Ending(episode["ending"])}) for episode in env["episodes"]
                ),
            }
        )
        for env in data["envs"]
    )
    return RunRecord(
        **{
            **data,
            "envs": envs,
            "warnings": tuple(data["warnings"]),
            "violations": tuple(tuple(v) for v in data["violations"]),
            "vector_envs": tuple(data["vector_envs"]),
        }
    )
