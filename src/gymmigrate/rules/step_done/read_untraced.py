"""The GM302 questions on reads of ``done`` for a step left unrewritten because its
receiver is not shown to be a Gym env: where the flag decides bootstrapping from the next
state, the receiver's question names the read, so whoever decides one decides both.

Separate from ``read_reports.py`` because these reads are only named, never rewritten:
the next state is any name computed from the observation. ``DoneUntracedReports`` sits
between ``DoneReadReports`` and ``DoneSettledReads`` in the family's resolution order.
"""

from __future__ import annotations

import ast
from collections.abc import Hashable

from gymmigrate.edits.plan import UNTRACED_BOUNDARY, UNTRACED_MASK, UNTRACED_SPLIT
from gymmigrate.facts.decisions import Decision
from gymmigrate.facts.done_uses import (
    DoneUse,
    classify_done_read,
    loaded_names,
    multiplies_bare,
    stored_in_sequence,
    value_site,
)
from gymmigrate.facts.flow import bound_names
from gymmigrate.facts.module import walk
from gymmigrate.findings import FixKind
from gymmigrate.rules.step_done.next_state import DoneStep, repacks_step
from gymmigrate.rules.step_done.read_settled import DoneSettledReads, _zero
from gymmigrate.rules.step_done.read_uses import resets


class DoneUntracedReports(DoneSettledReads):
    """The GM302 questions on reads of an unrewritten step's ``done`` (mixed into the family)."""

    def _report_untraced_masks(self, step: DoneStep, decision: Decision, question: Hashable | None) -> None:
        """The step is left (its receiver is not shown to be a Gym env), but its ``done``
        decides bootstrapping from the next state (``memory.push(s, a, r, s2, done)``,
        ``if done: s2 = zeros``, ``R = 0.0 if done else v(s)``): the same question names
        those reads, so whoever decides the receiver decides them with it (``terminated``
        there once the step gives five values). Loop control and display are not named."""
        for read in self.flow.reads(step.done):
            # the step binds the value read, also past a loop that may not run (an n-step
            # rollout's ``if done: R = 0.0`` after its ``for``): only named, never rewritten
            binding = self.flow.last_binding_before(read, step.done)
            if binding is None or self.facts.statement_of(binding) is not step.assign:
                continue
            what = self._untraced_bootstrap_use(read, step)
            if what is None:
                continue
            # per use, as the certain path decides it: a mask reads ``terminated``; a store
            # it keeps as the rollout's episode boundary, or a test that also resets the env,
            # needs the episode's end whatever ended it
            advice = f"{UNTRACED_MASK}, so a time-limit truncation still bootstraps"
            if classify_done_read(read, self.facts) is DoneUse.DATA:
                if not (self._masks_next_state(read, step) or self._callee_masks(read, step) is not None) and self._stored_as_boundary(read, step):
                    what = "is stored per step without the next state (a rollout's episode boundary)"
                    advice = f"{UNTRACED_BOUNDARY}, the episode's end legacy `done` was"
            elif (replaced_first := self._starts_new_episode(read, step)) is not None:
                if replaced_first:
                    # the test replaces a name of the next state, then resets: the reset needs
                    # the episode's end, the replacement only ``terminated``
                    what = f"{what} and ends the episode (its branch resets the env)"
                    advice = (
                        f"{UNTRACED_SPLIT}: reset under `terminated or truncated`, the episode's end legacy `done` "
                        "was, and replace the next state only under `terminated`"
                    )
                else:
                    # every name it sets comes after the reset: the new episode's start
                    what = "ends the episode: its branch resets the env and sets up the new episode"
                    advice = f"{UNTRACED_BOUNDARY}, the episode's end legacy `done` was"
            self.report(
                read,
                "GM302",
                f"{decision.reason}: if it is a Gym env, `{read.id}` {what} here: {advice}",
                FixKind.FLAG,
                question=question,
            )

    def _stored_per_step(self, read: ast.Name, step: DoneStep) -> bool:
        """The flag stored per step in a sequence or handed to a store with the step's reward
        but no next state: a rollout's episode boundary, unless the store may hold the next
        state (``_may_store_next_state``, checked by the caller)."""
        return (classify_done_read(read, self.facts) is DoneUse.DATA and stored_in_sequence(read, self.facts)) or (
            self._stores_step_without_next_state(read, step)
        )

    def _stored_as_boundary(self, read: ast.Name, step: DoneStep) -> bool:
        """What the certain path keeps as ``terminated or truncated`` with a note: a store
        per step without the next state (``experience = {"state": s, "terminal": done}``
        before ``s = s2``). After an auto-reset the next value belongs to another episode,
        so ``terminated`` there would join two episodes at a time-limit cut."""
        return self._stored_per_step(read, step) and not self._may_store_next_state(read, step)

    def _starts_new_episode(self, read: ast.Name, step: DoneStep) -> bool | None:
        """``if done:`` whose branch resets an env, at any depth (``if mode: s = env.reset(**cfg)``
        / ``else: s = env.reset()``): the test ends the episode. None when it does not;
        else whether a name computed from the observation is replaced before that reset
        (``if done: s2 = zeros; s = env.reset()``, a terminal transition) rather than set
        after it for the new episode (``s = env.reset(); ctx = init(s)``)."""
        parent = self.facts.parent(read)
        if not (isinstance(parent, ast.If) and parent.test is read):
            return None
        reset_at = next((index for index, statement in enumerate(parent.body) if resets(statement)), None)
        if reset_at is None:
            return None
        derived = self._derived_names(step)
        return any(
            isinstance(statement, ast.Assign)
            and not resets(statement.value)
            and any(name in derived for target in statement.targets for name in bound_names(target))
            for statement in parent.body[:reset_at]
        )

    def _untraced_bootstrap_use(self, read: ast.Name, step: DoneStep) -> str | None:
        """What ``read`` decides about bootstrapping, for a step left unrewritten (reported,
        never rewritten, so the next state is any name computed from the observation)."""
        next_state = self.facts.segment(step.target.elts[0])
        use = classify_done_read(read, self.facts)
        if use is DoneUse.DATA:
            if multiplies_bare(read, self.facts.parent):
                return None  # ``q(s2) * done``: no mask (the factor keeps ``done``)
            if repacks_step(self.facts.parent(read), read, step):
                return None  # ``(obs, reward, done, info)`` handed on: the step's own reply
            if self._beside_bootstrap_flag(read, step) is not None:
                return None  # passed beside its own bootstrap flag: there it is the episode's end
            derived = self._derived_names(step)
            if (
                self._masks_next_state(read, step)
                or self._callee_masks(read, step) is not None
                or loaded_names(value_site(read, self.facts)) & derived
            ):
                return f"masks bootstrapping from the next state `{next_state}`"
            return None
        node: ast.AST = read
        parent = self.facts.parent(node)
        negated = isinstance(parent, ast.UnaryOp) and isinstance(parent.op, ast.Not)
        if negated and parent is not None:
            node, parent = parent, self.facts.parent(parent)
        if self._bootstrap_choice(read, step, dominated=False) is not None:
            return "chooses whether to bootstrap from the next state"
        if isinstance(parent, ast.IfExp) and parent.test is node:
            when_done, otherwise = (parent.orelse, parent.body) if negated else (parent.body, parent.orelse)
            # ``final_value = 0.0 if done else value(s)``: no value past the episode's end
            if _zero(when_done) and any(isinstance(n, ast.Call) for n in walk(otherwise)) and not resets(otherwise):
                return "zeroes the value bootstrapped from the next state"
            return None
        if isinstance(parent, ast.If) and parent.test is node:
            done_branch, other = (parent.orelse, parent.body) if negated else (parent.body, parent.orelse)
            # ``if done: R = 0.0`` / ``else: R = value(s)``: no value past the episode's end
            zeroed = {
                name
                for statement in done_branch
                if isinstance(statement, ast.Assign) and _zero(statement.value)
                for target in statement.targets
                for name in bound_names(target)
            }
            if any(
                isinstance(statement, ast.Assign)
                and zeroed & {name for target in statement.targets for name in bound_names(target)}
                and any(isinstance(n, ast.Call) for n in walk(statement.value))
                and not resets(statement.value)
                for statement in other
            ):
                return "zeroes the value bootstrapped from the next state"
            derived = self._derived_names(step)
            for statement in done_branch:
                if (
                    isinstance(statement, ast.Assign)
                    and not resets(statement.value)
                    and any(name in derived for target in statement.targets for name in bound_names(target))
                ):
                    # ``if done: next_state = [0] * n`` (or None): a terminal transition
                    return f"decides whether the next state `{next_state}` is kept (replaced when the episode ends)"
        return None
