"""GM504: ``step`` returns ``(obs, reward, terminated, truncated, info)``.

A step limit the env counts itself (``self.steps >= self.max_steps`` in the done test)
becomes ``truncated``; everything else ``terminated``. Returns that are not a 4-tuple
literal are reported. The old migration guide: "replacing ``done`` with ``terminated``
and ``truncated=False`` in step should address most issues".
"""

from __future__ import annotations

import ast
import re
from collections.abc import Hashable

from gymmigrate.facts.env_classes import (
    FunctionIndex,
    identifiers,
    is_super_method_call,
)
from gymmigrate.facts.limits import (
    Cause,
    DoneCause,
    DoneTracer,
    Limit,
    data_end_attributes,
    if_setting_true,
    is_end_of_data,
    is_step_limit,
    unwrap_bool,
)
from gymmigrate.facts.module import own_returns
from gymmigrate.facts.receiver_classes import is_batched_step_return, keeps_legacy_step
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.custom_env.common import (
    ClassDecision,
    Method,
    delegates,
    inner_gym_env_call,
    tuple_len,
)
from gymmigrate.rules.custom_env.hooks import (
    local_subclasses,
    overrides,
    step_override_migratable,
    where,
)
from gymmigrate.rules.custom_env.plans import (
    BATCHED_STEP_QUESTION,
    STEP_LIMIT_WORD,
    batched_step_message,
    truncated_false_message,
)

__all__ = ["decide_step", "is_step_limit", "unwrap_bool"]


def decide_step(decision: ClassDecision, inherited: dict[int, list[str]]) -> None:
    """``inherited``: per subclass (by id), the hooks a base class of this module migrated,
    which its overrides migrate with (``hooks.py``); filled as the bases are decided."""
    project = decision.family.receivers.project
    if project is not None and decision.family.facts.parent(decision.classdef) is decision.family.facts.tree:
        # a hook a base of another module migrates (``class Task(pkg.BaseEnv)``): this
        # module's subclasses of the class follow it too
        for name in sorted(project.inherited_hooks(decision.classdef.name)):
            for target in (decision.classdef, *local_subclasses(decision)):
                if name not in inherited.get(id(target), []):
                    inherited.setdefault(id(target), []).append(name)
    for name in inherited.get(id(decision.classdef), ()):
        override = decision.methods.get(name)
        if override is not None and name not in decision.plan.step_helpers:
            decision.plan.step_helpers.append(name)
            _decide_returns(decision, override, set())
    function = decision.method("step")
    if function is None:
        return
    # The class's tests of the end of its data, as text, for the rewrite's own split
    # (``cst_edits._split_done``): they stay in terminated, whatever their names say.
    facts = decision.family.facts
    decision.plan.data_end_tests = frozenset(
        "".join(facts.segment(node).split())
        for node in ast.walk(decision.classdef)
        if isinstance(node, ast.Compare) and is_end_of_data(node, _data_ends(decision))
    )
    # ``def step(self, a): return self._step(a)`` (gym <= 0.9's own base class did
    # this): the helper's returns are the step's, so they get the five fields.
    helpers = []
    blocked: dict[str, str] = {}
    for helper in delegates(decision, function):
        local, elsewhere = overrides(decision, helper.name)
        # overrides in other modules follow only when all of them derive from this class
        # itself (the join checked each of them: facts/step_hooks.py)
        followed = not elsewhere or (
            project is not None
            and project.hook_followed_elsewhere(decision.classdef.name, helper.name)
            and len(elsewhere) == len(project.overridden_elsewhere(decision.classdef.name, helper.name))
        )
        if not followed or not all(step_override_migratable(m) for _, m in local):
            blocked[helper.name] = where(decision, local, elsewhere)
            continue
        helpers.append(helper)
        for subclass, _ in local:
            inherited.setdefault(id(subclass), []).append(helper.name)
    decision.plan.step_helpers += [h.name for h in helpers if h.name not in decision.plan.step_helpers]
    for step_function in (function, *helpers):
        _decide_returns(decision, step_function, {id(h) for h in helpers}, blocked)


def _decide_returns(decision: ClassDecision, function: Method, helpers: set[int], blocked: dict[str, str] | None = None) -> None:
    returns = own_returns(function)
    if any(tuple_len(r.value) == 5 or _returns_five_from_helper(r, decision) for r in returns):
        return  # already the five-value API
    index = decision.function(function)
    limit_hint = _step_limit_text(decision, function)
    data_ends = _data_ends(decision)
    facts = decision.family.facts
    # No step limit is possible when the class counts nothing: truncated=False is then
    # exact (TimeLimit truncates), an explanation rather than a question.
    no_counter = limit_hint is None and not _counts_toward_a_limit(decision)
    plain = (
        "step returns terminated (the old done) and truncated=False: the class counts nothing that could end "
        "an episode on a limit, so truncation is left to TimeLimit (max_episode_steps)"
    )
    tracer = done_tracer(decision)
    for position, ret in enumerate(returns):
        if ret.value is None:
            continue
        if _returns_helper(ret, decision, helpers) or is_super_method_call(ret.value, function.name):
            continue  # the helper's (or the base's own hook's) returns carry the contract
        if inner_gym_env_call(decision, ret.value, "step"):
            continue  # a Gym env the class holds: its step() returns the five values in Gymnasium
        hook = _blocked_hook(ret, blocked or {})
        if hook is not None:
            decision.report(
                ret,
                "GM504",
                f"step returns self.{hook[0]}(...), which subclasses override ({hook[1]}): the hook and every override "
                "must return (obs, reward, terminated, truncated, info) together; none was changed, migrate them by hand",
                FixKind.FLAG,
            )
            continue
        names = _unpacked_helper_names(decision, function, ret)
        if names is not None and not keeps_legacy_step(decision.classdef):
            # ``return self._observe()`` where ``_observe`` returns four values and other code
            # reads those four too: the helper keeps its contract, and step unpacks it.
            decision.plan.step = True
            decision.plan.unpacked_helper_returns.setdefault(function.name, {})[position] = names
            helper = ret.value.func.attr  # type: ignore[attr-defined]
            if limit_hint is None and no_counter:
                decision.report(
                    ret,
                    "GM504",
                    f"step unpacks the four values of self.{helper}(), which other code reads as they are, and returns "
                    "its done as terminated with truncated=False: the class counts nothing that could end an episode "
                    "on a limit",
                    FixKind.ASSIST,
                    tier=Tier.NOTE,
                )
            else:
                decision.report(
                    ret,
                    "GM504",
                    f"step unpacks the four values of self.{helper}(), which other code reads as they are, and returns "
                    f"its done as terminated with truncated=False; {truncated_false_message(limit_hint)}",
                    FixKind.ASSIST,
                )
            continue
        if keeps_legacy_step(decision.classdef) and is_batched_step_return(ret.value, function):
            # Stacked per-env flags: a batch of envs with its own API, where a scalar
            # ``truncated`` has no place and ``done`` folds each env's truncation into one
            # flag. Its contract is kept (and its callers' with it); one item per class.
            decision.plan.batched_step = True
            if not any(is_batched_step_return(r.value, function) for r in returns[:position]):
                # Kept whole (reset, step, render(mode) and the calls on its instances the
                # run traces), the batch works on Gymnasium as it did: an explanation, not a
                # question (an untraced caller is asked about at its own call).
                decision.report(
                    ret,
                    "GM504",
                    batched_step_message(
                        decision.classdef.name,
                        keeps_reset="reset" in decision.methods,
                        keeps_render="render" in decision.methods,
                    ),
                    FixKind.FLAG,
                    tier=Tier.NOTE,
                    question=BATCHED_STEP_QUESTION,
                )
            continue
        if tuple_len(ret.value) != 4:
            if not keeps_legacy_step(decision.classdef):
                kept = "; return (obs, reward, terminated, truncated, info) by hand"
            elif "reset" in decision.methods:
                kept = (
                    ": the step keeps its four fields and reset its own return (no seed/options), and so do the calls "
                    "of them this run can trace (their unpacks are left as they are); migrate reset, step and their "
                    "callers together"
                )
            else:
                kept = (
                    ": the step keeps its four fields, and so do the calls of it this run can trace (their unpacks are "
                    "left as they are); migrate the step and its callers together"
                )
            decision.report(ret, "GM504", f"step returns something other than a 4-tuple literal{kept}", FixKind.FLAG)
            continue
        done = ret.value.elts[2]  # type: ignore[attr-defined]
        base = _from_unknown_base_step(decision, index, done.id) if isinstance(done, ast.Name) else None
        if base is not None:
            # ``done, False`` would be right only if the base's step kept four values, and
            # ``bool(done) and not truncated, truncated`` only if it returns five: the run
            # cannot tell which, so the return stays and a person decides.
            decision.plan.kept_returns.setdefault(function.name, set()).add(position)
            decision.report(
                ret,
                "GM504",
                f"step returns the done of super().step(...), and {_unknown_base_text(decision, base)}: if its step "
                f"returns Gymnasium's five values, return `bool({done.id}) and not truncated, truncated` (its "
                "truncation stays one); if it keeps four, keep this step's unpack and return as they were; not rewritten",
                FixKind.FLAG,
            )
            continue
        decision.plan.step = True
        if isinstance(done, ast.Name) and index.assigns_name(done.id):
            assigned = _single_assignment(index, done.id)
            if assigned is not None and _split_done(assigned, data_ends):
                decision.report(
                    ret,
                    "GM504",
                    f"`{done.id}` split: the step-limit test became truncated, the rest terminated",
                    FixKind.ASSIST,
                    tier=_split_tier(tracer.trace(done), assigned, data_ends),
                    question=_split_question(assigned),
                )
                continue
        elif _split_done(done, data_ends):
            decision.report(
                ret,
                "GM504",
                "done split: the step-limit test became truncated, the rest terminated",
                FixKind.ASSIST,
                tier=_split_tier(tracer.trace(done), done, data_ends),
                question=_split_question(done),
            )
            continue
        if isinstance(done, ast.Constant) and done.value is False:
            # This return never ends an episode, on a limit or otherwise: nothing to split.
            decision.report(ret, "GM504", "step returns terminated=False and truncated=False, as its done was False", FixKind.ASSIST, tier=Tier.NOTE)
            continue
        if isinstance(done, ast.Name) and _unpacked_from_inner_step(decision, index, done.id):
            # The step family unpacks that step's terminated and truncated: return them as they
            # are (``done and False`` would fold the inner truncations into terminated).
            decision.plan.passthrough_returns.setdefault(function.name, set()).add(position)
            decision.report(
                ret,
                "GM504",
                f"step returns the terminated and truncated of the step it calls (`{done.id}` was their `or`)",
                FixKind.ASSIST,
                tier=Tier.NOTE,
            )
            continue
        if isinstance(done, ast.Name) and (ends := _task_ends(decision, index, done.id)) and _unpacked_from_inner_step(
            decision, index, done.id, frozenset(id(e) for e in ends)
        ):
            # ``obs, r, done, info = super().step(a)`` then ``if solved: done = True``: the
            # class's own end is a terminal state; the step it calls keeps its truncation.
            decision.plan.task_end_returns.setdefault(function.name, set()).add(position)
            decision.report(
                ret,
                "GM504",
                f"step returns the truncated of the step it calls, and its own end of the task (`{done.id} = True` on "
                f"line {ends[0].lineno}) as terminated: `bool({done.id}) and not truncated`",
                FixKind.ASSIST,
                tier=Tier.NOTE,
            )
            continue
        if isinstance(done, ast.Name) and (limit := _accumulated_limit(function, ret, done.id, data_ends)) is not None:
            # ``done = task`` ... ``done = done or self.t >= self.max_steps`` right before the
            # return: the last line adds the step limit to the task's end, so it is the
            # truncation and the flag before it the termination.
            decision.plan.accumulated_returns.setdefault(function.name, set()).add(position)
            decision.report(
                ret,
                "GM504",
                f"`{done.id}` split: its last line (line {limit.lineno}) adds the step limit, which became truncated; "
                "the value before it is terminated",
                FixKind.ASSIST,
                tier=Tier.NOTE,
            )
            continue
        if isinstance(done, ast.Name) and (flag := _flagged_limit(function, done.id, data_ends)) is not None:
            # ``done = False`` ... ``if self.t >= self.t_limit: done = True`` beside the task's
            # own ``if <end>: done = True``: that one ``if`` is the truncation, the rest of the
            # flag the termination, and nothing else reads or resets the flag.
            decision.plan.flagged_limit_returns.setdefault(function.name, set()).add(position)
            decision.report(
                ret,
                "GM504",
                f"`{done.id}` split: its step-limit line (line {flag.lineno}) became "
                f"`truncated = bool({decision.family.facts.segment(flag.test)})`, the task's own ends terminated",
                FixKind.ASSIST,
                tier=_split_tier(tracer.trace(done), flag.test, data_ends),
                question=_split_question(flag.test),
            )
            continue
        traced = tracer.trace(done)
        if traced.cause is Cause.TRUNCATION:
            decision.plan.truncating_returns.setdefault(function.name, set()).add(position)
            _report_truncation(decision, ret, done, traced)
            continue
        dm_last = next((limit for limit in traced.limits if limit.text.endswith(".last()") and not limit.where), None)
        if dm_last is not None:
            step = dm_last.text[: -len(".last()")]
            decision.report(
                ret,
                "GM504",
                f"step returns `{decision.family.facts.segment(done)}` as terminated with truncated=False, but "
                f"`{dm_last.text}` ({dm_last.place()}) is also True when dm_control's own time limit ends the episode "
                f"(with discount 1.0): return terminated = `{step}.last() and {step}.discount == 0` and truncated = "
                f"`{step}.last() and not terminated`",
                FixKind.ASSIST,
            )
            continue
        if traced.limits:
            what = (
                "split it from the task's own end by hand"
                if traced.cause is Cause.MIXED
                else "not every way to it could be followed: a dict of per-agent flags, an override that takes arguments"
            )
            decision.report(
                ret,
                "GM504",
                f"step returns `{decision.family.facts.segment(done)}` as terminated with truncated=False, but "
                f"{_limits_text(traced)} is a step/time limit among its causes: return that end as truncated, not "
                f"terminated; {what}",
                FixKind.ASSIST,
            )
            continue
        if traced.cause is Cause.TERMINATION and traced.ends_of_data and limit_hint is None:
            # The done is the end of the env's data (``self.day == self.max_step`` with
            # ``self.max_step = len(prices) - 1``): nothing comes after it, so the episode
            # cannot go on, a terminal state as legacy learners treated it, not a time limit.
            end = traced.ends_of_data[0]
            decision.report(
                ret,
                "GM504",
                f"step returns terminated (the old done) and truncated=False: `{end.text}` ({end.place()}) is the end "
                f"of the env's data{_bound_text(decision, end)}, a terminal state, not a step limit",
                FixKind.ASSIST,
                tier=Tier.NOTE,
                question=("step-done", id(function), facts.segment(done)),
            )
            continue
        _report_truncated_false(
            decision, ret, limit_hint, plain if no_counter else None, ("step-done", id(function), facts.segment(done))
        )


def done_tracer(decision: ClassDecision) -> DoneTracer:
    """The class's done tracer, with the overrides other modules of the run define."""
    facts = decision.family.facts
    project = decision.family.receivers.project
    classdef = decision.classdef

    def external(name: str) -> list[DoneCause]:
        if project is None:
            return []
        found: list[DoneCause] = []
        for owner in (classdef, *local_subclasses(decision)):
            if facts.parent(owner) is facts.tree:
                found += project.done_overrides(owner.name, name)
        return found

    return facts.memo(("done-tracer-run", id(classdef)), lambda: DoneTracer(facts, classdef, external))


def _limits_text(traced: DoneCause) -> str:
    """```self.t > self.T` (line 12)``, one entry per limit text with every place it is at."""
    places: dict[str, list[Limit]] = {}
    for limit in traced.limits:
        places.setdefault(limit.text, []).append(limit)
    parts = []
    for text, limits in list(places.items())[:3]:
        shown = ", ".join(limit.place() for limit in limits[:4]) + (", ..." if len(limits) > 4 else "")
        parts.append(f"`{text}` ({shown})")
    return " and ".join(parts) + (" and others" if len(places) > 3 else "")


def _report_truncation(decision: ClassDecision, ret: ast.Return, done: ast.expr, traced: DoneCause) -> None:
    text = decision.family.facts.segment(done)
    if traced.elsewhere():
        decision.report(
            ret,
            "GM504",
            f"step returns terminated=False and truncated=`{text}`: every override in the run ends the episode only on "
            f"the step/time limit {_limits_text(traced)}, a truncation; check subclasses outside this run",
            FixKind.ASSIST,
        )
    elif not traced.plain():
        decision.report(
            ret,
            "GM504",
            f"step returns terminated=False and truncated=`{text}`: it is True only on {_limits_text(traced)}, a count "
            "step advances on every call compared with a bound (an episode length, a truncation); if reaching it is "
            "the task's goal, return it as terminated instead",
            FixKind.ASSIST,
        )
    else:
        decision.report(
            ret,
            "GM504",
            f"step returns terminated=False and truncated=`{text}`: it is True only on the step/time limit "
            f"{_limits_text(traced)}, a truncation",
            FixKind.ASSIST,
            tier=Tier.NOTE,
        )


def _blocked_hook(ret: ast.Return, blocked: dict[str, str]) -> tuple[str, str] | None:
    call = ret.value
    if isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute) and call.func.attr in blocked:
        return call.func.attr, blocked[call.func.attr]
    return None


def _report_truncated_false(
    decision: ClassDecision, ret: ast.Return, limit_hint: str | None, certain: str | None, question: Hashable | None = None
) -> None:
    """``question``: the same done returned again by the same step (``self.terminal`` in both
    branches) is one decision: asked once, the other returns point at it."""
    if certain is not None:
        decision.report(ret, "GM504", certain, FixKind.ASSIST, tier=Tier.NOTE)
    else:
        decision.report(ret, "GM504", truncated_false_message(limit_hint), FixKind.ASSIST, question=question)


def _data_ends(decision: ClassDecision) -> frozenset[str]:
    return data_end_attributes(decision.family.facts, decision.classdef)


def _bound_text(decision: ClassDecision, end: Limit) -> str:
    """`` (`self.max_step = len(prices) - 1`, line 8)``: where the attribute the test
    compares with is bound to the data's length; "" when the test spells the length."""
    facts = decision.family.facts
    data_ends = _data_ends(decision)
    for node in ast.walk(decision.classdef):
        if not (isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Attribute)):
            continue
        target = node.targets[0]
        if isinstance(target.value, ast.Name) and target.value.id == "self" and target.attr in data_ends:
            if re.search(rf"\bself\.{re.escape(target.attr)}\b", end.text):
                return f" (`{facts.segment(node)}`, line {node.lineno})"
    return ""


_UNPACKED_NAMES = ("obs", "reward", "terminated", "info")


def _unpacked_helper_names(decision: ClassDecision, function: Method, ret: ast.Return) -> tuple[str, ...] | None:
    """``return self._observe(...)`` alone on its line, where every return of ``_observe``
    (a method of the class) is a 4-tuple literal: the names step unpacks it into (free in
    ``function``), or None."""
    call = ret.value
    if not (
        isinstance(call, ast.Call)
        and isinstance(call.func, ast.Attribute)
        and isinstance(call.func.value, ast.Name)
        and call.func.value.id == "self"
    ):
        return None
    helper = decision.methods.get(call.func.attr)
    if helper is None or helper is function:
        return None
    values = [r.value for r in own_returns(helper) if r.value is not None]
    if not values or any(tuple_len(v) != 4 for v in values):
        return None
    facts = decision.family.facts
    if ret.end_lineno is None or not 0 < ret.lineno <= ret.end_lineno <= len(facts.lines):
        return None
    # ast's columns count UTF-8 bytes
    if facts.lines[ret.lineno - 1].encode()[: ret.col_offset].strip():
        return None  # ``if x: return self._observe()``: not a statement of its own line
    rest = facts.lines[ret.end_lineno - 1].encode()[ret.end_col_offset or 0 :].strip()
    if rest and not rest.startswith(b"#"):
        return None  # ``return self._observe(); ...``
    used = {n.id for n in ast.walk(function) if isinstance(n, ast.Name)}
    used |= {a.arg for a in ast.walk(function) if isinstance(a, ast.arg)}
    names = []
    for name in _UNPACKED_NAMES:
        while name in used:
            name += "_"
        names.append(name)
    return tuple(names)


def _returns_helper(ret: ast.Return, decision: ClassDecision, helpers: set[int]) -> bool:
    call = ret.value
    return (
        isinstance(call, ast.Call)
        and isinstance(call.func, ast.Attribute)
        and id(decision.methods.get(call.func.attr)) in helpers
    )


def _returns_five_from_helper(ret: ast.Return, decision: ClassDecision) -> bool:
    """``return self._advance(a)`` where ``_advance`` already returns five values."""
    call = ret.value
    if not (isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute) and isinstance(call.func.value, ast.Name) and call.func.value.id == "self"):
        return False
    helper = decision.methods.get(call.func.attr)
    return helper is not None and any(tuple_len(r.value) == 5 for r in own_returns(helper))


def _counts_toward_a_limit(decision: ClassDecision) -> bool:
    """The class counts something (``self.steps += 1``, ``self.rounds -= 1``, ``t = t + 1``,
    ``self.time += self.dt``) or tests a step limit anywhere: that may end episodes on a
    limit, so a person decides. Physics updates (``self.x += dx``) are not counts, nor is
    an attribute the class never reads (``self.steps += 1`` kept for statistics) or one it
    moves both ways (``self.index += 1`` and ``self.index = max(self.index - 1, 0)``: a
    position, not a count)."""
    facts = decision.family.facts

    def compute() -> bool:
        if decision.env.has_local_env_base(decision.classdef) or decision.env.has_run_env_base(decision.classdef):
            return True  # the base class (in this file, or another of the run) may count steps for it
        # A name moved by a constant both ways (``pos -= 1`` for one action, ``pos += 1``
        # for another) is a position, not a count: it cannot run up to a limit by itself.
        directions: dict[str, set[bool]] = {}
        for node in ast.walk(decision.classdef):
            if isinstance(node, ast.AugAssign) and isinstance(node.op, (ast.Add, ast.Sub)) and _is_number(node.value):
                up = isinstance(node.op, ast.Add) == (node.value.value >= 0)  # type: ignore[attr-defined]
                directions.setdefault(facts.segment(node.target), set()).add(up)
        for node in ast.walk(decision.classdef):
            if isinstance(node, ast.AugAssign) and isinstance(node.op, (ast.Add, ast.Sub)):
                counted = (
                    _is_number(node.value)
                    and not isinstance(node.target, ast.Subscript)
                    and len(directions.get(facts.segment(node.target), ())) < 2
                )
                if counted or any(STEP_LIMIT_WORD.search(w) for w in identifiers(node.target)):
                    if not _idle_attribute(decision, node.target):
                        return True  # `self.steps += 1`, `self.t += self.dt`; not `self.pos[1] += 1`
            if isinstance(node, ast.Compare) and is_step_limit(node, _data_ends(decision)):
                return True  # a step-limit test in a helper (`def _done(self): return self.t > 200`)
            if (
                isinstance(node, ast.Assign)
                and len(node.targets) == 1
                and isinstance(node.value, ast.BinOp)
                and isinstance(node.value.op, (ast.Add, ast.Sub))
                and _is_number(node.value.right)
                and facts.segment(node.value.left) == facts.segment(node.targets[0])
            ):
                return True  # `self.t = self.t + 1`
        return False

    return facts.memo(("counts-by-constant", id(decision.classdef)), compute)


def _idle_attribute(decision: ClassDecision, target: ast.expr) -> bool:
    """``self.<name>`` that cannot limit an episode: the module never reads it
    but to count it, or it also moves it the other way or back from its own value
    (a position). Only attributes of the class itself; anything else may count."""
    if not (isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self"):
        return False
    facts = decision.family.facts
    directions: set[type] = set()
    reads = 0
    classdef = decision.classdef
    for attr in facts.attributes.get(target.attr, ()):
        holder = facts.parent(attr)
        if isinstance(attr.ctx, ast.Load):
            if not _self_update(holder, target.attr):
                reads += 1  # a read anywhere in the module (``env.steps`` in a script) may limit
            continue
        if not classdef.lineno <= attr.lineno <= (classdef.end_lineno or attr.lineno):
            continue  # another class's writes of the same name (its position is not this count)
        if isinstance(holder, ast.AugAssign):
            directions.add(type(holder.op))
        elif isinstance(holder, ast.Assign) and any(
            isinstance(n, ast.Attribute) and n.attr == target.attr and isinstance(n.value, ast.Name) and n.value.id == "self"
            for n in ast.walk(holder.value)
        ) and not _self_update(holder.value, target.attr):
            return True  # ``self.index = max(self.index - 1, 0)``: moved back, a position
    if len(directions) > 1:
        return True  # ``+=`` and ``-=``: a position
    return reads == 0


def _self_update(value: ast.AST | None, name: str) -> bool:
    """``self.<name> + <number>`` (the right side of ``self.n = self.n + 1``)."""
    return (
        isinstance(value, ast.BinOp)
        and isinstance(value.op, (ast.Add, ast.Sub))
        and isinstance(value.left, ast.Attribute)
        and value.left.attr == name
        and _is_number(value.right)
    )


def _is_number(node: ast.AST) -> bool:
    return isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool)


def _step_limit_text(decision: ClassDecision, function: ast.AST) -> str | None:
    data_ends = _data_ends(decision)
    found = [c for s in function.body for c in ast.walk(s) if isinstance(c, ast.Compare) and is_step_limit(c, data_ends)]  # type: ignore[attr-defined]
    if not found:
        return None
    first = min(found, key=lambda c: (c.lineno, c.col_offset, -(c.end_lineno or 0), -(c.end_col_offset or 0)))
    return _parenthesized_text(decision, first).strip()


def _parenthesized_text(decision: ClassDecision, node: ast.expr) -> str:
    """The source of ``node`` with the grouping parentheses around it, as LibCST prints it."""
    facts = decision.family.facts
    text = facts.segment(node)
    line = facts.lines[node.lineno - 1] if node.lineno == node.end_lineno else ""
    if not line.isascii():
        return text
    start, end = node.col_offset, node.end_col_offset or node.col_offset
    parent = facts.parent(node)
    call_paren = -1
    if isinstance(parent, ast.Call) and parent.func.end_lineno == node.lineno:
        call_paren = line.find("(", parent.func.end_col_offset or 0)
    while True:
        before = line[:start].rstrip()
        after = line[end:].lstrip()
        if not (before.endswith("(") and after.startswith(")")) or len(before) - 1 == call_paren:
            return text
        start = len(before) - 1
        end = len(line) - len(after) + 1
        text = line[start:end]


def _or_operands(expr: ast.AST) -> list[ast.AST]:
    if isinstance(expr, ast.BoolOp) and isinstance(expr.op, ast.Or):
        return [operand for value in expr.values for operand in _or_operands(value)]
    return [expr]


def _split_question(expr: ast.AST) -> Hashable:
    """The split of one done expression: the same wherever a class of the file (a twin
    subclass's own step) splits the same expression, so the file asks it once."""
    return ("GM504", "split", ast.dump(unwrap_bool(expr)))


def _accumulated_limit(function: ast.AST, ret: ast.Return, name: str, data_ends: frozenset[str]) -> ast.Assign | None:
    """``name = name or <step limit> [or ...]`` as the statement right before ``ret``, the
    function's last statement and only return, where every other binding of ``name`` is a
    plain assignment before it that tests no step limit: that line; else None."""
    body = getattr(function, "body", [])
    if len(body) < 3 or body[-1] is not ret or len(own_returns(function)) != 1:
        return None
    last = body[-2]
    if not (isinstance(last, ast.Assign) and len(last.targets) == 1 and isinstance(last.targets[0], ast.Name) and last.targets[0].id == name):
        return None
    value = unwrap_bool(last.value)
    if not (isinstance(value, ast.BoolOp) and isinstance(value.op, ast.Or)):
        return None
    own = [v for v in value.values if isinstance(v, ast.Name) and v.id == name]
    limits = [v for v in value.values if not (isinstance(v, ast.Name) and v.id == name)]
    if len(own) != 1 or not limits or not all(is_step_limit(v, data_ends) for v in limits):
        return None
    names = [n for n in ast.walk(function) if isinstance(n, ast.Name)]
    if any(n.id in ("terminated", "truncated") for n in names):
        return None
    done = ret.value.elts[2]
    if any(n.id == name and n is not done for n in ast.walk(ret.value) if isinstance(n, ast.Name)):
        return None  # ``float(done)`` as the reward: it reads the flag with the limit in it
    stores = [n for n in names if n.id == name and not isinstance(n.ctx, ast.Load)]
    for store in stores:
        if store is last.targets[0]:
            continue
        statement = next((s for s in ast.walk(function) if isinstance(s, ast.Assign) and store in s.targets), None)
        if statement is None or statement.lineno >= last.lineno:
            return None
        if any(isinstance(n, ast.Compare) and is_step_limit(n, data_ends) for n in ast.walk(statement.value)):
            return None
    return last if len(stores) > 1 else None


def _flagged_limit(function: ast.AST, name: str, data_ends: frozenset[str]) -> ast.If | None:
    """The one ``if <step limit>: name = True`` of a step whose ``name`` is a flag: set
    ``False`` once by a statement of the body, then ``True`` only by that ``if`` (a statement of
    the body after it, with no ``else``) and by ``if``s that test no step limit; read only as
    the done of returns that all come after that ``if``. Then ``truncated = bool(<limit>)`` in
    its place and the flag as terminated is legacy ``done`` split exactly. Else None."""
    body = getattr(function, "body", None)
    returns = own_returns(function)
    if not body or not returns:
        return None
    done_slots = set()
    for ret in returns:
        if not (isinstance(ret.value, ast.Tuple) and len(ret.value.elts) == 4):
            return None
        slot = ret.value.elts[2]
        if not (isinstance(slot, ast.Name) and slot.id == name):
            return None
        done_slots.add(id(slot))
    stores: list[ast.Assign] = []
    for node in ast.walk(function):
        if isinstance(node, (ast.Global, ast.Nonlocal)) and name in node.names:
            return None
        if isinstance(node, ast.Name) and node.id in ("terminated", "truncated"):
            return None
        if isinstance(node, ast.Name) and node.id == name:
            if isinstance(node.ctx, ast.Load):
                if id(node) not in done_slots:
                    return None  # read as something else (``float(done)``): it would lose the limit
                continue
            statement = _statement_of(function, node)
            if not (
                isinstance(statement, ast.Assign)
                and statement.targets == [node]
                and isinstance(statement.value, ast.Constant)
                and isinstance(statement.value.value, bool)
            ):
                return None
            stores.append(statement)
    falses = [s for s in stores if s.value.value is False]  # type: ignore[attr-defined]
    if len(falses) != 1 or falses[0] not in body:
        return None
    limits = [
        s
        for s in body
        if isinstance(s, ast.If) and not s.orelse and len(s.body) == 1 and s.body[0] in stores and is_step_limit(s.test, data_ends)
    ]
    if len(limits) != 1 or body.index(limits[0]) < body.index(falses[0]):
        return None
    limit = limits[0]
    for store in stores:
        if store is falses[0] or store is limit.body[0]:
            continue
        parent = next((n for n in ast.walk(function) if isinstance(n, ast.If) and (store in n.body or store in n.orelse)), None)
        if parent is None or any(isinstance(n, ast.Compare) and is_step_limit(n, data_ends) for n in ast.walk(parent.test)):
            return None
    if any(ret.lineno <= (limit.end_lineno or limit.lineno) for ret in returns):
        return None
    return limit


def _statement_of(function: ast.AST, target: ast.Name) -> ast.AST | None:
    return next((s for s in ast.walk(function) if isinstance(s, ast.Assign) and target in s.targets), None)


def _split_tier(traced: DoneCause, split: ast.AST, data_ends: frozenset[str]) -> Tier | None:
    """A split whose limits are all named as step limits in this module, with no override
    elsewhere in the run, and compared with a bound the env holds rather than a literal, is
    settled (``self.current_step >= self.ep_length``): a note, as for a done that is only such
    a limit (``_report_truncation``). ``self.t >= 2`` may be the game's own length: asked."""
    limits = [op for op in _or_operands(unwrap_bool(split)) if is_step_limit(op, data_ends)]
    literal = any(
        isinstance(side, ast.Constant) for op in limits if isinstance(op, ast.Compare) for side in (op.left, *op.comparators)
    )
    return Tier.NOTE if traced.limits and traced.plain() and not literal else None


def _split_done(expr: ast.AST, data_ends: frozenset[str] = frozenset()) -> bool:
    """``bool(task or self.steps >= self.max_steps)`` has a clear step-limit test."""
    return any(is_step_limit(op, data_ends) for op in _or_operands(unwrap_bool(expr)))


def _task_ends(decision: ClassDecision, index: FunctionIndex, name: str) -> list[ast.Assign]:
    """The ``name = True`` lines in one branch of an ``if`` whose test is no step limit and
    whose other branch leaves ``name`` as it was (``else: reward = -100; done = True``: the
    agent died), when every assignment of ``name`` but one is such a line; else nothing."""
    assigns = [
        a
        for a in index.of(ast.Assign)
        if len(a.targets) == 1 and isinstance(a.targets[0], ast.Name) and a.targets[0].id == name  # type: ignore[attr-defined]
    ]
    ends = []
    for assign in assigns:
        parent = if_setting_true(assign, decision.family.facts.parent(assign))
        if (
            parent is not None
            and not _assigns_in(parent.orelse if assign in parent.body else parent.body, name)
            and not any(isinstance(n, ast.Compare) and is_step_limit(n, _data_ends(decision)) for n in ast.walk(parent.test))
        ):
            ends.append(assign)
    return ends  # type: ignore[return-value]


def _assigns_in(statements: list[ast.stmt], name: str) -> bool:
    """A branch binds ``name`` (``if solved: done = True`` / ``else: done = False``): the
    ``if`` decides done both ways, which is no end of the task added to the step's."""
    return any(
        isinstance(node, ast.Name) and node.id == name and isinstance(node.ctx, ast.Store)
        for statement in statements
        for node in ast.walk(statement)
    )


def _unpacked_from_inner_step(decision: ClassDecision, index: FunctionIndex, name: str, besides: frozenset[int] = frozenset()) -> bool:
    """``name`` is bound once, as the done of ``obs, r, done, info = <step>`` where the step is
    an inner Gym env's (``self.env.step(a)``, or ``res = self.env.step(a)`` unpacked) or the
    base class's migrated one (``super().step(a)``): the step family unpacks five values there,
    as ``terminated``/``truncated`` (names the function must not use already)."""
    if any(isinstance(n, ast.Name) and n.id in ("terminated", "truncated") for n in index.of(ast.Name)):
        return False
    selection = decision.family.context.options.selection
    if selection is not None and not selection.allows("GM301"):
        return False  # the unpack stays a legacy one: so does this return's done
    value = _done_unpacked_from(index, name, besides)
    if value is None:
        return False
    if is_super_method_call(value, "step"):
        # five values after the run, and the step family unpacks them: both, or the return
        # would name flags the unpack never binds
        return decision.env.base_step_migrates(decision.classdef) is True and _step_family_unpacks_super(decision, value)
    return inner_gym_env_call(decision, value, "step")


def _unknown_base_text(decision: ClassDecision, base: str) -> str:
    if decision.env.base_step_migrates(decision.classdef):
        return f"the step family cannot tell that `{base}` is a Gym env"  # it leaves the unpack as it is
    return f"`{base}` is no env class this run holds"


def _step_family_unpacks_super(decision: ClassDecision, call: ast.expr) -> bool:
    """The step family takes ``super().step(a)`` here for a Gym env's (``super_kind``), so it
    unpacks five values: the same fact the two halves of the step body must share."""
    kind = decision.env.receivers.super_kind(call.func.value)  # type: ignore[attr-defined]
    return kind is not None and kind.is_gym


def _done_unpacked_from(index: FunctionIndex, name: str, besides: frozenset[int] = frozenset()) -> ast.expr | None:
    """What ``name`` is unpacked from as the done of ``obs, r, name, info = <value>``, its
    one binding but ``besides`` (``res = x.step(a)`` followed to the call); else None."""
    binders = [
        a
        for a in index.of(ast.Assign)
        for t in a.targets  # type: ignore[attr-defined]
        if isinstance(t, ast.Name) and t.id == name
        or isinstance(t, (ast.Tuple, ast.List)) and any(isinstance(e, ast.Name) and e.id == name for e in t.elts)
    ]
    binders = [a for a in binders if id(a) not in besides]  # the class's own task ends, judged by the caller
    others = [n for n in index.of(ast.AugAssign, ast.AnnAssign, ast.For) if isinstance(n.target, ast.Name) and n.target.id == name]  # type: ignore[attr-defined]
    if len(binders) != 1 or others:
        return None
    unpack = binders[0]
    target = unpack.targets[0] if len(unpack.targets) == 1 else None  # type: ignore[attr-defined]
    flags = unpack.value  # type: ignore[attr-defined]
    if isinstance(target, ast.Name) and isinstance(flags, ast.BoolOp) and isinstance(flags.op, ast.Or) and len(flags.values) == 2:
        # ``done = terminated or truncated`` after a five-name unpack (GM301's, seen again
        # when the run verifies its own output): the same done, from the same call.
        pair = [v.id for v in flags.values if isinstance(v, ast.Name)]
        unpacks = [
            a
            for a in index.of(ast.Assign)
            if len(a.targets) == 1  # type: ignore[attr-defined]
            and isinstance(a.targets[0], (ast.Tuple, ast.List))  # type: ignore[attr-defined]
            and len(a.targets[0].elts) == 5  # type: ignore[attr-defined]
            and [e.id if isinstance(e, ast.Name) else None for e in a.targets[0].elts[2:4]] == pair  # type: ignore[attr-defined]
        ]
        return unpacks[0].value if len(unpacks) == 1 else None  # type: ignore[attr-defined]
    if not (
        isinstance(target, (ast.Tuple, ast.List))
        and len(target.elts) == 4
        and isinstance(target.elts[2], ast.Name)
        and target.elts[2].id == name
    ):
        return None
    value = unpack.value  # type: ignore[attr-defined]
    if isinstance(value, ast.Name):  # ``res = self.env.step(a)`` then ``... = res``
        stores = [a for a in index.of(ast.Assign) if any(isinstance(t, ast.Name) and t.id == value.id for t in a.targets)]  # type: ignore[attr-defined]
        if len(stores) != 1:
            return None
        value = stores[0].value  # type: ignore[attr-defined]
    return value


def _from_unknown_base_step(decision: ClassDecision, index: FunctionIndex, name: str) -> str | None:
    """``name`` is the done of ``super().step(a)`` (or that done with the class's own task
    ends) where the run does not show what the first base's step returns once migrated:
    that base's text, else None."""
    ends = frozenset(id(e) for e in _task_ends(decision, index, name))
    value = _done_unpacked_from(index, name, ends)
    if value is None or not is_super_method_call(value, "step"):
        return None
    if decision.env.base_step_migrates(decision.classdef) and _step_family_unpacks_super(decision, value):
        return None
    bases = [b for b in decision.classdef.bases if not (isinstance(b, ast.Name) and b.id == "object")]
    return decision.family.facts.segment(bases[0]) if bases else None


def _single_assignment(index: FunctionIndex, name: str) -> ast.AST | None:
    assigns = [
        a for a in index.of(ast.Assign) if len(a.targets) == 1 and isinstance(a.targets[0], ast.Name) and a.targets[0].id == name  # type: ignore[attr-defined]
    ]
    others = [
        n
        for n in index.of(ast.AugAssign, ast.AnnAssign, ast.For)
        if isinstance(n.target, ast.Name) and n.target.id == name  # type: ignore[attr-defined]
    ]
    in_tuple = any(
        isinstance(t, ast.Tuple) and any(isinstance(e, ast.Name) and e.id == name for e in t.elts)
        for a in index.of(ast.Assign)
        for t in a.targets  # type: ignore[attr-defined]
    )
    if len(assigns) != 1 or others or in_tuple:
        return None
    return assigns[0].value  # type: ignore[attr-defined]
