"""JSON of a space's values (GM903): ``json.dumps`` cannot write an ``np.int64``.

``Discrete.n`` and ``Discrete.sample()`` are ``np.int64`` in Gymnasium 1.x (``int`` in gym
0.21), so ``json.dumps`` raises TypeError on them: a value traced to a ``Discrete`` gets
``int(...)``; one of a space whose class is not known here (a MultiBinary's ``n`` may be a
list, a Box's sample an array) is reported. Part of ``drift.SpaceDrift``.
"""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import RuleFamily
from gymmigrate.rules.spaces.values import UNKNOWN, SpaceValues

JSON_WRITERS = frozenset({"json.dumps", "json.dump"})


def decide_json(family: RuleFamily, spaces: SpaceValues, call: ast.Call) -> None:
    """``json.dumps(...)`` of a value traced to a space's ``n``/``sample()``."""
    if not call.args or isinstance(call.args[0], ast.Starred):
        return
    if any(k.arg in ("default", "cls") for k in call.keywords):
        return  # the code already serializes what json cannot
    certain, unsure = [], []
    for value in _json_values(call.args[0]):
        kind = spaces.space_value(value, frozenset({"n", "start", "sample"}))
        if kind == "Discrete":
            certain.append(value)
        elif kind == UNKNOWN:
            unsure.append(value)  # a MultiBinary's n may be a list, a Box's sample an array: int() would break them
    for value in certain:
        family.report(value, "GM903", "`Discrete.n`/`sample()` is an `np.int64` in Gymnasium 1.x, which json cannot write: converted with int()")
        family.plan.replace(value, _int_of)
    if unsure:
        text = family.facts.segment(unsure[0])
        family.report(
            call,
            "GM903",
            f"`{text}` is a NumPy value in Gymnasium 1.x (`np.int64` for a Discrete space), which json cannot write "
            "(TypeError): convert it (`int(...)`, `.tolist()`) for the space it is",
            FixKind.FLAG,
        )


def _json_values(expr: ast.expr) -> list[ast.expr]:
    """The values json writes: ``expr`` itself, or the items of dict/list/tuple literals."""
    if isinstance(expr, ast.Dict):
        return [v for value in expr.values for v in _json_values(value)]
    if isinstance(expr, (ast.List, ast.Tuple)):
        return [v for e in expr.elts if not isinstance(e, ast.Starred) for v in _json_values(e)]
    return [expr]


def _int_of(node: cst.CSTNode) -> cst.CSTNode:
    assert isinstance(node, cst.BaseExpression)
    return cst.Call(func=cst.Name("int"), args=[cst.Arg(node.with_changes(lpar=[], rpar=[]))])
