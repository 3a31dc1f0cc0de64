"""GM304: step results that are not unpacked.

``res = env.step(a)`` keeps working, but the tuple has five items now: ``res[3]`` is
``truncated``, not ``info``. Constant indices that certainly read this step's result
move (``res[3]`` -> ``res[4]``; ``res[2]`` -> ``res[2] or res[3]``, the legacy done);
observation, reward and ``res[-1]`` keep their places. Any other use (the result passed
on, indexed by a variable, read where another binding may reach) is reported, as is a
step result used without being stored at all (``env.step(a)[2]``).
"""

from __future__ import annotations

import ast
from bisect import bisect_left, bisect_right
from dataclasses import dataclass

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.decisions import Action, Decision, receiver_text
from gymmigrate.facts.flow import end, start
from gymmigrate.facts.module import LOOPS, ModuleFacts
from gymmigrate.findings import FixKind
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


class ResultRules(StepFamilyBase):
    """GM304 (mixed into the family)."""

    def report_unpacked_use(self, call: ast.Call, receiver: ast.expr) -> None:
        """A step whose result is used some other way than stored or unpacked."""
        if self._discarded(call):
            return  # ``[env.step(a) for a in actions]`` as a statement: nothing reads the result
        decision, _ = self.decision(receiver, legacy_shape=False)
        if decision.action is not Action.LEAVE and self.context.profile.imports_gym:
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
            self.report(
                call,
                "GM304",
                f"`{receiver_text(receiver)}.step()` result is used without unpacking five values "
                "(index 2 is now terminated, 3 truncated, 4 info): update this use by hand",
                FixKind.FLAG,
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
        scope = self.flow.binding_scope(result)
        group = (id(scope), result.id) if scope is not None else (id(assign), result.id)
        self.result_steps.setdefault(group, []).append(_ResultStep(assign, result, receiver, decision, vector))

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
        for read in reads:
            if not flow.same_frame(read, scope):
                stop = len(steps)  # a nested function may run after any of them
            else:
                before = bisect_right(ends, start(read))
                loop = _outermost_loop(read, self.facts)
                stop = max(before, bisect_left(starts, end(loop)) if loop is not None else 0)
            reach.append(stop)
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
        for read, stop in zip(reads, reach):
            # The step that dominates the read (one at most) moves its index; any other
            # step that reaches it cannot tell which value the read sees.
            owner = self._dominating_result(read, result, index_of)
            others = active[stop]
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
        index = self._constant_index(read)
        subscript = self.facts.parent(read)
        if index in (0, 1, -1):
            return  # observation, reward and info keep their places
        # An index is only found on a subscript (``_constant_index``).
        if index == 3 and isinstance(subscript, ast.Subscript):
            self.plan.replace(subscript, lambda node: _with_index(node, 4))
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
        if not isinstance(subscript, ast.Subscript) or subscript.value is not read:
            return None
        if not isinstance(subscript.ctx, ast.Load):
            return None  # a store into the result
        value = subscript.slice
        sign = 1
        if isinstance(value, ast.UnaryOp) and isinstance(value.op, ast.USub):
            sign, value = -1, value.operand
        if (
            isinstance(value, ast.Constant)
            and type(value.value) is int
            and not self._parenthesized(value)
        ):
            return sign * value.value
        return None

    def _parenthesized(self, node: ast.expr) -> bool:
        """Whether ``node`` is written inside its own parentheses (``res[(2)]``)."""
        line = self.facts.lines[node.lineno - 1].encode("utf-8")
        before = line[: node.col_offset].rstrip()
        return before.endswith(b"(")


def _with_index(subscript: cst.Subscript, index: int) -> cst.Subscript:
    element = subscript.slice[0]
    return subscript.with_changes(
        slice=[element.with_changes(slice=element.slice.with_changes(value=cst.Integer(str(index))))]
    )


def _either(subscript: cst.Subscript, bare: bool) -> cst.BaseExpression:
    """``res[2]`` -> ``res[2] or res[3]`` (parenthesized unless it stands alone)."""
    either = cst.BooleanOperation(
        left=subscript.with_changes(lpar=(), rpar=()),
        operator=cst.Or(),
        right=_with_index(subscript, 3).with_changes(lpar=(), rpar=()),
    )
    if bare:
        return either
    return either.with_changes(lpar=[cst.LeftParen()], rpar=[cst.RightParen()])


def _outermost_loop(node: ast.AST, facts: ModuleFacts) -> ast.AST | None:
    found = None
    for ancestor in facts.ancestors(node):
        if isinstance(ancestor, LOOPS):
            found = ancestor
    return found


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
