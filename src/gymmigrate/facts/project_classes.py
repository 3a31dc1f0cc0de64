"""Class hierarchies across the modules of the run, passes of ``ProjectFacts.join``: the
methods subclasses in other modules override and the step hooks they can follow, the
``self.render(mode)`` calls that reach a base's render(), the classes an ``entry_point``
registers, the classes that count no steps or derive a library API of their own, and the
names of the run that re-export any of them.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from gymmigrate.facts.import_roots import import_parts
from gymmigrate.facts.init_attributes import ClassStores, certain_attributes
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module_summary import MAX_CHAIN, OWN, REF, ModuleSummary, is_ref
from gymmigrate.facts.project_contracts import class_definer
from gymmigrate.facts.project_exports import Exports

if TYPE_CHECKING:
    from gymmigrate.facts.project import ProjectFacts


def join_registered_classes(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> None:
    """``register(id, entry_point="pkg.envs:Task")`` (``__name__ + ":Task"``): the class
    the entry point names, where it is defined; the ids the run registers, and the class
    each literal id makes."""
    classes_of: dict[str, set[tuple[str, str] | None]] = {}
    for path, summary in by_path.items():
        facts.registered_ids.update(summary.registered_ids)
        for env_id, entry in summary.registrations:
            module, _, name = entry.partition(":")
            where = facts.modules.get(module) if module else path
            definer = None if where is None or not name or "." in name else class_definer(facts, by_path, where, name)
            if definer is not None:
                facts.registered_classes.add(definer)
            if env_id is not None:
                classes_of.setdefault(env_id, set()).add(definer)
    for env_id, found in classes_of.items():
        only = next(iter(found)) if len(found) == 1 else None
        if only is not None:
            facts.id_classes[env_id] = only


def join_unset_spaces(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> None:
    """``ProjectFacts.unset_spaces``: the classes an entry point of the run makes with the env
    checker on (the class it names, re-exports followed, or those a def it names constructs)
    with the spaces they leave unset together with every base (``ModuleSummary.unset_spaces``).
    A base the run cannot follow, or that sets a space, leaves that space out."""
    memo: dict[tuple[str, str], frozenset[str]] = {}

    def unset(key: tuple[str, str], depth: int) -> frozenset[str]:
        if key in memo:
            return memo[key]
        memo[key] = frozenset()  # a cycle of bases adds nothing
        summary = by_path.get(key[0])
        entry = summary.unset_spaces.get(key[1]) if summary is not None else None
        if entry is None or depth > MAX_CHAIN:
            return frozenset()
        spaces, bases = entry
        found = frozenset(spaces)
        for base in bases:
            where = _class_named(facts, by_path, base, key[0])
            found &= unset(where, depth + 1) if where is not None else frozenset()
        memo[key] = found
        return found

    for path, summary in by_path.items():
        for entry in summary.checked_entries:
            module, _, name = entry.partition(":")
            where = facts.modules.get(module) if module else path
            if where is None or not name or "." in name:
                continue
            for made in _entry_makes(facts, by_path, where, name):
                spaces = unset(made, 0)
                if spaces:
                    facts.unset_spaces[made] = spaces

    def owner(key: tuple[str, str]) -> tuple[str, str]:
        # up through single bases of the run whose __init__ each class runs, while the base
        # leaves every space unset too: the spaces set there are set for the made class
        spaces = facts.unset_spaces[key]
        for _ in range(MAX_CHAIN):
            summary = by_path.get(key[0])
            entry = summary.unset_spaces.get(key[1]) if summary is not None else None
            if summary is None or entry is None or key[1] not in summary.base_built or len(entry[1]) != 1:
                break
            base = _class_named(facts, by_path, entry[1][0], key[0])
            if base is None or base == key or not spaces <= unset(base, 0):
                break
            key = base
        return key

    groups: dict[tuple[str, str], list[tuple[str, str]]] = {}
    for made in facts.unset_spaces:
        top = owner(made)
        if top != made:
            groups.setdefault(top, []).append(made)
    for top, heirs in groups.items():
        if len(heirs) + (top in facts.unset_spaces) < 2:
            continue  # one made class: its own item names it best
        facts.unset_heirs[top] = heirs
        facts.unset_owner.update((heir, top) for heir in heirs)


def join_unmade_classes(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> None:
    """``ProjectFacts.unmade_classes``: of the classes GM511 would report, those every
    registration of which has a literal id no module of the run names, in a run that names
    some other id it registers (its users are in it), whose every Gym make() passes a literal
    id and whose registrations are all read."""
    if not facts.unset_spaces or any(s.opaque_make or s.opaque_registrations for s in by_path.values()):
        return
    named = frozenset().union(*(s.named_ids for s in by_path.values()))
    if not named & {env_id for s in by_path.values() for env_id in s.registered_ids}:
        return  # the run makes none of its own ids: its users are elsewhere (a library)
    ids: dict[tuple[str, str], set[str | None]] = {}
    for path, summary in by_path.items():
        for env_id, entry in summary.registrations:
            module, _, name = entry.partition(":")
            where = facts.modules.get(module) if module else path
            if where is None or not name or "." in name:
                continue
            for made in _entry_makes(facts, by_path, where, name):
                ids.setdefault(made, set()).add(env_id)
    for made in facts.unset_spaces:
        registered = ids.get(made)
        if registered and None not in registered and not (registered & named):
            facts.unmade_classes.add(made)


def _entry_makes(facts: ProjectFacts, by_path: dict[str, ModuleSummary], path: str, name: str) -> list[tuple[str, str]]:
    """The classes an entry point ``name`` of module ``path`` makes: the class it names, or
    those the def it names constructs (re-exports followed to the def)."""
    for _ in range(MAX_CHAIN):
        summary = by_path.get(path)
        if summary is None:
            return []
        if name in summary.classes:
            return [(path, name)]
        if name in summary.defs:
            built = (_class_named(facts, by_path, b, path) for b in summary.def_builds.get(name, ()))
            return [where for where in built if where is not None]
        kind = summary.exports.get(name)
        if not is_ref(kind):
            return []
        split = facts._split(str(kind)[len(REF) :], path)
        if split is None or "." in split[1]:
            return []
        path, name = split
    return []


def _class_named(facts: ProjectFacts, by_path: dict[str, ModuleSummary], spelled: str, path: str) -> tuple[str, str] | None:
    """The class of the run a module spells ``spelled`` (``@Name`` for its own)."""
    if spelled.startswith(OWN):
        return path, spelled[len(OWN) :]
    split = facts._split(spelled, path)
    return None if split is None or "." in split[1] else class_definer(facts, by_path, *split)


def join_overrides(facts: ProjectFacts, summaries: list[ModuleSummary], by_path: dict[str, ModuleSummary]) -> None:
    """Which methods of a run's class are overridden by subclasses in other modules."""
    for summary in summaries:
        facts.self_calls.update(((summary.path, name), called) for name, called in summary.self_calls.items())
        for name in summary.instance_calls:
            facts.instance_calls.setdefault(name, []).append(summary.path)
        for name, line in summary.contains_calls:
            facts.contains_calls.setdefault(name, []).append((summary.path, line))
        facts.mujoco_py_uses.extend((summary.path, line) for line in summary.mujoco_py_uses)
        for name, bases, methods in summary.subclasses:
            for qualified in bases:
                level, parts = import_parts(qualified)
                path = facts._module_path(parts[:-1], level, summary.path) if len(parts) > 1 else None
                if not path or path == summary.path:
                    continue
                # ``class Task(pkg.BaseEnv)`` where ``pkg/__init__.py`` re-exports the
                # class of ``pkg/core.py``: the override is of the defining module's class.
                base = class_definer(facts, by_path, path, parts[-1]) or (path, parts[-1])
                if base[0] == summary.path:
                    continue
                found = facts.overrides.setdefault(base, {})
                for method in methods:
                    found.setdefault(method, []).append(f"{summary.path}:{name}")
                facts.subclasses_of.setdefault(base, []).append((summary.path, name))
            facts.subclass_methods[(summary.path, name)] = frozenset(methods)
            facts.base_calls[(summary.path, name)] = summary.super_calls.get(name, frozenset())
            facts.named_calls[(summary.path, name)] = summary.named_class_calls.get(name, frozenset())
        facts.init_passers.update((summary.path, name) for name in summary.passes_init_up)
        for name, methods_done in summary.done_methods.items():
            facts.done_methods[(summary.path, name)] = methods_done
        for name, methods_items in summary.done_items.items():
            facts.done_items[(summary.path, name)] = methods_items
    # A step hook is followed when every override elsewhere can follow it too; the
    # module of each override then migrates its returns with the base (hooks.py).
    for path, summary in by_path.items():
        for name, hooks in summary.step_hooks.items():
            if name not in summary.env_classes or name in summary.legacy_steps:
                continue  # a step the rules do not migrate: its hook stays as it is
            heirs: list[tuple[str, str]] = []
            todo = list(facts.subclasses_of.get((path, name), ()))
            while todo and len(heirs) < 1000:
                heir = todo.pop()
                if heir not in heirs:
                    heirs.append(heir)
                    todo += facts.subclasses_of.get(heir, ())
            followed = frozenset(
                hook
                for hook in hooks
                if all(
                    hook in by_path[where].plain_overrides.get(sub, ())
                    for where, sub in heirs
                    if hook in facts.subclass_methods.get((where, sub), ())
                )
            )
            if not followed:
                continue
            facts.followed_hooks[(path, name)] = followed
            for heir in heirs:
                facts.inherited_hooks[heir] = facts.inherited_hooks.get(heir, frozenset()) | followed


def star_reexporters(exports: Exports, path: str, name: str) -> list[str]:
    """The modules of the run whose ``from <module at path> import *`` binds ``name``, a
    class of ``path`` (one level: a package's ``__init__`` gathering its modules)."""
    if name not in exports.public_names(path, set()):
        return []
    return [
        where
        for where, summary in exports.by_path.items()
        if name not in summary.classes and name not in summary.exports and any(exports.star_target(summary, m) == path for m in summary.star_imports)
    ]


def join_step_shapes(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> None:
    """The helper steps of the run and the names that reach one, and the classes whose steps
    give five values once migrated (facts/own_steps.py). A candidate is a helper where
    every override of its step in another module, at any depth below classes that define
    no step, returns its own step values too, and at least one of them builds on it. The
    classes of its module below it whose step is its own (``helper_hand_ons``: none, or one
    that only hands it on) are looked through: overrides elsewhere below them count the
    same way, and one that hands it on needs a class below it."""
    helpers = set()
    intermediates = set()
    exports = Exports(facts, by_path)
    for path, summary in by_path.items():
        if path in facts.blocked:
            continue
        for name, local in summary.helper_candidates.items():
            overrides: int | None = local
            seen: set[tuple[str, str]] = set()
            todo = list(facts.subclasses_of.get((path, name), ()))
            hand_ons = summary.helper_hand_ons.get(name, ())
            for passing, needs_below in hand_ons:
                elsewhere = [
                    sub for where in (path, *star_reexporters(exports, path, passing)) for sub in facts.subclasses_of.get((where, passing), ())
                ]
                if needs_below and not elsewhere:
                    overrides = None  # its step hands the one value on as its own step
                todo += elsewhere
            while todo and overrides is not None:
                sub = todo.pop()
                if sub in seen:
                    continue
                seen.add(sub)
                if "step" not in facts.subclass_methods.get(sub, ()):
                    todo += facts.subclasses_of.get(sub, ())
                elif sub[0] in facts.blocked or sub[0] not in by_path or sub[1] not in by_path[sub[0]].own_step_shapes:
                    overrides = None
                else:
                    overrides += by_path[sub[0]].own_step_shapes[sub[1]]
            if overrides:
                helpers.add((path, name))
                intermediates |= {(path, passing) for passing, _ in hand_ons}
    facts.helper_steps = frozenset(helpers)
    reach = helpers | intermediates
    todo = list(reach)
    while todo:
        for sub in facts.subclasses_of.get(todo.pop(), ()):
            if sub not in reach and "step" not in facts.subclass_methods.get(sub, ()):
                reach.add(sub)
                todo.append(sub)
    for path, summary in by_path.items():
        for name in summary.exports:
            if name not in summary.classes and class_definer(facts, by_path, path, name) in reach:
                reach.add((path, name))  # a re-export (``from .base import Base``)
    for path, name in helpers | intermediates:
        # ``from .base import *`` in a package's ``__init__``: subclasses elsewhere name the
        # helper's classes through it
        reach |= {(where, name) for where in star_reexporters(exports, path, name)}
    facts.helper_step_names = frozenset(reach)
    facts.five_step_trees = frozenset(
        (path, name) for path, summary in by_path.items() if path not in facts.blocked for name in summary.five_step_trees
    )


def join_mode_renders(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> None:
    """``mode_renders_below``: a subclass's ``self.render(mode)`` reaches the render() of
    the nearest base that defines one; every class above it keeps ``mode`` (optional
    beside render_mode, or the whole legacy render() where it cannot) so the call still
    works."""
    for path, summary in by_path.items():
        for name, (line, call) in summary.mode_renders.items():
            where = (f"{os.path.basename(path)}:{line}", call)
            seen = {(path, name)}
            todo = [(path, name)]
            while todo:
                current = todo.pop()
                for base, subs in facts.subclasses_of.items():
                    if current in subs and base not in seen:
                        seen.add(base)
                        facts.mode_renders_below.setdefault(base, []).append(where)
                        if "render" not in facts.subclass_methods.get(base, frozenset()):
                            todo.append(base)  # a render() it does not define is its base's
    for path, name in facts.mode_renders_below:
        # render(mode) kept whole (its mode cannot become optional): no render_mode either
        if name in by_path[path].fixed_mode_renders and name in facts.render_mode_classes.get(path, ()):
            facts.render_mode_classes[path] = facts.render_mode_classes[path] - {name}


def own_api_classes(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> set[tuple[str, str]]:
    """The classes of the run deriving a library class with an env API of its own, their
    subclasses in other modules added until none is left (a chain is short)."""
    found = {(path, name) for path, summary in by_path.items() for name in summary.own_api_classes}
    for _ in range(MAX_CHAIN):
        added = False
        for path, summary in by_path.items():
            for name, bases, _methods in summary.subclasses:
                if (path, name) in found:
                    continue
                for qualified in bases:
                    level, parts = import_parts(qualified)
                    where = facts._module_path(parts[:-1], level, path) if len(parts) > 1 else None
                    if where and class_definer(facts, by_path, where, parts[-1]) in found:
                        found.add((path, name))
                        added = True
                        break
        if not added:
            break
    return found


def imported_class(facts: ProjectFacts, by_path: dict[str, ModuleSummary], path: str, qualified: str) -> tuple[str, str] | None:
    """The class of the run (its module and name, re-exports followed) that the base
    ``qualified`` of a class of module ``path`` names as that module's imports spell it."""
    level, parts = import_parts(qualified)
    where = facts._module_path(parts[:-1], level, path) if len(parts) > 1 else None
    return class_definer(facts, by_path, where, parts[-1]) if where else None


def inherit_driven_kinds(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> dict[tuple[str, str], dict[str, EnvKind]]:
    """(path, class) -> the attributes it drives or holds as its bases drive them: a class
    of the run that never stores ``self.env`` (``ModuleSummary.stored_attributes``) holds
    what its bases of other modules store and step there, at any depth (``class
    Deep(Fast)`` with ``Fast(Runner)`` storing nothing and ``Runner`` storing
    ``gym.make(...)``), when the bases that drive it agree. A module left as it is drives
    nothing."""
    found: dict[tuple[str, str], dict[str, EnvKind]] = {
        (path, name): dict(kinds)
        for path, summary in by_path.items()
        if path not in facts.blocked
        for name, kinds in summary.driven_kinds.items()
    }
    for _ in range(MAX_CHAIN):
        added = False
        for path, summary in by_path.items():
            if path in facts.blocked:
                continue
            for name, bases, _methods in summary.subclasses:
                stored = summary.stored_attributes.get(name)
                if stored is None:
                    continue
                offered: dict[str, set[EnvKind]] = {}
                for qualified in bases:
                    base = imported_class(facts, by_path, path, qualified)
                    for attribute, kind in found.get(base, {}).items() if base is not None else ():
                        if attribute not in stored:
                            offered.setdefault(attribute, set()).add(kind)
                own = found.setdefault((path, name), {})
                for attribute, kinds in offered.items():
                    if len(kinds) == 1 and attribute not in own:
                        own[attribute] = next(iter(kinds))
                        added = True
        if not added:
            break
    return {key: kinds for key, kinds in found.items() if kinds}


def quiet_classes(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> set[tuple[str, str]]:
    """The classes of the run that count no steps and whose bases, of any module of
    the run, count none either: a base the run does not define may count, so it keeps
    its subclasses out, as does a cycle."""
    memo: dict[tuple[str, str], bool] = {}

    def quiet(key: tuple[str, str]) -> bool:
        if key in memo:
            return memo[key]
        memo[key] = False  # while it is read (a cycle of bases proves nothing)
        entry = by_path[key[0]].step_counting.get(key[1]) if key[0] in by_path else None
        if entry is None:
            return False
        counts, local, other = entry
        found = not counts and all(quiet((key[0], base)) for base in local)
        for qualified in other if found else ():
            level, parts = import_parts(qualified)
            path = facts._module_path(parts[:-1], level, key[0]) if len(parts) > 1 else None
            base = class_definer(facts, by_path, path, parts[-1]) if path else None
            if base is None or not quiet(base):
                found = False
                break
        memo[key] = found
        return found

    return {(path, name) for path, summary in by_path.items() for name in summary.step_counting if quiet((path, name))}


def reexported(facts: ProjectFacts, by_path: dict[str, ModuleSummary], defined: set[tuple[str, str]]) -> frozenset[tuple[str, str]]:
    """``defined`` with every name of the run that re-exports one of them."""
    found = set(defined)
    for path, summary in by_path.items():
        for name, first in summary.exports.items():
            where = (path, name)
            export: EnvKind | str | None = first
            for _ in range(MAX_CHAIN):
                if not is_ref(export):
                    break
                split = facts._split(str(export)[len(REF) :], where[0])
                if split is None or "." in split[1] or split[0] not in by_path:
                    break
                where = split
                if where in defined:
                    found.add((path, name))
                    break
                export = by_path[where[0]].exports.get(where[1])
    exports = Exports(facts, by_path)
    for path, name in defined:
        if path in by_path:
            # ``from .base import *`` in a package's ``__init__``: its importers name the class there
            found |= {(where, name) for where in star_reexporters(exports, path, name)}
    return frozenset(found)




def join_duck_wrappers(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> None:
    """A plain class of the run shaped as a duck wrapper (``ModuleSummary.duck_wrappers``)
    that every construction in other modules gives a Gym env (``param_kinds``, after the
    parameters' pass) holds that env and forwards to it: its instances are Gym envs,
    under every name of the run that re-exports it (``call_kinds``). Its own module, which
    sees the same parameter kinds, migrates it as a wrapper."""
    proved: set[tuple[str, str]] = set()
    for path, summary in by_path.items():
        if path in facts.blocked:
            continue
        for name, param in summary.duck_wrappers.items():
            kinds = facts.param_kinds.get((path, f"{name}.__init__", param))
            if kinds and all(kind is EnvKind.GYM_ENV for kind in kinds):
                proved.add((path, name))
    if not proved:
        return
    for where in reexported(facts, by_path, proved):
        if facts.call_kinds.get(where) in (None, EnvKind.UNKNOWN):
            facts.call_kinds[where] = EnvKind.GYM_ENV


def join_init_attributes(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> None:
    """``ProjectFacts.init_attributes``: per name of the run bound to a class (re-exports
    followed), what its instances certainly hold once constructed, bases of other modules
    followed (``facts/init_attributes.py``). Classes that certainly hold nothing are left out."""
    def lookup(key: tuple[str, str]) -> ClassStores | None:
        summary = by_path.get(key[0])
        return summary.class_stores.get(key[1]) if summary is not None else None

    def resolve(key: tuple[str, str], base: str) -> tuple[str, str] | None:
        if base.startswith(OWN):
            return class_definer(facts, by_path, key[0], base[len(OWN) :])
        return imported_class(facts, by_path, key[0], base)

    found: dict[tuple[str, str], frozenset[str]] = {}
    for path, summary in by_path.items():
        for name in summary.class_stores:
            attributes = certain_attributes((path, name), lookup, resolve)
            if attributes:
                found[(path, name)] = attributes
    for path, summary in by_path.items():
        for name in summary.exports:
            where = class_definer(facts, by_path, path, name)
            if where is not None and where in found:
                facts.init_attributes[(path, name)] = found[where]
