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

import libcst as cst

from gymmigrate.facts.decisions import Action, receiver_text
from gymmigrate.findings import FixKind
from gymmigrate.rules.step_done.common import StepFamilyBase, looks_vectorised, stands_alone


class ResultRules(StepFamilyBase):
    """GM304 (mixed into the family)."""

    def report_unpacked_use(self, call: ast.Call, receiver: ast.expr) -> None:
        """A step whose result is used some other way than stored or unpacked."""
        decision, _ = self.decision(receiver, legacy_shape=False)
        if decision.action is not Action.LEAVE and self.context.profile.imports_gym:
            self.report(
                call,
                "GM304",
                f"`{receiver_text(receiver)}.step()` result is used without unpacking five values "
                "(index 2 is now terminated, 3 truncated, 4 info): update this use by hand",
                FixKind.FLAG,
            )

    def plan_result_name(self, assign: ast.Assign, result: ast.Name, receiver: ast.expr) -> None:
        decision, vector = self.decision(receiver, legacy_shape=False)
        if decision.action is Action.LEAVE:
            return
        flow = self.flow
        reads = [read for read in flow.reads(result) if flow.observes(read, assign, result)]
        if not self.context.profile.imports_gym or any((self._constant_index(read) or 0) in (4, -5) for read in reads):
            return  # Gymnasium code, or indices that already count five values: nothing to move
        if decision.action is Action.REPORT:
            self.report(assign, "GM304", f"{decision.reason}; if it is a Gym env, its step returns five values", FixKind.FLAG)
            return
        for read in reads:
            index = self._constant_index(read)
            subscript = self.facts.parent(read)
            dominated = flow.dominates(assign, read, result)
            if index in (0, 1, -1) and dominated:
                continue  # observation, reward and info keep their places
            if index == 3 and dominated:
                self.plan.replace(subscript, lambda node: _with_index(node, 4))  # type: ignore[arg-type]
                exact = FixKind.AUTO if decision.action is Action.REWRITE else FixKind.ASSIST
                self.report(subscript, "GM304", f"`{result.id}[3]` (info) is `{result.id}[4]` now", exact)  # type: ignore[arg-type]
            elif index == 2 and dominated and not (vector or looks_vectorised(receiver, result)):
                bare = stands_alone(subscript, self.facts.parent(subscript))  # type: ignore[arg-type]
                self.plan.replace(subscript, lambda node, bare=bare: _either(node, bare))  # type: ignore[arg-type, misc]
                self.report(
                    subscript,  # type: ignore[arg-type]
                    "GM304",
                    f"`{result.id}[2]` (done) is now `{result.id}[2] or {result.id}[3]`; "
                    f"if it feeds bootstrapping, use `{result.id}[2]` (terminated) alone",
                )
            else:
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
        slice=[element.with_changes(slice=element.slice.with_changes(value=cst.Integer(str(index))))]  # type: ignore[union-attr]
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
