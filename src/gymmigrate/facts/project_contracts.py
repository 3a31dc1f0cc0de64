"""Class contracts across the modules of the run, passes of ``ProjectFacts.join``: env
classes whose spaces are not Spaces (GM807), ``render_mode`` threaded down every chain of
subclasses (custom_env/render.py), the classes whose render(mode) stays the project's
own, the classes whose step keeps the legacy four-field contract, the methods each class of the run has from its bases of the run, and the
classes whose reset steps the wrapper around them (GM808).
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Iterator
from typing import TYPE_CHECKING

from gymmigrate.facts.import_roots import nearest_root
from gymmigrate.facts.kinds import EnvKind, join_kinds
from gymmigrate.facts.module_summary import (
    KNOWN,
    MAX_CHAIN,
    OWN,
    REF,
    ModuleSummary,
    is_ref,
)
from gymmigrate.facts.project_exports import Exports
from gymmigrate.facts.wrapper_steps import steps_its_wrapper

if TYPE_CHECKING:
    from gymmigrate.facts.project import ProjectFacts
    from gymmigrate.facts.project_view import ProjectView


class NonSpaces:
    """``ProjectFacts.non_space_envs``: classes of the run whose ``action_space`` or
    ``observation_space`` is an instance of a class of the run that certainly is not a
    ``Space`` (``class MultiAgentActionSpace(list)``), and every name re-exporting them."""

    def __init__(self, facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> None:
        self.facts = facts
        self.by_path = by_path

    def origin(self, path: str, name: str) -> tuple[str, str] | None:
        """The module and name that define ``name`` of module ``path``, re-exports followed."""
        for _ in range(MAX_CHAIN):
            summary = self.by_path.get(path)
            if summary is None:
                return None
            if name in summary.plain_classes or name in summary.space_calls:
                return path, name  # defined here (a subclass's export refers to its base)
            kind = summary.exports.get(name)
            if not is_ref(kind):
                return (path, name) if kind is not None else None
            split = self.facts._split(str(kind)[len(REF) :], path)
            if split is None or "." in split[1]:
                return None
            path, name = split
        return None

    def run(self) -> None:
        found: dict[tuple[str, str], tuple[str, str, str]] = {}
        for path, summary in self.by_path.items():
            if path in self.facts.blocked:
                continue
            for classname, calls in summary.space_calls.items():
                for attribute, callee in calls:
                    if callee.startswith(OWN):
                        where: tuple[str, str] | None = (path, callee[len(OWN) :])
                    else:
                        split = self.facts._split(callee, path)
                        where = self.origin(*split) if split is not None and "." not in split[1] else None
                    if where is None:
                        continue
                    base = self.by_path[where[0]].plain_classes.get(where[1])
                    if base is not None:
                        found.setdefault((path, classname), (attribute, where[1], base))
        rootless: dict[tuple[str, str], tuple[str, str]] = {}
        for path, summary in self.by_path.items():
            if path in self.facts.blocked:
                continue
            for classname, stores in summary.class_stores.items():
                root = None if classname in summary.plain_classes or not stores.bases else self.plain_root(path, classname, 0)
                if root is not None:
                    rootless[(path, classname)] = (root[1], root[0])
        if not found and not rootless:
            return
        for path, summary in self.by_path.items():
            for name in summary.exports:
                where = self.origin(path, name)
                if where is not None and where in found:
                    self.facts.non_space_envs[(path, name)] = found[where]
                # the class itself, or the one a re-export names: a subclass's export refers
                # to its base, which is not the class registered
                definer = class_definer(self.facts, self.by_path, path, name)
                if definer is not None and definer in rootless:
                    self.facts.rootless_envs[(path, name)] = rootless[definer]

    def plain_root(self, path: str, name: str, depth: int) -> tuple[str, str] | None:
        """The plain class of the run (no base, or builtins alone) that the class ends in,
        when every base of it at any depth is a class of the run: then it derives from no
        library class, gymnasium.Env included. None when any base is a library's or unknown."""
        summary = self.by_path.get(path)
        if summary is None or depth > MAX_CHAIN:
            return None
        if name in summary.plain_classes:
            return path, name
        stores = summary.class_stores.get(name)
        if stores is None or not stores.bases:
            return None
        first: tuple[str, str] | None = None
        for base in stores.bases:
            if base.startswith(OWN):
                where: tuple[str, str] | None = (path, base[len(OWN) :])
            else:
                split = self.facts._split(base, path) if base else None
                where = self._defined(*split) if split is not None and "." not in split[1] else None
                if where is None:
                    # a plain root in a module with no Gym code (``class Serializable(object)``)
                    masked = self._root_without_gym(base, path)
                    if masked is None:
                        return None  # a base the run does not show to be its own: it may be gymnasium.Env
                    first = first or masked
                    continue
            root = None if where is None else self.plain_root(*where, depth=depth + 1)
            if root is None:
                return None  # a base the run does not show to be its own: it may be gymnasium.Env
            first = first or root
        return first

    def _defined(self, path: str, name: str) -> tuple[str, str] | None:
        """Where the class ``name`` of module ``path`` is defined: there when the module
        defines it (a subclass exports a reference to its base, which ``origin`` follows),
        else its re-exports followed."""
        summary = self.by_path.get(path)
        return (path, name) if summary is not None and name in summary.classes else self.origin(path, name)

    def _root_without_gym(self, qualified: str, importer: str) -> tuple[str, str] | None:
        """``pkg.core.serializable.Serializable`` (absolute) named in a module with no Gym
        code, whose summary lists only its plain roots (``summarize_masks``), which ``_split``
        does not know: that module and the class, where the class is one of those roots."""
        parts = qualified.split(".")
        for cut in range(len(parts) - 1, 0, -1):
            paths = self.facts.mask_modules.get(".".join(parts[:cut]), ())
            path = nearest_root(paths, cut, importer) if paths else None
            if path is not None and cut == len(parts) - 1 and parts[-1] in self.facts.plain_roots.get(path, ()):
                return path, parts[-1]
        return None


def _definer(facts: ProjectFacts, by_path: dict[str, ModuleSummary], path: str, name: str) -> tuple[str, str] | None:
    """The module and name of the class ``name`` of module ``path`` is, re-exports followed.
    None for a def that returns the class's instances: it takes its own parameters, so
    whether a ``render_mode`` given to it reaches the class is not the class's to say."""
    for _ in range(MAX_CHAIN):
        summary = by_path.get(path)
        if summary is None:
            return None
        if name in summary.env_classes or any(heir[0] == name for heir in summary.render_mode_heirs):
            return path, name
        if name in summary.defs:
            return None
        kind = summary.exports.get(name)
        if not is_ref(kind):
            return (path, name) if kind is not None else None
        split = facts._split(str(kind)[len(REF) :], path)
        if split is None or "." in split[1]:
            return None
        path, name = split
    return None


def thread_render_mode(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> None:
    """A subclass (in any module of the run) of a class whose constructor takes
    ``render_mode`` takes it too when its ``__init__`` can hand it on: custom_env/render.py
    adds the parameter and passes it to the base's ``__init__``. Without that, render() of
    every such subclass is a silent no-op and ``gymnasium.make(id, render_mode=...)`` of a
    registered one a TypeError. Every name re-exporting such a class counts too."""
    takes = {(path, name) for path, names in facts.render_mode_classes.items() for name in names}
    # a class its module cannot classify, which the run shows to be an env class (its bases
    # are the run's: ``class Point(MultitaskEnv, Serializable)``), takes it as the rules give it
    takes |= {
        (path, name)
        for path, summary in by_path.items()
        if path not in facts.blocked
        for name in summary.render_mode_if_env
        if facts.call_kinds.get((path, name)) is EnvKind.GYM_ENV
    }

    def resolve(base: str, path: str) -> tuple[str, str] | None:
        if base.startswith(OWN):
            return path, base[len(OWN) :]
        split = facts._split(base, path)
        if split is None or "." in split[1]:
            return None
        return _definer(facts, by_path, *split)

    def makes_env_class(base: str, path: str) -> bool:
        """The base makes the subclass an env class the rules decide (a class of its own
        module, or one the run shows to be a Gym env class); another base may be the one
        that takes render_mode (``class Reach(ArmBase, TaskEnv)`` with only ``TaskEnv``
        known to be an env class, ``ArmBase`` taking render_mode from a base of its own)."""
        if base.startswith(OWN):
            return True
        split = facts._split(base, path)
        return split is not None and "." not in split[1] and facts.call_kinds.get(split) is EnvKind.GYM_ENV

    changed = True
    while changed:
        changed = False
        for path, summary in by_path.items():
            if path in facts.blocked:
                continue
            # where another module passes modes it cannot trace, a render(mode) that must
            # stay whole takes no render_mode; an optional one takes it beside the mode
            kept = summary.fixed_mode_renders if path in facts.render_called else frozenset()
            for name, bases, passes_on in summary.render_mode_heirs:
                if (
                    passes_on
                    and name not in kept
                    and (path, name) not in takes
                    and any(resolve(b, path) in takes for b in bases)
                    and any(makes_env_class(b, path) for b in bases)
                ):
                    takes.add((path, name))
                    changed = True
    for path, summary in by_path.items():
        for name in summary.exports:
            if (path, name) not in takes and _definer(facts, by_path, path, name) in takes:
                takes.add((path, name))
    for summary in by_path.values():
        for env_id, entry in summary.registrations:
            module, _, name = entry.partition(":")
            where = facts.modules.get(module)
            definer = _definer(facts, by_path, where, name) if where else None
            if definer is None or definer in takes:
                continue
            defined = by_path[definer[0]]
            if definer[1] in defined.env_classes or any(h[0] == definer[1] for h in defined.render_mode_heirs):
                facts.no_render_mode_ids.setdefault(env_id, definer[1])
                facts.no_render_mode_classes.setdefault(env_id, definer)
                facts.no_render_mode_registrars.setdefault(env_id, set()).add(summary.path)
    found: dict[str, set[str]] = defaultdict(set)
    for path, name in takes:
        found[path].add(name)
    facts.render_mode_classes = {path: frozenset(found.get(path, ())) for path in set(facts.render_mode_classes) | set(found)}


def seeds_untraced(facts: ProjectFacts, summary: ModuleSummary) -> bool:
    """``summary``'s module calls ``x.seed(...)`` on what the run leaves a seed() caller: a
    receiver no module can trace, or one only the join classifies (``seed_makers``) that
    GM203 does not make ``reset(seed=...)``. It does where every maker builds a Gym env the
    run migrates, as the receiver kinds see it there (``ProjectView.call_kind``, joined), and
    none is a make behind which a wrapper's seed() may still be called through
    ``get_wrapper_attr``: such a call leaves no caller, on the first run as on the output."""
    if summary.untraced_seed_call:
        return True
    view = facts.view(summary.path)
    for makers in summary.seed_makers:
        kinds = [_seed_maker_kind(view, maker) for maker in makers.split("|")]
        if join_kinds(kinds) is not EnvKind.GYM_ENV:
            return True
    return False


def _seed_maker_kind(view: ProjectView, maker: str) -> EnvKind:
    """What ``maker`` builds, for ``seeds_untraced``: a Gym env only where GM203 rewrites a
    seed call on it to ``reset(seed=...)``; unknown where it may do otherwise or leave it."""
    if maker == KNOWN + EnvKind.NOT_ENV.name:
        return EnvKind.NOT_ENV  # ``env = None`` before the branches: join_kinds drops it
    if maker.startswith(KNOWN) or view.returns_made(maker) or view.keeps_legacy_step(maker):
        return EnvKind.UNKNOWN  # a make (maybe under the run's seeding wrappers), an env kept on four fields
    return EnvKind.GYM_ENV if view.call_kind(maker) is EnvKind.GYM_ENV else EnvKind.UNKNOWN


def seed_keepers(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> tuple[frozenset[tuple[str, str]], dict[str, str]]:
    """The env classes of the run whose seed() GM503 keeps because another module calls
    ``x.seed(...)`` on what it cannot trace (``facts.seed_called``), and the literal ids the
    run registers for one of them (``register(id="Task-v0", entry_point="pkg.tasks:Task")``)."""
    classes = frozenset(
        (path, name)
        for path in facts.seed_called
        if path not in facts.blocked
        for name in facts.env_classes.get(path, ())
        if "seed" in facts.class_methods.get((path, name), ())
    )
    ids: dict[str, str] = {}
    for env_id, definer in _registered_definers(facts, by_path):
        if definer in classes:
            ids.setdefault(env_id, definer[1])
    return classes, ids


def _registered_definers(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> Iterator[tuple[str, tuple[str, str]]]:
    """Each literal id the run registers, with the (module path, class name) its entry point
    names, re-exports followed; ids whose entry point names no class of the run are left out."""
    for summary in by_path.values():
        for env_id, entry in summary.registrations:
            module, _, name = entry.partition(":")
            where = facts.modules.get(module)
            definer = _definer(facts, by_path, where, name) if where else None
            if env_id is not None and definer is not None:
                yield env_id, definer


def render_only_ids(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> dict[str, str]:
    """The literal ids the run registers with an entry point naming an env class whose
    drawing is its render() alone (``ModuleSummary.render_only_classes``), re-exports followed."""
    ids: dict[str, str] = {}
    for env_id, (path, name) in _registered_definers(facts, by_path):
        if path not in facts.blocked and name in by_path[path].render_only_classes:
            ids.setdefault(env_id, name)
    return ids


def legacy_steps(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> frozenset[tuple[str, str]]:
    """Every (path, name) of the run that calls a class whose step keeps the legacy
    contract: the class itself, its re-exports and subclasses that define no step, and the
    wrapper classes and factories of the run that give such an instance
    (``ModuleSummary.legacy_if``, followed until nothing is added)."""
    kept = {(path, name) for path, summary in by_path.items() if path not in facts.blocked for name in summary.legacy_steps}
    # a wrapper handing on its env's step and reset results keeps the contract of what it wraps
    return _through_makers(facts, by_path, kept, ("step",), facts.forwarding_wrappers)


def kept_resets(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> frozenset[tuple[str, str]]:
    """Every (path, name) of the run whose instances' reset the run keeps as it was
    (``ModuleSummary.kept_resets``), with the names that re-export one."""
    kept = {(path, name) for path, summary in by_path.items() if path not in facts.blocked for name in summary.kept_resets}
    return frozenset(_kept_names(facts, by_path, Exports(facts, by_path), kept, ("reset",)))


def own_renders(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> frozenset[tuple[str, str]]:
    """The env classes whose render(mode) only hands its mode on to objects of the project's
    own (``ModuleSummary.own_renders``, each object's class checked here to be a class of the
    run that is no env), with their re-exports and the subclasses that define no render():
    every such render stays the project's API (``render_modes.own_object_render``). Not one
    that a module of the run renders with a mode on an instance it made (``render_makers``),
    nor one the run registers: ``make`` reaches it, and takes its render mode there."""
    exports = Exports(facts, by_path)
    made_with_mode = set()
    for summary in by_path.values():
        for maker in summary.render_makers:
            split = facts._split(maker, summary.path)
            if split is not None:
                made_with_mode.add(split)
    found: set[tuple[str, str]] = set()
    for path, summary in by_path.items():
        if path in facts.blocked or not summary.own_renders:
            continue
        view = facts.view(path)
        for name, makers in summary.own_renders:
            if (path, name) in facts.registered_classes:
                continue
            if not all(maker == "" or view.call_kind(maker) is EnvKind.NOT_ENV for maker in makers):
                continue
            reach = _kept_names(facts, by_path, exports, {(path, name)}, ("render",)) | {(path, name)}
            if reach & made_with_mode or reach & facts.registered_classes:
                continue
            found |= reach
    return frozenset(found)


def modeless_renders(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> frozenset[tuple[str, str]]:
    """The env classes whose render() no render mode changes (``ModuleSummary.modeless_renders``),
    with their re-exports and the subclasses that define no render(): not one the run
    registers, whose ``make`` may hand it on through wrappers that ask for a mode."""
    kept = {
        (path, name)
        for path, summary in by_path.items()
        if path not in facts.blocked
        for name in summary.modeless_renders
    }
    if not kept:
        return frozenset()
    reach = _kept_names(facts, by_path, Exports(facts, by_path), kept, ("render",)) | kept
    return frozenset(reach - facts.registered_classes)


def varargs_renders(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> frozenset[tuple[str, str]]:
    """The classes whose render(self, *args) names no mode (``ModuleSummary.varargs_renders``),
    with their re-exports and the subclasses that define no render()."""
    kept = {
        (path, name)
        for path, summary in by_path.items()
        if path not in facts.blocked
        for name in summary.varargs_renders
    }
    if not kept:
        return frozenset()
    return frozenset(_kept_names(facts, by_path, Exports(facts, by_path), kept, ("render",)) | kept)


def legacy_seeds(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> tuple[frozenset[tuple[str, str]], frozenset[tuple[str, str]]]:
    """The (path, name) of the run that call a class defining ``seed()`` (its re-exports and
    subclasses too), and those whose instances hold one somewhere in their wrapper chain: the
    former with the wrapper classes and factories of the run that give an instance of one
    (``ModuleSummary.legacy_if``). Gymnasium's wrappers have no ``seed()`` to forward, but
    ``get_wrapper_attr("seed")`` reaches the one in the chain."""
    own = {
        (path, name)
        for path, summary in by_path.items()
        if path not in facts.blocked
        for name in summary.classes
        if f"{name}.seed" in summary.defs
    }
    owners = frozenset(_kept_names(facts, by_path, Exports(facts, by_path), own, ()))
    wrappers = {(path, name) for path, names in facts.wrapper_classes.items() for name in names}
    return owners, _through_makers(facts, by_path, own, (), wrappers)


def _through_makers(
    facts: ProjectFacts,
    by_path: dict[str, ModuleSummary],
    kept: set[tuple[str, str]],
    methods: tuple[str, ...],
    through: frozenset[tuple[str, str]] | set[tuple[str, str]],
) -> frozenset[tuple[str, str]]:
    """``kept`` with its re-exports and subclasses (``_kept_names``), and the wrapper classes
    and factories whose instances are built around one (``legacy_if``: imported classes of
    ``through`` put around it on the way), until nothing is added."""
    exports = Exports(facts, by_path)

    def reaches(chain: str, path: str) -> bool:
        # ``a.Outer>b.Kept``: ``Outer(Kept(...))``, outermost first
        for link in chain.split(">"):
            split = facts._split(link, path)
            if split is None:
                return False
            origin = exports.origin(*split, set())
            if split in found or origin in found:
                return True
            if split not in through and origin not in through:
                return False
        return False

    kept = set(kept)
    found = _kept_names(facts, by_path, exports, kept, methods)
    for _ in range(MAX_CHAIN):
        more = set()
        for path, summary in by_path.items():
            if path in facts.blocked:
                continue
            for name, imported in summary.legacy_if.items():
                if reaches(imported, path):
                    more.add((path, name))
        if more <= kept:
            break
        kept |= more
        found = _kept_names(facts, by_path, exports, kept, methods)
    return frozenset(found)


def forwarding_wrappers(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> frozenset[tuple[str, str]]:
    """Every (path, name) of the run that calls a Gym wrapper class whose step and reset hand
    on the wrapped env's results (``ModuleSummary.forwarding_wrappers``): the class, its
    re-exports (star imports too) and subclasses that define neither step nor reset."""
    exports = Exports(facts, by_path)
    own = {(path, name) for path, summary in by_path.items() if path not in facts.blocked for name in summary.forwarding_wrappers}
    return frozenset(_kept_names(facts, by_path, exports, own, ("step", "reset")))


def _kept_names(
    facts: ProjectFacts,
    by_path: dict[str, ModuleSummary],
    exports: Exports,
    kept: set[tuple[str, str]],
    methods: tuple[str, ...] = ("step",),
) -> set[tuple[str, str]]:
    """``kept`` with the names of the run that re-export one (star imports too) and the
    subclasses of one that define none of ``methods``."""
    found = set()
    for path, summary in by_path.items():
        if path in facts.blocked:
            continue
        for name in summary.exports:
            where: tuple[str, str] | None = (path, name)
            for _ in range(MAX_CHAIN):
                if where is None or where[0] in facts.blocked:
                    break
                here = by_path.get(where[0])
                if here is None:
                    break
                if where in kept:
                    found.add((path, name))
                    break
                kind = here.exports.get(where[1])
                if any(f"{where[1]}.{method}" in here.defs for method in methods) or not is_ref(kind):
                    break  # its own step, or not a name of the run to follow
                split = facts._split(str(kind)[len(REF) :], where[0])
                where = split if split is not None and "." not in split[1] else None
    # ``from .wrappers import *`` in a package's ``__init__``: ``from pkg import Kept`` makes
    # the same instances (star chains followed to the module that defines the name)
    for path, summary in by_path.items():
        if path in facts.blocked:
            continue
        for name in exports.star_names(summary):
            if name not in summary.exports and exports.origin(path, name, set()) in found:
                found.add((path, name))
    return found


def class_definer(facts: ProjectFacts, by_path: dict[str, ModuleSummary], path: str, name: str) -> tuple[str, str] | None:
    """The module and name of the class of the run that ``name`` of module ``path`` is,
    re-exports (``from .core import TrialEnv`` in a package's ``__init__``) followed."""
    for _ in range(MAX_CHAIN):
        summary = by_path.get(path)
        if summary is None:
            return None
        if name in summary.classes:
            return path, name
        kind = summary.exports.get(name)
        if not is_ref(kind):
            return None
        split = facts._split(str(kind)[len(REF) :], path)
        if split is None or "." in split[1]:
            return None
        path, name = split
    return None


def base_definer(facts: ProjectFacts, by_path: dict[str, ModuleSummary], path: str, base: str) -> tuple[str, str] | None:
    """The class of the run (module and name, re-exports followed) that the base ``base``
    of a class of module ``path`` names, as its summary spells it (``OWN`` for a class of
    that module)."""
    if base.startswith(OWN):
        return path, base[len(OWN) :]
    split = facts._split(base, path)
    return class_definer(facts, by_path, *split) if split is not None and "." not in split[1] else None


def _star_definer(
    facts: ProjectFacts, by_path: dict[str, ModuleSummary], exports: Exports, path: str, name: str, seen: frozenset[tuple[str, str]]
) -> tuple[str, str] | None:
    """``class_definer``, with a module's ``from m import *`` of the run's modules followed
    too (a package's ``__init__`` that re-exports its submodules' classes so). Where several
    star imports bind the name (a submodule re-exporting what an earlier one gave), they
    must all lead to one class: a binding that comes back to the name itself is the earlier
    one again, anything else two classes is not known."""
    summary = by_path.get(path)
    if summary is None or (path, name) in seen or len(seen) > MAX_CHAIN * 4:
        return None
    seen = seen | {(path, name)}
    if name in summary.classes:
        return path, name
    kind = summary.exports.get(name)
    if kind is not None:
        split = facts._split(str(kind)[len(REF) :], path) if is_ref(kind) else None
        return _star_definer(facts, by_path, exports, *split, seen) if split is not None and "." not in split[1] else None
    found = {
        where
        for module in summary.star_imports
        if (target := exports.star_target(summary, module)) is not None
        and name in exports.public_names(target, set())
        and (where := _star_definer(facts, by_path, exports, target, name, seen)) is not None
    }
    return found.pop() if len(found) == 1 else None


def render_definers(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> dict[str, tuple[str, str]]:
    """Each literal id of ``no_render_mode_classes`` -> the class whose render()
    ``gymnasium.make(id)`` reaches: its class, or the first base of the run up its chain
    that defines render() (bases in the order they are named). A base that cannot be
    followed leaves the id out: what its render() takes is not known."""
    exports = Exports(facts, by_path)
    found = {}
    for env_id, start in facts.no_render_mode_classes.items():
        key: tuple[str, str] | None = start
        for _ in range(MAX_CHAIN):
            if env_id is None or key is None:
                break
            summary = by_path[key[0]]
            if f"{key[1]}.render" in summary.defs:
                found[env_id] = key
                break
            bases = summary.run_bases.get(key[1], ())
            key = _star_definer(facts, by_path, exports, *split, frozenset()) if bases and (split := _base_split(facts, key[0], bases[0])) else None
    return found


def _base_split(facts: ProjectFacts, path: str, base: str) -> tuple[str, str] | None:
    if base.startswith(OWN):
        return path, base[len(OWN) :]
    split = facts._split(base, path)
    return split if split is not None and "." not in split[1] else None


def class_methods(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> dict[tuple[str, str], frozenset[str]]:
    """(path, name) -> the methods of the class of the run that ``name`` of module ``path``
    is (re-exports followed), with those of its bases of the run in any module, at any
    depth. ``class Task(pkg.TrialEnv)`` defining only ``_step`` is a gym < 0.9 env when no
    such base defines ``step``; when ``TrialEnv`` does, ``_step`` is that base's own hook
    (custom_env/common.py)."""
    bases: dict[tuple[str, str], tuple[str, ...]] = {}
    for path, summary in by_path.items():
        for name, heir_bases, _ in summary.render_mode_heirs:
            bases[(path, name)] = heir_bases

    def definer(path: str, name: str) -> tuple[str, str] | None:
        return class_definer(facts, by_path, path, name)

    memo: dict[tuple[str, str], frozenset[str]] = {}

    def methods(key: tuple[str, str], depth: int) -> frozenset[str]:
        if key in memo:
            return memo[key]
        memo[key] = frozenset()  # a cycle of bases adds nothing
        path, name = key
        prefix = name + "."
        found = {q[len(prefix) :] for q in by_path[path].defs if q.startswith(prefix) and "." not in q[len(prefix) :]}
        for base in bases.get(key, ()) if depth < MAX_CHAIN else ():
            where = base_definer(facts, by_path, path, base)
            if where is not None and where[1] in by_path[where[0]].classes:
                found |= methods(where, depth + 1)
        memo[key] = frozenset(found)
        return memo[key]

    result: dict[tuple[str, str], frozenset[str]] = {}
    for path, summary in by_path.items():
        for name in summary.classes:
            result[(path, name)] = methods((path, name), 0)
        for name, kind in summary.exports.items():
            if name not in summary.classes and is_ref(kind):
                where = definer(path, name)
                if where is not None:
                    result[(path, name)] = methods(where, 0)
    return result


def wrapper_steppers(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> dict[tuple[str, str], str]:
    """(path, name) -> the class of the run whose reset steps the wrapper its instance was
    handed (``facts/wrapper_steps.py``: ``self._top.step(...)``, where a class of the run
    calls ``env.unwrapped.set_top(self)``), for that class, every subclass of it at any
    depth and every name re-exporting one. A subclass that overrides reset counts too: it
    may call the base's (``super().reset()``), and counting it costs only the checker."""
    handoffs = frozenset().union(*(summary.self_handoffs for summary in by_path.values()))
    own = {
        (path, name)
        for path, summary in by_path.items()
        for name, steps in summary.reset_steps.items()
        if steps_its_wrapper(steps, handoffs)
    }
    if not own:
        return {}
    bases: dict[tuple[str, str], tuple[str, ...]] = {}
    for path, summary in by_path.items():
        for name, heir_bases, _ in summary.render_mode_heirs:
            bases[(path, name)] = heir_bases
    memo: dict[tuple[str, str], str | None] = {}

    def stepper(key: tuple[str, str], depth: int) -> str | None:
        if key in memo:
            return memo[key]
        memo[key] = None  # a cycle of bases adds nothing
        found = key[1] if key in own else None
        for base in bases.get(key, ()) if depth < MAX_CHAIN and found is None else ():
            where = base_definer(facts, by_path, key[0], base)
            if where is not None and where[1] in by_path[where[0]].classes:
                found = found or stepper(where, depth + 1)
        memo[key] = found
        return found

    result: dict[tuple[str, str], str] = {}
    for path, summary in by_path.items():
        for name in summary.classes | set(summary.exports):
            where = (path, name) if name in summary.classes else class_definer(facts, by_path, path, name)
            found = stepper(where, 0) if where is not None else None
            if found is not None:
                result[(path, name)] = found
    return result
