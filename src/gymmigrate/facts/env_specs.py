"""Which names hold the registry's ``EnvSpec``s: ``spec.make(**kwargs)`` on one makes an env.

``EnvSpec.make(**kwargs)`` is ``make(spec, **kwargs)`` in gym 0.21-0.26 and in Gymnasium
1.x alike, so it is a creation site like ``gym.make`` (it takes ``render_mode``). A name is
an EnvSpec only where that is certain:

* the target of a ``for`` loop or comprehension over the registry
  (``for spec in gym.envs.registry.values()``, ``registry.all()``) or over a list of its
  specs;
* a test's parameter that ``@pytest.mark.parametrize("spec", SPECS)`` draws from such a
  list, ``SPECS`` bound once at the top of this module or imported from a module of the
  run that binds it so (``ModuleSummary.spec_lists``);
* ``spec = gym.spec("CartPole-v1")``.

Every binding of the name must be one of those.
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.facts import names as N
from gymmigrate.facts.module import ModuleFacts, string_value, walk

if TYPE_CHECKING:
    from gymmigrate.facts.project_view import ProjectView

# The registry as gym/gymnasium spell it (after the ``gym.``/``gymnasium.`` prefix).
_REGISTRY = frozenset({"envs.registry", "registry", "envs.registration.registry"})
_SPEC = frozenset({"spec", "envs.spec", "envs.registration.spec"})
_COMPREHENSIONS = (ast.ListComp, ast.GeneratorExp)


def is_spec_list_value(facts: ModuleFacts, expr: ast.AST) -> bool:
    """``gym.envs.registry.values()`` (or ``.all()``), ``list(...)`` of it, or a comprehension
    over it that keeps the specs themselves (``[s for s in ... if ...]``)."""
    if isinstance(expr, ast.Call) and not expr.keywords and isinstance(expr.func, ast.Attribute):
        if expr.func.attr in ("values", "all") and not expr.args:
            return any(N.strip_gym_prefix(q) in _REGISTRY for q in facts.qualified_names(expr.func.value))
    if isinstance(expr, ast.Call) and isinstance(expr.func, ast.Name) and expr.func.id in ("list", "tuple", "sorted"):
        if len(expr.args) == 1 and not expr.keywords and not facts.bindings_of(expr.func):
            return is_spec_list_value(facts, expr.args[0])
    if isinstance(expr, _COMPREHENSIONS) and len(expr.generators) == 1:
        generator = expr.generators[0]
        return (
            isinstance(generator.target, ast.Name)
            and isinstance(expr.elt, ast.Name)
            and expr.elt.id == generator.target.id
            and is_spec_list_value(facts, generator.iter)
        )
    return False


def module_spec_lists(facts: ModuleFacts) -> frozenset[str]:
    """Top-level names bound once, to a list of the registry's specs."""
    found = set()
    for statement in facts.tree.body:
        if not (isinstance(statement, ast.Assign) and len(statement.targets) == 1 and isinstance(statement.targets[0], ast.Name)):
            continue
        name = statement.targets[0].id
        if len(facts.module_scope.bindings.get(name, ())) == 1 and is_spec_list_value(facts, statement.value):
            found.add(name)
    return frozenset(found)


def _holds_specs(facts: ModuleFacts, project: ProjectView | None, expr: ast.AST) -> bool:
    """An iterable of specs: the registry's values, or a name bound to a list of them."""
    if is_spec_list_value(facts, expr):
        return True
    if not isinstance(expr, ast.Name):
        return False
    bindings = facts.bindings_of(expr)
    if len(bindings) == 1 and isinstance(bindings[0], ast.Name):
        assign = facts.parent(bindings[0])
        if isinstance(assign, ast.Assign) and facts.enclosing_function(assign) is None:
            return len(assign.targets) == 1 and assign.targets[0] is bindings[0] and is_spec_list_value(facts, assign.value)
    return project is not None and any(project.is_spec_list(q) for q in facts.qualified_names(expr))


def is_env_spec(facts: ModuleFacts, project: ProjectView | None, name: ast.Name) -> bool:
    """Every binding of ``name`` makes it one of the registry's EnvSpecs (see the module)."""
    return facts.memo(("env-spec", id(name)), lambda: _is_env_spec(facts, project, name), while_computing=False)


def _is_env_spec(facts: ModuleFacts, project: ProjectView | None, name: ast.Name) -> bool:
    bindings = facts.bindings_of(name)
    return bool(bindings) and all(_binds_spec(facts, project, binding) for binding in bindings)


def _binds_spec(facts: ModuleFacts, project: ProjectView | None, binding: ast.AST) -> bool:
    parent = facts.parent(binding)
    if isinstance(parent, (ast.For, ast.AsyncFor, ast.comprehension)) and parent.target is binding:
        return _holds_specs(facts, project, parent.iter)
    if isinstance(parent, ast.Assign) and len(parent.targets) == 1 and parent.targets[0] is binding:
        value = parent.value
        return isinstance(value, ast.Call) and any(N.strip_gym_prefix(q) in _SPEC for q in facts.qualified_names(value.func))
    if isinstance(binding, ast.arg):
        function = facts.enclosing_function(binding)
        return function is not None and _parametrized_over_specs(facts, project, function, binding.arg)
    return False


def _parametrized_over_specs(facts: ModuleFacts, project: ProjectView | None, function: ast.AST, param: str) -> bool:
    """``@pytest.mark.parametrize("spec", SPECS, ...)`` with SPECS a list of specs."""
    for decorator in getattr(function, "decorator_list", ()):
        if not (isinstance(decorator, ast.Call) and len(decorator.args) >= 2):
            continue
        if not any(q.endswith("parametrize") for q in facts.qualified_names(decorator.func)):
            continue
        names = string_value(decorator.args[0])
        if names is not None and [n.strip() for n in names.split(",")] == [param]:
            return _holds_specs(facts, project, decorator.args[1])
    return False


def is_spec_make(facts: ModuleFacts, project: ProjectView | None, call: ast.Call) -> bool:
    """``spec.make(...)`` on one of the registry's EnvSpecs."""
    func = call.func
    return (
        isinstance(func, ast.Attribute)
        and func.attr == "make"
        and isinstance(func.value, ast.Name)
        and is_env_spec(facts, project, func.value)
    )


def recreates_from_spec(facts: ModuleFacts) -> bool:
    """``ModuleSummary.recreates_from_spec``: a ``make(x.spec)`` or ``x.spec.make()`` call."""
    if ".spec" not in facts.text:
        return False
    for node in walk(facts.tree):
        if not isinstance(node, ast.Call):
            continue
        func = node.func
        name = func.attr if isinstance(func, ast.Attribute) else func.id if isinstance(func, ast.Name) else None
        if name != "make":
            continue
        if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Attribute) and func.value.attr == "spec":
            return True  # ``env.spec.make()``
        if node.args and isinstance(node.args[0], ast.Attribute) and node.args[0].attr == "spec":
            return True  # ``gym.make(env.spec)``
    return False
