"""The settings of one run that change what the rules write (not how files are found)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from gymmigrate.facts.project import ProjectFacts
    from gymmigrate.selection import Selection


@dataclass(frozen=True)
class RewriteOptions:
    """Settings that change what the rules write (not how files are found)."""

    seed: int | None = None
    selection: Selection | None = None  # --select/--ignore; None: every rule
    # Facts across the files of the run (facts/project.py); None for a file on its own.
    project: ProjectFacts | None = field(default=None, compare=False)
