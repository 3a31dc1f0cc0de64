"""Which expressions are an ``EnvSpec`` (GM806's receivers): ``x.spec``, ``gym.spec(...)``,
an item of the registry, a name only ever bound to one of those or iterated over the
registry's specs. Read by rules/env_ids/registry.py."""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.rules.env_ids.syntax import is_registry

_SPEC_FUNCTIONS = frozenset({"spec", "envs.spec", "envs.registration.spec"})
# How far ``spec = specs[i]; s = spec`` chains are followed: enough for real code, and
# it bounds the work per attribute.
_MAX_SPEC_DEPTH = 3


def is_env_spec(facts: ModuleFacts, expr: ast.AST, depth: int = 0) -> bool:
    if depth > _MAX_SPEC_DEPTH:
        return False
    if isinstance(expr, ast.Attribute) and expr.attr == "spec":
        return True  # env.spec, self.spec, gym.make(...).spec
    if isinstance(expr, ast.Call):
        if any(N.strip_gym_prefix(q) in _SPEC_FUNCTIONS for q in facts.qualified_names(expr.func)):
            return True
        return isinstance(expr.func, ast.Attribute) and expr.func.attr == "spec" and is_registry(facts, expr.func.value)
    if isinstance(expr, ast.Subscript):
        return is_registry(facts, expr.value) or _is_env_specs_dict(facts, expr.value)
    if isinstance(expr, ast.Name):
        return _name_is_env_spec(facts, expr, depth)
    return False


def _is_env_specs_dict(facts: ModuleFacts, expr: ast.AST) -> bool:
    return isinstance(expr, ast.Attribute) and expr.attr == "env_specs" and is_registry(facts, expr.value)


def _iterates_specs(facts: ModuleFacts, iterable: ast.AST) -> bool:
    """``registry.all()``, ``registry.values()``, ``registry.env_specs.values()``."""
    if not (isinstance(iterable, ast.Call) and isinstance(iterable.func, ast.Attribute)):
        return False
    owner = iterable.func.value
    return iterable.func.attr in ("all", "values") and (is_registry(facts, owner) or _is_env_specs_dict(facts, owner))


def _lists_specs(facts: ModuleFacts, iterable: ast.AST, depth: int) -> bool:
    """``specs = [s for s in registry.values() if ...]``: a name bound only to a list of
    the registry's specs (a comprehension over them that yields its own target)."""
    if depth > _MAX_SPEC_DEPTH or not isinstance(iterable, ast.Name):
        return False
    bindings = facts.bindings_of(iterable)
    for binding in bindings:
        parent = facts.parent(binding) if isinstance(binding, ast.Name) else None
        value = parent.value if isinstance(parent, ast.Assign) and binding in parent.targets else None
        if not (
            isinstance(value, (ast.ListComp, ast.GeneratorExp, ast.SetComp))
            and len(value.generators) == 1
            and isinstance(value.elt, ast.Name)
            and isinstance(value.generators[0].target, ast.Name)
            and value.elt.id == value.generators[0].target.id
            and _iterates_specs(facts, value.generators[0].iter)
        ):
            return False
    return bool(bindings)


def _name_is_env_spec(facts: ModuleFacts, name: ast.Name, depth: int) -> bool:
    """Every binding of ``name`` is ``name = <an EnvSpec>`` or ``for name in <the specs>``."""
    bindings = facts.bindings_of(name)
    if not bindings:
        return False
    for binding in bindings:
        if not isinstance(binding, ast.Name):
            return False
        parent = facts.parent(binding)
        if isinstance(parent, ast.Assign) and binding in parent.targets:
            if not is_env_spec(facts, parent.value, depth + 1):
                return False
        elif isinstance(parent, (ast.For, ast.AsyncFor, ast.comprehension)) and parent.target is binding:
            if not (_iterates_specs(facts, parent.iter) or _lists_specs(facts, parent.iter, depth)):
                return False
        else:
            return False
    return True
