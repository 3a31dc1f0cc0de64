"""GM301 / GM703 / GM302: a four-target step unpack gets five targets.

``obs, r, done, info = env.step(a)`` becomes ``obs, r, terminated, truncated, info =
env.step(a)`` (vector envs: ``terminations, truncations``). The old flag is kept as
``done = terminated or truncated`` (vector: ``np.logical_or``, since ``or`` on arrays
raises) right after the step, but only where something still reads it: a loop test, a
``break`` condition, a ``while not done`` around the step, a reader in another scope.

Reads of ``done`` that feed a value (``1 - done``, masks, tensors, replay writes) and
that certainly see this step's flag become ``terminated`` (GM302, review): a time-limit
truncation must still bootstrap from the next state. Value reads that may see another
binding, and reads whose purpose is unclear, are reported instead.
"""

from __future__ import annotations

import ast
import re
from bisect import bisect_left, bisect_right
from collections.abc import Hashable
from dataclasses import dataclass

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.bootstrap import next_state_masks
from gymmigrate.facts.decisions import Action, Decision, receiver_text
from gymmigrate.facts.done_uses import (
    STORE_METHODS,
    DoneUse,
    classify_done_read,
    loaded_names,
    stored_in_sequence,
    value_site,
)
from gymmigrate.facts.flow import bound_names, end, start
from gymmigrate.facts.module import FUNCTIONS, LOOPS, Scope, full_name
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.step_done.common import (
    StepFamilyBase,
    StepNames,
    StepUnpack,
    looks_vectorised,
)


@dataclass(frozen=True)
class _DoneStep:
    """A rewritten step whose done target is a name: its reads are planned together."""

    assign: ast.Assign
    done: ast.Name
    names: StepNames
    target: ast.Tuple | ast.List  # ``assign``'s only target, the unpacked values


class UnpackRules(StepFamilyBase):
    """GM301, GM302 and GM703 (mixed into the family)."""

    def _done_read_per_env(self, done_target: ast.expr) -> bool:
        """The done flags are read one per env (``zip(..., dones)``, ``for d in dones``,
        ``dones[i]``): a batched step, where ``terminated or truncated`` would be wrong."""
        if not isinstance(done_target, ast.Name):
            return False
        for read in self.flow.reads(done_target):
            parent = self.facts.parent(read)
            if isinstance(parent, ast.Subscript) and parent.value is read:
                return True
            if isinstance(parent, (ast.For, ast.AsyncFor, ast.comprehension)) and parent.iter is read:
                return True
            if (
                isinstance(parent, ast.Call)
                and isinstance(parent.func, ast.Name)
                and parent.func.id in ("zip", "enumerate", "len", "any", "all", "sum", "list")
            ):
                return True
        return False

    def plan_unpack(self, assign: ast.Assign, target: ast.Tuple | ast.List, receiver: ast.expr) -> None:
        decision, vector = self.decision(receiver, legacy_shape=True)
        done_target = target.elts[2]
        if decision.action is Action.LEAVE:
            self.note_guarded_info(target.elts[3])
            return
        if not isinstance(done_target, (ast.Name, ast.Attribute, ast.Subscript)):
            self.report(
                assign,
                "GM301",
                f"step now returns terminated and truncated, and the done target `{self.facts.segment(done_target)}` "
                "cannot be split: unpack five values by hand",
                FixKind.FLAG,
            )
            return
        if decision.action is Action.REWRITE_FOR_REVIEW and (
            looks_vectorised(receiver, done_target) or self._done_read_per_env(done_target)
        ):
            decision = Decision(
                Action.REPORT,
                f"could not trace where `{receiver_text(receiver)}` comes from, and it may be a vector env (its done "
                "flags look batched); not rewritten",
            )
        if decision.action is Action.REPORT:
            question = self.receiver_question(receiver, decision)
            self.report(
                assign,
                "GM301",
                f"{decision.reason}: if it is a Gym env, unpack `obs, reward, terminated, truncated, info`",
                FixKind.FLAG,
                question=question,
            )
            if isinstance(done_target, ast.Name) and done_target.id != "_":
                self._report_untraced_masks(_DoneStep(assign, done_target, self._step_names(assign, vector), target), decision, question)
            return
        names = self._step_names(assign, vector)
        self.plan.replace(target, lambda node: _split_done(node, names))
        discarded = isinstance(done_target, ast.Name) and done_target.id == "_"
        self.notes.step_unpacks[assign] = StepUnpack(names, discarded)
        if isinstance(done_target, ast.Name):
            if done_target.id != "_":
                # Whether ``done`` is still read is decided once every step is known.
                scope = self.flow.binding_scope(done_target)
                group = (id(scope), done_target.id) if scope is not None else (id(assign), done_target.id)
                self.done_steps.setdefault(group, []).append(_DoneStep(assign, done_target, names, target))
        else:
            self._keep_done(assign, done_target, names)  # ``self.done``/``dones[i]``: readers cannot be traced
            self._report_stored_attribute(assign, done_target, names)
        if isinstance(target.elts[3], ast.Name):
            self.info_steps[assign] = names
        message = f"step now returns {names.terminated} and {names.truncated} instead of one done flag"
        if decision.action is Action.REWRITE_FOR_REVIEW:
            self.report(
                assign, names.code, f"{message}; {decision.reason}", FixKind.ASSIST, question=self.receiver_question(receiver, decision)
            )
        else:
            self.report(assign, names.code, message)

    def _report_untraced_masks(self, step: _DoneStep, decision: Decision, question: Hashable | None) -> None:
        """The step is left (its receiver is not shown to be a Gym env), but its ``done``
        masks bootstrapping from the next state (``memory.push(s, a, r, s2, done)``): the
        same question names that read, so whoever decides the receiver decides the mask
        with it (``terminated`` there once the step gives five values)."""
        for read in self.flow.reads(step.done):
            if self._dominating_step(read, step.done) is not step.assign:
                continue
            if classify_done_read(read, self.facts) is not DoneUse.DATA:
                continue
            if not (self._masks_next_state(read, step) or self._callee_masks(read, step) is not None):
                continue
            next_state = self.facts.segment(step.target.elts[0])
            self.report(
                read,
                "GM302",
                f"{decision.reason}: if it is a Gym env, `{read.id}` masks bootstrapping from the next state "
                f"`{next_state}` here: read `terminated` once the step gives five values, so a time-limit truncation "
                "still bootstraps",
                FixKind.FLAG,
                question=question,
            )

    # -- the done reads ---------------------------------------------------------------------

    def _keep_done(self, assign: ast.Assign, done_target: ast.expr, names: StepNames) -> None:
        """``done = terminated or truncated`` right after the step (``np.logical_or`` for vectors)."""
        if names.vector and self.numpy_name is None:
            self.plan.add_import("import numpy as np")
        line = f"{self.facts.segment(done_target)} = {names.joined()}"
        self.plan.insert_after(assign, line)
        noted = self.notes.step_unpacks.get(assign)
        if noted is not None:
            noted.done_line = line

    def finish_done_reads(self) -> None:
        """Plan the reads of every rewritten step's ``done``, one variable at a time."""
        for steps in self.done_steps.values():
            keep = self._plan_done_reads(steps)
            for step, needed in zip(steps, keep):
                # ``global done``: readers live in other scopes and cannot all be traced.
                if needed or self._declared_outside(step.assign, step.done.id):
                    self._keep_done(step.assign, step.done, step.names)

    def _plan_done_reads(self, steps: list[_DoneStep]) -> list[bool]:
        """Plan every read of one ``done`` variable that its rewritten steps bind (in
        source order); for each step, whether ``done = ...`` must be kept after it.

        A read belongs to the four-target step that dominates it, if any: a value read
        there becomes ``terminated``. Otherwise every rewritten step that can reach it (not
        one before the step that dominates it) must keep ``done``; those steps form a run
        in source order (the ones before the read, then the ones in a loop around it), so
        each read marks a range, and the first step of the range reports it.
        """
        flow = self.flow
        done = steps[0].done
        reads = flow.reads(done)
        if not reads:
            return [False] * len(steps)
        scope = self.facts.scope_of(done)
        starts = [start(step.assign) for step in steps]
        ends = [end(step.assign) for step in steps]
        index_of = {id(step.assign): i for i, step in enumerate(steps)}
        marks = [0] * (len(steps) + 1)
        for read in reads:
            owner = self._dominating_step(read, done)
            first = 0
            if owner is not None:
                first = index_of.get(id(owner), bisect_left(starts, end(owner)))
                if first < len(steps) and steps[first].assign is owner and self._beside_bootstrap_flag(read, steps[first]):
                    pass  # ``store(s, a, r, s2, terminal, done)``: the boundary stays (reported below)
                elif first < len(steps) and steps[first].assign is owner:
                    if classify_done_read(read, self.facts) is DoneUse.DATA and self._masks_next_state(read, steps[first]):
                        self._claim(read, steps[first])
                        continue
                    callee = self._callee_masks(read, steps[first])
                    if callee is not None:
                        self._claim(read, steps[first], callee=callee)
                        continue
                    masked = self._none_mask(read, steps[first])
                    if masked is not None and masked[1]:
                        self._claim(read, steps[first], none_mask=masked[0])
                        continue
                    if masked is not None:
                        self._report_none_mask(read, steps[first], masked[0])
                    elif (simple := self._bootstrap_choice(read, steps[first], dominated=True)) is not None:
                        if simple:
                            self._claim(read, steps[first])
                            continue
                        self._report_bootstrap_choice(read, steps[first])
            if not flow.same_frame(read, scope):
                stop = len(steps)  # a nested function may run after any of them
            else:
                before = bisect_right(ends, start(read))
                loop = self._outermost_loop(read)
                stop = max(before, bisect_left(starts, end(loop)) if loop is not None else 0)
            if first >= stop:
                continue
            marks[first] += 1
            marks[stop] -= 1
            self._report_open_read(read, steps[first])
        keep, running = [], 0
        for mark in marks[:-1]:
            running += mark
            keep.append(running > 0)
        return keep

    def _dominating_step(self, read: ast.Name, done: ast.Name) -> ast.Assign | None:
        """The four-target step that certainly binds the value ``read`` sees, if any.

        Only the statement holding the last binding before the read can dominate it, so
        one lookup replaces a test against every step.
        """
        binding = self.flow.last_binding_before(read, done)
        if binding is None:
            return None
        step = self.facts.statement_of(binding)
        if (
            step in self.legacy_unpacks
            and any(done.id in bound_names(t) for t in step.targets)
            and self.flow.dominates(step, read, done)
        ):
            return step
        return None

    def _outermost_loop(self, node: ast.AST) -> ast.AST | None:
        found = None
        for ancestor in self.facts.ancestors(node):
            if isinstance(ancestor, LOOPS):
                found = ancestor
        return found

    def _claim(self, read: ast.Name, step: _DoneStep, none_mask: str | None = None, callee: str | None = None) -> None:
        terminated = step.names.terminated
        self.notes.step_unpacks[step.assign].claimed_reads += 1
        self.plan.replace(read, lambda node: node.with_changes(value=terminated))
        next_state = self.facts.segment(step.target.elts[0])
        if none_mask is not None:
            message = (
                f"`{read.id}` decides whether the stored next state `{none_mask}` is None (a terminal transition, "
                f"no bootstrapping): it now reads `{terminated}`, so a time-limit truncation keeps its next state"
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

    def _bootstrap_choice(self, read: ast.Name, step: _DoneStep, dominated: bool) -> bool | None:
        """``R = 0.0 if done else v(s2)``, ``if done: y = r`` / ``else: y = r + gamma * q(s2)``,
        ``if not done: y += gamma * q(s2)``: the flag chooses between a value computed from
        the step's next state and one that is not, so it masks bootstrapping from that state.
        Returns whether the test can simply read ``terminated`` (a conditional expression, or
        branches that only assign: a ``break`` there is loop control, which stays ``done``);
        None when the flag makes no such choice. A None on the done side is the next state
        itself (``_none_mask``). ``dominated``: the step certainly binds the flag read, and
        the next state is what the step's observation certainly gave; otherwise any name
        computed from that observation counts (the read is reported, never rewritten)."""
        facts = self.facts
        node: ast.AST = read
        negated = False
        parent = facts.parent(node)
        if isinstance(parent, ast.UnaryOp) and isinstance(parent.op, ast.Not):
            node, negated, parent = parent, True, facts.parent(parent)
        if dominated:
            next_names = self._next_state_names(step)

            def reads(parts: list[ast.AST]) -> bool:
                return any(self._reads_next_state(part, step, next_names) for part in parts)
        else:
            next_names = self._derived_names(step)

            def reads(parts: list[ast.AST]) -> bool:
                return any(n.id in next_names for part in parts for n in ast.walk(part) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load))

        if not next_names:
            return None
        if isinstance(parent, ast.IfExp) and parent.test is node:
            when_done, otherwise = (parent.orelse, parent.body) if negated else (parent.body, parent.orelse)
            # ``state = env.reset() if done else obs``: the next state itself, or a new episode
            if isinstance(otherwise, ast.Name) or _is_none(when_done) or _resets(when_done):
                return None
            if not reads([otherwise]) or reads([when_done]):
                return None
            return True
        if isinstance(parent, ast.If) and parent.test is node:
            done_branch, other = (parent.orelse, parent.body) if negated else (parent.body, parent.orelse)
            if any(isinstance(s, ast.Assign) and _is_none(s.value) for s in done_branch) or any(map(_resets, done_branch)):
                return None  # ``if done: next_state = None`` (the None mask), ``if done: obs = env.reset()``
            # One target chosen both ways (``if done: y = r`` / ``else: y = r + gamma * q(s2)``), or
            # only added to when not done (``if not done: y += gamma * q(s2)``): a value, not a
            # state to go on from (``if not done: state = preprocess(s2)``).
            chosen = {name for s in done_branch if isinstance(s, (ast.Assign, ast.AnnAssign)) for name in _assigned(s)}
            computed: list[ast.AST] = [
                s.value
                for s in other
                if ((isinstance(s, (ast.Assign, ast.AnnAssign)) and _assigned(s) & chosen) or (not done_branch and isinstance(s, ast.AugAssign)))
                and s.value is not None
                and not isinstance(s.value, ast.Name)
            ]
            if not reads(computed) or reads(list(done_branch)):
                return None
            return all(isinstance(s, (ast.Assign, ast.AugAssign, ast.AnnAssign, ast.Pass)) for s in [*done_branch, *other])
        return None

    def _derived_names(self, step: _DoneStep) -> set[str]:
        """The step's observation target and every name assigned, anywhere in its function,
        from an expression that reads one of them (in source order, without flow)."""

        def compute() -> set[str]:
            first = step.target.elts[0]
            if not isinstance(first, ast.Name) or first.id == "_":
                return set()
            names = {first.id}
            function = self.facts.enclosing_function(step.assign) or self.facts.tree
            assigns = sorted(
                (n for n in ast.walk(function) if isinstance(n, ast.Assign) and n is not step.assign),
                key=lambda n: (n.lineno, n.col_offset),
            )
            for assign in assigns:
                if loaded_names(assign.value) & names:
                    names.update(name for target in assign.targets for name in bound_names(target))
            return names

        return self.facts.memo(("derived-next-names", id(step.assign)), compute)

    def _report_bootstrap_choice(self, read: ast.Name, step: _DoneStep, dominated: bool = True) -> None:
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

    # -- ``next_state = None if done else obs``: the mask is the next state itself -------------

    def _none_mask(self, read: ast.Name, step: _DoneStep) -> tuple[str, bool] | None:
        """``next_state = None if done else s2`` or ``if done: next_state = None`` (the PyTorch
        DQN tutorial's terminal transition): the flag decides whether the transition stored
        afterwards has a next state to bootstrap from. Returns the masked name and whether the
        test can simply read ``terminated``: only when the branches do nothing but assign
        (a ``break`` there is loop control, which must stay ``done``). None: not such a mask."""
        facts = self.facts
        node: ast.AST = read
        negated = False
        parent = facts.parent(node)
        if isinstance(parent, ast.UnaryOp) and isinstance(parent.op, ast.Not):
            node, negated, parent = parent, True, facts.parent(parent)
        next_names = self._next_state_names(step)
        if isinstance(parent, ast.IfExp) and parent.test is node:
            when_done = parent.orelse if negated else parent.body
            statement = facts.statement_of(parent)
            if not (_is_none(when_done) and isinstance(statement, ast.Assign) and statement.value is parent):
                return None
            targets = [t.id for t in statement.targets if isinstance(t, ast.Name)]
            if len(targets) != 1 or targets[0] not in next_names or not self._stored_later(statement, targets[0]):
                return None
            return targets[0], True
        if isinstance(parent, ast.If) and parent.test is node:
            done_branch, other = (parent.orelse, parent.body) if negated else (parent.body, parent.orelse)
            masked = [
                s.targets[0].id
                for s in done_branch
                if isinstance(s, ast.Assign) and len(s.targets) == 1 and isinstance(s.targets[0], ast.Name) and _is_none(s.value)
            ]
            masked = [name for name in masked if name in next_names and self._stored_later(parent, name)]
            if not masked:
                return None
            simple = all(isinstance(s, (ast.Assign, ast.AnnAssign, ast.Pass)) for s in [*done_branch, *other])
            return masked[0], simple
        return None

    def _stored_later(self, statement: ast.stmt, name: str) -> bool:
        """``name`` is handed on after ``statement`` in the same function, as an argument
        (``memory.push(state, action, next_state, r)``, ``agent.update(s, a, r, s2)``), and never
        tested (``if state is None: reset``: then None means "start a new episode", not a
        terminal transition)."""
        function = self.facts.enclosing_function(statement) or self.facts.tree
        stored = False
        for node in ast.walk(function):
            if isinstance(node, (ast.If, ast.While, ast.IfExp)) and name in loaded_names(node.test):
                return False
            if (
                isinstance(node, ast.Call)
                and node.lineno > statement.lineno
                and not (isinstance(node.func, ast.Name) and node.func.id in _NOT_TRANSITIONS)
                and any(_passes(arg, name) for arg in [*node.args, *(k.value for k in node.keywords)])
            ):
                stored = True
        return stored

    def _report_none_mask(self, read: ast.Name, step: _DoneStep, masked: str) -> None:
        names = step.names
        self._report_read(
            read,
            f"`{read.id}` decides whether the stored next state `{masked}` is None (no bootstrapping) and also "
            f"controls the loop here; it now means `{names.terminated} or {names.truncated}`: set `{masked}` to None "
            f"on `{names.terminated}` only, and keep `{read.id}` for ending the episode",
            FixKind.FLAG,
            question=("GM302", id(step.assign)),
        )

    # -- what a value read of ``done`` masks -------------------------------------------------------

    def _masks_next_state(self, read: ast.Name, step: _DoneStep) -> bool:
        """Does this value read mask bootstrapping from the step's own next observation?

        Only there is ``terminated`` right: the transition stores the next state, or the
        target computes its value (``r + gamma * (1 - done) * V(s2)``, also through one
        name: ``mask = 1 - done``). A flag stored per step without the next state (an
        on-policy rollout whose GAE reads ``values[k + 1]`` of the following step) marks
        the episode boundary: after a reset that value belongs to the next episode, so
        the flag stays ``terminated or truncated``.
        """
        next_names = self._next_state_names(step)
        if not next_names:
            return False
        facts = self.facts
        site = value_site(read, facts)
        if _repacks_step(facts.parent(read), read, step):
            return False  # ``(obs, reward, done, info)`` passed on: the step's own result, not a transition
        if self._reads_next_state(site, step, next_names):
            return True
        statement = facts.statement_of(read)
        function = facts.enclosing_function(step.assign) or facts.tree
        if isinstance(statement, ast.Assign) and site is statement.value:
            # ``mask = 1 - done`` read by a target that also reads the next state
            targets = {t.id for t in statement.targets if isinstance(t, ast.Name)}
            if targets and any(
                targets & names and names & next_names for names in self._statement_reads(function).values()
            ):
                return True
        if stored_in_sequence(read, facts):
            # separate lists: ``next_states.append(s2)`` beside ``dones.append(done)``
            return facts.memo(
                ("stores-next-state", id(step.assign)),
                lambda: any(self._stores_next_state(node, step, next_names) for node in ast.walk(function)),
            )
        return False

    def _beside_bootstrap_flag(self, read: ast.Name, step: _DoneStep) -> str | None:
        """``store_transition(s, a, r, s2, terminal, done)`` where ``terminal`` (or ``dw``) is
        computed from ``done`` after the step together with something else (``if done and
        steps != limit: terminal = True``, ``dw = done and not truncated``): the code already
        keeps a separate bootstrap mask, so ``done`` beside it in the same call or tuple is the
        episode boundary (an n-step cut, the end of a rollout). The name of that flag, or None."""
        facts = self.facts
        holder: ast.AST | None = facts.parent(read)
        if isinstance(holder, ast.keyword):
            holder = facts.parent(holder)
        if not isinstance(holder, (ast.Call, ast.Tuple, ast.List)) or getattr(holder, "func", None) is read:
            return None
        values = [*holder.args, *(k.value for k in holder.keywords)] if isinstance(holder, ast.Call) else holder.elts
        function = facts.enclosing_function(step.assign) or facts.tree
        for value in values:
            if value is read or not isinstance(value, ast.Name) or value.id == read.id:
                continue
            if self._computed_from_done(value, step, function):
                return value.id
        return None

    def _computed_from_done(self, flag: ast.Name, step: _DoneStep, function: ast.AST) -> bool:
        """``flag`` is bound after the step, in its function, from a value or under a test
        that reads ``done`` with something else (``done and steps != limit``)."""
        done = step.done.id
        for binding in self.flow.bindings(flag):
            statement = self.facts.statement_of(binding)
            if not isinstance(binding, ast.Name) or statement is None or start(statement) <= end(step.assign):
                continue  # ``terminal = False`` before the loop: not what the step decides
            if (self.facts.enclosing_function(statement) or self.facts.tree) is not function:
                continue
            value = getattr(statement, "value", None)
            if value is not None and any(_joins_done(node, done) for node in ast.walk(value)):
                return True  # ``dw = done and steps != limit``, ``terminal = True if done and ... else False``
            for ancestor in self.facts.ancestors(binding):
                if ancestor is function:
                    break
                if (
                    isinstance(ancestor, ast.If)
                    and _joins_done(ancestor.test, done)
                    and isinstance(value, ast.Constant)
                    and value.value in (True, False)  # also 1, 0, 1.0, 0.0
                ):
                    return True  # ``if done and steps != limit: terminal = True`` (not ``reward = -1`` there)
        return False

    # -- ``agent.train_model(s, a, r, s2, done)``: the callee says what the flag is for ---------

    def _callee_masks(self, read: ast.Name, step: _DoneStep) -> str | None:
        """The callee's text when ``read`` is an argument of a call that also passes the
        step's next state, and the callee (a def of this module, or of another module of
        the run) masks bootstrapping from that parameter with this one
        (``facts/bootstrap.py``). None when the call passes no next state or the callee
        cannot be followed: then the read is decided as before."""
        call = self.facts.parent(read)
        if isinstance(call, ast.keyword):
            call = self.facts.parent(call)
        if not isinstance(call, ast.Call) or call.func is read or any(isinstance(a, ast.Starred) for a in call.args):
            return None
        next_names = self._next_state_names(step)
        if not next_names:
            return None
        passed_next = [
            argument
            for argument in [*call.args, *(k.value for k in call.keywords)]
            if argument is not read and isinstance(argument, ast.Name) and self._reads_next_state(argument, step, next_names)
        ]
        if not passed_next:
            return None
        found = self._callee_signature(call.func)
        if found is None:
            return None
        params, masks = found

        def param_of(argument: ast.expr) -> str | None:
            for index, value in enumerate(call.args):
                if value is argument:
                    return params[index] if index < len(params) else None
            for keyword in call.keywords:
                if keyword.value is argument:
                    return keyword.arg
            return None

        flag = param_of(read)
        if flag is None or not any((flag, param_of(argument)) in masks for argument in passed_next):
            return None
        return self.facts.segment(call.func)

    def _hands_step_on(self, read: ast.Name, step: _DoneStep) -> bool:
        """``return agent_state, terminal, agent_reward`` or ``pipe.send((obs, reward, done,
        info))``: the flag in one tuple with the step's observation and reward (or values
        computed from them), returned or sent as a call's only argument. The step's result
        is handed on, an env-like reply: its receiver reads the flag as the episode's end."""
        site = self.facts.parent(read)
        if not isinstance(site, ast.Tuple):
            return False
        holder = self.facts.parent(site)
        if isinstance(holder, ast.Call):
            if holder.args != [site] or holder.keywords or holder.func is site:
                return False
        elif not isinstance(holder, ast.Return):
            return False
        elements = step.target.elts
        if len(elements) < 2 or not all(isinstance(e, ast.Name) for e in elements[:2]):
            return False
        observation, reward = elements[0].id, elements[1].id  # type: ignore[attr-defined]
        function = self.facts.enclosing_function(step.assign) or self.facts.tree
        derived = {observation: {observation}, reward: {reward}}
        for node in ast.walk(function):
            if isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name):
                for names in derived.values():
                    if loaded_names(node.value) & names:
                        names.add(node.targets[0].id)
        others = [loaded_names(e) for e in site.elts if e is not read]
        if not (any(n & derived[observation] for n in others) and any(n & derived[reward] for n in others)):
            return False
        # every value is the step's (``reward``, ``info``) or set after it from the step
        # (``agent_state = featurize(state)``, the auto-reset ``obs = env.reset()``): a
        # transition (``(obs, action, next_obs, reward, done)``) holds the state before it
        return all(self._from_step(e, step) for e in site.elts if e is not read)

    def _from_step(self, value: ast.expr, step: _DoneStep) -> bool:
        step_names = {e.id for e in step.target.elts if isinstance(e, ast.Name)}
        for node in ast.walk(value):
            if not (isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load)):
                continue
            binding = self.flow.last_binding_of(node)
            statement = self.facts.statement_of(binding) if binding is not None else None
            if statement is step.assign:
                return True
            if (
                isinstance(statement, ast.Assign)
                and start(statement) > end(step.assign)
                and self.facts.enclosing_function(statement) is self.facts.enclosing_function(step.assign)
                and (loaded_names(statement.value) & step_names or node.id in step_names)
            ):
                return True
        return False

    def _stores_step_without_next_state(self, read: ast.Name, step: _DoneStep) -> bool:
        """``memory.store_memory(obs, value, reward, done)``: a call that hands on the step's
        reward and flag but no next state (``obs`` still holds the state the step started
        from). Whatever the callee does, it cannot bootstrap from the next state with this
        flag: a rollout store, where the flag is the episode boundary."""
        call = self.facts.parent(read)
        if isinstance(call, ast.keyword):
            call = self.facts.parent(call)
        if not isinstance(call, ast.Call) or call.func is read or any(isinstance(a, ast.Starred) for a in call.args):
            return False
        reward = step.target.elts[1] if len(step.target.elts) > 1 else None
        if not isinstance(reward, ast.Name):
            return False
        arguments = [*call.args, *(k.value for k in call.keywords)]
        if not any(isinstance(a, ast.Name) and a.id == reward.id for a in arguments):
            return False
        next_names = self._next_state_names(step)
        return not any(a is not read and self._reads_next_state(a, step, next_names) for a in arguments)

    def _only_ends_or_unread(self, read: ast.Name) -> str | None:
        """What the code shows the flag is for, when that settles it: returned by a def of the
        file whose every caller unpacks the result and reads the flag only to end a loop
        (``if done: break``), or stored in a list of the function that nothing reads
        (``episode.append(Transition(..., done=done))``). None otherwise."""
        node: ast.AST = read
        parent = self.facts.parent(node)
        if isinstance(parent, ast.Tuple) and isinstance(self.facts.parent(parent), ast.Return):
            return self._returned_for_loop_exit(read, parent)
        while parent is not None and not isinstance(parent, ast.stmt):
            if (
                isinstance(parent, ast.Call)
                and isinstance(parent.func, ast.Attribute)
                and parent.func.attr in ("append", "extend", "insert")
                and node is not parent.func
                and isinstance(parent.func.value, ast.Name)
                and isinstance(self.facts.parent(parent), ast.Expr)
            ):
                return self._unread_list(parent.func.value)
            node, parent = parent, self.facts.parent(parent)
        return None

    def _returned_for_loop_exit(self, read: ast.Name, values: ast.Tuple) -> str | None:
        function = self.facts.enclosing_function(read)
        if not isinstance(function, FUNCTIONS) or self.facts.enclosing_class(read) is not None:
            return None
        index = next(i for i, value in enumerate(values.elts) if value is read)
        calls = self.facts.calls_by_name.get(function.name, [])
        if not calls:
            return None
        for call in calls:
            assign = self.facts.parent(call)
            if not (isinstance(assign, ast.Assign) and assign.value is call and len(assign.targets) == 1):
                return None
            target = assign.targets[0]
            if not isinstance(target, (ast.Tuple, ast.List)) or len(target.elts) != len(values.elts):
                return None
            flag = target.elts[index]
            if not isinstance(flag, ast.Name):
                return None
            if any(
                classify_done_read(use, self.facts) not in (DoneUse.CONTROL, DoneUse.NEUTRAL) for use in self.flow.reads(flag)
            ):
                return None
        return f"is returned by `{function.name}`, whose callers read it only to end their loop"

    def _unread_list(self, name: ast.Name) -> str | None:
        """``episode`` bound only to new lists in a function and only ever appended to."""
        scope = self.flow.binding_scope(name)
        if scope is None or self.facts.enclosing_function(name) is None or self._declared_outside(name, name.id):
            return None
        bindings = scope.bindings.get(name.id, ())
        for binding in bindings:
            assign = self.facts.parent(binding)
            if not (
                isinstance(binding, ast.Name)
                and isinstance(assign, ast.Assign)
                and assign.targets == [binding]
                and isinstance(assign.value, (ast.List, ast.ListComp))
            ):
                return None
        for use in self.flow.reads(name):
            method = self.facts.parent(use)
            call = self.facts.parent(method)
            if not (
                isinstance(method, ast.Attribute)
                and method.attr in ("append", "extend", "insert")
                and isinstance(call, ast.Call)
                and call.func is method
                and isinstance(self.facts.parent(call), ast.Expr)
            ):
                return None
        return f"is stored in `{name.id}`, which nothing reads"

    def _may_store_next_state(self, read: ast.Name, step: _DoneStep) -> bool:
        """The store beside ``read`` holds a value that may be the step's next state in a way
        not followed (``frames.append(obs)``, then ``state = np.stack(frames)``): a name that
        says so (``next_state``, ``s_``), or one bound after the step
        from something else than its reward, flag or info. Then "stored without the next
        state" would be a guess: the read is a question, not a note."""
        site = value_site(read, self.facts)
        if isinstance(site, ast.Call):
            values: list[ast.AST] = [*site.args, *(k.value for k in site.keywords)]
        else:
            values = [site]
        step_values = {e.id for e in step.target.elts[1:] if isinstance(e, ast.Name)}
        function = self.facts.enclosing_function(step.assign)
        for value in values:
            for node in ast.walk(value):
                if not (isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load)) or node.id == read.id:
                    continue
                if _says_next(node.id):
                    return True
                binding = self.flow.last_binding_of(node)
                statement = self.facts.statement_of(binding) if binding is not None else None
                if (
                    isinstance(statement, (ast.Assign, ast.AnnAssign, ast.AugAssign))
                    and statement is not step.assign
                    and start(statement) > end(step.assign)
                    and self.facts.enclosing_function(statement) is function
                    and statement.value is not None
                    and not (loaded_names(statement.value) & step_values)
                ):
                    return True
        return False

    def _callee_signature(self, func: ast.expr) -> tuple[tuple[str, ...], frozenset[tuple[str, str]]] | None:
        """The parameters a call binds by position (``self`` left out) and the callee's
        bootstrap masks; None when the callee cannot be followed."""
        function = self.receivers.local_function(func) or self.receivers.own_method(func)
        method = function is not None and isinstance(self.facts.parent(function), ast.ClassDef)
        if function is None and isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name):
            classes = self._instance_classes(func.value)
            if len(classes) == 1:
                classdef = next(iter(classes))
                if isinstance(classdef, ast.ClassDef):
                    function = next(
                        (s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == func.attr), None
                    )
                    method = True
                elif self.receivers.project is not None:
                    found = self.receivers.project.bootstrap_masks(f"{classdef}.{func.attr}")
                    return None if found is None else (found[0][1:], found[1])
        if function is None and self.receivers.project is not None and isinstance(func, ast.Name):
            qualified = self.facts.qualified_names(func)
            if len(qualified) == 1:
                found = self.receivers.project.bootstrap_masks(next(iter(qualified)))
                return found
        if function is None:
            return None
        params = tuple(a.arg for a in (*function.args.posonlyargs, *function.args.args))
        return (params[1:] if method else params), next_state_masks(function)

    def _instance_classes(self, owner: ast.Name) -> set[ast.ClassDef | str]:
        """What every binding of ``owner`` constructs: a class of this module, or the
        qualified name of an imported one (``agent = Agent(...)``)."""
        found: set[ast.ClassDef | str] = set()
        bindings = self.facts.bindings_of(owner)
        if not bindings:
            return found
        for binding in bindings:
            assign = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
            if not (isinstance(assign, ast.Assign) and isinstance(assign.value, ast.Call) and assign.targets == [binding]):
                return set()
            local = self.receivers.local_class(assign.value.func)
            if local is not None:
                found.add(local)
                continue
            qualified = self.facts.qualified_names(assign.value.func)
            if len(qualified) != 1:
                return set()
            found.add(next(iter(qualified)))
        return found

    def _reads_next_state(self, site: ast.AST, step: _DoneStep, next_names: set[str]) -> bool:
        """``site`` reads the step's next state: a name of ``next_names`` whose binding before
        the read comes after the step. ``remember(obs, a, r, done)`` before ``obs = obs_`` reads
        the state the step started from (an on-policy rollout), not the next one."""
        steps_after = self._next_state_bindings(step)
        for node in ast.walk(site):
            if isinstance(node, ast.Name) and node.id in next_names and isinstance(node.ctx, ast.Load):
                binding = self.flow.last_binding_of(node)
                if binding is not None and id(self.facts.statement_of(binding)) in steps_after:
                    return True
        return False

    def _next_state_bindings(self, step: _DoneStep) -> set[int]:
        """The statements that bind a next-state name: the step and the assignments after it."""
        self._next_state_names(step)
        return self.facts.memo(("next-state-bindings", id(step.assign)), lambda: {id(step.assign)})

    def _next_state_names(self, step: _DoneStep) -> set[str]:
        """The step's observation target and the names computed from it in the same function."""
        return self.facts.memo(("next-state-names", id(step.assign)), lambda: self._compute_next_state_names(step))

    def _compute_next_state_names(self, step: _DoneStep) -> set[str]:
        first = step.target.elts[0]
        if not isinstance(first, ast.Name) or first.id == "_":
            return set()
        names = {first.id}
        bindings = self.facts.memo(("next-state-bindings", id(step.assign)), lambda: {id(step.assign)})
        function = self.facts.enclosing_function(step.assign) or self.facts.tree

        def sees_step(node: ast.Name, statement: ast.stmt) -> bool:
            if node.id == first.id and self.flow.dominates(step.assign, node, first):
                return True
            # ``next_state = np.reshape(next_state, shape)`` right after the step, then
            # ``next_state = np.append(state[:, :, 1:], next_state[..., None], axis=2)``
            # (frame stacking): each read sees the step's value or one computed from it
            # just above, the statement's own binding comes after it
            above = self.flow.binding_above(node, statement)
            holder: ast.AST | None = statement
            while above is None and isinstance(holder := self.facts.parent(holder), (ast.If, ast.With)):
                # ``if use_norm: s_ = norm(s_)``: the read sees what was bound above the ``if``
                above = self.flow.binding_above(node, holder)
            return above is not None and id(self.facts.statement_of(above)) in bindings

        def after_step(value: ast.AST, statement: ast.stmt) -> bool:  # reads this step's observation, not an earlier one
            return any(
                isinstance(node, ast.Name) and node.id in names and isinstance(node.ctx, ast.Load) and sees_step(node, statement)
                for node in ast.walk(value)
            )

        # in source order, so a chain of reassignments is followed link by link
        assigns = sorted(
            (node for node in ast.walk(function) if isinstance(node, ast.Assign)), key=lambda node: start(node)
        )
        for node in assigns:
            if node is not step.assign and len(node.targets) == 1:
                target = node.targets[0]
                if isinstance(target, ast.Name) and after_step(node.value, node):
                    names.add(target.id)
                    bindings.add(id(node))
                elif isinstance(target, (ast.Tuple, ast.List)) and isinstance(node.value, (ast.Tuple, ast.List)):
                    for element, value in zip(target.elts, node.value.elts):
                        if isinstance(element, ast.Name) and after_step(value, node):
                            names.add(element.id)
                            bindings.add(id(node))
        return names

    def _statement_reads(self, function: ast.AST) -> dict[int, set[str]]:
        def compute() -> dict[int, set[str]]:
            return {
                id(node): loaded_names(node)
                for node in ast.walk(function)
                if isinstance(node, ast.stmt) and not isinstance(node, (*LOOPS, ast.If, ast.With, ast.Try, *FUNCTIONS))
            }

        return self.facts.memo(("statement-reads", id(function)), compute)

    def _stores_next_state(self, node: ast.AST, step: _DoneStep, next_names: set[str]) -> bool:
        """``next_states.append(s2)`` or ``next_obs_buf[t] = s2`` that runs after the step, in its
        iteration: a replay memory kept in separate arrays. The store or the value must say
        "next state" (``next_``, ``new_``, ``s2``, ``s_``): a trajectory log that records each
        step's observation (``observations.append(obs)``) is not a replay memory."""
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr in STORE_METHODS:
            values: list[ast.AST] = list(node.args)
            store = node.func.value
        elif isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Subscript):
            values = [node.value]
            store = node.targets[0].value
        else:
            return False
        first = step.target.elts[0]
        if not isinstance(first, ast.Name):
            return False  # then ``next_names`` is empty: nothing below could match
        for value in values:
            for name in ast.walk(value):
                if isinstance(name, ast.Name) and name.id in next_names and isinstance(name.ctx, ast.Load):
                    if not (_says_next(name.id) or _says_next(full_name(store) or "")):
                        continue
                    if name.id != first.id or self.flow.dominates(step.assign, name, first):
                        return True
        return False

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
        """``obs, r, self.done, info = env.step(a)`` and ``self.done`` stored as a value elsewhere."""
        for read in self._self_attribute_data_reads(assign, target):
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

    def _report_open_read(self, read: ast.Name, step: _DoneStep) -> None:
        use = classify_done_read(read, self.facts)
        names = step.names
        # The reads of one step's done ask one question: what its done should mean.
        question = ("GM302", id(step.assign))
        owner = self._dominating_step(read, step.done)
        statement = self.facts.statement_of(read)
        stored = (
            self._self_attribute_data_reads(read, statement.targets[0])
            if isinstance(statement, ast.Assign) and statement.value is read and len(statement.targets) == 1
            else []
        )
        beside = self._beside_bootstrap_flag(read, step) if owner is step.assign else None
        if beside is not None:
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
        elif owner is step.assign and (settled := self._only_ends_or_unread(read)) is not None:
            # The code shows what the flag is for: ending a loop, or nothing at all (a note).
            self._report_read(
                read,
                f"`{read.id}` {settled}: it stays `{names.terminated} or {names.truncated}`, the episode's end "
                "legacy `done` was",
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

    def _report_read(
        self, read: ast.Name, message: str, kind: FixKind, tier: Tier | None = None, question: Hashable | None = None
    ) -> None:
        if id(read) not in self.reported_reads:
            self.reported_reads.add(id(read))
            self.report(read, "GM302", message, kind, tier, question=question)

    def _declared_outside(self, node: ast.AST, name: str) -> bool:
        function = self.facts.enclosing_function(node)
        if function is None:
            return False
        scope = self.facts.scopes[function]
        return name in scope.declared_global or name in scope.declared_nonlocal

    def note_guarded_info(self, info_target: ast.expr) -> None:
        """SB3 VecEnv infos still carry ``TimeLimit.truncated`` (SB104): stay silent on them."""
        if isinstance(info_target, ast.Name):
            scope = self.flow.binding_scope(info_target)
            if scope is not None:
                self.guarded_infos.add((id(scope), info_target.id))

    # -- names --------------------------------------------------------------------------------

    def _step_names(self, assign: ast.Assign, vector: bool) -> StepNames:
        base = ("terminations", "truncations") if vector else ("terminated", "truncated")
        numpy = self.numpy_name or "np"
        if not any(name in self.facts.text for name in base):
            # A name the file never spells is free: no walk of the scope for the names it uses.
            return StepNames(*base, vector=vector, numpy=numpy)
        scope = self.facts.scope_of(assign)
        taken = self.flow.names_used_in(scope)
        compatible = self._step_flag_names(scope) if any(name in taken for name in base) else set()
        terminated, truncated = (_fresh(name, taken, compatible) for name in base)
        return StepNames(terminated, truncated, vector=vector, numpy=numpy)

    def _step_flag_names(self, scope: Scope) -> set[str]:
        """Names that only ever hold step flags in ``scope`` (safe to bind again)."""
        return self.facts.memo(("step-flag-names", id(scope.node)), lambda: _collect_flag_names(scope.node))


_NEXT_WORDS = re.compile(r"(^|_|\.)(next|new)|next_?$|(^|_|\.)(s|o|obs|state|x)(2|_|p|tp1|_tp1|_next|_prime)$", re.IGNORECASE)


def _says_next(name: str) -> bool:
    """``next_states``, ``new_obs``, ``s2``, ``s_``, ``obs_tp1``, ``self.next_obs_buf``."""
    last = name.rsplit(".", 1)[-1]
    return bool(_NEXT_WORDS.search(last)) or last.endswith("2")


def _fresh(base: str, taken: set[str], compatible: set[str]) -> str:
    if base not in taken or base in compatible:
        return base
    candidate, number = base + "_", 2
    while candidate in taken:
        candidate, number = f"{base}_{number}", number + 1
    return candidate


def _collect_flag_names(root: ast.AST) -> set[str]:
    """Names bound as the flags of a five-target step in ``root``, and nowhere else."""
    flags: set[str] = set()
    other: set[str] = set()
    for node in ast.walk(root):
        if isinstance(node, ast.Assign):
            value = node.value
            is_step = isinstance(value, ast.Call) and isinstance(value.func, ast.Attribute) and value.func.attr == "step"
            for target in node.targets:
                if is_step and isinstance(target, (ast.Tuple, ast.List)) and len(target.elts) == 5:
                    flags.update(el.id for el in target.elts[2:4] if isinstance(el, ast.Name))
                    continue
                other |= bound_names(target)
        elif isinstance(node, ast.arg):
            other.add(node.arg)
        elif isinstance(node, (ast.For, ast.AsyncFor, ast.AugAssign, ast.NamedExpr)):
            other |= bound_names(node.target)
        elif isinstance(node, ast.alias) and node.asname:
            other.add(node.asname)
        elif isinstance(node, ast.withitem) and node.optional_vars is not None:
            other |= bound_names(node.optional_vars)
        elif isinstance(node, ast.ExceptHandler) and node.name:
            other.add(node.name)
    return flags - other


def _joins_done(test: ast.AST, done: str) -> bool:
    """``done and steps != limit``, ``done and not info.get(...)``: ``done`` read together
    with another condition (``done`` alone, or negated, is the flag itself)."""
    if not isinstance(test, ast.BoolOp) or not isinstance(test.op, ast.And):
        return False
    return done in loaded_names(test) and any(done not in loaded_names(v) for v in test.values)


def _split_done(target: cst.BaseExpression, names: StepNames) -> cst.BaseExpression:
    """``obs, r, done, info`` -> ``obs, r, terminated, truncated, info`` (user spacing kept)."""
    elements = list(target.elements)  # type: ignore[attr-defined]
    done = elements[2]
    discard = isinstance(done.value, cst.Name) and done.value.value == "_"
    first = cst.Name("_" if discard else names.terminated)
    second = cst.Name("_" if discard else names.truncated)
    comma = done.comma if isinstance(done.comma, cst.Comma) else cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))
    elements[2:3] = [cst.Element(value=first, comma=comma), cst.Element(value=second, comma=comma)]
    return target.with_changes(elements=elements)


def _repacks_step(site: ast.AST | None, read: ast.Name, step: _DoneStep) -> bool:
    """``(obs, reward, done, info)`` with the step's own four targets in their places: the
    legacy step result handed on (a worker's reply), whose done is the episode's end."""
    if not (isinstance(site, ast.Tuple) and len(site.elts) == len(step.target.elts) == 4 and site.elts[2] is read):
        return False
    return all(
        isinstance(mine, ast.Name) and isinstance(theirs, ast.Name) and mine.id == theirs.id
        for mine, theirs in zip(site.elts, step.target.elts)
    )
# Calls that show or test a value rather than take a transition.
_NOT_TRANSITIONS = frozenset({"print", "repr", "str", "len", "isinstance", "type", "id"})


def _passes(argument: ast.expr, name: str) -> bool:
    """The argument is ``name``, or a tuple or list that holds it (a transition)."""
    if isinstance(argument, (ast.Tuple, ast.List)):
        return any(_passes(element, name) for element in argument.elts)
    return isinstance(argument, ast.Name) and argument.id == name


def _assigned(statement: ast.Assign | ast.AnnAssign) -> set[str]:
    targets = statement.targets if isinstance(statement, ast.Assign) else [statement.target]
    return {name for target in targets for name in bound_names(target)}


def _resets(node: ast.AST) -> bool:
    """``node`` calls some ``x.reset(...)``: the flag starts a new episode there."""
    return any(isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute) and n.func.attr == "reset" for n in ast.walk(node))


def _is_none(node: ast.AST) -> bool:
    return isinstance(node, ast.Constant) and node.value is None
