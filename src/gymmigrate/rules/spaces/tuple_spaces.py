"""``Tuple.spaces`` is a tuple in Gymnasium (GM905): gym kept the list it was built from.

``space.spaces + [extra]`` (or ``[extra] + space.spaces``) on a space known to be a
``Tuple`` raises ``TypeError: can only concatenate tuple (not "list") to tuple`` on
Gymnasium 1.x. The ``.spaces`` operand becomes ``list(space.spaces)``: the sum is then the
very list gym gave, whatever the other operand is (gym's sum only ran with a list there).
Changing the tuple in place (``.append``, ``.extend``, ``+=``, an item or slice
assignment, ``del``) is reported: a Tuple space's members change by building another
Tuple. Part of ``drift.SpaceDrift``; what a space is comes from ``values.py``.
"""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.module import dotted_name, walk
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import RuleFamily
from gymmigrate.rules.spaces.values import LIST_MUTATORS, SpaceValues


def decide_tuple_members(family: RuleFamily, spaces: SpaceValues, attribute: ast.Attribute) -> None:
    """``<space>.spaces`` read where ``<space>`` is known to be a ``Tuple``."""
    if attribute.attr != "spaces" or spaces.space_class(attribute.value) != "Tuple":
        return
    facts = family.facts
    parent = facts.parent(attribute)
    shown = dotted_name(attribute) or facts.segment(attribute)
    if isinstance(parent, ast.BinOp) and isinstance(parent.op, ast.Add) and isinstance(attribute.ctx, ast.Load):
        other = parent.right if parent.left is attribute else parent.left
        if isinstance(other, ast.Tuple) or (isinstance(other, ast.Attribute) and other.attr == "spaces"):
            return  # a tuple beside it: gym's list raised there, Gymnasium's tuple does not
        if _binds_list(facts.tree):
            family.report(attribute, "GM905", f"`{shown}` is a tuple in Gymnasium 1.x (gym kept a list): adding a list to it raises TypeError; make it `list({shown})`", FixKind.FLAG)
            return
        family.report(attribute, "GM905", f"`{shown}` is a tuple in Gymnasium 1.x (gym kept a list): read as `list({shown})`, so the sum is the list gym gave")
        family.plan.replace(attribute, _list_of)
        return
    mutated = None
    if isinstance(parent, ast.Attribute) and parent.attr in LIST_MUTATORS and isinstance(facts.parent(parent), ast.Call):
        mutated = f"`{shown}.{parent.attr}()`"
    elif isinstance(parent, ast.AugAssign) and parent.target is attribute:
        mutated = f"`{shown} {_op(parent.op)}= ...`"
    elif isinstance(parent, ast.Subscript) and parent.value is attribute and isinstance(parent.ctx, (ast.Store, ast.Del)):
        mutated = f"an item {'assignment' if isinstance(parent.ctx, ast.Store) else 'deletion'} of `{shown}`"
    if mutated is not None:
        family.report(
            attribute,
            "GM905",
            f"`{shown}` is a tuple in Gymnasium 1.x (gym kept a list): {mutated} raises there; build another Tuple "
            "space with the members it should have",
            FixKind.FLAG,
        )


def _op(op: ast.operator) -> str:
    return "+" if isinstance(op, ast.Add) else "*" if isinstance(op, ast.Mult) else "?"


def _binds_list(tree: ast.AST) -> bool:
    """The module binds the name ``list`` itself (a function, a class, an import, a target):
    ``list(...)`` would not be the builtin."""
    for node in walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) and node.name == "list":
            return True
        if isinstance(node, ast.Name) and node.id == "list" and not isinstance(node.ctx, ast.Load):
            return True
        if isinstance(node, ast.alias) and (node.asname or node.name) == "list":
            return True
        if isinstance(node, ast.arg) and node.arg == "list":
            return True
    return False


def _list_of(node: cst.CSTNode) -> cst.CSTNode:
    assert isinstance(node, cst.BaseExpression)
    return cst.Call(func=cst.Name("list"), args=[cst.Arg(node.with_changes(lpar=[], rpar=[]))])
