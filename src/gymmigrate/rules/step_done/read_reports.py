"""The findings on reads of a rewritten step's ``done`` (GM302): a read rewritten to
``terminated`` (a claim), the notes where the code settles what the flag means, and the
questions where it does not.

Every read is reported at most once (``reported_reads``); the reads of one step ask one
question, what its ``done`` should mean.
"""

from __future__ import annotations

import ast
from collections.abc import Hashable

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.class_shapes import is_batched_step_return, keeps_legacy_step
from gymmigrate.facts.decisions import Decision
from gymmigrate.facts.done_uses import (
    DoneUse,
    always_false_here,
    classify_done_read,
    loaded_names,
    multiplies_bare,
    stored_in_sequence,
    value_site,
)
from gymmigrate.facts.flow import bound_names
from gymmigrate.facts.module import own_returns
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.step_done.bookkeeping import DoneBookkeeping
from gymmigrate.rules.step_done.common import TIME_LIMIT_KEY, StepNames
from gymmigrate.rules.step_done.next_state import DoneStep, repacks_step
from gymmigrate.rules.step_done.read_uses import resets


class DoneReadReports(DoneBookkeeping):
    """The GM302 findings on reads of ``done`` (mixed into the family)."""

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
            self.report(
                read,
                "GM302",
                f"{decision.reason}: if it is a Gym env, `{read.id}` {what} here: read `terminated` once the step "
                "gives five values, so a time-limit truncation still bootstraps",
                FixKind.FLAG,
                question=question,
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
            if _zero(when_done) and any(isinstance(n, ast.Call) for n in ast.walk(otherwise)) and not resets(otherwise):
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
                and any(isinstance(n, ast.Call) for n in ast.walk(statement.value))
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

    def _claim(
        self, read: ast.Name, step: DoneStep, none_mask: str | None = None, callee: str | None = None, tail: str | None = None
    ) -> None:
        terminated = step.names.terminated
        self.notes.step_unpacks[step.assign].claimed_reads += 1
        self.plan.replace(read, lambda node: node.with_changes(value=terminated))
        next_state = self.facts.segment(step.target.elts[0])
        if none_mask is not None:
            message = (
                f"`{read.id}` decides whether the stored next state `{none_mask}` is None (a terminal transition, "
                f"no bootstrapping): it now reads `{terminated}`, so a time-limit truncation keeps its next state"
            )
        elif tail is not None:
            message = (
                f"`{read.id}` is stored in {tail}: it now reads `{terminated}`, so a time-limit truncation still "
                "bootstraps"
            )
        elif callee is not None:
            message = (
                f"`{read.id}` is passed with the next state to `{callee}`, which masks bootstrapping from that state "
                f"with it (a target or stored transition): it now reads `{terminated}`, so a time-limit truncation "
                "still bootstraps"
            )
        else:
            message = (
                f"`{read.id}` masks bootstrapping from the next state `{next_state}` (a target or stored transition): "
                f"it now reads `{terminated}`, so a time-limit truncation still bootstraps"
            )
        self._report_read(read, message, FixKind.ASSIST, Tier.NOTE)  # the migration guide's own rewrite

    def _readers_keep_boundary(self, read: ast.Name, step: DoneStep) -> bool:
        """The flag is stored with the next state, but the readers this module shows use the
        stored flag to end something (``if done: break``) or to pick the next record's value
        (``m[t + 1].value``, a new episode after a reset): then it is the episode boundary and
        stays ``done``, with a note, or a question when other readers mask a next-state value
        with it. False: no such reader, the read is decided as before."""
        readers = self._stored_flag_readers(read)
        boundary = [r.node.lineno for r in readers if r.use == "boundary"]
        if not boundary:
            return False
        masks = [r.node.lineno for r in readers if r.use == "mask"]
        names = step.names
        kept = f"it stays `{names.terminated} or {names.truncated}`, the episode boundary legacy `done` was"
        if masks:
            self._report_read(
                read,
                f"`{read.id}` is stored with the next state; its readers use the stored flag both as an episode "
                f"boundary (line {boundary[0]}) and to mask a next-state value (line {masks[0]}): {kept}. Store "
                f"`{names.terminated}` beside it for the mask, so that a time-limit truncation still bootstraps",
                FixKind.FLAG,
                question=("GM302", id(step.assign)),
            )
        else:
            self._report_read(
                read,
                f"`{read.id}` is stored with the next state, but its readers use the stored flag only as an episode "
                f"boundary (line {boundary[0]}: a cut, or the next record's value), never to mask a next-state value: "
                f"{kept}. To bootstrap time-limit truncations, also store `{names.terminated}` and mask the final "
                "observation's value with it",
                FixKind.FLAG,
                Tier.NOTE,
            )
        return True

    def _report_bootstrap_choice(self, read: ast.Name, step: DoneStep, dominated: bool = True) -> None:
        names = step.names
        why = (
            "its branches also do more than assign (loop control stays on it)"
            if dominated
            else f"it may not come from the step on line {step.assign.lineno}"
        )
        self._report_read(
            read,
            f"`{read.id}` chooses whether a value is computed from the next state (a bootstrap target), but {why}; "
            f"it now means `{names.terminated} or {names.truncated}`: decide bootstrapping on `{names.terminated}` "
            f"so that a time-limit truncation still bootstraps, and keep `{read.id}` for ending the episode",
            FixKind.FLAG,
            question=("GM302", id(step.assign)),
        )

    def _discount_test(self, read: ast.expr) -> bool:
        """``if done: return ts.termination(obs, r)`` (or a 0 where the other return has the
        discount): the test of ``read`` chooses the transition's discount."""
        test: ast.AST = read
        parent = self.facts.parent(test)
        if isinstance(parent, ast.UnaryOp) and isinstance(parent.op, ast.Not):
            test, parent = parent, self.facts.parent(parent)
        return isinstance(parent, ast.If) and parent.test is test and _chooses_discount(parent, self.facts.enclosing_function(parent))

    def _split_by_time_limit(self, read: ast.Name, step: DoneStep) -> bool:
        """``if done:`` whose body tells a time-limit end apart from a terminal one by the
        step's ``info["TimeLimit.truncated"]`` (directly, or through a name bound from it
        alone in that body) before choosing the discount: GM303 makes that test
        ``truncated and not terminated``, so the body already ends a truncated transition with
        its discount kept and a terminated one without: nothing is left to decide."""
        branch = self.facts.parent(read)
        info = step.target.elts[-1] if step.target.elts else None
        if not (isinstance(branch, ast.If) and branch.test is read and isinstance(info, ast.Name)):
            return False
        flags: set[str] = set()
        for statement in branch.body:
            if (
                isinstance(statement, ast.Assign)
                and len(statement.targets) == 1
                and isinstance(statement.targets[0], ast.Name)
                and _only_time_limit_key(statement.value, info.id)
            ):
                flags.add(statement.targets[0].id)
                continue
            if isinstance(statement, ast.If):
                test = statement.test
                if (isinstance(test, ast.Name) and test.id in flags) or _only_time_limit_key(test, info.id):
                    return True
            if any(name in flags or name == info.id for name in _names_bound_within(statement)):
                return False  # the flag (or info) changes before the test
        return False

    def _report_discount_choice(self, read: ast.Name, step: DoneStep) -> None:
        names = step.names
        self._report_read(
            read,
            f"`{read.id}` chooses the discount of the transition here (0: no bootstrapping from the next state), and "
            f"it now means `{names.terminated} or {names.truncated}`: test `{names.terminated}` for the terminal "
            "transition, and end a truncated one with its discount kept",
            FixKind.FLAG,
            question=("GM302", id(step.assign)),
        )

    def _report_none_mask(self, read: ast.Name, step: DoneStep, masked: str, boundary: str | None = None) -> None:
        names = step.names
        if boundary is not None:
            self._report_read(
                read,
                f"`{read.id}` sets the next state `{masked}` to None, and `{boundary}` also reads that None as the "
                f"episode's end (it closes or flushes what the episode gathered): the test stays `{names.terminated} "
                f"or {names.truncated}`, as legacy `done` was, so a time-limit truncation is still stored as terminal. "
                f"To bootstrap it, hand the final state on and tell the callee `{names.terminated}` apart from the end",
                FixKind.FLAG,
                question=("GM302", id(step.assign)),
            )
            return
        self._report_read(
            read,
            f"`{read.id}` decides whether the stored next state `{masked}` is None (no bootstrapping) and also "
            f"controls the loop here; it now means `{names.terminated} or {names.truncated}`: set `{masked}` to None "
            f"on `{names.terminated}` only, and keep `{read.id}` for ending the episode",
            FixKind.FLAG,
            question=("GM302", id(step.assign)),
        )

    def _self_attribute_data_reads(self, near: ast.AST, target: ast.expr) -> list[ast.Attribute]:
        """Reads of ``self.<attr>`` (``target``) in the class around ``near`` that feed a value."""
        if not (isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self"):
            return []
        classdef = self.facts.enclosing_class(near)
        if classdef is None:
            return []
        return [
            node
            for node in self.facts.attributes.get(target.attr, ())
            if isinstance(node, ast.Attribute)
            and isinstance(node.ctx, ast.Load)
            and isinstance(node.value, ast.Name)
            and node.value.id == "self"
            and self.facts.enclosing_class(node) is classdef
            and classify_done_read(node, self.facts) is DoneUse.DATA  # type: ignore[arg-type]
        ]

    def _report_stored_attribute(self, assign: ast.Assign, target: ast.expr, names: StepNames) -> None:
        """``obs, r, self.done, info = env.step(a)`` and ``self.done`` stored as a value
        elsewhere, or tested by an ``if`` that chooses the discount (``_report_discount_tests``)."""
        self._report_discount_tests(assign, target, names)
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
            for node in ast.walk(stmt)
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

    def _sibling_block(self, statement: ast.stmt) -> list[ast.stmt] | None:
        """The statement list that holds ``statement`` directly."""
        parent = self.facts.parent(statement)
        for field in ("body", "orelse", "finalbody"):
            block = getattr(parent, field, None)
            if isinstance(block, list) and statement in block:
                return block
        return None

    def _report_open_read(self, read: ast.Name, step: DoneStep) -> None:
        use = classify_done_read(read, self.facts)
        names = step.names
        # The reads of one step's done ask one question: what its done should mean. Handed to
        # a callee (``agent.observe(obs, r, done, reset)``), the question is what that callee
        # does with the argument, asked once however many loops call it.
        question: tuple[object, ...] = ("GM302", id(step.assign))
        call = self.facts.parent(read)
        argument: tuple[str, object] | None = None
        if isinstance(call, ast.Call) and read in call.args and not any(isinstance(a, ast.Starred) for a in call.args):
            argument = (self.facts.segment(call.func), call.args.index(read))
        elif isinstance(call, ast.keyword) and call.arg is not None and isinstance(caller := self.facts.parent(call), ast.Call):
            argument = (self.facts.segment(caller.func), call.arg)
        if argument is not None:
            question = self.callee_questions.setdefault(argument, question)
        owner = self._dominating_step(read, step.done)
        statement = self.facts.statement_of(read)
        stored = (
            self._self_attribute_data_reads(read, statement.targets[0])
            if isinstance(statement, ast.Assign) and statement.value is read and len(statement.targets) == 1
            else []
        )
        beside = self._beside_bootstrap_flag(read, step) if owner is step.assign else None
        if always_false_here(read, self.facts):
            # ``if done: obs = env.reset(); done = False`` just above: a false flag ends
            # nothing and masks nothing (a note).
            self._report_read(
                read,
                f"`{read.id}` is always false here (the `if {read.id}:` just above sets it false): it decides nothing "
                "about the episode's end or bootstrapping",
                FixKind.FLAG,
                Tier.NOTE,
            )
        elif beside is not None:
            # Nothing to decide: both flags keep what they meant (a note).
            self._report_read(
                read,
                f"`{read.id}` is passed beside `{beside}`, a bootstrap flag computed from it after the step: "
                f"`{read.id}` is the episode boundary there and stays `{names.terminated} or {names.truncated}`, "
                f"as legacy `done` was; `{beside}` keeps its meaning (it can become `{names.terminated}` where its "
                "own test is the env's time limit)",
                FixKind.FLAG,
                Tier.NOTE,
            )
        elif owner is step.assign and (factor := self._bare_factor(read, step)) is not None:
            # ``q(s2) * gamma * done``: no mask (that reads ``1 - done``); keeping the episode's
            # end computes what the legacy code did, ``terminated`` would not.
            self._report_read(
                read,
                f"`{read.id}` {factor}, not `1 - {read.id}`: the legacy code bootstraps only when the episode ends. "
                f"It stays `{names.terminated} or {names.truncated}`, which computes the same; if the factor was meant "
                f"as a mask, write `(1 - {names.terminated})` there",
                FixKind.FLAG,
                question=question,
            )
        elif owner is step.assign and (chooser := self._returned_to_bootstrap_choice(read)) is not None:
            helper, test = chooser
            self._report_read(
                read,
                f"`{read.id}` is returned by `{helper}`, and its caller tests it at line {test.lineno} to choose "
                f"whether to bootstrap from the returned next state: it stays `{names.terminated} or "
                f"{names.truncated}` here; return `{names.terminated}` as well and test that at line {test.lineno}, "
                f"so that a time-limit truncation still bootstraps (keep `{read.id}` for ending the episode)",
                FixKind.FLAG,
                question=question,
            )
        elif owner is step.assign and (settled := self._only_ends_or_unread(read)) is not None:
            # The code shows what the flag is for: ending a loop, or nothing at all (a note).
            self._report_read(
                read,
                f"`{read.id}` {settled}: it stays `{names.terminated} or {names.truncated}`, the episode's end "
                "legacy `done` was",
                FixKind.FLAG,
                Tier.NOTE,
            )
        elif (unwrapped := self._unwrapped_for_loop_exit(read)) is not None:
            # ``done = done[0] if isinstance(done, list) else done`` then ``while not done``:
            # whichever step bound it, the flag only ends a loop (a note).
            self._report_read(
                read,
                f"`{read.id}` {unwrapped}: it stays `{names.terminated} or {names.truncated}`, the episode's end "
                "legacy `done` was",
                FixKind.FLAG,
                Tier.NOTE,
            )
        elif (books := self._bookkeeping(read, step, owner is step.assign)) is not None:
            # The code shows the flag only keeps an episode's books: the episode's end is
            # what it needs, however the episode ended (a note).
            self._report_read(
                read,
                f"`{read.id}` {books}",
                FixKind.FLAG,
                Tier.NOTE,
            )
        elif owner is not step.assign and self._bootstrap_choice(read, step, dominated=False) is not None:
            self._report_bootstrap_choice(read, step, dominated=False)
        elif stored and any(id(node) in self.reported_reads for node in stored):
            self.reported_reads.add(id(read))  # the stored value is reported already: one item
        elif stored:
            self._report_read(
                read,
                f"`{read.id}` is kept in `{self.facts.segment(statement.targets[0])}` and stored as a value on line "  # type: ignore[attr-defined]
                f"{stored[0].lineno}; it means `{names.terminated} or {names.truncated}`: if it masks bootstrapping "
                f"from the next state, store `{names.terminated}`",
                FixKind.FLAG,
                question=question,
            )
        elif owner is step.assign and use is DoneUse.DATA and (episode := self._episode_store_with_tail(read, step)) is not None:
            container, handed, emptied = episode
            callee = self._callee_masks_tail(handed, container)
            if callee is not None:
                self._claim(
                    read,
                    step,
                    tail=f"`{container}`, which `{callee}()` walks back from the value of the next state it is handed "
                    f"(line {handed.lineno}), masking that value with each stored flag",
                )
                return
            self._report_read(
                read,
                f"`{read.id}` is stored in `{container}`, which holds one episode: at its end `{container}` is handed "
                f"to `{self.facts.segment(handed.func)}()` with a value of the next state (line {handed.lineno}) and "
                f"emptied (line {emptied.lineno}), so the last stored flag can only mask that value, a bootstrap. It "
                f"stays `{names.terminated} or {names.truncated}` here; if the callee masks it with the flag, store "
                f"`{names.terminated}` so that a time-limit truncation still bootstraps",
                FixKind.FLAG,
                question=question,
            )
        elif (
            owner is step.assign
            and ((use is DoneUse.DATA and stored_in_sequence(read, self.facts)) or self._stores_step_without_next_state(read, step))
            and not self._may_store_next_state(read, step)
        ):
            # Nothing to decide: the boundary means what legacy ``done`` meant (a note).
            self._report_read(
                read,
                f"`{read.id}` is stored per step without the next state (a rollout or a log): it stays "
                f"`{names.terminated} or {names.truncated}`, the episode boundary legacy `done` was. To bootstrap "
                f"time-limit truncations, also keep the value of the final observation and mask it with "
                f"`{names.terminated}`",
                FixKind.FLAG,
                Tier.NOTE,
            )
        elif owner is step.assign and self._in_kept_batch_return(read):
            # The batch's own four-field step (GM504/GM602 report the class): the flag is
            # each env's end for the batch's callers, as legacy ``done`` was (a note).
            self._report_read(
                read,
                f"`{read.id}` is returned among a batch's stacked flags, whose step keeps its four fields: it stays "
                f"`{names.terminated} or {names.truncated}`, each env's end, as legacy `done` was",
                FixKind.FLAG,
                Tier.NOTE,
            )
        elif owner is step.assign and self._in_kept_step_result(read):
            # ``results = zip(*[(obs, reward, done, info)] + replies)``, then ``return results``:
            # the four fields of a step the run keeps (GM504 reports it) hand the flag on to
            # that step's callers, which read it as the episode's end, as legacy ``done`` was.
            self._report_read(
                read,
                f"`{read.id}` is handed on in the four fields of a step the run keeps (GM504): it stays "
                f"`{names.terminated} or {names.truncated}`, the episode's end, as legacy `done` was",
                FixKind.FLAG,
                Tier.NOTE,
            )
        elif owner is step.assign and self._sent_with_reset_observation(read, step):
            # ``if done: obs = env.reset()`` then ``pipe.send((obs, reward, done, ...))``: the
            # receiver gets the next episode's first observation, never the final one, so
            # the flag can only end the episode (a note).
            self._report_read(
                read,
                f"`{read.id}` is handed on with the observation of the reset that follows the episode's end, never "
                f"the final one, so no receiver can bootstrap from it: it stays `{names.terminated} or "
                f"{names.truncated}`, the episode's end",
                FixKind.FLAG,
                Tier.NOTE,
            )
        elif owner is step.assign and self._and_not_truncation(read, step):
            # ``done and not <info's TimeLimit.truncated>``: with the run's rewrite of that
            # key it is exactly ``terminated`` (a note).
            self._report_read(
                read,
                f"`{read.id} and not {self.facts.segment(self.facts.parent(read).values[1].operand)}` is "  # type: ignore[union-attr]
                f"`{names.terminated}` once the time-limit key is the step's truncated: nothing to change",
                FixKind.FLAG,
                Tier.NOTE,
            )
        elif use is DoneUse.AMBIGUOUS and owner is step.assign and self._hands_step_on(read, step):
            self._report_read(
                read,
                f"`{read.id}` is handed on with the step's observation and reward (an env-like reply or adapter): "
                f"it stays `{names.terminated} or {names.truncated}`, the episode's end, for its receiver to read",
                FixKind.FLAG,
                Tier.NOTE,
            )
        elif use is DoneUse.DATA and owner is step.assign:
            self._report_read(
                read,
                f"`{read.id}` used as a value now means `{names.terminated} or {names.truncated}`; if it masks "
                f"bootstrapping from the next state, use `{names.terminated}` there",
                FixKind.FLAG,
                question=question,
            )
        elif use is DoneUse.DATA:
            self._report_read(
                read,
                f"`{read.id}` used as a value may not come from the step on line {step.assign.lineno}; "
                f"if it feeds bootstrapping, use `{names.terminated}` there",
                FixKind.FLAG,
                question=question,
            )
        elif use is DoneUse.AMBIGUOUS:
            self._report_read(
                read,
                f"`{read.id}` now means `{names.terminated} or {names.truncated}`; "
                f"if this use decides bootstrapping, use `{names.terminated}`",
                FixKind.FLAG,
                question=question,
            )

    def _sent_with_reset_observation(self, read: ast.Name, step: DoneStep) -> bool:
        """``pipe.send((obs, reward, done, info, total))`` after
        ``if done: obs = env.reset()`` in the same block as the step: the observation sent
        with a true flag is the new episode's, so no receiver can bootstrap from the final
        one. No other element may read the observation."""
        site = self.facts.parent(read)
        holder = self.facts.parent(site) if isinstance(site, ast.Tuple) else None
        # a call's only argument (a return of the step's values is a step of its own: GM504)
        if not isinstance(holder, ast.Call) or holder.args != [site] or holder.keywords:
            return False
        first = step.target.elts[0] if step.target.elts else None
        if not isinstance(first, ast.Name):
            return False
        observation = first.id
        if not any(isinstance(e, ast.Name) and e.id == observation for e in site.elts):  # type: ignore[union-attr]
            return False
        if any(observation in loaded_names(e) for e in site.elts if not (isinstance(e, ast.Name) and e.id == observation)):  # type: ignore[union-attr]
            return False
        block = self._sibling_block(step.assign)
        statement = self.facts.statement_of(read)
        if block is None or statement not in block:
            return False
        between = block[block.index(step.assign) + 1 : block.index(statement)]
        if any(observation in _names_bound_within(s) for s in between if not _resets_on_done(s, step.done.id, observation)):
            return False
        return any(_resets_on_done(s, step.done.id, observation) for s in between)

    def _and_not_truncation(self, read: ast.Name, step: DoneStep) -> bool:
        """``failure = done and not limited`` where ``limited`` is bound once, after the step
        in its block, from the step's info's ``'TimeLimit.truncated'`` alone: the run turns
        that into the step's truncated (without terminated), so the expression is exactly
        ``terminated``."""
        parent = self.facts.parent(read)
        if not (isinstance(parent, ast.BoolOp) and isinstance(parent.op, ast.And) and len(parent.values) == 2 and parent.values[0] is read):
            return False
        other = parent.values[1]
        if not (isinstance(other, ast.UnaryOp) and isinstance(other.op, ast.Not) and isinstance(other.operand, ast.Name)):
            return False
        info = step.target.elts[-1] if step.target.elts else None
        if not isinstance(info, ast.Name):
            return False
        block = self._sibling_block(step.assign)
        statement = self.facts.statement_of(read)
        if block is None or statement not in block:
            return False
        between = block[block.index(step.assign) + 1 : block.index(statement)]
        flag = other.operand.id
        binders = [s for s in between if flag in _names_bound_within(s)]
        if len(binders) != 1 or not isinstance(binders[0], ast.Assign) or len(binders[0].targets) != 1:
            return False
        if any(read.id in _names_bound_within(s) for s in between):
            return False
        return _only_time_limit_key(binders[0].value, info.id)

    def _in_kept_batch_return(self, read: ast.Name) -> bool:
        """``read`` is in a stacked return of a step that keeps its four fields (a batch)."""
        statement = self.facts.statement_of(read)
        function = self.facts.enclosing_function(read)
        classdef = self.facts.enclosing_class(read)
        return (
            isinstance(statement, ast.Return)
            and function is not None
            and classdef is not None
            and function.name == "step"
            and keeps_legacy_step(classdef)
            and is_batched_step_return(statement.value, function)
        )

    def _in_kept_step_result(self, read: ast.Name) -> bool:
        """``read`` is the done of an ``(obs, reward, done, info)`` tuple that the ``step`` of a
        class keeping its four fields returns, directly or through one name it returns."""
        site = self.facts.parent(read)
        function = self.facts.enclosing_function(read)
        classdef = self.facts.enclosing_class(read)
        if not (
            isinstance(site, ast.Tuple)
            and len(site.elts) == 4
            and site.elts[2] is read
            and function is not None
            and classdef is not None
            and function.name == "step"
            and self.facts.parent(function) is classdef
            and keeps_legacy_step(classdef)
        ):
            return False
        statement = self.facts.statement_of(read)
        if isinstance(statement, ast.Return):
            return True
        if not (isinstance(statement, ast.Assign) and len(statement.targets) == 1 and isinstance(statement.targets[0], ast.Name)):
            return False
        name = statement.targets[0].id
        return any(isinstance(r.value, ast.Name) and r.value.id == name for r in own_returns(function))

    def _report_read(
        self, read: ast.Name, message: str, kind: FixKind, tier: Tier | None = None, question: Hashable | None = None
    ) -> None:
        if id(read) not in self.reported_reads:
            self.reported_reads.add(id(read))
            self.report(read, "GM302", message, kind, tier, question=question)


def _names_bound_within(statement: ast.stmt) -> set[str]:
    """The names a statement (and the statements inside it) binds."""
    return {
        node.id for node in ast.walk(statement) if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store)
    }


def _resets_on_done(statement: ast.stmt, done: str, observation: str) -> bool:
    """``if done: observation = env.reset()`` (or ``env.reset()[0]``, or the first of an unpack)."""
    if not (isinstance(statement, ast.If) and isinstance(statement.test, ast.Name) and statement.test.id == done):
        return False
    for inner in statement.body:
        if not isinstance(inner, ast.Assign) or len(inner.targets) != 1:
            continue
        target, value = inner.targets[0], inner.value
        if isinstance(target, ast.Tuple) and target.elts:
            target = target.elts[0]
        if isinstance(value, ast.Subscript):
            value = value.value
        if (
            isinstance(target, ast.Name)
            and target.id == observation
            and isinstance(value, ast.Call)
            and isinstance(value.func, ast.Attribute)
            and value.func.attr == "reset"
        ):
            return True
    return False


def _only_time_limit_key(value: ast.expr, info: str) -> bool:
    """``info['TimeLimit.truncated']``, ``info.get('TimeLimit.truncated', False)``, or
    ``'TimeLimit.truncated' in info and`` one of them: a lookup of that key of ``info``,
    which GM303 replaces by ``truncated and not terminated`` (a bare membership test
    becomes ``truncated`` alone, and ``done and not truncated`` is not ``terminated``)."""
    if isinstance(value, ast.BoolOp) and isinstance(value.op, ast.And):
        parts = value.values
        return any(_time_limit_lookup(p, info) for p in parts) and all(
            _time_limit_lookup(p, info) or _time_limit_membership(p, info) for p in parts
        )
    return _time_limit_lookup(value, info)


def _is_key(node: ast.AST) -> bool:
    return isinstance(node, ast.Constant) and node.value == TIME_LIMIT_KEY


def _time_limit_lookup(node: ast.expr, info: str) -> bool:
    if isinstance(node, ast.Subscript):
        return isinstance(node.value, ast.Name) and node.value.id == info and _is_key(node.slice)
    return (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and node.func.attr == "get"
        and isinstance(node.func.value, ast.Name)
        and node.func.value.id == info
        and bool(node.args)
        and _is_key(node.args[0])
        and all(isinstance(a, ast.Constant) and a.value in (False, None) for a in node.args[1:])
    )


def _time_limit_membership(node: ast.expr, info: str) -> bool:
    return (
        isinstance(node, ast.Compare)
        and len(node.ops) == 1
        and isinstance(node.ops[0], ast.In)
        and _is_key(node.left)
        and isinstance(node.comparators[0], ast.Name)
        and node.comparators[0].id == info
    )


def _chooses_discount(branch: ast.If, function: ast.AST | None) -> bool:
    """One side of ``branch`` ends the transition without a discount: a ``termination(...)``
    call (dm_env, tf_agents), a ``discount``-named store of 0, or a returned tuple with 0
    where another return of ``function`` puts a ``discount``-named value."""
    discount_slots = {
        index
        for ret in (own_returns(function) if function is not None else [])
        if isinstance(ret.value, ast.Tuple)
        for index, element in enumerate(ret.value.elts)
        if any("discount" in _word(n).lower() for n in ast.walk(element))
    }
    for statement in [*branch.body, *branch.orelse]:
        for node in ast.walk(statement):
            if isinstance(node, ast.Call) and _word(node.func) == "termination":
                return True
            if isinstance(node, ast.Assign) and _zero(node.value) and any("discount" in _word(t).lower() for t in node.targets):
                return True
            if isinstance(node, ast.Return) and isinstance(node.value, ast.Tuple):
                if any(_zero(e) and i in discount_slots for i, e in enumerate(node.value.elts)):
                    return True
    return False


def _word(node: ast.AST) -> str:
    return node.id if isinstance(node, ast.Name) else node.attr if isinstance(node, ast.Attribute) else ""


def _zero(node: ast.AST) -> bool:
    return isinstance(node, ast.Constant) and not isinstance(node.value, bool) and node.value == 0
