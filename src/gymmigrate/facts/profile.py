"""Cheap facts about a file's imports, read from its text before parsing."""

from __future__ import annotations

import re
from dataclasses import dataclass


@dataclass(frozen=True)
class FileProfile:
    """Cheap facts about a file's imports, read from its text before parsing."""

    imports_gym: bool
    imports_gymnasium: bool
    imports_sb3: bool
    imports_pettingzoo: bool

    @classmethod
    def from_source(cls, source: str) -> FileProfile:
        return cls(
            imports_gym=bool(_IMPORT_RE["gym"].search(source)),
            imports_gymnasium=bool(_IMPORT_RE["gymnasium"].search(source)),
            imports_sb3=bool(_IMPORT_RE["sb3"].search(source)),
            imports_pettingzoo=bool(_IMPORT_RE["pettingzoo"].search(source)),
        )

    @property
    def gym_only(self) -> bool:
        """The file uses Gym and none of the libraries whose envs keep other APIs.

        In such a file an env-like name of unknown origin is, in practice, a Gym env;
        rules may rewrite it as ASSIST (with a review item) instead of only flagging it.
        """
        return (self.imports_gym or self.imports_gymnasium) and not (self.imports_sb3 or self.imports_pettingzoo)


_IMPORT_RE = {
    "gym": re.compile(r"^\s*(?:import\s+gym\b|from\s+gym(?:\.|\s+import\b))", re.M),
    "gymnasium": re.compile(r"^\s*(?:import\s+gymnasium\b|from\s+gymnasium\b)", re.M),
    # Every VecEnv family: Stable-Baselines3, stable_baselines 2.x, OpenAI baselines.
    "sb3": re.compile(r"^\s*(?:import|from)\s+(?:stable_baselines3?|sb3_contrib|baselines)\b", re.M),
    "pettingzoo": re.compile(r"^\s*(?:import|from)\s+(?:pettingzoo|supersuit)\b", re.M),
}
