"""The findings on reads of a rewritten step's ``done`` (GM302): a read rewritten to
``terminated`` (a claim), the notes where the code settles what the flag means, and the
questions where it does not.

Every read is reported at most once (``reported_reads``); the reads of one step ask one
question, what its ``done`` should mean. What the code around a read settles by its shape
is asked of ``read_settled``; the reads of a step left unrewritten are ``read_untraced``'s,
a ``done`` stored in ``self`` is ``read_attributes``'.
"""

from __future__ import annotations

import ast
from collections.abc import Hashable

from gymmigrate.facts.done_uses import (
    DoneUse,
    always_false_here,
    classify_done_read,
)
from gymmigrate.facts.module import walk
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.step_done.common import TIME_LIMIT_KEY
from gymmigrate.rules.step_done.next_state import DoneStep
from gymmigrate.rules.step_done.read_untraced import DoneUntracedReports


class DoneReadReports(DoneUntracedReports):
    """The GM302 findings on reads of ``done`` (mixed into the family)."""

    def _claim(
        self,
        read: ast.Name,
        step: DoneStep,
        none_mask: str | None = None,
        callee: str | None = None,
        tail: str | None = None,
        cap: ast.If | None = None,
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
        if cap is not None:
            message += (
                f"; the loop's own step limit (line {cap.lineno}) sets `{read.id}` only to end the episode, a "
                "truncation the mask leaves out as well"
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
        info_key = self._stored_in_step_info(read, step) if owner is step.assign else None
        if info_key is not None:
            # ``info["done"] = done`` after the step: the key's readers are beyond this
            # code (a trainer's replay), and the flag now ends at truncations in its own
            # right; the store is where the choice is made.
            self._report_read(
                read,
                f"`{read.id}` is stored in the step's info as {info_key}: it stays `{names.terminated} or "
                f"{names.truncated}`, true at a time-limit truncation as legacy `done` was; Gymnasium tells the two "
                f"apart, so if readers of that key take it as the episode's real end (a replay's terminal flag), "
                f"store `{names.terminated}` there",
                FixKind.FLAG,
                question=question,
            )
        elif always_false_here(read, self.facts):
            # ``if done: obs = env.reset(); done = False`` just above: a false flag ends
            # nothing and masks nothing (a note).
            self._report_read(
                read,
                f"`{read.id}` is always false here (the `if {read.id}:` just above sets it false): it decides nothing "
                "about the episode's end or bootstrapping",
                FixKind.FLAG,
                Tier.NOTE,
            )
        elif (store := self._rollout_tail(read, step)) is not None:
            # ``values.append(v(s2) * (1 - done))`` after the rollout's loop: the flag of its last
            # step, which the rollout stores as its boundary; the read follows that decision.
            self._report_read(
                read,
                f"`{read.id}` after the loop is the flag of its last step (line {step.assign.lineno}), which the "
                f"rollout stores per step as the episode boundary (line {store.lineno}): it stays "
                f"`{names.terminated} or {names.truncated}` here too, as legacy `done` was. To bootstrap time-limit "
                f"truncations, mask with `{names.terminated}` both here and where the stored flags mask values (store "
                f"it beside them)",
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
        elif owner is step.assign and (stored_by := self._returned_to_store(read)) is not None:
            # The caller stores the returned flag with the returned next state (a replay
            # memory): that store masks bootstrapping, but the flag also leaves the helper for
            # the caller's other reads (loop control), so one item, at the store.
            helper, store, next_state = stored_by
            self.reported_reads.add(id(read))
            self._report_read(
                store,
                f"`{store.id}` is stored with the next state `{next_state}`, both returned by `{helper}`: the flag is "
                f"the step's `{read.id}` there (line {read.lineno}), now `{names.terminated} or "
                f"{names.truncated}`, so a time-limit truncation is stored as terminal. Return `{names.terminated}` "
                f"from `{helper}` as well and store it here (keep `{store.id}` for ending the episode)",
                FixKind.FLAG,
                question=question,
            )
        elif (owner is step.assign or self._returned_in_tuple(read)) and (settled := self._only_ends_or_unread(read)) is not None:
            # Returned to callers that only end a loop with it (or drop it): whichever binding
            # reaches the return (``done = True`` before a retry loop too), no caller bootstraps.
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
            after_reset = self._valued_after_reset(read, step)
            if after_reset is None:
                self._report_bootstrap_choice(read, step, dominated=False)
                return
            # ``if done: state = env.reset()`` ends each episode in the loop: with the flag
            # true here, ``state`` is the next episode's first state, which no bootstrap may
            # value. Legacy ``done`` guarded exactly that (a note).
            valued, reset = after_reset
            self._report_read(
                read,
                f"`{read.id}` chooses whether a value is computed from `{valued}`, but when it is true `{valued}` "
                f"was already replaced by the reset on line {reset.lineno} (the next episode's first state): it "
                f"stays `{names.terminated} or {names.truncated}`, as legacy `done` was; testing `{names.terminated}` "
                f"would value the new episode's state. To bootstrap a time-limit truncation, keep the final "
                f"observation before that reset and value it when `{names.truncated}`",
                FixKind.FLAG,
                Tier.NOTE,
            )
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
            (
                (owner is step.assign and self._stored_per_step(read, step))
                # carried into the next iteration's slot: only a store of the flag itself
                # (``news[i] = new``), never a call that also takes the step's observation
                or (owner is None and use is DoneUse.DATA and self._flag_alone_in_slot(statement, read) and self._step_or_start_flag(read, step))
            )
            and not self._may_store_next_state(read, step)
        ):
            # Nothing to decide: the boundary means what legacy ``done`` meant (a note).
            self.rollout_stores.setdefault(step.assign, read)
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

    def _report_zero_tails(self, step: DoneStep) -> None:
        """``if done: buffer.store(trajectory, 0); trajectory = []``: an on-policy rollout ends
        its trajectory on the kept ``done`` with a last value of 0. That is right for a real
        end and what legacy code did, but a time-limit truncation is now told apart and
        should bootstrap from the final observation's value instead. One item per rollout
        function, naming every such line."""
        function = self.facts.enclosing_function(step.assign)
        if function is None or id(function) in self.zero_tail_functions:
            return
        if TIME_LIMIT_KEY in self.facts.segment(function):
            return  # the code already tells truncations apart
        lines = self._zero_tails(step, function)
        if not lines:
            return
        self.zero_tail_functions.add(id(function))
        names = step.names
        shown = ", ".join(str(line) for line in lines)
        observation = self.facts.segment(step.target.elts[0])
        self.report(
            step.assign,
            "GM302",
            f"`{step.done.id}` ends a trajectory with a last value of 0 (line{'s' if len(lines) > 1 else ''} {shown}): "
            f"it stays `{names.terminated} or {names.truncated}`, as legacy `done` was, so a time-limit truncation is "
            f"closed as if the episode had really ended. Where `{names.truncated}` is true, pass the value of the "
            f"final observation `{observation}` instead (`0 if {names.terminated} else V({observation})`)",
            FixKind.FLAG,
        )

    def _returned_in_tuple(self, read: ast.Name) -> bool:
        """``return obs, reward, done, info``: the flag is one element of a returned tuple."""
        parent = self.facts.parent(read)
        return isinstance(parent, ast.Tuple) and isinstance(self.facts.parent(parent), ast.Return)

    @staticmethod
    def _flag_alone_in_slot(statement: ast.AST, read: ast.Name) -> bool:
        """``news[i] = new``: the flag alone, stored into a slot of a sequence."""
        return isinstance(statement, ast.Assign) and statement.value is read and all(isinstance(t, ast.Subscript) for t in statement.targets)

    def _step_or_start_flag(self, read: ast.Name, step: DoneStep) -> bool:
        """Every binding of the flag ``read`` sees is the step's (carried over from the
        previous iteration) or a bare ``True``/``False`` (``new = True`` before the loop:
        the first slot starts an episode): the flag is still the episode boundary."""
        bindings = self.facts.bindings_of(read)
        if not bindings:
            return False
        for binding in bindings:
            statement = self.facts.statement_of(binding)
            if statement is step.assign:
                continue
            if not (
                isinstance(statement, ast.Assign)
                and len(statement.targets) == 1
                and statement.targets[0] is binding
                and isinstance(statement.value, ast.Constant)
                and isinstance(statement.value.value, bool)
            ):
                return False
        return any(self.facts.statement_of(binding) is step.assign for binding in bindings)

    def _rollout_tail(self, read: ast.Name, step: DoneStep) -> ast.Name | None:
        """The read storing ``step``'s flag as its rollout's episode boundary, when ``read``
        comes after the loop of that rollout and can only see the flag of its last step
        (``Flow.left_by_loop``); else None."""
        store = self.rollout_stores.get(step.assign)
        if store is None or not self.flow.left_by_loop(step.assign, read):
            return None
        return store

    def _stored_in_step_info(self, read: ast.Name, step: DoneStep) -> str | None:
        """The key text of ``info["key"] = done`` where ``info`` is the step's own info
        target, a plain string key, and the function returns that info; else None."""
        statement = self.facts.parent(read)
        if not (isinstance(statement, ast.Assign) and statement.value is read and len(statement.targets) == 1):
            return None
        target = statement.targets[0]
        unpack = step.assign.targets[0]
        info = unpack.elts[3] if isinstance(unpack, (ast.Tuple, ast.List)) and len(unpack.elts) == 4 else None
        if not (
            isinstance(target, ast.Subscript)
            and isinstance(target.value, ast.Name)
            and isinstance(info, ast.Name)
            and target.value.id == info.id
            and isinstance(target.slice, ast.Constant)
            and isinstance(target.slice.value, str)
            and target.slice.value != TIME_LIMIT_KEY
        ):
            return None
        # The info goes back to callers (a wrapper's or adapter's step returns it): the
        # key's readers are theirs, beyond what this function shows.
        function = self.facts.enclosing_function(read)
        if function is None or not any(
            isinstance(node, ast.Return)
            and node.value is not None
            and any(isinstance(n, ast.Name) and n.id == info.id for n in walk(node.value))
            and self.facts.enclosing_function(node) is function
            for node in walk(function)
        ):
            return None
        return f"`{self.facts.segment(target)}`"

    def _report_read(
        self, read: ast.Name, message: str, kind: FixKind, tier: Tier | None = None, question: Hashable | None = None
    ) -> None:
        if id(read) not in self.reported_reads:
            self.reported_reads.add(id(read))
            self.report(read, "GM302", message, kind, tier, question=question)
