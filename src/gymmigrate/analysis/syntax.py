"""Small syntax queries several rule families ask of LibCST trees."""

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


def own_return_values(function: cst.FunctionDef) -> list[cst.BaseExpression]:
    """The values a function returns (bare ``return`` left out)."""
    return [statement.value for statement in own_returns(function) if statement.value is not None]
