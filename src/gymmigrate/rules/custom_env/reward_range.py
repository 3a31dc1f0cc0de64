"""GM507: reads of ``reward_range``, removed from ``Env`` and ``Wrapper`` in Gymnasium 1.0.

Reported, never rewritten: the value only exists where an env class defines it.
"""

from __future__ import annotations

import ast

from gymmigrate.facts.decisions import Action, decide
from gymmigrate.facts.env_classes import EnvClasses, is_self_attribute
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import ModuleFacts
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext, Rule, RuleFamily


class RewardRange(RuleFamily):
    RULES = (Rule("GM507", "reward_range", FixKind.FLAG, "Reads of `reward_range`, removed from `Env` and `Wrapper`, are reported."),)

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        return "reward_range" in facts.text

    def decide(self) -> None:
        env = EnvClasses.of(self.facts, self.receivers)
        for node in list(self.facts.parents):
            if isinstance(node, ast.Attribute) and node.attr == "reward_range" and not self._is_store(node):
                self._check(env, node)

    def _is_store(self, node: ast.Attribute) -> bool:
        parent = self.facts.parent(node)
        if isinstance(parent, ast.Assign):
            return any(target is node for target in parent.targets)
        return isinstance(parent, ast.AnnAssign) and parent.target is node

    def _check(self, env: EnvClasses, node: ast.Attribute) -> None:
        owner = node.value
        classdef = self.facts.enclosing_class(node)
        if isinstance(owner, ast.Name) and owner.id == "self" and classdef is not None:
            if self.receivers.is_gym_wrapper_class(classdef):
                self.report(node, "GM507", "Wrapper.reward_range was removed in Gymnasium 1.0; read `self.env.unwrapped.reward_range` if the env defines it")
            elif env.is_custom_env(classdef) and not _defines_reward_range(env, classdef):
                self.report(node, "GM507", "Env.reward_range was removed in Gymnasium 1.0; define `reward_range` on this class or drop the read")
            return
        kind = self.receivers.kind_of(owner)
        decision = decide(kind, owner, self.context.profile)
        if decision.action is not Action.LEAVE or kind is EnvKind.GYM_ENV:
            self.report(
                node,
                "GM507",
                "reward_range was removed from Env and Wrapper in Gymnasium 1.0 (reads through a wrapper raise AttributeError); use `env.unwrapped.reward_range` if the env defines it",
            )


def _defines_reward_range(env: EnvClasses, classdef: ast.ClassDef) -> bool:
    for assign in env.index(classdef).assigns:
        for target in assign.targets:
            if (isinstance(target, ast.Name) and target.id == "reward_range") or is_self_attribute(target, ("reward_range",)):
                return True
    return False
