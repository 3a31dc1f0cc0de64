"""What calling an item of a sequence of thunks returns: ``def __init__(self, env_fns):
self.envs = [fn() for fn in env_fns]`` holds what the lambdas, defs, ``functools.partial``
objects or thunk factories (``[make_env(i) for i in range(n)]``) its callers pass return
(``thunks_returned_kind``).

Separate from ``receiver_params.py`` because it follows a parameter one call further:
not what the callers pass, but what the things they pass return when called, through
lambdas, defs and factories of the module. Part of ``Receivers`` (through
``ParameterKinds``).
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import FUNCTIONS, call_argument, own_returns

if TYPE_CHECKING:
    from gymmigrate.facts.kinds import ReceiverFacade as _Facade
else:
    _Facade = object


class ThunkKinds(_Facade):
    """What the thunks passed for a parameter return (part of ``Receivers``)."""

    def thunks_returned_kind(self, param: ast.arg) -> EnvKind:
        """``def __init__(self, env_fns): self.envs = [fn() for fn in env_fns]``: what calling
        an item of the sequence ``param`` holds returns, when every call of the def in this
        module (every construction, for ``__init__``) passes a list of thunks this module
        defines (a lambda, a def, ``functools.partial``, or a call of a def of the module
        returning one of those: ``[make_env(i) for i in range(n)]``) and every such thunk
        returns the same kind. A thunk returning an instance of a class whose step keeps the
        four-field contract, a call the module cannot follow, or callers in other modules:
        unknown (the calls are left alone)."""
        return self.facts.memo(("thunks-returned-kind", id(param)), lambda: self._thunks_returned_kind(param), while_computing=EnvKind.UNKNOWN)

    def _thunks_returned_kind(self, param: ast.arg) -> EnvKind:
        function = self.facts.parent(self.facts.parent(param))
        if not isinstance(function, FUNCTIONS):
            return EnvKind.UNKNOWN
        classdef = self.facts.parent(function)
        is_method = isinstance(classdef, ast.ClassDef) and self.facts.is_method(function)
        params = [*function.args.posonlyargs, *function.args.args]
        position = next((i for i, p in enumerate(params) if p is param), None)
        if position is not None and is_method:
            if position == 0:
                return EnvKind.UNKNOWN
            position -= 1
        if self.callables.external_param_kinds(function, classdef if is_method else None, param.arg):  # type: ignore[arg-type]
            return EnvKind.UNKNOWN  # other modules of the run pass thunks this one cannot see
        if is_method and function.name == "__init__":
            constructions, elsewhere = self.constructions(classdef)  # type: ignore[arg-type]
            if elsewhere or (self.project is not None and self.project.built_elsewhere(classdef.name)):  # type: ignore[union-attr]
                return EnvKind.UNKNOWN
            calls, shifts = [c for c, _ in constructions], {id(c): shift for c, shift in constructions}
        else:
            calls, shifts = self.call_sites(function, classdef if is_method else None), {}  # type: ignore[arg-type]
        if not calls:
            return EnvKind.UNKNOWN
        returned: list[ast.expr | EnvKind] = []
        for call in calls:
            argument = call_argument(call, None if position is None else position + shifts.get(id(call), 0), param.arg)
            thunks = self._passed_thunks(argument)
            if thunks is None:
                return EnvKind.UNKNOWN
            for thunk in thunks:
                values = self._thunk_returns(thunk, 0)
                if values is None:
                    return EnvKind.UNKNOWN
                returned += values
        if not returned or any(not isinstance(value, EnvKind) and self.legacy_step_class(value) is not None for value in returned):
            return EnvKind.UNKNOWN
        kinds = {value if isinstance(value, EnvKind) else self.kind_of(value) for value in returned}
        return kinds.pop() if len(kinds) == 1 else EnvKind.UNKNOWN

    def _passed_thunks(self, argument: ast.expr | None) -> list[ast.expr] | None:
        """The items of a list passed as a sequence of thunks: a display, a comprehension's
        item, or a name bound once to either. None for anything else."""
        if isinstance(argument, ast.Name):
            values = self.facts.assigned_values(argument, sole_target=True)
            if not values or len(values) != 1:
                return None
            argument = values[0]
        if isinstance(argument, (ast.List, ast.Tuple)) and argument.elts and not any(isinstance(e, ast.Starred) for e in argument.elts):
            return list(argument.elts)
        if isinstance(argument, (ast.ListComp, ast.GeneratorExp)):
            return [argument.elt]
        return None

    def _thunk_returns(self, thunk: ast.expr, depth: int) -> list[ast.expr | EnvKind] | None:
        """What calling ``thunk`` returns, as the expressions of this module that make it: a
        lambda's body, the returns of a def (a name bound to it), or, for a call of a def of
        the module that returns a thunk (``make_env(rank)``), what that thunk returns. None
        when a return cannot be followed; a library callable's kind stands for its call."""
        if depth > 3:
            return None
        if isinstance(thunk, ast.Lambda):
            return [thunk.body]
        if isinstance(thunk, ast.Name):
            bindings = self.facts.bindings_of(thunk)
            if len(bindings) != 1:
                return None
            binding = bindings[0]
            if isinstance(binding, FUNCTIONS):
                return self._def_returns(binding)
            if isinstance(binding, ast.Name):
                values = self.facts.assigned_values(thunk, sole_target=True)
                if values is not None and len(values) == 1:
                    return self._thunk_returns(values[0], depth + 1)
            return None
        if isinstance(thunk, ast.Call):
            if "functools.partial" in self.qualified_names(thunk.func):
                if not thunk.args:
                    return None
                inner = thunk.args[0]
                if self.local_class(inner) is not None:
                    return None  # ``partial(Board, size=3)``: the project's own class, left alone
                if self.qualified_names(inner):
                    # ``partial(gym.make, env_id)``: what the library callable returns
                    return [self.callables.returned_kind(thunk)]
                return self._thunk_returns(inner, depth + 1)
            function = self.local_function(thunk.func)
            if function is None:
                return None
            made = self._def_returns(function)
            if made is None:
                return None
            found: list[ast.expr | EnvKind] = []
            for value in made:
                if isinstance(value, EnvKind):
                    return None
                inner_values = self._thunk_returns(value, depth + 1)
                if inner_values is None:
                    return None
                found += inner_values
            return found
        return None

    @staticmethod
    def _def_returns(function: ast.FunctionDef | ast.AsyncFunctionDef) -> list[ast.expr | EnvKind] | None:
        values = [r.value for r in own_returns(function)]
        if not values or any(v is None for v in values):
            return None
        return values  # type: ignore[return-value]
