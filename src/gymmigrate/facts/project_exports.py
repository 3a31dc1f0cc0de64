"""The run's names, re-exports followed: what calling each top-level name of the run gives
(``ProjectFacts.call_kinds``, ``aliases``, ``made``, ``bare_env_classes``), and which
re-exported names are Gym wrapper classes. Passes of ``ProjectFacts.join``.
"""

from __future__ import annotations

from collections import defaultdict
from typing import TYPE_CHECKING

from gymmigrate.facts.import_roots import import_parts
from gymmigrate.facts.kinds import EnvKind, agreed_kind
from gymmigrate.facts.module_summary import MAX_CHAIN, OWN, REF, ModuleSummary, is_ref

if TYPE_CHECKING:
    from gymmigrate.facts.project import ProjectFacts


class Exports:
    """``ProjectFacts.call_kinds``: every top-level name of the run with what calling it
    gives, re-exports (``__init__``, star imports, ``make = utils.make``) and subclasses
    followed to the module that decides. One memoized answer per name; a cycle or a chain
    longer than ``MAX_CHAIN`` is unknown."""

    def __init__(self, facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> None:
        self.facts = facts
        self.by_path = by_path
        self.depth = 0

    def run(self) -> None:
        for path, summary in self.by_path.items():
            for name in summary.exports:
                self.kind(path, name)
                alias = self._alias(path, name)
                if alias is not None:
                    self.facts.aliases[(path, name)] = alias
            for name in self._star_names(summary, set()):
                self.kind(path, name)  # ``from .envs import *``: its names are this module's too
        for key, kind in self.facts.call_kinds.items():
            if kind is EnvKind.GYM_ENV:
                trail: list[tuple[str, str]] = []
                where = self.origin(*key, set(), trail)
                if where is None:
                    continue
                defining = self.by_path[where[0]]
                if where[1] in defining.made_factories:
                    self.facts.made.add(key)
                    self.facts.made_at[key] = where
                if (
                    where[1] in defining.classes
                    and (where[1] in self.facts.env_classes.get(where[0], ()) or self._wrapper_free(where[0], where[1], set()))
                    and not any(n in self.by_path[p].wrapper_classes for p, n in trail)
                ):
                    self.facts.bare_env_classes.add(key)

    def _wrapper_free(self, path: str, name: str, seen: set[tuple[str, str]]) -> bool:
        """The class ``name`` of module ``path``, which the run shows to make Gym envs though
        its own module cannot tell (``class Reach(ArmBase, TaskEnv)``), and its bases of the
        run at any depth are no Gym wrapper classes: an instance made by calling it is the
        env itself. False where a base of the run cannot be followed (a plain root of the
        run, deriving only ``object``, needs none)."""
        if (path, name) in seen:
            return True
        seen.add((path, name))
        summary = self.by_path.get(path)
        if summary is None or name in summary.wrapper_classes or len(seen) > MAX_CHAIN:
            return False
        heir = next((h for h in summary.render_mode_heirs if h[0] == name), None)
        for base in heir[1] if heir is not None else ():
            if base.startswith(OWN):
                where: tuple[str, str] | None = (path, base[len(OWN) :])
            elif self.facts.view(path).is_plain_root(base):
                continue  # a class of the run deriving only ``object``: no wrapper
            else:
                split = self.facts._split(base, path)
                trail: list[tuple[str, str]] = []
                where = self.origin(*split, set(), trail) if split is not None and "." not in split[1] else None
                if where is None or any(n in self.by_path[p].wrapper_classes for p, n in trail):
                    return False
            if where is None or not self._wrapper_free(where[0], where[1], seen):
                return False
        return True

    def origin(
        self, path: str, name: str, seen: set[tuple[str, str]], trail: list[tuple[str, str]] | None = None
    ) -> tuple[str, str] | None:
        """The module and name that define ``name`` of module ``path``: re-exports, star
        imports and subclasses of a class of another module (``ref:``) followed, each once;
        ``trail`` gets every name passed on the way."""
        summary = self.by_path.get(path)
        if summary is None or (path, name) in seen or len(seen) >= MAX_CHAIN:
            return None
        seen.add((path, name))
        kind = summary.exports.get(name)
        if kind is None:
            for star in self._star_paths(summary):
                found = self.origin(star, name, seen, trail)
                if found is not None:
                    return found
            return None
        if trail is not None:
            trail.append((path, name))
        if isinstance(kind, EnvKind):
            return path, name
        split = self.facts._split(kind[len(REF) :], path)
        return None if split is None or "." in split[1] else self.origin(*split, seen, trail)

    def star_names(self, summary: ModuleSummary) -> set[str]:
        """The public names ``summary``'s star imports bring in (``_star_names``)."""
        return self._star_names(summary, set())

    def _star_names(self, summary: ModuleSummary, seen: set[str]) -> set[str]:
        """The public names a module's star imports bring in (star chains followed once)."""
        seen.add(summary.path)
        names: set[str] = set()
        for path in self._star_paths(summary):
            if path in seen:
                continue
            star = self.by_path[path]
            names.update(n for n in star.exports if not n.startswith("_"))
            names.update(self._star_names(star, seen))
        return names

    def public_names(self, path: str, seen: set[str]) -> frozenset[str]:
        """The names ``from <module at path> import *`` binds: its ``__all__``, else its
        top-level names not starting with ``_``, with those its own star imports bind (each
        module once, chains of at most ``MAX_CHAIN``)."""
        summary = self.by_path[path]
        if summary.declared_all is not None:
            return frozenset(summary.declared_all)
        seen.add(path)
        names = {n for n in summary.exports if not n.startswith("_")}
        if len(seen) < MAX_CHAIN:
            for star in self._star_paths(summary):
                if star not in seen:
                    names |= self.public_names(star, seen)
        return frozenset(names)

    def star_target(self, summary: ModuleSummary, module: str) -> str | None:
        """The module of the run that ``summary``'s ``from <module> import *`` names."""
        level, parts = import_parts(module)
        path = self.facts._module_path(parts, level, summary.path)
        return path if path and path != summary.path and path in self.by_path else None

    def _star_paths(self, summary: ModuleSummary) -> list[str]:
        found = []
        for module in summary.star_imports:
            level, parts = import_parts(module)
            path = self.facts._module_path(parts, level, summary.path)
            if path and path != summary.path and path in self.by_path:
                found.append(path)
        return found

    def _alias(self, path: str, name: str) -> str | None:
        """``gym.make`` for a name bound to it here or through a chain of re-exports."""
        for _ in range(MAX_CHAIN):
            summary = self.by_path.get(path)
            if summary is None:
                return None
            if name in summary.aliases:
                return summary.aliases[name]
            kind = summary.exports.get(name)
            if not is_ref(kind):
                return None
            split = self.facts._split(str(kind)[len(REF) :], path)
            if split is None:
                return None
            path, name = split
        return None

    def kind(self, path: str, name: str) -> EnvKind | None:
        """What calling ``name`` of module ``path`` gives; None when the module does not
        bind it (not even through a star import)."""
        key = (path, name)
        known = self.facts.call_kinds.get(key)
        if known is not None:
            return known
        summary = self.by_path.get(path)
        if summary is None or self.depth >= MAX_CHAIN:
            return None
        kind = summary.exports.get(name)
        self.facts.call_kinds[key] = EnvKind.UNKNOWN  # a cycle adds no evidence
        self.depth += 1
        try:
            if kind is None:
                found = self._from_stars(summary, name)
                if found is None:
                    del self.facts.call_kinds[key]
                    return None
            elif isinstance(kind, EnvKind):
                # A module the run leaves as it is: its classes did not migrate.
                found = EnvKind.UNKNOWN if path in self.facts.blocked and kind is not EnvKind.NOT_ENV else kind
            else:
                found = self._follow(kind[len(REF) :], path)
            if found is EnvKind.UNKNOWN and key in self.facts.registered_classes and path not in self.facts.blocked:
                # a class of a library base (``class Game(NESEnv)``) the run registers with
                # Gym's registry: a Gym env, as ``make`` of its id gives one
                found = EnvKind.GYM_ENV
        finally:
            self.depth -= 1
        self.facts.call_kinds[key] = found
        return found

    def _follow(self, qualified: str, importer: str) -> EnvKind:
        split = self.facts._split(qualified, importer)
        if split is None:
            return EnvKind.UNKNOWN  # a library name the module could not classify
        path, name = split
        if "." in name:
            return EnvKind.UNKNOWN  # ``module.Class.method``: not a top-level name
        found = self.kind(path, name)
        return EnvKind.UNKNOWN if found is None else found

    def _from_stars(self, summary: ModuleSummary, name: str) -> EnvKind | None:
        for path in self._star_paths(summary):
            found = self.kind(path, name)
            if found is not None:
                return found
        return None


def star_bindings(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> dict[str, dict[str, str]]:
    """Per module, the names its top-level classes derive (``ModuleSummary.star_bases``)
    that one of its star imports of the run's modules binds, each with the qualified name
    it stands for: ``{"Base": ".base.Base"}`` for ``from .base import *`` then ``class
    Child(Base)``. The last star import that binds a name wins, as at import time."""
    exports = Exports(facts, by_path)
    found: dict[str, dict[str, str]] = {}
    for path, summary in by_path.items():
        if not summary.star_bases:
            continue
        bound: dict[str, str] = {}
        for module in summary.star_imports:
            target = exports.star_target(summary, module)
            if target is None:
                continue
            given = exports.public_names(target, set())
            for name in summary.star_bases & given:
                bound[name] = f"{module}.{name}" if module and not module.endswith(".") else module + name
        if bound:
            found[path] = bound
    return found


def reexport_wrappers(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> None:
    """A name that re-exports a wrapper class of another module (``from .utils import
    Stats`` in a package's ``__init__``) is that wrapper class too."""
    added: dict[str, set[str]] = defaultdict(set)
    for path, summary in by_path.items():
        if path in facts.blocked:
            continue
        for name, first in summary.exports.items():
            where = (path, name)
            export: EnvKind | str | None = first
            for _ in range(MAX_CHAIN):
                if not isinstance(export, str):
                    break
                split = facts._split(export[len(REF) :], where[0])
                if split is None or "." in split[1] or split[0] not in by_path:
                    break
                where = split
                if where[1] in facts.wrapper_classes.get(where[0], ()):
                    added[path].add(name)
                    break
                export = by_path[where[0]].exports.get(where[1])
    # ``from .wrappers import *`` in a package's ``__init__`` re-exports its wrapper classes too
    exports = Exports(facts, by_path)
    for path, summary in by_path.items():
        if path in facts.blocked:
            continue
        for name in exports.star_names(summary):
            origin = None if name in summary.exports else exports.origin(path, name, set())
            if origin is not None and origin[1] in facts.wrapper_classes.get(origin[0], ()):
                added[path].add(name)
    for path, names in added.items():
        facts.wrapper_classes[path] = facts.wrapper_classes.get(path, frozenset()) | names


def join_thunk_factory_refs(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> None:
    """A def whose thunks call names of other modules of the run (``def creator(_): return
    Orchard(n)``, ``ModuleSummary.thunk_factory_refs``): its thunks return what those calls
    give (``call_kinds``), when every name gives the same kind and the run knows it."""
    for path, summary in by_path.items():
        if path in facts.blocked or not summary.thunk_factory_refs:
            continue
        found: dict[str, EnvKind] = {}
        for name, refs in summary.thunk_factory_refs.items():
            kinds: set[EnvKind | None] = set()
            for ref in refs:
                split = facts._split(ref, path)
                if split is None or "." in split[1] or split in facts.legacy_steps:
                    kinds.add(None)  # its step keeps the four fields: what it builds is no Gym env to its callers
                    continue
                kinds.add(facts.call_kinds.get(split))
            kind = kinds.pop() if len(kinds) == 1 else None
            if kind is not None and kind is not EnvKind.UNKNOWN:
                found[name] = kind
        if found:
            facts.thunk_factories[path] = {**facts.thunk_factories.get(path, {}), **found}


def join_tables(facts: ProjectFacts, by_path: dict[str, ModuleSummary], writes: list[tuple[str, str]]) -> None:
    """What calling through each closed table of creators of the run gives
    (``ProjectFacts.table_kinds``; ``ModuleSummary.tables``): the one kind all its
    callables give, names of other modules followed through ``call_kinds``. A table
    another module writes into (``writes``: each module and the imported name it writes
    into, ``ModuleSummary.altered``) holds what the run does not see, and gets no answer
    (``altered_tables``)."""
    altered = set()
    for path, qualified in writes:
        split = facts._split(qualified, path)
        if split is not None:
            altered.add(split)
    facts.altered_tables = frozenset(altered)
    for path, summary in by_path.items():
        if path in facts.blocked:
            continue  # its creators stay on the old API
        for (name, field), kinds in summary.tables.items():
            if (path, name) not in altered:
                facts.table_kinds[(path, name, field)] = agreed_kind(_resolved(facts, kind, path) for kind in kinds)
                if all(_made(facts, made, path) for made in summary.made_tables.get((name, field), ("",))):
                    facts.made_tables.add((path, name, field))


def _made(facts: ProjectFacts, made: str, path: str) -> bool:
    if made == OWN:
        return True
    split = facts._split(made[len(REF) :], path) if is_ref(made) else None
    return split is not None and split in facts.made


def _resolved(facts: ProjectFacts, kind: EnvKind | str, path: str) -> EnvKind:
    if isinstance(kind, EnvKind):
        return kind
    split = facts._split(kind[len(REF) :], path) if is_ref(kind) else None
    if split is None or "." in split[1]:
        return EnvKind.UNKNOWN
    return facts.call_kinds.get(split, EnvKind.UNKNOWN)
