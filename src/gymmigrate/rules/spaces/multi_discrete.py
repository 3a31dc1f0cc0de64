"""GM912: gym's ``MultiDiscrete`` bounds ``.low`` / ``.high`` (gym <= 0.9).

gym 0.9's ``MultiDiscrete([[0, 4], [0, 1]])`` kept the bounds of each dimension as ``low``
and ``high`` (inclusive). Gymnasium 1.4's has ``nvec`` (the number of values per
dimension) and ``start`` (the first value), and no ``low`` / ``high``: reading them raises
AttributeError. Under ``isinstance(space, MultiDiscrete)`` (the space is made elsewhere,
already Gymnasium's), ``space.low`` becomes ``space.start`` and ``space.high``
``(space.start + space.nvec - 1)``, the same arrays. A ``MultiDiscrete`` built in the module
is reported: gym 0.9 built it from ``[[low, high], ...]``, which Gymnasium reads as a
two-dimensional ``nvec``, so the reads follow a construction the author ports first.

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
