"""Why a custom PettingZoo env's ``dones`` value is True: the game ended, or a step limit.

PettingZoo 1.21 split ``dones`` by meaning: a game that ends (a catch, a knock-out, a
win) is a termination, a match called off by a step or cycle counter is a truncation.
This traces each stored value to its causes with the single-agent predicate
(``is_step_limit``, GM504's): a comparison of a counter with a limit
(``self.num_moves >= self.max_cycles``, ``self.frames > 500``) is a limit, and so is

* a name assigned once in the same function from a limit (``over = self.t >= T``),
* ``self.helper()`` whose every return is a limit (``def _out_of_time(self): ...``),
* ``self.sim.helper()["__all__"]`` (a class of the module that the env holds, and the key
  of the dict its helper returns) where every value stored under that key is a limit,
* ``self.flag`` whose every store in the class is a limit or ``False``
  (``self.truncate = self.frames >= self.max_cycles``, as PettingZoo's pistonball keeps it),
* ``True`` stored under ``if <limit>:`` (the branch that calls the match off).

Everything else is a termination, unless a limit hides inside it (``not <limit>``,
``dict(zip(...))`` around one): that is left for review. ``a or <limit>`` splits into both; an agent that
terminated on the step is then not also truncated (``not terminated and <limit>``, as
PettingZoo's cooperative_pong decides the two).
"""

from __future__ import annotations

import ast
import enum
from dataclasses import dataclass, field
from typing import TypeVar

from gymmigrate.facts.done_causes import Cause as DoneCause
from gymmigrate.facts.limit_tests import is_step_limit, under_limit, unwrap_bool
from gymmigrate.facts.limits import DoneTracer
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts, own_returns, walk
from gymmigrate.facts.self_attributes import self_stores

_Node = TypeVar("_Node", bound=ast.AST)


class Cause(enum.Enum):
    TERMINATION = "termination"
    TRUNCATION = "truncation"
    SPLIT = "split"  # ``a or <limit>``
    UNKNOWN = "unknown"  # a limit mixed into a test some other way: by hand


@dataclass
class Traced:
    cause: Cause
    task: list[ast.expr] = field(default_factory=list)  # the termination operands of a split
    limit: list[ast.expr] = field(default_factory=list)  # the limit operands of a split
    name: ast.Name | None = None  # ``done`` when the split was traced through its assignment
    assign: ast.Assign | None = None  # that assignment


class Endings:
    """Traces stores of ``dones`` in one class."""

    def __init__(self, facts: ModuleFacts, classdef: ast.ClassDef) -> None:
        self.facts = facts
        self.classdef = classdef
        self.methods = {m.name: m for m in classdef.body if isinstance(m, FUNCTIONS)}

    # -- limits ---------------------------------------------------------------------------

    def is_limit(self, expr: ast.AST, depth: int = 0) -> bool:
        if depth > 4:
            return False
        if is_step_limit(expr):
            return True
        expr = unwrap_bool(expr)
        if isinstance(expr, ast.BoolOp) and isinstance(expr.op, ast.Or):
            return all(self.is_limit(v, depth + 1) for v in expr.values)
        if isinstance(expr, ast.Call) and not expr.args and not expr.keywords:
            helper = self._self_method(expr.func)
            if helper is not None:
                returns = [r.value for r in own_returns(helper)]
                return bool(returns) and all(v is not None and self.is_limit(v, depth + 1) for v in returns)
            return self._traced_limit(expr)  # ``self.sim.compute_done()``, a class of the module
        if isinstance(expr, ast.Subscript):
            return self._traced_limit(expr)  # ``self.sim.compute_dones()["__all__"]``
        if isinstance(expr, ast.Name):
            assign = self.single_assignment(expr)
            return assign is not None and self.is_limit(assign.value, depth + 1)
        if isinstance(expr, ast.Attribute) and isinstance(expr.ctx, ast.Load) and _is_self(expr.value):
            values = self._attribute_values(expr.attr)
            limits = [v for v in values or () if not (isinstance(v, ast.Constant) and v.value in (False, None))]
            return values is not None and bool(limits) and all(self.is_limit(v, depth + 1) for v in limits)
        return False

    def _traced_limit(self, expr: ast.expr) -> bool:
        """A helper's result (or one key of the dict it returns) that is only ever a step
        limit, through the helpers and the classes of the module (``facts/limits.py``)."""
        facts, classdef = self.facts, self.classdef
        tracer = facts.memo(("done-tracer", id(classdef)), lambda: DoneTracer(facts, classdef))
        return tracer.trace(expr).cause is DoneCause.TRUNCATION

    def _attribute_values(self, name: str) -> list[ast.expr] | None:
        """Every value ``self.<name> = value`` stores in this class; None when a store is
        anything else (an augmented assignment, a tuple target, ...)."""
        return self_stores(self.facts, self.classdef, name)

    def mentions_limit(self, expr: ast.AST) -> bool:
        kinds = (ast.Compare, ast.Call, ast.Name, ast.Attribute)
        return any(self.is_limit(node) for node in walk(expr) if isinstance(node, kinds))

    def _self_method(self, func: ast.AST) -> ast.FunctionDef | ast.AsyncFunctionDef | None:
        if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name) and func.value.id == "self":
            return self.methods.get(func.attr)
        return None

    def single_assignment(self, name: ast.Name) -> ast.Assign | None:
        """The one ``name = value`` of a local read in a function, before the read."""
        if not isinstance(name.ctx, ast.Load):
            return None
        function = self.facts.enclosing_function(name)
        if function is None:
            return None
        bindings = self.facts.scopes[function].bindings.get(name.id, [])
        if len(bindings) != 1:
            return None
        holder = self.facts.parent(bindings[0])
        if not (isinstance(holder, ast.Assign) and holder.targets == [bindings[0]]):
            return None
        if (holder.lineno, holder.col_offset) >= (name.lineno, name.col_offset):
            return None
        return holder

    # -- values and branches --------------------------------------------------------------

    def value(self, expr: ast.expr) -> Traced:
        """The cause of one stored value."""
        operands = _or_operands(unwrap_bool(expr))
        limits = [op for op in operands if self.is_limit(op)]
        if not limits:
            if isinstance(expr, ast.Name):
                assign = self.single_assignment(expr)
                if assign is not None:
                    traced = self.value(assign.value)
                    if traced.cause is Cause.SPLIT and traced.name is None:
                        return Traced(Cause.SPLIT, traced.task, traced.limit, expr, assign)
            # a limit inside something else (``not self._out_of_time()``, ``dict(zip(...))``)
            return Traced(Cause.UNKNOWN if self.mentions_limit(expr) else Cause.TERMINATION)
        if len(limits) == len(operands):
            return Traced(Cause.TRUNCATION)
        task = [op for op in operands if op not in limits]
        if any(self.mentions_limit(op) for op in task):
            return Traced(Cause.UNKNOWN)
        return Traced(Cause.SPLIT, task, limits)

    def branch(self, statement: ast.stmt) -> Cause | None:
        """The cause the enclosing ``if`` gives a store: TRUNCATION in the body of
        ``if <limit>:`` (or the else of ``if not <limit>:`` / ``if counter < limit:``),
        TERMINATION in the other branch, UNKNOWN under a test that mixes a limit with
        other causes, else None."""
        child: ast.AST = statement
        for parent in self.facts.ancestors(statement):
            if isinstance(parent, (*FUNCTIONS, ast.ClassDef, ast.Lambda)):
                return None
            if isinstance(parent, ast.If) and child is not parent.test:
                test, negated = parent.test, False
                if isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not):
                    test, negated = test.operand, True
                if under_limit(test):
                    negated = not negated  # ``if self.num_moves < self.max_cycles:`` plays on
                in_body = child in parent.body
                if self.is_limit(test):
                    return Cause.TRUNCATION if in_body != negated else Cause.TERMINATION
                if self.mentions_limit(test):
                    return Cause.UNKNOWN
            child = parent
        return None


def _is_self(expr: ast.AST) -> bool:
    return isinstance(expr, ast.Name) and expr.id == "self"



def _or_operands(expr: ast.expr) -> list[ast.expr]:
    if isinstance(expr, ast.BoolOp) and isinstance(expr.op, ast.Or):
        return [operand for value in expr.values for operand in _or_operands(value)]
    return [expr]


def joined(parts: list[ast.expr], facts: ModuleFacts) -> str:
    """``a or b`` from operands, each parenthesized where ``or`` would bind it differently."""
    texts = [f"({facts.segment(p)})" if isinstance(p, (ast.IfExp, ast.Lambda, ast.NamedExpr)) else facts.segment(p) for p in parts]
    return " or ".join(texts)


def is_true(expr: ast.AST) -> bool:
    return isinstance(expr, ast.Constant) and expr.value is True
