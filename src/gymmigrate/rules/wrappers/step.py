"""GM602: a wrapper's ``step`` override returns five values.

``return obs, reward, done, info`` -> ``return obs, reward, terminated, truncated, info``
with the flags of the override's inner step unpack, as the step family rewrote it
(``notes.step_unpacks``) or as it already was (five targets). When the override
changes ``done`` itself, its own end condition is returned as truncation, for review,
except a lost life (baselines' ``EpisodicLifeEnv``): that sets ``terminated``, as
Stable-Baselines3's port does; and an end of the task (a goal, success, a crash): its line
sets ``terminated`` instead of ``done``, as an env class's own end does (GM504). The
``done = terminated or truncated`` line the step family inserts is withdrawn when the
return was its last reader.

What the override's lines say on their own is read in ``step_ends.py`` (the end
conditions it adds to ``done``) and ``step_inner.py`` (its inner step unpacks: their
flags, aliases of the wrapped env, per-agent flags, other changes of ``done``); this
module decides, and ``step_returns.py`` builds the returns it decides on.
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from dataclasses import replace

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.class_shapes import is_batched_step_return, keeps_legacy_step
from gymmigrate.facts.flow import Flow, bound_on_every_path, contains
from gymmigrate.facts.module import FUNCTIONS, own_returns, walk
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.base import RuleFamily
from gymmigrate.rules.custom_env.plans import (
    BATCHED_STEP_QUESTION,
    batched_step_message,
)
from gymmigrate.rules.step_done.common import StepUnpack
from gymmigrate.rules.wrappers.common import (
    _assigned_names,
    _inner_call,
    _is_inner_env,
    inner_env_names,
)
from gymmigrate.rules.wrappers.step_ends import (
    _clears,
    _done_changes,
    _life_loss_sets,
    _merges_life_loss,
    _names,
    _never_ends,
    _only_own_step_limit,
    _only_step_limits,
    _own_end_kind,
    _replaces_inner_end,
    _task_end_sets,
    gym_time_limit_test,
    limit_tests,
)
from gymmigrate.rules.wrappers.step_inner import (
    _only_inner_done,
    _read_inner_step,
    _reads_per_agent,
    _reduces_per_agent,
    _reduction_of,
    _reshapes,
)
from gymmigrate.rules.wrappers.step_returns import (
    _code,
    _cut,
    _five,
    _own_cut,
    _reduced_flags,
    _reshaped_flags,
)

# A returned ``done`` built as a collection: per-agent flags, not one bool.
_COLLECTIONS = (ast.List, ast.Tuple, ast.Set, ast.Dict, ast.ListComp, ast.SetComp, ast.DictComp, ast.GeneratorExp)


class StepOverrides(RuleFamily):
    """GM602 (mixed into the family; no ``RULES``, so not registered itself)."""

    def _between(self, node: ast.AST, function: ast.AST) -> list[ast.AST]:
        """The nodes around ``node`` inside ``function``."""
        around: list[ast.AST] = []
        for ancestor in self.facts.ancestors(node):
            if ancestor is function:
                break
            around.append(ancestor)
        return around

    def _settle_key_writes(self, function: ast.AST) -> None:
        """The override now returns its step limit as truncation: the StepDone family's
        GM303 item on its ``info["TimeLimit.truncated"] = True`` (asking for exactly that)
        is settled, a note that the leftover key is harmless."""
        first, last = function.lineno, function.end_lineno or function.lineno  # type: ignore[attr-defined]
        writes: set[int] = set()
        for index, node in enumerate(self.plan.finding_nodes):
            finding = self.plan.findings[index]
            if finding.rule == "GM303" and isinstance(node, ast.Subscript) and first <= finding.line <= last and finding.needs_review:
                # the whole statement: ``info[KEY] = (`` may span lines, its value's reads too
                statement = self.facts.statement_of(node)
                last_line = getattr(statement, "end_lineno", None) or finding.line
                writes.update(range(finding.line, last_line + 1))
                self.plan.findings[index] = replace(
                    finding,
                    message=f"{finding.message.split(':', 1)[0]}: the step now returns its time limit as `truncated`, so the "
                    "key is only a leftover (harmless; delete it when convenient)",
                    tier=Tier.NOTE,
                )
        for index, node in enumerate(self.plan.finding_nodes):
            finding = self.plan.findings[index]
            # ``info["TimeLimit.truncated"] = not done``: the leftover key's value asks nothing
            if finding.rule == "GM302" and finding.line in writes and finding.needs_review and not isinstance(node, ast.stmt):
                self.plan.findings[index] = replace(finding, message=f"{finding.message} (the value of the leftover key)", tier=Tier.NOTE)

    def _limit_tests(self, classdef: ast.AST | None) -> Callable[[ast.AST], bool]:
        """The step-limit tests of the wrapper class (``step_ends.limit_tests``), with the
        overrides of its methods in other modules of the run."""
        project = self.receivers.project
        if not isinstance(classdef, ast.ClassDef):
            return limit_tests(self.facts, None, lambda name: True)

        def overridden(name: str) -> bool:
            top_level = self.facts.parent(classdef) is self.facts.tree
            return project is not None and top_level and bool(project.overridden_elsewhere(classdef.name, name))

        return limit_tests(self.facts, classdef, overridden)

    def _settle_merged_reads(self, function: ast.AST, name: str, done_name: str) -> None:
        """The StepDone family's GM302 items on reads of ``done_name`` in ``name = done_name
        or <lost life>``: the return splits ``name`` into terminated and truncated, so what
        those reads asked is answered; a note of why the merged done stays there."""
        lines = {
            node.lineno
            for node in walk(function)
            if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == name for t in node.targets)
        }
        for index, finding in enumerate(self.plan.findings):
            if finding.rule == "GM302" and finding.line in lines and finding.needs_review:
                self.plan.findings[index] = replace(
                    finding,
                    message=f"{finding.message.split(';', 1)[0]}: kept, `{name}` is the old done here and the step's "
                    "return splits it",
                    tier=Tier.NOTE,
                )


    def _task_ends_terminate(
        self,
        function: ast.AST,
        ends: list[ast.Assign],
        done_name: str,
        flags: tuple[str, str],
        unpacks: dict[ast.stmt, StepUnpack | None],
    ) -> int:
        """``done = True`` -> ``terminated = True``, ``done = done or <end>`` -> ``terminated =
        terminated or <end>``: the override's own ends of the task set the inner step's
        terminated. Where ``done`` is read elsewhere than in those lines and the returns
        (``if done: break``), it keeps its old meaning: ``done = True`` stays beside the new
        line, ``done = terminated or truncated`` follows the other. The reads of ``done``
        this takes away from the lines."""
        terminated, truncated = flags
        operands = [
            value
            for end in ends
            if isinstance(end.value, ast.BoolOp)
            for value in end.value.values
            if isinstance(value, ast.Name) and value.id == done_name
        ]
        returned = [
            ret.value.elts[2]
            for ret in own_returns(function)
            if isinstance(ret.value, ast.Tuple)
            and len(ret.value.elts) == 4
            and isinstance(ret.value.elts[2], ast.Name)
            and ret.value.elts[2].id == done_name
        ]
        claimed = sum(noted.claimed_reads for noted in unpacks.values() if noted is not None)
        reads = sum(1 for node in walk(function) if isinstance(node, ast.Name) and node.id == done_name and isinstance(node.ctx, ast.Load))
        keep = reads - claimed - len(returned) - len(operands) > 0
        for end in ends:
            if isinstance(end.value, ast.BoolOp):
                self.plan.replace(end.targets[0], lambda node, t=terminated: cst.Name(t))
                for operand in end.value.values:
                    if isinstance(operand, ast.Name) and operand.id == done_name:
                        self.plan.replace(operand, lambda node, t=terminated: node.with_changes(value=t))
                if keep:
                    self.plan.insert_after(end, f"{done_name} = {terminated} or {truncated}")
            elif keep:
                self.plan.insert_after(end, f"{terminated} = True")
            else:
                self.plan.replace(end.targets[0], lambda node, t=terminated: cst.Name(t))
        return len(operands)

    def _only_unpacked_steps(self, function: ast.AST, unpacks: dict[ast.stmt, StepUnpack | None]) -> bool:
        """Every ``step`` call of the override is an inner step unpack the step family
        rewrote (none already on five targets, none kept whole in a name, no other object's
        step): where none of them reaches a return, nothing else of a step does."""
        if not unpacks or any(noted is None for noted in unpacks.values()):
            return False
        calls = [n for n in walk(function) if isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute) and n.func.attr == "step"]
        return all(any(call is line.value for line in unpacks if isinstance(line, ast.Assign)) for call in calls)

    def _only_passed_through_steps(self, function: ast.AST, unpacks: dict[ast.stmt, StepUnpack | None]) -> bool:
        """The override unpacks no step: each ``step`` call in it is the whole value of a
        ``return`` of the wrapped env's step (``return self.env.step(action)``), which hands
        Gymnasium's five values on as they are; at least one exists. No inner step's flags
        are bound anywhere in it, so a four-value return beside those is the override's own
        transition (an error path's ``return obs, 0.0, True, {}``)."""
        if unpacks:
            return False
        classdef = self.facts.parent(function)
        inner = inner_env_names(classdef) if isinstance(classdef, ast.ClassDef) else ()
        calls = [n for n in walk(function) if isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute) and n.func.attr == "step"]
        returned = {id(ret.value) for ret in own_returns(function) if _inner_call(ret.value, "step", inner) is not None}
        return bool(calls) and all(id(call) in returned for call in calls)

    def _ignores_inner_done(self, unpacks: dict[ast.stmt, StepUnpack | None]) -> bool:
        """No inner step's done is ever read: each unpack's done target is ``_``, or a name
        every read of which another binding reaches first (``done = info["level"] > n`` right
        after the unpack). The override decides its episode's end alone."""
        flow = Flow.of(self.facts)
        for line, noted in unpacks.items():
            if noted is None or noted.claimed_reads or not isinstance(line, ast.Assign):
                return False
            target = line.targets[0]
            held = target.elts[2] if isinstance(target, (ast.Tuple, ast.List)) and len(target.elts) == 4 else None
            if noted.discarded:
                continue
            if not isinstance(held, ast.Name):
                return False
            for read in flow.reads(held):
                reaching = flow.reaching(read)
                if reaching is None or any(binding is held for binding in reaching):
                    return False
        return True

    def _reached_by_inner(self, ret: ast.Return, function: ast.AST, unpacks: dict[ast.stmt, StepUnpack | None]) -> bool:
        flow = Flow.of(self.facts)
        return any(flow.may_run_before(line, ret, function) for line in unpacks)

    def _return_own_end(
        self,
        function: ast.AST,
        ret: ast.Return,
        unpacks: dict[ast.stmt, StepUnpack | None],
        flags: tuple[str, str] | None,
        ignored: bool,
        passed_through: bool = False,
    ) -> bool:
        """``return obs, reward, done, info`` where ``done`` is the override's own end alone:
        a step count is returned as truncated (terminated False); any other end as terminated
        with truncated False, so ``terminated or truncated`` is the old done, a note where
        every test names the task's end or the lives (a terminal state, as GM504 returns an
        env's own end), an item where it does not say. False where ``done`` reads a flag."""
        assert isinstance(ret.value, ast.Tuple)
        done = ret.value.elts[2]
        if flags is not None and _names(done) & (set(flags) - {"_"}):
            return False
        why = (
            "this step override never reads the inner step's done (it decides the episode's end itself)"
            if ignored
            else "no inner step's result reaches this return (the override only hands the wrapped env's step on whole "
            "elsewhere and builds this transition itself)"
            if passed_through
            else "no inner step runs on the way to this return (the override builds this transition itself)"
        )
        kind = _own_end_kind(self.facts, function, done, set(unpacks))
        if kind == "limit":
            self.report(ret, "GM602", f"{why}: its own step limit is returned as truncated, with terminated False", kind=FixKind.ASSIST, tier=Tier.NOTE)
            self.plan.replace(ret.value, lambda node: _five(node, [cst.Name("False"), node.elements[2].value]))
            return True
        if kind == "task":
            message = f"{why}: its own end names the task's end or the lives, a terminal state: returned as terminated, with truncated False"
            self.report(ret, "GM602", message, kind=FixKind.ASSIST, tier=Tier.NOTE)
        else:
            message = (
                f"{why}: its own `done` is returned as terminated, with truncated False, and the inner step's flags are "
                "not passed on, as before; if that end is a cut-off (a time or budget limit), return it as truncated instead"
            )
            self.report(ret, "GM602", message, kind=FixKind.ASSIST)
        self.plan.replace(ret.value, lambda node: _five(node, [node.elements[2].value, cst.Name("False")]))
        return True

    def _flags_bound(self, function: ast.FunctionDef | ast.AsyncFunctionDef, ret: ast.Return, unpacks: dict[ast.stmt, StepUnpack | None], flags: tuple[str, str]) -> bool:
        """Every path to ``ret`` binds both flags (an inner step unpack binds them once
        rewritten)."""
        names = frozenset(flags)
        bound = bound_on_every_path(function, ret, names, lambda statement: names if statement in unpacks else frozenset())
        return bound is None or names <= bound

    def _bind_terminated(
        self, function: ast.AST, ret: ast.Return, unpacks: dict[ast.stmt, StepUnpack | None], terminated: str, anchored: set[int]
    ) -> bool:
        """``terminated = False`` right before the first statement that holds an inner step
        reaching ``ret``, in the innermost block holding them all and ``ret``: it runs
        whenever those steps may run (a loop's every turn included), so where no step runs
        on the way to ``ret`` no step terminated. False where no such block puts it ahead of
        ``ret``."""
        flow = Flow.of(self.facts)
        reaching = [line for line in unpacks if flow.may_run_before(line, ret, function)]
        for holder in [ret, *self._between(ret, function)]:
            if not isinstance(holder, ast.stmt):
                continue
            block = flow.block_of(holder)
            if block is None:
                continue
            statements, index = block
            holding = [i for i, s in enumerate(statements) if any(contains(s, line) for line in reaching)]
            if len(holding) and all(any(contains(statements[i], line) for i in holding) for line in reaching):
                first = holding[0]
                if first > index:
                    return False
                if id(statements[first]) not in anchored:
                    anchored.add(id(statements[first]))
                    self.plan.insert_before(statements[first], f"{terminated} = False")
                return True
        return False

    def _report_other_method_returns(self, classdef: ast.ClassDef, function: ast.FunctionDef | ast.AsyncFunctionDef) -> None:
        """``return self.multistep([action])``: the step hands on what another method gives,
        not the inner step. Where that method (the class's own, followed through its returns)
        gives four values, or ends in a method of the wrapped env other than step, whose
        arity this wrapper cannot see, the override may keep gym's four values under
        Gymnasium's five-value callers: one item. A method that hands on the inner step or
        returns five values is the new contract already."""
        inner = inner_env_names(classdef)
        for ret in own_returns(function):
            call = ret.value
            if not isinstance(call, ast.Call) or not isinstance(call.func, ast.Attribute) or call.func.attr == "step":
                continue
            if any(isinstance(n, ast.Attribute) and n.attr == "step" for n in walk(call)):
                continue  # the inner step's result, processed: its own rules read it
            shape = _other_method_shape(classdef, call, inner, set())
            if shape is None:
                continue
            what = (
                "gives four values (obs, reward, done, info)"
                if shape == 4
                else f"ends in the wrapped env's own `{shape}`, whose result this wrapper cannot see"
            )
            self.report(
                ret,
                "GM602",
                f"this step override returns `{ast.unparse(call.func)}(...)`, not the inner step, and that {what}: "
                "Gymnasium's callers unpack five values from step; where it keeps gym's four, unpack them here and "
                "return (obs, reward, terminated, truncated, info) with done split, or port that method to five "
                "values together with the env's step",
                kind=FixKind.FLAG,
            )

    def _fix_step(self, function: ast.FunctionDef | ast.AsyncFunctionDef) -> None:
        """Return the inner step's terminated/truncated instead of ``done``.

        The flags are those of the step unpack in the override, as the step family
        rewrote it (``notes.step_unpacks``) or as it already was (five targets).
        """
        classdef = self.facts.parent(function)
        if isinstance(classdef, ast.ClassDef) and keeps_legacy_step(classdef):
            batched = [r for r in own_returns(function) if is_batched_step_return(r.value, function)]
            if batched:
                # A batch of envs (a single env shown as a batch of one): stacked flags, no
                # place for one scalar ``truncated``; its contract and its callers' are kept.
                self.report(
                    batched[0],
                    "GM602",
                    batched_step_message(classdef.name, keeps_reset=any(isinstance(s, FUNCTIONS) and s.name == "reset" for s in classdef.body)),
                    kind=FixKind.FLAG,
                    question=BATCHED_STEP_QUESTION,
                )
                return
        if isinstance(classdef, ast.ClassDef):
            self._report_other_method_returns(classdef, function)
        inner = _read_inner_step(function, classdef, self.notes.step_unpacks)
        lines, unpacks, flags, consistent = inner.lines, inner.unpacks, inner.flags, inner.consistent
        done_name, done_line, inserted, inner_done = inner.done_name, inner.done_line, inner.inserted, inner.inner_done
        bound, done_attribute, per_agent, done_modified = inner.bound, inner.done_attribute, inner.per_agent, inner.done_modified
        loops = (ast.For, ast.AsyncFor, ast.While)
        passed_through = self._only_passed_through_steps(function, unpacks)
        own_steps = passed_through or self._only_unpacked_steps(function, unpacks)
        ignored = own_steps and not passed_through and self._ignores_inner_done(unpacks)
        anchored: set[int] = set()  # statements a ``terminated = False`` is bound before
        replaced_done_reads = 0
        settled_lives: set[int] = set()
        settled_task_ends = False
        # ``if self.steps < self.min_len: done = False`` after the inner step takes back the
        # inner end too: where a return passes the inner flags on, that line clears both
        # (``terminated = truncated = False``), else the inner ``terminated`` would end an
        # episode the override keeps going.
        clears = (
            _clears(lines, done_name, done_line, unpacks)
            if done_name is not None and flags is not None and consistent and "_" not in flags and not per_agent
            else []
        )
        clear_note = (
            f"; `{done_name} = False` (line{'s' if len(clears) > 1 else ''} "
            f"{', '.join(str(c.lineno) for c in clears)}) takes back the inner end too, so it clears both flags there"
            if clears
            else ""
        )
        clears_flags = False
        for ret in own_returns(function):
            value = ret.value
            if not isinstance(value, ast.Tuple) or len(value.elts) != 4:
                continue
            if any(isinstance(e, ast.Starred) for e in value.elts):
                continue
            if own_steps and (ignored or not self._reached_by_inner(ret, function, unpacks)):
                # No inner step's done reaches this return: what it returns is the override's
                # own end (a replayed or synthetic step, or an inner done it never read). The
                # inner flags are not passed on here, as before, and not read either.
                if self._return_own_end(function, ret, unpacks, flags, ignored, passed_through):
                    continue
            if flags is None or not consistent or "_" in flags:
                self.report(
                    ret,
                    "GM602",
                    "this step override returns four values but the inner step's terminated/truncated could "
                    "not be found; return (obs, reward, terminated, truncated, info)",
                    kind=FixKind.FLAG,
                )
                continue
            terminated, truncated = flags
            done = value.elts[2]
            if not self._flags_bound(function, ret, unpacks, flags):
                # Some path reaches this return without running an inner step (a branch that
                # builds its own transition): the flags are unbound there, and a return that
                # read them would raise UnboundLocalError on that path.
                if per_agent or _names(done) & set(flags) or not self._bind_terminated(function, ret, unpacks, terminated, anchored):
                    self.report(
                        ret,
                        "GM602",
                        "this step override returns four values, but not every path to this return runs the inner step, "
                        "so its terminated/truncated are not bound on all of them: return (obs, reward, terminated, "
                        "truncated, info) by hand",
                        kind=FixKind.FLAG,
                    )
                    continue
                self.report(
                    ret,
                    "GM602",
                    f"not every path to this return runs the inner step: where it does not, `{terminated}` is False "
                    f"(bound before the branches), so the override's own `done` is returned as truncation (`... and not "
                    f"{terminated}`): if it really ends the episode, return it as terminated instead",
                    kind=FixKind.ASSIST,
                )
                self.plan.replace(value, lambda node, t=terminated: _five(node, _cut(node, t)))
                continue
            plain_done = isinstance(done, ast.Name) and (
                (done.id == done_name and not done_modified) or done.id not in bound
            )
            if isinstance(done, ast.Name) and done.id == done_name and done_modified and done_line is not None:
                # ``if done: return obs, reward, done, info`` before the override's own end
                # (``done = lives == 0`` below): only the inner step's done reaches this
                # return, so it passes the inner flags on; nothing of its own to ask about.
                plain_done = (
                    done_line.lineno < ret.lineno
                    and all(change.lineno > ret.lineno for change in inner.done_changes)
                    and not any(isinstance(a, loops) for a in self._between(ret, function))
                )
            if done_attribute is not None and _only_inner_done(classdef, function, done, done_attribute, ret):
                # ``self.done`` set only by the unpack above: the inner flags themselves (the
                # attribute keeps ``terminated or truncated``), no end of the override's own.
                self.report(ret, "GM602", "step returns (obs, reward, terminated, truncated, info)")
                self.plan.replace(value, lambda node, t=terminated, u=truncated: _five(node, [cst.Name(t), cst.Name(u)]))
            elif plain_done and isinstance(done, ast.Name):  # ``plain_done`` implies a Name
                replaced_done_reads += done.id == done_name
                self.report(ret, "GM602", "step returns (obs, reward, terminated, truncated, info)")
                self.plan.replace(value, lambda node, t=terminated, u=truncated: _five(node, [cst.Name(t), cst.Name(u)]))
            elif (
                isinstance(done, ast.Name)
                and done.id == done_name
                and _only_step_limits(
                    self.facts, lines, done_name, done_line, unpacks, bool(per_agent), self._limit_tests(classdef)
                )
            ):
                # The TimeLimit pattern: the override ends episodes only on a step count,
                # which is truncation by definition. An explanation, not a question.
                self.report(
                    ret,
                    "GM602",
                    "this step override ends episodes only on a step limit (the TimeLimit pattern): that end is "
                    + (
                        f"returned as truncation agent by agent (`done and not {terminated}` of each agent: the flags are "
                        "per-agent lists)"
                        if per_agent
                        else f"returned as truncation (`... and not {terminated}`)"
                    )
                    + clear_note,
                    kind=FixKind.ASSIST,
                    tier=Tier.NOTE,
                )
                clears_flags = True
                self.plan.replace(value, lambda node, t=terminated: _five(node, _cut(node, t, per_agent)))
                self._settle_key_writes(function)
            elif (
                isinstance(done, ast.Name)
                and done.id == done_name
                and isinstance(classdef, ast.ClassDef)
                and _only_step_limits(
                    self.facts, lines, done_name, done_line, unpacks, bool(per_agent), gym_time_limit_test(self.facts, classdef)
                )
            ):
                # ``if self._past_limit(): done = True`` in a subclass of gym's TimeLimit: the
                # end is its base's limit, a truncation whatever else the class does; but the
                # test calls a method Gymnasium's TimeLimit does not have.
                self.report(
                    ret,
                    "GM602",
                    "this step override ends episodes only on `self._past_limit()`, the limit test of gym's TimeLimit it "
                    "derives from (a truncation): that end is returned as truncation "
                    + (
                        f"agent by agent (`done and not {terminated}` of each agent: the flags are per-agent lists)"
                        if per_agent
                        else f"(`... and not {terminated}`)"
                    )
                    + "; Gymnasium's TimeLimit has no `_past_limit()`: test `self._elapsed_steps >= "
                    "self._max_episode_steps` there"
                    + clear_note,
                    kind=FixKind.ASSIST,
                )
                clears_flags = True
                self.plan.replace(value, lambda node, t=terminated: _five(node, _cut(node, t, per_agent)))
            elif done_name not in _names(done) and inner_done not in _names(done) and _only_own_step_limit(function, done, flags):
                # ``done = False; if self.t >= self.t_max: done = True`` returned, the inner
                # step's done read for something else (a penalty): the wrapper hides the inner
                # end and ends the episode only at its own step count, which is truncation.
                # Passing the inner flags on would end episodes the wrapper kept going.
                self.report(
                    ret,
                    "GM602",
                    "this step override returns only its own step limit as `done` (the inner step's end is not passed "
                    "on, as before): returned as truncated, with terminated False",
                    kind=FixKind.ASSIST,
                    tier=Tier.NOTE,
                )
                self.plan.replace(value, lambda node: _five(node, [cst.Name("False"), node.elements[2].value]))
            elif isinstance(done, ast.Constant) and (done.value is None or isinstance(done.value, bool)):
                # ``return obs, reward, False, info``: the override's own constant end.
                self.report(
                    ret,
                    "GM602",
                    f"this step override returns a constant `done` ({done.value}): returned as terminated, with "
                    "truncated False; the inner step's flags are not passed on, as before",
                    kind=FixKind.ASSIST,
                )
                self.plan.replace(value, lambda node: _five(node, [node.elements[2].value, cst.Name("False")]))
            elif isinstance(done, _COLLECTIONS):
                # ``return [obs], [reward], [done], info``: a wrapper that makes an env look
                # multi-agent returns per-agent flags, not one bool; cutting them against
                # ``terminated`` would be always false. They are returned whole as
                # terminated, with truncated False, as custom envs' per-agent lists are
                # (GM504): ``terminated or truncated`` is the old ``done``.
                self.report(
                    ret,
                    "GM602",
                    "this step override returns per-agent `done` flags (a collection): they are returned as terminated "
                    "with truncated False, so `terminated or truncated` is the old done (the inner step's truncation "
                    "included); split them per agent where a learner bootstraps on terminated",
                    kind=FixKind.ASSIST,
                )
                self.plan.replace(value, lambda node: _five(node, [node.elements[2].value, cst.Name("False")]))
            elif (
                per_agent
                and not done_modified
                and (reduced := _reduction_of(done, done_name)) is not None
            ):
                # ``return obs, reward, all(done), info`` over per-agent lists (a wrapper that
                # squashes them for a single-agent learner): each flag is reduced on its own.
                # ``any`` splits exactly; for ``all``, the episode ends when every agent is done
                # (as before), and it is terminated only when every agent terminated.
                self.report(
                    ret,
                    "GM602",
                    f"this step override reduces per-agent `done` flags with {reduced}(): it returns {reduced}() of the "
                    f"inner `{terminated}` as terminated, and the old done when that is false as truncated",
                    kind=FixKind.ASSIST,
                    tier=Tier.NOTE,
                )
                self.plan.replace(
                    value,
                    lambda node, t=terminated, r=reduced, d=done_name: _five(node, _reduced_flags(r, d, t)),
                )
            elif _reads_per_agent(done, agent_flags := {name for name in (done_name, *flags) if name is not None}) or (
                isinstance(done, ast.Name) and _reduces_per_agent(function, done.id, agent_flags)
            ):
                # ``all(done)``, ``list(done.values())``, or ``done = all(done)`` returned: the
                # inner flags are per agent; cutting the result against ``terminated`` (a
                # collection too) would always be false. The old done, reduced as before, is
                # returned as terminated with truncated False, as the per-agent lists above.
                self.report(
                    ret,
                    "GM602",
                    "this step override reduces per-agent `done` flags (all()/any()/values() of the inner ones): the "
                    "result is returned as terminated with truncated False, so `terminated or truncated` is the old "
                    "done; split it where a learner bootstraps on terminated",
                    kind=FixKind.ASSIST,
                )
                self.plan.replace(value, lambda node: _five(node, [node.elements[2].value, cst.Name("False")]))
            elif isinstance(done, ast.Name) and done_name is not None and done.id == done_name and (
                life_losses := _life_loss_sets(self.facts, lines, done_name, done_line, unpacks, flags)
            ):
                # A lost life ends the agent's episode: Stable-Baselines3's EpisodicLifeEnv
                # returns it as ``terminated=True`` and keeps ``truncated`` from the inner step;
                # no life left is the game over, a terminal state too.
                game_over = any(not text.endswith("= True") for _, text in life_losses)
                self.report(
                    ret,
                    "GM602",
                    (
                        "this step override ends the episode on a test of the lives (no life left is the game over): "
                        f"that end sets `{terminated}`, a terminal state as a lost life is for Stable-Baselines3; "
                        f"`{truncated}` stays the inner step's"
                        if game_over
                        else "this step override ends the episode on a lost life (the EpisodicLifeEnv pattern): a lost "
                        f"life sets `{terminated}` as Stable-Baselines3 does; `{truncated}` stays the inner step's"
                    )
                    + clear_note,
                    kind=FixKind.ASSIST,
                    tier=Tier.NOTE,
                )
                clears_flags = True
                for life_loss, text in life_losses:
                    if id(life_loss) not in settled_lives:  # once for every return that reads it
                        settled_lives.add(id(life_loss))
                        self.plan.insert_after(life_loss, text)
                self.plan.replace(value, lambda node, t=terminated, u=truncated: _five(node, [cst.Name(t), cst.Name(u)]))
            elif (
                isinstance(done, ast.Name)
                and done_name is not None
                and done.id != done_name
                and not done_modified
                and _merges_life_loss(function, done.id, done_name, flags)
            ):
                # ``if self.terminal_on_life_loss: end = done or lives < self.lives else: end =
                # done``: the inner done, or it with a lost life, under a name of the override's
                # own. The name keeps the old done for the reads before the return (a frame-skip
                # loop's ``break``); the return splits it: a lost life or the inner end is
                # terminated, the inner truncation stays truncated.
                self.report(
                    ret,
                    "GM602",
                    f"this step override ends the episode on a lost life (merged into `{done.id}` with the inner done): "
                    f"that end is returned as `{terminated}`, as Stable-Baselines3 does, the inner step's `{truncated}` as "
                    "it was (a life lost on the very step a time limit cuts counts as the cut)",
                    kind=FixKind.ASSIST,
                    tier=Tier.NOTE,
                )
                self._settle_merged_reads(function, done.id, done_name)
                self.plan.replace(
                    value,
                    lambda node, t=terminated, u=truncated: _five(
                        node, [cst.parse_expression(f"({_code(node.elements[2].value)} and not {u}) or {t}"), cst.Name(u)]
                    ),
                )
            elif (
                isinstance(done, ast.Name)
                and done_name is not None
                and done.id == done_name
                and not per_agent
                and (task_ends := _task_end_sets(self.facts, lines, done_name, done_line, unpacks, classdef))
            ):
                # ``done = done or info["is_success"]``: the wrapper's own condition is the task
                # ending (success, a goal, a crash), which Gymnasium calls terminated, on the
                # step a time limit cuts too: the line sets ``terminated`` itself, as an env
                # class's own end does (GM504), and the inner step's truncation stays truncated.
                if not settled_task_ends:
                    settled_task_ends = True
                    replaced_done_reads += self._task_ends_terminate(function, task_ends, done_name, flags, unpacks)
                replaced_done_reads += 1
                ends = ", ".join(str(end.lineno) for end in task_ends)
                self.report(
                    ret,
                    "GM602",
                    "this step override ends the episode when the task ends (success, a goal, a failure): that end "
                    f"sets `{terminated}` (line{'s' if len(task_ends) > 1 else ''} {ends}), a terminal state even on the "
                    f"step a time limit cuts; `{truncated}` stays the inner step's" + clear_note,
                    kind=FixKind.ASSIST,
                    tier=Tier.NOTE,
                )
                clears_flags = True
                self.plan.replace(value, lambda node, t=terminated, u=truncated: _five(node, [cst.Name(t), cst.Name(u)]))
            elif (reshaped := done_name or inner_done) is not None and not done_modified and _reshapes(done, reshaped, terminated):
                # ``np.asarray(done)``, ``bool(done)``: the inner done only reshaped, no end of
                # the override's own; the same call on each flag keeps both and the shape.
                self.report(
                    ret,
                    "GM602",
                    f"step returns the inner step's `{terminated}` and `{truncated}`, each passed through the call that "
                    f"reshaped `{reshaped}`",
                    kind=FixKind.ASSIST,
                    tier=Tier.NOTE,
                )
                replaced_done_reads += reshaped == done_name
                self.plan.replace(value, lambda node, t=terminated, u=truncated: _five(node, _reshaped_flags(node, t, u)))
            elif (
                isinstance(done, ast.Name)
                and done.id == done_name
                and isinstance(classdef, ast.ClassDef)
                and (source := _never_ends(_done_changes(lines, done_name, done_line, unpacks), done_name, classdef, self.facts))
                is not None
            ):
                # ``obs, done = self.fire()`` where ``fire`` only ever returns a false flag: the
                # override adds no end of its own, the cut below keeps the inner step's flags.
                self.report(
                    ret,
                    "GM602",
                    f"this step override sets `{done_name}` from {source}, which is always false: it adds no end of its "
                    f"own, so the step returns the inner `{terminated}` and `{done_name} and not {terminated}` as "
                    "truncated (the inner truncation)",
                    kind=FixKind.ASSIST,
                    tier=Tier.NOTE,
                )
                self.plan.replace(value, lambda node, t=terminated: _five(node, _cut(node, t, per_agent)))
            elif per_agent:
                self.report(
                    ret,
                    "GM602",
                    "this step override decides its per-agent `done` list itself; its own end condition is now "
                    f"returned as truncation agent by agent (`done and not {terminated}` of each agent): if it really "
                    f"ends an agent's episode, return it in `{terminated}` instead (Gymnasium releases of multi-agent "
                    "envs may return one bool per step: then use `or` and `and not` on the flags themselves)",
                    kind=FixKind.ASSIST,
                )
                self.plan.replace(value, lambda node, t=terminated: _five(node, _cut(node, t, per_agent)))
            elif _replaces_inner_end(function, done, {done_name, inner_done, *flags} - {None}, done_attribute[0] if done_attribute else None):  # type: ignore[arg-type]
                # ``done_trial = False; if self.done_mdp: ... done_trial = True`` returned: the
                # override's own flag stands in for the inner end (which it read to decide, and
                # may have reset from). Returning the inner ``terminated`` beside it would end
                # episodes the override keeps going; both flags are cut from its own, so
                # ``terminated or truncated`` is its old done.
                self.report(
                    ret,
                    "GM602",
                    "this step override returns its own `done` in place of the inner step's (which it only reads to "
                    f"decide): returned as terminated where the inner step terminated (`... and {terminated}`) and as "
                    f"truncation otherwise (`... and not {terminated}`), so `terminated or truncated` is its old done; "
                    "if its own end really ends the episode, return it as terminated instead",
                    kind=FixKind.ASSIST,
                )
                self.plan.replace(value, lambda node, t=terminated: _five(node, _own_cut(node, t)))
            else:
                self.report(
                    ret,
                    "GM602",
                    "this step override decides `done` itself; its own end condition is now returned as truncation "
                    f"(`... and not {terminated}`): if it really ends the episode (e.g. a lost life), return it as "
                    "terminated instead" + clear_note,
                    kind=FixKind.ASSIST,
                )
                clears_flags = True
                self.plan.replace(value, lambda node, t=terminated: _five(node, _cut(node, t)))
        dropped = False
        if done_name is not None and done_line is not None and replaced_done_reads:
            claimed = sum(noted.claimed_reads for noted in unpacks.values() if noted is not None)
            reads = sum(
                1
                for node in walk(function)
                if isinstance(node, ast.Name) and node.id == done_name and isinstance(node.ctx, ast.Load)
            )
            dropped = reads - claimed - replaced_done_reads <= 0
            if dropped:
                # nothing reads ``done`` any more: drop the line that kept it
                if inserted is not None and done_line is inserted[0]:
                    self.plan.withdraw(inserted[0], inserted[1].done_line)
                else:
                    self.plan.remove(done_line)
                for line, noted in unpacks.items():
                    # a later inner step's ``done = ...`` line, unread as well
                    if noted is not None and noted.done_line is not None and line is not done_line and done_name in _assigned_names(line):
                        self.plan.withdraw(line, noted.done_line)
        if clears_flags and flags is not None:
            terminated, truncated = flags
            for clear in clears:
                if dropped:
                    # nothing reads ``done`` any more: the line clears the flags instead
                    self.plan.replace(
                        clear,
                        lambda node, t=terminated, u=truncated: node.with_changes(
                            targets=[cst.AssignTarget(target=cst.Name(t)), cst.AssignTarget(target=cst.Name(u))]
                        ),
                    )
                else:
                    self.plan.insert_after(clear, f"{terminated} = {truncated} = False")


def _other_method_shape(classdef: ast.ClassDef, call: ast.Call, inner: tuple[str, ...], seen: set[str]) -> int | str | None:
    """What ``call`` (``self.m(...)`` or ``self.env.m(...)``) is known to give: 4 where the
    class's own ``m`` returns a four-value tuple (followed through its returns), the method's
    name where it ends in a method of the wrapped env other than step, None where it returns
    five values, the inner step, or what this class cannot follow."""
    func = call.func
    if not isinstance(func, ast.Attribute) or func.attr == "step":
        return None
    if _is_inner_env(func.value, inner):
        return func.attr
    if not (isinstance(func.value, ast.Name) and func.value.id == "self") or func.attr in seen:
        return None
    method = next((m for m in classdef.body if isinstance(m, FUNCTIONS) and m.name == func.attr), None)
    if method is None:
        return None
    seen.add(func.attr)
    shapes: set[int | str | None] = set()
    for ret in own_returns(method):
        value = ret.value
        if isinstance(value, ast.Tuple) and not any(isinstance(e, ast.Starred) for e in value.elts):
            shapes.add(4 if len(value.elts) == 4 else None)
        elif isinstance(value, ast.Call):
            shapes.add(_other_method_shape(classdef, value, inner, seen))
        else:
            shapes.add(None)
    known = shapes - {None}
    # one answer on every path: a method that sometimes gives five values is the class's own contract
    return known.pop() if len(known) == 1 and None not in shapes else None
