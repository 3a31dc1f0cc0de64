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
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, TypeVar

from gymmigrate.facts import names as N
from gymmigrate.facts.flow import Flow, contains, is_after
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import FUNCTIONS, call_argument, own_returns

if TYPE_CHECKING:
    from gymmigrate.facts.kinds import ReceiverFacade as _Facade
else:
    _Facade = object

# What ``_every_thunk_list`` asks of each list of thunks: a kind, or a Gym-only stack.
_Answer = TypeVar("_Answer")


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
        project = self.project
        return self._every_thunk_list(
            param, self.thunk_list_kind, (lambda qualname: project.thunk_kinds(qualname, param.arg)) if project is not None else None, EnvKind.UNKNOWN
        )

    def thunks_returned_stack(self, param: ast.arg) -> str | None:
        """``env_fns`` as ``thunks_returned_kind`` reads it: the Gym-only library stack (GM107)
        every thunk that every call passes makes an env of (``thunk_list_stack``), in this
        module and in the others of the run (``ProjectView.thunk_stacks``); None otherwise."""
        project = self.project
        return self.facts.memo(
            ("thunks-returned-stack", id(param)),
            lambda: self._every_thunk_list(
                param, self.thunk_list_stack, (lambda qualname: project.thunk_stacks(qualname, param.arg)) if project is not None else None, None
            ),
            while_computing=None,
        )

    def _every_thunk_list(
        self,
        param: ast.arg,
        answer: Callable[[ast.expr | None], _Answer],
        elsewhere: Callable[[str], Sequence[_Answer]] | None,
        unknown: _Answer,
    ) -> _Answer:
        """The one ``answer`` every list of thunks passed for ``param`` gives: the lists this
        module's calls (constructions, for ``__init__``) pass, and ``elsewhere``'s answers for
        the calls of other modules of the run. ``unknown`` where they differ or a call is
        not followed."""
        function = self.facts.parent(self.facts.parent(param))
        if not isinstance(function, FUNCTIONS):
            return unknown
        classdef = self.facts.parent(function)
        is_method = isinstance(classdef, ast.ClassDef) and self.facts.is_method(function)
        params = [*function.args.posonlyargs, *function.args.args]
        position = next((i for i, p in enumerate(params) if p is param), None)
        if position is not None and is_method:
            if position == 0:
                return unknown
            position -= 1
        qualname = f"{classdef.name}.{function.name}" if is_method else function.name  # type: ignore[union-attr]
        external = self.callables.external_param_kinds(function, classdef if is_method else None, param.arg)  # type: ignore[arg-type]
        answers: list[_Answer] = []
        if external:
            # Other modules of the run pass it too: each such call's list of thunks, as the
            # caller's module follows it (``CallSummary.thunks``); one it cannot follow, or
            # fewer followed than passed, leaves the items unknown.
            assert elsewhere is not None
            followed = elsewhere(qualname)
            if len(followed) != len(external) or unknown in followed:
                return unknown
            answers += followed
        if self.project is not None and (self.project.handed_on(qualname) or (is_method and self.project.handed_on(classdef.name))):  # type: ignore[union-attr]
            return unknown  # read as a value in another module: called with arguments no summary shows
        if is_method and function.name == "__init__":
            constructions, elsewhere_built = self.constructions(classdef)  # type: ignore[arg-type]
            if elsewhere_built or (not external and self.project is not None and self.project.built_elsewhere(classdef.name)):  # type: ignore[union-attr]
                return unknown
            calls, shifts = [c for c, _ in constructions], {id(c): shift for c, shift in constructions}
        else:
            calls, shifts = self.call_sites(function, classdef if is_method else None), {}  # type: ignore[arg-type]
        if not calls and not answers:
            return unknown
        for call in calls:
            answers.append(answer(call_argument(call, None if position is None else position + shifts.get(id(call), 0), param.arg)))
        found = set(answers)
        return found.pop() if len(found) == 1 else unknown

    def thunk_list_kind(self, argument: ast.expr | None) -> EnvKind:
        """What calling every item of ``argument``, a list of thunks this module defines
        (``_passed_thunks``), returns, when they all return the same kind and none an
        instance of a class whose step keeps the four-field contract; unknown otherwise.
        Also what a module tells the run of the thunks it passes to another's def
        (``CallSummary.thunks``)."""
        thunks = self._passed_thunks(argument)
        if thunks is None:
            return EnvKind.UNKNOWN
        returned: list[ast.expr | EnvKind] = []
        for thunk in thunks:
            values = self._thunk_returns(thunk, 0)
            if values is None:
                return EnvKind.UNKNOWN
            returned += values
        if not returned or any(not isinstance(value, EnvKind) and self.legacy_step_class(value) is not None for value in returned):
            return EnvKind.UNKNOWN
        kinds = {value if isinstance(value, EnvKind) else self.kind_of(value) for value in returned}
        return kinds.pop() if len(kinds) == 1 else EnvKind.UNKNOWN

    def thunk_list_stack(self, argument: ast.expr | None) -> str | None:
        """The Gym-only library stack (GM107) that every item of ``argument``, a list of thunks
        this module defines (``_passed_thunks``), makes an env of when called
        (``gym_only_stack`` of what each returns: ``lambda: make_particles(name)``); None
        when one is not shown to. Also what a module tells the run of the thunks it passes to
        another's def (``CallSummary.thunk_stacks``)."""
        thunks = self._passed_thunks(argument)
        if thunks is None:
            return None
        stacks: set[str | None] = set()
        for thunk in thunks:
            values = self._thunk_returns(thunk, 0)
            if not values:
                return None
            stacks.update(None if isinstance(value, EnvKind) else self.gym_only_stack(value) for value in values)
        return stacks.pop() if len(stacks) == 1 else None

    def thunk_list_maker(self, argument: ast.expr | None) -> str | None:
        """The qualified name of the one imported callable that makes every env the items of
        ``argument``, a list of thunks, return: ``lambda: make_env(name)``, or a closure's
        ``env = make_env(name)`` then ``return env``, with ``make_env`` imported. What that
        callable makes is its module's to say. None otherwise."""
        thunks = self._passed_thunks(argument)
        if thunks is None:
            return None
        names: set[str] = set()
        for thunk in thunks:
            values = self._thunk_returns(thunk, 0)
            if not values:
                return None
            for value in values:
                made = self._made_by_calls(value)
                if made is None:
                    return None
                for call in made:
                    qualified = self.qualified_names(call.func)
                    if len(qualified) != 1 or self._thunk_factory_def(call.func) is not None or self.local_class(call.func) is not None:
                        return None
                    names |= qualified
        return names.pop() if len(names) == 1 else None

    def _made_by_calls(self, value: ast.expr | EnvKind) -> list[ast.Call] | None:
        """The calls that make what a thunk returns: the call itself, or for ``return env``
        the call every assignment of ``env`` that reaches the return is; None otherwise."""
        if isinstance(value, ast.Call):
            return [value]
        if not isinstance(value, ast.Name):
            return None
        reaching = _returned_bindings(self.facts, value)
        if not reaching:
            return None
        calls = [self.facts.parent(binding).value for binding in reaching]  # type: ignore[union-attr]
        return calls if all(isinstance(call, ast.Call) for call in calls) else None

    def _mixed_thunks(self, expr: ast.AST) -> str | None:
        """``self.envs[i]`` (or ``env`` in ``for env in self.envs``) with ``self.envs = [fn()
        for fn in env_fns]``, where the thunks this module's constructions pass return a Gym
        env on some paths and something not shown to be one on others (a library's own
        wrapper around it): which, and where. None when that is not the reason."""
        if isinstance(expr, ast.Subscript):
            expr = expr.value
        if isinstance(expr, ast.Name):
            bindings = self.facts.bindings_of(expr)
            loop = self.facts.parent(bindings[0]) if len(bindings) == 1 else None
            if not (isinstance(loop, (ast.For, ast.comprehension)) and loop.target is bindings[0]):
                return None
            expr = loop.iter
        if not (isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and self.is_self(expr.value)):
            return None
        stored = self.self_attribute_values(expr, expr.attr)
        if len(stored) != 1 or not isinstance(stored[0], ast.ListComp) or len(stored[0].generators) != 1:
            return None
        comp = stored[0]
        made, loop_ = comp.elt, comp.generators[0]
        if not (isinstance(made, ast.Call) and not made.args and not made.keywords and isinstance(made.func, ast.Name)):
            return None
        if not (isinstance(loop_.target, ast.Name) and loop_.target.id == made.func.id and isinstance(loop_.iter, ast.Name)):
            return None
        params = self.facts.bindings_of(loop_.iter)
        if len(params) != 1 or not isinstance(params[0], ast.arg):
            return None
        return self.facts.memo(("mixed-thunks", id(params[0])), lambda: self._thunk_mix(params[0]))

    def _thunk_mix(self, param: ast.arg) -> str | None:
        function = self.facts.parent(self.facts.parent(param))
        classdef = self.facts.parent(function)
        if not (isinstance(function, FUNCTIONS) and function.name == "__init__" and isinstance(classdef, ast.ClassDef)):
            return None
        params = [*function.args.posonlyargs, *function.args.args]
        if param not in params[1:]:
            return None
        position = params.index(param) - 1
        constructions, _ = self.constructions(classdef)
        gym: list[ast.expr] = []
        other: list[ast.expr] = []
        for call, shift in constructions:
            for thunk in self._passed_thunks(call_argument(call, position + shift, param.arg)) or []:
                for value in self._thunk_returns(thunk, 0) or []:
                    if isinstance(value, EnvKind):
                        continue
                    # ``return env``: each binding of it that reaches the return
                    reaching = _returned_bindings(self.facts, value) if isinstance(value, ast.Name) else None
                    for made in [self.facts.parent(b).value for b in reaching] if reaching else [value]:  # type: ignore[union-attr]
                        kind = self.kind_of(made)
                        if kind.is_gym:
                            gym.append(made)
                        elif kind is not EnvKind.UNKNOWN or isinstance(made, ast.Call):
                            # another kind, or a call the run cannot classify (a library's
                            # wrapper); a name passed through (``lambda: env``) says nothing
                            other.append(made)
        if not gym or not other:
            return None
        return (
            f"the thunks its constructions pass return a Gym env on some paths (`{self.facts.segment(gym[0])}`, line "
            f"{gym[0].lineno}) and on others something not shown to be one (`{self.facts.segment(other[0])}`, line "
            f"{other[0].lineno}), so no one API serves both"
        )

    def factory_thunk_kind(self, function: ast.FunctionDef | ast.AsyncFunctionDef, item: tuple[int, int | None] | None = None) -> EnvKind:
        """What calling the thunk a def returns on every path returns (``make_env(i)``
        returning a nested def around ``gym.make``), or with ``item`` (index, size: None for
        any) the thunk every return holds at that index of a tuple (``return create, name``):
        one kind, else unknown."""
        values = self._def_returns(function) if item is None else self.returned_items(function, *item)
        if values is None or any(isinstance(v, EnvKind) for v in values):
            return EnvKind.UNKNOWN
        returned: list[ast.expr | EnvKind] = []
        for value in values:
            inner = self._thunk_returns(value, 1)  # type: ignore[arg-type]
            if inner is None:
                return EnvKind.UNKNOWN
            returned += inner
        if not returned or any(not isinstance(value, EnvKind) and self.legacy_step_class(value) is not None for value in returned):
            return EnvKind.UNKNOWN
        kinds = {value if isinstance(value, EnvKind) else self.kind_of(value) for value in returned}
        return kinds.pop() if len(kinds) == 1 else EnvKind.UNKNOWN

    def returned_items(self, function: ast.FunctionDef | ast.AsyncFunctionDef, index: int, size: int | None) -> list[ast.expr] | None:
        """The ``index``-th item of what ``function`` returns on every path, when every return
        is a tuple display of ``size`` items (of one size, when None) without a starred
        item; None otherwise."""
        values = self._def_returns(function)
        if values is None or not all(isinstance(v, ast.Tuple) and not any(isinstance(e, ast.Starred) for e in v.elts) for v in values):
            return None
        sizes = {len(v.elts) for v in values}  # type: ignore[union-attr]
        if len(sizes) != 1 or (size is not None and sizes != {size}) or not 0 <= index < sizes.pop():
            return None
        return [v.elts[index] for v in values]  # type: ignore[union-attr]

    def thunk_item(self, function: ast.FunctionDef | ast.AsyncFunctionDef) -> tuple[int, int] | None:
        """(index, size) of the one item that every return of ``function``, a tuple of one
        size, holds a thunk the def defines at (``return create_env, env_name`` with
        ``create_env`` a nested def or a lambda); None when there is no such one item."""
        values = self._def_returns(function)
        if not values or not isinstance(values[0], ast.Tuple):
            return None
        size = len(values[0].elts)
        found = [
            index
            for index in range(size)
            if (items := self.returned_items(function, index, size)) is not None and all(self._defined_thunk(item, function) for item in items)
        ]
        return (found[0], size) if len(found) == 1 else None

    def _defined_thunk(self, item: ast.expr, function: ast.AST) -> bool:
        """``item`` is a lambda, or a name every binding of which is a def nested in ``function``."""
        if isinstance(item, ast.Lambda):
            return True
        bindings = self.facts.bindings_of(item) if isinstance(item, ast.Name) else []
        return bool(bindings) and all(isinstance(b, FUNCTIONS) and self.facts.parent(b) is not self.facts.tree and function in self.facts.ancestors(b) for b in bindings)

    def thunk_returns(self, thunk: ast.expr) -> list[ast.expr | EnvKind] | None:
        """What calling ``thunk`` returns (``_thunk_returns``), for the summaries."""
        return self._thunk_returns(thunk, 1)

    def factory_thunk_refs(self, function: ast.FunctionDef | ast.AsyncFunctionDef) -> frozenset[str] | None:
        """The names of other modules of the run that the thunks a def returns call on every
        path (``def creator(_): return Orchard(n)`` with ``Orchard`` imported), when that is
        all they return and this module cannot tell their kind; None otherwise. The join
        gives the def what those calls give (``ModuleSummary.thunk_factory_refs``)."""
        values = self._def_returns(function)
        if values is None or any(isinstance(v, EnvKind) for v in values):
            return None
        names: set[str] = set()
        for value in values:
            returned = self._thunk_returns(value, 1)  # type: ignore[arg-type]
            if not returned:
                return None
            # ``env = Wrapper(env)`` then ``return env``: the last calls that make the name
            # say what the thunk returns, as a call returned directly does
            calls = [self._made_by_calls(made) for made in returned]
            if any(found is None for found in calls):
                return None
            for made in (call for found in calls for call in found or ()):
                if not isinstance(made.func, (ast.Name, ast.Attribute)):
                    return None
                if self.kind_of(made) is not EnvKind.UNKNOWN:
                    return None  # this module knows what it makes (``factory_thunk_kind`` says it)
                qualified = self.qualified_names(made.func)
                name = next(iter(qualified)) if len(qualified) == 1 else ""
                if "." not in name or N.is_library(name):
                    return None  # a name of this module, or a library's
                names.add(name)
        return frozenset(names) or None

    def own_thunk_factory(self, argument: ast.expr) -> str | None:
        """The name of the one top-level def of this module whose calls are every item of a
        list of thunks (``[make_env(i) for i in range(n)]``), when its thunks return calls of
        names of other modules of the run (``factory_thunk_refs``): what they return is the
        join's to say (``ProjectFacts.thunk_factories``). None otherwise."""
        thunks = self._passed_thunks(argument)
        if not thunks or not all(isinstance(t, ast.Call) for t in thunks):
            return None
        functions = [self.local_function(t.func) for t in thunks]  # type: ignore[attr-defined]
        function = functions[0]
        if function is None or any(f is not function for f in functions):
            return None
        if self.facts.parent(function) is not self.facts.tree or self.factory_thunk_refs(function) is None:
            return None
        return function.name

    def called_factory_kind(self, factory_call: ast.Call) -> EnvKind:
        """``get_creator(name)(config)``: what calling the thunk that ``factory_call`` returns
        gives, for a def of this module (``factory_thunk_kind``) or of another module of the
        run (``ModuleSummary.thunk_factories``). Unknown for anything else."""
        function = self.local_function(factory_call.func)
        if function is not None:
            return self.facts.memo(("factory-thunk-kind", id(function)), lambda: self.factory_thunk_kind(function), while_computing=EnvKind.UNKNOWN)
        if self.project is None:
            return EnvKind.UNKNOWN
        kinds = {self.project.thunk_factory_kind(q) for q in self.qualified_names(factory_call.func)}
        found = kinds.pop() if len(kinds) == 1 else None
        return found if found is not None else EnvKind.UNKNOWN

    def called_item_kind(self, factory_call: ast.Call, index: int, size: int | None) -> EnvKind:
        """``create, _ = make_creator(params)`` then ``create()`` (``size`` 2), or
        ``make_creator(params)[0]()`` (``size`` None): what calling the thunk the ``index``-th
        item of what ``factory_call`` returns gives, for a def of this module
        (``factory_thunk_kind``) or of another module of the run
        (``ModuleSummary.thunk_items``). Unknown for anything else."""
        function = self.local_function(factory_call.func)
        if function is not None:
            return self.facts.memo(
                (f"factory-item-kind {index} {size}", id(function)),
                lambda: self.factory_thunk_kind(function, (index, size)),
                while_computing=EnvKind.UNKNOWN,
            )
        if self.project is None:
            return EnvKind.UNKNOWN
        kinds = {self.project.thunk_item_kind(q, index, size) for q in self.qualified_names(factory_call.func)}
        found = kinds.pop() if len(kinds) == 1 else None
        return found if found is not None else EnvKind.UNKNOWN

    def imported_thunk_factory(self, argument: ast.expr) -> str | None:
        """The qualified name of the one def imported from another module whose calls are
        every item of a list of thunks (``[make_env(i) for i in range(n)]`` with ``make_env``
        imported): what the items return is that module's to say. None otherwise."""
        thunks = self._passed_thunks(argument)
        if not thunks or not all(isinstance(t, ast.Call) and self.local_function(t.func) is None for t in thunks):
            return None
        names = {frozenset(self.qualified_names(t.func)) for t in thunks}  # type: ignore[attr-defined]
        if len(names) != 1:
            return None
        found = names.pop()
        return next(iter(found)) if len(found) == 1 else None

    def is_thunk_list(self, argument: ast.expr) -> bool:
        """``argument`` is a list of callables as ``thunk_list_kind`` reads one."""
        return self._passed_thunks(argument) is not None

    def _passed_thunks(self, argument: ast.expr | None) -> list[ast.expr] | None:
        """The items of a list passed as a sequence of thunks: a display, a comprehension's
        item, or a name bound once to either, or whose one assignment that reaches the call
        is (``envs = [make_env(i) ...]`` then ``envs = SubprocVecEnv(envs)``). None for
        anything else."""
        if isinstance(argument, ast.Name):
            values = self.facts.assigned_values(argument, sole_target=True)
            if not values or len(values) != 1:
                values = self._reaching_value(argument)
            if not values or len(values) != 1:
                return None
            argument = values[0]
        if isinstance(argument, (ast.List, ast.Tuple)) and argument.elts and not any(isinstance(e, ast.Starred) for e in argument.elts):
            return list(argument.elts)
        if isinstance(argument, (ast.ListComp, ast.GeneratorExp)):
            return [argument.elt]
        return None

    def _reaching_value(self, read: ast.Name) -> list[ast.expr] | None:
        """The value of the one plain assignment of ``read`` that reaches it (``Flow.reaching``,
        less those in the other branch of an ``if`` the read sits in: ``if n > 1: envs =
        Subproc(envs)`` / ``else: envs = Dummy(envs)``), or None."""
        reaching = [b for b in Flow.of(self.facts).reaching(read) or [] if not self._other_branch(b, read)]
        if len(reaching) != 1:
            return None
        statement = self.facts.parent(reaching[0])
        return [statement.value] if isinstance(statement, ast.Assign) and statement.targets == [reaching[0]] else None

    def _other_branch(self, binding: ast.AST, read: ast.AST) -> bool:
        """``binding`` and ``read`` sit in the two branches of one ``if``: one never sees the other."""
        for node in self.facts.ancestors(binding):
            if isinstance(node, ast.If) and contains(node, read):
                body, orelse = node.body, node.orelse
                return (_within(body, binding) and _within(orelse, read)) or (_within(orelse, binding) and _within(body, read))
        return False

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
            if len(bindings) > 1 and all(isinstance(b, FUNCTIONS) for b in bindings):
                # ``if name == "a": def creator(): ...`` / ``else: def creator(): ...`` then
                # ``return creator``: what every def of that name returns (one kind is asked of them)
                every: list[ast.expr | EnvKind] = []
                for binding in bindings:
                    returned = self._def_returns(binding)  # type: ignore[arg-type]
                    if returned is None:
                        return None
                    every += returned
                return every
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
            function = self._thunk_factory_def(thunk.func)
            if function is None:
                # ``make_env(i)`` imported from another module of the run: the kind its
                # thunks return there (``ModuleSummary.thunk_factories``)
                kinds = {self.project.thunk_factory_kind(q) for q in self.qualified_names(thunk.func)} if self.project is not None else set()
                return [kinds.pop()] if len(kinds) == 1 and None not in kinds else None  # type: ignore[list-item]
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

    def _thunk_factory_def(self, func: ast.expr) -> ast.FunctionDef | ast.AsyncFunctionDef | None:
        """The def a call of ``func`` runs: one of the module (``local_function``), or the one
        def a name is bound to in the scope of the call (``def get_env_fn(rank)`` nested in
        the function that builds the vec env)."""
        function = self.local_function(func)
        if function is not None or not isinstance(func, ast.Name):
            return function
        bindings = self.facts.bindings_of(func)
        return bindings[0] if len(bindings) == 1 and isinstance(bindings[0], FUNCTIONS) else None

    @staticmethod
    def _def_returns(function: ast.FunctionDef | ast.AsyncFunctionDef) -> list[ast.expr | EnvKind] | None:
        values = [r.value for r in own_returns(function)]
        if not values or any(v is None for v in values):
            return None
        return values  # type: ignore[return-value]


def _within(statements: list[ast.stmt], node: ast.AST) -> bool:
    return any(contains(statement, node) for statement in statements)


def _returned_bindings(facts, read: ast.Name) -> list[ast.AST] | None:
    """The assignments of ``read`` (``return env``) that may reach it: ``Flow.reaching``,
    less those inside a branch that a later assignment of an enclosing block overwrites
    (``if dm: env = dm.make(...)`` then ``env = Wrapper(env)``). None when one is no plain
    single-target assignment."""
    flow = Flow.of(facts)
    reaching = flow.reaching(read)
    if not reaching:
        return None
    found = []
    for binding in reaching:
        parent = facts.parent(binding) if isinstance(binding, ast.Name) else None
        if not (isinstance(parent, ast.Assign) and parent.targets == [binding]):
            return None
        statement: ast.AST | None = parent
        overwritten = False
        while isinstance(statement, ast.stmt) and not isinstance(statement, (*FUNCTIONS, ast.ClassDef)):
            if is_after(read, statement) and flow._overwritten(statement, read):
                overwritten = True
                break
            statement = facts.parent(statement)
        if not overwritten:
            found.append(binding)
    return found
