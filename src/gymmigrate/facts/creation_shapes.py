"""Shapes of one call, def or class that ``CreationFinder`` (creation.py) reads: the argument
a call passes for a parameter (or its first, in source order, or the env it wraps), the
slot a property hands out, the values and nested defs a function returns, the iterable of
``enumerate``, and a held attribute changed in place (and the items it is given so).
"""

from __future__ import annotations

import ast

from gymmigrate.facts.module import (
    FUNCTIONS,
    ModuleFacts,
    own_returns,
    self_attribute,
    walk,
)


def property_slot(classdef: ast.ClassDef, name: str) -> str | None:
    """``x`` for ``@property def <name>(self): return self.x`` in ``classdef``'s body (an
    adapter handing out the env it holds), else None."""
    for statement in classdef.body:
        if not (isinstance(statement, ast.FunctionDef) and statement.name == name):
            continue
        decorated = [d for d in statement.decorator_list if isinstance(d, ast.Name) and d.id == "property"]
        params = statement.args.args
        if len(decorated) != 1 or len(statement.decorator_list) != 1 or len(params) != 1 or len(statement.body) != 1:
            return None
        returned = statement.body[0].value if isinstance(statement.body[0], ast.Return) else None
        if isinstance(returned, ast.Attribute) and isinstance(returned.value, ast.Name) and returned.value.id == params[0].arg:
            return returned.attr
        return None
    return None


def argument_for(call: ast.Call, name: str, position: int | None) -> ast.expr | None:
    """What ``call`` passes for the parameter ``name`` at ``position``: its keyword, else its
    positional argument (None after a ``*args``, which may have shifted it)."""
    argument = next((k.value for k in call.keywords if k.arg == name), None)
    if argument is None and position is not None and position < len(call.args) and not any(isinstance(a, ast.Starred) for a in call.args):
        argument = call.args[position]
    return argument


def first_argument(call: ast.Call) -> ast.expr | None:
    """The first argument in source order (LibCST's ``call.args[0]``), keyword or not."""
    candidates: list[ast.expr] = [a.value if isinstance(a, ast.Starred) else a for a in call.args]
    if call.keywords:
        first_keyword = min(call.keywords, key=lambda k: (k.lineno, k.col_offset))
        if not candidates or (first_keyword.lineno, first_keyword.col_offset) < (call.args[0].lineno, call.args[0].col_offset):
            return first_keyword.value
    return candidates[0] if candidates else None


def last_name(func: ast.AST) -> str:
    """``Wrapper`` for ``gym.wrappers.Wrapper`` (and for ``Wrapper``); "" for other callees."""
    if isinstance(func, ast.Attribute):
        return func.attr
    return func.id if isinstance(func, ast.Name) else ""


def wrapped_env_argument(call: ast.Call) -> ast.expr | None:
    for kw in call.keywords:
        if kw.arg in ("env", "venv"):
            return kw.value
    if call.args and not isinstance(call.args[0], ast.Starred) and first_argument(call) is call.args[0]:
        return call.args[0]
    return None


def return_values(function: ast.AST) -> list[ast.expr]:
    """The values a function returns (bare ``return`` left out)."""
    return [r.value for r in own_returns(function) if r.value is not None]


def nested_function(function: ast.AST, value: ast.AST) -> ast.FunctionDef | ast.AsyncFunctionDef | None:
    if not isinstance(value, ast.Name):
        return None
    for statement in getattr(function, "body", ()):
        if isinstance(statement, FUNCTIONS) and statement.name == value.id:
            return statement
    return None


def enumerated_iterable(facts: ModuleFacts, binding: ast.Name) -> ast.expr | None:
    """``envs`` for ``env`` of ``for i, env in enumerate(envs)`` (the builtin's one argument)."""
    target = facts.parent(binding)
    loop = facts.parent(target) if isinstance(target, ast.Tuple) else None
    if not (isinstance(target, ast.Tuple) and len(target.elts) == 2 and target.elts[1] is binding):
        return None
    if not (isinstance(loop, (ast.For, ast.AsyncFor, ast.comprehension)) and loop.target is target):
        return None
    call = loop.iter
    if not (isinstance(call, ast.Call) and isinstance(call.func, ast.Name) and call.func.id == "enumerate"):
        return None
    if len(call.args) != 1 or call.keywords or isinstance(call.args[0], ast.Starred):
        return None
    scope, _ = facts.resolve("enumerate", facts.scope_of(call.func))
    return call.args[0] if scope is None else None


# Methods of a list that add no item to it.
NO_NEW_ITEMS = frozenset({"pop", "clear", "remove", "sort", "reverse", "index", "count", "copy"})


def items_added_in_place(classdef: ast.ClassDef, name: str) -> tuple[list[ast.expr], list[ast.expr]] | None:
    """What ``classdef`` adds in place to the list ``self.<name>``: the items (``v`` of
    ``self.<name>.append(v)``, ``.insert(i, v)``, ``self.<name>[i] = v``) and the
    containers whose items it takes (``.extend(c)``, ``self.<name> += c``). None when the
    class changes it another way (a method whose effect on the items is not known)."""
    items: list[ast.expr] = []
    containers: list[ast.expr] = []
    for node in walk(classdef):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and self_attribute(node.func.value) == name:
            method, args = node.func.attr, node.args
            if any(isinstance(a, ast.Starred) for a in args) or node.keywords:
                return None
            if method == "append" and len(args) == 1:
                items.append(args[0])
            elif method == "insert" and len(args) == 2:
                items.append(args[1])
            elif method == "extend" and len(args) == 1:
                containers.append(args[0])
            elif method not in NO_NEW_ITEMS:
                return None
        elif isinstance(node, ast.Subscript) and isinstance(node.ctx, ast.Store) and self_attribute(node.value) == name:
            assign = _parent_assign(classdef, node)
            if assign is None:
                return None
            items.append(assign.value)
        elif isinstance(node, ast.AugAssign) and self_attribute(node.target) == name:
            if not isinstance(node.op, ast.Add):
                return None
            containers.append(node.value)
    return items, containers


def holds_no_items(node: ast.AST) -> bool:
    """``[]``, ``()`` or ``None`` (a list dropped in ``close()``): no item comes from it."""
    return (isinstance(node, (ast.List, ast.Tuple, ast.Set)) and not node.elts) or (isinstance(node, ast.Constant) and node.value is None)


def _parent_assign(classdef: ast.ClassDef, target: ast.Subscript) -> ast.Assign | None:
    """The ``self.x[i] = v`` statement whose single target is ``target``."""
    for node in walk(classdef):
        if isinstance(node, ast.Assign) and node.targets == [target]:
            return node
    return None


def changed_in_place(classdef: ast.ClassDef, name: str) -> bool:
    """``self.<name>.append(...)`` (any method call on it) or ``self.<name>[i] = ...`` in the class."""
    for node in walk(classdef):
        held = None
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
            held = node.func.value
        elif isinstance(node, ast.Subscript) and not isinstance(node.ctx, ast.Load):
            held = node.value
        if self_attribute(held) == name:
            return True
    return False
