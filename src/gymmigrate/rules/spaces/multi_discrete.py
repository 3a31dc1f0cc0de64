"""GM912: gym's ``MultiDiscrete`` bounds ``.low`` / ``.high`` (gym <= 0.9).

gym 0.9's ``MultiDiscrete([[0, 4], [0, 1]])`` kept the bounds of each dimension as ``low``
and ``high`` (inclusive). Gymnasium 1.4's has ``nvec`` (the number of values per
dimension) and ``start`` (the first value), and no ``low`` / ``high``: reading them raises
AttributeError. Under ``isinstance(space, MultiDiscrete)`` (the space is made elsewhere,
already Gymnasium's), ``space.low`` becomes ``space.start`` and ``space.high``
``(space.start + space.nvec - 1)``, the same arrays. A ``MultiDiscrete`` built in the module
is reported: gym 0.9 built it from ``[[low, high], ...]``, which Gymnasium reads as a
two-dimensional ``nvec``, so the reads follow a construction the author ports first.

The construction ``MultiDiscrete([[low, high], ...])`` itself raises in Gymnasium (``nvec``
holds counts, which must be positive; a pair is a row of a two-dimensional ``nvec``, and a
low of 0 is no count). Where every low is 0, each ``[0, n]`` becomes ``n + 1``: the same
values, sampled alike. Other lows are reported: the counts alone would shift every value
sampled or checked by ``low``; ``start=`` keeps them, but the code reading the actions is
the author's to check.

Sources: Gymnasium 1.4.0 ``spaces/multi_discrete.py``; gym 0.9 ``spaces/multi_discrete.py``.
"""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import RuleFamily
from gymmigrate.rules.spaces.values import SpaceValues


def decide_bounds_read(family: RuleFamily, spaces: SpaceValues, attribute: ast.Attribute) -> None:
    """``space.low`` / ``space.high`` read on a ``MultiDiscrete``."""
    if attribute.attr not in ("low", "high") or not isinstance(attribute.ctx, ast.Load):
        return
    if spaces.space_class(attribute.value) != "MultiDiscrete":
        return
    if spaces.narrowed(attribute.value) != "MultiDiscrete" or not _plain(attribute.value):
        # A space built here: gym 0.9 built it from ``[[low, high], ...]``, which Gymnasium
        # reads as a two-dimensional ``nvec``; the construction is the author's to port first.
        family.report(
            attribute,
            "GM912",
            "Gymnasium's `MultiDiscrete` has no `low` / `high` (AttributeError): its bounds are `start` and "
            "`start + nvec - 1` (a space built from gym 0.9's `[[low, high], ...]` is a two-dimensional `nvec` in Gymnasium)",
            kind=FixKind.FLAG,
        )
        return
    new = "start" if attribute.attr == "low" else "start + nvec - 1"
    family.report(
        attribute,
        "GM912",
        f"gym's `MultiDiscrete.{attribute.attr}` does not exist in Gymnasium (AttributeError): written as `{new}` on the space",
    )
    family.plan.replace(attribute, _low if attribute.attr == "low" else _high)


def _plain(node: ast.expr) -> bool:
    """A name: read twice, it is the same object."""
    return isinstance(node, ast.Name)


def _low(node: cst.Attribute) -> cst.BaseExpression:
    return node.with_changes(attr=cst.Name("start"))


def _high(node: cst.Attribute) -> cst.BaseExpression:
    start = node.with_changes(attr=cst.Name("start"), lpar=[], rpar=[])
    nvec = node.with_changes(attr=cst.Name("nvec"), lpar=[], rpar=[])
    total = cst.BinaryOperation(start, cst.Add(), nvec)
    return cst.BinaryOperation(total, cst.Subtract(), cst.Integer("1"), lpar=[cst.LeftParen()], rpar=[cst.RightParen()])


def decide_pairs_construction(family: RuleFamily, call: ast.Call) -> None:
    """``MultiDiscrete([[0, 1], [0, 4]])`` / ``MultiDiscrete([[0, 1]] * 4 + [[-10, 10]])``:
    gym 0.9's inclusive bounds per dimension, spelled with int literals."""
    if not call.args or isinstance(call.args[0], ast.Starred):
        return
    pairs = _bound_pairs(call.args[0], 0)
    if not pairs or all(low > 0 for _, low, _ in pairs):
        # Pairs of positive numbers are also a two-dimensional ``nvec`` (gym 0.10 on, and
        # Gymnasium): only a low that is no count (0 or less) proves gym 0.9's bounds.
        return
    if all(low == 0 for _, low, _ in pairs):
        family.report(
            call,
            "GM912",
            "gym 0.9's `MultiDiscrete([[0, n], ...])` (inclusive bounds) raises ValueError in Gymnasium, whose "
            "`MultiDiscrete` takes the number of values per dimension: written as `[n + 1, ...]`, the same values",
        )
        for node, _, high in pairs:
            family.plan.replace(node, _count(high + 1))
        return
    family.report(
        call,
        "GM912",
        "gym 0.9's `MultiDiscrete([[low, high], ...])` (inclusive bounds) raises ValueError in Gymnasium, whose "
        "`MultiDiscrete` takes the number of values per dimension, from 0: `MultiDiscrete([high - low + 1, ...], "
        "start=[low, ...])` keeps the values of the pairs whose low is not 0; check the code that reads the actions "
        "(and gym's `low` / `high`) as you write it",
        kind=FixKind.FLAG,
    )


# Deeper than ``[[0, 1]] * 4 + [[0, 2]] * 2 + ...`` in real code; bounds the recursion.
_MAX_PAIR_DEPTH = 16


def _bound_pairs(node: ast.expr, depth: int) -> list[tuple[ast.expr, int, int]] | None:
    """The ``[low, high]`` pairs a list of them spells (a literal, ``* k`` of one, ``+`` of
    such), each with its node; None for any other value (a list of counts among them)."""
    if depth > _MAX_PAIR_DEPTH:
        return None
    if isinstance(node, ast.List):
        pairs = [_bound_pair(element) for element in node.elts]
        found = [pair for pair in pairs if pair is not None]
        return found if node.elts and len(found) == len(pairs) else None
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Mult):
        if _int_literal(node.right) is not None:
            return _bound_pairs(node.left, depth + 1)
        if _int_literal(node.left) is not None:
            return _bound_pairs(node.right, depth + 1)
        return None
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add):
        left, right = _bound_pairs(node.left, depth + 1), _bound_pairs(node.right, depth + 1)
        return left + right if left is not None and right is not None else None
    return None


def _bound_pair(node: ast.expr) -> tuple[ast.expr, int, int] | None:
    if not (isinstance(node, (ast.List, ast.Tuple)) and len(node.elts) == 2):
        return None
    low, high = (_int_literal(element) for element in node.elts)
    return (node, low, high) if low is not None and high is not None and high >= low else None


def _int_literal(node: ast.expr) -> int | None:
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
        value = _int_literal(node.operand)
        return -value if value is not None else None
    if isinstance(node, ast.Constant) and type(node.value) is int:
        return node.value
    return None


def _count(value: int):
    def build(node: cst.BaseExpression) -> cst.BaseExpression:
        return cst.Integer(str(value), lpar=[], rpar=[])

    return build
