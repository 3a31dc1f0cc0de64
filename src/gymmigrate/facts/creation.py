"""Where was this env created? Finds the creation calls (``gym.make(...)``) behind an expression.

Rendering (GM401-GM403, GM407) and vector rules (GM705, GM706) must change the call
that *created* an env, not the call site that uses it: Gymnasium fixes the render mode
and the vector autoreset mode at construction. This module follows an expression back
to those calls through the same evidence the receiver analysis trusts: bindings of a
name (``env = gym.make(...)``, then ``env = SomeWrapper(env)``), ``self.env = ...``
stores in the same class, ``with ... as env``, returns of functions defined in the
module, arguments at the call sites of a module-level function, and the env factories
in a ``DummyVecEnv([lambda: gym.make(...)])`` list.

The answer says whether the search was complete: a rule may only rewrite a creation
site when every path was followed (a parameter, an import or an unknown factory makes
the answer incomplete, and the rule reports instead).

Every answer is memoized per node, and a node reached again while its own answer is
being computed adds nothing (``env = Wrapper(env)`` loops back to itself), so a chain
of rebindings costs linear time; past ``MAX_DEPTH`` nested steps the search gives up
as incomplete instead of nearing the interpreter's recursion limit.

Which ``render`` calls pass a legacy mode, and the env classes that must keep one (and so
are no creation site for a render mode), are ``render_modes``.
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from dataclasses import dataclass, field

from gymmigrate.facts import names as N
from gymmigrate.facts import same_tests
from gymmigrate.facts.creation_shapes import (
    argument_for,
    changed_in_place,
    enumerated_iterable,
    first_argument,
    last_name,
    nested_function,
    property_slot,
    return_values,
    wrapped_env_argument,
)
from gymmigrate.facts.flow import Flow, contains
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts
from gymmigrate.facts.receivers import Receivers

# SB3 / baselines / Gym VecEnv constructors that take a list of env factories.
ENV_FN_LIST_CONSTRUCTORS = ("DummyVecEnv", "SubprocVecEnv", "SyncVectorEnv", "AsyncVectorEnv")
# Far deeper than any real chain of rebindings and wrappers.
MAX_DEPTH = 150


@dataclass
class Creation:
    """The creation calls found for one expression, and whether the search was complete."""

    calls: list[ast.Call] = field(default_factory=list)
    complete: bool = True
    # Why the search stopped, for the report ("`env` is a function parameter").
    gap: str = ""
    # Calls of defs of other modules of the run that return make(...) results: each a make,
    # made where this module cannot edit (``ProjectView.made_at``)
    made_elsewhere: list[ast.Call] = field(default_factory=list)
    untraced: bool = False  # the search stopped somewhere else too (not at such a call)

    def add(self, call: ast.Call) -> None:
        if not any(c is call for c in self.calls):
            self.calls.append(call)

    def merge(self, other: Creation) -> None:
        for call in other.calls:
            self.add(call)
        self.made_elsewhere.extend(c for c in other.made_elsewhere if not any(c is m for m in self.made_elsewhere))
        self.untraced = self.untraced or other.untraced
        if not other.complete:
            self.complete = False
            self.gap = self.gap or other.gap

    def fail(self, gap: str, made_elsewhere: ast.Call | None = None) -> None:
        self.complete = False
        self.gap = self.gap or gap
        if made_elsewhere is None:
            self.untraced = True
        else:
            self.made_elsewhere.append(made_elsewhere)

    def copy(self) -> Creation:
        return Creation(list(self.calls), self.complete, self.gap, list(self.made_elsewhere), self.untraced)

    @property
    def found(self) -> bool:
        return self.complete and bool(self.calls)


_NOTHING = Creation()  # what a node adds while its own answer is being computed


class CreationFinder:
    """Follows expressions of one module back to the calls that created them.

    ``is_creation(call)`` says which calls end the search (``gym.make`` for render
    modes; vector constructors for autoreset); every other call is followed only if it
    looks like a wrapper around its first argument. Each finder keeps its own memo, so
    finders with different ``is_creation`` never share answers.
    """

    def __init__(
        self, facts: ModuleFacts, receivers: Receivers, is_creation: Callable[[ast.Call], bool], nesting: int = 0
    ) -> None:
        self.facts = facts
        self.receivers = receivers
        self._is_creation = is_creation
        self._nesting = nesting  # finders started for constructor arguments, around this one
        self._memo: dict[tuple[str, int], Creation] = {}
        self._open: set[tuple[str, int]] = set()  # the answers being computed
        self._cycles: list[set[tuple[str, int]]] = []  # per answer being computed: the open ones it met
        self._depth = 0

    def find(self, expr: ast.AST) -> Creation:
        """The creation calls behind ``expr`` (a fresh object: callers may annotate it)."""
        return self._follow(expr, self._expr).copy()

    def reached(self, expr: ast.AST) -> bool:
        """A search of this finder went through ``expr`` (and kept its answer): what ``expr``
        makes flows into an expression asked about (``env = Wrapper(made)`` on the way from
        a make to a render of the wrapper)."""
        return ("_expr", id(expr)) in self._memo

    # -- memo -----------------------------------------------------------------------------

    def _follow(self, node: ast.AST, compute: Callable[[ast.AST], Creation]) -> Creation:
        return self._memoized((compute.__name__, id(node)), lambda: compute(node))

    def _memoized(self, key: tuple[str, int], compute: Callable[[], Creation]) -> Creation:
        """One answer per node. A node reached again while its own answer is being computed
        (a cycle: ``env = Monitor(env)`` reads the binding it makes) adds nothing there; an
        answer computed through such an unfinished node is partial, so it is not kept: the
        next question recomputes it (asked first from inside the cycle, ``env`` of
        ``Monitor(env)`` had been kept with no creation)."""
        known = self._memo.get(key)
        if known is not None:
            if key in self._open:
                self._cycles[-1].add(key)
            return known
        if self._depth >= MAX_DEPTH:
            result = Creation()
            result.fail("the chain of assignments is too long to follow")
            return result
        self._memo[key] = _NOTHING
        self._open.add(key)
        self._cycles.append(set())
        self._depth += 1
        try:
            result = compute()
        finally:
            self._depth -= 1
            self._open.discard(key)
            cycles = self._cycles.pop()
        cycles.discard(key)
        if cycles:
            del self._memo[key]
            if self._cycles:
                self._cycles[-1].update(cycles)
        else:
            self._memo[key] = result
        return result

    # -- expressions --------------------------------------------------------------------

    def _expr(self, expr: ast.AST) -> Creation:
        if isinstance(expr, ast.Call):
            return self._call(expr)
        if isinstance(expr, ast.Name):
            return self._name(expr)
        if isinstance(expr, ast.Attribute):
            return self._attribute(expr)
        result = Creation()
        if isinstance(expr, ast.IfExp):
            result.merge(self._follow(expr.body, self._expr))
            result.merge(self._follow(expr.orelse, self._expr))
            return result
        if isinstance(expr, ast.NamedExpr):
            return self._follow(expr.value, self._expr)
        if isinstance(expr, ast.Subscript):
            return self._items(expr.value)
        if isinstance(expr, ast.Constant) and expr.value is None:
            # ``env = None`` before ``if env is None: env = gym.make(...)``: a sentinel no
            # env method can be called on, so it creates nothing the search has to find
            # (a name that is only ever None is reported by ``_bindings``).
            return result
        result.fail(f"`{self.facts.segment(expr)}` is not a call or a name")
        return result

    def _items(self, container: ast.AST) -> Creation:
        """The envs held in a list: ``envs[0]``, ``for env in envs``."""
        return self._follow(container, self._compute_items) if isinstance(container, ast.Name) else self._compute_items(container)

    def _compute_items(self, container: ast.AST) -> Creation:
        result = Creation()
        if isinstance(container, (ast.List, ast.Tuple)):
            for element in container.elts:
                if isinstance(element, ast.Starred):
                    result.fail("a starred element")
                else:
                    result.merge(self._follow(element, self._expr))
            return result
        if isinstance(container, (ast.ListComp, ast.GeneratorExp)):
            return self._follow(container.elt, self._expr)
        if isinstance(container, ast.Attribute) and isinstance(container.value, ast.Name) and container.value.id == "self":
            # ``self.envs = [gym.make(...) for _ in range(n)]`` in the class, and never changed
            # in place (an ``append`` there may add anything)
            values = self.receivers.self_attribute_values(container, container.attr)
            classdef = self.facts.enclosing_class(container)
            if not values or classdef is None or changed_in_place(classdef, container.attr):
                result.fail(f"`{self.facts.segment(container)}` is not a list built here")
            for value in values:
                result.merge(self._items(value))
            return result
        if isinstance(container, ast.Name):
            bindings = self.facts.bindings_of(container)
            if not bindings:
                result.fail(f"`{container.id}` is never assigned here")
            for binding in bindings:
                assign = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
                if isinstance(assign, ast.Assign):
                    result.merge(self._items(assign.value))
                else:
                    result.fail(f"`{container.id}` is not a list built here")
            return result
        result.fail(f"`{self.facts.segment(container)}` is not a list built here")
        return result

    def _call(self, call: ast.Call) -> Creation:
        result = Creation()
        if self._is_creation(call):
            result.add(call)
            return result
        first = first_argument(call)
        if last_name(call.func) in ENV_FN_LIST_CONSTRUCTORS and first is not None:
            return self._env_fn_list(first)
        function = self.receivers.local_function(call.func)
        if function is not None:
            return self._follow(function, self._returns)
        inner = wrapped_env_argument(call)
        if inner is not None and self._looks_like_wrapper(call.func):
            return self._follow(inner, self._expr)
        looped = self._loop_wrapped(call)
        if looped is not None:
            return self._follow(looped, self._expr)
        if isinstance(call.func, ast.Name) and not self.facts.qualified_names(call.func) and self.facts.bindings_of(call.func):
            return self._follow(call.func, self._called)
        own = self.receivers.own_method(call.func)  # ``self.env = self.make_env()``
        if own is not None:
            return self._follow(own, self._returns)
        handed_on = self.receivers.wrapped_argument(call)
        if handed_on is not None:
            # ``env = make_env(env)`` with a def of the run that only wraps its argument and
            # returns it: the env was created where that argument was.
            return self._follow(handed_on, self._expr)
        project = self.receivers.project
        for qualified in self.facts.qualified_names(call.func) if project is not None else ():
            where = project.made_at(qualified)  # type: ignore[union-attr]
            if where is not None:
                # A factory of another module of the run: its make is the creation site, in
                # a file this one cannot edit; the question names it.
                result.fail(f"`{self.facts.segment(call.func)}(...)` makes it with {where}, in another module", call)
                return result
        result.fail(f"`{self.facts.segment(call.func)}(...)` is not a known env factory")
        return result

    def _called(self, callee: ast.AST) -> Creation:
        """What calling ``callee`` creates: ``make_env = lambda: gym.make(...)``, a nested
        ``def thunk()``, an ``env_fn`` parameter given such callables at its call sites."""
        result = Creation()
        if isinstance(callee, ast.Lambda):
            return self._follow(callee.body, self._expr)
        if isinstance(callee, FUNCTIONS):
            return self._follow(callee, self._returns)
        if not isinstance(callee, ast.Name):
            result.fail(f"`{self.facts.segment(callee)}` is not a factory defined here")
            return result
        function = self.receivers.local_function(callee)
        if function is not None:
            return self._follow(function, self._returns)
        for binding in self.facts.bindings_of(callee):
            parent = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
            if isinstance(binding, FUNCTIONS):
                result.merge(self._follow(binding, self._returns))
            elif isinstance(parent, ast.Assign):
                result.merge(self._follow(parent.value, self._called))
            elif isinstance(binding, ast.arg):
                result.merge(self._parameter_factories(binding))
            else:
                result.fail(f"`{callee.id}` is not a factory defined here")
        return result

    def _parameter_factories(self, param: ast.arg) -> Creation:
        """``def run(env_fn): env = env_fn()``: the factories passed at its call sites here."""
        result = Creation()
        function = self.facts.parent(self.facts.parent(param))
        if not isinstance(function, FUNCTIONS) or self.facts.parent(function) is not self.facts.tree:
            result.fail(f"`{param.arg}` is a function parameter")
            return result
        params = [*function.args.posonlyargs, *function.args.args]
        position = next((i for i, p in enumerate(params) if p is param), None)
        calls = self.receivers.call_sites(function, None)
        if not calls:
            result.fail(f"`{param.arg}` is a parameter of `{function.name}`, which is not called here")
        for call in calls:
            argument = argument_for(call, param.arg, position)
            if argument is None:
                result.fail(f"`{param.arg}` is not passed at every call of `{function.name}`")
            else:
                result.merge(self._follow(argument, self._called))
        return result

    def _env_fn_list(self, fns: ast.AST) -> Creation:
        """``[lambda: gym.make(...)]``, ``[make_env(i) for i in range(n)]``, ``[fn] * n``."""
        result = Creation()
        if isinstance(fns, ast.BinOp) and isinstance(fns.op, ast.Mult):
            fns = fns.left
        if isinstance(fns, (ast.List, ast.Tuple)):
            items = list(fns.elts)
        elif isinstance(fns, (ast.ListComp, ast.GeneratorExp)):
            items = [fns.elt]
        else:
            result.fail(f"`{self.facts.segment(fns)}` is not a list of env factories")
            return result
        for item in items:
            if isinstance(item, ast.Lambda):
                result.merge(self._follow(item.body, self._expr))
            elif isinstance(item, ast.Name) and self.receivers.local_function(item) is not None:
                result.merge(self._follow(self.receivers.local_function(item), self._returns))  # type: ignore[arg-type]
            elif isinstance(item, ast.Call) and self.receivers.local_function(item.func) is not None:
                # ``make_env(i)`` returning a thunk ``def thunk(): return gym.make(...)``
                result.merge(self._thunk_factory(self.receivers.local_function(item.func)))  # type: ignore[arg-type]
            else:
                result.fail(f"`{self.facts.segment(item)}` is not an env factory defined here")
        return result

    def _thunk_factory(self, function: ast.FunctionDef | ast.AsyncFunctionDef) -> Creation:
        result = Creation()
        returned = return_values(function)
        if not returned:
            result.fail(f"`{function.name}` returns nothing")
        for value in returned:
            if isinstance(value, ast.Lambda):
                result.merge(self._follow(value.body, self._expr))
                continue
            inner = nested_function(function, value)
            if inner is None:
                result.fail(f"`{function.name}` does not return an env factory")
            else:
                result.merge(self._follow(inner, self._returns))
        return result

    def _returns(self, function: ast.AST) -> Creation:
        result = Creation()
        values = return_values(function)
        if not values:
            result.fail(f"`{function.name}` returns nothing")  # type: ignore[attr-defined]
        for value in values:
            result.merge(self._follow(value, self._expr))
        return result

    # -- names ----------------------------------------------------------------------------

    def _name(self, name: ast.Name) -> Creation:
        # A read that one assignment certainly reaches (``env = gym.make(...)`` above it in
        # the block, a notebook cell that makes its env) sees that value alone, whatever
        # other cells or branches bind the name to later.
        flow = Flow.of(self.facts)
        last = flow.last_binding_of(name)
        statement = self.facts.statement_of(last) if isinstance(last, ast.Name) else None
        rebinding = isinstance(statement, ast.Assign) and contains(statement.value, name)
        if rebinding:
            # ``env = Monitor(env, ...)``: the read sees the assignment just above it in the
            # same block (``binding_above`` checks both)
            last = flow.binding_above(name, statement)  # type: ignore[arg-type]
            statement = self.facts.statement_of(last) if isinstance(last, ast.Name) else None
        if (
            isinstance(statement, ast.Assign)
            and not contains(statement, name)
            and last in statement.targets
            and (rebinding or flow.dominates(statement, name, name))
        ):
            return self._follow(last, self._binding)
        reaching = flow.reaching(name) if same_tests.guards(self.facts, name) else None
        if reaching:
            # ``if MODE == "cart": env = gym.make(...)`` read under the same unchanged test
            # later: the branches that test it the other way bind nothing this read sees.
            cut = same_tests.excluded(self.facts, name, reaching)
            if cut:
                return self._bindings(name, [b for b in reaching if id(b) not in cut])
        # Every read that resolves to the same bindings has the same answer: one
        # computation per (scope, name), not per read (a chain of n rebindings has n reads).
        bindings = self.facts.bindings_of(name)
        return self._follow_bindings(name, bindings)

    def _follow_bindings(self, name: ast.Name, bindings: list[ast.AST]) -> Creation:
        if not bindings:  # an unbound name's empty list is a fresh object: nothing to share
            return self._bindings(name, bindings)
        return self._memoized(("bindings", id(bindings)), lambda: self._bindings(name, bindings))

    def _bindings(self, name: ast.Name, bindings: list[ast.AST]) -> Creation:
        result = Creation()
        if not bindings:
            result.fail(f"`{name.id}` is never assigned here")
        for binding in bindings:
            if isinstance(binding, ast.alias):
                result.fail(f"`{name.id}` is imported or a builtin")
                continue
            result.merge(self._follow(binding, self._binding))
        if result.complete and not result.calls:
            result.fail(f"`{name.id}` is never bound to a call here")
        return result

    def _binding(self, binding: ast.AST) -> Creation:
        if isinstance(binding, ast.arg):
            return self._parameter(binding)
        label = getattr(binding, "id", None) or getattr(binding, "name", None) or "?"
        parent = self.facts.parent(binding)
        if isinstance(binding, ast.Name):
            if isinstance(parent, ast.Assign):
                return self._follow(parent.value, self._expr)
            if isinstance(parent, ast.AnnAssign) and parent.value is not None:
                return self._follow(parent.value, self._expr)
            if isinstance(parent, ast.NamedExpr):
                return self._follow(parent.value, self._expr)
            if isinstance(parent, ast.withitem):
                return self._follow(parent.context_expr, self._expr)
            if isinstance(parent, (ast.For, ast.AsyncFor, ast.comprehension)) and parent.target is binding:
                return self._items(parent.iter)
            enumerated = enumerated_iterable(self.facts, binding)
            if enumerated is not None:
                return self._items(enumerated)  # ``for i, env in enumerate(envs)``
            if isinstance(parent, ast.Delete):
                return Creation()  # ``del env`` creates nothing
        result = Creation()
        result.fail(f"`{label}` is assigned in a way that is not followed")
        return result

    def _parameter(self, param: ast.arg) -> Creation:
        """A parameter of a module-level function: the arguments at its call sites in this module."""
        result = Creation()
        label = param.arg
        function = self.facts.parent(self.facts.parent(param))  # arg -> arguments -> def
        if isinstance(function, FUNCTIONS) and function.name == "__init__":
            return self._constructor_parameter(param, function)
        if not isinstance(function, FUNCTIONS) or self.facts.parent(function) is not self.facts.tree:
            result.fail(f"`{label}` is a function parameter")
            return result
        params = [*function.args.posonlyargs, *function.args.args]
        position = next((i for i, p in enumerate(params) if p is param), None)
        calls = [
            c
            for c in self.receivers.call_sites(function, None)
            if not any(isinstance(a, ast.Starred) for a in c.args) and not any(k.arg is None for k in c.keywords)
        ]
        if not calls:
            result.fail(f"`{label}` is a parameter of `{function.name}`, which is not called here")
            return result
        for call in calls:
            argument = argument_for(call, label, position)
            if argument is None:
                result.fail(f"`{label}` is not passed at every call of `{function.name}`")
            else:
                result.merge(self._follow(argument, self._expr))
        return result

    def _constructor_parameter(self, param: ast.arg, init: ast.FunctionDef | ast.AsyncFunctionDef) -> Creation:
        """``class Agent: def __init__(self, env): self.env = env`` with ``Agent(gym.make(...))``:
        the arguments where this module builds the class or a subclass of it (``super().__init__(env)``
        included). Complete only when nothing else can build it: no call or subclass in another
        module of the run."""
        result = Creation()
        label = param.arg
        classdef = self.facts.parent(init)
        if not isinstance(classdef, ast.ClassDef) or self.facts.parent(classdef) is not self.facts.tree:
            result.fail(f"`{label}` is a function parameter")
            return result
        params = [*init.args.posonlyargs, *init.args.args][1:]  # without ``self``
        position = next((i for i, p in enumerate(params) if p is param), None)
        # Every call that runs this ``__init__``: the class's own calls and its subclasses'
        # (inherited ``__init__``, ``super().__init__(env)``), as the receiver analysis finds them.
        constructions, subclassed_elsewhere = self.receivers.constructions(classdef)
        project = self.receivers.project
        elsewhere = subclassed_elsewhere or (
            project is not None and any(project.param_kinds(qualname, label) for qualname in (classdef.name, f"{classdef.name}.__init__"))
        )
        calls = [
            (c, shift)
            for c, shift in constructions
            if shift or isinstance(c.func, ast.Attribute) or self.receivers.local_class(c.func) is not None
        ]
        if elsewhere or not calls or len(calls) != len(constructions):
            result.fail(f"`{label}` is a parameter of `{classdef.name}`, which is not only built here")
            return result
        if self._nesting >= _MAX_NESTING:
            result.fail("envs passed through too many constructors")
            return result
        arguments = CreationFinder(self.facts, self.receivers, self._is_creation, self._nesting + 1)
        for call, shift in calls:
            argument = argument_for(call, label, None if position is None else position + shift)
            if argument is None or any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords):
                result.fail(f"`{label}` is not passed at every construction of `{classdef.name}`")
            else:
                # A finder of its own: this search may have entered the class from the very
                # name the argument reads (``env = Monitor(env)`` after ``Agent(env)``), and
                # answers memoized inside that open cycle would be partial.
                result.merge(arguments.find(argument))
        return result


    def _attribute(self, attr: ast.Attribute) -> Creation:
        result = Creation()
        if isinstance(attr.value, ast.Name) and attr.value.id == "self":
            classdef = self.facts.enclosing_class(attr)
            if classdef is None:
                result.fail("`self` outside a class")
                return result
            # where the class stores none, what a base class of this module stores: the
            # inherited ``__init__`` set it (``DQNAgent(Agent)`` reads Agent's ``self.env``)
            values = self.receivers.self_stores(classdef).get(attr.attr, []) or self.receivers.self_attribute_values(attr, attr.attr)
            if not values:
                result.fail(f"`self.{attr.attr}` is never assigned in the class")
            for value in values:
                result.merge(self._follow(value, self._expr))
            return result
        held = self._held_by_own_object(attr)
        if held:
            for value in held:
                result.merge(self._follow(value, self._expr))
            return result
        if attr.attr in ("env", "unwrapped", "venv"):
            # ``wrapper.env`` / ``env.unwrapped``: the same underlying env
            return self._follow(attr.value, self._expr)
        result.fail(f"`{self.facts.segment(attr)}` is not followed")
        return result

    def _held_by_own_object(self, attr: ast.Attribute) -> list[ast.expr]:
        """``player.env`` where ``player`` is only ever built by a class of this module that is
        no env nor wrapper (``Player(model, env)``): what that class stores in ``self.env``
        (its constructor's parameter, followed to the constructions), not ``player``'s first
        argument as for a wrapper's ``.env``; for a plain class of another module of the run
        that holds the attribute from a constructor parameter (``ProjectView.held_slot``), the
        argument the construction passes there. Empty when that is not the shape."""
        if not isinstance(attr.value, ast.Name):
            return []
        # the bindings that reach the read (``env = make(...)`` then ``env = Holder(env)``
        # at module level: the holder), or every one when the flow cannot say
        bindings = Flow.of(self.facts).reaching(attr.value) or self.facts.bindings_of(attr.value)
        project = self.receivers.project
        values: list[ast.expr] = []
        for binding in bindings:
            statement = self.facts.parent(binding)
            if not (isinstance(statement, ast.Assign) and statement.targets == [binding] and isinstance(statement.value, ast.Call)):
                return []
            call = statement.value
            classdef = self.receivers.local_class(call.func)
            if classdef is not None:
                if self.receivers.class_kind(classdef) not in (EnvKind.UNKNOWN, EnvKind.NOT_ENV):
                    return []
                stores = self.receivers.self_stores(classdef)
                stored = stores.get(attr.attr) or stores.get(property_slot(classdef, attr.attr) or "", [])
                if not stored:
                    return []
                values.extend(stored)
                continue
            # A plain holder class of another module of the run: the argument this very
            # construction passes for the parameter the attribute holds.
            slots = {slot for q in self.facts.qualified_names(call.func) if project is not None and (slot := project.held_slot(q, attr.attr))}
            if len(slots) != 1 or any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords):
                return []
            param, position = slots.pop()
            argument = argument_for(call, param, position)
            if argument is None:
                return []
            values.append(argument)
        return values

    def _loop_wrapped(self, call: ast.Call) -> ast.Name | None:
        """``for wrapper in wrappers: env = wrapper(env)``: the env that goes through the
        loop, whose creation is the creation of what comes out (each pass hands the
        wrapped env on). Only when the loop variable is bound by that loop alone, the call
        rebinds the very name it is given. A list written here must hold only wrapper
        classes (``[TimeLimit, FrameStack]``), not functions that may make another env; a
        list handed in (a parameter) is followed: whatever it holds is given the env and
        its result goes on, so the make before the loop is where that env was created."""
        func, inner = call.func, wrapped_env_argument(call)
        assign = self.facts.parent(call)
        if not (
            isinstance(func, ast.Name)
            and isinstance(inner, ast.Name)
            and isinstance(assign, ast.Assign)
            and assign.value is call
            and [t.id for t in assign.targets if isinstance(t, ast.Name)] == [inner.id]
            and len(assign.targets) == 1
        ):
            return None
        bindings = self.facts.bindings_of(func)
        loop = self.facts.parent(bindings[0]) if len(bindings) == 1 else None
        if not (isinstance(loop, (ast.For, ast.AsyncFor)) and loop.target is bindings[0]):
            return None
        if not any(ancestor is loop for ancestor in self.facts.ancestors(call)):
            return None
        items = loop.iter
        if isinstance(items, ast.Name):
            values = self.facts.assigned_values(items)
            items = values[0] if values is not None and len(values) == 1 else items
        if isinstance(items, (ast.List, ast.Tuple)) and not all(
            isinstance(element, (ast.Name, ast.Attribute)) and self._looks_like_wrapper(element)
            for element in items.elts
        ):
            return None
        return inner

    def _looks_like_wrapper(self, func: ast.expr) -> bool:
        """``SomeWrapper`` of ``SomeWrapper(env, ...)``: a gym wrapper, a wrapper class of
        this module, or a class."""
        for q in self.facts.qualified_names(func):
            rest = N.strip_gym_prefix(q)
            if rest is not None:
                return rest.startswith("wrappers.")
            if q.startswith(N.SB3_VEC_PREFIXES) or N.top_package(q) in N.SB3_PACKAGES:
                return q.rsplit(".", 1)[-1][:1].isupper()
            if N.top_package(q) in N.NOT_ENV_PACKAGES:
                return False
        if self.receivers.local_class(func) is not None:
            return True
        name = last_name(func)
        return name[:1].isupper() and not name.isupper()


_MAX_NESTING = 3  # constructor arguments followed through constructors
