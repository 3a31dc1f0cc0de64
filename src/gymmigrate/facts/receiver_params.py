"""What a parameter of a def holds: its annotation, the arguments at every call site of
the module (constructions of a class through its subclasses too) and of the run
(``ProjectView.param_kinds``), or the pytest fixtures and parametrizations that feed a
test (``ParameterKinds``, mixed into ``Receivers``). Which calls reach a def is
``receiver_callers.py``; what the thunks passed for a parameter return is
``receiver_thunks.py``; both are mixed in here.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import names as N
from gymmigrate.facts.callables import (
    optional_of,
    parse_annotation,
    string_names,
    union_members,
)
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.import_roots import is_test_path
from gymmigrate.facts.kinds import EnvKind, join_kinds
from gymmigrate.facts.module import FUNCTIONS, call_argument, param_default, walk
from gymmigrate.facts.pytest_params import (
    fixture_values,
    injected,
    param_fixtures,
    param_values,
    pytest_fixture,
)
from gymmigrate.facts.receiver_callers import CallerSites
from gymmigrate.facts.receiver_classes import other_library_class_kind
from gymmigrate.facts.receiver_thunks import ThunkKinds


class ParameterKinds(CallerSites, ThunkKinds):
    """The kinds of parameters (part of ``Receivers``)."""

    # parameters whose callers pass a Gym env and another kind of env: (gym kinds, others)
    _mixed_params: dict[ast.arg, tuple[list[str], list[str]]]
    _own_mixed_params: dict[ast.arg, tuple[list[str], list[str]]]
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
            if self.wraps_vec_env(classdef):  # type: ignore[arg-type]
                return EnvKind.SB3_VEC
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
            conftest = self._conftest_fixture_kind(function, name)
            if conftest is not None:
                return conftest
            return EnvKind.GYM_ENV if self._wrapped_in_gym_wrapper(function, param) else EnvKind.UNKNOWN
        defaults = has_default(function, param)
        kinds = list(external)
        own_objects: list[str] = []  # arguments of unknown kind that the project itself makes
        mixed_own: list[str] = []  # the project's own objects a name bound to a Gym env in other branches may hold
        handed: list[tuple[list[str], list[str]]] = []  # what a mixed parameter handed on here may hold
        for call in calls:
            shift = shifts.get(id(call), 0)
            argument = call_argument(call, None if position is None else position + shift, name)
            if argument is None:
                if defaults and not any(k.arg is None for k in call.keywords):
                    continue
                kinds.append(EnvKind.UNKNOWN)  # not passed (or maybe in ``**kwargs``)
            else:
                kinds.append(self.kind_of(argument))
                if kinds[-1] is EnvKind.UNKNOWN and self.run_defined(argument):
                    own_objects.append(self._made_by(argument))
                if kinds[-1] is EnvKind.UNKNOWN:
                    mixed_own.extend(self._own_beside_gym(argument))
                    handed.extend(self._handed_mixed(argument))
        gym = {k for k in kinds if k.is_gym}
        if EnvKind.SB3_VEC in kinds and own_objects and not gym:
            # A VecEnv at some sites, an object of the project's own at others (a proxy around
            # an env the run migrates, as likely as not): a VecEnv at one site proves nothing of
            # the others, so the calls are reported (``mixed_callers``), not left in silence.
            shown = ", ".join(f"`{text}`" for text in sorted(set(own_objects)))
            self.note(self._mixed_params, param, ([f"project's own object ({shown})"], [EnvKind.SB3_VEC.value]))
            return EnvKind.UNKNOWN

        if handed and not mixed_own:
            # a parameter of a caller that is itself mixed (``def collect(self, env):
            # self.play(env)``): the same objects reach this one
            self.note(self._mixed_params, param, handed[0])
            self.note(self._own_mixed_params, param, handed[0])
            return EnvKind.UNKNOWN
        if mixed_own:
            # ``env = Point() if own else gym.make(name)`` handed on: the same calls serve the
            # project's own class, on its own (old) API, and a Gym env, so no rewrite is right
            # for both and the file's imports settle nothing; reported (``mixed_callers``)
            shown = ", ".join(f"`{text}`" for text in sorted(set(mixed_own)))
            mixed = ([EnvKind.GYM_ENV.value], [f"project's own object ({shown}, not shown to be a Gym env: migrate its class together with these calls, or branch)"])
            self.note(self._mixed_params, param, mixed)
            self.note(self._own_mixed_params, param, mixed)
            return EnvKind.UNKNOWN
        others = {k for k in kinds if k not in (EnvKind.NOT_ENV, EnvKind.UNKNOWN) and not k.is_gym}
        if gym and others:
            # Some callers pass a Gym env, others a VecEnv or a PettingZoo env: the same code
            # serves both, so no rewrite is right for all of them; reported (``mixed_callers``).
            self.note(self._mixed_params, param, (sorted(k.value for k in gym), sorted(k.value for k in others)))
            local = kinds[len(external) :]
            if self.project is not None and not any(k in others for k in local) and not is_test_path(self.project.path):
                # every other kind is a test module's double (``MockEnv`` with an ``ale`` of its
                # own): what a made env needs is still the production path's question
                qualname = f"{classdef.name}.{function.name}" if is_method else function.name  # type: ignore[union-attr]
                doubles = self.project.test_double_callers(qualname, name)
                if doubles:
                    self.note(self._test_double_params, param, doubles)
            return EnvKind.UNKNOWN
        if gym:
            kept, other = self.param_kept_classes(param)
            if kept and other:
                # Some callers pass an instance of a class whose step and reset the run keeps
                # on their own contract (``legacy_step_class``), others another env: the calls
                # here cannot follow both contracts; reported (``mixed_callers``).
                self.note(self._mixed_params, param, (sorted(k.value for k in gym), [f"{name} (whose step and reset keep their own contract)" for name in sorted(kept)]))
                return EnvKind.UNKNOWN
        return join_kinds(kinds)

    def _handed_mixed(self, argument: ast.expr) -> list[tuple[list[str], list[str]]]:
        """What a parameter ``argument`` reads holds, where its own callers pass the project's
        own object beside a Gym env (``_own_mixed_params``): it hands the same objects on.
        (A parameter mixed with a VecEnv is asked where it is read, as before: its hand-ons
        keep the fallback.)"""
        if not isinstance(argument, ast.Name):
            return []
        return [self._own_mixed_params[b] for b in self.facts.bindings_of(argument) if isinstance(b, ast.arg) and b in self._own_mixed_params]

    def _own_beside_gym(self, argument: ast.expr) -> list[str]:
        """What the project itself makes (``Point`` for ``env = Point()``) among the values a
        name argument may hold, when another of them is a Gym env (``env = gym.make(name)`` in
        the other branch): the object handed on is one or the other. Empty otherwise."""
        if not isinstance(argument, ast.Name):
            return []
        reaching = Flow.of(self.facts).reaching(argument)
        bindings = reaching if reaching is not None else self.facts.bindings_of(argument)
        values: list[ast.expr] = []
        for binding in bindings:
            parent = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
            if isinstance(parent, ast.Assign) and len(parent.targets) == 1 and parent.targets[0] is binding:
                values.append(parent.value)  # a plain ``env = ...``; a parameter or unpack says nothing here
        kinds = [self.kind_of(value) for value in values]
        if not any(k.is_gym for k in kinds):
            return []
        return [
            self.facts.segment(value.func if isinstance(value, ast.Call) else value)
            for value, kind in zip(values, kinds)
            if kind is EnvKind.UNKNOWN and self.run_defined(value)
        ]

    def _made_by(self, argument: ast.expr) -> str:
        """What an argument is made by, as the code spells it: ``Recorder`` for ``env`` bound
        (where it is read) only to ``Recorder(...)``; else the argument's own text."""
        value: ast.AST = argument
        if isinstance(argument, ast.Name):
            reaching = Flow.of(self.facts).reaching(argument)
            parents = [self.facts.parent(b) for b in reaching or ()]
            if len(parents) == 1 and isinstance(parents[0], ast.Assign):
                value = parents[0].value
        return self.facts.segment(value.func if isinstance(value, ast.Call) else value)

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
        calls = self.facts.memo(("calls-in", id(function)), lambda: [n for n in walk(function) if isinstance(n, ast.Call)])
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
            lambda: frozenset(n.id for n in walk(function) if isinstance(n, ast.Name) and not isinstance(n.ctx, ast.Load)),
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

    def mixed_callers(self, expr: ast.AST, _depth: int = 0) -> str | None:
        """Why ``expr`` (a parameter, ``self.x`` stored from one, or a name bound to either)
        has no single kind: its callers pass a Gym env at some sites and another kind of env
        at others. None when that is not the reason."""
        if _depth > 4:
            return None
        thunks = self._mixed_thunks(expr)
        if thunks is not None:
            return thunks
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
        members = union_members(annotation, self.qualified_names)
        if members is not None:
            # ``Union[gym.Env, gym.Wrapper]``: a Gym env whichever member it is; one member
            # of another kind (the project's own vec env) leaves the kind unknown
            kinds = {self.annotation_kind(m) for m in members}
            return kinds.pop() if len(kinds) == 1 and EnvKind.UNKNOWN not in kinds else EnvKind.UNKNOWN
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


    def _conftest_fixture_kind(self, function: ast.FunctionDef | ast.AsyncFunctionDef, name: str) -> EnvKind | None:
        """What pytest gives the parameter ``name`` of a test or fixture from a conftest.py
        of the run above this module (``ProjectView.fixture_kind``): the module's own
        fixtures and parametrizations, asked first, override it. None where none is known."""
        if self.project is None or not injected(self.facts, function):
            return None
        classdef = self.facts.enclosing_class(function)
        if classdef is not None and not _pytest_test_method(function, classdef, name):
            return None  # the class's own fixture of that name comes first
        return self.project.fixture_kind(name)

    def requested_fixture_kind(self, names: list[str]) -> EnvKind:
        """What ``request.getfixturevalue(n)`` gives for each name it may ask: the module's
        fixture of that name, else the nearest conftest.py's."""
        kinds = []
        for name in names:
            local = pytest_fixture(self.facts, name)
            found = self._fixture_kind(local) if local is not None else (self.project.fixture_kind(name) if self.project is not None else None)
            kinds.append(EnvKind.UNKNOWN if found is None else found)
        return join_kinds(kinds)

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
    return param_default(function, param) is not None  # type: ignore[arg-type]
