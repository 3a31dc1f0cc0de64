"""Which expressions hold what ``gym.make`` returned with no wrapper of any kind around it,
on every path: the forwarding rules (``forwarding.py``) leave a make result's own TimeLimit
attribute alone (GM605), rewrite ``env.env.state`` below make's layers (GM604) and keep
``isinstance(env, TimeLimit)`` (GM606) there.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.made_holders import made_attributes
from gymmigrate.facts.module import FUNCTIONS, call_argument
from gymmigrate.facts.receivers import Receivers
from gymmigrate.facts.self_attributes import self_stores
from gymmigrate.rules.wrapper_usage.atari_limits import is_make_call


def bare_make_result(facts: ModuleFacts, expr: ast.AST) -> bool:
    """A ``make`` call, or a name every binding of which assigns one directly."""
    if is_make_call(facts, expr):
        return True
    if not isinstance(expr, ast.Name):
        return False
    values = []
    for binding in facts.bindings_of(expr):
        statement = facts.parent(binding)
        if not (isinstance(statement, ast.Assign) and binding in statement.targets):
            return False
        values.append(statement.value)
    return bool(values) and all(is_make_call(facts, value) for value in values)


def bare_make(facts: ModuleFacts, receivers: Receivers, expr: ast.expr, seen: frozenset[int]) -> bool:
    """``expr`` is, on every path, what ``gym.make(...)`` returned with no wrapper of any
    kind around it: the call itself, a name or ``self.x`` every binding of which is one
    (``x = y`` followed), a parameter of a module function every call here passes one."""
    if is_make_call(facts, expr):
        return True
    if id(expr) in seen:
        return False
    seen |= {id(expr)}
    if isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and expr.value.id == "self":
        classdef = facts.enclosing_class(expr)
        if classdef is None or receivers.is_gym_wrapper_class(classdef):
            return False  # a wrapper's ``self.env`` is whatever it wraps
        values = self_stores(facts, classdef, expr.attr)
        if not values:
            return False
        return all(bare_make(facts, receivers, value, seen) for value in values)
    if isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name):
        return held_bare_make(facts, receivers, expr.value, expr.attr)
    if not isinstance(expr, ast.Name):
        return False
    bindings = facts.bindings_of(expr)
    if not bindings:
        return False
    for binding in bindings:
        if id(binding) in seen:
            return False
        if isinstance(binding, ast.arg):
            if not param_bare_make(facts, receivers, binding, seen | {id(binding)}):
                return False
            continue
        statement = facts.parent(binding)
        if not (isinstance(statement, ast.Assign) and statement.targets == [binding]):
            return False
        if not bare_make(facts, receivers, statement.value, seen | {id(binding)}):
            return False
    return True


def param_bare_make(facts: ModuleFacts, receivers: Receivers, param: ast.arg, seen: frozenset[int]) -> bool:
    arguments = facts.parent(param)
    function = facts.parent(arguments) if arguments is not None else None
    if not isinstance(function, FUNCTIONS) or facts.enclosing_class(function) is not None:
        return False
    params = [*function.args.posonlyargs, *function.args.args]
    position = next((i for i, p in enumerate(params) if p is param), None)
    calls = receivers.call_sites(function, None)
    if not calls:
        return False
    for call in calls:
        argument = call_argument(call, position, param.arg)
        if argument is None or not bare_make(facts, receivers, argument, seen):
            return False
    return True


def held_bare_make(facts: ModuleFacts, receivers: Receivers, holder: ast.Name, attribute: str) -> bool:
    """``holder.<attribute>`` is a bare make result on every path: ``holder`` is, wherever it
    is bound, an instance of a class of the run that holds one there (``made_holders``):
    ``holder = GymEnv(name)``, or a parameter every call of the run passes one
    (``MBEnvWrapper(GymEnv(name))`` in another module)."""
    bindings = facts.bindings_of(holder)
    if not bindings:
        return False
    for binding in bindings:
        if isinstance(binding, ast.arg):
            if not _param_holds_made(facts, receivers, binding, attribute):
                return False
            continue
        statement = facts.parent(binding)
        if not (isinstance(statement, ast.Assign) and statement.targets == [binding] and _instance_holds_made(facts, receivers, statement.value, attribute)):
            return False
    return True


def _instance_holds_made(facts: ModuleFacts, receivers: Receivers, value: ast.expr | None, attribute: str) -> bool:
    """``value`` builds an instance of a class of this module or of the run that holds a
    bare make result in ``attribute``."""
    if not isinstance(value, ast.Call):
        return False
    local = receivers.local_class(value.func)
    if local is not None:
        return attribute in made_attributes(facts, receivers, local)
    project = receivers.project
    qualified = facts.qualified_names(value.func)
    return project is not None and len(qualified) == 1 and project.holds_made(next(iter(qualified)), attribute)


def _param_holds_made(facts: ModuleFacts, receivers: Receivers, param: ast.arg, attribute: str) -> bool:
    """Every call of ``param``'s def, here and in the other modules of the run, passes an
    instance holding a bare make result in ``attribute`` (and some call does)."""
    function = facts.parent(facts.parent(param))
    if not isinstance(function, FUNCTIONS):
        return False
    classdef = facts.parent(function)
    is_method = isinstance(classdef, ast.ClassDef) and facts.is_method(function)
    params = [*function.args.posonlyargs, *function.args.args]
    position = next((i for i, p in enumerate(params) if p is param), None)
    if position is not None and is_method:
        position -= 1  # calls do not pass self
    if is_method and function.name == "__init__":
        constructions, elsewhere = receivers.constructions(classdef)  # type: ignore[arg-type]
        if elsewhere:
            return False
        calls = [(call, shift) for call, shift in constructions]
    else:
        calls = [(call, 0) for call in receivers.call_sites(function, classdef if is_method else None)]  # type: ignore[arg-type]
    for call, shift in calls:
        argument = call_argument(call, None if position is None else position + shift, param.arg)
        if not _instance_holds_made(facts, receivers, argument, attribute):
            return False
    project = receivers.project
    held = None
    if project is not None and (facts.parent(function) is facts.tree or (is_method and facts.parent(classdef) is facts.tree)):
        held = project.held_made(f"{classdef.name}.{function.name}" if is_method else function.name, param.arg)  # type: ignore[union-attr]
    if held is not None and attribute not in held:
        return False
    return bool(calls) or held is not None
