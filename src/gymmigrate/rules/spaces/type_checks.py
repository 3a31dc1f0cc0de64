"""``isinstance`` and ``type()`` checks on what a space gives (GM903, GM905).

``Discrete.n``, ``.start`` and ``sample()`` are ``np.int64`` in Gymnasium 1.x, not ``int``:
``isinstance(x, int)`` and ``type(x) is int`` on them become checks that accept
``np.integer`` too. ``Dict.sample()`` and ``Dict.spaces`` are a plain ``dict``, not an
``OrderedDict``: checks for OrderedDict become checks for dict. Part of
``drift.SpaceDrift``.
"""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import walk
from gymmigrate.rules.base import RuleFamily
from gymmigrate.rules.spaces.values import UNKNOWN, SpaceValues, space_class_of


def _is_builtin(facts: ModuleFacts, expr: ast.AST, name: str) -> bool:
    return isinstance(expr, ast.Name) and expr.id == name and not facts.bindings_of(expr)


def _is_ordered_dict(facts: ModuleFacts, expr: ast.AST) -> bool:
    return "collections.OrderedDict" in facts.qualified_names(expr)


def decide_isinstance(family: RuleFamily, spaces: SpaceValues, call: ast.Call) -> None:
    """``isinstance(x, int)`` / ``isinstance(x, OrderedDict)`` on what a space gives."""
    if len(call.args) != 2 or call.keywords or any(isinstance(a, ast.Starred) for a in call.args):
        return
    value, classes = call.args
    options = classes.elts if isinstance(classes, ast.Tuple) else [classes]
    if any(_is_builtin(family.facts, c, "int") for c in options) and not any(_integer_class(family.facts, c) for c in options):
        kind = spaces.space_value(value, frozenset({"n", "start", "sample"}))
        if kind is None and _discrete_element(family.facts, value):
            numpy = family.plan.ensure_import("numpy", asname="np")
            family.report(
                call,
                "GM903",
                "a method of a `Discrete` space subclass receives the space's elements, and Gymnasium 1.x gives them "
                "as `np.int64` (`sample()`, arithmetic on `n`), not `int`: the check accepts `np.integer` too",
            )
            family.plan.replace(classes, _add_integer(numpy))
            return
        if kind is None and _discrete_action(family, value):
            numpy = family.plan.ensure_import("numpy", asname="np")
            family.report(
                call,
                "GM903",
                "this env's actions are Discrete, and `action_space.sample()` gives an `np.int64` in Gymnasium "
                "1.x, not an `int`: the check accepts `np.integer` too",
            )
            family.plan.replace(classes, _add_integer(numpy))
            return
        if kind is not None and kind in ("Discrete", UNKNOWN):
            numpy = family.plan.ensure_import("numpy", asname="np")
            family.report(call, "GM903", "a space's `n`/`sample()` is an `np.int64` in Gymnasium 1.x, not an `int`: the check accepts `np.integer` too")
            family.plan.replace(classes, _add_integer(numpy))
        return
    if len(options) == 1 and _is_ordered_dict(family.facts, classes) and spaces.space_value(value, frozenset({"sample", "spaces"})) is not None:
        family.report(call, "GM905", "`Dict.sample()` (and `Dict.spaces`) is a plain `dict` in Gymnasium 1.x, not an `OrderedDict`: checked as a dict")
        family.plan.replace(classes, lambda node: cst.Name("dict"))


def _discrete_element(facts: ModuleFacts, value: ast.AST) -> bool:
    """``idx`` in ``def get_action(self, idx)`` of a subclass of ``spaces.Discrete`` (a
    parameter the method never rebinds): an element of the space, ``np.int64`` when
    it comes from ``sample()`` or from arithmetic on ``n``."""
    if not isinstance(value, ast.Name):
        return False
    function = facts.enclosing_function(value)
    classdef = facts.enclosing_class(value)
    if function is None or classdef is None or facts.parent(function) is not classdef:
        return False
    if function.name in ("__init__", "__new__"):
        return False  # its arguments build the space: a size, not an element
    if not any(space_class_of(facts.qualified_names(base)) == "Discrete" for base in classdef.bases):
        return False
    params = function.args.args[1:]  # after self
    bindings = facts.bindings_of(value)
    return len(bindings) == 1 and any(bindings[0] is p for p in params)


def _discrete_action(family: RuleFamily, value: ast.AST) -> bool:
    """``action`` in ``def step(self, action)`` of a Gym env class whose action space is
    only ever a ``Discrete``: every action is an integer, and a sampled one is ``np.int64``."""
    if not isinstance(value, ast.Name):
        return False
    function = family.facts.enclosing_function(value)
    classdef = family.facts.enclosing_class(value)
    if function is None or classdef is None or function.name != "step" or family.facts.parent(function) is not classdef:
        return False
    params = function.args.args
    if len(params) < 2 or params[1].arg != value.id or family.receivers.class_kind(classdef) is not EnvKind.GYM_ENV:
        return False
    if any(isinstance(b, ast.Name) and b.id == value.id for b in family.facts.bindings_of(value) if b is not params[1]):
        return False
    spaces = [
        node.value
        for node in walk(classdef)
        if isinstance(node, ast.Assign)
        and any(isinstance(t, ast.Attribute) and t.attr == "action_space" for t in node.targets)
    ]
    return bool(spaces) and all(
        isinstance(space, ast.Call)
        and any(q.endswith("spaces.Discrete") or q.endswith("spaces.discrete.Discrete") for q in family.facts.qualified_names(space.func))
        for space in spaces
    )


def _integer_class(facts: ModuleFacts, expr: ast.AST) -> bool:
    return bool({"numpy.integer", "numbers.Integral", "numpy.int64"} & facts.qualified_names(expr))


def type_check(family: RuleFamily, spaces: SpaceValues, node: ast.Compare, op: ast.cmpop, typed: ast.expr, cls: ast.expr) -> bool:
    """``type(x) is int`` / ``type(x) == OrderedDict`` (either side)."""
    if not (isinstance(typed, ast.Call) and _is_builtin(family.facts, typed.func, "type") and len(typed.args) == 1 and not typed.keywords):
        return False
    value = typed.args[0]
    if isinstance(value, ast.Starred):
        return False
    negated = isinstance(op, (ast.IsNot, ast.NotEq))
    if _is_builtin(family.facts, cls, "int"):
        kind = spaces.space_value(value, frozenset({"n", "start", "sample"}))
        if kind not in ("Discrete", UNKNOWN):
            return False
        numpy = family.plan.ensure_import("numpy", asname="np")
        family.report(node, "GM903", "a space's `n`/`sample()` is an `np.int64` in Gymnasium 1.x, so `type(...) is int` is False: an isinstance check that accepts `np.integer` too")
        family.plan.replace(node, _isinstance_of(f"(int, {numpy}.integer)", negated))
        return True
    if _is_ordered_dict(family.facts, cls) and spaces.space_value(value, frozenset({"sample", "spaces"})) is not None:
        family.report(node, "GM905", "`Dict.sample()` (and `Dict.spaces`) is a plain `dict` in Gymnasium 1.x: `type(...) is OrderedDict` is False; checked as a dict")
        family.plan.replace(node, _isinstance_of("dict", negated))
        return True
    return False


# -- building the new code ------------------------------------------------------------------


def _add_integer(numpy: str):
    """``int`` -> ``(int, np.integer)``; ``(int, float)`` -> ``(int, float, np.integer)``."""

    def build(node: cst.BaseExpression) -> cst.BaseExpression:
        integer = cst.parse_expression(f"{numpy}.integer")
        if isinstance(node, cst.Tuple):
            elements = list(node.elements)
            last = elements[-1]
            elements[-1] = last.with_changes(comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" ")))
            return node.with_changes(elements=[*elements, cst.Element(integer)])
        return cst.parse_expression(f"(int, {numpy}.integer)")

    return build


def _isinstance_of(classes: str, negated: bool):
    def build(node: cst.Comparison) -> cst.BaseExpression:
        typed = node.left if _is_type_call(node.left) else node.comparisons[0].comparator
        value = typed.args[0].value  # type: ignore[attr-defined]
        check = cst.Call(
            func=cst.Name("isinstance"),
            args=[cst.Arg(value, comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))), cst.Arg(cst.parse_expression(classes))],
        )
        if negated:
            return cst.UnaryOperation(operator=cst.Not(), expression=check, lpar=node.lpar, rpar=node.rpar)
        return check.with_changes(lpar=node.lpar, rpar=node.rpar)

    return build


def _is_type_call(node: cst.BaseExpression) -> bool:
    return isinstance(node, cst.Call) and isinstance(node.func, cst.Name) and node.func.value == "type"
