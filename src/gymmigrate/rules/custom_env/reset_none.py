"""GM501: a custom env's ``reset`` that returns nothing, on every path or on some.

Some legacy envs reset their state and return nothing (``def reset(self): self.h =
zeros(...)``): their own code never read the result, and gym never checked it. GM501 gives
such a reset Gymnasium's signature and seeding, but Gymnasium's reset must return ``(obs,
info)``: ``make()``'s env checker asserts it, every wrapper and vector env unpacks it, and
``None`` raises there. The class has no observation at hand to return (what it would be is
a decision about its contract, with its ``step``), so this is one item at the reset; a
reset that returns a value on some paths names the others (a bare ``return``, the end of
its body).

Only where the run proves the class is used directly (built in its own module, each
instance only asked for its attributes, its reset's result never read; no other module
imports that module, and nothing registers it for ``make``) is that a note: no wrapper,
checker or ``make`` ever meets the ``None``.
"""

from __future__ import annotations

import ast

from gymmigrate.facts.fall_through import may_fall_off
from gymmigrate.facts.module import ModuleFacts, own_returns, walk
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.custom_env.common import (
    ClassDecision,
    Method,
    is_docstring,
    local_subclasses,
)
from gymmigrate.rules.custom_env.hooks import overrides


def decide_reset_without_observation(decision: ClassDecision) -> None:
    function = decision.method("reset")
    if function is None or not _legacy(function) or _abstract(decision, function):
        return
    bare = [ret for ret in own_returns(function) if _returns_none(ret)]
    valued = [ret for ret in own_returns(function) if not _returns_none(ret)]
    falls = may_fall_off(function.body)
    if not bare and not falls:
        return
    if valued:
        places = [f"line {ret.lineno} (a bare `return`)" for ret in bare] + (["the end of its body"] if falls else [])
        what = (
            f"reset returns nothing at {' and at '.join(places)}, an observation elsewhere: Gymnasium's reset must "
            "return `(obs, info)` on every path"
        )
        todo = "return the observation with an info dict there too, by hand"
    else:
        what = "reset returns nothing: Gymnasium's reset must return `(obs, info)`"
        todo = "there is no observation at hand here, so returning one with an info dict is a decision to take with what step() returns"
    name = decision.classdef.name
    step = decision.method("step")
    if not valued and _placeholder(function) and step is not None and _placeholder(step):
        # A template: reset and step both only `pass` (behind a docstring), so no observation
        # exists anywhere yet and legacy returned None too; whoever writes the bodies writes
        # the contract, and there is nothing to decide about this code as it is.
        decision.report(
            function,
            "GM501",
            "reset and step are placeholders (no body but a docstring, `pass` or `...`): when they are written, "
            "reset must return `(obs, info)` and step `(obs, reward, terminated, truncated, info)`",
            FixKind.FLAG,
            tier=Tier.NOTE,
        )
        return
    heirs = _base_of_overrides_only(decision)
    if heirs:
        # A base whose own instances the run never makes: its reset runs only under the
        # overrides (``super().reset()``), which return the observation themselves; no
        # wrapper, checker or ``make`` meets its None.
        decision.report(
            function,
            "GM501",
            f"{what}; the run never builds `{name}` itself and every subclass of it overrides reset ({heirs}), so "
            "its reset runs only under theirs, which return the observation: nothing unpacks this one's None",
            FixKind.FLAG,
            tier=Tier.NOTE,
        )
        return
    direct = _used_directly(decision)
    decision.report(
        function,
        "GM501",
        f"{what}, which `make()`'s env checker, every wrapper and the vector envs unpack (a TypeError on None); {todo}"
        + (
            f"; the run uses `{name}` only directly (built in this module, never handed on, wrapped, registered or "
            "imported elsewhere, its reset's result unread), where nothing unpacks it"
            if direct
            else ""
        ),
        FixKind.FLAG,
        tier=Tier.NOTE if direct else None,
    )


def _legacy(function: Method) -> bool:
    """A gym-era signature the family migrates: no ``seed``/``options`` pair yet, no
    ``return_info`` (whose resets return a value in either mode), not a generator."""
    args = function.args
    names = {a.arg for a in (*args.posonlyargs, *args.args, *args.kwonlyargs)}
    if "return_info" in names or {"seed", "options"} <= names:
        return False
    return not any(isinstance(node, (ast.Yield, ast.YieldFrom)) for node in walk(function))


def _abstract(decision: ClassDecision, function: Method) -> bool:
    """A placeholder for subclasses: ``@abstractmethod``, or a body of only a docstring,
    ``pass`` and ``...`` that subclasses (here or elsewhere in the run) override."""
    for decorator in function.decorator_list:
        name = decorator.attr if isinstance(decorator, ast.Attribute) else decorator.id if isinstance(decorator, ast.Name) else ""
        if name == "abstractmethod":
            return True
    local, elsewhere = overrides(decision, "reset")
    return _placeholder(function) and bool(local or elsewhere)


def _placeholder(function: Method) -> bool:
    """A body of only a docstring, ``pass`` and ``...``."""
    body = function.body[1:] if is_docstring(function.body[:1]) else function.body
    return all(
        isinstance(s, ast.Pass) or (isinstance(s, ast.Expr) and isinstance(s.value, ast.Constant) and s.value.value is Ellipsis)
        for s in body
    )


def _returns_none(ret: ast.Return) -> bool:
    return ret.value is None or (isinstance(ret.value, ast.Constant) and ret.value.value is None)


def _used_directly(decision: ClassDecision) -> bool:
    """The run proves no wrapper, checker or ``make`` reaches an instance: the class is
    reached from no other module (``ProjectView.reached_from_outside``), nothing here
    derives from it, and each read of its name builds an instance that is bound to a name
    (or asked for an attribute at once) whose every read asks it for an attribute, without
    reading what its reset returns."""
    family = decision.family
    project = family.receivers.project
    classdef = decision.classdef
    facts = family.facts
    if project is None or facts.parent(classdef) is not facts.tree or project.reached_from_outside(classdef.name):
        return False
    if local_subclasses(decision):
        return False
    reads = facts.reads_of(classdef.name)
    if not reads:
        return False
    for read in reads:
        call = facts.parent(read)
        if not (isinstance(call, ast.Call) and call.func is read):
            return False
        holder = facts.parent(call)
        if isinstance(holder, ast.Attribute) and _only_asked(facts, holder):
            continue
        if not (isinstance(holder, ast.Assign) and holder.value is call and len(holder.targets) == 1 and isinstance(holder.targets[0], ast.Name)):
            return False
        target = holder.targets[0]
        uses = facts.reads_of(target.id, target)
        for use in uses:
            owner = facts.parent(use)
            if not (isinstance(owner, ast.Attribute) and _only_asked(facts, owner)):
                return False
    return True


def _base_of_overrides_only(decision: ClassDecision) -> str:
    """The names of the subclasses overriding reset, where the run proves the class is
    only a base: no code of the run builds it (a call of its name here, a call from another
    module, a registration), it has subclasses, and each direct subclass defines its own
    reset or is, in this module, only such a base itself (``class CameraSim(BaseSim)``
    with no reset, whose subclasses elsewhere override it). "" otherwise."""
    names = _overriders(decision, decision.classdef, set())
    if not names:
        return ""
    return ", ".join(names[:4]) + (f" and {len(names) - 4} more" if len(names) > 4 else "")


def _overriders(decision: ClassDecision, classdef: ast.ClassDef, seen: set[int]) -> list[str]:
    """The subclasses under ``classdef`` whose own reset runs in place of its, where the
    run builds ``classdef`` nowhere and every subclass below it either overrides reset or
    is such a base too; [] where that is not proved."""
    family = decision.family
    project = family.receivers.project
    facts = family.facts
    if project is None or facts.parent(classdef) is not facts.tree or id(classdef) in seen:
        return []
    seen.add(id(classdef))
    name = classdef.name
    # a subclass's ``super().__init__(...)`` elsewhere builds that subclass, not this base
    if project.built_from_outside(name) or project.registered_here(name) or project.facts.registers_from_data:
        return []
    for read in facts.reads_of(name):
        holder = facts.parent(read)
        if isinstance(holder, ast.ClassDef) and read in holder.bases:
            continue
        if isinstance(holder, ast.Call) and isinstance(holder.func, ast.Name) and holder.func.id == "super" and holder.args[:1] == [read]:
            continue  # ``super(Base, self)``
        return []  # built, or handed on (a table of classes, a factory's argument)
    if project.subclasses_elsewhere_without(name, "reset"):
        return []
    names: list[str] = []
    for sub in walk(facts.tree):
        if not isinstance(sub, ast.ClassDef) or not any(family.receivers.local_class(b) is classdef for b in sub.bases):
            continue
        if decision.env.index(sub).methods.get("reset") is not None:
            names.append(sub.name)
            continue
        below = _overriders(decision, sub, seen)
        if not below:
            return []
        names.extend(below)
    return names + [w.rsplit(":", 1)[-1] for w in project.overridden_elsewhere(name, "reset")]


def _only_asked(facts: ModuleFacts, attribute: ast.Attribute) -> bool:
    """``x.attr`` read or called; a ``reset()`` called only for its effect."""
    if attribute.attr != "reset":
        return True
    call = facts.parent(attribute)
    return isinstance(call, ast.Call) and call.func is attribute and isinstance(facts.parent(call), ast.Expr)
