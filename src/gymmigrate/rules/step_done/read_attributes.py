"""The GM302 findings on a step's ``done`` stored in an attribute of ``self``
(``obs, r, self.done, info = env.step(a)``): a read of it stored with the next state in
the same block reads ``terminated``; a test of it that chooses the discount, or a read
stored as a value elsewhere in the class, asks the step's question.

Separate from ``read_reports.py`` because an attribute's reads are found through the
class, not through the flow of one name. ``DoneAttributeReports`` sits right above
``DoneReadReports`` in the family's resolution order.
"""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.module import walk
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.step_done.common import StepNames
from gymmigrate.rules.step_done.next_state import DoneStep
from gymmigrate.rules.step_done.read_reports import DoneReadReports


class DoneAttributeReports(DoneReadReports):
    """The GM302 findings on a ``done`` stored in ``self`` (mixed into the family)."""

    def _report_stored_attribute(self, assign: ast.Assign, target: ast.expr, names: StepNames) -> None:
        """``obs, r, self.done, info = env.step(a)`` and ``self.done`` stored as a value
        elsewhere, or tested by an ``if`` that chooses the discount (``_report_discount_tests``)."""
        self._report_discount_tests(assign, target, names)
        self._report_attribute_left_unread(assign, target, names)
        for read in self._self_attribute_data_reads(assign, target):
            if id(read) not in self.reported_reads and self._claim_stored_attribute(assign, target, names, read):
                continue
            if id(read) not in self.reported_reads:
                self.reported_reads.add(id(read))
                self.report(
                    read,
                    "GM302",
                    f"`{self.facts.segment(read)}` is set by the step on line {assign.lineno} to "
                    f"`{names.terminated} or {names.truncated}`; if this value masks bootstrapping from the next state, store "
                    f"`{names.terminated}` there",
                    FixKind.FLAG,
                    question=("GM302", id(assign)),
                )

    def _report_attribute_left_unread(self, assign: ast.Assign, target: ast.expr, names: StepNames) -> None:
        """``obs, r, self.terminal, info = self.env.step(a)`` where nothing in this module reads
        ``self.terminal``: the flag leaves the class (a base elsewhere packs it into the
        experience its step returns, a learner reads it from the object), so its readers are
        beyond what this file shows. It keeps the episode's end, which is right for ending
        loops, but a learner that masks bootstrapping with it now masks time-limit cuts too:
        one question for the class, asked at its first such step."""
        if not (isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self"):
            return
        classdef = self.facts.enclosing_class(assign)
        if classdef is None or any(
            isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Load) for node in self.facts.attributes.get(target.attr, ())
        ):
            return  # read in this module: those reads are decided where they are
        spelled = self.facts.segment(target)
        self.report(
            assign,
            "GM302",
            f"`{spelled}` keeps `{names.terminated} or {names.truncated}`, the episode's end legacy `done` was, and leaves "
            f"`{classdef.name}` (nothing in this module reads it: it is stored for code elsewhere, such as an experience "
            "record the step returns): where a learner uses it as a bootstrap mask (`0 if terminal else 1`, a TD or "
            f"return target), a time-limit truncation now stops bootstrapping; store `{names.terminated}` beside it for "
            "the mask",
            FixKind.FLAG,
            question=("GM302 stored", id(classdef), target.attr),
        )

    def _report_discount_tests(self, assign: ast.Assign, target: ast.expr, names: StepNames) -> None:
        """``if self._done: return ts.termination(obs, r)`` / ``return obs, r, 0.0`` against
        ``return obs, r, self._discount``: the test of the stored done chooses the discount
        of the transition (0: no bootstrapping from the next state), so a time-limit
        truncation now drops it too. A question, as for any value that masks bootstrapping."""
        if not (isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self"):
            return
        classdef = self.facts.enclosing_class(assign)
        if classdef is None:
            return
        for node in self.facts.attributes.get(target.attr, ()):
            if not (
                isinstance(node, ast.Attribute)
                and isinstance(node.ctx, ast.Load)
                and isinstance(node.value, ast.Name)
                and node.value.id == "self"
                and self.facts.enclosing_class(node) is classdef
                and id(node) not in self.reported_reads
            ):
                continue
            if not self._discount_test(node):
                continue
            self.reported_reads.add(id(node))
            self.report(
                node,
                "GM302",
                f"`{self.facts.segment(node)}` is set by the step on line {assign.lineno} to `{names.terminated} or "
                f"{names.truncated}` and chooses the discount here (0: no bootstrapping from the next state): test "
                f"`{names.terminated}` for the terminal transition, and end a truncated one with its discount kept",
                FixKind.FLAG,
                question=("GM302", id(assign)),
            )

    def _claim_stored_attribute(self, assign: ast.Assign, target: ast.expr, names: StepNames, read: ast.Attribute) -> bool:
        """``obs2, r, self.done, info = env.step(a)`` then, in a later statement of the same
        block with no store of ``self.done`` between, ``memory.append((s, obs2, self.done))``:
        the read holds this step's flag, and where it masks bootstrapping from the step's next
        state it reads ``terminated``, as a plain local would (``self.done`` keeps the episode's
        end for the code that resets on it). True when claimed."""
        block = self._sibling_block(assign)
        statement = self.facts.statement_of(read)
        if block is None or statement not in block or block.index(statement) <= block.index(assign):
            return False
        attribute = target.attr  # type: ignore[attr-defined]
        between = block[block.index(assign) + 1 : block.index(statement) + 1]
        if any(
            isinstance(node, ast.Attribute) and node.attr == attribute and not isinstance(node.ctx, ast.Load)
            for stmt in between
            for node in walk(stmt)
        ):
            return False
        step = DoneStep(assign, read, names, assign.targets[0])  # type: ignore[arg-type]
        if not self._masks_next_state(read, step) or self._readers_keep_boundary(read, step):  # type: ignore[arg-type]
            return False
        terminated = names.terminated
        noted = self.notes.step_unpacks.get(assign)
        if noted is not None:
            noted.claimed_reads += 1
        self.plan.replace(read, lambda node: cst.Name(terminated, lpar=node.lpar, rpar=node.rpar))
        self.reported_reads.add(id(read))
        self.report(
            read,
            "GM302",
            f"`{self.facts.segment(read)}` is stored with the next state `{self.facts.segment(step.target.elts[0])}`, "
            f"set by the step on line {assign.lineno}: it now reads `{terminated}`, so a time-limit truncation still "
            f"bootstraps (`{self.facts.segment(read)}` keeps `{names.terminated} or {names.truncated}` for ending the episode)",
            FixKind.ASSIST,
            Tier.NOTE,
        )
        return True
