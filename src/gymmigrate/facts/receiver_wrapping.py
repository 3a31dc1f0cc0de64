"""Which calls hand on the env they are given (``WrappingCalls``, mixed into
``Receivers``): a Gym wrapper class (Gymnasium's, this module's or another module's of the
run), a def of the run that returns its first argument or Gym wrappers around it
(``wrap_deepmind(env)``), an adapter deriving from a library with its own env API.

Separate from ``receivers.py`` because it decides from a callee's definition, not from
the expression being classified: ``Receivers`` asks it what a call returns, and
``BindingKinds`` whether ``env = wrap(env)`` rebinds a name to the same env. Second of
``Receivers``' bases, so its methods resolve as they did when ``Receivers`` defined them.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

from gymmigrate.facts import names as N
from gymmigrate.facts.kinds import MAX_DEPTH
from gymmigrate.facts.module import FUNCTIONS, own_returns

if TYPE_CHECKING:
    from gymmigrate.facts.kinds import ReceiverFacade as _Facade
else:
    _Facade = object


class WrappingCalls(_Facade):
    """The calls that return the env they are given (part of ``Receivers``)."""

    def _makes_own_api_env(self, value: ast.expr) -> bool:
        """``Adapter(env)`` with a class of this module or another of the run that derives from
        a library class with an env API of its own (``dm_env.Environment``): an env of that API whatever ``env`` was."""
        if not isinstance(value, ast.Call):
            return False
        local = self.local_class(value.func)
        if local is not None:
            return self.derives_own_api(local)
        # ``gym_wrapper.GymAdapter(env)`` with the class in another module of the run
        project = self.project
        return project is not None and any(project.derives_own_api(q) for q in self.qualified_names(value.func))

    def _makes_gym_wrapper(self, value: ast.expr) -> bool:
        """``Wrapper(env, ...)`` with a Gym wrapper class (Gymnasium's, this module's, or
        another module's of the run): a Gym env whatever ``env`` was."""
        return isinstance(value, ast.Call) and self.names_gym_wrapper_class(value.func)

    def names_gym_wrapper_class(self, func: ast.expr) -> bool:
        """``func`` names a Gym wrapper class (Gymnasium's, an env library's, this module's
        or another module's of the run)."""
        for q in self.qualified_names(func):
            rest = N.strip_gym_prefix(q)
            if rest is not None and (rest in N.GYM_WRAPPER_BASE_CLASSES or N.is_wrapper_class_path(rest)):
                return True
            if self.project is not None and self.project.is_wrapper_class(q):
                return True
        if isinstance(func, ast.Name) and self.project is not None and not self.facts.bindings_of(func):
            return self.project.star_wrapper_class(func.id, self.facts.star_imports)
        if self.library_wrapper_class(func):
            return True
        local = self.local_class(func)
        return local is not None and self.is_gym_wrapper_class(local)

    def library_wrapper_class(self, func: ast.expr) -> bool:
        """``func`` names a Gym wrapper class of an env library (``N.GYM_LIBRARY_WRAPPERS``:
        ``ImgObsWrapper`` of gym_minigrid), imported by name or through a star import of its
        module where the file binds the name nowhere else."""
        names = self.qualified_names(func)
        if isinstance(func, ast.Name) and not self.facts.bindings_of(func):
            names = names | {f"{module}.{func.id}" for module in self.facts.star_imports}
        for qualified in names:
            module, _, name = qualified.rpartition(".")
            if name in N.GYM_LIBRARY_WRAPPERS.get(module, ()):
                return True
        return False

    def wrapped_argument(self, value: ast.AST) -> ast.expr | None:
        """The env ``value`` hands on: its first argument, where it calls a def of the run
        that returns that argument or Gym wrappers around it (``def wrap_deepmind(env):
        if clip: env = ClipReward(env); return env``; ``ProjectView.wraps_argument``)."""
        if not isinstance(value, ast.Call) or (value.args and isinstance(value.args[0], ast.Starred)):
            return None
        parameter: str | None = None
        local = self.local_function(value.func)
        if local is not None:
            parameter = self.wrapped_parameter(local) if self.wraps_argument(local) else None
        elif self.project is not None:
            parameter = next(
                (p for q in self.qualified_names(value.func) if (p := self.project.wrapped_parameter(q)) is not None), None
            )
        if parameter is None:
            return None
        if value.args:
            return value.args[0]
        # ``wrap_deepmind(env=make_atari(id), ...)``: the same argument, passed by its name
        return next((k.value for k in value.keywords if k.arg == parameter), None)

    @staticmethod
    def wrapped_parameter(function: ast.FunctionDef | ast.AsyncFunctionDef) -> str:
        """The name of the first parameter, the one a def that ``wraps_argument`` hands on."""
        return [*function.args.posonlyargs, *function.args.args][0].arg

    def wraps_argument(self, function: ast.AST) -> bool:
        """Every return of the top-level def ``function`` is its first parameter, maybe
        rebound to Gym wrappers around it (or to what another such def of the module gives)."""
        return bool(self.facts.memo(("wraps-argument", id(function)), lambda: self._wraps_argument(function), while_computing=False))

    def _wraps_argument(self, function: ast.AST) -> bool:
        if not isinstance(function, FUNCTIONS) or self.facts.parent(function) is not self.facts.tree:
            return False
        positional = [*function.args.posonlyargs, *function.args.args]
        if not positional:
            return False
        values = [r.value for r in own_returns(function)]
        answers: dict[tuple[int, frozenset[int]], _HandedOn] = {}
        return bool(values) and all(v is not None and self._hands_on_param(v, positional[0], function, 0, frozenset(), answers, _Walk()) for v in values)

    def _hands_on_param(
        self,
        value: ast.expr,
        param: ast.arg,
        function: ast.AST,
        depth: int,
        seen: frozenset[int],
        answers: dict[tuple[int, frozenset[int]], _HandedOn],
        walk: _Walk,
    ) -> bool:
        walk.deepest = max(walk.deepest, depth)
        if depth > MAX_DEPTH:
            walk.cut = True
            return False
        if isinstance(value, ast.Call):
            if value.args and isinstance(value.args[0], ast.Starred):
                return False
            if not value.args:
                # ``PermuteFrame(env=env, ...)``: gym.Wrapper names the env it wraps ``env``
                inner = next((k.value for k in value.keywords if k.arg == "env"), None)
                return inner is not None and self._makes_gym_wrapper(value) and self._hands_on_param(inner, param, function, depth + 1, seen, answers, walk)
            local = self.local_function(value.func)
            hands_on = self._makes_gym_wrapper(value) or (local is not None and local is not function and self.wraps_argument(local))
            return hands_on and self._hands_on_param(value.args[0], param, function, depth + 1, seen, answers, walk)
        if not (isinstance(value, ast.Name) and value.id == param.arg):
            return False
        for binding in self.facts.bindings_of(value):
            if binding is param:
                continue
            assign = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
            if not (isinstance(assign, ast.Assign) and assign.targets == [binding]):
                return False
            if self.facts.enclosing_function(assign) is not function:
                return False
            if id(assign) in seen:
                continue  # ``env = Clip(env)`` read back through itself: no other value
            if not self._assigned_hands_on(assign, param, function, depth + 1, seen | {id(assign)}, answers, walk):
                return False
        return True

    def _assigned_hands_on(
        self,
        assign: ast.Assign,
        param: ast.arg,
        function: ast.AST,
        depth: int,
        seen: frozenset[int],
        answers: dict[tuple[int, frozenset[int]], _HandedOn],
        walk: _Walk,
    ) -> bool:
        """``_hands_on_param`` of one rebinding's value. Every read of the parameter's name
        reads all its bindings in the def (``env = A(env)`` ten times over), each walked with
        the bindings already on the path left out: every order of them, 10! walks (``wrap_deepmind``:
        minutes). The walk from a rebinding depends on that set, not on the order it was
        built in, so its answer is kept per (rebinding, set) and the walks follow the sets;
        one the depth bound cut short is walked again, as before (and reused only where
        the bound is as far away)."""
        key = (id(assign), seen)
        known = answers.get(key)
        if known is not None and depth + known.height <= MAX_DEPTH:
            walk.deepest = max(walk.deepest, depth + known.height)
            return known.answer
        inner = _Walk()
        answer = self._hands_on_param(assign.value, param, function, depth, seen, answers, inner)
        if not inner.cut:
            answers[key] = _HandedOn(answer, inner.deepest - depth)
        walk.cut = walk.cut or inner.cut
        walk.deepest = max(walk.deepest, inner.deepest)
        return answer


@dataclass
class _Walk:
    """What one walk of ``_hands_on_param`` met: whether the depth bound cut it short, and
    how deep it went."""

    cut: bool = False
    deepest: int = 0


class _HandedOn(NamedTuple):
    """A rebinding's answer, from a walk the depth bound did not cut short."""

    answer: bool
    height: int  # how far below the rebinding the walk went
