"""GM405: ``def render(self, mode="human")`` -> ``def render(self)`` reading ``self.render_mode``.

``gymnasium.make(id, render_mode=...)`` passes the mode to the constructor, so
``__init__`` takes ``render_mode=None`` and stores it; without a mode, ``render()``
draws nothing (Gymnasium's convention).
"""

from __future__ import annotations

import ast

from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.custom_env.common import ClassDecision, param_names


def decide_render(decision: ClassDecision) -> None:
    function = decision.method("render")
    if function is None:
        return
    args = function.args
    params = args.args  # LibCST's ``params``: positional-or-keyword parameters
    mode_index = next((i for i, p in enumerate(params) if p.arg == "mode"), None)
    if mode_index is None:
        return
    first_default = len(params) - len(args.defaults)
    default = args.defaults[mode_index - first_default] if mode_index >= first_default else None
    old_default = ""
    if default is not None:
        text = decision.family.facts.segment(default)
        old_default = f" (the old default was {text}: pass render_mode={text} to gymnasium.make to keep it)"
    decision.plan.render = True
    _report_forwarded_modes(decision, function)
    # Notes: the standard Gymnasium signature, applied; the render calls and creation
    # sites in the run are reviewed where they are (GM401/GM402), not here.
    decision.report(function, "GM405", f"render() takes no mode: it reads self.render_mode, fixed when the env is made, and draws nothing when that is None{old_default}", tier=Tier.NOTE)
    init = decision.method("__init__")
    if init is None:
        if decision.env.has_local_env_base(decision.classdef):
            decision.plan.local_env_base = True
            decision.report(decision.classdef, "GM405", "render_mode must reach __init__: add a render_mode=None parameter to the base class and store self.render_mode", FixKind.FLAG)
            return
        decision.report(decision.classdef, "GM405", "added __init__(self, render_mode=None) storing self.render_mode: gymnasium.make passes render_mode to the constructor", tier=Tier.NOTE)
        return
    if "render_mode" not in param_names(init):
        decision.report(init, "GM405", "__init__ takes render_mode=None (gymnasium.make passes it) and stores self.render_mode", tier=Tier.NOTE)




def _report_forwarded_modes(decision: ClassDecision, function: ast.AST) -> None:
    """``env.render(mode, close)`` to inner envs loses its ``mode`` argument (the build
    drops it: Gymnasium's render() takes none); the inner envs then render in the mode
    they were made with, and any other argument must still be one they accept."""
    for call in decision.function(function).of(ast.Call):
        func = call.func  # type: ignore[attr-defined]
        if not (isinstance(func, ast.Attribute) and func.attr == "render") or _is_super(func.value):
            continue
        passes_mode = [a for a in call.args if isinstance(a, ast.Name) and a.id == "mode"]  # type: ignore[attr-defined]
        passes_mode += [k for k in call.keywords if k.arg == "mode" and isinstance(k.value, ast.Name) and k.value.id == "mode"]  # type: ignore[attr-defined]
        if not passes_mode:
            continue
        others = len(call.args) + len(call.keywords) - len(passes_mode)  # type: ignore[attr-defined]
        rest = " and the arguments left must be ones its render() accepts (Gymnasium's takes none)" if others else ""
        decision.report(
            call,
            "GM405",
            f"the mode is no longer passed on to {decision.family.facts.segment(func.value)}.render(): make the inner envs "
            f"with render_mode=self.render_mode{rest}",
            FixKind.ASSIST,
        )


def _is_super(node: ast.AST) -> bool:
    return isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "super"
