"""Why an env's ``done`` is True, as ``DoneTracer`` (limits.py) answers it: a ``Cause``
(never, a termination, a truncation, both, unknown) with the ``Limit`` tests it found, and
how the causes of alternatives combine.
"""

from __future__ import annotations

import enum
from collections.abc import Iterable
from dataclasses import dataclass


class Cause(enum.Enum):
    NEVER = "never"  # ``False``: ends nothing
    TERMINATION = "termination"
    TRUNCATION = "truncation"
    MIXED = "mixed"  # some causes a limit, some the task's end
    UNKNOWN = "unknown"  # a limit mixed in some other way, or not a flag (a dict)


@dataclass(frozen=True)
class Limit:
    line: int
    text: str
    where: str = ""  # another module of the run ("HoverAviary.py"); "" for this one
    by_counter: bool = False  # found as a count ``step`` advances, not by its name
    # attributes of its bound the class draws at random (a horizon per episode, maybe the task's)
    drawn: tuple[str, ...] = ()

    def place(self) -> str:
        return f"{self.where}:{self.line}" if self.where else f"line {self.line}"


@dataclass(frozen=True)
class DoneCause:
    cause: Cause
    limits: tuple[Limit, ...] = ()
    # tests of the end of the env's data among the causes (``is_end_of_data``): terminations
    ends_of_data: tuple[Limit, ...] = ()
    # values read off an object the env holds (``self._env.episode_over``): that object
    # decides the end by itself, on limits of its own this class never shows
    held: tuple[Limit, ...] = ()

    def elsewhere(self) -> bool:
        return any(limit.where for limit in self.limits)

    def plain(self) -> bool:
        """Every limit is named as one and in this module: settled, not a question."""
        return not any(limit.where or limit.by_counter or limit.drawn for limit in self.limits)

    def drawn(self) -> tuple[str, ...]:
        """The attributes drawn at random that bound its limits (``Limit.drawn``)."""
        return tuple(dict.fromkeys(a for limit in self.limits for a in limit.drawn))


NEVER = DoneCause(Cause.NEVER)
TERMINATION = DoneCause(Cause.TERMINATION)


def combine(parts: Iterable[DoneCause]) -> DoneCause:
    """The cause of a value that is true when any of ``parts`` is (an ``or``, or the
    alternatives: several returns, several stores)."""
    parts = list(parts)
    limits: list[Limit] = []
    ends: list[Limit] = []
    held: list[Limit] = []
    for part in parts:
        limits += [limit for limit in part.limits if limit not in limits]
        ends += [end for end in part.ends_of_data if end not in ends]
        held += [read for read in part.held if read not in held]
    causes = {part.cause for part in parts} - {Cause.NEVER}
    if not causes:
        return DoneCause(Cause.NEVER, tuple(limits), tuple(ends), tuple(held))
    if Cause.UNKNOWN in causes:
        cause = Cause.UNKNOWN
    elif len(causes) == 1:
        cause = causes.pop()
    else:
        cause = Cause.MIXED
    return DoneCause(cause, tuple(limits), tuple(ends), tuple(held))
