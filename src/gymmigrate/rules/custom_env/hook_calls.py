"""gym < 0.9 hooks called across a class hierarchy follow their rename.

A subclass of the run's own env calls its base's old hook by name: ``super()._reset()``,
``Base._step(self, a)``, or ``self._seed(s)`` where only a base defines ``_seed``, in the
base's module or another of the run (whose renames the run's facts give:
``ProjectView.hooks_renamed_above``). The
base's ``_reset`` becomes ``reset`` in the same run, so a call left on the old name raises
AttributeError on every reset. Renaming the call alone is not enough either: the renamed
base returns ``(obs, info)`` (five step values), so the caller's use of the result must
follow the new contract too. That is what the family already does for the same code
written with the public names (``return super().reset()``, ``ob, r, d, i =
super().step(a)``), so the renames are made in a round of their own
(``Plan.renames_first``) and the next round migrates the renamed code as it would have
with the names written so.
"""

from __future__ import annotations

import ast

from gymmigrate.facts.env_classes import EnvClasses, self_calls
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import is_super_call
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.base import RuleFamily
from gymmigrate.rules.custom_env.common import (
    UNDERSCORE_METHODS,
    UNDERSCORE_RULE,
    ClassDecision,
    Method,
)

Renames = dict[int, tuple[ast.ClassDef, dict[str, str]]]  # id(classdef) -> (class, old -> new)


def rename_hook_calls_first(family: RuleFamily, env: EnvClasses) -> bool:
    """Where a class calls a renamed hook of a base of the run, rename every hook of the
    module and those calls alone (a first round); True when it did."""
    if not family.plan.allow_renames_first:
        return False
    renames: Renames = {}
    defs: dict[int, dict[str, Method]] = {}  # the methods of each class, as the family indexes them
    builtin: set[int] = set()  # classes whose first base is one of Gym's own env classes
    for classdef in family.facts.all_classes:
        if not env.is_custom_env(classdef) or family.receivers.class_kind(classdef) is EnvKind.OWN_API:
            continue
        decision = ClassDecision(family, env, classdef)
        if decision.plan.published:
            continue  # ``reset = _reset``: the hooks keep their names (``common.ClassDecision``)
        own = {old: new for new, old in decision.renamed.items() if old in decision.methods}
        renames[id(classdef)] = (classdef, own)
        defs[id(classdef)] = decision.methods
        if env.builtin_env_base(classdef):
            builtin.add(id(classdef))
    calls = [
        (call, new)
        for classdef, own in renames.values()
        for call, new in _base_hook_calls(
            family, classdef, own, _renamed_above(family, classdef, renames), builtin=id(classdef) in builtin
        )
    ]
    for classdef, own in renames.values():
        if id(classdef) in builtin:
            _report_unfollowed_builtin_hooks(family, classdef, own)
    if not calls:
        return False
    family.plan.renames_first = True
    for classdef, own in renames.values():
        methods = defs[id(classdef)]
        for old, new in own.items():
            family.plan.replace(methods[old], lambda node, new=new: node.with_changes(name=node.name.with_changes(value=new)))
            family.report(methods[old], UNDERSCORE_RULE[new], f"gym < 0.9 method `{old}` renamed `{new}`", tier=Tier.NOTE)
            calls.extend((call, new) for call in self_calls(family.facts, classdef, old))
    for call, new in calls:
        family.plan.replace(call.func, lambda node, new=new: node.with_changes(attr=node.attr.with_changes(value=new)))
    return True


def _renamed_above(family: RuleFamily, classdef: ast.ClassDef, renames: Renames) -> set[str]:
    """The hooks that the class's bases rename (at any depth): this module's, and those of
    other modules of the run that the lookup reaches first (``ProjectView.hooks_renamed_above``)."""
    found: set[str] = set()
    seen = {id(classdef)}
    todo = [classdef]
    project = family.receivers.project
    while todo:
        for base in todo.pop().bases:
            local = family.receivers.local_class(base)
            if local is None:
                if project is not None:
                    for qualified in family.facts.qualified_names(base):
                        found.update(project.hooks_renamed_above(qualified))
                continue
            if id(local) in seen:
                continue
            seen.add(id(local))
            found.update(renames.get(id(local), (local, {}))[1])
            todo.append(local)
    return found


# gym <= 0.9.5's own envs defined ``_step``/``_reset`` (``Env.step`` called them); Gymnasium's
# name them ``step``/``reset``, with the new contracts the next round gives the call. Their
# ``_render``/``_seed`` are not followed: Gymnasium's render takes no mode and seeding moved
# into reset (CarRacing even has an internal ``_render`` of another signature).
_BUILTIN_HOOKS = frozenset({"_step", "_reset"})


def _base_hook_calls(
    family: RuleFamily, classdef: ast.ClassDef, own: dict[str, str], above: set[str], *, builtin: bool = False
) -> list[tuple[ast.Call, str]]:
    """The class's calls of a base's gym < 0.9 hook that the run renames: ``super()._reset()``
    and ``Base._reset(self)`` from a hook the class renames itself or from any other method
    (a ``_reset`` kept as the helper of a public reset of its own), and ``self._step(a)`` on
    a hook it does not define. A base renames its hook under the class's own condition (no
    public name above it), so the class's rename stands for the base's; otherwise only a
    rename seen above (``above``: bases of this module, and of other modules through the
    run's facts) counts (a base may publish its hook under the public name, ``reset =
    _reset``, and keep it)."""
    inherited = family.receivers.base_methods(classdef)
    if builtin:
        inherited = inherited | _BUILTIN_HOOKS  # the first base is one of Gym's own env classes
    bases = {ast.unparse(base) for base in classdef.bases}
    found: list[tuple[ast.Call, str]] = []
    for old, new in UNDERSCORE_METHODS.items():
        if old not in inherited:
            continue
        # ``super()._reset()`` reaches the base's hook whether the class renames its own
        # (then the base, under the same condition, renames its too) or keeps its own as a
        # helper beside a public ``reset`` (then only a rename seen above says so)
        through_base = old in own or old in above
        through_self = old not in own and old in above and not _defines(classdef, old, new)
        for call in family.facts.attribute_calls.get(old, ()):
            func = call.func
            if not isinstance(func, ast.Attribute) or family.facts.enclosing_class(call) is not classdef:
                continue
            target = func.value
            is_super = is_super_call(target)
            is_base = isinstance(target, (ast.Name, ast.Attribute)) and ast.unparse(target) in bases
            is_self = isinstance(target, ast.Name) and target.id == "self"
            if (through_base and (is_super or is_base)) or (through_self and is_self):
                found.append((call, new))
    return found


def _defines(classdef: ast.ClassDef, *names: str) -> bool:
    return any(isinstance(s, (ast.FunctionDef, ast.AsyncFunctionDef)) and s.name in names for s in classdef.body)


def _report_unfollowed_builtin_hooks(family: RuleFamily, classdef: ast.ClassDef, own: dict[str, str]) -> None:
    """``super()._render(mode, close)`` (or ``_seed``, ``_close``) of Gym's own env class from
    a hook the class renames: Gymnasium's class has no such hook (CarRacing's ``_render`` is
    an internal of another signature), and what replaces it (a render without a mode, a
    seeded reset) is not the same call. Reported at the call."""
    for call in family.facts.attribute_calls.get("_render", []) + family.facts.attribute_calls.get("_seed", []) + family.facts.attribute_calls.get("_close", []):
        func = call.func
        if not isinstance(func, ast.Attribute) or func.attr not in own or family.facts.enclosing_class(call) is not classdef:
            continue
        target = func.value
        if not is_super_call(target):
            continue
        new = own[func.attr]
        family.report(
            call,
            UNDERSCORE_RULE[new],
            f"`{family.facts.segment(call)}` calls gym 0.9's `{func.attr}` hook of Gym's own env class, which this class's "
            f"`{func.attr}` now overrides as `{new}`: Gymnasium's class has no such hook (its `{new}` takes other arguments, "
            "and CarRacing's internal `_render` another signature); call what you mean by hand",
            FixKind.FLAG,
        )
