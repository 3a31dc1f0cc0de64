"""Classes of the project's own that hold what ``gym.make`` returned, bare, in an attribute
(``self.env = gym.make(name)`` in a plain class ``GymEnv``): what ``holder.env`` is for an
instance of one, in this module or handed to a def of another module of the run
(``ModuleSummary.made_holders``, joined by ``facts/project_holders.py``).

The forwarding rules (``rules/wrapper_usage/``) read ``holder.env.env`` as a chain below a
bare make result, as they read ``env.env`` on a name bound to ``gym.make``: gym's make
stacked known wrappers under that attribute, and nothing of the project's own.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import names as N
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import ModuleFacts
from gymmigrate.facts.receivers import Receivers
from gymmigrate.facts.self_attributes import self_stores


def is_make(facts: ModuleFacts, expr: ast.AST) -> bool:
    """A call of gym's ``make`` (through the module's imports)."""
    return isinstance(expr, ast.Call) and any(N.strip_gym_prefix(q) in N.GYM_ENV_FACTORIES for q in facts.qualified_names(expr.func))


def holds_bare_make(facts: ModuleFacts, value: ast.expr) -> bool:
    """``value`` is a ``make(...)`` call, or a local name every binding of which assigns one
    (``env = gym.make(name)`` then ``self.env = env``)."""
    if is_make(facts, value):
        return True
    if not isinstance(value, ast.Name):
        return False
    bindings = facts.bindings_of(value)
    for binding in bindings:
        statement = facts.parent(binding) if isinstance(binding, ast.Name) else None
        if not (isinstance(statement, ast.Assign) and statement.targets == [binding] and is_make(facts, statement.value)):
            return False
    return bool(bindings)


def made_attributes(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> frozenset[str]:
    """The attributes every store of which in ``classdef`` is a bare make result, for a class
    that derives from nothing but ``object`` (a base could store the attribute otherwise) and
    is no Gym env or wrapper (whose ``self.env`` is what it wraps)."""

    def compute() -> frozenset[str]:
        if classdef.keywords or any(not (isinstance(b, ast.Name) and b.id == "object") for b in classdef.bases):
            return frozenset()
        if receivers.is_gym_wrapper_class(classdef) or receivers.class_kind(classdef) is EnvKind.GYM_ENV:
            return frozenset()
        found = set()
        for attribute in receivers.self_stores(classdef):
            values = self_stores(facts, classdef, attribute)
            if values and all(holds_bare_make(facts, value) for value in values):
                found.add(attribute)
        return frozenset(found)

    return facts.memo(("made-attributes", id(classdef)), compute)


def made_holders(facts: ModuleFacts, receivers: Receivers) -> dict[str, frozenset[str]]:
    """``ModuleSummary.made_holders``: per top-level class, ``made_attributes``."""
    return {name: held for name, classdef in facts.classes.items() if (held := made_attributes(facts, receivers, classdef))}
