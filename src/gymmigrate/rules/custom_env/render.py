"""GM405: ``def render(self, mode="human")`` -> ``def render(self)`` reading ``self.render_mode``.

``gymnasium.make(id, render_mode=...)`` passes the mode to the constructor, so
``__init__`` takes ``render_mode=None`` and stores it; without a mode, ``render()``
draws nothing (Gymnasium's convention).
"""

from __future__ import annotations

from gymmigrate.findings import FixKind
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
    decision.report(function, "GM405", f"render() takes no mode: it reads self.render_mode, fixed when the env is made, and draws nothing when that is None{old_default}")
    init = decision.method("__init__")
    if init is None:
        if decision.env.has_local_env_base(decision.classdef):
            decision.plan.local_env_base = True
            decision.report(decision.classdef, "GM405", "render_mode must reach __init__: add a render_mode=None parameter to the base class and store self.render_mode", FixKind.FLAG)
            return
        decision.report(decision.classdef, "GM405", "added __init__(self, render_mode=None) storing self.render_mode: gymnasium.make passes render_mode to the constructor")
        return
    if "render_mode" not in param_names(init):
        decision.report(init, "GM405", "__init__ takes render_mode=None (gymnasium.make passes it) and stores self.render_mode")


