"""Where an env comes from, and what its outermost wrapper defines: what the forwarding
rules (GM604-GM606, ``forwarding.py``) know of a receiver before they decide.

An origin is MADE (a ``gym.make`` result, maybe wrapped further), WRAPPED (wrapper
constructors around something else), INNER (a wrapper's ``self.env``) or RAW (an env
class's constructor, ``.unwrapped``). ``EnvOrigins`` holds one file's answers: origins are
memoized per name binding site, and a name whose origin is being computed counts as
"no evidence" (CYCLE) when reached again, so the classic ``env = Wrapper(env)``
preprocessing stack costs one visit per assignment instead of one per path through them.
The wrapper met around such a name is not dropped with it: the name may hold its other
values wrapped (``env = Tank()``, then ``if noisy: env = Gauge(env)``), which its answer
takes in once all its bindings are known. An answer that rests on a name still being
computed is not kept as final: that open question may still change it.
It also tells the wrapper class outermost on a read and what that class defines; what the
project's own classes hold from their constructions is asked in ``held_envs.py`` (mixed in).
"""

from __future__ import annotations

import ast
import bisect
from collections.abc import Callable

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.creation_shapes import holds_no_items, items_added_in_place
from gymmigrate.facts.creator_tables import entries, lookup, table_display
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import FUNCTIONS, call_argument, own_returns, walk
from gymmigrate.facts.project_view_fixtures import FixtureOrigin
from gymmigrate.facts.pytest_params import (
    fixture_values,
    injected,
    param_fixtures,
    param_values,
    pytest_fixture,
    requested_fixtures,
)
from gymmigrate.facts.receiver_classes import duck_wrapper_attribute
from gymmigrate.facts.receivers import Receivers
from gymmigrate.facts.self_attributes import store_seen
from gymmigrate.rules.wrapper_usage.held_envs import HeldEnvQuestions
from gymmigrate.rules.wrapper_usage.tables import (
    OWN_ATTRIBUTES,
    current_name,
    wrapper_class_rest,
    wrapper_rest,
)

# Where an env came from.
MADE = "made"  # gym.make (+ wrappers): a wrapper stack with a spec
WRAPPED = "wrapped"  # wrapper constructors around something else: a stack, maybe no spec
INNER = "inner"  # a wrapper's ``self.env`` / ``env`` argument: almost always a make() result
RAW = "raw"  # an env class's constructor or ``.unwrapped``: no wrapper in between
# Reached a name whose origin is being computed (``env = Wrapper(env)``): no evidence
# either way; the other bindings decide.
CYCLE = "cycle"



# Deeper than any real chain of distinct names; beyond it the origin is unknown (reported).
MAX_DEPTH = 20

Origin = str | None
# What an answer is memoized under: (scope, name), (def, "<returns>"), (parameter, "<param>").
_Key = tuple[int, str]
_SYNC_VECTOR_ENVS = frozenset({"vector.SyncVectorEnv", "vector.sync_vector_env.SyncVectorEnv"})


def join_origins(origins: list[Origin]) -> Origin:
    found = set(origins)
    found.discard(CYCLE)
    if not found:
        return CYCLE if origins else None
    if None in found:
        return None
    if len(found) == 1:
        return found.pop()
    if RAW in found:
        return None
    return WRAPPED if WRAPPED in found or INNER in found else MADE


def _with_own_wrappers(origin: Origin) -> Origin:
    """What a name holds whose bindings give ``origin`` and that is also rebound to a
    wrapper around itself (``env = Tank()``, then ``if noisy: env = Gauge(env)``): a made
    env stays made (wrappers over make keep its spec); any other env may or may not sit
    under the wrapper where it is read, and get_wrapper_attr reads the bare env and the
    stack alike."""
    if origin in (RAW, INNER, WRAPPED):
        return WRAPPED
    return origin


class EnvOrigins(HeldEnvQuestions):
    """One file's origins and wrapper knowledge, memoized (one per ``WrapperForwarding``)."""

    def __init__(self, facts: ModuleFacts, receivers: Receivers) -> None:
        self.facts = facts
        self.receivers = receivers
        self._final: dict[_Key, Origin] = {}
        # The answers being computed, as a stack: a key's index in it, and per entry the
        # lowest index its computation reached while that key was open (an answer that rests
        # on an open key below its own is provisional), whether a wrapper around the entry's
        # own key was met, and the provisional answers to drop when the entry closes.
        self._open: dict[_Key, int] = {}
        self._lows: list[int] = []
        self._rewrapped: list[bool] = []
        self._provisional: dict[_Key, tuple[Origin, int]] = {}
        self._provisional_at: list[list[_Key]] = []
        # names that hold an env of their own class, bare on one path and wrapped around
        # themselves on another: what one read sees may still be told (``at_read``)
        self._bare_or_wrapped: set[_Key] = set()
        self._depth = 0
        self._local_attrs: set[str] | None = None
        self._class_attrs: dict[ast.ClassDef, set[str]] = {}
        # (scope, name) -> (lines, values) of its assignments, sorted by line; None if one is not ``x = ...``
        self._assign_lines: dict[tuple[int, str], tuple[list[int], list[ast.expr]] | None] = {}
        # assignment -> what the reads it settles may hold (``reached``)
        self._reached_after: dict[ast.Assign, frozenset[Origin]] = {}

    def origin(self, expr: ast.AST | None) -> Origin:
        """MADE / WRAPPED / INNER / RAW, CYCLE, or None when it cannot be told."""
        if expr is None or self._depth > MAX_DEPTH:
            return None
        self._depth += 1
        try:
            if isinstance(expr, ast.Call):
                return self._call_origin(expr)
            if isinstance(expr, ast.Attribute):
                return self._attribute_origin(expr)
            if isinstance(expr, ast.Name):
                origin = self._name_origin(expr)
                if origin in (None, CYCLE) and self.receivers.narrowing.is_env(expr):
                    return WRAPPED  # ``isinstance(env, gym.Env)`` checked it: bare or wrapped
                return origin
            if isinstance(expr, ast.Subscript):
                return self._items_origin(expr.value)
            if isinstance(expr, ast.IfExp):
                # ``Sim() if coop else gym.make(id)``: what either branch gives
                return join_origins([self.origin(expr.body), self.origin(expr.orelse)])
            return None
        finally:
            self._depth -= 1

    def _items_origin(self, container: ast.expr) -> Origin:
        """``self.envs[i]`` with ``self.envs = [gym.make(...) for _ in ...]`` stored in the class:
        what its items are."""
        values: list[ast.expr] = [container]
        origins: list[Origin] = []
        if isinstance(container, ast.Attribute) and isinstance(container.value, ast.Name) and container.value.id == "self":
            classdef = self.facts.enclosing_class(container)
            values = self.receivers.self_stores(classdef).get(container.attr, []) if classdef is not None else []
            added = items_added_in_place(classdef, container.attr) if classdef is not None else None
            if added is not None and any(added):
                # ``self.envs = []`` then ``self.envs.append(OwnEnv(...))``: the items it is
                # given in place; an empty display (or None, dropped in ``close()``) holds none
                items, containers = added
                origins.extend(self.origin(item) for item in items)
                values = [v for v in (*values, *containers) if not holds_no_items(v)]
        for value in values:
            if isinstance(value, (ast.ListComp, ast.GeneratorExp)):
                origins.append(self.origin(value.elt))
            elif isinstance(value, (ast.List, ast.Tuple)) and value.elts:
                origins.extend(self.origin(item) for item in value.elts)
            else:
                return None
        return join_origins(origins) if origins else None

    def _attribute_origin(self, expr: ast.Attribute) -> Origin:
        if expr.attr == "unwrapped":
            return RAW
        if isinstance(expr.value, ast.Name) and expr.value.id == "self":
            classdef = self.facts.enclosing_class(expr)
            if classdef is None:
                return None
            if expr.attr in ("env", duck_wrapper_attribute(classdef)) and self.receivers.is_gym_wrapper_class(classdef):
                return INNER
            stores = self.receivers.self_stores(classdef).get(expr.attr, [])
            # ``self.env = None`` in ``__init__`` and the env stored by another method: a read
            # that meets the None fails on any attribute, so it only ever reads the other stores
            held = [v for v in stores if not (isinstance(v, ast.Constant) and v.value is None)]
            return join_origins([self.origin(v) for v in held])
        return None

    def _call_origin(self, call: ast.Call) -> Origin:
        requested = self._requested(call)
        if requested is not None:
            return _join_fed(requested)  # pytest's ``request.getfixturevalue(...)``
        if len(call.args) == 1 and self.facts.qualified_names(call.func) & {"copy.deepcopy", "copy.copy"}:
            return self.origin(call.args[0])  # a copy of the env, as made or wrapped as it is
        for q in self.facts.qualified_names(call.func):
            rest = N.strip_gym_prefix(q)
            if rest is None:
                continue
            if rest in N.GYM_ENV_FACTORIES:
                return MADE
            if rest.startswith("wrappers.") and not rest.startswith("wrappers.vector."):
                # a recorder or frame buffer beside the wrappers is no env at all, whatever it is handed
                return self._wrapped(call) if wrapper_class_rest(q) is not None else None
            if rest.startswith("envs."):
                return RAW
        if self.is_run_wrapper_class(call.func) or self.receivers.library_wrapper_class(call.func):
            return self._wrapped(call)  # (an env library's Gym wrappers, ``ImgObsWrapper``, as gym's own)
        local = self.receivers.local_class(call.func)
        if local is not None:
            if self.receivers.is_gym_wrapper_class(local):
                return self._wrapped(call)
            if self.receivers.class_kind(local) is EnvKind.GYM_ENV:
                return RAW
        wrappers = self.receivers.handed_wrappers(call)
        if wrappers is not None:
            # ``for w in wrappers: env = w(env)`` over Gym wrapper classes every caller shows:
            # wrapped where some caller hands one in; with none the call never runs and the
            # name keeps what it held
            return self._wrapped(call) if wrappers else self.origin(call.args[0])
        if isinstance(call.func, (ast.Subscript, ast.Call)):
            thunk = _called_factory(call.func)
            if thunk is not None:
                # ``make_creator(params)[0]()``, ``make_single(id)()``: what the factory's thunk returns
                return self._called_thunk_origin(*thunk)
        if isinstance(call.func, ast.Subscript):
            return self._table_origin(call.func)
        if self.receivers.local_function(call.func) is None:
            handed = self.receivers.wrapped_argument(call)
            if handed is not None:
                return self._handed_through(handed)
        return self._returns_origin(call.func)

    def reached(self, expr: ast.expr) -> frozenset[Origin]:
        """The origins of every value ``expr`` may hold, unjoined: each assignment of a name,
        each branch of a conditional, each return of a def of the module it calls. Where they
        disagree ``origin`` answers None for a bare env on one path and a made one on another
        as for an untraced one; this tells them apart. A name reached again adds nothing."""
        if isinstance(expr, ast.Name):
            # the one assignment every path to the read passes last is all the read sees
            flow = Flow.of(self.facts)
            last = flow.last_binding_of(expr)
            statement = self.facts.statement_of(last) if isinstance(last, ast.Name) else None
            if isinstance(statement, ast.Assign) and statement.targets == [last] and flow.dominates(statement, expr, expr):
                scope, _ = self.facts.resolve(expr.id, self.facts.scope_of(expr))
                # every read after the same assignment sees the same values: asked once
                found = self._reached_after.get(statement)
                if found is None:
                    found = self._reached_after[statement] = self._reached(statement.value, frozenset({(id(scope), expr.id)}))
                return found
        return self._reached(expr, frozenset())

    def _reached(self, expr: ast.expr | None, seen: frozenset[_Key]) -> frozenset[Origin]:
        if expr is None or len(seen) > MAX_DEPTH:
            return frozenset({None})
        if isinstance(expr, ast.IfExp):
            return self._reached(expr.body, seen) | self._reached(expr.orelse, seen)
        if isinstance(expr, ast.Name):
            scope, bindings = self.facts.resolve(expr.id, self.facts.scope_of(expr))
            if scope is None:
                return frozenset({None})
            key = (id(scope), expr.id)
            if key in seen:
                return frozenset()
            found: set[Origin] = set()
            for binding in bindings:
                parent = self.facts.parent(binding)
                if isinstance(binding, ast.arg):
                    found.add(self._param_origin(binding))
                elif isinstance(binding, ast.Name) and isinstance(parent, ast.Assign) and binding in parent.targets:
                    if _walks_down(parent.value, expr.id):
                        continue  # ``env = env.env`` searching the layers: a layer of what it already held
                    found |= self._reached(parent.value, seen | {key})
                else:
                    found.add(None)
            return frozenset(found)
        if isinstance(expr, ast.Call):
            function = self.receivers.local_function(expr.func)
            returned = (id(function), "<returns>")
            # a def that hands its argument back, maybe wrapped (``env = dress(env)``), is
            # what its own origin says: which branch a call takes is not told here
            if function is not None and returned not in seen and not self.receivers.wraps_argument(function):
                returns = own_returns(function)
                if returns:
                    found = set()
                    for r in returns:
                        found |= self._reached(r.value, seen | {returned})
                    return frozenset(found)
        origin = self.origin(expr)
        # a value resting on the name itself (``env = dress(env)``): not told here
        return frozenset({None}) if origin == CYCLE else frozenset({origin})

    def _handed_through(self, argument: ast.expr) -> Origin:
        """What a def of another module of the run gives that returns its argument, maybe in
        Gym wrappers (``wrap_deepmind(env=make_atari(id))``): as made as the argument is;
        any other Gym env may come back bare or wrapped, and get_wrapper_attr reads both."""
        inner = self.origin(argument)
        if inner in (MADE, CYCLE):
            return inner
        if inner is not None or self.receivers.kind_of(argument) is EnvKind.GYM_ENV:
            return WRAPPED
        return None

    def _returns_origin(self, func: ast.expr) -> Origin:
        """What calling ``func`` returns, for a def of the module or a name of the run."""
        function = self.receivers.local_function(func)
        if function is not None:
            values = [r.value for r in own_returns(function) if r.value is not None]
            return self._memo((id(function), "<returns>"), lambda: join_origins([self.origin(v) for v in values]))
        if isinstance(func, ast.Name):
            thunk = self._thunk_origin(func)
            if thunk is not None:
                return thunk
            listed = self._listed_thunk_origin(func)
            if listed is not None:
                return listed
        if isinstance(func, ast.Attribute):
            # ``factory.get_env()`` on an instance of a class of the module: what its method
            # returns (one that returns nothing gives None, on which any attribute read fails)
            values = [r.value for m in self.receivers.instance_methods(func.value, func.attr) for r in own_returns(m) if r.value is not None]
            if values:
                return join_origins([self.origin(v) for v in values])
        if isinstance(func, ast.Attribute) and self.receivers.callables.held_callable_kind(func) is EnvKind.GYM_ENV:
            # ``env = holder.x()`` in a worker every spawn hands ``Pickled(fn)``, each ``fn``
            # a thunk returning a Gym env: bare or wrapped, as the kinds say
            return WRAPPED
        view = self.receivers.project
        if view is not None:
            qualified = self.facts.qualified_names(func)
            if any(view.returns_made(q) for q in qualified):
                return MADE  # a def of another module of the run that returns make() results
            if any(view.makes_bare_env(q) for q in qualified):
                return RAW  # an env class of another module of the run: the env itself
        return None

    def _listed_thunk_origin(self, func: ast.Name) -> Origin:
        """``fn()`` in ``self.envs = [fn() for fn in env_fns]`` (or a ``for fn in env_fns``
        loop), ``env_fns`` a parameter that every call the run shows (in this module and in
        the others) feeds a list of thunks returning Gym envs (``thunks_returned_kind``): a
        Gym env, bare or wrapped, so its own methods are reached through make's wrappers.
        None where one caller feeds anything else, or ``fn`` is bound otherwise."""
        bindings = self.facts.bindings_of(func)
        loop = self.facts.parent(bindings[0]) if len(bindings) == 1 else None
        if not (isinstance(loop, (ast.For, ast.comprehension)) and loop.target is bindings[0] and isinstance(loop.iter, ast.Name)):
            return None
        sources = self.facts.bindings_of(loop.iter)
        if len(sources) != 1 or not isinstance(sources[0], ast.arg):
            return None
        return WRAPPED if self.receivers.thunks_returned_kind(sources[0]) is EnvKind.GYM_ENV else None

    def _thunk_origin(self, func: ast.Name) -> Origin:
        """``create()`` where every binding of ``create`` takes the thunk a factory returns:
        ``create = make_single(id)``, ``create = make_creator(params)[0]`` or ``create, _ =
        make_creator(params)``: what that thunk's returns are, for a def of this module, or
        MADE where a def of another module of the run is shown to return a thunk of make()
        results there (``ProjectView.thunk_made``). None for any other binding."""
        bindings = self.facts.bindings_of(func)
        if not bindings:
            return None
        origins: list[Origin] = []
        for binding in bindings:
            factory = _factory_item(self.facts, binding)
            if factory is None:
                return None
            call, item = factory
            origins.append(self._memo((id(binding), "<thunk>"), lambda call=call, item=item: self._called_thunk_origin(call, item)))  # type: ignore[misc]
        return join_origins(origins)

    def _called_thunk_origin(self, call: ast.Call, item: tuple[int, int | None] | None) -> Origin:
        function = self.receivers.local_function(call.func)
        if function is None:
            view = self.receivers.project
            if view is not None and any(view.thunk_made(q, item) for q in self.facts.qualified_names(call.func)):
                return MADE
            return None
        thunks = [r.value for r in own_returns(function)] if item is None else self.receivers.returned_items(function, *item)
        if not thunks or any(t is None for t in thunks):
            return None
        values: list[ast.expr] = []
        for thunk in thunks:
            returned = self.receivers.thunk_returns(thunk)  # type: ignore[arg-type]
            if not returned or any(not isinstance(v, ast.expr) for v in returned):
                return None
            values += returned  # type: ignore[arg-type]
        return join_origins([self.origin(v) for v in values])

    def _table_origin(self, callee: ast.Subscript) -> Origin:
        """``CREATORS[name](...)``, ``ENVS[key]["make"](...)`` on a closed table of creators
        (``facts/creator_tables.py``): what every callable there returns, joined; a table
        of another module of the run is made when its every callable returns a make()."""
        found = lookup(self.facts, callee)
        if found is None:
            return None
        table, field = found
        view = self.receivers.project
        if isinstance(table, ast.Name):
            display = table_display(self.facts, table)
            if display is not None:
                values = entries(display, field)
                if values is None or (view is not None and view.table_altered(table.id)):
                    return None
                return join_origins([self.origin(v.body) if isinstance(v, ast.Lambda) else self._returns_origin(v) for v in values])
        if view is not None and any(view.table_made(q, field) for q in self.facts.qualified_names(table)):
            return MADE
        return None

    def _wrapped(self, call: ast.Call) -> Origin:
        """A wrapper around its first argument: as made as what it wraps, or merely wrapped."""
        first = call.args[0] if call.args else (call.keywords[0].value if call.keywords else None)
        if first is None:
            return WRAPPED
        inner, reached = self._reaching(lambda: self.origin(first))
        if inner == CYCLE:
            if reached is not None:
                # A wrapper around a name still being computed (``env = Gauge(env)``): no
                # evidence of what is inside, but evidence that the name may hold it wrapped.
                self._rewrapped[reached] = True
            return CYCLE
        return MADE if inner == MADE else WRAPPED

    def _name_origin(self, name: ast.Name) -> Origin:
        scope, bindings = self.facts.resolve(name.id, self.facts.scope_of(name))
        if scope is None:
            return None
        # reached again while open (``env = Wrapper(env)``): CYCLE, the other bindings decide
        return self._memo((id(scope), name.id), lambda: self._bindings_origin(bindings))

    def _bindings_origin(self, bindings: list[ast.AST]) -> Origin:
        origins: list[Origin] = []
        for binding in bindings:
            if isinstance(binding, ast.arg):
                origins.append(self._param_origin(binding))
                continue
            parent = self.facts.parent(binding)
            if isinstance(binding, ast.Name) and isinstance(parent, ast.Assign) and binding in parent.targets:
                origins.append(self.origin(parent.value))
                continue
            if isinstance(binding, ast.Name) and isinstance(parent, ast.AnnAssign) and parent.value is not None:
                origins.append(self.origin(parent.value))
                continue
            if isinstance(parent, ast.For) and parent.target is binding and _self_attribute(parent.iter):
                # ``for env in self.envs``: an item of what the class stores there
                origins.append(self._items_origin(parent.iter))
                continue
            return None
        return join_origins(origins)

    def _param_origin(self, param: ast.arg) -> Origin:
        origin = self._memo((id(param), "<param>"), lambda: self._callers_origin(param))
        return None if origin == CYCLE else origin  # a recursive call adds no evidence: unknown

    def _callers_origin(self, param: ast.arg) -> Origin:
        arguments = self.facts.parent(param)
        function = self.facts.parent(arguments) if arguments is not None else None  # arg -> arguments -> def
        if not isinstance(function, FUNCTIONS):
            return None
        classdef = self.facts.enclosing_class(function)
        if classdef is not None:
            if function.name == "__init__" and param.arg == "env" and self.receivers.is_gym_wrapper_class(classdef):
                return INNER
            if function.name == "__init__" and self.facts.parent(classdef) is self.facts.tree:
                return self._constructions_origin(classdef, function, param)
            return None
        if param.annotation is not None and any(
            wrapper_rest(q) == "TimeLimit" for q in self.facts.qualified_names(param.annotation)
        ):
            return MADE  # ``env: gym.wrappers.TimeLimit``: what make returns, its outermost layer
        # A module function: the env is whatever its callers in this module pass.
        params = [*function.args.posonlyargs, *function.args.args]
        position = next((i for i, p in enumerate(params) if p is param), None)
        calls = self.receivers.call_sites(function, None)
        if not calls:
            fixtures = param_fixtures(self.facts, function, param.arg)
            if not fixtures:
                # pytest gives it the fixture of that name of a conftest.py above the module,
                # unless the module parametrizes it itself
                conftest = self._conftest_fixture(function, param.arg)
                return _join_fed(conftest) if conftest is not None else None
            # A test's parameter named after a pytest fixture of the module (or parametrized
            # over fixtures with ``fixture_ref``) gets what the fixtures yield or return.
            return join_origins([self.origin(value) for fixture in fixtures for value in fixture_values(self.facts, fixture)])
        origins: list[Origin] = []
        for call in calls:
            argument = call_argument(call, position, param.arg)
            origin = self.origin(argument) if argument is not None else None
            origins.append(None if origin == CYCLE else origin)
        return join_origins(origins)

    def _constructions_origin(self, classdef: ast.ClassDef, init: ast.FunctionDef | ast.AsyncFunctionDef, param: ast.arg) -> Origin:
        """A constructor parameter of a class of this module that no other module of the run
        builds (``Adapter(env)`` after ``env = gym.make(...)``): what every construction here
        passes, as a module function's parameter is what its callers pass."""
        params = [*init.args.posonlyargs, *init.args.args]
        index = next((i for i, p in enumerate(params) if p is param), None)
        if index is None or index == 0:
            return None  # ``self``, or a keyword-only parameter
        calls, elsewhere = self.receivers.constructions(classdef)
        view = self.receivers.project
        if not calls or elsewhere or (view is not None and view.built_elsewhere(classdef.name)):
            return None
        origins: list[Origin] = []
        for call, shift in calls:
            if any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords):
                return None  # ``Adapter(*args)``: which argument lands here is not shown
            argument = call_argument(call, index - 1 + shift, param.arg)
            origin = self.origin(argument) if argument is not None else None
            origins.append(None if origin == CYCLE else origin)
        return join_origins(origins)

    def _conftest_fixture(self, function: ast.FunctionDef | ast.AsyncFunctionDef, name: str) -> list[FixtureOrigin] | None:
        """Per value of the conftest fixture pytest hands the parameter ``name`` of a test or
        fixture of this module (``ProjectView.fixture_origin``): where it comes from and what
        its outermost wrapper defines. None where the module feeds it itself, or no conftest
        of the run defines it."""
        view = self.receivers.project
        if view is None or not injected(self.facts, function) or param_values(self.facts, function, name) is not None:
            return None
        return view.fixture_origin(name)

    def _requested(self, call: ast.Call) -> list[FixtureOrigin] | None:
        """Per value of the fixtures ``request.getfixturevalue(n)`` may give (this module's
        fixture of that name, else the nearest conftest's): where it comes from and what its
        outermost wrapper defines (None: not shown). None for any other call."""
        names = requested_fixtures(self.facts, call)
        if names is None:
            return None
        found: list[FixtureOrigin] = []
        view = self.receivers.project
        for name in names:
            local = pytest_fixture(self.facts, name)
            if local is not None:
                found += [self._value_outer(value) for value in fixture_values(self.facts, local)]
                continue
            remote = view.fixture_origin(name) if view is not None else None
            found += remote if remote is not None else [(None, None)]
        return found

    def _value_outer(self, value: ast.expr) -> FixtureOrigin:
        origin = self.origin(value)
        if origin == CYCLE:
            origin = None
        return origin, (frozenset(self.outer_attributes(value)) if self.outer_wrapper(value) is not None else None)

    def _fed_by_fixtures(self, expr: ast.expr) -> list[FixtureOrigin] | None:
        """For a name that holds what pytest hands a test (its parameter named after a
        fixture, or ``request.getfixturevalue(...)`` bound to it), per value of those
        fixtures, where it comes from and what its outermost wrapper defines."""
        if not isinstance(expr, ast.Name):
            return None
        bindings = self.facts.bindings_of(expr)
        if len(bindings) != 1:
            return None
        binding = bindings[0]
        if isinstance(binding, ast.arg):
            function = self.facts.parent(self.facts.parent(binding))
            if not isinstance(function, FUNCTIONS) or self.receivers.call_sites(function, None):
                return None
            local = param_fixtures(self.facts, function, binding.arg)
            if local:
                return [self._value_outer(value) for fixture in local for value in fixture_values(self.facts, fixture)]
            return self._conftest_fixture(function, binding.arg)
        statement = self.facts.parent(binding)
        if isinstance(statement, ast.Assign) and statement.targets == [binding] and isinstance(statement.value, ast.Call):
            return self._requested(statement.value)
        return None

    def fixture_attributes(self, expr: ast.expr) -> frozenset[str] | None:
        """What every value a pytest fixture may hand ``expr`` has on its outermost layer
        without forwarding: a wrapper's own attributes, anything on a bare env (RAW). None
        where ``expr`` is no fixture's value or a value's outermost layer is not shown."""
        fed = self._fed_by_fixtures(expr)
        if not fed:
            return None
        common: frozenset[str] | None = None  # None here: every name so far (only bare envs)
        for origin, attributes in fed:
            if origin == RAW:
                continue
            if origin != WRAPPED or attributes is None:
                return frozenset()
            common = attributes if common is None else common & attributes
        return common

    def _memo(self, key: _Key, compute: Callable[[], Origin]) -> Origin:
        """``compute()``, kept for ``key`` unless it rests on an answer still being computed.

        Reached again while open, ``key`` answers CYCLE. An answer whose computation reached
        an open key below its own is provisional: reused only until that key closes (so a
        web of names still costs one visit each), then asked again. A key that closes with
        a wrapper met around itself takes it in (``_with_own_wrappers``)."""
        if key in self._final:
            return self._final[key]
        index = self._open.get(key)
        if index is not None:
            self._reach(index)
            return CYCLE
        if key in self._provisional:
            origin, low = self._provisional[key]
            self._reach(low)
            return origin
        index = self._push()
        self._open[key] = index
        try:
            origin = compute()
        finally:
            del self._open[key]
            low, rewrapped = self._pop()
        if rewrapped and origin == RAW:
            self._bare_or_wrapped.add(key)
        else:
            self._bare_or_wrapped.discard(key)
        if rewrapped:
            origin = _with_own_wrappers(origin)
        if low < index:
            self._provisional[key] = (origin, low)
            self._provisional_at[low].append(key)
        elif origin != CYCLE:  # a cycle is an answer only from inside it
            self._final[key] = origin
        return origin

    def _reaching(self, compute: Callable[[], Origin]) -> tuple[Origin, int | None]:
        """``compute()`` and the lowest entry open before it that it reached, if any."""
        index = self._push()
        try:
            origin = compute()
        finally:
            low, _ = self._pop()
        return origin, (low if low < index else None)

    def _push(self) -> int:
        index = len(self._lows)
        self._lows.append(index)
        self._rewrapped.append(False)
        self._provisional_at.append([])
        return index

    def _pop(self) -> tuple[int, bool]:
        low = self._lows.pop()
        rewrapped = self._rewrapped.pop()
        for key in self._provisional_at.pop():
            self._provisional.pop(key, None)  # rested on this entry, which is settled now
        self._reach(low)
        return low, rewrapped

    def _reach(self, index: int) -> None:
        """The computation on top of the stack rests on the open entry ``index``."""
        if self._lows and index < self._lows[-1]:
            self._lows[-1] = index

    def at_read(self, receiver: ast.expr) -> Origin:
        """The origin of what ``receiver`` holds where it is read: a name's bindings joined,
        and where they disagree, or where the name holds an env of its own class that it
        wraps on some path (``_with_own_wrappers``), what the read itself sees if that can
        be told (``above``: ``env = Arena()`` just above ``env = dress(env, env.size)``)."""
        origin = self.origin(receiver)
        if isinstance(receiver, ast.Name) and (origin is None or self._bare_or_wrapped_name(receiver)):
            seen = self.above(receiver)
            if seen is not None:
                origin = seen
        elif isinstance(receiver, ast.Attribute) and isinstance(receiver.value, ast.Name) and receiver.value.id == "self":
            # ``self._env = gym.make(id)`` above in the same method: the read sees that store,
            # whatever the attribute is given afterwards (``self._env = Preproc(self._env.env)``)
            value = store_seen(self.facts, receiver, receiver.attr)
            seen = self.origin(value) if value is not None else None
            if seen is not None:
                origin = seen
        return origin

    def _bare_or_wrapped_name(self, name: ast.Name) -> bool:
        scope, _ = self.facts.resolve(name.id, self.facts.scope_of(name))
        return scope is not None and (id(scope), name.id) in self._bare_or_wrapped

    def dominating(self, name: ast.Name) -> Origin:
        """Where the name's values disagree (``env = gym.make(...)`` in one branch, ``env =
        TakeoffAviary(...)`` later): the origin of the one assignment every path to this
        read passes last, if there is one (and it does not rebind the name from itself)."""
        flow = Flow.of(self.facts)
        last = flow.last_binding_of(name)
        statement = self.facts.statement_of(last) if isinstance(last, ast.Name) else None
        if not (isinstance(statement, ast.Assign) and statement.targets == [last]):
            return None
        if not flow.dominates(statement, name, name):
            return None
        if isinstance(statement.value, ast.Attribute) and statement.value.attr == "unwrapped":
            return RAW  # ``env = env.unwrapped``: the base env, whatever the name held before
        if any(isinstance(n, ast.Name) and n.id == name.id for n in walk(statement.value)):
            return None  # ``env = Wrapper(env)``: its origin rests on the earlier values too
        origin = self.origin(statement.value)
        return None if origin == CYCLE else origin

    def above(self, name: ast.Name) -> Origin:
        """The origin of what ``name`` holds where the other bindings disagree: in ``env =
        env.env`` the assignment just above in the same block (``env = gym.make(id)``),
        elsewhere the one assignment every path to the read passes last. A read in the value
        of the assignment (``env = dress(env, env.size)``) sees the assignment above, unless
        a lambda or def there defers it past the rebinding."""
        statement = self.facts.statement_of(name)
        if isinstance(statement, ast.Assign) and any(isinstance(t, ast.Name) and t.id == name.id for t in statement.targets):
            flow = Flow.of(self.facts)
            scope, _ = self.facts.resolve(name.id, self.facts.scope_of(name))
            if scope is None or not flow.same_frame(name, scope):
                return None
            above = flow.binding_above(name, statement)
            holder = self.facts.statement_of(above) if isinstance(above, ast.Name) else None
            if not (isinstance(holder, ast.Assign) and holder.targets == [above]):
                return None
            if any(isinstance(n, ast.Name) and n.id == name.id for n in walk(holder.value)):
                return None
            origin = self.origin(holder.value)
            return None if origin == CYCLE else origin
        return self.dominating(name)

    def nearest_assignment(self, name: ast.Name) -> ast.expr | None:
        scope, bindings = self.facts.resolve(name.id, self.facts.scope_of(name))
        if scope is None:
            return None
        key = (id(scope), name.id)
        if key not in self._assign_lines:
            found: list[tuple[int, ast.expr]] = []
            for binding in bindings:
                parent = self.facts.parent(binding)
                if not (isinstance(parent, ast.Assign) and binding in parent.targets):
                    self._assign_lines[key] = None
                    break
                found.append((parent.lineno, parent.value))
            else:
                found.sort(key=lambda item: item[0])  # stable: the first of a line stays first
                self._assign_lines[key] = ([line for line, _ in found], [value for _, value in found])
        table = self._assign_lines[key]
        if not table:
            return None
        lines, values = table
        before = bisect.bisect_left(lines, name.lineno)  # assignments on lines above the read
        if before == 0:
            return None
        return values[bisect.bisect_left(lines, lines[before - 1])]  # the first one on the nearest line

    def is_sub_env(self, receiver: ast.expr) -> bool:
        """``self.envs[i]`` in a subclass of Gym's ``SyncVectorEnv``, which never rebinds
        ``envs``: one of the envs its ``env_fns`` made."""
        if not (
            isinstance(receiver, ast.Subscript)
            and isinstance(receiver.value, ast.Attribute)
            and receiver.value.attr == "envs"
            and isinstance(receiver.value.value, ast.Name)
            and receiver.value.value.id == "self"
        ):
            return False
        classdef = self.facts.enclosing_class(receiver)
        if classdef is None or "envs" in self.receivers.self_stores(classdef):
            return False
        return any(
            N.strip_gym_prefix(q) in _SYNC_VECTOR_ENVS for base in classdef.bases for q in self.facts.qualified_names(base)
        )

    def outer_wrapper(self, expr: ast.expr) -> str | None:
        """The wrapper class that is the outermost layer of ``expr`` where it is read.

        For a name, the binding is the nearest assignment above the read in the same scope
        (``env = RecordEpisodeStatistics(env)`` then ``env.return_queue``): straight-line
        script code, which is where such reads live.
        """
        value: ast.expr | None = expr
        if isinstance(expr, ast.Name):
            value = self.nearest_assignment(expr)
            if value is None:
                value = self._looped_construction(expr)
            annotation = self._annotated_wrapper(expr) if value is None else None
            if annotation is not None:  # ``env: gym.wrappers.TimeLimit``
                named = {rest for q in self.facts.qualified_names(annotation) if (rest := wrapper_class_rest(q)) is not None}
                return current_name(named.pop()) if len(named) == 1 else None
        if not isinstance(value, ast.Call):
            return None
        names = {rest for q in self.facts.qualified_names(value.func) if (rest := wrapper_class_rest(q)) is not None}
        if len(names) == 1:
            # Its 1.x name: ``FrameStack`` is becoming FrameStackObservation in the same run.
            return current_name(names.pop())
        local = self.receivers.local_class(value.func)
        if local is not None and self.receivers.is_gym_wrapper_class(local):
            return local.name
        return None

    def _looped_construction(self, name: ast.Name) -> ast.Call | None:
        """``for env in envs:`` where ``envs = [Tracked(gym.make(i)) for i in ids]`` (or a
        list or tuple of constructions) in the same scope, bound once and never added to or
        stored into: each item the loop binds is built by one of those calls, and the first
        is returned where they all have one outermost wrapper class. None otherwise."""
        bindings = self.facts.bindings_of(name)
        # every binding of the name a loop over the same list (``for env in envs:`` to train,
        # again to evaluate): whichever reaches the read, its item is one of that list's
        iterated: list[ast.Name] = []
        for binding in bindings:
            loop = self.facts.parent(binding)
            if not (isinstance(loop, ast.For) and loop.target is binding and isinstance(loop.iter, ast.Name)):
                return None
            iterated.append(loop.iter)
        if not iterated:
            return None
        held = self.facts.bindings_of(iterated[0])
        if any(self.facts.bindings_of(other) != held for other in iterated):
            return None
        assign = self.facts.parent(held[0]) if len(held) == 1 else None
        if not (isinstance(assign, ast.Assign) and assign.targets == [held[0]]):
            return None
        if self.facts.scope_of(held[0]) is not self.facts.scope_of(bindings[0]):
            return None  # a list of an enclosing scope: what else fills it is not in view
        items: list[ast.expr]
        if isinstance(assign.value, ast.ListComp):
            items = [assign.value.elt]
        elif isinstance(assign.value, (ast.List, ast.Tuple)):
            items = list(assign.value.elts)
        else:
            return None
        if not items or not all(isinstance(item, ast.Call) for item in items):
            return None
        for read in self.facts.reads_of(iterated[0].id, held[0]):
            parent = self.facts.parent(read)
            if isinstance(parent, ast.Attribute) or (isinstance(parent, ast.Subscript) and not isinstance(parent.ctx, ast.Load)):
                return None  # ``envs.append(other)``, ``envs[0] = other``: items built elsewhere
        owners = {self.outer_wrapper(item) for item in items}
        if len(owners) != 1 or None in owners:
            return None
        return items[0]  # type: ignore[return-value]

    def _annotated_wrapper(self, name: ast.Name) -> ast.expr | None:
        """The annotation of the parameter ``name`` is, when it is its only binding."""
        bindings = self.facts.bindings_of(name)
        if len(bindings) == 1 and isinstance(bindings[0], ast.arg) and bindings[0].annotation is not None:
            return bindings[0].annotation
        return None

    def is_run_wrapper_class(self, func: ast.expr) -> bool:
        """A Gym wrapper class another module of the run defines."""
        view = self.receivers.project
        return view is not None and any(view.is_wrapper_class(q) for q in self.facts.qualified_names(func))

    def outer_is_wrapper(self, expr: ast.expr) -> bool:
        """``expr`` is, where it is read, a Gym wrapper made by a constructor call: Gymnasium's
        wrappers, this module's wrapper classes, or another module's of the run."""
        if self.outer_wrapper(expr) is not None:
            return True
        value = self.nearest_assignment(expr) if isinstance(expr, ast.Name) else expr
        return isinstance(value, ast.Call) and self.is_run_wrapper_class(value.func)

    def outer_attributes(self, expr: ast.expr) -> set[str]:
        """Attributes the outermost wrapper of ``expr`` defines itself (gymnasium's or this module's)."""
        owner = self.outer_wrapper(expr)
        if owner is None:
            fixed = self.fixture_attributes(expr)
            # only bare envs: the read needs no forwarding, whatever the name (left to RAW)
            return set(fixed) if fixed is not None else set()
        if owner in OWN_ATTRIBUTES:
            return OWN_ATTRIBUTES[owner]
        local = self.facts.classes.get(owner)
        return self.defined_attributes(local) if local is not None else set()

    def local_wrapper_attributes(self) -> set[str]:
        """Attributes and methods defined by wrapper classes of this module or of another
        module of the run (they shadow the base env's: ``play(env)`` may get one of them)."""
        if self._local_attrs is None:
            attrs: set[str] = set()
            for classdef in self.facts.classes.values():
                if self.receivers.is_gym_wrapper_class(classdef):
                    attrs |= self.defined_attributes(classdef)
            if self.receivers.project is not None:
                attrs |= self.receivers.project.run_wrapper_attributes()
            self._local_attrs = attrs
        return self._local_attrs

    def defined_attributes(self, classdef: ast.ClassDef) -> set[str]:
        names = self._class_attrs.get(classdef)
        if names is None:
            names = self._class_attrs[classdef] = _defined_attributes(classdef)
        return names

def _self_attribute(expr: ast.expr) -> bool:
    """``self.envs``: an attribute of the instance a method reads."""
    return isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and expr.value.id == "self"


def _factory_item(facts: ModuleFacts, binding: ast.AST) -> tuple[ast.Call, tuple[int, int | None] | None] | None:
    """The factory call a name's binding takes a thunk from, and which item of its return
    (None: all of it): ``create = f(x)``, ``create = f(x)[0]`` ((0, None): any size),
    ``create, _ = f(x)`` ((0, 2)). None for any other binding."""
    parent = facts.parent(binding) if isinstance(binding, ast.Name) else None
    if isinstance(parent, ast.Assign) and parent.targets == [binding]:
        return _called_factory(parent.value)
    if isinstance(parent, ast.Tuple) and not any(isinstance(e, ast.Starred) for e in parent.elts):
        assign = facts.parent(parent)
        if isinstance(assign, ast.Assign) and assign.targets == [parent] and isinstance(assign.value, ast.Call):
            return assign.value, (parent.elts.index(binding), len(parent.elts))  # type: ignore[arg-type]
    return None


def _called_factory(value: ast.expr) -> tuple[ast.Call, tuple[int, int | None] | None] | None:
    """``f(x)`` (the whole return) or ``f(x)[0]`` ((0, None): that item, of a tuple of any
    size) as a callable: the factory call and which item of its return. None otherwise."""
    if isinstance(value, ast.Call):
        return value, None
    index = value.slice if isinstance(value, ast.Subscript) else None
    if isinstance(value, ast.Subscript) and isinstance(value.value, ast.Call) and isinstance(index, ast.Constant) and type(index.value) is int:
        return value.value, (index.value, None)
    return None


def _join_fed(fed: list[FixtureOrigin]) -> Origin:
    """Where the values fixtures hand one name come from: a bare env in some and a wrapper
    in others, every one shown, is read with get_wrapper_attr (a Gymnasium env has it too,
    bare or wrapped), as a wrapper."""
    origins = [origin for origin, _ in fed]
    joined = join_origins(origins)
    if joined is None and RAW in origins and None not in origins and CYCLE not in origins:
        return WRAPPED
    return joined


def _defined_attributes(classdef: ast.ClassDef) -> set[str]:
    """Methods (at any depth) and ``self.x = ...`` targets of a class, unpacked ones too
    (``self.obs, info = self.env.reset()``, as the migrated reset stores it)."""
    names: set[str] = set()
    for node in walk(classdef):
        if isinstance(node, FUNCTIONS):
            names.add(node.name)
        elif isinstance(node, ast.Assign):
            targets = list(node.targets)
            while targets:
                target = targets.pop()
                if isinstance(target, (ast.Tuple, ast.List)):
                    targets.extend(target.elts)
                elif isinstance(target, ast.Starred):
                    targets.append(target.value)
                elif isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self":
                    names.add(target.attr)
    return names


def _walks_down(value: ast.expr, name: str) -> bool:
    """``name.env`` / ``name.env.env``: a layer of the stack the name already holds."""
    while isinstance(value, ast.Attribute) and value.attr == "env":
        value = value.value
    return isinstance(value, ast.Name) and value.id == name and not isinstance(value, ast.Attribute)

