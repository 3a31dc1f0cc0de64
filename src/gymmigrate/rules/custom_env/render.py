"""GM405: ``def render(self, mode="human")`` -> ``def render(self)`` reading ``self.render_mode``.

``gymnasium.make(id, render_mode=...)`` passes the mode to the constructor, so
``__init__`` takes ``render_mode=None`` and stores it; without a mode, ``render()``
draws nothing (Gymnasium's convention). No caller is left broken: a forwarding
``env.render(mode, ...)`` to inner envs stops passing the mode (reviewed), and the
signature is kept (reported) while a render call elsewhere in the file still passes a
mode and may reach an instance of the class.
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from typing import TYPE_CHECKING

from gymmigrate.facts import names as N
from gymmigrate.facts.creation import CreationFinder, passes_mode
from gymmigrate.facts.env_classes import is_super_method_call
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.custom_env.common import ClassDecision, param_names
from gymmigrate.rules.custom_env.hooks import local_subclasses

if TYPE_CHECKING:
    from gymmigrate.rules.base import RuleFamily


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
    own = _own_mode_call(decision)
    if own is not None:
        decision.report(
            function,
            "GM405",
            f"render(mode) kept: `{decision.family.facts.segment(own)}` on line {own.lineno} (this class, a base or a "
            "subclass in this file) asks render() for a mode, a TypeError once render() takes none; render that mode "
            "another way (or drop the argument), then run again",
            FixKind.FLAG,
        )
        return
    blocking = _unmigrated_mode_call(decision)
    project = decision.family.receivers.project
    if blocking is None and project is not None and project.render_called_elsewhere():
        decision.report(
            function,
            "GM405",
            "render(mode) kept: another module of this run imports this class and passes a mode to `.render()` on an "
            "object that could not be traced, which may be an instance of it; give that env its render_mode where it "
            "is made, then run again",
            FixKind.FLAG,
        )
        return
    if blocking is not None:
        facts = decision.family.facts
        decision.report(
            function,
            "GM405",
            f"render(mode) kept: `{facts.segment(blocking)}` on line {blocking.lineno} still passes a mode (its env's "
            "creation could not be followed, so it was not migrated) and may reach this class; give that env its "
            "render_mode where it is made, then run again",
            FixKind.FLAG,
        )
        return
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


def _own_mode_call(decision: ClassDecision) -> ast.Call | None:
    """``self.render(mode="ansi")`` (or ``super().render("ansi")``) outside a render method,
    in this class, a local base or a local subclass: it reaches this render(), and with the
    mode removed it would be a TypeError. The mode it asks for is not the env's
    render_mode, so it is not rewritten: the class keeps render(mode) with the call."""
    facts = decision.family.facts
    hierarchy = [decision.classdef, *local_subclasses(decision)]
    receivers = decision.family.receivers
    todo = list(decision.classdef.bases)
    while todo:
        base = receivers.local_class(todo.pop())
        if base is not None and base not in hierarchy:
            hierarchy.append(base)
            todo.extend(base.bases)
    for classdef in hierarchy:
        for call in (*decision.env.index(classdef).self_calls.get("render", ()), *_super_render_calls(decision, classdef)):
            if passes_mode(call, facts):
                return call  # type: ignore[no-any-return]
    return None


def _super_render_calls(decision: ClassDecision, classdef: ast.ClassDef) -> list[ast.Call]:
    return [c for c in decision.env.index(classdef).nodes[ast.Call] if is_super_method_call(c, "render")]  # type: ignore[misc]


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


def _unmigrated_mode_call(decision: ClassDecision) -> ast.Call | None:
    """A render call elsewhere in the file that the rendering rules leave passing a mode
    and that may reach an instance of this class: removing ``mode`` from this render()
    would turn it into a TypeError."""
    family = decision.family
    left = family.notes.render_mode_calls_left
    if not left:
        return None
    finder = family.facts.memo(("custom-env-render-finder", 0), lambda: CreationFinder(family.facts, family.receivers, _is_creation(family)))
    for call in left:
        if family.facts.enclosing_class(call) is decision.classdef:
            continue  # its own calls: forwarding (above) or self.render(...)
        receiver = call.func.value  # type: ignore[attr-defined]
        if family.receivers.kind_of(receiver) not in (EnvKind.GYM_ENV, EnvKind.UNKNOWN):
            continue
        creation = finder.find(receiver)
        if creation.found and not any(family.receivers.local_class(c.func) is decision.classdef for c in creation.calls):
            continue  # made elsewhere (gym.make or another class): not this class's render
        return call
    return None


def _is_creation(family: RuleFamily) -> Callable[[ast.Call], bool]:
    """gym.make and friends, or a call of a class defined in this file."""
    def is_creation(call: ast.Call) -> bool:
        if family.receivers.local_class(call.func) is not None:
            return True
        return any(N.strip_gym_prefix(q) in N.GYM_ENV_FACTORIES for q in family.facts.qualified_names(call.func))

    return is_creation
