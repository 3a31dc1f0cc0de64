"""What a Gym-era requirement becomes: one decision per package, shared by every file format.

A requirement is read with ``packaging`` (name, extras, specifier, marker, URL); the
decision says which package, extras and specifier to write, and what to report. The
formats only locate requirements and put the new text back (``render_pep508`` for
requirement strings; Poetry renders its own table entries).

The versions below were read from the packages' own metadata (``Requires-Dist`` and
``Provides-Extra`` of the wheels on PyPI), see docs/dependencies.md.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from packaging.requirements import InvalidRequirement, Requirement
from packaging.specifiers import InvalidSpecifier, SpecifierSet
from packaging.utils import canonicalize_name
from packaging.version import Version

from gymmigrate.findings import FixKind

GYM_PACKAGE = "GM109"  # gym and Gym-era packages rewritten to their Gymnasium successors
GYM_ONLY = "GM110"  # Gym-only packages and requirements that cannot be read: reported, never rewritten
PINS = "SB110"  # libraries that moved to Gymnasium with it: pins raised to a Gymnasium-1.x release

GYMNASIUM_SPEC = ">=1.0"
ALE_SPEC = ">=0.9"  # what gymnasium 1.4's `atari` extra requires (ale_py>=0.9)
GYMNASIUM_TARGET = Version("1.4.0")

# gym extra (canonical name) -> gymnasium 1.4 extra (None: dropped). Gymnasium 1.4's
# Provides-Extra: atari, box2d, classic-control, mujoco, toy-text, jax, torch,
# array-api, other, all, testing.
GYM_EXTRAS: dict[str, str | None] = {
    "atari": "atari",
    "accept-rom-license": None,  # the ROMs ship with ale-py; Gymnasium 1.0 dropped the extra
    "box2d": "box2d",
    "classic-control": "classic-control",
    "toy-text": "toy-text",
    "mujoco": "mujoco",
    "mujoco-py": "mujoco",
    "other": "other",
    "all": "all",
    "testing": "testing",
}
GYMNASIUM_EXTRAS = frozenset({"atari", "box2d", "classic-control", "mujoco", "toy-text", "jax", "torch", "array-api", "other", "all", "testing"})

# Libraries that moved to Gymnasium with it: a pin that excludes the release that supports
# Gymnasium 1.x (``current``, the newest checked) is raised to ``minimum``.
MOVED_WITH_GYM: dict[str, tuple[str, str, str]] = {
    # name: (minimum spec, newest release checked, why)
    "stable-baselines3": (">=2.9", "2.9.2", "SB3 2.9 is the first release that accepts Gymnasium 1.3/1.4 (gymnasium<2.0)"),
    "sb3-contrib": (">=2.9", "2.9.2", "sb3-contrib follows SB3 (2.9.2 requires stable_baselines3>=2.9.2)"),
    "pettingzoo": (">=1.25", "1.27.0", "PettingZoo 1.25 is the first release that requires gymnasium>=1.0"),
    "supersuit": (">=3.10", "3.11.0", "SuperSuit 3.10 is the first release that requires gymnasium>=1.0"),
    "shimmy": (">=2.0", "2.0.1", "Shimmy 2.0 is the first release that requires gymnasium>=1.0"),
    "minigrid": (">=3.0", "3.2.0", "MiniGrid 3.0 is the release made for Gymnasium 1.0"),
}

# Render and physics packages that gym's and PettingZoo 1.2x's extras pinned exactly
# (gym 0.26: pygame==2.1.0, box2d-py==2.3.5; PettingZoo 1.21/1.22: pygame==2.1.0,
# pymunk==6.2.0): projects copied those pins, which have no wheel for Python 3.11 and which
# the Gymnasium-1.x stack does not accept. A pin that admits none of ``releases`` (the ones
# Gymnasium 1.4's and PettingZoo 1.27's extras accept, read from their wheels' Requires-Dist)
# becomes ``name spec``.
ERA_PINS: dict[str, tuple[str, str, tuple[str, ...], str]] = {
    # old name: (new name, new spec, releases the new stack accepts, why)
    "pygame": (
        "pygame-ce",
        ">=2.3",
        ("2.3.0", "2.4.0", "2.5.2", "2.6.1"),
        "Gymnasium 1.4's extras, PettingZoo 1.27's and mpe2 depend on `pygame-ce` (>=2.3.0 for PettingZoo), the maintained "
        "fork that provides the same `pygame` module; pygame before 2.1.3 has no wheel for Python 3.11, and `pygame` next to "
        "`pygame-ce` puts two copies of the module in one environment",
    ),
    "pymunk": (
        "pymunk",
        ">=6.2.0",
        ("6.3.0", "6.11.1", "7.3.1"),
        "PettingZoo 1.27's butterfly and sisl envs require pymunk>=6.2.0; pymunk 6.2.x has no wheel for Python 3.11",
    ),
    "box2d-py": (
        "box2d",
        "==2.3.10",
        ("2.3.8",),
        "Gymnasium 1.4's box2d extra requires `box2d==2.3.10` (the same `Box2D` module, with wheels); box2d-py 2.3.5 builds "
        "only with swig and installing both puts two copies of `Box2D` in one environment",
    ),
}

# Packages that left a declared library: what the migrated code imports -> (the library it
# came out of, the requirement to add next to it, why). mpe2 1.0 is the first release;
# mpe2 1.1.1 requires pettingzoo>=1.24.3 (its wheel's Requires-Dist).
COMPANIONS: dict[str, tuple[str, str, str]] = {
    "mpe2": ("pettingzoo", "mpe2>=1.0", "PettingZoo's MPE envs moved to the mpe2 package"),
    # gym 0.26's MuJoCo envs rendered without imageio; importing anything under
    # gymnasium.envs.mujoco (1.x) imports its renderer, which imports imageio at load time.
    # gymnasium[mujoco] requires imageio>=2.14.1: the same bound.
    "imageio": ("mujoco", "imageio>=2.14.1", "Gymnasium 1.x's MuJoCo envs import imageio with their renderer"),
}

# Renamed packages: old name -> (new requirement head, message).
RENAMED: dict[str, tuple[str, str]] = {
    "gym-minigrid": ("minigrid>=3.0", "gym-minigrid is now minigrid (imports change: `gym_minigrid` -> `minigrid`, and `import minigrid` registers its envs)"),
}
# Packages that only fetched Atari ROMs or wrapped the old ALE: ale-py replaces them, and
# gymnasium[atari] already requires it.
ALE_PREDECESSORS = frozenset({"atari-py", "autorom", "autorom-accept-rom-license"})

# Packages written for the Gym API that no Gymnasium release replaces.
GYM_ONLY_PACKAGES: dict[str, str] = {
    "mujoco-py": "Gymnasium's MuJoCo envs (v4/v5) use the `mujoco` bindings (`gymnasium[mujoco]`); mujoco-py serves only the legacy v2/v3 envs",
    "gym-super-mario-bros": "a Gym-only env package",
    "nes-py": "a Gym-only env package",
    "gym-retro": "a Gym-only env package (its successor is stable-retro)",
    "procgen": "a Gym-only env package",
    "roboschool": "a Gym-only env package (abandoned)",
    "pybullet-envs": "a Gym-only env package",
    "dmc2gym": "a Gym-only env package (Shimmy's dm_control envs replace it)",
    "dm2gym": "a Gym-only env package (Shimmy's dm_control envs replace it)",
    "slimevolleygym": "a Gym-only env package",
    "gym-ignition": "a Gym-only env package (archived): its runtimes derive legacy gym.Env",
    "universe": "OpenAI universe, abandoned and built on gym 0.9: its wrappers and remote envs keep gym's old API",
    "safety-gym": "a Gym-only env package (archived; its successor is safety-gymnasium)",
    "pybullet": "if the project uses its bundled envs (pybullet_envs), they register with Gym only",
    "gym-notices": "a dependency of gym only, not needed by Gymnasium: remove it",
    # ptan 0.7 requires gym and atari-py; ptan 0.8.1 requires gymnasium>=0.29 but pins
    # stable-baselines3==2.3.2, whose wheel requires gymnasium<0.30 (both wheels' metadata).
    "ptan": (
        "no ptan release installs with Gymnasium 1.x (0.7 requires gym; 0.8.1 pins stable-baselines3==2.3.2, "
        "which requires gymnasium<0.30): port the parts the code uses, or keep this project on gym"
    ),
}
# Gym-only packages for which Shimmy's route does not apply (not env packages).
NO_SHIMMY_ROUTE = frozenset({"gym-notices", "ptan"})
MUJOCO_IMAGEIO = (
    "`mujoco` alone does not run Gymnasium 1.x's MuJoCo envs: their renderer imports `imageio` (ModuleNotFoundError at "
    "make); add `imageio>=2.14.1` next to it, or depend on `gymnasium[mujoco]`, which requires both"
)
SHIMMY_ROUTE = 'keep it on Gym through Shimmy (`shimmy[gym-v21]` or `shimmy[gym-v26]`, then `gymnasium.make("GymV21Environment-v0", env_id=...)`) or port it'

_GYM_WORD = re.compile(r"(?<![A-Za-z0-9])(gym|atari[-_]py|autorom|mujoco[-_]py|stable[-_]baselines3?|pettingzoo|supersuit)(?![A-Za-z0-9])", re.I)


def mentions_gym(text: str) -> bool:
    return _GYM_WORD.search(text) is not None


@dataclass(frozen=True)
class Note:
    code: str
    kind: FixKind
    message: str


@dataclass
class Decision:
    """What to do with one requirement. ``name`` is None: leave it as it is."""

    name: str | None = None
    extras: list[str] = field(default_factory=list)
    specifier: str = ""
    notes: list[Note] = field(default_factory=list)
    ale: bool = False  # the requirement only brings ale-py: redundant next to gymnasium[atari]

    @property
    def rewrites(self) -> bool:
        return self.name is not None


def parse(text: str) -> Requirement | None:
    try:
        return Requirement(text)
    except InvalidRequirement:
        return None


def decide(requirement: Requirement) -> Decision:
    """The decision for one parsed requirement (URL requirements are only reported)."""
    name = canonicalize_name(requirement.name)
    extras: list[str] = sorted(canonicalize_name(extra) for extra in requirement.extras)
    if requirement.url:
        if name in ("gym",) or name in MOVED_WITH_GYM or name in RENAMED or name in ALE_PREDECESSORS or name in GYM_ONLY_PACKAGES:
            return Decision(notes=[Note(GYM_ONLY, FixKind.FLAG, f"`{requirement.name}` is installed from a URL; point it at a Gymnasium-1.x release by hand")])
        return Decision()
    if name == "gym":
        return _gym(requirement, extras)
    if name == "gymnasium":
        return _gymnasium(requirement, extras)
    if name in MOVED_WITH_GYM:
        return _moved(requirement, name, extras)
    if name in RENAMED:
        head, why = RENAMED[name]
        new = Requirement(head)
        return Decision(new.name, extras, str(new.specifier), [Note(GYM_PACKAGE, FixKind.ASSIST, f"`{requirement.name}` -> `{head}`: {why}")])
    if name in ALE_PREDECESSORS:
        return Decision(
            "ale-py",
            [],
            ALE_SPEC,
            [Note(GYM_PACKAGE, FixKind.AUTO, f"`{requirement}` -> `ale-py{ALE_SPEC}`: Atari ROMs ship with ale-py, no licence step or ROM download is needed")],
            ale=True,
        )
    if name in ERA_PINS:
        return _era_pin(requirement, name)
    if name == "mujoco" and not extras:
        # gym 0.26's MuJoCo envs rendered without imageio; Gymnasium 1.x's import it with
        # their renderer (gymnasium[mujoco] requires imageio>=2.14.1).
        return Decision(notes=[Note(GYM_ONLY, FixKind.FLAG, MUJOCO_IMAGEIO)])
    if name in GYM_ONLY_PACKAGES:
        route = "" if name in NO_SHIMMY_ROUTE else f"; {SHIMMY_ROUTE}"
        return Decision(notes=[Note(GYM_ONLY, FixKind.FLAG, f"`{requirement.name}`: {GYM_ONLY_PACKAGES[name]}{route}")])
    return Decision()


MIGRATE_WITH_IT = "the code must be migrated with it (imports, reset/step API)"
# ...and what it says where the same run migrates the code beside the file.
MIGRATED_WITH_IT = "the code beside it is migrated with it in the same run (imports, reset/step API)"
ROMS_SHIP_WITH_ALE = "`accept-rom-license` is gone: the ROMs ship with ale-py"


def only_describes_gym_pin(message: str) -> bool:
    """A GM109 message on gym's pin whose every reason describes the rewrite (the code moves
    with it, the ROM licence extra is gone): where the same document's code is migrated in
    the same run (a notebook's ``!pip install``), nothing is left to decide."""
    head, _, reasons = message.partition(": ")
    return head.endswith("`") and bool(reasons) and set(reasons.split("; ")) <= {MIGRATE_WITH_IT, ROMS_SHIP_WITH_ALE}


def _gym(requirement: Requirement, extras: list[str]) -> Decision:
    notes: list[Note] = []
    new_extras: list[str] = []
    dropped: list[str] = []
    for extra in extras:
        mapped = GYM_EXTRAS.get(extra)
        if mapped is None:
            dropped.append(extra)
        elif mapped not in new_extras:
            new_extras.append(mapped)
    message = f"`{requirement}` -> `gymnasium{_extras(new_extras)}{GYMNASIUM_SPEC}`"
    kind = FixKind.ASSIST
    reasons = [MIGRATE_WITH_IT]
    if "accept-rom-license" in dropped:
        reasons.append(ROMS_SHIP_WITH_ALE)
        dropped.remove("accept-rom-license")
    if "mujoco" in extras or "mujoco-py" in extras:
        reasons.append("gym's `mujoco` extra meant mujoco-py (v2/v3 envs); gymnasium[mujoco] uses the `mujoco` bindings and v4/v5 envs")
    if "robotics" in dropped:
        reasons.append("the robotics envs moved to the `gymnasium-robotics` package")
        dropped.remove("robotics")
    if dropped:
        reasons.append("extras Gymnasium 1.4 does not have were dropped: " + ", ".join(dropped))
    notes.append(Note(GYM_PACKAGE, kind, f"{message}: {'; '.join(reasons)}"))
    return Decision("gymnasium", sorted(new_extras), GYMNASIUM_SPEC, notes)


GYMNASIUM_1X = tuple(Version(v) for v in ("1.0.0", "1.1.1", "1.2.0", "1.3.0", "1.4.0"))


def _gymnasium(requirement: Requirement, extras: list[str]) -> Decision:
    """Already Gymnasium. A pin that admits no 1.x release is raised to ``>=1.0``; one that
    admits 1.x but not 1.4 is the project's choice and only reported; unknown extras are
    reported; ``accept-rom-license`` is dropped."""
    notes: list[Note] = []
    unknown = [extra for extra in extras if extra not in GYMNASIUM_EXTRAS and extra != "accept-rom-license"]
    if unknown:
        notes.append(Note(GYM_ONLY, FixKind.FLAG, f"`{requirement}`: Gymnasium 1.4 has no extra {', '.join(unknown)}"))
    specifier = requirement.specifier
    admits_1x = any(specifier.contains(version, prereleases=True) for version in GYMNASIUM_1X)
    rom_extra = "accept-rom-license" in extras
    if admits_1x and not specifier.contains(GYMNASIUM_TARGET, prereleases=True):
        notes.append(Note(PINS, FixKind.FLAG, f"`{requirement}` excludes Gymnasium 1.4; left as it is (another dependency may need the cap)"))
    if not rom_extra and admits_1x:
        return Decision(notes=notes)
    new_extras = sorted(extra for extra in requirement.extras if canonicalize_name(extra) != "accept-rom-license")
    spec = str(specifier) if admits_1x else GYMNASIUM_SPEC
    reasons = []
    if not admits_1x:
        reasons.append("the pin admitted no Gymnasium 1.x release")
    if rom_extra:
        reasons.append("`accept-rom-license` is gone: the ROMs ship with ale-py")
    notes.insert(0, Note(GYM_PACKAGE, FixKind.ASSIST, f"`{requirement}` -> `gymnasium{_extras(new_extras)}{spec}`: {'; '.join(reasons)}"))
    return Decision("gymnasium", new_extras, spec, notes)


def _moved(requirement: Requirement, name: str, extras: list[str]) -> Decision:
    minimum, current, why = MOVED_WITH_GYM[name]
    if requirement.specifier.contains(Version(current), prereleases=True):
        return Decision()
    new_name = requirement.name
    message = f"`{requirement}` -> `{new_name}{_extras(sorted(requirement.extras))}{minimum}`: {why}"
    return Decision(new_name, sorted(requirement.extras), minimum, [Note(PINS, FixKind.ASSIST, message)])


def _era_pin(requirement: Requirement, name: str) -> Decision:
    """A Gym-era exact pin of a render or physics package, raised to what the new stack
    accepts. An unpinned requirement, or one that admits a current release, is left
    (box2d-py 2.3.8 is what Gymnasium itself takes on Python 3.14)."""
    new_name, spec, releases, why = ERA_PINS[name]
    if not requirement.specifier:
        return Decision()
    if any(requirement.specifier.contains(Version(v), prereleases=True) for v in releases):
        return Decision()
    extras = sorted(requirement.extras)
    message = f"`{requirement}` -> `{new_name}{_extras(extras)}{spec}`: {why}"
    return Decision(new_name, extras, spec, [Note(PINS, FixKind.ASSIST, message)])


def _extras(extras: list[str]) -> str:
    return f"[{','.join(extras)}]" if extras else ""


def render_pep508(original: str, decision: Decision) -> str:
    """The requirement string with name, extras and specifier replaced; the marker (after
    ``;``) and the whitespace around it are kept as written."""
    head, separator, marker = original.partition(";")
    trailing = head[len(head.rstrip()) :]
    leading = head[: len(head) - len(head.lstrip())]
    return f"{leading}{decision.name}{_extras(decision.extras)}{decision.specifier}{trailing}{separator}{marker}"


def spec_admits_target(spec: str) -> bool:
    """Whether a PEP 440 specifier admits Gymnasium 1.4.0 (tests use it on every written spec)."""
    try:
        return SpecifierSet(spec).contains(GYMNASIUM_TARGET, prereleases=True)
    except InvalidSpecifier:
        return False
