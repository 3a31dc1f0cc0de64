"""Whether ``env.set_wrapper_attr("x", v)`` on what ``gym.make`` returned certainly sets ``x``
on the env itself, as the legacy write to the bare env did (GM604, ``forwarding.py``).

Gymnasium 1.4's ``Wrapper.set_wrapper_attr`` sets the name on the outermost layer that
has it, and on the outermost wrapper when none does. So the write reaches the env where the
env has the name when it is written and no layer ``make`` adds has it: every class the make
may build stores it when constructed (``facts/init_attributes.py``), and it is no attribute
of make's wrappers (``MAKE_LAYER_ATTRIBUTES``). The classes are those the run registers for
the ids the make is given, where the run spells every id and entry point it registers.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.init_attributes import local_init_attributes
from gymmigrate.facts.module import call_argument, own_entry_point, string_value
from gymmigrate.facts.receivers import Receivers
from gymmigrate.rules.wrapper_usage.atari_limits import made_on_every_path, make_ids
from gymmigrate.rules.wrapper_usage.tables import MAKE_LAYER_ATTRIBUTES

_REGISTER = frozenset({"register", "envs.register", "envs.registration.register"})


def classes_holding(facts: ModuleFacts, receivers: Receivers, receiver: ast.expr, name: str) -> list[str] | None:
    """The classes the makes ``receiver`` holds may build, by name, where each certainly has
    ``name`` once constructed and no layer ``make`` adds has it; None where the run cannot
    tell (an id it does not register, or that is no literal)."""
    if name in MAKE_LAYER_ATTRIBUTES or not isinstance(receiver, ast.Name):
        return None
    makes = made_on_every_path(facts, receiver)
    if makes is None:
        return None
    found: set[str] = set()
    for make in makes:
        ids = make_ids(facts, receivers, make)
        if not ids or None in ids:
            return None
        for env_id in ids:
            assert env_id is not None
            holder = _holder(facts, receivers, env_id, name)
            if holder is None:
                return None
            found.add(holder)
    return sorted(found) or None


def _holder(facts: ModuleFacts, receivers: Receivers, env_id: str, name: str) -> str | None:
    """The class ``make(env_id)`` builds, where it certainly has ``name`` once constructed."""
    view = receivers.project
    if view is not None:
        where = view.class_of_id(env_id)
        if where is None:
            return None
        attributes = view.facts.init_attributes.get(where, frozenset())
        return where[1] if name in attributes else None
    classdef = _local_class_of_id(facts, env_id.rpartition(":")[2])
    return classdef.name if classdef is not None and name in local_init_attributes(facts, classdef) else None


def _local_class_of_id(facts: ModuleFacts, env_id: str) -> ast.ClassDef | None:
    """For a file processed alone: the class of the file its one registration of ``env_id``
    names (``entry_point=__name__ + ":Task"``), where every registration of the file spells
    its id."""
    found = None
    for call in (*facts.calls_by_name.get("register", ()), *facts.attribute_calls.get("register", ())):
        if not any(N.strip_gym_prefix(q) in _REGISTER for q in facts.qualified_names(call.func)):
            continue
        registered = call_argument(call, 0, "id")
        registered_id = string_value(registered) if registered is not None else None
        if registered_id is None:
            return None  # an id the file does not spell may be this one
        if registered_id.rpartition(":")[2] != env_id:
            continue
        entry = own_entry_point(call_argument(call, 1, "entry_point"))
        classdef = facts.classes.get(entry[1:]) if entry is not None else None
        if classdef is None or found is not None:
            return None
        found = classdef
    return found
