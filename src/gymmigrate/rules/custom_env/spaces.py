"""GM511: an env class that ``gymnasium.make`` builds but that never sets a space (report only).

gym 0.21's ``Env`` gave every env ``action_space = None`` and ``observation_space = None``;
Gymnasium's only annotates them, and the env checker ``make`` puts around every env raises
``AttributeError: The environment must specify an observation space`` the moment the env is
built. Asked once at the class, where an entry point of the run makes it (the class itself or
a registered def that constructs it) and neither the class nor a base sets the space by the
end of its construction (``facts/space_setters.py``).

Source: Gymnasium 1.4 ``wrappers/common.py`` (``PassiveEnvChecker.__init__``), ``core.py``.
"""

from __future__ import annotations

import ast

from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import ModuleFacts, call_argument, string_value
from gymmigrate.facts.space_setters import SPACES, local_unset_spaces, registered_here
from gymmigrate.facts.summaries.defs import named_ids
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.custom_env.common import ClassDecision


def decide_unset_spaces(decision: ClassDecision) -> None:
    classdef = decision.classdef
    family = decision.family
    facts, receivers = family.facts, family.receivers
    if not family.context.profile.imports_gym:
        return  # written for Gymnasium: no legacy default was ever there
    if facts.classes.get(classdef.name) is not classdef or receivers.class_kind(classdef) is not EnvKind.GYM_ENV:
        return
    project = receivers.project
    unset = project.unset_spaces(classdef.name) if project is not None else frozenset()
    if not unset:
        # ``register(id=..., entry_point=Sim)`` in this module (a run of one file, or an entry
        # point the join does not read: the class object itself)
        made = facts.memo(("registered-here", 0), lambda: registered_here(facts, receivers, None))
        unset = (local_unset_spaces(facts, receivers, classdef) or frozenset()) if classdef.name in made else frozenset()
    if not unset:
        return
    missing = [space for space in SPACES if space in unset]
    named = " and ".join(f"`{space}`" for space in missing)
    first = missing[0].split("_")[0]
    if project.made_by_nothing(classdef.name) if project is not None else _made_by_nothing_here(facts, classdef.name):
        # registered, but no module of the run names its id: no make of the run builds it,
        # and a make elsewhere met the same unset spaces under gym (its reset raised first)
        decision.report(
            classdef,
            "GM511",
            f"`{classdef.name}` leaves {named} unset once built; it is registered, but no make of the run names its id: "
            f"where something else makes it, the env checker `gymnasium.make` puts around it raises AttributeError "
            f"(\"The environment must specify an {first} space\")",
            FixKind.FLAG,
            Tier.NOTE,
        )
        return
    decision.report(
        classdef,
        "GM511",
        f"`{classdef.name}` leaves {named} unset once built (gym 0.21's Env had None there; Gymnasium's has no default), and an entry "
        f"point of the run makes it: the env checker `gymnasium.make` puts around it raises AttributeError (\"The environment "
        f"must specify an {first} space\") where no wrapper in between sets one; set "
        + " and ".join(f"`self.{space}`" for space in missing)
        + " in `__init__`, or register (or make) it with `disable_env_checker=True`",
        FixKind.FLAG,
    )


def _made_by_nothing_here(facts: ModuleFacts, name: str) -> bool:
    """A run of this module alone: every ``register()`` naming class ``name`` as its entry
    point passes a literal id that no other string of the module names, the module names
    another id it registers, and every make() of the module passes a literal id
    (``ProjectFacts.unmade_classes`` for one module)."""
    named, opaque = named_ids(facts)
    if opaque:
        return False
    ids = []
    others = False  # the module makes another id it registers: its users are here
    for call in (*facts.calls_by_name.get("register", ()), *facts.attribute_calls.get("register", ())):
        entry = call_argument(call, 1, "entry_point")
        if entry is None:
            continue
        text = string_value(entry)
        if text is None and isinstance(entry, ast.BinOp) and isinstance(entry.right, ast.Constant):
            text = string_value(entry.right)  # ``__name__ + ":Class"``
        if text is None and isinstance(entry, ast.Name):
            text = ":" + entry.id
        env_id = call_argument(call, 0, "id")
        literal = string_value(env_id) if env_id is not None else None
        if text is None or text.rpartition(":")[2] != name:
            others = others or literal in named
            continue
        ids.append(literal)
    return others and bool(ids) and None not in ids and not (set(ids) & named)
