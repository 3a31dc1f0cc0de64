"""GM616: gym < 0.9 wrapper hooks ``_observation`` / ``_action`` / ``_reverse_action`` /
``_reward`` become ``observation`` / ``action`` / ``reverse_action`` / ``reward``.

Before gym 0.9.6 ``ObservationWrapper.step`` called ``self._observation(obs)``, and so on
for actions and rewards. Gymnasium's wrappers call the public names only, so an old
wrapper's hook is never called and the wrapper silently passes everything through. The
hook is renamed where the class derives from a Gym wrapper and does not define the
public name too; its own ``self._observation(...)`` calls follow. The old ``_step`` /
``_reset`` / ``_render`` / ``_seed`` / ``_close`` of a wrapper change their contract as
well (five values, ``(obs, info)``): where no base of the run defines the public name
(then ``_step`` is that base's own hook), they are renamed in a round of their own
(``Plan.renames_first``), and the next round migrates them as the wrapper's ``step`` /
``reset`` it decides on the renamed code, as it would have with the names written so.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.env_classes import self_calls
from gymmigrate.facts.legacy_wrapper_hooks import API_HOOKS, dead_hook_internals
from gymmigrate.facts.module import is_super_call
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext, Rule, RuleFamily

HOOKS = {"_observation": "observation", "_action": "action", "_reverse_action": "reverse_action", "_reward": "reward"}
# The Gym wrapper class whose step called each hook.
HOOK_BASES = {
    "_observation": "ObservationWrapper",
    "_action": "ActionWrapper",
    "_reverse_action": "ActionWrapper",
    "_reward": "RewardWrapper",
}
API_METHODS = API_HOOKS


class LegacyWrapperHooks(RuleFamily):
    RULES = (
        Rule(
            "GM616",
            "gym < 0.9 wrapper hooks",
            FixKind.AUTO,
            "`_observation` / `_action` / `_reward` hooks of a wrapper become `observation` / `action` / `reward`.",
        ),
    )

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        return any(f"def {name}(" in facts.text for name in (*HOOKS, *API_METHODS))

    def decide(self) -> None:
        for classdef in self.facts.all_classes:
            if not self.receivers.is_gym_wrapper_class(classdef):
                continue
            methods = {s.name: s for s in classdef.body if isinstance(s, (ast.FunctionDef, ast.AsyncFunctionDef))}
            bases, inherited = self._ancestry(classdef)
            renames = {
                old: new
                for old, new in HOOKS.items()
                if old in methods and new not in methods and new not in inherited and HOOK_BASES[old] in bases
            }
            for old, new in renames.items():
                self.plan.replace(methods[old], lambda node, new=new: node.with_changes(name=node.name.with_changes(value=new)))
                for call in self_calls(self.facts, classdef, old):
                    self.plan.replace(call.func, lambda node, new=new: node.with_changes(attr=node.attr.with_changes(value=new)))
                self.report(
                    methods[old],
                    "GM616",
                    f"gym < 0.9 wrapper hook `{old}` renamed `{new}`: Gymnasium's wrappers call `{new}` only",
                )
            base_methods = self.receivers.base_methods(classdef)
            for old, new in API_METHODS.items():
                if old not in methods or new in methods or new in base_methods:
                    continue  # not a dead hook: the class's own step, or a base's step calls it
                if not self.plan.allow_renames_first:
                    continue  # the rename was left out (--ignore GM616, a suppression comment)
                if self._reads_gone_internals(methods[old], old, new):
                    continue
                self.plan.renames_first = True
                self.plan.replace(methods[old], lambda node, new=new: node.with_changes(name=node.name.with_changes(value=new)))
                for call in self._hook_calls(classdef, old):
                    self.plan.replace(call.func, lambda node, new=new: node.with_changes(attr=node.attr.with_changes(value=new)))
                self.report(
                    methods[old],
                    "GM616",
                    f"gym < 0.9 wrapper method `{old}` renamed `{new}` (Gymnasium calls `{new}` only), and migrated as "
                    f"the wrapper's `{new}`",
                )

    def _reads_gone_internals(self, hook: ast.FunctionDef | ast.AsyncFunctionDef, old: str, new: str) -> bool:
        """The hook was written for gym 0.9's internals of its base wrapper class
        (``facts/legacy_wrapper_hooks.py``): renamed, Gymnasium would call a body that raises
        AttributeError at once; left as it is, it is never called and the class works as
        Gymnasium's base does. Reported, not renamed."""
        found = dead_hook_internals(self.receivers, hook)
        if found is None:
            return False
        base, gone = found
        shown = ", ".join(f"`{name}`" for name in gone)
        self.report(
            hook,
            "GM616",
            f"gym < 0.9 wrapper method `{old}` left as it is: it reads {shown}, gym 0.9's internals of `{base}` that "
            f"neither this class nor Gymnasium's `{base}` has, so renamed `{new}` it would raise AttributeError on "
            f"its first call; as it is, Gymnasium never calls it and the class does what Gymnasium's `{base}` does. "
            f"Port the body to `{new}` by hand if it should still run",
            FixKind.FLAG,
        )
        return True

    def _ancestry(self, classdef: ast.ClassDef) -> tuple[set[str], set[str]]:
        """The Gym wrapper classes ``classdef`` derives from (last name: ``ObservationWrapper``),
        and the methods its local base classes define."""
        bases: set[str] = set()
        inherited: set[str] = set()
        seen: set[int] = {id(classdef)}
        todo = [classdef]
        while todo:
            current = todo.pop()
            for base in current.bases:
                local = self.receivers.local_class(base)
                if local is not None and id(local) not in seen:
                    seen.add(id(local))
                    inherited.update(s.name for s in local.body if isinstance(s, (ast.FunctionDef, ast.AsyncFunctionDef)))
                    todo.append(local)
                    continue
                for qualified in self.facts.qualified_names(base):
                    bases.add(qualified.rsplit(".", 1)[-1])
        return bases, inherited

    def _hook_calls(self, classdef: ast.ClassDef, name: str) -> list[ast.Call]:
        """``self._step(a)``, ``super()._step(a)`` and ``self.env._step(a)`` in the class:
        gym < 0.9's Wrapper._step called the inner env's step, and so does the renamed one."""
        return [
            call
            for call in self.facts.attribute_calls.get(name, ())
            if isinstance(call.func, ast.Attribute)
            and self.facts.enclosing_class(call) is classdef
            and (
                (isinstance(call.func.value, ast.Name) and call.func.value.id == "self")
                or is_super_call(call.func.value)
                or (
                    isinstance(call.func.value, ast.Attribute)
                    and call.func.value.attr == "env"
                    and isinstance(call.func.value.value, ast.Name)
                    and call.func.value.value.id == "self"
                )
            )
        ]

