"""Why an env's ``done`` is True: a step or time limit the env counts (a truncation in
Gymnasium), the task's own end (a termination), or both.

``DoneTracer.trace(expr)`` follows a done value to its causes inside one class:

* a comparison of a step or time counter with a bound (``self.t >= self.max_steps``,
  ``self.step_counter / self.SIM_FREQ > self.EPISODE_LEN_SEC``) is a limit. A counter is
  named like one (``STEP_LIMIT_WORD``) or is an attribute (or a named entry of a dict the
  env holds, ``self.state["count"]``) the class's ``step`` advances by a fixed amount on
  every call (``self.n += 1`` at the top of ``step``), unless it is named as a place or an
  amount (``self.agent_pos``). A test of a period (``self.t % FREQ == 0``) is not a limit;
* a local assigned in the same function, ``self.flag`` as the class stores it, ``True``
  stored or returned under ``if <limit>:``, ``True if <limit> else False``, ``bool(...)``;
  a local unpacked from a tuple (``rewards, over = self.score(infos)``: the value in its
  place of what the helper returns); a parameter, as what the call being followed passes;
* ``self.helper(...)`` through every return of the helper and of its overrides (subclasses
  of the module, and of the run: the caller passes what the run's summaries give), its
  parameters holding the call's arguments, and ``self.helper()["__all__"]`` through the
  key's stores in the dict the helper returns;
* ``self.inner.helper()`` where the class stores an instance of a class of the module
  in ``self.inner``.

The result is certain only as far as the code shows it: anything the tracer cannot see
into is a termination (what ``done`` meant before truncation existed), and a limit mixed
into a test in any other way than ``a or <limit>``, or into a collection of flags (per
agent: a dict, ``tuple(done for _ in agents)``), makes the cause UNKNOWN, with the limits
it found, so that a report can name them.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Callable

from gymmigrate.facts.done_causes import (
    NEVER,
    TERMINATION,
    Cause,
    DoneCause,
    Limit,
    combine,
)
from gymmigrate.facts.limit_tests import (
    LIMIT_OPS,
    compares_the_action,
    data_end_attributes,
    elapsed_since_step_mark,
    is_dm_env_last,
    is_end_of_data,
    is_limit_setting_test,
    is_periodic,
    is_self,
    is_step_limit,
    limit_under_guard,
    random_bound,
    self_field,
    streak_attributes,
    under_limit,
    unwrap_bool,
)
from gymmigrate.facts.module import (
    FUNCTIONS,
    ModuleFacts,
    own_returns,
    self_attribute,
    walk,
)
from gymmigrate.facts.self_attributes import self_stores

# An attribute named as a place or an amount (``self.agent_pos += 1``) that reaches a bound is
# the task's goal even when step advances it every call: not taken for a step count.
_PLACE_WORD = re.compile(
    r"(^|_)(pos|position|loc|location|coord|coords|x|y|z|dist|distance|height|depth|level|score|"
    r"energy|health|fuel|money|balance|cash|stock|inventory)(_|$)"
)
# Deep enough for a flag handed through a helper's arguments and a tuple another method
# returns (``rewards, over = self.score(infos)``, ``return self.per_agent(dones, over)``).
_MAX_DEPTH = 12


def _opaque(found: DoneCause) -> DoneCause:
    """A value that hides what it holds (``not <limit>``, ``a and b``, a dict)."""
    return DoneCause(Cause.UNKNOWN, found.limits) if found.limits else TERMINATION


def _held_read(expr: ast.AST) -> bool:
    """``self.<held>.<name>``: an attribute of an object the instance holds, read as it is."""
    return (
        isinstance(expr, ast.Attribute)
        and isinstance(expr.ctx, ast.Load)
        and isinstance(expr.value, ast.Attribute)
        and is_self(expr.value.value)
    )


Method = ast.FunctionDef | ast.AsyncFunctionDef
# Overrides of a method that other modules of the run define: (method name, the position of
# the value in the tuple it returns, None for the whole value) -> their causes.
External = Callable[[str, "int | None"], list[DoneCause]]
# What the parameters of a method hold while a call of it is followed: for each parameter,
# the tracer of the caller and the argument (or the callee's and the default).
Arguments = dict[str, tuple["DoneTracer", ast.expr]]


class DoneTracer:
    """Traces done values of one class of a module (see the module docstring)."""

    def __init__(self, facts: ModuleFacts, classdef: ast.ClassDef, external: External | None = None) -> None:
        self.facts = facts
        self.classdef = classdef
        self.external = external
        self.methods: dict[str, Method] = {m.name: m for m in classdef.body if isinstance(m, FUNCTIONS)}
        self._counters: set[str] | None = None
        self.data_ends = data_end_attributes(facts, classdef)
        self.streaks = streak_attributes(facts, classdef)
        self._subclasses: list[ast.ClassDef] | None = None
        self._busy: set[tuple[str, int] | tuple[str, int, str]] = set()

    def tracer_of(self, classdef: ast.ClassDef) -> DoneTracer:
        if classdef is self.classdef:
            return self
        key = ("done-tracer", id(classdef))
        return self.facts.memo(key, lambda: DoneTracer(self.facts, classdef))

    # -- limits ---------------------------------------------------------------------------

    @property
    def counters(self) -> set[str]:
        """What ``step`` advances by a fixed amount on every call: ``self.n += 1`` (or
        ``self.t = self.t + self.dt``), or a named entry of a dict the env holds
        (``self.state["count"] += 1``, ``limit_tests.self_field``), among the top-level
        statements of ``step``."""
        if self._counters is None:
            found: set[str] = set()
            step = self.methods.get("step") or self.methods.get("_step")
            for statement in step.body if step is not None else ():
                if isinstance(statement, ast.AugAssign) and isinstance(statement.op, (ast.Add, ast.Sub)):
                    field = self_field(statement.target)
                    if field is not None and _fixed(statement.value) and not _PLACE_WORD.search(field[1]):
                        found.add(field[0])
                elif isinstance(statement, ast.Assign) and len(statement.targets) == 1:
                    field = self_field(statement.targets[0])
                    value = statement.value
                    if (
                        field is not None
                        and isinstance(value, ast.BinOp)
                        and isinstance(value.op, (ast.Add, ast.Sub))
                        and self_field(value.left) == field
                        and _fixed(value.right)
                        and not _PLACE_WORD.search(field[1])
                    ):
                        found.add(field[0])
            self._counters = found
        return self._counters

    def is_limit(self, expr: ast.AST) -> bool:
        """A comparison of a step or time counter with a bound (not the end of the data)."""
        if isinstance(expr, ast.Compare) and is_limit_setting_test(expr) and not self._counter(_nonzero_side(expr)):
            return False  # ``if self.t_limit > 0:`` picks a mode; its ``else`` is no limit reached
        if elapsed_since_step_mark(self.facts, expr):
            return False  # time since the task's own event, which the step marks again
        if isinstance(expr, ast.Compare) and compares_the_action(self.facts, expr):
            return False  # the action the step was given is neither a count nor its bound
        if is_step_limit(expr, self.data_ends, self.streaks):
            return True
        if not isinstance(expr, ast.Compare) or len(expr.ops) != 1 or not isinstance(expr.ops[0], LIMIT_OPS):
            return False
        if is_end_of_data(expr, self.data_ends):
            return False
        if is_periodic(expr) or not self.counters:
            return False
        sides = (expr.left, expr.comparators[0])
        return any(self._counter(a) and _bound(b) for a, b in (sides, sides[::-1]))

    def _counter(self, expr: ast.AST) -> bool:
        while isinstance(expr, ast.BinOp) and isinstance(expr.op, (ast.Div, ast.FloorDiv, ast.Mult)):
            expr = expr.left  # ``self.step_counter / self.SIM_FREQ``: seconds of a step count
        field = self_field(expr)
        return field is not None and field[0] in self.counters

    # -- tracing --------------------------------------------------------------------------

    def trace(self, expr: ast.expr | None, depth: int = 0) -> DoneCause:
        if expr is None or depth > _MAX_DEPTH:
            return TERMINATION
        expr = unwrap_bool(expr)
        if isinstance(expr, ast.Constant):
            return NEVER if expr.value in (False, None, 0) else TERMINATION
        if isinstance(expr, ast.Compare):
            if self.is_limit(expr):
                limit = Limit(
                    expr.lineno,
                    self.facts.segment(expr),
                    by_counter=not is_step_limit(expr, self.data_ends, self.streaks),
                    drawn=tuple(random_bound(self.facts, self.classdef, expr)),
                )
                return DoneCause(Cause.TRUNCATION, (limit,))
            if is_end_of_data(expr, self.data_ends):
                return DoneCause(Cause.TERMINATION, ends_of_data=(Limit(expr.lineno, self.facts.segment(expr)),))
            return self._inside(expr, depth)
        if isinstance(expr, ast.BoolOp) and isinstance(expr.op, ast.Or):
            return combine(self.trace(v, depth + 1) for v in expr.values)
        guarded = limit_under_guard(expr)
        if guarded is not None and self.is_limit(guarded):
            return self.trace(guarded, depth + 1)  # ``self.max_steps is not None and <limit>``
        if isinstance(expr, ast.IfExp):
            if _is_true(expr.body) and _is_false(expr.orelse):
                return self.trace(expr.test, depth + 1)  # ``True if <limit> else False``
            return _opaque(combine([self._inside(expr.test, depth), self.trace(expr.body, depth + 1), self.trace(expr.orelse, depth + 1)]))
        if isinstance(expr, ast.Name):
            return self._local(expr, depth)
        if isinstance(expr, ast.Attribute) and isinstance(expr.ctx, ast.Load) and is_self(expr.value):
            return self._attribute(expr.attr, depth)
        if _held_read(expr):
            # ``self._env.episode_over``: the held object's own flag, set by its own rules
            return DoneCause(Cause.TERMINATION, held=(Limit(expr.lineno, self.facts.segment(expr)),))
        flags = _flags_of(expr)
        if flags is not None:
            # One flag per agent (``tuple(done for _ in agents)``, ``(done,) * 2``): not one
            # flag; the limits among their causes are named.
            return _opaque(combine(self.trace(flag, depth + 1) for flag in flags))
        if isinstance(expr, ast.Call):
            if is_dm_env_last(self.facts, expr):
                # dm_env's ``time_step.last()`` is also True when dm_control's own time limit
                # ends the episode (with discount 1.0): a task end and a limit in one flag.
                return DoneCause(Cause.MIXED, (Limit(expr.lineno, self.facts.segment(expr), by_counter=True),))
            found = self._call(expr, depth)
            if found is not None:
                return found
            if _held_read(expr.func) and not expr.args and not expr.keywords:
                # ``self.sim.is_over()``: asked of the held object, which decides by itself
                return DoneCause(Cause.TERMINATION, held=(Limit(expr.lineno, self.facts.segment(expr)),))
            return self._inside(expr, depth)
        if isinstance(expr, ast.Subscript):
            values = self._keyed_values(expr, depth)
            if values is not None:
                return combine(self._in_context(v, depth + 1) for v in values)
            return self._inside(expr, depth)
        return self._inside(expr, depth)

    def _inside(self, expr: ast.AST, depth: int) -> DoneCause:
        """Something the tracer does not see through: a termination, unless a limit is in it."""
        limits = [
            Limit(node.lineno, self.facts.segment(node))
            for node in walk(expr)
            if isinstance(node, ast.Compare) and self.is_limit(node)
        ]
        return DoneCause(Cause.UNKNOWN, tuple(limits)) if limits else TERMINATION

    def _in_context(self, value: ast.expr, depth: int) -> DoneCause:
        """A stored or returned value: ``True`` takes its cause from the ``if`` it is under."""
        if not _is_true(value):
            return self.trace(value, depth)
        child: ast.AST = value
        for parent in self.facts.ancestors(value):
            if isinstance(parent, (*FUNCTIONS, ast.ClassDef, ast.Lambda)):
                break
            if isinstance(parent, ast.If) and child is not parent.test:
                test = parent.test
                negated = False
                if isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not):
                    test, negated = test.operand, True
                if under_limit(test):
                    negated = not negated  # ``if self.t < self.T: ... else: return True``
                found = self.trace(test, depth + 1)
                if (child in parent.body) != negated:
                    return found
                return _opaque(found)  # the branch where the test is false
            child = parent
        return TERMINATION

    def _local(self, name: ast.Name, depth: int) -> DoneCause:
        function = self.facts.enclosing_function(name)
        scope = self.facts.scopes.get(function) if function is not None else None
        bindings = scope.bindings.get(name.id, []) if scope is not None else []
        key = ("local", id(function), name.id)
        if key in self._busy:
            # ``ended = over or ended``: the name read again while its own bindings are
            # followed adds no cause the other bindings do not give
            return NEVER
        values = []
        followed: list[DoneCause] = []
        self._busy.add(key)
        try:
            for binding in bindings:
                holder = self.facts.parent(binding)
                if function is not None and _killed_before(function, binding, name):
                    continue  # ``done = <test>`` later in the body replaces it before the read: dead
                if isinstance(binding, ast.arg) and function is not None:
                    if _overwritten(function, name):
                        continue  # ``dones = tuple(...)`` before the read: the parameter's value is gone
                    passed = _arguments(self.facts).get(id(function))
                    if not passed or name.id not in passed[-1]:
                        return self._inside(name, depth)
                    caller, argument = passed[-1][name.id]
                    followed.append(caller.trace(argument, depth + 1))
                    continue
                if isinstance(holder, (ast.Tuple, ast.List)):
                    unpacked = self._unpacked(holder, binding, depth)
                    if unpacked is None:
                        return self._inside(name, depth)
                    followed.append(unpacked)
                    continue
                if not (isinstance(holder, ast.Assign) and holder.targets == [binding]):
                    return self._inside(name, depth)
                values.append(holder.value)
            if followed:
                return combine([*followed, *([self._assigned(values, function, name, depth)] if values else [])])
            return self._assigned(values, function, name, depth)
        finally:
            self._busy.discard(key)

    def _unpacked(self, target: ast.Tuple | ast.List, binding: ast.AST, depth: int) -> DoneCause | None:
        """``rewards, over = self.score(infos)``: the value in ``binding``'s
        place of what is unpacked (a tuple literal, or the tuples the method returns); None
        for anything else."""
        holder = self.facts.parent(target)
        if not (isinstance(holder, ast.Assign) and holder.targets == [target]) or any(isinstance(e, ast.Starred) for e in target.elts):
            return None
        index = next(i for i, element in enumerate(target.elts) if element is binding)
        value = holder.value
        if isinstance(value, (ast.Tuple, ast.List)):
            if len(value.elts) != len(target.elts) or any(isinstance(e, ast.Starred) for e in value.elts):
                return None
            return self.trace(value.elts[index], depth + 1)
        if isinstance(value, ast.Call):
            return self._call(value, depth, index)
        return None

    def _assigned(self, values: list[ast.expr], function: ast.AST | None, name: ast.Name, depth: int) -> DoneCause:
        if not values or function is None:
            return TERMINATION
        if any(_is_dict(self.facts, v) for v in values):
            # A dict of flags (per agent, ``"__all__"``): not one flag; its limits are named.
            stored = _key_stores(self.facts, function, name.id, ast.Dict(keys=[], values=[]), _ANY_KEY) or []
            parts = [self._dict_values(v, depth) for v in values] + [self._in_context(v, depth + 1) for v in stored]
            return _opaque(combine(parts))
        return combine(self._in_context(v, depth + 1) for v in values)

    def _dict_values(self, value: ast.expr, depth: int) -> DoneCause:
        if isinstance(value, ast.Dict):
            return combine(self.trace(v, depth + 1) for v in value.values)
        if isinstance(value, ast.DictComp):
            return self.trace(value.value, depth + 1)
        if isinstance(value, ast.Call) and _is_dict(self.facts, value):
            return combine(self.trace(k.value, depth + 1) for k in value.keywords)
        return TERMINATION

    def _attribute(self, name: str, depth: int) -> DoneCause:
        key = ("attribute", hash(name))
        if key in self._busy:
            return TERMINATION
        self._busy.add(key)
        try:
            values = self_stores(self.facts, self.classdef, name)
            return combine(self._in_context(v, depth + 1) for v in values) if values else TERMINATION
        finally:
            self._busy.discard(key)

    # -- methods --------------------------------------------------------------------------

    def _call(self, call: ast.Call, depth: int, index: int | None = None) -> DoneCause | None:
        """``self.m(...)`` / ``self.inner.m(...)``: the causes of what every candidate ``m``
        returns (``index``: of the value at that position of the tuples it returns), its
        parameters holding what the call passes."""
        returns = self._returned(call, index)
        if returns is None:
            return None
        causes = []
        stack = _arguments(self.facts)
        for tracer, method in returns[0]:
            passed = stack.setdefault(id(method), [])
            passed.append(self._passed(call, method, tracer))
            try:
                causes.append(tracer.returns_cause(method, depth + 1, index))
            finally:
                passed.pop()
        return combine([*causes, *returns[1]])

    def _passed(self, call: ast.Call, method: Method, callee: DoneTracer) -> Arguments:
        """What ``call`` gives each parameter of ``method`` (after ``self``): its argument, or
        the parameter's default; nothing where a ``*args`` or ``**kwargs`` hides the mapping."""
        if any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords):
            return {}
        args = method.args
        params = [*args.posonlyargs, *args.args]
        passed: Arguments = {}
        for param, default in zip(params[len(params) - len(args.defaults) :], args.defaults, strict=False):
            passed[param.arg] = (callee, default)
        for param, keyword_default in zip(args.kwonlyargs, args.kw_defaults, strict=False):
            if keyword_default is not None:
                passed[param.arg] = (callee, keyword_default)
        static = any(isinstance(d, ast.Name) and d.id == "staticmethod" for d in method.decorator_list)
        for param, argument in zip(params if static else params[1:], call.args, strict=False):
            passed[param.arg] = (self, argument)
        for keyword in call.keywords:
            passed[keyword.arg] = (self, keyword.value)  # type: ignore[index]
        return passed

    def _returned(self, call: ast.Call, index: int | None = None) -> tuple[list[tuple[DoneTracer, Method]], list[DoneCause]] | None:
        if not isinstance(call.func, ast.Attribute):
            return None
        owner, name = call.func.value, call.func.attr
        if is_self(owner):
            tracer = self
        else:
            inner = self._instance_class(owner)
            if inner is None:
                return None
            tracer = self.tracer_of(inner)
        methods = tracer.candidates(name)
        external = tracer.external(name, index) if tracer.external is not None else []
        if not methods and not external:
            return None
        return methods, external

    def candidates(self, name: str) -> list[tuple[DoneTracer, Method]]:
        """The class's own ``name`` (or a local base's) with returns, and its overrides in
        subclasses of this module."""
        found: list[tuple[DoneTracer, Method]] = []
        own = self._own_or_inherited(self.classdef, name, set())
        if own is not None and _returns_values(own[1]):
            found.append((self.tracer_of(own[0]), own[1]))
        for sub in self._local_subclasses():
            method = next((m for m in sub.body if isinstance(m, FUNCTIONS) and m.name == name), None)
            if method is not None and _returns_values(method):
                found.append((self.tracer_of(sub), method))
        return found

    def defines(self, name: str) -> bool:
        """The class or a base of it in this module defines the method ``name``."""
        return self._own_or_inherited(self.classdef, name, set()) is not None

    def returns_cause(self, method: Method, depth: int, index: int | None = None) -> DoneCause:
        """Why what ``method`` returns is True (``index``: the value at that position of the
        tuples it returns; a return that is no tuple literal hides it)."""
        key = ("method", id(method))
        if key in self._busy:
            return TERMINATION
        self._busy.add(key)
        try:
            causes = []
            for ret in own_returns(method):
                value = ret.value
                if value is None:
                    continue
                if index is None:
                    causes.append(self._in_context(value, depth))
                elif isinstance(value, ast.Tuple) and index < len(value.elts) and not any(isinstance(e, ast.Starred) for e in value.elts):
                    causes.append(self._in_context(value.elts[index], depth))
                else:
                    causes.append(_opaque(self.trace(value, depth)))
            return combine(causes) if causes else TERMINATION
        finally:
            self._busy.discard(key)

    def returned_items(self, method: Method) -> tuple[DoneCause, ...]:
        """Why each value of the tuples ``method`` returns is True, where every return is a
        tuple literal of one length (``return rewards, done``); empty otherwise."""
        lengths = {len(r.value.elts) if isinstance(r.value, ast.Tuple) else -1 for r in own_returns(method)}
        if len(lengths) != 1 or (length := lengths.pop()) < 2:
            return ()
        return tuple(self.returns_cause(method, 0, index) for index in range(length))

    def _own_or_inherited(self, classdef: ast.ClassDef, name: str, seen: set[int]) -> tuple[ast.ClassDef, Method] | None:
        if id(classdef) in seen:
            return None
        seen.add(id(classdef))
        for statement in classdef.body:
            if isinstance(statement, FUNCTIONS) and statement.name == name:
                return classdef, statement
        for base in classdef.bases:
            local = self.facts.classes.get(base.id) if isinstance(base, ast.Name) else None
            if local is not None:
                found = self._own_or_inherited(local, name, seen)
                if found is not None:
                    return found
        return None

    def _local_subclasses(self) -> list[ast.ClassDef]:
        if self._subclasses is None:
            self._subclasses = self._find_subclasses()
        return self._subclasses

    def _find_subclasses(self) -> list[ast.ClassDef]:
        found: list[ast.ClassDef] = []
        names = {self.classdef.name}
        grew = True
        while grew:
            grew = False
            for classdef in self.facts.classes.values():
                if classdef in found or classdef is self.classdef:
                    continue
                if any(isinstance(b, ast.Name) and b.id in names for b in classdef.bases):
                    found.append(classdef)
                    names.add(classdef.name)
                    grew = True
        return found

    def _instance_class(self, owner: ast.AST) -> ast.ClassDef | None:
        """``self.inner`` that the class only ever sets to ``C(...)``, ``C`` a class of the module."""
        name = self_attribute(owner)
        if name is None:
            return None
        found: ast.ClassDef | None = None
        for attr in self.facts.attributes.get(name, ()):
            if not isinstance(attr.ctx, ast.Store) or not is_self(attr.value) or self.facts.enclosing_class(attr) is not self.classdef:
                continue
            holder = self.facts.parent(attr)
            value = holder.value if isinstance(holder, ast.Assign) and holder.targets == [attr] else None
            if not (isinstance(value, ast.Call) and isinstance(value.func, ast.Name)):
                return None
            classdef = self.facts.classes.get(value.func.id)
            if classdef is None or (found is not None and classdef is not found):
                return None
            found = classdef
        return found

    # -- dicts ----------------------------------------------------------------------------

    def _keyed_values(self, subscript: ast.Subscript, depth: int) -> list[ast.expr] | None:
        """The values stored under a constant key of the dict ``subscript`` reads:
        ``self.helper()["__all__"]``, or ``dones["__all__"]`` with ``dones = self.helper()``."""
        key = subscript.slice
        if not (isinstance(key, ast.Constant) and isinstance(key.value, (str, int))):
            return None
        holder = subscript.value
        if isinstance(holder, ast.Name):
            function = self.facts.enclosing_function(holder)
            scope = self.facts.scopes.get(function) if function is not None else None
            bindings = scope.bindings.get(holder.id, []) if scope is not None else []
            if function is None or len(bindings) != 1:
                return None
            assign = self.facts.parent(bindings[0])
            if not (isinstance(assign, ast.Assign) and assign.targets == [bindings[0]]):
                return None
            if _is_dict(self.facts, assign.value):
                return _key_stores(self.facts, function, holder.id, assign.value, key.value)
            holder = assign.value
        if not isinstance(holder, ast.Call):
            return None
        returned = self._returned(holder)
        if returned is None or returned[1]:
            return None  # overrides in other modules: their dicts are not summarized
        values: list[ast.expr] = []
        for tracer, method in returned[0]:
            for ret in own_returns(method):
                found = tracer._returned_dict(method, ret.value, key.value)
                if found is None:
                    return None
                values += found
        return values or None

    def _returned_dict(self, method: Method, value: ast.expr | None, key: object) -> list[ast.expr] | None:
        if isinstance(value, ast.Name):
            scope = self.facts.scopes.get(method)
            bindings = scope.bindings.get(value.id, []) if scope is not None else []
            if len(bindings) != 1:
                return None
            assign = self.facts.parent(bindings[0])
            if not (isinstance(assign, ast.Assign) and assign.targets == [bindings[0]] and _is_dict(self.facts, assign.value)):
                return None
            return _key_stores(self.facts, method, value.id, assign.value, key)
        if isinstance(value, ast.Dict):
            return _literal_values(value, key)
        return None


_ANY_KEY = object()  # every key of a dict


def _arguments(facts: ModuleFacts) -> dict[int, list[Arguments]]:
    """The arguments of the calls being followed, by method (``id``), innermost last: shared
    by the tracers of a module, since a call of one class may reach a method of another."""
    return facts.memo(("done-arguments", id(facts.tree)), dict)


def _overwritten(function: ast.AST, name: ast.Name) -> bool:
    """A statement of ``function``'s body before the one holding ``name`` assigns the name
    (``dones = tuple(...)`` before ``return dones``): the parameter's value cannot reach it."""
    body = getattr(function, "body", [])
    for statement in body:
        if statement.lineno <= name.lineno <= (statement.end_lineno or statement.lineno):
            return False
        if isinstance(statement, ast.Assign) and any(isinstance(t, ast.Name) and t.id == name.id for t in statement.targets):
            return True
    return False


def _killed_before(function: ast.AST, binding: ast.AST, read: ast.Name) -> bool:
    """A statement of ``function``'s own body after the one holding ``binding`` and before
    the one holding ``read`` assigns the name afresh (``done = <test>``, its value not
    reading the name): every path from the binding to the read passes it, so the binding's
    value never reaches the read (a test overwritten on the next line ends nothing)."""
    body = getattr(function, "body", [])
    place = [_position(body, node) for node in (binding, read)]
    if place[0] is None or place[1] is None:
        return False
    for statement in body[place[0] + 1 : place[1]]:
        if (
            isinstance(statement, ast.Assign)
            and any(isinstance(t, ast.Name) and t.id == read.id for t in statement.targets)
            and not any(isinstance(n, ast.Name) and n.id == read.id for n in walk(statement.value))
        ):
            return True
    return False


def _position(body: list[ast.stmt], node: ast.AST) -> int | None:
    """The index of the statement of ``body`` that holds ``node`` (by its lines)."""
    line = getattr(node, "lineno", None)
    if line is None:
        return None
    for index, statement in enumerate(body):
        if statement.lineno <= line <= (statement.end_lineno or statement.lineno):
            return index
    return None


def _flags_of(expr: ast.expr) -> list[ast.expr] | None:
    """The flags of a collection of them, one per agent: ``(done, done)``, ``[done] * n``,
    ``tuple(done for _ in agents)``, ``[d for d in dones]``; None for anything else."""
    if isinstance(expr, ast.BinOp) and isinstance(expr.op, ast.Mult):
        for side in (expr.left, expr.right):
            if isinstance(side, (ast.Tuple, ast.List)):
                return _flags_of(side)
        return None
    if isinstance(expr, (ast.Tuple, ast.List)) and expr.elts and not any(isinstance(e, ast.Starred) for e in expr.elts):
        return list(expr.elts)
    if isinstance(expr, (ast.ListComp, ast.GeneratorExp)):
        return [expr.elt]
    if (
        isinstance(expr, ast.Call)
        and isinstance(expr.func, ast.Name)
        and expr.func.id in ("tuple", "list")
        and len(expr.args) == 1
        and not expr.keywords
        and isinstance(expr.args[0], (ast.ListComp, ast.GeneratorExp, ast.List, ast.Tuple))
    ):
        return _flags_of(expr.args[0])
    return None


def _key_stores(facts: ModuleFacts, function: ast.AST, name: str, created: ast.expr, key: object) -> list[ast.expr] | None:
    """What ``name[key]`` may hold: its value where the dict is made, then ``name[key] = v``
    stores in ``function``. None when the dict is changed in any way this does not follow."""
    values = _literal_values(created, key)
    if values is None:
        return None
    for node in walk(function):
        if isinstance(node, ast.Name) and node.id == name and isinstance(node.ctx, ast.Load):
            parent = facts.parent(node)
            if isinstance(parent, ast.Subscript) and isinstance(parent.ctx, ast.Store):
                holder = facts.parent(parent)
                index = parent.slice
                if isinstance(holder, (ast.Tuple, ast.List)) and _other_key(index, key):
                    continue  # ``name["x"], name["y"] = ...``: other entries, this one untouched
                if not (isinstance(holder, ast.Assign) and holder.targets == [parent]):
                    return None
                if isinstance(index, ast.Constant) and key is not _ANY_KEY:
                    if index.value == key:
                        values.append(holder.value)
                else:
                    values.append(holder.value)  # ``dones[agent] = ...``: may be any key
            elif isinstance(parent, ast.Attribute) and parent.attr in ("update", "setdefault", "__setitem__"):
                return None
    return values


def _other_key(index: ast.expr, key: object) -> bool:
    """``index`` is a constant key that is not ``key`` (a store that leaves ``key`` as it was)."""
    return key is not _ANY_KEY and isinstance(index, ast.Constant) and index.value != key


def _literal_values(created: ast.expr, key: object) -> list[ast.expr] | None:
    if isinstance(created, ast.Dict):
        if any(k is None for k in created.keys):
            return None  # ``{**other}``
        return [v for k, v in zip(created.keys, created.values, strict=True) if not isinstance(k, ast.Constant) or k.value == key]
    if isinstance(created, ast.DictComp):
        return [created.value]
    if isinstance(created, ast.Call):  # ``dict(done=False, ...)``, vetted by ``_is_dict``
        return [k.value for k in created.keywords if key is _ANY_KEY or k.arg == key]
    return None


def _is_dict(facts: ModuleFacts, value: ast.expr) -> bool:
    """A dict made here whose keys are all spelled: a literal, a comprehension, or the
    builtin ``dict(done=False, ...)`` with keywords alone (the same dict as the literal;
    a ``dict`` bound in the module, or ``dict(other)``/``dict(**kw)``, is something else)."""
    if isinstance(value, ast.Call):
        return (
            isinstance(value.func, ast.Name)
            and value.func.id == "dict"
            and not facts.reaching_bindings(value.func)
            and not value.args
            and all(k.arg is not None for k in value.keywords)
        )
    return isinstance(value, (ast.Dict, ast.DictComp))


def _returns_values(method: Method) -> bool:
    return any(r.value is not None for r in own_returns(method))


def _fixed(value: ast.expr) -> bool:
    """A count: a positive number (``self.n += 1``), not an amount that varies
    (``self.x += action``, ``self.ball += self.speed``)."""
    return isinstance(value, ast.Constant) and isinstance(value.value, (int, float)) and not isinstance(value.value, bool) and value.value > 0



def _bound(expr: ast.AST) -> bool:
    """A limit a counter is compared with: a number, a name or attribute (no call)."""
    return all(isinstance(node, (ast.Constant, ast.Name, ast.Attribute, ast.BinOp, ast.operator, ast.expr_context)) for node in walk(expr))


def _nonzero_side(test: ast.Compare) -> ast.expr:
    right = test.comparators[0]
    return test.left if isinstance(right, ast.Constant) else right


def _is_true(expr: ast.AST) -> bool:
    return isinstance(expr, ast.Constant) and expr.value is True


def _is_false(expr: ast.AST) -> bool:
    return isinstance(expr, ast.Constant) and expr.value is False
