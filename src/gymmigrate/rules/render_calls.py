"""The syntax of ``render(...)`` calls for the rendering rules (``rules/rendering/``):
reading a legacy call's arguments on ``ast``, and the LibCST builds that rewrite the call
and the make it moves its mode to."""

from __future__ import annotations

import ast
from typing import Any

from gymmigrate.edits.arguments import append_keyword, remove_args
from gymmigrate.edits.lazy import cst
from gymmigrate.facts.module import keyword, own_returns

RGB_ARRAY = "rgb_array"  # the mode recorders need (also ``rendering.RGB_ARRAY``)


# -- ast helpers ----------------------------------------------------------------------------


def is_render(call: ast.Call) -> bool:
    return isinstance(call.func, ast.Attribute) and call.func.attr == "render"


def mode_argument(call: ast.Call) -> ast.AST | None:
    """The ``mode`` argument of a legacy ``render`` call (keyword or first positional)."""
    found = keyword(call, "mode")
    if found is not None:
        return found
    first = first_argument(call)
    if isinstance(first, ast.expr) and not isinstance(first, ast.Starred):
        return first
    return None


def arguments_in_order(call: ast.Call) -> list[ast.expr | ast.keyword]:
    """Positional arguments and keywords in source order (LibCST's ``call.args``)."""
    arguments: list[ast.expr | ast.keyword] = [*call.args, *call.keywords]
    return sorted(arguments, key=lambda a: (a.lineno, a.col_offset))


def first_argument(call: ast.Call) -> ast.AST | None:
    arguments = arguments_in_order(call)
    return arguments[0] if arguments else None


def in_source_order(calls: list[ast.Call]) -> list[ast.Call]:
    """Unique calls, outer before inner (the order a LibCST visitor met them)."""
    unique = {id(c): c for c in calls}.values()
    return sorted(unique, key=lambda c: (c.lineno, c.col_offset, -(c.end_lineno or 0), -(c.end_col_offset or 0)))


# -- builds (LibCST) ------------------------------------------------------------------------


def code(node: cst.CSTNode) -> str:
    return cst.Module(body=[]).code_for_node(node)


def close_call(node: Any) -> Any:
    return node.with_changes(
        func=node.func.with_changes(attr=cst.Name("close")), args=[], whitespace_before_args=cst.SimpleWhitespace("")
    )


def unwrapped_render_call(node: Any) -> Any:
    """``env.render(...)`` -> ``env.unwrapped.render(...)``: Gymnasium's wrappers (make adds
    some) take no render arguments; the env's own render still does."""
    return node.with_changes(func=node.func.with_changes(value=cst.Attribute(value=node.func.value, attr=cst.Name("unwrapped"))))


def without_mode_argument(node: Any) -> Any:
    mode = next((a for a in node.args if a.keyword is not None and a.keyword.value == "mode"), None)
    if mode is None and node.args and node.args[0].keyword is None and not node.args[0].star:
        mode = node.args[0]
    return remove_args(node, lambda arg: arg is mode)


def with_keyword(node: Any, func: str, name: str, literal: str) -> Any:
    """Add ``name=literal`` to the make call, even when another family wrapped it (``Autoreset(make(...))``)."""
    if isinstance(node, cst.Call) and "".join(code(node.func).split()) != "".join(func.split()):
        inner = node.args[0].value if node.args else None
        if isinstance(inner, cst.Call):
            args = list(node.args)
            args[0] = args[0].with_changes(value=with_keyword(inner, func, name, literal))
            return node.with_changes(args=args)
    if isinstance(node, cst.Call) and any(arg.keyword is not None and arg.keyword.value == name for arg in node.args):
        return node  # given already: by the same build for another site of this make (one edit per finding)
    # A literal, or a creation-time conditional (`"human" if rank == 0 else None`).
    value = cst.SimpleString(literal) if literal[:1] in ("'", '"') and literal[-1:] == literal[:1] else cst.parse_expression(literal)
    return append_keyword(node, name, value)


def single_frame_fixed(node: Any) -> Any:
    return node.with_changes(value=f"{node.prefix}{node.quote}{RGB_ARRAY}{node.quote}")


def fetched_render(facts: Any, receivers: Any, call: ast.Call) -> ast.Call | None:
    """``render_func()`` with ``render_func`` bound once, to ``get_render_func(env)``: a call of
    a def of the module whose every return is a render method it fetches (``return
    venv.envs[0].render``), a call of itself (``get_render_func(venv.venv)``) or None. That
    call of the def; None for anything else."""
    if not isinstance(call.func, ast.Name) or call.args or call.keywords:
        return None
    bindings = facts.bindings_of(call.func)
    statement = facts.parent(bindings[0]) if len(bindings) == 1 and isinstance(bindings[0], ast.Name) else None
    if not (isinstance(statement, ast.Assign) and statement.targets == bindings and isinstance(statement.value, ast.Call)):
        return None
    getter = statement.value
    function = receivers.local_function(getter.func)
    if function is None:
        return None
    values = [r.value for r in own_returns(function)]
    fetched = False
    for value in values:
        if isinstance(value, ast.Attribute) and value.attr == "render":
            fetched = True
        elif not (
            (isinstance(value, ast.Constant) and value.value is None)
            or value is None
            or (isinstance(value, ast.Call) and isinstance(value.func, ast.Name) and receivers.local_function(value.func) is function)
        ):
            return None
    return getter if fetched else None
