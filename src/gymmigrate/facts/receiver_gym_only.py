"""Which Gym-only library stack (GM107: ``nes_py`` for ``gym_super_mario_bros``) makes
every value an expression may hold, followed through the run's own wrappers, factories
and lists of such envs (``gym_only_stack``, ``returns_gym_only_stack``).

Separate from ``receiver_origins.py`` because it answers a question of the porting
decision, not of the rewrite: such an env keeps gym's API until its stack is ported, so
its resets and steps are that decision's. ``GymOnlyStacks``, a base of ``MadeObjects``,
mixed into ``Receivers``.
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.facts import names as N
from gymmigrate.facts.kinds import MAX_DEPTH
from gymmigrate.facts.module import own_returns

if TYPE_CHECKING:
    from gymmigrate.facts.kinds import ReceiverFacade as _Facade
else:
    _Facade = object


class GymOnlyStacks(_Facade):
    """The Gym-only stack an expression's envs come from (part of ``Receivers``)."""

    def gym_only_stack(self, expr: ast.AST) -> str | None:
        """The Gym-only library stack (GM107: ``nes_py`` for ``gym_super_mario_bros``) that
        makes every value ``expr`` may hold, followed through the run's own code: its
        wrapper classes around that library's env (``wraps_gym_only``), its factories
        (``def make_env(): ...; return Skip(JoypadSpace(env))``, here or in another module of
        the run), its lists of such envs (``self.envs[i]``). Such an env keeps gym's API
        until that stack is ported, so its resets and steps are that decision's, or None."""
        return self.facts.memo(("gym-only-stack", id(expr)), lambda: self._gym_only_stack(expr), while_computing=None)

    def _gym_only_stack(self, expr: ast.AST) -> str | None:
        if self.depth > MAX_DEPTH:
            return None
        self.depth += 1
        try:
            return self._agreed(self._stack_values(expr))
        finally:
            self.depth -= 1

    @staticmethod
    def _agreed(stacks: list[str | None]) -> str | None:
        found = set(stacks)
        return found.pop() if len(found) == 1 and None not in found else None

    def _stack_values(self, expr: ast.AST) -> list[str | None]:
        """One answer per value ``expr`` may hold (None: not shown to be the stack's)."""
        if isinstance(expr, ast.Call):
            return [self._call_stack(expr)]
        if isinstance(expr, ast.Name):
            answers: list[str | None] = []
            for binding in self.facts.bindings_of(expr):
                parent = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
                if isinstance(parent, ast.Assign) and binding in parent.targets:
                    answers.append(self.gym_only_stack(parent.value))
                elif isinstance(parent, (ast.For, ast.AsyncFor, ast.comprehension)) and parent.target is binding:
                    answers.append(self.gym_only_stack(parent.iter))  # an item of a list of them
                elif (zipped := self.callables.loop_container(binding)) is not None:
                    answers.append(self.gym_only_stack(zipped))  # ``for a, env in zip(actions, self.envs)``
                else:
                    return [None]  # a parameter, an import, an unpacking: not known here
            return answers or [None]
        if isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and self.is_self(expr.value):
            values = self.self_attribute_values(expr, expr.attr)
            return [self.gym_only_stack(v) for v in values] or [None]
        if isinstance(expr, ast.Subscript):
            return [self.gym_only_stack(expr.value)]  # ``self.envs[i]``: one of the list
        if isinstance(expr, (ast.List, ast.Tuple)) and expr.elts:
            return [self.gym_only_stack(el) for el in expr.elts]
        if isinstance(expr, (ast.ListComp, ast.GeneratorExp)):
            return [self.gym_only_stack(expr.elt)]
        return [None]

    def returns_gym_only_stack(self, function: ast.AST) -> str | None:
        """The Gym-only stack every return of ``function`` comes from (``gym_only_stack``)."""
        returns = own_returns(function)
        if not returns or any(r.value is None for r in returns):
            return None
        return self._agreed([self.gym_only_stack(r.value) for r in returns if r.value is not None])

    def _called_thunk_stack(self, callee: ast.expr) -> str | None:
        """``fn()`` for ``fn`` an item of a list of env functions a parameter holds (``self.envs
        = [fn() for fn in env_fns]``), or ``env_fn_wrapper.x()`` in a worker a process is
        spawned on with ``Holder(env_fn)``: the stack every env function passed there makes
        an env of (``thunks_returned_stack``), or None."""
        if isinstance(callee, ast.Attribute):
            held = self.callables.held_values(callee)
            return self._agreed([self._called_thunk_stack(value) for value in held]) if held else None
        param = self.callables.thunk_list_param(callee)
        return self.thunks_returned_stack(param) if param is not None else None

    def _call_stack(self, call: ast.Call) -> str | None:
        classdef = self.local_class(call.func)
        if classdef is not None:
            made = self.wraps_gym_only(classdef)  # the run's wrapper around the library's env
            top = made.split(".", 1)[0] if made is not None else None
            return N.gym_only_stack(top) if top in N.GYM_ONLY_PACKAGES else None
        function = self.local_function(call.func)
        if function is not None:
            return self.returns_gym_only_stack(function)
        if not self.qualified_names(call.func):
            return self._called_thunk_stack(call.func)
        stacks: set[str | None] = set()
        for qualified in self.qualified_names(call.func):
            top = qualified.split(".", 1)[0]
            if top in N.GYM_ONLY_PACKAGES:
                stacks.add(N.gym_only_stack(top))
            elif self.project is not None:
                stacks.add(self.project.gym_only_maker(qualified))  # a factory of another module of the run
            else:
                stacks.add(None)
        return self._agreed(list(stacks))
