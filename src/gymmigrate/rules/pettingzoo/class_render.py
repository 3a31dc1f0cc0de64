"""PZ107 in custom env classes: ``render(self, mode=...)`` takes its mode at construction.

PettingZoo 1.22 fixed the render mode at construction: ``render()`` takes no mode and
reads ``self.render_mode`` (its wrappers assert that the attribute exists). A class whose
``__init__`` can take one more keyword gets ``render_mode=None`` there and reads it in
``render``; a ``render`` that only hands the mode to a held env whose own ``render`` takes
none loses it on both sides. Anything else is named for review. ``env_classes.py`` finds
the classes.
"""

from __future__ import annotations

import ast

from gymmigrate.edits.arguments import remove_args
from gymmigrate.facts.module import FUNCTIONS
from gymmigrate.findings import FixKind
from gymmigrate.rules.pettingzoo.common import (
    PettingZooFamily,
    insert_first,
    with_params,
    without_param,
)


def plan_render(family: PettingZooFamily, classdef: ast.ClassDef, methods: dict[str, ast.FunctionDef | ast.AsyncFunctionDef]) -> None:
    """``def render(self, mode="human")``: since 1.22 the mode is ``self.render_mode``, set at
    construction (PettingZoo's wrappers assert that the attribute exists)."""
    render = methods["render"]
    params = [a.arg for a in render.args.args[1:]]
    if "mode" not in params or any(
        isinstance(attr.ctx, ast.Store) and family.facts.enclosing_class(attr) is classdef
        for attr in family.facts.attributes.get("render_mode", ())
    ):
        return  # no mode to move, or the class already stores ``self.render_mode``
    handed_on = _mode_handed_to_modeless_render(family, render)
    if handed_on is not None:
        # ``def render(self, mode="human"): return self.env.render(mode)`` around an env
        # whose render takes no mode (it reads its own render_mode): that call raised
        # TypeError already; without the mode, both are what PettingZoo 1.22 calls.
        family.changed()
        family.plan.replace(render, lambda node: without_param(node, "mode"))
        family.plan.replace(handed_on, lambda node: remove_args(node, lambda arg: True))
        held = family.facts.segment(handed_on.func.value)  # type: ignore[attr-defined]
        family.report(render, "PZ107", f"`render()` takes no mode since PettingZoo 1.22, and `{held}.render()`, which "
                    "this one handed the mode to, takes none either (its own render_mode decides): the mode is "
                    "dropped from both", FixKind.ASSIST)
        return
    init = methods.get("__init__")
    if init is None or init.args.vararg or init.args.kwarg or init.args.kwonlyargs or any(
        a.arg == "render_mode" for a in init.args.args
    ):
        family.report(render, "PZ107", "`render()` takes no mode since PettingZoo 1.22: take `render_mode` in "
                    "`__init__`, store `self.render_mode` and read it in `render()`", FixKind.FLAG)
        return
    family.changed()
    family.plan.replace(render, lambda node: without_param(node, "mode"))
    insert_first(family.plan, render, "mode = self.render_mode")
    family.plan.replace(init, lambda node: with_params(node, ["render_mode"]))
    insert_first(family.plan, init, "self.render_mode = render_mode")
    family.report(render, "PZ107", "the render mode is fixed at construction (`render_mode=`, PettingZoo 1.22); "
                "review: `render()` now reads `self.render_mode`", FixKind.ASSIST)

def _mode_handed_to_modeless_render(family: PettingZooFamily, render: ast.FunctionDef | ast.AsyncFunctionDef) -> ast.Call | None:
    """The one use of ``mode`` in ``render`` is ``self.<x>.render(mode)``, where every value
    the class stores in ``self.<x>`` is an instance of a class of this module whose
    ``render(self)`` takes nothing: that call; else None."""
    reads = family.facts.scopes[render].reads.get("mode", []) if render in family.facts.scopes else []
    if len(reads) != 1:
        return None
    call = family.facts.parent(reads[0])
    if not (
        isinstance(call, ast.Call)
        and len(call.args) == 1
        and call.args[0] is reads[0]
        and not call.keywords
        and isinstance(call.func, ast.Attribute)
        and call.func.attr == "render"
    ):
        return None
    held = call.func.value
    if not (isinstance(held, ast.Attribute) and isinstance(held.value, ast.Name) and held.value.id == "self"):
        return None
    values = family.receivers.self_attribute_values(held, held.attr)
    if not values:
        return None
    for value in values:
        classdef = family.receivers.local_class(value.func) if isinstance(value, ast.Call) else None
        if classdef is None:
            return None
        inner = next((m for m in classdef.body if isinstance(m, FUNCTIONS) and m.name == "render"), None)
        if inner is None or inner.args.vararg or inner.args.kwarg or len([*inner.args.posonlyargs, *inner.args.args]) != 1 or inner.args.kwonlyargs:
            return None
    return call
