"""``Box`` bounds that cross (GM909): a ``low`` above its ``high``.

gym built such a Box without a check (its ``sample()`` drew between the two bounds, its
``contains()`` was False for every value); Gymnasium 1.x raises ``ValueError: Box all low
values must be less than or equal to high``. The bounds are judged where their values are
constants the module shows: literals, ``np.ones(2)``-style arrays, arithmetic of those, and
names bound once to one of these or to a parameter's literal default (``def __init__(self,
size=-5)``: the value every caller that leaves the parameter out builds). Part of
``drift.SpaceDrift``; whatever is not such a constant is not judged.
"""

from __future__ import annotations

import ast
import math
import operator
from collections.abc import Callable
from dataclasses import dataclass

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.module import call_argument, param_default
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import RuleFamily

# A scalar, or a 1-D array of scalars (what the bounds of a flat Box hold).
Value = float | tuple[float, ...]

_MAX_DEPTH = 6
_MAX_LENGTH = 10_000  # np.ones(n) larger than this is not built to compare
_OPERATORS: dict[type[ast.operator], Callable[[float, float], float]] = {
    ast.Add: operator.add,
    ast.Sub: operator.sub,
    ast.Mult: operator.mul,
    ast.Div: operator.truediv,
}
_FILLED = {"ones": 1.0, "zeros": 0.0}


@dataclass
class _Evaluation:
    """What the bounds' constants came from: the parameter defaults they read, for the message."""

    facts: ModuleFacts
    defaults: list[str]


def decide_crossed_bounds(family: RuleFamily, call: ast.Call) -> None:
    low_expr, high_expr = call_argument(call, 0, "low"), call_argument(call, 1, "high")
    if low_expr is None or high_expr is None:
        return
    evaluation = _Evaluation(family.facts, [])
    low, high = _value(evaluation, low_expr, 0), _value(evaluation, high_expr, 0)
    if low is None or high is None:
        return
    pairs = _broadcast(low, high)
    if pairs is None or not any(lo > hi for lo, hi in pairs):
        return
    defaults = sorted(set(evaluation.defaults))
    via = f" (with the default {', '.join(defaults)})" if defaults else ""
    family.report(
        call,
        "GM909",
        f"`Box` low {_shown(low)} is above high {_shown(high)}{via}: Gymnasium 1.x raises ValueError (gym built it "
        "unchecked: its sample() drew between the bounds, its contains() was False for every value); correct the "
        + ("default, or the bounds" if defaults else "bounds"),
        FixKind.FLAG,
    )


def _value(evaluation: _Evaluation, expr: ast.AST, depth: int) -> Value | None:
    if depth > _MAX_DEPTH:
        return None
    if isinstance(expr, ast.Constant):
        value = expr.value
        return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else None
    if isinstance(expr, ast.UnaryOp) and isinstance(expr.op, (ast.USub, ast.UAdd)):
        operand = _value(evaluation, expr.operand, depth + 1)
        if operand is None or isinstance(expr.op, ast.UAdd):
            return operand
        return tuple(-x for x in operand) if isinstance(operand, tuple) else -operand
    if isinstance(expr, ast.BinOp) and type(expr.op) in _OPERATORS:
        left, right = _value(evaluation, expr.left, depth + 1), _value(evaluation, expr.right, depth + 1)
        if left is None or right is None:
            return None
        return _apply(_OPERATORS[type(expr.op)], left, right)
    if isinstance(expr, ast.Name):
        return _name_value(evaluation, expr, depth)
    if isinstance(expr, ast.Call):
        return _numpy_value(evaluation, expr, depth)
    if isinstance(expr, ast.Attribute) and evaluation.facts.qualified_names(expr) & {"numpy.inf", "numpy.Inf"}:
        return math.inf
    return None


def _name_value(evaluation: _Evaluation, name: ast.Name, depth: int) -> Value | None:
    """A name bound once where it is read: to a constant, or as a parameter with a literal default."""
    facts = evaluation.facts
    bindings = facts.bindings_of(name)
    if len(bindings) != 1:
        return None
    binding = bindings[0]
    if isinstance(binding, ast.arg):
        default = _default_of(facts, binding)
        if default is None:
            return None
        value = _value(evaluation, default, depth + 1)
        if value is not None:
            evaluation.defaults.append(f"{binding.arg}={facts.segment(default)}")
        return value
    statement = facts.parent(binding)
    if isinstance(binding, ast.Name) and isinstance(statement, ast.Assign) and statement.targets == [binding]:
        return _value(evaluation, statement.value, depth + 1)
    return None


def _default_of(facts: ModuleFacts, param: ast.arg) -> ast.expr | None:
    function = facts.parent(facts.parent(param))
    if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
        return None
    return param_default(function, param)


def _numpy_value(evaluation: _Evaluation, call: ast.Call, depth: int) -> Value | None:
    """``np.ones(2)``, ``np.zeros((3,))``, ``np.full(2, 5.0)``, ``np.array([1.0, -1.0])``."""
    names = {q.rsplit(".", 1)[-1] for q in evaluation.facts.qualified_names(call.func) if q.startswith("numpy.") and q.count(".") == 1}
    if len(names) != 1 or any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords):
        return None
    name = names.pop()
    if name in _FILLED or name == "full":
        length = _length(evaluation, call_argument(call, 0, "shape"), depth)
        fill = _FILLED.get(name)
        if name == "full":
            fill_value = call_argument(call, 1, "fill_value")
            value = _value(evaluation, fill_value, depth + 1) if fill_value is not None else None
            fill = value if isinstance(value, float) else None
        return (fill,) * length if length is not None and fill is not None else None
    if name in ("array", "asarray") and len(call.args) == 1:
        items = call.args[0]
        if not isinstance(items, (ast.List, ast.Tuple)) or not items.elts:
            return None
        values = [_value(evaluation, item, depth + 1) for item in items.elts]
        if any(not isinstance(v, float) for v in values):
            return None
        return tuple(v for v in values if isinstance(v, float))
    return None


def _length(evaluation: _Evaluation, shape: ast.AST | None, depth: int) -> int | None:
    if isinstance(shape, ast.Tuple) and len(shape.elts) == 1:
        shape = shape.elts[0]
    value = _value(evaluation, shape, depth + 1) if shape is not None else None
    if not isinstance(value, float) or not value.is_integer() or not 0 < value <= _MAX_LENGTH:
        return None
    return int(value)


def _apply(op: Callable[[float, float], float], left: Value, right: Value) -> Value | None:
    pairs = _broadcast(left, right)
    if pairs is None:
        return None
    try:
        results = tuple(op(a, b) for a, b in pairs)
    except ZeroDivisionError:
        return None
    return results if isinstance(left, tuple) or isinstance(right, tuple) else results[0]


def _broadcast(left: Value, right: Value) -> list[tuple[float, float]] | None:
    lefts = left if isinstance(left, tuple) else None
    rights = right if isinstance(right, tuple) else None
    if lefts is not None and rights is not None:
        return list(zip(lefts, rights)) if len(lefts) == len(rights) else None
    if lefts is not None:
        return [(a, float(right)) for a in lefts]  # type: ignore[arg-type]
    if rights is not None:
        return [(float(left), b) for b in rights]  # type: ignore[arg-type]
    return [(float(left), float(right))]  # type: ignore[arg-type]


def _shown(value: Value) -> str:
    if isinstance(value, tuple):
        return "[" + ", ".join(f"{v:g}" for v in value[:6]) + (", ..." if len(value) > 6 else "") + "]"
    return f"{value:g}"
