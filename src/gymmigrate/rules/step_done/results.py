"""GM304: step results that are not unpacked.

``res = env.step(a)`` keeps working, but the tuple has five items now: ``res[3]`` is
``truncated``, not ``info``. Constant indices that certainly read this step's result
move (``res[3]`` -> ``res[4]``; ``res[2]`` -> ``res[2] or res[3]``, the legacy done);
observation, reward and ``res[-1]`` keep their places. Any other use (the result passed
on, indexed by a variable, read where another binding may reach) is reported, as is a
step result used without being stored at all (``if env.step(a)[2]:``), except the two
constant reads of it that ``UnpackRules.plan_indexed_step`` migrates.
"""

from __future__ import annotations

import ast
from bisect import bisect_left, bisect_right
from dataclasses import dataclass

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.decisions import Action, Decision, receiver_text
from gymmigrate.facts.flow import end, start
from gymmigrate.facts.module import LOOPS, ModuleFacts, full_name, is_super_call
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.step_done.common import (
    StepFamilyBase,
    looks_vectorised,
    stands_alone,
)


@dataclass(frozen=True)
class _ResultStep:
    """``res = x.step(a)`` on a receiver that may be a Gym env."""

    assign: ast.Assign
    result: ast.Name
    receiver: ast.expr
    decision: Decision
    vector: bool


def _unpacked_into_no_gym_count(parent: ast.AST | None, call: ast.Call) -> bool:
    """``a, b, c, d, e, f = x.step(...)`` or ``reward, done, info = x.step(...)``: one plain
    target of a count of names no Gym step returns (neither four nor five), none starred."""
    return (
        isinstance(parent, ast.Assign)
        and parent.value is call
        and len(parent.targets) == 1
        and isinstance(parent.targets[0], (ast.Tuple, ast.List))
        and len(parent.targets[0].elts) not in (4, 5)
        and not any(isinstance(element, ast.Starred) for element in parent.targets[0].elts)
    )


# Calls that only show a value: printing or logging any tuple works, whatever its length
_SHOWING_FUNCTIONS = frozenset({"print", "pprint"})
_SHOWING_METHODS = frozenset({"debug", "info", "warning", "warn", "error", "critical", "log", "pprint"})


def _only_shown(call: ast.Call, facts: ModuleFacts) -> bool:
    """The step result is an argument of ``print`` or a logging call, straight or inside an
    f-string that is one: the five values are shown, nothing reads a field of them."""
    node: ast.AST = call
    parent = facts.parent(node)
    while isinstance(parent, (ast.FormattedValue, ast.JoinedStr)):
        node, parent = parent, facts.parent(parent)
    if not isinstance(parent, ast.Call) or node is parent.func:
        return False
    if not (node in parent.args or any(keyword.value is node for keyword in parent.keywords)):
        return False
    if isinstance(parent.func, ast.Name):
        return parent.func.id in _SHOWING_FUNCTIONS
    name = full_name(parent.func) or ""
    return isinstance(parent.func, ast.Attribute) and (
        parent.func.attr in _SHOWING_METHODS or name.startswith(("logging.", "logger.", "log."))
    )


# What a tuple has: a step result read through anything else is no Gym step result
_TUPLE_ATTRIBUTES = frozenset({"count", "index"}) | frozenset(a for a in dir(tuple) if a.startswith("__"))


class ResultRules(StepFamilyBase):
    """GM304 (mixed into the family)."""

    def report_unpacked_use(self, call: ast.Call, receiver: ast.expr) -> None:
        """A step whose result is used some other way than stored or unpacked."""
        if self._discarded(call):
            return  # ``[env.step(a) for a in actions]`` as a statement: nothing reads the result
        if subscript_index(self.facts.parent(call), call) in _SAME_PLACE:
            return  # ``env.step(0)[0]``: the observation (reward, info) is where it was
        if _unpacked_into_no_gym_count(self.facts.parent(call), call):
            # ``ob, s_ob, reward, done, info, avail = env.step(a)``, ``reward, terminated,
            # env_info = env.step(a)`` (SMAC's multi-agent API): no Gym env, legacy (four) or
            # Gymnasium (five), returns six or three values, so the legacy code would have
            # raised on one; the receiver has a protocol of its own, nothing to port here
            return
        decision, _ = self.decision(receiver, legacy_shape=False)
        profile = self.context.profile
        # A file that imports neither package may still step the envs others hand it (a
        # vector env over ``self.envs``); one that imports only gymnasium is migrated already.
        if decision.action is not Action.LEAVE and (profile.imports_gym or not profile.imports_gymnasium):
            chained = _chained_four(self.facts.parent(call), call)
            if chained is not None:
                obs, reward, done, info = (self.facts.segment(el) for el in chained.elts)
                others = ", ".join(f"`{self.facts.segment(t)}`" for t in self.facts.parent(call).targets if t is not chained)  # type: ignore[union-attr]
                self.report(
                    call,
                    "GM304",
                    f"a chained assignment also stores the step result in {others}, which would hold five values now: "
                    f"split it: `{obs}, {reward}, terminated, truncated, {info} = {receiver_text(receiver)}.step(...)`, "
                    f"`{done} = terminated or truncated`, then assign `{obs}, {reward}, {done}, {info}` to the other targets",
                    FixKind.FLAG,
                )
                return
            if decision.action is Action.REPORT and (self._gym_only_origin(receiver) or self.receivers.gym_only_stack(receiver)):
                # an env of a stack still on gym (a pipe worker's ``send(self.envs[i].step(a))``):
                # it returns four values until that stack is ported, so this use is the
                # stack's decision, asked at its import
                self.report(
                    call,
                    "GM304",
                    f"{decision.reason}; then this step() result holds five values (index 2 is terminated, "
                    "3 truncated, 4 info): update this use with it",
                    FixKind.FLAG,
                    question=self.receiver_question(receiver, decision),
                )
                return
            if _only_shown(call, self.facts):
                self.report(
                    call,
                    "GM304",
                    f"`{receiver_text(receiver)}.step()` result is only printed or logged: it shows five values now "
                    "(terminated and truncated where done was); nothing to change",
                    FixKind.FLAG,
                    Tier.NOTE,
                )
                return
            unsure = f"{decision.reason.removesuffix('; not rewritten')}: if it is, its " if decision.action is Action.REPORT else ""
            self.report(
                call,
                "GM304",
                f"{unsure}`{receiver_text(receiver)}.step()` result is used without unpacking five values "
                "(index 2 is now terminated, 3 truncated, 4 info): update this use by hand",
                FixKind.FLAG,
                # "is it a Gym env?" is the question; its other uses in the function (or class) ask it too
                question=self.receiver_question(receiver, decision) if decision.action is Action.REPORT else None,
            )

    def _discarded(self, call: ast.Call) -> bool:
        """The step is the element of a comprehension that is itself a statement, or the call
        a statement's whole expression: its result is thrown away."""
        parent = self.facts.parent(call)
        if isinstance(parent, (ast.ListComp, ast.SetComp, ast.GeneratorExp)) and parent.elt is call:
            parent = self.facts.parent(parent)
        return isinstance(parent, ast.Expr)

    def plan_result_name(self, assign: ast.Assign, result: ast.Name, receiver: ast.expr) -> None:
        """``res = env.step(a)``: its reads are planned once every such step is known."""
        if not self.context.profile.imports_gym:
            return  # Gymnasium code: nothing to move
        decision, vector = self.decision(receiver, legacy_shape=False)
        if decision.action is Action.LEAVE:
            return
        if decision.action is Action.REPORT and self.receivers.own_api_holder(receiver) is not None and self._read_as_object(result):
            # a wrapper of another env API forwarding its own step, whose result it reads as
            # ``timestep.observation``, ``timestep.last()`` (a dm_env TimeStep): no Gym step
            # result (a tuple, legacy or Gymnasium) has such attributes
            return
        scope = self.flow.binding_scope(result)
        group = (id(scope), result.id) if scope is not None else (id(assign), result.id)
        self.result_steps.setdefault(group, []).append(_ResultStep(assign, result, receiver, decision, vector))

    def _read_as_object(self, result: ast.Name) -> bool:
        """Some read of ``result`` takes an attribute a tuple lacks, and none indexes it."""
        attributes = False
        for read in self.flow.reads(result):
            parent = self.facts.parent(read)
            if isinstance(parent, ast.Subscript) and parent.value is read:
                return False
            if isinstance(parent, ast.Attribute) and parent.value is read:
                if parent.attr in _TUPLE_ATTRIBUTES:
                    return False
                attributes = True
        return attributes

    def finish_results(self) -> None:
        for steps in self.result_steps.values():
            self._plan_result_reads(steps)

    def _plan_result_reads(self, steps: list[_ResultStep]) -> None:
        """Plan the reads of one result variable that its steps (in source order) bind.

        The steps that can reach a read form a run from the first one (those before the
        read, then those in a loop around it), so each read is one range. A step none of
        whose reachable reads already counts five values (``res[4]``) moves the indices
        of the reads it dominates; every other reachable read is reported once.
        """
        flow = self.flow
        result = steps[0].result
        scope = self.facts.scope_of(result)
        starts = [start(step.assign) for step in steps]
        ends = [end(step.assign) for step in steps]
        index_of = {id(step.assign): i for i, step in enumerate(steps)}
        reads = flow.reads(result)
        reach: list[int] = []  # per read: the steps [0, stop) that can reach it
        poisoned = 0  # steps [0, poisoned) reach an index that already counts five values
        low: list[int] = []  # per read: steps before this one cannot reach it (rebound on the way)
        for read in reads:
            first = 0
            if not flow.same_frame(read, scope):
                stop = len(steps)  # a nested function may run after any of them
            else:
                before = bisect_right(ends, start(read))
                killer = _always_bound_before(read, result.id, self.facts)
                loop = _outermost_loop(read, self.facts, outside=killer)
                stop = max(before, bisect_left(starts, end(loop)) if loop is not None else 0)
                if killer is not None:
                    # ``result = self.policy(obs)`` on every path to the read: only the steps
                    # from there on (or in a loop around both) can reach it.
                    first = min(bisect_left(starts, start(killer)), stop)
            reach.append(stop)
            low.append(first)
            if (self._constant_index(read) or 0) in (4, -5):
                poisoned = max(poisoned, stop)
        active = [0]
        for i, step in enumerate(steps):
            live = i >= poisoned
            if live and step.decision.action is Action.REPORT:
                self.report(
                    step.assign,
                    "GM304",
                    f"{step.decision.reason}; if it is a Gym env, its step returns five values",
                    FixKind.FLAG,
                    question=self.receiver_question(step.receiver, step.decision),
                )
            active.append(active[-1] + (live and step.decision.action is not Action.REPORT))
        for read, first, stop in zip(reads, low, reach):
            # The step that dominates the read (one at most) moves its index; any other
            # step that reaches it cannot tell which value the read sees.
            owner = self._dominating_result(read, result, index_of)
            others = active[stop] - active[first]
            if owner is not None and owner >= poisoned and steps[owner].decision.action is not Action.REPORT:
                self._move_index(read, steps[owner])
                others -= 1
            if others > 0:
                self._report_by_hand(read, result)

    def _dominating_result(self, read: ast.Name, result: ast.Name, index_of: dict[int, int]) -> int | None:
        """Index of the step (among ``index_of``) that certainly binds the value ``read`` sees."""
        binding = self.flow.last_binding_before(read, result)
        if binding is None:
            return None
        statement = self.facts.statement_of(binding)
        index = index_of.get(id(statement))
        if index is not None and self.flow.dominates(statement, read, result):
            return index
        return None

    def _move_index(self, read: ast.Name, step: _ResultStep) -> None:
        """Move the index of a read ``step`` dominates (or report it when it cannot move)."""
        result = step.result
        if self._passed_through(read, step):
            return  # the wrapper's step returns its inner env's five values, as Gymnasium's do
        index = self._constant_index(read)
        subscript = self.facts.parent(read)
        if index in (0, 1, -1):
            return  # observation, reward and info keep their places
        # An index is only found on a subscript (``_constant_index``).
        if index == 3 and isinstance(subscript, ast.Subscript):
            self.plan.replace(subscript, lambda node: with_index(node, 4))
            exact = FixKind.AUTO if step.decision.action is Action.REWRITE else FixKind.ASSIST
            self.report(subscript, "GM304", f"`{result.id}[3]` (info) is `{result.id}[4]` now", exact)
            return
        if index == 2 and isinstance(subscript, ast.Subscript) and not (step.vector or looks_vectorised(step.receiver, result)):
            bare = stands_alone(subscript, self.facts.parent(subscript))
            self.plan.replace(subscript, lambda node: _either(node, bare))
            self.report(
                subscript,
                "GM304",
                f"`{result.id}[2]` (done) is now `{result.id}[2] or {result.id}[3]`; "
                f"if it feeds bootstrapping, use `{result.id}[2]` (terminated) alone",
            )
            return
        self._report_by_hand(read, result)

    def _passed_through(self, read: ast.Name, step: _ResultStep) -> bool:
        """``return res`` in a class's ``step``, ``res`` its base's ``super().step(a)`` or, in
        a Gym wrapper, the wrapped ``self.env.step(a)``: the step hands that result on
        unchanged, which is right for any length."""
        statement = self.facts.parent(read)
        function = self.facts.enclosing_function(read)
        receiver = step.receiver
        classdef = self.facts.enclosing_class(read)
        if not (
            isinstance(statement, ast.Return)
            and statement.value is read
            and isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef))
            and function.name == "step"
            and self.facts.enclosing_function(step.assign) is function
            and classdef is not None
            and self.facts.parent(function) is classdef
        ):
            return False
        if is_super_call(receiver):
            return True
        return (
            self.receivers.is_gym_wrapper_class(classdef)
            and isinstance(receiver, ast.Attribute)
            and receiver.attr == "env"
            and isinstance(receiver.value, ast.Name)
            and self.receivers.is_self(receiver.value)
        )

    def _report_by_hand(self, read: ast.Name, result: ast.Name) -> None:
        self.report(
            read,
            "GM304",
            f"`{result.id}` holds a five-value step result now (2 terminated, 3 truncated, 4 info): "
            "update this use by hand",
            FixKind.FLAG,
        )

    def _constant_index(self, read: ast.Name) -> int | None:
        """``res[2]`` read (not stored) with a literal integer index -> 2; otherwise None."""
        subscript = self.facts.parent(read)
        index = subscript_index(subscript, read)
        if index is None or self._parenthesized(subscript.slice):  # type: ignore[union-attr]
            return None
        return index

    def _parenthesized(self, node: ast.expr) -> bool:
        """Whether ``node`` is written inside its own parentheses (``res[(2)]``)."""
        line = self.facts.lines[node.lineno - 1].encode("utf-8")
        before = line[: node.col_offset].rstrip()
        return before.endswith(b"(")


def with_index(subscript: cst.Subscript, index: int) -> cst.Subscript:
    element = subscript.slice[0]
    return subscript.with_changes(
        slice=[element.with_changes(slice=element.slice.with_changes(value=cst.Integer(str(index))))]
    )


def _either(subscript: cst.Subscript, bare: bool) -> cst.BaseExpression:
    """``res[2]`` -> ``res[2] or res[3]`` (parenthesized unless it stands alone)."""
    either = cst.BooleanOperation(
        left=subscript.with_changes(lpar=(), rpar=()),
        operator=cst.Or(),
        right=with_index(subscript, 3).with_changes(lpar=(), rpar=()),
    )
    if bare:
        return either
    return either.with_changes(lpar=[cst.LeftParen()], rpar=[cst.RightParen()])


_SAME_PLACE = (0, 1, -1)  # observation, reward and info: the same index in both APIs


def subscript_index(subscript: ast.AST | None, value: ast.AST) -> int | None:
    """``value[2]`` read (not stored) with a literal integer index -> 2; otherwise None."""
    if not isinstance(subscript, ast.Subscript) or subscript.value is not value:
        return None
    if not isinstance(subscript.ctx, ast.Load):
        return None  # a store into the result
    index = subscript.slice
    sign = 1
    if isinstance(index, ast.UnaryOp) and isinstance(index.op, ast.USub):
        sign, index = -1, index.operand
    if isinstance(index, ast.Constant) and type(index.value) is int:
        return sign * index.value
    return None


def _outermost_loop(node: ast.AST, facts: ModuleFacts, outside: ast.AST | None = None) -> ast.AST | None:
    """The outermost loop around ``node`` (that does not hold ``outside``: a loop around both
    runs ``outside`` again before it comes back to ``node``)."""
    found = None
    for ancestor in facts.ancestors(node):
        if isinstance(ancestor, LOOPS) and (outside is None or not _holds(ancestor, outside, facts)):
            found = ancestor
    return found


def _holds(outer: ast.AST, inner: ast.AST, facts: ModuleFacts) -> bool:
    return any(a is outer for a in facts.ancestors(inner))


def _always_bound_before(read: ast.Name, name: str, facts: ModuleFacts) -> ast.stmt | None:
    """The nearest statement before ``read``, in the statement lists around it (up to its
    function), that binds ``name`` on every path through it: ``result = ...``, or an
    ``if``/``with`` whose every branch does. Every value ``read`` sees was bound there or
    after it."""
    node: ast.AST = read
    for holder in facts.ancestors(read):
        for field in ("body", "orelse", "finalbody"):
            block = getattr(holder, field, None)
            if isinstance(block, list) and any(s is node for s in block):
                found = _nearest_binding(block, node, name)
                if found is not None:
                    return found
        if isinstance(holder, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef, ast.Module)):
            return None
        node = holder
    return None


def _nearest_binding(block: list[ast.stmt], node: ast.AST, name: str) -> ast.stmt | None:
    index = next((i for i, s in enumerate(block) if s is node), None)
    if index is None:
        return None
    for statement in reversed(block[:index]):
        if _always_binds(statement, name):
            return statement
    return None


def _always_binds(statement: ast.stmt, name: str) -> bool:
    if isinstance(statement, ast.Assign):
        # ``obs, reward, done, info = env.step(a)`` binds ``obs`` too: one field of that
        # step, not a step result, so no step before it reaches the reads after it
        return any(_target_binds(t, name) for t in statement.targets)
    if isinstance(statement, ast.AnnAssign):
        return statement.value is not None and isinstance(statement.target, ast.Name) and statement.target.id == name
    if isinstance(statement, ast.If):
        return bool(statement.orelse) and _block_binds(statement.body, name) and _block_binds(statement.orelse, name)
    if isinstance(statement, (ast.With, ast.AsyncWith)):
        return _block_binds(statement.body, name)
    return False


def _target_binds(target: ast.expr, name: str) -> bool:
    if isinstance(target, ast.Name):
        return target.id == name
    if isinstance(target, ast.Starred):
        return _target_binds(target.value, name)
    if isinstance(target, (ast.Tuple, ast.List)):
        return any(_target_binds(element, name) for element in target.elts)
    return False


def _block_binds(block: list[ast.stmt], name: str) -> bool:
    for statement in block:
        if _always_binds(statement, name):
            return True
        if isinstance(statement, (ast.Return, ast.Raise, ast.Continue, ast.Break)):
            return True  # the path ends here: it never reaches the read unbound
    return False


def _chained_four(parent: ast.AST | None, call: ast.Call) -> ast.Tuple | ast.List | None:
    """``out = obs, reward, done, info = env.step(a)``: the four-name target of a chained
    assignment of a step result (its other targets get the whole result)."""
    if not (isinstance(parent, ast.Assign) and parent.value is call and len(parent.targets) > 1):
        return None
    for target in parent.targets:
        if isinstance(target, (ast.Tuple, ast.List)) and len(target.elts) == 4:
            if not any(isinstance(el, ast.Starred) for el in target.elts):
                return target
    return None
