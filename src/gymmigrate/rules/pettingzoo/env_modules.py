"""PZ111: PettingZoo env modules that moved to their own package or were bumped to a new version.

PettingZoo 1.21 shipped ``pettingzoo.mpe`` (``simple_spread_v2``...) and older versions of
several envs. On PettingZoo 1.27:

- ``pettingzoo.mpe`` only raises ``ImportError`` ("MPE has been moved into its own package:
  MPE2"): the envs live in the ``mpe2`` package (``from mpe2 import simple_spread_v3``),
  ``pettingzoo.magent`` likewise in ``magent2``.
- a superseded version still imports from its family, but its ``env()`` / ``parallel_env()``
  raise ``DeprecatedEnv: knights_archers_zombies_v10 is now deprecated, use
  knights_archers_zombies_v11 instead`` (so only an older version the file reads is a
  question; one per statement names them all); importing from the old env module itself
  (``from pettingzoo.atari.pong_v1 import env``) fails; an env removed outright raises on import.

A version bump is a change of behaviour, so the table below says, per env, which old
version is the known predecessor of the current one and what changed between them (read
from each env's "Version History" and from the sources of PettingZoo 1.21.0, 1.22.3,
1.24.3, 1.27.0 and mpe2 1.1.1). The import (and every read of the name it binds) is
rewritten to the current version only from that predecessor; the finding says what the
new version does differently, and calls that pass a keyword the new version no longer
takes are reported. Older versions, removed envs and packages whose layout was not
checked are reported, never rewritten.
"""

from __future__ import annotations

import ast
import re
from dataclasses import dataclass, field

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext
from gymmigrate.rules.pettingzoo.common import PZ111, PettingZooFamily

_ENV_NAME = re.compile(r"^([a-z_]+?)_v(\d+)$")

# Families that left PettingZoo: old package -> (new package, whether the env table below
# covers it). MAgent2's modules were not checked, so its imports are only reported.
MOVED_FAMILIES = N.PZ_MOVED_FAMILIES

_MPE_V3 = ("positions now integrate before the velocity update, so trajectories and rewards differ from "
           "v{old} for the same seed and actions, and continuous actions move the same way as the discrete "
           "ones (their left/right and down/up components were reversed); spaces, agents and arguments are "
           "unchanged (mpe2 adds `dynamic_rescaling`, a rendering option)")


@dataclass(frozen=True)
class Bump:
    """The current version of an env, the old version it replaced, and what changed."""

    current: int
    previous: int
    change: str
    # keyword of the old version -> {its literal value (ANY: whatever it is): the new
    # (keyword, value source) it means, ("", "") to drop it}; a value not listed, or a
    # keyword mapped to None, has no certain equivalent and is reported
    keywords: dict[str, dict[object, tuple[str, str | None]] | None] = field(default_factory=dict)
    # envs whose bumps change the same thing (MPE's move to mpe2): one decision for a file
    # that imports several of them, asked once (the change text differs only in the version)
    group: str = ""

    @property
    def removed_keywords(self) -> tuple[str, ...]:
        return tuple(self.keywords)


ANY = object()  # any value: the keyword is renamed, its value kept (value source None)
DROP = ("", "")
# The env factories a module-level env exposes.
FACTORIES = frozenset({"env", "parallel_env", "raw_env"})


# (family module, env name) -> its bump. Families: the package the env is imported from
# in PettingZoo 1.21 (``pettingzoo.mpe``'s envs now come from ``mpe2``).
BUMPS: dict[tuple[str, str], Bump] = {
    **{("pettingzoo.mpe", name): Bump(3, 2, _MPE_V3.format(old=2), group="mpe2") for name in (
        "simple", "simple_adversary", "simple_crypto", "simple_push", "simple_reference",
        "simple_spread", "simple_tag", "simple_world_comm")},
    ("pettingzoo.mpe", "simple_speaker_listener"): Bump(4, 3, _MPE_V3.format(old=3), group="mpe2"),
    ("pettingzoo.butterfly", "knights_archers_zombies"): Bump(
        11, 10, "v11 (PettingZoo 1.25.1) is a rewrite with numerous fixes: `spawn_rate` is `spawn_delay`, "
        "`vector_state`, `use_typemasks` and `transformer` became `obs_method` (default \"vector\"), "
        "`pad_observation` was removed",
        {
            # the same count of cycles between two zombies (the v10 docs said "rate")
            "spawn_rate": {ANY: ("spawn_delay", None)},
            # v10 images and v11's "image" are both Box(0, 255, (512, 512, 3), uint8); typemasked
            # vectors are (27, 11) in both
            "vector_state": {False: ("obs_method", '"image"'), True: ("obs_method", '"vector"')},
            "use_typemasks": {True: ("obs_method", '"vector-masked"'), False: DROP},
            "pad_observation": {True: DROP},  # v11 always pads
            "transformer": None,  # v11's "vector-sequence" is a Sequence space, not v10's Box
        }),
    ("pettingzoo.butterfly", "cooperative_pong"): Bump(
        6, 5, "v6 (PettingZoo 1.25.5) fixed an incorrect termination condition and the random bounce behaviour"),
    ("pettingzoo.classic", "chess"): Bump(
        6, 5, "v6 (PettingZoo 1.23.2) fixed which player starts, and insufficient material, the 50-move rule "
        "and threefold repetition now end the game"),
    ("pettingzoo.sisl", "pursuit"): Bump(5, 4, "v5 (PettingZoo 1.27.0) adds `state()` and a state space"),
}

# The env modules of PettingZoo 1.27's own families and their current versions (read from
# its package). An older version still imports from the family (``from pettingzoo.atari
# import pong_v2`` binds a ``DeprecatedModule``) and raises ``DeprecatedEnv`` only when
# its ``env()``/``parallel_env()`` is called: an import never read decides nothing.
CURRENT: dict[str, dict[str, int]] = {
    "pettingzoo.atari": {
        "basketball_pong": 3, "boxing": 2, "combat_plane": 2, "combat_tank": 2, "double_dunk": 3,
        "entombed_competitive": 3, "entombed_cooperative": 3, "flag_capture": 2, "foozpong": 3,
        "ice_hockey": 2, "joust": 3, "mario_bros": 3, "maze_craze": 3, "othello": 3, "pong": 3,
        "quadrapong": 4, "space_invaders": 2, "space_war": 2, "surround": 2, "tennis": 3,
        "video_checkers": 4, "volleyball_pong": 3, "warlords": 3, "wizard_of_wor": 3,
    },
    "pettingzoo.butterfly": {"cooperative_pong": 6, "knights_archers_zombies": 11, "pistonball": 6},
    "pettingzoo.classic": {
        "chess": 6, "connect_four": 3, "go": 5, "hanabi": 5, "leduc_holdem": 4, "rps": 2,
        "texas_holdem_no_limit": 6, "texas_holdem": 4, "tictactoe": 3,
    },
    "pettingzoo.sisl": {"multiwalker": 9, "pursuit": 5},
}

# Envs whose successor is not a drop-in: reported with the reason.
NOT_MAPPED: dict[tuple[str, str], str] = {
    ("pettingzoo.classic", "hanabi"): "hanabi_v5 (PettingZoo 1.23) runs on OpenSpiel through Shimmy "
    "(`shimmy[openspiel]`) and takes `observation_type` as a string: port it by hand",
    ("pettingzoo.classic", "gin_rummy"): "gin_rummy was removed from PettingZoo; its implementation remains in RLCard",
    ("pettingzoo.sisl", "waterworld"): "waterworld is not in PettingZoo 1.27: check the release you target",
}


def _question(changes: list[str]) -> tuple[str, str] | None:
    """What the review of these bumps asks: the same for every import of the file that
    bumps envs of one group (or of one env), so the file asks it once."""
    groups = {next((b.group or b.change for b in BUMPS.values() if b.change == change), change) for change in changes}
    return ("PZ111", groups.pop()) if len(groups) == 1 else None


def new_module(family: str) -> str:
    moved = MOVED_FAMILIES.get(family)
    return moved[0] if moved else family


class EnvModules(PettingZooFamily):
    RULES = (PZ111,)

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        """Only the file's own imports of PettingZoo's env families matter here."""
        return any(q == "pettingzoo" or q.startswith("pettingzoo.") for q in facts.imports.values())

    def decide(self) -> None:
        for statement in self.facts.import_statements:
            if isinstance(statement, ast.ImportFrom) and statement.level == 0:
                module = statement.module or ""
                if module in MOVED_FAMILIES or module in _FAMILIES:
                    self._from_family(statement, module)
                elif "." in module and module.rsplit(".", 1)[0] in (*MOVED_FAMILIES, *_FAMILIES):
                    self._from_env_module(statement, *module.rsplit(".", 1))
            elif isinstance(statement, ast.Import):
                for alias in statement.names:
                    family = next((f for f in MOVED_FAMILIES if alias.name == f or alias.name.startswith(f + ".")), None)
                    if family is not None:
                        self.report(statement, "PZ111", f"`{family}` moved to the `{new_module(family)}` package "
                                    f"(PettingZoo 1.27 raises ImportError): import the env from `{new_module(family)}`",
                                    FixKind.FLAG)

    # -- from pettingzoo.mpe import simple_spread_v2 -----------------------------------------

    def _from_family(self, statement: ast.ImportFrom, family: str) -> None:
        if any(alias.name == "*" for alias in statement.names):
            if family in MOVED_FAMILIES:
                self.report(statement, "PZ111", f"`{family}` moved to `{new_module(family)}`: import its envs by name "
                            "from there", FixKind.FLAG)
            return
        renames: dict[str, str] = {}
        notes: dict[str, list[str]] = {}  # what changed -> the renames it applies to
        superseded: list[str] = []  # the statement's older versions that the file uses
        for alias in statement.names:
            decided = self._decide(family, alias.name, statement, superseded=(superseded, alias))
            if decided is None:
                if family in MOVED_FAMILIES:
                    return  # reported: the statement keeps its module, so none of it moves
                continue
            new_name, note = decided
            if new_name != alias.name:
                if alias.asname is None and not self._can_rename(alias, new_name):
                    self.report(statement, "PZ111", f"`{alias.name}` is `{new_name}` now, but the name is bound or "
                                "read elsewhere in a way this rule does not follow: change it by hand", FixKind.FLAG)
                    if family in MOVED_FAMILIES:
                        return
                    continue
                renames[alias.name] = new_name
            if note:
                notes.setdefault(note, []).append(f"`{alias.name}` -> `{new_name}`")
        if superseded:
            self.report(statement, "PZ111", f"{'; '.join(superseded)}: PettingZoo 1.27 raises DeprecatedEnv when "
                        f"{'it is' if len(superseded) == 1 else 'they are'} called, and the changes were not "
                        "checked: port by hand", FixKind.FLAG)
        target = new_module(family)
        if not renames and target == family:
            return
        self.changed()
        for alias in statement.names:
            if alias.name in renames and alias.asname is None:
                for read in self._reads(alias):
                    self.rename(read, renames[alias.name])

        def build(node: cst.ImportFrom) -> cst.ImportFrom:
            assert not isinstance(node.names, cst.ImportStar)  # star imports are only reported
            names = [
                a.with_changes(name=cst.Name(renames[a.name.value]))
                if isinstance(a.name, cst.Name) and a.name.value in renames else a
                for a in node.names
            ]
            return node.with_changes(module=cst.parse_expression(target), names=names)

        self.plan.replace(statement, build)
        moved = f"`{family}` is the `{target}` package now" if target != family else ""
        bumped = "; ".join(f"{', '.join(pairs)} (the old version raises DeprecatedEnv on PettingZoo 1.27); "
                           f"review: {change}" for change, pairs in notes.items())
        message = "; ".join(part for part in (moved, bumped) if part)
        self.report(statement, "PZ111", message, FixKind.ASSIST if notes else FixKind.AUTO,
                    question=_question(list(notes)))

    # -- from pettingzoo.mpe.simple_spread_v2 import parallel_env ----------------------------

    def _from_env_module(self, statement: ast.ImportFrom, family: str, env_module: str) -> None:
        decided = self._decide(family, env_module, statement, bound=[a.asname or a.name for a in statement.names])
        if decided is None:
            return
        new_name, note = decided
        target = f"{new_module(family)}.{new_name}"
        if target == statement.module:
            return
        self.changed()
        self.plan.replace(statement, lambda node: node.with_changes(module=cst.parse_expression(target)))
        moved = f"`{statement.module}` is `{target}` now"
        if note:
            moved += f" (the old version raises DeprecatedEnv on PettingZoo 1.27); review: {note}"
        self.report(statement, "PZ111", moved, FixKind.ASSIST if note else FixKind.AUTO,
                    question=_question([note] if note else []))

    # -- the table ---------------------------------------------------------------------------

    def _decide(self, family: str, imported: str, statement: ast.ImportFrom,
                bound: list[str] | None = None,
                superseded: tuple[list[str], ast.alias] | None = None) -> tuple[str, str] | None:
        """The env module's current name and what changed ("" for nothing), or None (reported).
        ``superseded``: for ``from family import x_vN``, where an older version that the file
        reads is listed for one item of the statement (one never read is no question); without
        it (``from family.x_vN import env`` fails on import) the version is reported here."""
        match = _ENV_NAME.match(imported)
        if match is None:
            if family in MOVED_FAMILIES:
                self.report(statement, "PZ111", f"`{family}` moved to `{new_module(family)}`: `{imported}` is not "
                            "an env module this rule knows; change the import by hand", FixKind.FLAG)
            return None
        env, version = match.group(1), int(match.group(2))
        if (family, env) in NOT_MAPPED:
            self.report(statement, "PZ111", f"`{imported}`: {NOT_MAPPED[family, env]}", FixKind.FLAG)
            return None
        moved, checked = MOVED_FAMILIES.get(family, (family, True))
        bump = BUMPS.get((family, env))
        current = bump.current if bump is not None else CURRENT.get(family, {}).get(env)
        if current is not None and version < current and (bump is None or version != bump.previous):
            text = f"`{imported}` is superseded by `{env}_v{current}`"
            if superseded is None or family in MOVED_FAMILIES:  # the import itself fails
                self.report(statement, "PZ111", f"{text} (on PettingZoo 1.27 this import fails), and the changes since "
                            f"v{version} were not checked: port it by hand", FixKind.FLAG)
            elif self._reads(superseded[1]):
                superseded[0].append(text)
            return None
        if bump is None or not checked:
            if moved != family:
                self.report(statement, "PZ111", f"`{family}` moved to the `{moved}` package (PettingZoo 1.27 raises "
                            f"ImportError); `{imported}` was not checked against it: change the import by hand", FixKind.FLAG)
            return None
        if version == bump.current or version != bump.previous:
            return imported, ""  # a version above the current one is not PettingZoo's: left
        self._report_removed_keywords(imported, bump, statement, bound)
        return f"{env}_v{bump.current}", bump.change

    def _report_removed_keywords(self, imported: str, bump: Bump, statement: ast.ImportFrom,
                                 bound: list[str] | None) -> None:
        """Calls ``<name>.env(k=...)`` (or ``env(k=...)`` imported from the env module) that pass
        a keyword the new version no longer takes: rewritten where the table gives its
        certain equivalent, reported otherwise."""
        if not bump.keywords:
            return
        aliases = [alias for alias in statement.names
                   if (bound is not None) or alias.name == imported]
        for alias in aliases:
            name = alias.asname or alias.name
            if bound is None:  # ``from family import env_vN``: ``env_vN.env(...)``
                calls = [call for attr in FACTORIES for call in self.facts.attribute_calls.get(attr, ())
                         if isinstance(call.func, ast.Attribute) and isinstance(call.func.value, ast.Name)
                         and call.func.value.id == name and alias in self.facts.bindings_of(call.func.value)]
            elif alias.name in FACTORIES:  # ``from family.env_vN import env``: ``env(...)``
                calls = [call for call in self.facts.calls_by_name.get(name, ())
                         if isinstance(call.func, ast.Name) and alias in self.facts.bindings_of(call.func)]
            else:
                continue
            for call in calls:
                self._keywords(call, imported, bump)

    def _keywords(self, call: ast.Call, imported: str, bump: Bump) -> None:
        passed = [k for k in call.keywords if k.arg in bump.keywords]
        if not passed:
            return
        new_name = f"{imported.rsplit('_v', 1)[0]}_v{bump.current}"
        changes: dict[str, tuple[str, str | None]] = {}
        uncertain: list[str] = []
        for keyword in passed:
            assert keyword.arg is not None
            table = bump.keywords[keyword.arg]
            target = None
            if table is not None:
                value = keyword.value
                literal = isinstance(value, ast.Constant) and value.value in table
                target = table[value.value] if literal and isinstance(value, ast.Constant) else table.get(ANY)
            if target is None:
                uncertain.append(keyword.arg)
            else:
                changes[keyword.arg] = target
        targets = [new for new, _ in changes.values() if new]
        if uncertain or len(targets) != len(set(targets)) or any(
            k.arg in targets for k in call.keywords if k.arg not in changes):
            self.report(call, "PZ111", f"{', '.join(f'`{k.arg}`' for k in passed)}: not an argument of `{new_name}`, "
                        "and this call has no certain equivalent (see the import's PZ111 finding): change it by hand",
                        FixKind.FLAG)
            return
        self.changed()
        self.plan.replace(call, lambda node: _rewrite_keywords(node, changes))
        done = ", ".join(f"`{old}` -> `{new}`" if new else f"`{old}` dropped" for old, (new, _) in changes.items())
        self.report(call, "PZ111", f"{done}: the arguments of `{new_name}`", FixKind.AUTO)

    # -- renaming the bound name -------------------------------------------------------------

    def _reads(self, alias: ast.alias) -> list[ast.Name]:
        found: list[ast.Name] = []
        for each in self.facts.scopes.values():
            for read in each.reads.get(alias.name, ()):
                if alias in self.facts.bindings_of(read):
                    found.append(read)
        return found

    def _can_rename(self, alias: ast.alias, new_name: str) -> bool:
        """Every read of the name sees only this import, the name is bound nowhere else in
        the module, and the new name is free."""
        old = alias.name
        for scope in self.facts.scopes.values():
            if new_name in scope.bindings or new_name in scope.reads:
                return False
            if old in scope.declared_global or old in scope.declared_nonlocal:
                return False
            if any(binding is not alias for binding in scope.bindings.get(old, ())):
                return False
            for read in scope.reads.get(old, ()):
                if self.facts.bindings_of(read) != [alias]:
                    return False
        return True


# PettingZoo's own env families: their envs stay in PettingZoo, some at a new version.
_FAMILIES = frozenset(CURRENT)


def _rewrite_keywords(node: cst.Call, changes: dict[str, tuple[str, str | None]]) -> cst.Call:
    """Rename, revalue or drop the keyword arguments ``changes`` names, commas kept valid."""
    args: list[cst.Arg] = []
    for arg in node.args:
        change = changes.get(arg.keyword.value) if arg.keyword is not None else None
        if change is None:
            args.append(arg)
            continue
        new, value = change
        if not new:
            continue
        arg = arg.with_changes(keyword=cst.Name(new))
        if value is not None:
            arg = arg.with_changes(value=cst.parse_expression(value))
        args.append(arg)
    if args and node.args and args[-1] is not node.args[-1]:
        args[-1] = args[-1].with_changes(comma=node.args[-1].comma)
    return node.with_changes(args=args)
