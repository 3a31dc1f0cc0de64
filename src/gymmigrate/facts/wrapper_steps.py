"""Env classes whose ``reset`` steps the wrapper around them (GM808).

A task library may let its wrappers register themselves with the env they wrap
(``env.unwrapped.set_top(self)``, stored as ``self._top = wrapper``) so that the env's own
``reset`` takes its first observation from ``self._top.step(...)``: the outermost wrapper's
step, which the wrappers modify. With ``gymnasium.make`` the ``PassiveEnvChecker`` sits
between those wrappers and the env, and sees that step while its own ``reset`` has not
returned: Gymnasium 1.x's data-reuse check then unpacks the reset it has not seen yet
(``TypeError: cannot unpack non-iterable NoneType object``); gym 0.24's checker had no such
check, older gyms no checker.

Per module: each top-level class's attributes that its ``reset`` (or a method of the class
that ``reset`` calls as ``self.m(...)``, at any depth) steps as ``self.<attribute>.step(...)``,
with the methods of the class that store that attribute from one of their parameters; and
what the module's wrapper classes hand ``self`` to (``x.m(self)``, ``x.a = self``). The join
(``project_contracts.wrapper_steppers``) matches the two across the run.
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.facts import names as N
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts, walk

if TYPE_CHECKING:
    from gymmigrate.facts.receivers import Receivers

# ``ModuleSummary.self_handoffs``: ``x.a = self`` is spelled ``=a``, ``x.m(self)`` is ``m``.
STORED = "="


def _self_name(function: ast.FunctionDef | ast.AsyncFunctionDef) -> str | None:
    if any(isinstance(d, ast.Name) and d.id in ("staticmethod", "classmethod") for d in function.decorator_list):
        return None
    positional = (*function.args.posonlyargs, *function.args.args)
    return positional[0].arg if positional else None


def _is_name(node: ast.AST, name: str) -> bool:
    return isinstance(node, ast.Name) and node.id == name


def reset_steps(classdef: ast.ClassDef) -> tuple[tuple[str, str], ...]:
    """(attribute, setter) for each ``self.<attribute>.step(...)`` that the class's ``reset``
    reaches through its own methods; ``setter`` names a method of the class that stores the
    attribute from one of its parameters (``def set_top(self, wrapper): self._top = wrapper``),
    "" once per attribute for a store from outside (``env.unwrapped._top = self``)."""
    methods = {s.name: s for s in classdef.body if isinstance(s, FUNCTIONS)}
    if "reset" not in methods:
        return ()
    stepped: set[str] = set()
    seen: set[str] = set()
    todo = ["reset"]
    while todo:
        name = todo.pop()
        if name in seen or name not in methods:
            continue
        seen.add(name)
        this = _self_name(methods[name])
        if this is None:
            continue
        for node in walk(methods[name]):
            if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)):
                continue
            owner = node.func.value
            if _is_name(owner, this):
                todo.append(node.func.attr)
            elif node.func.attr == "step" and isinstance(owner, ast.Attribute) and _is_name(owner.value, this):
                stepped.add(owner.attr)
    found: set[tuple[str, str]] = {(attribute, "") for attribute in stepped}
    for name, method in methods.items():
        this = _self_name(method)
        if this is None:
            continue
        params = {a.arg for a in (*method.args.posonlyargs, *method.args.args, *method.args.kwonlyargs)} - {this}
        for node in walk(method):
            if not isinstance(node, ast.Assign) or not (isinstance(node.value, ast.Name) and node.value.id in params):
                continue
            for target in node.targets:
                if isinstance(target, ast.Attribute) and _is_name(target.value, this) and target.attr in stepped:
                    found.add((target.attr, name))
    return tuple(sorted(found))


def module_reset_steps(facts: ModuleFacts) -> dict[str, tuple[tuple[str, str], ...]]:
    """``ModuleSummary.reset_steps``: ``reset_steps`` of each top-level class that has any."""
    found = {}
    for name, classdef in facts.classes.items():
        steps = reset_steps(classdef)
        if steps:
            found[name] = steps
    return found


def _may_be_wrapper(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> bool:
    """A Gym wrapper class, or a subclass of a class of another module of the run (which
    may be one: ``class Block(TrialWrapper)``). A plain class handing itself on (``child.parent
    = self``) is no wrapper: the env's step through it meets no checker."""
    if receivers.is_gym_wrapper_class(classdef):
        return True
    for base in classdef.bases:
        if receivers.local_class(base) is None and (qualified := facts.qualified_names(base)) and not any(N.is_library(q) for q in qualified):
            return True
    return False


def self_handoffs(facts: ModuleFacts, receivers: Receivers) -> frozenset[str]:
    """What the methods of the module's wrapper classes hand their own instance to: ``m``
    for ``x.m(..., self, ...)``, ``=a`` for ``x.a = self`` (``x`` anything but ``self``)."""
    found: set[str] = set()
    for classdef in facts.all_classes:
        if not _may_be_wrapper(facts, receivers, classdef):
            continue
        for method in classdef.body:
            if not isinstance(method, FUNCTIONS) or (this := _self_name(method)) is None:
                continue
            for node in walk(method):
                if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and not _is_name(node.func.value, this):
                    if any(_is_name(arg, this) for arg in node.args) or any(_is_name(k.value, this) for k in node.keywords):
                        found.add(node.func.attr)
                elif isinstance(node, ast.Assign) and _is_name(node.value, this):
                    for target in node.targets:
                        if isinstance(target, ast.Attribute) and not _is_name(target.value, this):
                            found.add(STORED + target.attr)
    return frozenset(found)


def steps_its_wrapper(steps: tuple[tuple[str, str], ...], handoffs: frozenset[str] | set[str]) -> bool:
    """The attribute a reset steps is one the run's objects set to themselves."""
    return any((setter and setter in handoffs) or STORED + attribute in handoffs for attribute, setter in steps)
