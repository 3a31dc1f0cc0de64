"""LibCST syntax helpers for build callbacks: the nodes rules construct or inspect while
an edit is applied (decisions use ``gymmigrate.facts`` instead)."""

from __future__ import annotations

import libcst as cst


class _OwnReturns(cst.CSTVisitor):
    def __init__(self) -> None:
        self.returns: list[cst.Return] = []

    # A nested def, lambda or class returns to its own caller, not ours.
    def visit_FunctionDef(self, node: cst.FunctionDef) -> bool:
        return False

    def visit_Lambda(self, node: cst.Lambda) -> bool:
        return False

    def visit_ClassDef(self, node: cst.ClassDef) -> bool:
        return False

    def visit_Return(self, node: cst.Return) -> None:
        self.returns.append(node)


def own_returns(function: cst.FunctionDef | cst.BaseSuite) -> list[cst.Return]:
    """The ``return`` statements of one function (or body), in order, not of nested ones."""
    collector = _OwnReturns()
    body = function.body if isinstance(function, cst.FunctionDef) else function
    body.visit(collector)
    return collector.returns


def dotted_node(path: str) -> cst.Name | cst.Attribute:
    """``a.b.c`` as a Name/Attribute chain."""
    parts = path.split(".")
    node: cst.Name | cst.Attribute = cst.Name(parts[0])
    for part in parts[1:]:
        node = cst.Attribute(value=node, attr=cst.Name(part))
    return node
