"""The wrapper class family: finds the Gym wrapper subclasses and hands their
``__init__`` (GM603), ``step`` (GM602) and ``reset`` (GM601) to their rules."""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.module import FUNCTIONS
from gymmigrate.rules.base import FileContext
from gymmigrate.rules.wrappers.common import RULES
from gymmigrate.rules.wrappers.reset import ResetOverrides
from gymmigrate.rules.wrappers.step import StepOverrides


class WrapperClasses(StepOverrides, ResetOverrides):
    RULES = RULES
    after = ("ResetSeed", "StepDone")

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        return "Wrapper" in facts.text or "wrappers" in facts.text

    def decide(self) -> None:
        for classdef in self.facts.all_classes:
            if not self.receivers.is_gym_wrapper_class(classdef):
                continue
            for statement in classdef.body:
                if not isinstance(statement, FUNCTIONS):
                    continue
                if statement.name == "__init__":
                    self._check_init(classdef, statement)
                elif statement.name == "step":
                    self._fix_step(statement)
                elif statement.name == "reset":
                    self._fix_reset(classdef, statement)

    # -- GM603 ------------------------------------------------------------------------------

    def _check_init(self, classdef: ast.ClassDef, init: ast.FunctionDef | ast.AsyncFunctionDef) -> None:
        if not any(_is_super_init(node) for node in ast.walk(init)):
            self.report(
                init,
                "GM603",
                f"`{classdef.name}.__init__` never calls `super().__init__(env)`: gymnasium.Wrapper "
                "needs it to set `env` and the action/observation space and metadata properties; call it "
                "instead of setting `self.env` by hand",
            )


def _is_super_init(node: ast.AST) -> bool:
    """``super().__init__(...)``, ``super(Cls, self).__init__(...)`` or ``Base.__init__(self, ...)``."""
    if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "__init__"):
        return False
    owner = node.func.value
    if isinstance(owner, ast.Call) and isinstance(owner.func, ast.Name) and owner.func.id == "super":
        return True
    if isinstance(owner, (ast.Name, ast.Attribute)) and node.args:
        first = node.args[0]
        return isinstance(first, ast.Name) and first.id == "self"
    return False
