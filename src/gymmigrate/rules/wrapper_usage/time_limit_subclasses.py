"""Subclasses of gym's ``TimeLimit`` (GM609): Gymnasium's ``TimeLimit.__init__`` requires
``max_episode_steps``.

gym's ``TimeLimit(env)`` read the limit from the wrapped env's spec; Gymnasium's raises
TypeError without one. ``TimeLimit(env)`` itself is a changed signature like the others
(``arguments.py``); here are the subclasses of this module: one whose ``__init__`` calls
``super().__init__(env)`` without the limit, and one built without it that inherits
TimeLimit's ``__init__``. Part of ``renames.WrapperRenames``.
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.env_classes import is_super_method_call
from gymmigrate.facts.module import walk
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.env_ids.syntax import gym_alias
from gymmigrate.rules.wrapper_usage.arguments import (
    missing_or_none,
    parameter,
    time_limit_without_limit,
)
from gymmigrate.rules.wrapper_usage.tables import wrapper_rest

if TYPE_CHECKING:
    from gymmigrate.rules.wrapper_usage.stacks import StacksFamily


def time_limit_subclass_call(family: StacksFamily, call: ast.Call) -> None:
    """A call that constructs no gym wrapper: a ``super().__init__`` in a TimeLimit
    subclass's ``__init__``, or a construction of a subclass that keeps TimeLimit's."""
    _super_init(family, call)
    subclass = _subclass_called(family, call)
    if subclass is not None:
        build = time_limit_without_limit(family, call, subclass)
        if build is not None:
            family.plan.replace(call, build)


def _super_init(family: StacksFamily, call: ast.Call) -> None:
    """``super().__init__(env)`` in the ``__init__`` of a subclass of gym's ``TimeLimit``,
    without ``max_episode_steps``: legacy defaulted it to the wrapped env's
    ``spec.max_episode_steps`` (None without a spec), Gymnasium's requires a positive int
    (TypeError). Where the ``__init__`` itself sets ``self._max_episode_steps`` and
    ``self._elapsed_steps`` afterwards (it decides the limit, as gym's body did) and its
    arguments are on record (GM617, or its own ``RecordConstructorArgs``), what TimeLimit's
    ``__init__`` did is all done by the subclass save ``Wrapper.__init__``: the call
    becomes that (its reset and step are TimeLimit's, reading those attributes). Anything
    else is reported."""
    if not is_super_method_call(call, "__init__"):
        return
    init = family.facts.enclosing_function(call)
    classdef = family.facts.parent(init) if init is not None else None
    if init is None or init.name != "__init__" or not isinstance(classdef, ast.ClassDef):
        return
    bases = [b for b in classdef.bases if not (isinstance(b, ast.Name) and b.id == "object")]
    if len(bases) != 1 or not any(
        wrapper_rest(q) == "TimeLimit" and q.startswith("gym.") for q in family.facts.qualified_names(bases[0])
    ):
        return
    if not missing_or_none(call, "max_episode_steps", 1):
        return
    env = parameter(call, "env", 0)
    statement = family.facts.parent(call)
    alias = gym_alias(family.facts)
    if (
        isinstance(statement, ast.Expr)
        and statement in init.body
        and env is not None
        and len(call.args) + len(call.keywords) == 1
        and alias is not None
        and _sets_after(init, statement, ("_max_episode_steps", "_elapsed_steps"))
        and _arguments_recorded(classdef, init)
    ):
        env_text = family.facts.segment(env)
        family.report(
            call,
            "GM609",
            f"`{classdef.name}` sets `_max_episode_steps` and `_elapsed_steps` itself, but Gymnasium's TimeLimit "
            "requires max_episode_steps (TypeError without it; gym read the spec's): "
            f"`{alias}.Wrapper.__init__(self, {env_text})` does the rest of what TimeLimit's __init__ did",
            kind=FixKind.AUTO,
            tier=Tier.NOTE,
        )
        family.plan.replace(call, lambda node: cst.parse_expression(f"{alias}.Wrapper.__init__(self, {env_text})"))
        return
    family.report(
        call,
        "GM609",
        f"`{classdef.name}` subclasses TimeLimit, whose __init__ requires max_episode_steps in Gymnasium 1.x "
        "(a positive int, TypeError without it; gym took the wrapped env's spec.max_episode_steps, None without "
        "a spec): compute the limit before this call and pass it",
        kind=FixKind.FLAG,
    )


def _subclass_called(family: StacksFamily, call: ast.Call) -> str | None:
    """The name of the class of this module ``call`` builds when it derives from gym's
    ``TimeLimit`` (through classes here) and neither it nor a class between defines
    ``__init__``: TimeLimit's own takes the arguments (``max_episode_steps`` required now)."""
    classdef = family.receivers.local_class(call.func)
    name = classdef.name if classdef is not None else None
    seen: set[int] = set()
    while classdef is not None and id(classdef) not in seen:
        seen.add(id(classdef))
        if any(isinstance(s, (ast.FunctionDef, ast.AsyncFunctionDef)) and s.name == "__init__" for s in classdef.body):
            return None
        bases = [b for b in classdef.bases if not (isinstance(b, ast.Name) and b.id == "object")]
        if len(bases) != 1:
            return None
        if any(wrapper_rest(q) == "TimeLimit" for q in family.facts.qualified_names(bases[0])):
            return name
        classdef = family.receivers.local_class(bases[0])
    return None


def _sets_after(init: ast.FunctionDef | ast.AsyncFunctionDef, statement: ast.stmt, names: tuple[str, ...]) -> bool:
    """Every ``self.<name> = ...`` is a statement of the ``__init__`` body itself (not under
    a branch) after ``statement``."""
    after = init.body[init.body.index(statement) + 1 :]
    set_here = {
        target.attr
        for s in after
        if isinstance(s, (ast.Assign, ast.AnnAssign))
        for target in (s.targets if isinstance(s, ast.Assign) else [s.target])
        if isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self"
    }
    return set(names) <= set_here


def _arguments_recorded(classdef: ast.ClassDef, init: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    """``RecordConstructorArgs`` gets this wrapper's arguments without TimeLimit's __init__:
    the class calls it itself, or GM617 adds the call (arguments besides the env, none in
    ``*args``). Gymnasium's ``Wrapper.spec`` reads ``_saved_kwargs`` of a TimeLimit."""
    named = {n.attr if isinstance(n, ast.Attribute) else n.id for n in walk(classdef) if isinstance(n, (ast.Attribute, ast.Name))}
    if "EzPickle" in named:
        return False
    if "RecordConstructorArgs" in named:
        return True
    args = init.args
    positional = [*args.posonlyargs, *args.args]
    return (
        not args.posonlyargs
        and args.vararg is None
        and len(positional) >= 2
        and bool(positional[2:] or args.kwonlyargs or args.kwarg)
    )
