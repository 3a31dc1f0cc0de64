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


def keyword_argument(call: cst.Call, name: str) -> cst.Arg | None:
    """The ``name=...`` argument of a call, if passed."""
    return next((arg for arg in call.args if arg.keyword is not None and arg.keyword.value == name), None)


def string_value(node: cst.BaseExpression | None) -> str | None:
    """The text of a plain string literal (not bytes, f-strings or concatenations)."""
    if isinstance(node, cst.SimpleString):
        value = node.evaluated_value
        return value if isinstance(value, str) else None
    return None


def dotted_node(path: str) -> cst.Name | cst.Attribute:
    """``a.b.c`` as a Name/Attribute chain."""
    parts = path.split(".")
    node: cst.Name | cst.Attribute = cst.Name(parts[0])
    for part in parts[1:]:
        node = cst.Attribute(value=node, attr=cst.Name(part))
    return node
