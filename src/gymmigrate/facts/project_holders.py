"""What the run's classes hold, passes of ``ProjectFacts.join``: the holders of bare make
results (``ModuleSummary.made_holders``) and the parameters every call of another module
hands one of their instances (``CallSummary.holders``): ``def __init__(self, env)`` given
``GymEnv(name)`` by every caller, where ``GymEnv`` stores ``self.env = gym.make(name)``,
reads ``env.env`` as that make result. And the properties that only return an attribute of
``self`` (``ModuleSummary.property_aliases``), inherited along the bases of the run: a
subclass of a proxy reads ``self.wrapped_env`` as the ``self._wrapped_env`` its base stores.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from gymmigrate.facts.module_summary import MAX_CHAIN, OWN, CallSummary, ModuleSummary
from gymmigrate.facts.project_contracts import class_definer

if TYPE_CHECKING:
    from gymmigrate.facts.project import ProjectFacts


def join_made_holders(facts: ProjectFacts, by_path: dict[str, ModuleSummary], calls_to: dict[tuple[str, str], list[tuple[str, CallSummary]]]) -> None:
    """``ProjectFacts.made_holders`` for every name of a holder class (re-exports followed),
    and ``ProjectFacts.held_made``: per parameter some call of another module passes to, the
    attributes that hold a bare make result in what every such call passes (empty where one
    passes anything else)."""
    for path, summary in by_path.items():
        if path in facts.blocked:
            continue
        for name in summary.exports:
            if name in summary.defs:
                continue  # a def's export names what it returns, not a class
            where = class_definer(facts, by_path, path, name)
            held = by_path[where[0]].made_holders.get(where[1]) if where is not None and where[0] not in facts.blocked else None
            if held:
                facts.made_holders[(path, name)] = held
    if not facts.made_holders:
        return
    for (path, qualname), calls in calls_to.items():
        signature = by_path[path].defs.get(qualname)
        if signature is None:
            continue
        positional = list(signature.params[1:] if signature.is_method else signature.params)
        for caller, call in calls:
            if caller == path:
                continue  # the file sees its own call sites itself
            holders = dict(call.holders)
            given = {name for name, _ in call.keywords}
            for index, param in enumerate(positional):
                slot = str(index) if index < len(call.args) else param if param in given else None
                held = _held(facts, holders.get(slot), caller) if slot is not None else frozenset()
                key = (path, qualname, param)
                facts.held_made[key] = facts.held_made[key] & held if key in facts.held_made else held


def _held(facts: ProjectFacts, holder: str | None, caller: str) -> frozenset[str]:
    """The attributes holding a bare make result in an instance of ``holder`` as ``caller``
    names it (``@Name`` for a class of its own)."""
    if holder is None:
        return frozenset()
    where = (caller, holder[len(OWN) :]) if holder.startswith(OWN) else facts._split(holder, caller)
    return facts.made_holders.get(where, frozenset()) if where is not None else frozenset()


def join_property_aliases(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> None:
    """``ProjectFacts.property_aliases`` for every name of a class of the run (re-exports
    followed) that has such properties, its own or its bases' of the run."""
    memo: dict[tuple[str, str], dict[str, str]] = {}
    for path, summary in by_path.items():
        for name in summary.exports:
            if name in summary.defs:
                continue  # a def's export names what it returns, not a class
            where = class_definer(facts, by_path, path, name)
            found = _aliases(facts, by_path, where, memo, 0) if where is not None else {}
            if found:
                facts.property_aliases[(path, name)] = found


def _aliases(
    facts: ProjectFacts, by_path: dict[str, ModuleSummary], where: tuple[str, str], memo: dict[tuple[str, str], dict[str, str]], depth: int
) -> dict[str, str]:
    """The property aliases of the class ``where`` defines, its own over its bases' (an
    earlier base over a later one, as the method resolution order reads them)."""
    if where in memo:
        return memo[where]
    memo[where] = {}  # a cycle of bases adds nothing
    if depth > MAX_CHAIN:
        return {}
    path, name = where
    summary = by_path[path]
    found: dict[str, str] = {}
    stores = summary.class_stores.get(name)
    for base in reversed(stores.bases if stores is not None else ()):
        split = (path, base[len(OWN) :]) if base.startswith(OWN) else facts._split(base, path) if base else None
        definer = class_definer(facts, by_path, *split) if split is not None and "." not in split[1] else None
        if definer is not None:
            found.update(_aliases(facts, by_path, definer, memo, depth + 1))
    found.update(summary.property_aliases.get(name, {}))
    memo[where] = found
    return found
