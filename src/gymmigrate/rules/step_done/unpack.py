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
from bisect import bisect_left, bisect_right

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.batched_steps import done_read_per_env
from gymmigrate.facts.class_shapes import concatenated_lists
from gymmigrate.facts.collection_reads import (
    CollectionRead,
    Shape,
    collection_read,
    named,
)
from gymmigrate.facts.decisions import Action, Decision, receiver_text
from gymmigrate.facts.done_uses import DoneUse, classify_done_read
from gymmigrate.facts.flow import bound_names, end, start
from gymmigrate.facts.module import LOOPS, Scope, walk
from gymmigrate.facts.per_agent_flags import PerAgent, per_agent_done
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.step_done.common import StepNames, StepUnpack, looks_vectorised
from gymmigrate.rules.step_done.next_state import DoneStep
from gymmigrate.rules.step_done.read_attributes import DoneAttributeReports
from gymmigrate.rules.step_done.results import subscript_index, with_index


class UnpackRules(DoneAttributeReports):
    """GM301, GM302 and GM703 (mixed into the family)."""

    def _done_concatenated(self, done_target: ast.expr) -> bool:
        """The function extends a list it starts empty with ``done`` (``done_n += done``)."""
        function = self.facts.enclosing_function(done_target)
        if not isinstance(done_target, ast.Name) or function is None:
            return False
        return any(
            isinstance(value, ast.Name) and value.id == done_target.id
            for values in concatenated_lists(function).values()
            for value in values
        )

    def plan_unpack(self, assign: ast.Assign, target: ast.Tuple | ast.List, receiver: ast.expr) -> None:
        decision, vector = self.decision(receiver, legacy_shape=True)
        done_target = target.elts[2]
        if decision.action is Action.LEAVE:
            self.note_guarded_info(target.elts[3])
            return
        if decision.action is not Action.REWRITE and self._done_concatenated(done_target):
            # ``done_n += done``: the done is a list of flags (``list += bool`` raises), so the
            # stepped env has a per-agent API of its own whose step the run keeps at four
            # fields (GM504 reports it), not a Gym env's one-flag step.
            self.report(
                assign,
                "GM301",
                f"the done of `{receiver_text(receiver)}.step()` is a list the function concatenates (per-agent flags): "
                "an env on its own four-field API; the unpack is left as it is",
                FixKind.FLAG,
                Tier.NOTE,
            )
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
            looks_vectorised(receiver, done_target) or done_read_per_env(self.facts, done_target, target)
        ):
            decision = Decision(
                Action.REPORT,
                f"could not trace where `{receiver_text(receiver)}` comes from, and it may be a vector env (its done "
                "flags look batched); not rewritten",
            )
        if decision.action is Action.REPORT:
            self.note_unsure_info(target.elts[3], receiver)
            question = self.receiver_question(receiver, decision)
            self.report(
                assign,
                "GM301",
                f"{decision.reason}: if it is a Gym env, unpack `obs, reward, terminated, truncated, info`",
                FixKind.FLAG,
                question=question,
            )
            if isinstance(done_target, ast.Name) and done_target.id != "_":
                self._report_untraced_masks(DoneStep(assign, done_target, self._step_names(assign, vector), target), decision, question)
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
                self.done_steps.setdefault(group, []).append(DoneStep(assign, done_target, names, target))
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

    def plan_indexed_step(self, call: ast.Call, receiver: ast.expr) -> bool:
        """``done = env.step(a)[2]`` or ``env.step(a)[3]`` on a receiver the run rewrites: the
        result is read at one constant place and never kept, so its new places are certain.
        Index 3 (info) is index 4 now; a done assigned to a name becomes a five-target unpack
        with ``done = terminated or truncated`` after it, the legacy flag's very value (the
        result holds no second read to write ``res[2] or res[3]`` with). Any other use of an
        indexed step stays GM304's report. True when planned."""
        subscript = self.facts.parent(call)
        index = subscript_index(subscript, call)
        if index not in (2, 3) or not isinstance(subscript, ast.Subscript):
            return False
        statement = self.facts.parent(subscript)
        done_target = statement.targets[0] if isinstance(statement, ast.Assign) and len(statement.targets) == 1 else None
        if index == 2 and not (
            isinstance(statement, ast.Assign) and statement.value is subscript
            and isinstance(done_target, ast.Name) and done_target.id != "_"
        ):
            return False  # ``if env.step(a)[2]:``: no statement of its own to unpack in
        decision, vector = self.decision(receiver, legacy_shape=False)
        if decision.action not in (Action.REWRITE, Action.REWRITE_FOR_REVIEW) or vector or looks_vectorised(receiver, done_target or call):
            return False
        question = self.receiver_question(receiver, decision) if decision.action is Action.REWRITE_FOR_REVIEW else None
        kind = FixKind.AUTO if decision.action is Action.REWRITE else FixKind.ASSIST
        unsure = f"; {decision.reason}" if decision.action is Action.REWRITE_FOR_REVIEW else ""
        text = self.facts.segment(call)
        if index == 3:
            self.plan.replace(subscript, lambda node: with_index(node, 4))
            self.report(subscript, "GM304", f"`{text}[3]` (info) is `{text}[4]` now{unsure}", kind, question=question)
            return True
        assert isinstance(statement, ast.Assign) and isinstance(done_target, ast.Name)
        names = self._step_names(statement, vector=False)
        self.plan.replace(done_target, lambda node: _five_targets(node, names))
        self.plan.replace(subscript, lambda node: node.value.with_changes(lpar=node.lpar, rpar=node.rpar))
        self._keep_done(statement, done_target, names)
        self.report(
            statement,
            "GM304",
            f"`{text}[2]` (done) is `{names.terminated} or {names.truncated}` now: the step is unpacked into five values "
            f"and `{done_target.id}` keeps the legacy flag{unsure}",
            kind,
            question=question,
        )
        return True

    def _keep_done(self, assign: ast.Assign, done_target: ast.expr, names: StepNames) -> None:
        """``done = terminated or truncated`` right after the step (``np.logical_or`` for vectors)."""
        if (names.vector or (names.per_agent and not names.by_name)) and self.numpy_name is None:
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
                if needed:
                    self._report_zero_tails(step)

    def _plan_done_reads(self, steps: list[DoneStep]) -> list[bool]:
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
            if owner is None and self._rebound_fresh(read, done):
                continue  # ``done = float(i == T - 1)`` before it: a new flag, not the step's
            capped = self._step_past_own_limit(read, done) if owner is None else None
            if capped is not None and id(capped[0]) in index_of:
                # ``if t >= cap: done = True`` between the step and a bootstrap mask: the cap
                # is a truncation, so the mask reads the step's terminated, as it would
                # without the cap; ``done`` keeps the cap for ending the episode.
                step = steps[index_of[id(capped[0])]]
                if (
                    classify_done_read(read, self.facts) is DoneUse.DATA
                    and self._masks_next_state(read, step)
                    and not self._readers_keep_boundary(read, step)
                ):
                    self._claim(read, step, cap=capped[1])
                    continue
            first = 0
            if owner is not None:
                first = index_of.get(id(owner), bisect_left(starts, end(owner)))
                if first < len(steps) and steps[first].assign is owner and self._beside_bootstrap_flag(read, steps[first]):
                    pass  # ``store(s, a, r, s2, terminal, done)``: the boundary stays (reported below)
                elif first < len(steps) and steps[first].assign is owner and self._rollout_tail(read, steps[first]) is not None:
                    pass  # after the loop of a rollout that stores the flag as its boundary (reported below)
                elif first < len(steps) and steps[first].assign is owner:
                    if classify_done_read(read, self.facts) is DoneUse.DATA and self._masks_next_state(read, steps[first]):
                        if not self._readers_keep_boundary(read, steps[first]):
                            self._claim(read, steps[first])
                            continue
                    elif (callee := self._callee_masks(read, steps[first])) is not None:
                        if not self._readers_keep_boundary(read, steps[first]):
                            self._claim(read, steps[first], callee=callee)
                            continue
                    elif self._callee_flushes(read):
                        # the callee ends the episode's state on the flag (so it masks
                        # nothing by ``facts/bootstrap.py``): the same item as a store
                        # whose readers use it both ways
                        self._readers_keep_boundary(read, steps[first])
                    masked = self._none_mask(read, steps[first])
                    if masked is not None and masked[1]:
                        self._claim(read, steps[first], none_mask=masked[0])
                        continue
                    if masked is not None:
                        self._report_none_mask(read, steps[first], masked[0], masked[2])
                    elif (simple := self._bootstrap_choice(read, steps[first], dominated=True)) is not None:
                        if simple:
                            self._claim(read, steps[first])
                            continue
                        self._report_bootstrap_choice(read, steps[first])
                    elif self._discount_test(read) and not self._split_by_time_limit(read, steps[first]):
                        self._report_discount_choice(read, steps[first])
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

    def _rebound_fresh(self, read: ast.Name, done: ast.Name) -> bool:
        """``read`` certainly sees a plain assignment that is no step and computes the name
        afresh, without reading it (``done = float(i == T - 1)``): no step's flag reaches it."""
        binding = self.flow.last_binding_before(read, done)
        statement = self.facts.statement_of(binding) if binding is not None else None
        if isinstance(statement, ast.Assign):
            if statement.targets != [binding]:
                return False
        elif not (isinstance(statement, ast.AnnAssign) and statement.value is not None and statement.target is binding):
            return False
        if statement in self.legacy_unpacks or statement.value is None:
            return False
        value = statement.value
        if any(isinstance(n, ast.Name) and n.id == done.id for n in walk(value)):
            return False  # ``done = done or stuck``: the step's flag flows on
        if any(isinstance(n, ast.Attribute) and n.attr == "step" for n in walk(value)):
            return False  # ``done = env.step(a)[2]``: a step's flag after all
        return self.flow.dominates(statement, read, done)

    def _outermost_loop(self, node: ast.AST) -> ast.AST | None:
        found = None
        for ancestor in self.facts.ancestors(node):
            if isinstance(ancestor, LOOPS):
                found = ancestor
        return found

    def note_guarded_info(self, info_target: ast.expr) -> None:
        """SB3 VecEnv infos still carry ``TimeLimit.truncated`` (SB104): stay silent on them."""
        if isinstance(info_target, ast.Name):
            scope = self.flow.binding_scope(info_target)
            if scope is not None:
                self.guarded_infos.add((id(scope), info_target.id))

    def note_unsure_info(self, info_target: ast.expr, receiver: ast.expr) -> None:
        """A step left for review: its infos may be an SB3 VecEnv's, which keep the key."""
        if isinstance(info_target, ast.Name):
            scope = self.flow.binding_scope(info_target)
            if scope is not None:
                self.unsure_infos[(id(scope), info_target.id)] = receiver_text(receiver)

    # -- names --------------------------------------------------------------------------------

    def _step_names(self, assign: ast.Assign, vector: bool) -> StepNames:
        base = ("terminations", "truncations") if vector else ("terminated", "truncated")
        numpy = self.numpy_name or "np"
        elementwise = not vector and self._reads_batched_done(assign)
        agents = None if vector else self._per_agent_done(assign)
        shape = {
            "per_agent": agents is not None,
            "guard": agents.guard if agents is not None else None,
            "by_name": agents is not None and agents.by_name,
        }
        if not any(name in self.facts.text for name in base):
            # A name the file never spells is free: no walk of the scope for the names it uses.
            return StepNames(*base, vector=vector, numpy=numpy, elementwise=elementwise, **shape)  # type: ignore[arg-type]
        scope = self.facts.scope_of(assign)
        taken = self.flow.names_used_in(scope)
        compatible = self._step_flag_names(scope) if any(name in taken for name in base) else set()
        terminated, truncated = (_fresh(name, taken, compatible) for name in base)
        return StepNames(terminated, truncated, vector=vector, numpy=numpy, elementwise=elementwise, **shape)  # type: ignore[arg-type]

    def _per_agent_done(self, assign: ast.Assign) -> PerAgent | None:
        """The function (or module) of ``obs, r, done, info = x.step(a)`` uses ``done`` as a
        list of per-agent flags (``all(done)``, ``zip(obs, done)``)."""
        target = assign.targets[0]
        if not isinstance(target, (ast.Tuple, ast.List)) or len(target.elts) != 4 or not isinstance(target.elts[2], ast.Name):
            return None
        scope = self.facts.enclosing_function(assign) or self.facts.scope_of(assign).node
        name = target.elts[2].id
        return self.facts.memo((f"per-agent-done:{name}", id(scope)), lambda: per_agent_done(scope, name))

    def _reads_batched_done(self, assign: ast.Assign) -> bool:
        """The function of ``obs, r, done, info = x.step(a)`` handles ``done`` as per-env
        flags too (``[done] if isinstance(done, bool) else done``, ``done[i]``, ``for d in
        done``, ``np.any(done)``, ``done.any()``): a batch may come through, where ``or``
        raises on arrays."""
        target = assign.targets[0]
        function = self.facts.enclosing_function(assign)
        if function is None or not isinstance(target, (ast.Tuple, ast.List)) or len(target.elts) != 4:
            return False
        done = target.elts[2]
        return isinstance(done, ast.Name) and reads_as_batch(function, done.id)

    def _step_flag_names(self, scope: Scope) -> set[str]:
        """Names that only ever hold step flags in ``scope`` (safe to bind again)."""
        return self.facts.memo(("step-flag-names", id(scope.node)), lambda: _collect_flag_names(scope.node))


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
    for node in walk(root):
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


def _five_targets(done: cst.BaseExpression, names: StepNames) -> cst.BaseExpression:
    """``done`` (the name an indexed step's flag went to) -> ``_, _, terminated, truncated, _``."""
    comma = cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))
    values = ("_", "_", names.terminated, names.truncated, "_")
    elements = [cst.Element(value=cst.Name(v), comma=comma if i < 4 else cst.MaybeSentinel.DEFAULT) for i, v in enumerate(values)]
    return cst.Tuple(elements=elements, lpar=[], rpar=[]).with_changes(lpar=done.lpar, rpar=done.rpar)


# ``np.any(done)``, ``np.logical_not(done)``: calls that read a flag array element by element
_ELEMENTWISE_CALLS = frozenset({"any", "all", "logical_or", "logical_and", "logical_not", "where", "nonzero", "flatnonzero"})


def reads_as_batch(function: ast.AST, name: str) -> bool:
    """``function`` reads ``name`` as a collection of per-env flags somewhere."""
    is_done = named(name)
    return any(_batch_read(collection_read(node, is_done)) for node in walk(function))


def _batch_read(read: CollectionRead | None) -> bool:
    """Indexed, iterated, read element by element by NumPy, or type-tested at all
    (``isinstance(done, bool)``: a bool or something else, a batch). A yes only turns ``or``
    into ``|``, the same on two bools, so a test that also lets one flag through counts."""
    if read is None:
        return False
    if read.shape in (Shape.METHOD, Shape.ARRAY_CALL):
        return read.callee in _ELEMENTWISE_CALLS
    return read.shape in (Shape.INDEXED, Shape.KEYED, Shape.ITERATED, Shape.TYPE_TEST)
