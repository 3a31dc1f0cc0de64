"""What a parameter of a def holds: its annotation, the arguments at every call site of
the module (constructions of a class through its subclasses too) and of the run
(``ProjectView.param_kinds``), or the pytest fixtures and parametrizations that feed a
test (``ParameterKinds``, mixed into ``Receivers``).
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.facts import names as N
from gymmigrate.facts.callables import optional_of, parse_annotation, string_names
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.import_roots import is_test_path
from gymmigrate.facts.kinds import EnvKind, join_kinds
from gymmigrate.facts.module import FUNCTIONS, call_argument, own_returns
from gymmigrate.facts.pytest_params import fixture_values, param_fixtures, param_values
from gymmigrate.facts.receiver_classes import is_object, other_library_class_kind

if TYPE_CHECKING:
    from gymmigrate.facts.kinds import ReceiverFacade as _Facade
else:
    _Facade = object


class ParameterKinds(_Facade):
    """The kinds of parameters (part of ``Receivers``)."""

    # parameters whose callers pass a Gym env and another kind of env: (gym kinds, others)
    _mixed_params: dict[ast.arg, tuple[list[str], list[str]]]
    _test_double_params: dict[ast.arg, list[str]]

    def _param_kind(self, param: ast.arg) -> EnvKind:
        if param.annotation is not None:
            kind = self.annotation_kind(param.annotation)
            if kind is not EnvKind.UNKNOWN:
                return kind
        function = self.facts.parent(self.facts.parent(param))  # arg -> arguments -> def
        if not isinstance(function, FUNCTIONS):
            return EnvKind.UNKNOWN
        params = [*function.args.posonlyargs, *function.args.args]
        name = param.arg
        classdef = self.facts.parent(function)
        is_method = isinstance(classdef, ast.ClassDef) and self.facts.is_method(function)
        if is_method and params and params[0] is param:
            return EnvKind.NOT_ENV  # self / cls
        if is_method and name == "env" and function.name == "__init__" and self.is_gym_wrapper_class(classdef):  # type: ignore[arg-type]
            if self.wraps_pz_parallel(classdef):  # type: ignore[arg-type]
                return EnvKind.PZ_PARALLEL
            return EnvKind.NOT_ENV if self.wraps_gym_only(classdef) is not None else EnvKind.GYM_ENV  # type: ignore[arg-type]
        checked = self._checked_multi_agent_kind(function, name)
        if checked is not None:
            return checked  # what the def itself proves outweighs what any caller is said to pass
        position = next((i for i, p in enumerate(params) if p is param), None)
        if position is not None and is_method:
            position -= 1  # calls do not pass self
        external = self.callables.external_param_kinds(function, classdef if is_method else None, name)  # type: ignore[arg-type]
        if is_method and function.name == "__init__":
            # A constructor parameter: every call that runs this ``__init__`` (subclasses too).
            constructions, elsewhere = self.constructions(classdef)  # type: ignore[arg-type]
            if elsewhere:
                external = [*external, EnvKind.UNKNOWN]
            calls = [call for call, _ in constructions]
            shifts = {id(call): shift for call, shift in constructions}
        else:
            calls = self.call_sites(function, classdef if is_method else None)  # type: ignore[arg-type]
            shifts = {}
        if not calls and not external:
            fixtures = param_fixtures(self.facts, function, name) if not is_method else []
            if fixtures:
                return join_kinds(self._fixture_kind(fixture) for fixture in fixtures)
            values = param_values(self.facts, function, name) if not is_method else None
            if values:
                return join_kinds(self.kind_of(value) for value in values)
            return EnvKind.GYM_ENV if self._wrapped_in_gym_wrapper(function, param) else EnvKind.UNKNOWN
        defaults = has_default(function, param)
        kinds = list(external)
        for call in calls:
            shift = shifts.get(id(call), 0)
            argument = call_argument(call, None if position is None else position + shift, name)
            if argument is None:
                if defaults and not any(k.arg is None for k in call.keywords):
                    continue
                kinds.append(EnvKind.UNKNOWN)  # not passed (or maybe in ``**kwargs``)
            else:
                kinds.append(self.kind_of(argument))
        gym = {k for k in kinds if k.is_gym}
        others = {k for k in kinds if k not in (EnvKind.NOT_ENV, EnvKind.UNKNOWN) and not k.is_gym}
        if gym and others:
            # Some callers pass a Gym env, others a VecEnv or a PettingZoo env: the same code
            # serves both, so no rewrite is right for all of them; reported (``mixed_callers``).
            self._mixed_params[param] = (sorted(k.value for k in gym), sorted(k.value for k in others))
            local = kinds[len(external) :]
            if self.project is not None and not any(k in others for k in local) and not is_test_path(self.project.path):
                # every other kind is a test module's double (``MockEnv`` with an ``ale`` of its
                # own): what a made env needs is still the production path's question
                qualname = f"{classdef.name}.{function.name}" if is_method else function.name  # type: ignore[union-attr]
                doubles = self.project.test_double_callers(qualname, name)
                if doubles:
                    self._test_double_params[param] = doubles
            return EnvKind.UNKNOWN
        if gym:
            kept, other = self.param_kept_classes(param)
            if kept and other:
                # Some callers pass an instance of a class whose step and reset the run keeps
                # on their own contract (``legacy_step_class``), others another env: the calls
                # here cannot follow both contracts; reported (``mixed_callers``).
                self._mixed_params[param] = (sorted(k.value for k in gym), [f"{name} (whose step and reset keep their own contract)" for name in sorted(kept)])
                return EnvKind.UNKNOWN
        return join_kinds(kinds)

    def _checked_multi_agent_kind(self, function: ast.FunctionDef | ast.AsyncFunctionDef, name: str) -> EnvKind | None:
        """``def to_vec(par_env): assert isinstance(par_env, ParallelEnv); ...`` (or ``if not
        isinstance(...): raise``) as a leading statement of the def, the parameter never
        rebound in it: every read past the check holds that PettingZoo kind, whatever the
        callers are thought to pass. None for any other shape."""
        if name in self._stored_names(function):
            return None
        for statement in function.body:
            test: ast.expr | None = None
            if isinstance(statement, ast.Assert):
                test = statement.test
            elif (
                isinstance(statement, ast.If)
                and isinstance(statement.test, ast.UnaryOp)
                and isinstance(statement.test.op, ast.Not)
                and statement.body
                and isinstance(statement.body[-1], ast.Raise)
                and not statement.orelse
            ):
                test = statement.test.operand
            elif isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Constant):
                continue  # the docstring
            else:
                return None  # only checks before anything else runs
            kind = self._isinstance_multi_agent_kind(test, name)
            if kind is not None:
                return kind
        return None

    def _isinstance_multi_agent_kind(self, test: ast.expr, name: str) -> EnvKind | None:
        """``isinstance(name, <PettingZoo AEC or parallel class>)`` (a tuple of one family):
        that kind; anything else: None."""
        if not (
            isinstance(test, ast.Call)
            and isinstance(test.func, ast.Name)
            and test.func.id == "isinstance"
            and not self.facts.bindings_of(test.func)
            and len(test.args) == 2
            and not test.keywords
            and isinstance(test.args[0], ast.Name)
            and test.args[0].id == name
        ):
            return None
        classes = test.args[1]
        items = classes.elts if isinstance(classes, ast.Tuple) else [classes]
        kinds = {other_library_class_kind(q) for item in items for q in (self.qualified_names(item) or {""})}
        if len(kinds) == 1 and kinds <= {EnvKind.PZ_AEC, EnvKind.PZ_PARALLEL}:
            return kinds.pop()
        return None

    def _wrapped_in_gym_wrapper(self, function: ast.AST, param: ast.arg) -> bool:
        """``def prepare(env, seed): env.seed(seed); env = Monitor(env, d)``, called nowhere the
        run shows: the def hands the parameter to a Gym wrapper class as the env it wraps
        (first argument or ``env=``), which only a Gym env can be."""
        # The def's calls are walked once: every parameter of every use asks this again.
        calls = self.facts.memo(("calls-in", id(function)), lambda: [n for n in ast.walk(function) if isinstance(n, ast.Call)])
        for node in calls:
            wrapped = node.args[0] if node.args else next((k.value for k in node.keywords if k.arg == "env"), None)
            if not (isinstance(wrapped, ast.Name) and wrapped.id == param.arg):
                continue
            if self._makes_gym_wrapper(node) and param in self.facts.bindings_of(wrapped):
                return True
        return False

    def _stored_names(self, function: ast.AST) -> frozenset[str]:
        """The names ``function`` (nested defs included: cautious) assigns or deletes; walked
        once per def, not once per parameter use."""
        return self.facts.memo(
            ("stored-names", id(function)),
            lambda: frozenset(n.id for n in ast.walk(function) if isinstance(n, ast.Name) and not isinstance(n.ctx, ast.Load)),
        )

    def param_kept_classes(self, param: ast.arg) -> tuple[frozenset[str], bool]:
        """The classes whose step and reset the run keeps on their own contract
        (``legacy_step_class``: a batch's four fields, a wrapper's own record) that callers
        of the def (in this module, or in others through ``ProjectView.kept_step_classes``)
        pass for ``param``; and whether some caller passes anything else, or the callers are
        not all known. A call of the def itself passing ``param`` on adds nothing."""
        return self.facts.memo(("param-kept", id(param)), lambda: self._param_kept_classes(param), while_computing=(frozenset(), True))

    def _param_kept_classes(self, param: ast.arg) -> tuple[frozenset[str], bool]:
        annotated = self.annotation_kept_class(param.annotation) if param.annotation is not None else None
        if annotated is not None:
            # ``def __init__(self, env: MultiEnv)``: the project declares the parameter an
            # instance of its own class kept on its four-field API, whoever builds it (its
            # callers are often outside the run: tests, scripts, another package).
            return frozenset({annotated}), False
        function = self.facts.parent(self.facts.parent(param))
        if not isinstance(function, FUNCTIONS):
            return frozenset(), True
        classdef = self.facts.parent(function)
        is_method = isinstance(classdef, ast.ClassDef) and self.facts.is_method(function)
        params = [*function.args.posonlyargs, *function.args.args]
        position = next((i for i, p in enumerate(params) if p is param), None)
        if position is not None and is_method:
            position -= 1
        if is_method and function.name == "__init__":
            constructions, elsewhere = self.constructions(classdef)  # type: ignore[arg-type]
            calls, shifts = [c for c, _ in constructions], {id(c): shift for c, shift in constructions}
        else:
            calls, shifts, elsewhere = self.call_sites(function, classdef if is_method else None), {}, False  # type: ignore[arg-type]
        found: set[str] = set()
        other = elsewhere
        defaults = has_default(function, param)
        for call in calls:
            argument = call_argument(call, None if position is None else position + shifts.get(id(call), 0), param.arg)
            if argument is None:
                other = other or not defaults or any(k.arg is None for k in call.keywords)
                continue
            if isinstance(argument, ast.Name) and param in self.facts.bindings_of(argument):
                continue  # the def passing its own parameter on: what its callers pass
            kept = self.legacy_step_class(argument)
            if kept is None:
                other = True
            else:
                found.add(kept)
        if not calls and (not is_method or _pytest_test_method(function, classdef, param.arg)):  # type: ignore[arg-type]
            # A test fed by a pytest fixture of this module (``def env(): return
            # MultiEnv(...)``) or a parametrization: what the fixture returns on every path.
            # A ``test_*`` method of a ``Test*`` class gets the module's fixtures too.
            fixtures = param_fixtures(self.facts, function, param.arg)
            values = [v for fixture in fixtures for v in fixture_values(self.facts, fixture)] if fixtures else param_values(self.facts, function, param.arg)
            if values:
                made = {self.legacy_step_class(value) for value in values}
                if None not in made:
                    return frozenset(made), False  # type: ignore[arg-type]
        if self.project is not None:
            qualname = function.name if not is_method else f"{classdef.name}.{function.name}"  # type: ignore[union-attr]
            for kept in self.project.kept_step_classes(qualname, param.arg):
                if kept is None:
                    other = True
                else:
                    found.add(kept)
        return frozenset(found), other or not (calls or found)

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

    def constructions(self, classdef: ast.ClassDef, _seen: frozenset[int] = frozenset()) -> tuple[list[tuple[ast.Call, int]], bool]:
        """The calls of this module that run ``classdef.__init__``, each with how far its
        positional arguments are shifted (1 for ``Base.__init__(self, env)``): the class's own
        calls, the calls of subclasses here that inherit ``__init__``, and the
        ``super().__init__(...)`` / ``Base.__init__(self, ...)`` of subclasses that define
        their own. The flag says another module of the run subclasses it (its calls are not
        known here)."""
        found: list[tuple[ast.Call, int]] = [(call, 0) for call in self.facts.calls_by_name.get(classdef.name, [])]
        elsewhere = (
            self.project is not None
            and self.facts.parent(classdef) is self.facts.tree
            and self.project.subclassed_elsewhere(classdef.name)
            and not self.project.built_through_super_elsewhere(classdef.name)
        )
        for sub in self.facts.classes.values():
            if sub is classdef or id(sub) in _seen or not any(self.local_class(b) is classdef for b in sub.bases):
                continue
            own_init = any(isinstance(s, FUNCTIONS) and s.name == "__init__" for s in sub.body)
            if not own_init:
                inherited, far = self.constructions(sub, _seen | {id(classdef)})
                found += inherited
                # A subclass built in another module (or, with no run to ask, one never built
                # here: other modules may build it) passes arguments this module cannot see.
                if self.project is None:
                    far = far or not inherited
                else:
                    far = far or self.project.built_elsewhere(sub.name)
                elsewhere = elsewhere or far
                continue
            first_base = next((b for b in sub.bases if not is_object(b)), None)
            for call in self.facts.attribute_calls.get("__init__", []):
                if self.facts.enclosing_class(call) is not sub:
                    continue
                owner = call.func.value  # type: ignore[attr-defined]
                if isinstance(owner, ast.Call) and isinstance(owner.func, ast.Name) and owner.func.id == "super":
                    if first_base is not None and self.local_class(first_base) is classdef:
                        found.append((call, 0))
                elif isinstance(owner, ast.Name) and self.local_class(owner) is classdef:
                    found.append((call, 1))  # ``Base.__init__(self, env)``
        # ``Wrapper = DummyVecEnv`` ... ``Wrapper(envs)``, ``make(cls=DummyVecEnv)``: the class
        # is built under another name too, with arguments the calls by its name do not show
        return found, elsewhere or self._class_escapes(classdef)

    def _class_escapes(self, classdef: ast.ClassDef) -> bool:
        """The module reads the class's name as a value other than a call, a base, an
        ``isinstance``/``issubclass`` argument, an attribute owner or an annotation."""
        return bool(self.facts.memo(("class-escapes", id(classdef)), lambda: self._escapes(classdef)))

    def _escapes(self, classdef: ast.ClassDef) -> bool:
        facts = self.facts
        for node in facts.reads_of(classdef.name):
            parent = facts.parent(node)
            if isinstance(parent, ast.Call) and parent.func is node:
                continue
            if isinstance(parent, ast.ClassDef) and node in parent.bases:
                continue
            if isinstance(parent, ast.Attribute):  # ``DummyVecEnv.__init__(self, ...)``, class constants
                continue
            if isinstance(parent, (ast.Tuple, ast.Call)):
                call = facts.parent(parent) if isinstance(parent, ast.Tuple) else parent
                if isinstance(call, ast.Call) and isinstance(call.func, ast.Name) and call.func.id in ("isinstance", "issubclass", "type"):
                    continue
            if _in_annotation(node, facts):
                continue
            return True
        return False

    def mixed_callers(self, expr: ast.AST, _depth: int = 0) -> str | None:
        """Why ``expr`` (a parameter, ``self.x`` stored from one, or a name bound to either)
        has no single kind: its callers pass a Gym env at some sites and another kind of env
        at others. None when that is not the reason."""
        if _depth > 4:
            return None
        self.kind_of(expr)  # fills ``_mixed_params`` on the way
        values: list[ast.AST] = []
        if isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and self.is_self(expr.value):
            classdef = self.facts.enclosing_class(expr)
            values = list(self.self_attribute_values(expr, expr.attr))
            if not values and classdef is not None:
                values = list(self.attributes.inherited_values(classdef, expr.attr))
        elif isinstance(expr, ast.Name):
            for binding in self.facts.bindings_of(expr):
                if isinstance(binding, ast.arg) and binding in self._mixed_params:
                    gym, others = self._mixed_params[binding]
                    doubles = self._test_double_params.get(binding)
                    if doubles:
                        # the only other feed is a test's stand-in: say so, and what porting needs
                        return (
                            f"its callers here pass a {' or '.join(gym)}, and only tests pass a double with an API of "
                            f"its own ({', '.join(doubles)}): to migrate these calls, port that double's reset and step "
                            "(or the mock's configured returns) with them"
                        )
                    return f"its callers pass a {' or '.join(gym)} at some sites and a {' or '.join(others)} at others"
                parent = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
                if isinstance(parent, ast.Assign):
                    values.append(parent.value)
        for value in values:
            found = self.mixed_callers(value, _depth + 1)
            if found is not None:
                return found
        return None

    def test_double_callers(self, expr: ast.AST, _depth: int = 0) -> list[str] | None:
        """Where test modules pass a double of their own to what ``expr`` (a parameter, ``self.x``
        stored from one, or a name bound to either) holds, when this module's own calls pass
        it a Gym env and only tests pass anything else. None when that is not so."""
        if _depth > 4:
            return None
        self.kind_of(expr)  # fills ``_test_double_params`` on the way
        values: list[ast.AST] = []
        if isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and self.is_self(expr.value):
            values = list(self.self_attribute_values(expr, expr.attr))
        elif isinstance(expr, ast.Name):
            for binding in self.facts.bindings_of(expr):
                if isinstance(binding, ast.arg):
                    if binding not in self._test_double_params:
                        return None
                    return self._test_double_params[binding]
                parent = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
                if isinstance(parent, ast.Assign):
                    values.append(parent.value)
        found: list[str] = []
        for value in values:
            callers = self.test_double_callers(value, _depth + 1)
            if callers is None:
                return None
            found += [c for c in callers if c not in found]
        return found or None

    def annotation_kind(self, annotation: ast.AST) -> EnvKind:
        if isinstance(annotation, ast.Constant) and isinstance(annotation.value, str):
            parsed = parse_annotation(annotation.value)  # ``env: "gym.Env"``
            named = self.facts.classes.get(parsed.id) if isinstance(parsed, ast.Name) else None
            if named is not None:
                return self.class_kind(named)  # ``env: "Board"``, a class of this module, as below
            return self.annotation_names_kind(string_names(self.facts, parsed)) if parsed is not None else EnvKind.UNKNOWN
        optional = optional_of(annotation, self.qualified_names)
        if optional is not None:
            return self.annotation_kind(optional)
        local = self.local_class(annotation)
        if local is not None:
            # ``def test_x(env: Warehouse)`` with Warehouse defined here; a class of the run
            # that is no env (``model_env: ModelEnv``) is the project's own object: left alone.
            return self.class_kind(local)
        return self.annotation_names_kind(self.qualified_names(annotation))

    def annotation_kept_class(self, annotation: ast.AST) -> str | None:
        """The class of the run an annotation names (``MultiEnv``, ``"MultiEnv"``,
        ``Optional[envs.MultiEnv]``) when its step keeps the four-field contract
        (``legacy_step_class``), else None."""
        if isinstance(annotation, ast.Constant) and isinstance(annotation.value, str):
            parsed = parse_annotation(annotation.value)
            named = self.facts.classes.get(parsed.id) if isinstance(parsed, ast.Name) else None
            if named is not None:
                return named.name if self.class_keeps_legacy_step(named) else None
            names = string_names(self.facts, parsed) if parsed is not None else set()
        else:
            optional = optional_of(annotation, self.qualified_names)
            if optional is not None:
                return self.annotation_kept_class(optional)
            local = self.local_class(annotation)
            if local is not None:
                return local.name if self.class_keeps_legacy_step(local) else None
            names = self.qualified_names(annotation)
        if self.project is not None:
            for qualified in names:
                if self.project.keeps_legacy_step(qualified):
                    return qualified.rsplit(".", 1)[-1]
        return None

    def annotation_names_kind(self, names: set[str]) -> EnvKind:
        for q in names:
            rest = N.strip_gym_prefix(q)
            if rest in N.GYM_ENV_BASE_CLASSES:
                return EnvKind.GYM_ENV
            if rest is not None and N.is_wrapper_class_path(rest):
                return EnvKind.GYM_ENV  # ``env: gym.wrappers.TimeLimit``: a wrapper class is a Gym env
            if rest is not None and rest.startswith("vector.") and rest.endswith("Env"):
                return EnvKind.GYM_VEC
            other = other_library_class_kind(q)
            if other is not None:
                return other
            if self.project is not None:
                found = self.project.call_kind(q)  # a class of another module of the run
                if found is not None:
                    return found
        return EnvKind.UNKNOWN

    def call_sites(self, function: ast.AST, classdef: ast.ClassDef | None) -> list[ast.Call]:
        """Calls in this module that reach ``function`` (a method when ``classdef`` is given)."""
        name = function.name  # type: ignore[attr-defined]
        if classdef is None:
            calls = self.facts.calls_by_name.get(name, [])
            module = self.facts.module_scope
            defs = [b for b in module.bindings.get(name, ()) if isinstance(b, FUNCTIONS)]
            if self.facts.parent(function) is self.facts.tree and (len(defs) > 1 or self.facts.functions.get(name) is not function):
                # A def the module defines again (a notebook's cells, run in order): a call of
                # the module's own code reaches the def bound where it runs, the one above it
                # in the text; a call inside a def runs whenever that def is called, so it may
                # reach any of them (``worker()`` calling ``run_episode`` defined in two cells).
                flow = Flow.of(self.facts)
                return [
                    c
                    for c in calls
                    if isinstance(c.func, ast.Name)
                    and self.facts.resolve(name, self.facts.scope_of(c.func))[0] is module
                    and (flow.last_binding_of(c.func) is function or not flow.same_frame(c.func, module))
                ]
            return [c for c in calls if self.local_function(c.func) is function]
        if name == "__init__":
            return list(self.facts.calls_by_name.get(classdef.name, []))
        if name == "__call__":
            # ``evaluate(env, policy)`` where ``evaluate`` holds an instance of the class (bound
            # to ``Evaluator(...)``, or a parameter every call of its def passes one).
            instances: list[ast.Call] = self.facts.memo(("instance-calls", id(classdef)), lambda: self._instance_calls(classdef))
        else:
            instances = []
        # ``self.train(env)`` in the class, and ``Agent().train(env)`` or ``algo.train(env)``
        # with ``algo = Agent()`` in the module: the instances the module makes itself.
        return [
            c
            for c in self.facts.attribute_calls.get(name, [])
            if (isinstance(c.func.value, ast.Name) and self.is_self(c.func.value))  # type: ignore[attr-defined]
            or self._made_instance_of(c.func.value, classdef, name)  # type: ignore[attr-defined]
            or self._unwrapped_of(c.func.value, classdef)  # type: ignore[attr-defined]
        ] + instances

    def _instance_calls(self, classdef: ast.ClassDef) -> list[ast.Call]:
        found = []
        for calls in self.facts.calls_by_name.values():
            for call in calls:
                values = self.called_instances(call.func)
                if values and all(self._made_instance_of(v, classdef, "__call__") for v in values):
                    found.append(call)
        return found

    def called_instances(self, func: ast.expr) -> list[ast.expr]:
        """What a called name holds, where that is a construction: the values of a name
        every binding of which is an assignment of a call (``evaluate = Evaluator(3)``), or,
        for a parameter of a top-level def, those of the name (or the call) every call of the
        def in the module passes there (``train(env, evaluate)``). Empty when unclear."""
        if not isinstance(func, ast.Name):
            return []
        bindings = self.facts.bindings_of(func)
        if len(bindings) == 1 and isinstance(bindings[0], ast.arg):
            param = bindings[0]
            function = self.facts.parent(self.facts.parent(param))
            if not isinstance(function, FUNCTIONS) or self.facts.functions.get(function.name) is not function:
                return []
            positional = [*function.args.posonlyargs, *function.args.args]
            position = next((i for i, p in enumerate(positional) if p is param), None)
            values: list[ast.expr] = []
            for call in self.call_sites(function, None):
                argument = call_argument(call, position, param.arg)
                if argument is None:
                    return []
                found = self.facts.assigned_values(argument, sole_target=True) if isinstance(argument, ast.Name) else [argument]
                if not found or not all(isinstance(v, ast.Call) for v in found):
                    return []
                values.extend(found)
            return values
        found = self.facts.assigned_values(func, sole_target=True)
        return found if found is not None and all(isinstance(v, ast.Call) for v in found) else []

    def _unwrapped_of(self, owner: ast.AST, classdef: ast.ClassDef) -> bool:
        """``x.unwrapped.set_top(self)`` with ``set_top`` a method of this module's Gym env
        class: ``unwrapped`` is the env under every wrapper, and a method only the run's env
        classes define is theirs (a wrapper registering itself with the env it wraps)."""
        return (
            isinstance(owner, ast.Attribute)
            and owner.attr == "unwrapped"
            and not self.is_gym_wrapper_class(classdef)
            and self.class_kind(classdef) is EnvKind.GYM_ENV
        )

    def _made_instance_of(self, owner: ast.AST, classdef: ast.ClassDef, method: str) -> bool:
        """``owner`` is ``Cls(...)`` or a name every binding of which is ``Cls(...)``, with
        ``Cls`` this module's ``classdef`` or a subclass here that inherits ``method``."""
        if isinstance(owner, ast.Name):
            bindings = self.facts.bindings_of(owner)
            values = []
            for binding in bindings:
                assign = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
                if not (isinstance(assign, ast.Assign) and assign.targets == [binding]):
                    return False
                values.append(assign.value)
            return bool(values) and all(self._made_instance_of(v, classdef, method) for v in values)
        if not isinstance(owner, ast.Call):
            return False
        made = self.local_class(owner.func)
        seen: set[int] = set()
        while made is not None and made is not classdef and id(made) not in seen:
            seen.add(id(made))
            if any(isinstance(st, FUNCTIONS) and st.name == method for st in made.body):
                return False  # the subclass has a method of its own
            bases = [b for b in made.bases if not is_object(b)]
            made = self.local_class(bases[0]) if len(bases) == 1 else None
        return made is classdef

    def _fixture_kind(self, fixture: ast.FunctionDef | ast.AsyncFunctionDef) -> EnvKind:
        values = fixture_values(self.facts, fixture)
        return join_kinds(self.kind_of(value) for value in values) if values else EnvKind.NOT_ENV


def _pytest_test_method(function: ast.FunctionDef | ast.AsyncFunctionDef, classdef: ast.ClassDef, name: str) -> bool:
    """``function`` is a pytest test method (``Test*.test_*``) whose class does not define a
    fixture of its own called ``name`` (which would shadow the module's)."""
    return (
        classdef.name.startswith("Test")
        and function.name.startswith("test")
        and not any(isinstance(s, FUNCTIONS) and s.name == name for s in classdef.body)
    )


def has_default(function: ast.AST, param: ast.arg) -> bool:
    """Whether ``param`` has a default value."""
    args = function.args  # type: ignore[attr-defined]
    positional = [*args.posonlyargs, *args.args]
    if param in positional:
        return positional.index(param) >= len(positional) - len(args.defaults)
    if param in args.kwonlyargs:
        return args.kw_defaults[args.kwonlyargs.index(param)] is not None
    return False


def _in_annotation(node: ast.AST, facts) -> bool:
    """``node`` sits in an annotation (of an argument, a return or an assignment)."""
    child, parent = node, facts.parent(node)
    while parent is not None and not isinstance(parent, ast.stmt):
        if isinstance(parent, ast.arg) and parent.annotation is child:
            return True
        child, parent = parent, facts.parent(parent)
    if isinstance(parent, ast.AnnAssign) and parent.annotation is child:
        return True
    if isinstance(parent, (ast.FunctionDef, ast.AsyncFunctionDef)) and parent.returns is child:
        return True
    return False
