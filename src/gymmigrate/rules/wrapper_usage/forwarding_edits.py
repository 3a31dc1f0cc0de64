"""How the forwarding rules (GM604-GM606, ``forwarding.py``) rewrite a read or a write: the
LibCST builders the plan applies, and the quoting of ``get_wrapper_attr("name")`` inside
f-strings."""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import ModuleFacts

if TYPE_CHECKING:
    from gymmigrate.edits.plan import Plan


def replace_with_get_wrapper_attr(facts: ModuleFacts, plan: Plan, attr: ast.Attribute, name: str, below: int = 0) -> None:
    """``x.get_wrapper_attr("name")``, quoted so that it can stand inside the f-strings
    around it (before Python 3.12 an f-string cannot hold its own quote); ``below`` ``.env``
    links between ``x`` and the name are dropped (``x.env.name``: the search starts at ``x``)."""
    used = set()
    for ancestor in facts.ancestors(attr):
        if isinstance(ancestor, ast.JoinedStr):
            text = facts.segment(ancestor).lstrip("rRbBfFuU")
            used.add(text[:1])
    quote = next((q for q in ('"', "'") if q not in used), None)
    if quote is None:
        return  # both quotes taken by nested f-strings: the finding stands alone
    plan.replace(attr, get_wrapper_attr(name, quote, below))


def unwrapped_below(depth: int):
    """``env.env.env.state`` (``depth`` ``.env``) -> ``env.unwrapped.state``."""

    def build(node: cst.Attribute) -> cst.BaseExpression:
        value: cst.BaseExpression = node.value
        for _ in range(depth):
            assert isinstance(value, cst.Attribute)
            value = value.value
        return node.with_changes(value=cst.Attribute(value=value, attr=cst.Name("unwrapped")))

    return build


def set_wrapper_attr(name: str):
    """``env.foo = value`` -> ``env.set_wrapper_attr("foo", value)``."""

    def build(node: cst.Assign) -> cst.BaseSmallStatement:
        target = node.targets[0].target
        assert isinstance(target, cst.Attribute)
        call = cst.Call(
            func=cst.Attribute(value=target.value, attr=cst.Name("set_wrapper_attr")),
            args=[
                cst.Arg(value=cst.SimpleString(f'"{name}"'), comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))),
                cst.Arg(value=node.value),
            ],
        )
        return cst.Expr(call, semicolon=node.semicolon)

    return build


def through(*attrs: str):
    """``env.foo`` -> ``env.<attrs...>`` (``env.unwrapped.foo``, ``env.spec.max_episode_steps``)."""

    def build(node: cst.Attribute) -> cst.BaseExpression:
        value: cst.BaseExpression = node.value
        for name in attrs[:-1]:
            value = cst.Attribute(value=value, attr=cst.Name(name))
        return node.with_changes(value=value, attr=cst.Name(attrs[-1]))

    return build


def get_wrapper_attr(name: str, quote: str = '"', below: int = 0):
    def build(node: cst.Attribute) -> cst.BaseExpression:
        value: cst.BaseExpression = node.value
        for _ in range(below):
            assert isinstance(value, cst.Attribute)
            value = value.value
        return cst.Call(
            func=cst.Attribute(value=value, attr=cst.Name("get_wrapper_attr")),
            args=[cst.Arg(value=cst.SimpleString(f"{quote}{name}{quote}"))],
            lpar=node.lpar,
            rpar=node.rpar,
        )

    return build


def self_env() -> cst.Attribute:
    return cst.Attribute(value=cst.Name("self"), attr=cst.Name("env"))


def get_wrapper_attr_of():
    """``getattr(target, name)`` -> ``target.get_wrapper_attr(name)``."""

    def build(node: cst.Call) -> cst.BaseExpression:
        return cst.Call(
            func=cst.Attribute(value=node.args[0].value, attr=cst.Name("get_wrapper_attr")),
            args=[cst.Arg(value=node.args[1].value)],
            lpar=node.lpar,
            rpar=node.rpar,
        )

    return build


def has_wrapper_attr():
    """``hasattr(x, "name")`` -> ``x.has_wrapper_attr("name")``."""

    def build(node: cst.Call) -> cst.BaseExpression:
        receiver, key = node.args
        return cst.Call(
            func=cst.Attribute(value=receiver.value, attr=cst.Name("has_wrapper_attr")),
            args=[key.with_changes(comma=cst.MaybeSentinel.DEFAULT)],
            lpar=node.lpar,
            rpar=node.rpar,
        )

    return build


def hasattr_unwrapped():
    """``hasattr(x, "name")`` -> ``hasattr(x.unwrapped, "name")``."""

    def build(node: cst.Call) -> cst.BaseExpression:
        receiver = node.args[0]
        return node.with_changes(
            args=[receiver.with_changes(value=cst.Attribute(value=receiver.value, attr=cst.Name("unwrapped"))), *node.args[1:]]
        )

    return build
