"""Why an env's ``done`` is True: a step or time limit the env counts (a truncation in
Gymnasium), the task's own end (a termination), or both.

``DoneTracer.trace(expr)`` follows a done value to its causes inside one class:

* a comparison of a step or time counter with a bound (``self.t >= self.max_steps``,
  ``self.step_counter / self.SIM_FREQ > self.EPISODE_LEN_SEC``) is a limit. A counter is
  named like one (``STEP_LIMIT_WORD``) or is an attribute the class's ``step`` advances by
  a fixed amount on every call (``self.n += 1`` at the top of ``step``), unless it is named as a
  place or an amount (``self.agent_pos``). A test of a
  period (``self.t % FREQ == 0``) is not a limit;
* a local assigned in the same function, ``self.flag`` as the class stores it, ``True``
  stored or returned under ``if <limit>:``, ``True if <limit> else False``, ``bool(...)``;
* ``self.helper()`` through every return of the helper and of its overrides (subclasses of
  the module, and of the run: the caller passes what the run's summaries give), and
  ``self.helper()["__all__"]`` through the key's stores in the dict the helper returns;
* ``self.inner.helper()`` where the class stores an instance of a class of the module
  in ``self.inner``.

The result is certain only as far as the code shows it: anything the tracer cannot see
into is a termination (what ``done`` meant before truncation existed), and a limit mixed
into a test in any other way than ``a or <limit>`` makes the cause UNKNOWN, with the limits
it found, so that a report can name them.
"""

from __future__ import annotations

import ast
import enum
import re
from collections.abc import Callable, Collection, Iterable
from dataclasses import dataclass
from typing import TypeVar

from gymmigrate.facts.env_classes import identifiers
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts, own_returns
from gymmigrate.facts.self_attributes import self_stores

# A word that counts steps or time (matched on the lower-cased identifier: ``MAX_STEPS``
# too). ``cycles``, ``frames`` and ``num_moves`` are how PettingZoo's envs count theirs
# (``self.frames >= self.max_cycles``); a bare ``moves`` is often a list of legal moves.
STEP_LIMIT_WORD = re.compile(
    r"(^|_)(t|ts|step|steps|timestep|timesteps|tick|ticks|iter|iters|iteration|iterations|horizon|"
    r"time|time_limit|ep_len|episode_len|episode_length|counter|cycle|cycles|frame|frames|num_moves|n_moves)(_|$)"
)
# An attribute named as a place or an amount (``self.agent_pos += 1``) that reaches a bound is
# the task's goal even when step advances it every call: not taken for a step count.
_PLACE_WORD = re.compile(
    r"(^|_)(pos|position|loc|location|coord|coords|x|y|z|dist|distance|height|depth|level|score|"
    r"energy|health|fuel|money|balance|cash|stock|inventory)(_|$)"
)
_LIMIT_OPS = (ast.Gt, ast.GtE, ast.Lt, ast.LtE, ast.Eq)
_MAX_DEPTH = 8


def is_periodic(expr: ast.AST) -> bool:
    """``self.t % FREQ == 0``: a test that comes true every so many steps, not a limit."""
    return any(isinstance(node, ast.BinOp) and isinstance(node.op, ast.Mod) for node in ast.walk(expr))


def is_step_limit(expr: ast.AST, data_ends: Collection[str] = ()) -> bool:
    """A comparison that names a step or time counter (``self.steps >= self.max_steps``),
    unless it tests the end of the env's data (``is_end_of_data``; ``data_ends``: the
    class's attributes bound to its data's length)."""
    if not isinstance(expr, ast.Compare) or not all(isinstance(op, _LIMIT_OPS) for op in expr.ops):
        return False
    if is_periodic(expr) or is_end_of_data(expr, data_ends):
        return False
    return any(STEP_LIMIT_WORD.search(word.lower()) and "beyond" not in word for word in identifiers(expr))


def _minus_constant(expr: ast.AST) -> ast.AST:
    """``x - 1`` (or ``x + 1``) -> ``x``: an index's offset from a length."""
    while isinstance(expr, ast.BinOp) and isinstance(expr.op, (ast.Add, ast.Sub)) and _number(expr.right):
        expr = expr.left
    return expr


def _number(expr: ast.AST) -> bool:
    return isinstance(expr, ast.Constant) and isinstance(expr.value, (int, float)) and not isinstance(expr.value, bool)


def is_data_length(expr: ast.AST) -> bool:
    """``len(x)``, ``x.shape[0]``, either minus a constant (``len(self.df.index.unique()) - 1``):
    the length of something the env holds, here the end of its data, not a step budget."""
    expr = _minus_constant(expr)
    if isinstance(expr, ast.Call):
        return isinstance(expr.func, ast.Name) and expr.func.id == "len" and len(expr.args) == 1 and not expr.keywords
    return (
        isinstance(expr, ast.Subscript)
        and isinstance(expr.value, ast.Attribute)
        and expr.value.attr == "shape"
        and isinstance(expr.slice, ast.Constant)
        and expr.slice.value == 0
    )


def is_end_of_data(expr: ast.AST, data_ends: Collection[str] = ()) -> bool:
    """``self.day == self.max_step`` where the class binds ``self.max_step`` only to a data
    length (``data_ends``), or ``self.t >= len(self.prices) - 1``: the counter reaches the
    last row of the env's data, after which the episode cannot go on. A terminal state (legacy
    learners did not bootstrap there), not a time limit, whatever the names say. Not when the
    other side is itself a budget (``len(self.history) >= self.max_steps``, ``>= 200``)."""
    if not isinstance(expr, ast.Compare) or len(expr.ops) != 1 or not isinstance(expr.ops[0], _LIMIT_OPS):
        return False

    def bound(side: ast.AST) -> bool:
        name = _self_attribute(_minus_constant(side))
        return is_data_length(side) or (name is not None and name in data_ends)

    sides = (expr.left, expr.comparators[0])
    return any(bound(a) and not bound(b) and not is_data_length(b) and not _is_bound_name(b) for a, b in (sides, sides[::-1]))


def data_end_attributes(facts: ModuleFacts, classdef: ast.ClassDef) -> frozenset[str]:
    """The attributes every store of which in ``classdef`` is a data length
    (``self.max_step = self.price_ary.shape[0] - 1``): the end of the env's data, whatever
    the attribute is called. One store of anything else (a parameter, a constant) and the
    attribute may be a step budget: it is not one of these."""

    def compute() -> frozenset[str]:
        found = set()
        for name, attrs in facts.attributes.items():
            if not any(isinstance(a.ctx, ast.Store) and _is_self(a.value) and facts.enclosing_class(a) is classdef for a in attrs):
                continue
            values = self_stores(facts, classdef, name)
            if values and all(is_data_length(v) for v in values):
                found.add(name)
        return frozenset(found)

    return facts.memo(("data-end-attributes", id(classdef)), compute)


def if_setting_true(line: ast.AST, parent: ast.AST | None) -> ast.If | None:
    """The ``if`` of ``if <test>: done = True`` (a plain name set to ``True`` in a branch of
    ``parent``): what the "done is set when ..." checks of the step rules share (a task's own
    end in an env's step, a step limit or a lost life in a wrapper's), each with its own test
    and its own demand on the other branch. None for any other line."""
    if not (
        isinstance(line, ast.Assign)
        and len(line.targets) == 1
        and isinstance(line.targets[0], ast.Name)
        and isinstance(line.value, ast.Constant)
        and line.value.value is True
        and isinstance(parent, ast.If)
        and (line in parent.body or line in parent.orelse)
    ):
        return None
    return parent


_AnyNode = TypeVar("_AnyNode", bound=ast.AST)


def unwrap_bool(expr: _AnyNode) -> _AnyNode | ast.expr:
    """``bool(x)`` -> ``x``; anything else as it is."""
    if (
        isinstance(expr, ast.Call)
        and isinstance(expr.func, ast.Name)
        and expr.func.id == "bool"
        and len(expr.args) == 1
        and not expr.keywords
        and not isinstance(expr.args[0], ast.Starred)
    ):
        return expr.args[0]
    return expr


def or_operands(expr: ast.expr) -> list[ast.expr]:
    if isinstance(expr, ast.BoolOp) and isinstance(expr.op, ast.Or):
        return [operand for value in expr.values for operand in or_operands(value)]
    return [expr]


class Cause(enum.Enum):
    NEVER = "never"  # ``False``: ends nothing
    TERMINATION = "termination"
    TRUNCATION = "truncation"
    MIXED = "mixed"  # some causes a limit, some the task's end
    UNKNOWN = "unknown"  # a limit mixed in some other way, or not a flag (a dict)


@dataclass(frozen=True)
class Limit:
    line: int
    text: str
    where: str = ""  # another module of the run ("HoverAviary.py"); "" for this one
    by_counter: bool = False  # found as a count ``step`` advances, not by its name

    def place(self) -> str:
        return f"{self.where}:{self.line}" if self.where else f"line {self.line}"


@dataclass(frozen=True)
class DoneCause:
    cause: Cause
    limits: tuple[Limit, ...] = ()
    # tests of the end of the env's data among the causes (``is_end_of_data``): terminations
    ends_of_data: tuple[Limit, ...] = ()

    def elsewhere(self) -> bool:
        return any(limit.where for limit in self.limits)

    def plain(self) -> bool:
        """Every limit is named as one and in this module: settled, not a question."""
        return not any(limit.where or limit.by_counter for limit in self.limits)


NEVER = DoneCause(Cause.NEVER)
TERMINATION = DoneCause(Cause.TERMINATION)


def combine(parts: Iterable[DoneCause]) -> DoneCause:
    """The cause of a value that is true when any of ``parts`` is (an ``or``, or the
    alternatives: several returns, several stores)."""
    parts = list(parts)
    limits: list[Limit] = []
    ends: list[Limit] = []
    for part in parts:
        limits += [limit for limit in part.limits if limit not in limits]
        ends += [end for end in part.ends_of_data if end not in ends]
    causes = {part.cause for part in parts} - {Cause.NEVER}
    if not causes:
        return DoneCause(Cause.NEVER, tuple(limits), tuple(ends))
    if Cause.UNKNOWN in causes:
        cause = Cause.UNKNOWN
    elif len(causes) == 1:
        cause = causes.pop()
    else:
        cause = Cause.MIXED
    return DoneCause(cause, tuple(limits), tuple(ends))


def _opaque(found: DoneCause) -> DoneCause:
    """A value that hides what it holds (``not <limit>``, ``a and b``, a dict)."""
    return DoneCause(Cause.UNKNOWN, found.limits) if found.limits else TERMINATION


def _is_self(node: ast.AST) -> bool:
    return isinstance(node, ast.Name) and node.id == "self"


def _self_attribute(node: ast.AST) -> str | None:
    return node.attr if isinstance(node, ast.Attribute) and _is_self(node.value) else None


Method = ast.FunctionDef | ast.AsyncFunctionDef
# Overrides of a method that other modules of the run define: method name -> their causes.
External = Callable[[str], list[DoneCause]]


class DoneTracer:
    """Traces done values of one class of a module (see the module docstring)."""

    def __init__(self, facts: ModuleFacts, classdef: ast.ClassDef, external: External | None = None) -> None:
        self.facts = facts
        self.classdef = classdef
        self.external = external
        self.methods: dict[str, Method] = {m.name: m for m in classdef.body if isinstance(m, FUNCTIONS)}
        self._counters: set[str] | None = None
        self.data_ends = data_end_attributes(facts, classdef)
        self._subclasses: list[ast.ClassDef] | None = None
        self._busy: set[tuple[str, int]] = set()

    def tracer_of(self, classdef: ast.ClassDef) -> DoneTracer:
        if classdef is self.classdef:
            return self
        key = ("done-tracer", id(classdef))
        return self.facts.memo(key, lambda: DoneTracer(self.facts, classdef))

    # -- limits ---------------------------------------------------------------------------

    @property
    def counters(self) -> set[str]:
        """Attributes ``step`` advances by a fixed amount on every call: ``self.n += 1``
        (or ``self.t = self.t + self.dt``) among the top-level statements of ``step``."""
        if self._counters is None:
            found: set[str] = set()
            step = self.methods.get("step") or self.methods.get("_step")
            for statement in step.body if step is not None else ():
                if isinstance(statement, ast.AugAssign) and isinstance(statement.op, (ast.Add, ast.Sub)):
                    name = _self_attribute(statement.target)
                    if name is not None and _fixed(statement.value) and not _PLACE_WORD.search(name):
                        found.add(name)
                elif isinstance(statement, ast.Assign) and len(statement.targets) == 1:
                    name = _self_attribute(statement.targets[0])
                    value = statement.value
                    if (
                        name is not None
                        and isinstance(value, ast.BinOp)
                        and isinstance(value.op, (ast.Add, ast.Sub))
                        and _self_attribute(value.left) == name
                        and _fixed(value.right)
                        and not _PLACE_WORD.search(name)
                    ):
                        found.add(name)
            self._counters = found
        return self._counters

    def is_limit(self, expr: ast.AST) -> bool:
        """A comparison of a step or time counter with a bound (not the end of the data)."""
        if is_step_limit(expr, self.data_ends):
            return True
        if not isinstance(expr, ast.Compare) or len(expr.ops) != 1 or not isinstance(expr.ops[0], _LIMIT_OPS):
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
        name = _self_attribute(expr)
        return name is not None and name in self.counters

    # -- tracing --------------------------------------------------------------------------

    def trace(self, expr: ast.expr | None, depth: int = 0) -> DoneCause:
        if expr is None or depth > _MAX_DEPTH:
            return TERMINATION
        expr = unwrap_bool(expr)
        if isinstance(expr, ast.Constant):
            return NEVER if expr.value in (False, None, 0) else TERMINATION
        if isinstance(expr, ast.Compare):
            if self.is_limit(expr):
                limit = Limit(expr.lineno, self.facts.segment(expr), by_counter=not is_step_limit(expr, self.data_ends))
                return DoneCause(Cause.TRUNCATION, (limit,))
            if is_end_of_data(expr, self.data_ends):
                return DoneCause(Cause.TERMINATION, ends_of_data=(Limit(expr.lineno, self.facts.segment(expr)),))
            return self._inside(expr, depth)
        if isinstance(expr, ast.BoolOp) and isinstance(expr.op, ast.Or):
            return combine(self.trace(v, depth + 1) for v in expr.values)
        if isinstance(expr, ast.IfExp):
            if _is_true(expr.body) and _is_false(expr.orelse):
                return self.trace(expr.test, depth + 1)  # ``True if <limit> else False``
            return _opaque(combine([self._inside(expr.test, depth), self.trace(expr.body, depth + 1), self.trace(expr.orelse, depth + 1)]))
        if isinstance(expr, ast.Name):
            return self._local(expr, depth)
        if isinstance(expr, ast.Attribute) and isinstance(expr.ctx, ast.Load) and _is_self(expr.value):
            return self._attribute(expr.attr, depth)
        if isinstance(expr, ast.Call):
            if is_dm_env_last(self.facts, expr):
                # dm_env's ``time_step.last()`` is also True when dm_control's own time limit
                # ends the episode (with discount 1.0): a task end and a limit in one flag.
                return DoneCause(Cause.MIXED, (Limit(expr.lineno, self.facts.segment(expr), by_counter=True),))
            found = self._call(expr, depth)
            if found is not None:
                return found
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
            for node in ast.walk(expr)
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
        values = []
        for binding in bindings:
            holder = self.facts.parent(binding)
            if not (isinstance(holder, ast.Assign) and holder.targets == [binding]):
                return self._inside(name, depth)
            values.append(holder.value)
        if not values or function is None:
            return TERMINATION
        if any(_is_dict(v) for v in values):
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

    def _call(self, call: ast.Call, depth: int) -> DoneCause | None:
        """``self.m()`` / ``self.inner.m()``: the causes of what every candidate ``m`` returns."""
        returns = self._returned(call)
        if returns is None:
            return None
        causes = [tracer.returns_cause(method, depth + 1) for tracer, method in returns[0]]
        return combine([*causes, *returns[1]])

    def _returned(self, call: ast.Call) -> tuple[list[tuple[DoneTracer, Method]], list[DoneCause]] | None:
        if call.args or call.keywords or not isinstance(call.func, ast.Attribute):
            return None
        owner, name = call.func.value, call.func.attr
        if _is_self(owner):
            tracer = self
        else:
            inner = self._instance_class(owner)
            if inner is None:
                return None
            tracer = self.tracer_of(inner)
        methods = tracer.candidates(name)
        external = tracer.external(name) if tracer.external is not None else []
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

    def returns_cause(self, method: Method, depth: int) -> DoneCause:
        key = ("method", id(method))
        if key in self._busy:
            return TERMINATION
        self._busy.add(key)
        try:
            values = [r.value for r in own_returns(method) if r.value is not None]
            return combine(self._in_context(v, depth) for v in values) if values else TERMINATION
        finally:
            self._busy.discard(key)

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
        name = _self_attribute(owner)
        if name is None:
            return None
        found: ast.ClassDef | None = None
        for attr in self.facts.attributes.get(name, ()):
            if not isinstance(attr.ctx, ast.Store) or not _is_self(attr.value) or self.facts.enclosing_class(attr) is not self.classdef:
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
            if _is_dict(assign.value):
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
            if not (isinstance(assign, ast.Assign) and assign.targets == [bindings[0]] and _is_dict(assign.value)):
                return None
            return _key_stores(self.facts, method, value.id, assign.value, key)
        if isinstance(value, ast.Dict):
            return _literal_values(value, key)
        return None


_ANY_KEY = object()  # every key of a dict


def _key_stores(facts: ModuleFacts, function: ast.AST, name: str, created: ast.expr, key: object) -> list[ast.expr] | None:
    """What ``name[key]`` may hold: its value where the dict is made, then ``name[key] = v``
    stores in ``function``. None when the dict is changed in any way this does not follow."""
    values = _literal_values(created, key)
    if values is None:
        return None
    for node in ast.walk(function):
        if isinstance(node, ast.Name) and node.id == name and isinstance(node.ctx, ast.Load):
            parent = facts.parent(node)
            if isinstance(parent, ast.Subscript) and isinstance(parent.ctx, ast.Store):
                holder = facts.parent(parent)
                if not (isinstance(holder, ast.Assign) and holder.targets == [parent]):
                    return None
                index = parent.slice
                if isinstance(index, ast.Constant) and key is not _ANY_KEY:
                    if index.value == key:
                        values.append(holder.value)
                else:
                    values.append(holder.value)  # ``dones[agent] = ...``: may be any key
            elif isinstance(parent, ast.Attribute) and parent.attr in ("update", "setdefault", "__setitem__"):
                return None
    return values


def _literal_values(created: ast.expr, key: object) -> list[ast.expr] | None:
    if isinstance(created, ast.Dict):
        if any(k is None for k in created.keys):
            return None  # ``{**other}``
        return [v for k, v in zip(created.keys, created.values, strict=True) if not isinstance(k, ast.Constant) or k.value == key]
    if isinstance(created, ast.DictComp):
        return [created.value]
    return None


def _is_dict(value: ast.expr) -> bool:
    return isinstance(value, (ast.Dict, ast.DictComp))


def _returns_values(method: Method) -> bool:
    return any(r.value is not None for r in own_returns(method))


def _fixed(value: ast.expr) -> bool:
    """A count: a positive number (``self.n += 1``), not an amount that varies
    (``self.x += action``, ``self.ball += self.speed``)."""
    return isinstance(value, ast.Constant) and isinstance(value.value, (int, float)) and not isinstance(value.value, bool) and value.value > 0


def _bound(expr: ast.AST) -> bool:
    """A limit a counter is compared with: a number, a name or attribute (no call)."""
    return all(isinstance(node, (ast.Constant, ast.Name, ast.Attribute, ast.BinOp, ast.operator, ast.expr_context)) for node in ast.walk(expr))


def under_limit(test: ast.AST) -> bool:
    """``counter < limit`` (or ``limit > counter``): true while the episode (or match) goes on."""
    if not (isinstance(test, ast.Compare) and len(test.ops) == 1):
        return False
    left_is_limit = _is_bound_name(test.left)
    if isinstance(test.ops[0], (ast.Lt, ast.LtE)):
        return not left_is_limit
    if isinstance(test.ops[0], (ast.Gt, ast.GtE)):
        return left_is_limit
    return False


def _is_bound_name(expr: ast.AST) -> bool:
    """A limit rather than a counter: a number, a CONSTANT, or a name that says max/limit."""
    if isinstance(expr, ast.Constant):
        return True
    name = expr.attr if isinstance(expr, ast.Attribute) else expr.id if isinstance(expr, ast.Name) else ""
    return name.isupper() or any(word in name.lower() for word in ("max", "limit", "horizon"))


def _is_true(expr: ast.AST) -> bool:
    return isinstance(expr, ast.Constant) and expr.value is True


def _is_false(expr: ast.AST) -> bool:
    return isinstance(expr, ast.Constant) and expr.value is False


def is_dm_env_last(facts: ModuleFacts, call: ast.Call) -> bool:
    """``time_step.last()`` in a module that uses dm_control or dm_env: the ``TimeStep``'s
    end of episode, which dm_control's environments also signal at their time limit."""
    return (
        isinstance(call.func, ast.Attribute)
        and call.func.attr == "last"
        and not call.args
        and not call.keywords
        and ("dm_control" in facts.text or "dm_env" in facts.text)
    )
