"""Methods the run removes or renames, and the classes of other modules that still call them
by their old name: a pass of ``ProjectFacts.join``.

A module migrates its own classes: it deletes a canonical ``seed()`` (GM503) and renames
gym <= 0.9's ``_reset`` to ``reset``. A subclass in another module that calls
``self.seed(s)`` or ``super()._reset()`` reaches that method by its old name, and would
raise AttributeError once its base migrated. Each module's summary lists, per class, its
bases of the run in order, the names it calls on ``self`` and on a base, and the hooks it
renames on its own knowledge (``ModuleSummary.run_bases``, ``self_calls``,
``super_calls``, ``renamed_hooks``); this pass joins them:

* ``hook_renames``: the hooks each env class of the run renames, less those whose public
  name a base in another module defines (then the hook is that base's own, kept);
* ``called_below``: for a method of a class, the classes of other modules whose
  ``self.m(...)`` or ``super().m(...)`` reaches it (the first class defining ``m`` from
  the caller up, bases in the order they are named): the base keeps what they call, or
  they follow its rename (``rules/custom_env/seed.py``, ``hook_calls.py``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from gymmigrate.facts.env_classes import UNDERSCORE_HOOKS
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module_summary import MAX_CHAIN, ModuleSummary
from gymmigrate.facts.project_contracts import base_definer, class_definer

if TYPE_CHECKING:
    from gymmigrate.facts.project import ProjectFacts

Key = tuple[str, str]  # (path, class)

# The methods whose callers elsewhere the join follows: those the run removes (seed) or
# renames (gym <= 0.9's hooks), under either name.
_FOLLOWED = frozenset({"seed", *UNDERSCORE_HOOKS})


def join_hook_calls(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> None:
    """Fill ``facts.class_bases``, ``hook_renames``, ``renamed_above`` and ``called_below``."""
    bases: dict[Key, tuple[Key, ...]] = {}
    for path, summary in by_path.items():
        for name, spelled in summary.run_bases.items():
            resolved = [where for base in spelled if (where := base_definer(facts, by_path, path, base)) is not None]
            if resolved:
                bases[(path, name)] = tuple(resolved)
    facts.class_bases = bases
    for path, summary in by_path.items():
        if path in facts.blocked:
            continue  # left as it is: nothing of it is renamed
        wrappers = facts.wrapper_classes.get(path, frozenset())
        for name, olds in summary.renamed_hooks.items():
            key = (path, name)
            if name in wrappers or facts.call_kinds.get(key) is not EnvKind.GYM_ENV:
                continue  # the rules rename the hooks of Gym env classes only
            methods = facts.class_methods.get(key, frozenset())
            kept = frozenset(old for old in olds if UNDERSCORE_HOOKS[old] not in methods)
            if kept:
                facts.hook_renames[key] = kept
    if facts.hook_renames:
        for path, summary in by_path.items():
            for name in summary.exports:
                where = class_definer(facts, by_path, path, name)
                renamed = renamed_reaching(facts, where) if where is not None else frozenset()
                if renamed:
                    facts.renamed_above[(path, name)] = renamed
    for path, summary in by_path.items():
        for name in summary.run_bases:
            caller = (path, name)
            own = summary.self_calls.get(name, frozenset()) & _FOLLOWED
            up = summary.super_calls.get(name, frozenset()) & _FOLLOWED
            for method, starts in [(m, (caller,)) for m in sorted(own)] + [(m, bases.get(caller, ())) for m in sorted(up)]:
                definer = first_definer(facts, starts, method)
                if definer is None and method == "seed":
                    # gym <= 0.9's Env.seed called ``self._seed``: a base's ``_seed`` is what runs
                    definer = first_definer(facts, starts, "_seed")
                    method = "_seed" if definer is not None else method
                if definer is not None and definer[0] != path:
                    found = facts.called_below.setdefault(definer, {}).setdefault(method, [])
                    if f"{path}:{name}" not in found:
                        found.append(f"{path}:{name}")


def first_definer(facts: ProjectFacts, starts: tuple[Key, ...], method: str) -> Key | None:
    """The first class from ``starts`` up (depth first, bases in the order they are named)
    whose own body defines ``method``."""
    seen: set[Key] = set()
    todo = list(reversed(starts))
    while todo and len(seen) < MAX_CHAIN * 4:
        key = todo.pop()
        if key in seen:
            continue
        seen.add(key)
        if f"{key[1]}.{method}" in facts.defs.get(key[0], frozenset()):
            return key
        todo.extend(reversed(facts.class_bases.get(key, ())))
    return None


def renamed_reaching(facts: ProjectFacts, start: Key) -> frozenset[str]:
    """The gym <= 0.9 hooks that a lookup from the class ``start`` up finds first in a class
    that renames them: ``super()._reset()`` below it calls a method that is gone."""
    return frozenset(
        old
        for old in UNDERSCORE_HOOKS
        if (definer := first_definer(facts, (start,), old)) is not None and old in facts.hook_renames.get(definer, frozenset())
    )
