"""GM504: ``step`` returns ``(obs, reward, terminated, truncated, info)``.

A step limit the env counts itself (``self.steps >= self.max_steps`` in the done test)
becomes ``truncated``; everything else ``terminated``. Returns that are not a 4-tuple
literal are reported. The old migration guide: "replacing ``done`` with ``terminated``
and ``truncated=False`` in step should address most issues".

This module decides each return and words its findings; where a done holds a step limit
(and the shapes the rewrite splits exactly) is ``step_limits``; a step whose returns or
done come from another step (a helper, an inner env's, the base class's) is
``step_delegates``.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Hashable

from gymmigrate.facts.class_shapes import is_batched_step_return, keeps_legacy_step
from gymmigrate.facts.done_causes import Cause, DoneCause, Limit
from gymmigrate.facts.env_classes import (
    is_self_attribute,
    is_super_method_call,
)
from gymmigrate.facts.limit_tests import (
    elapsed_since_step_mark,
    is_end_of_data,
    is_step_limit,
    unwrap_bool,
)
from gymmigrate.facts.limits import DoneTracer
from gymmigrate.facts.module import ModuleFacts, own_returns, walk
from gymmigrate.facts.own_steps import hands_on_base_step, helper_step
from gymmigrate.facts.step_hooks import ENV_API
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.custom_env.common import (
    ClassDecision,
    Method,
    delegates,
    inner_gym_env_call,
    is_self_call,
    method_of,
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
    batched_step_message,
    truncated_false_message,
)
from gymmigrate.rules.custom_env.step_delegates import (
    from_unknown_base_step,
    returns_five_from_helper,
    returns_helper,
    single_assignment,
    task_ends,
    unknown_base_text,
    unpacked_from_foreign_step,
    unpacked_from_inner_step,
    unpacked_helper_names,
)
from gymmigrate.rules.custom_env.step_limits import (
    accumulated_limit,
    class_data_ends,
    class_streaks,
    counts_toward_a_limit,
    flagged_limit,
    split_done,
    split_question,
    split_tier,
    step_limit_text,
)
from gymmigrate.rules.custom_env.step_per_agent import (
    per_agent_split,
    reads_parallel_dones,
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
    if helper_step(decision.family.facts, decision.family.receivers, decision.classdef) and not decision.plan.reset_kept:
        # Its overrides return the step's values themselves: five fields here would reach
        # them as their observation. An explanation, nothing to decide. (A reset the class
        # keeps on its own return is still asked about below: its subclasses' resets need it.)
        local, elsewhere = overrides(decision, "step")
        count = len(local) + len(elsewhere)
        shown = f" ({count} in the run)" if count > 1 else ""
        decision.report(
            function,
            "GM504",
            f"`{decision.classdef.name}.step` returns one value (the observation, or a flag), no step result: a helper, "
            "not a Gym step; every override"
            f"{shown} returns the step's values itself (five once migrated), building on it with `super().step(...)`, "
            "so it keeps its return",
            FixKind.FLAG,
            tier=Tier.NOTE,
        )
        return
    # The class's tests of the end of its data and of a run of consecutive steps, as text, for
    # the rewrite's own split (``cst_edits._split_done``): they stay in terminated, whatever
    # their names say.
    facts = decision.family.facts
    data_ends, streaks = class_data_ends(decision), class_streaks(decision)
    decision.plan.non_limit_tests = frozenset(
        "".join(facts.segment(node).split())
        for node in walk(decision.classdef)
        if isinstance(node, ast.Compare)
        and (
            is_end_of_data(node, data_ends)
            or (is_step_limit(node, data_ends) and not is_step_limit(node, data_ends, streaks))
            or (is_step_limit(node, data_ends) and elapsed_since_step_mark(facts, node))
        )
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
    absent = _absent_hooks(decision, function)
    for name in absent:
        # ``def step(self, *a, **k): return self._step(*a, **k)`` in a class of gym.Env
        # alone that does not define ``_step``: only its subclasses do, so the step is
        # what they return. Settled when every override in the run follows (plain ones);
        # with none in the run, whoever defines it elsewhere must return five values.
        local, elsewhere = overrides(decision, name)
        followed = not elsewhere or (
            project is not None
            and project.hook_followed_elsewhere(decision.classdef.name, name)
            and len(elsewhere) == len(project.overridden_elsewhere(decision.classdef.name, name))
        )
        if not followed or not all(step_override_migratable(m) for _, m in local):
            blocked[name] = where(decision, local, elsewhere)
            continue
        for subclass, _ in local:
            inherited.setdefault(id(subclass), []).append(name)
    for ret in own_returns(function):
        call = ret.value
        if isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute) and call.func.attr in absent and call.func.attr not in blocked:
            local, elsewhere = overrides(decision, call.func.attr)
            if local and not elsewhere and all(_returns_five(m) for _, m in local):
                continue  # every override already returns five values: nothing changes, nothing to say
            if local or elsewhere:
                decision.report(
                    ret,
                    "GM504",
                    f"step returns self.{call.func.attr}(...), which this class does not define: its overrides in the run "
                    f"({where(decision, local, elsewhere)}) return (obs, reward, terminated, truncated, info) with it",
                    FixKind.ASSIST,
                    Tier.NOTE,
                )
            else:
                decision.report(
                    ret,
                    "GM504",
                    f"step returns self.{call.func.attr}(...), which no class of this run defines: a subclass elsewhere "
                    "that defines it must return (obs, reward, terminated, truncated, info)",
                    FixKind.FLAG,
                )
    for step_function in (function, *helpers):
        _decide_returns(decision, step_function, {id(h) for h in helpers}, blocked, absent)


def _absent_hooks(decision: ClassDecision, function: Method) -> set[str]:
    """``return self.<hook>(...)`` in the step, for a hook the class does not define, nor its
    one base (gym.Env itself), and that no other method of the class calls."""
    if len(decision.classdef.bases) != 1 or not decision.env.extends_gym_env_directly(decision.classdef):
        return set()
    found = set()
    for ret in own_returns(function):
        call = ret.value
        if not (isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute)):
            continue
        if not (isinstance(call.func.value, ast.Name) and call.func.value.id == "self"):
            continue
        name = call.func.attr
        if name in decision.methods or name in ENV_API or name in decision.renamed.values():
            continue
        callers = decision.index.self_calls.get(name, ())
        if all(method_of(decision, c) is function for c in callers):
            found.add(name)
    return found


def _decide_none_info(decision: ClassDecision, function: Method, ret: ast.Return) -> None:
    """``info = None`` ... ``return obs, reward, done, info``: gym let the info be None, but
    Gymnasium's env checker (which make puts around every env) asserts a dict. Where every
    binding of that local is ``= None`` and it is read only as a returned info, the
    bindings become ``{}``; where other code reads (or tests) it too, a person decides."""
    info = ret.value.elts[3]  # type: ignore[union-attr]
    if not isinstance(info, ast.Name):
        return
    bindings = _none_info_bindings(function, info.id)
    if bindings is None:
        return
    names = decision.plan.none_infos.setdefault(function.name, set())
    asked = decision.plan.none_infos_asked
    if info.id in names or (function.name, info.id) in asked:
        return  # one finding per local, however many returns hand it on
    if bindings[0]:
        names.add(info.id)
        decision.report(
            bindings[1][0],
            "GM504",
            f"`{info.id} = None` -> `{info.id} = {{}}`: it is step's info, which Gymnasium's env checker (put around "
            "the env by make) asserts is a dict",
            FixKind.AUTO,
        )
        return
    asked.add((function.name, info.id))
    decision.report(
        bindings[1][0],
        "GM504",
        f"`{info.id}` is returned as step's info and is None here, but other code reads it too: Gymnasium's env checker (put around the env "
        "by make) asserts a dict; return `{}` where it is None",
        FixKind.FLAG,
    )


_SCOPES = (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)


def _walk_own(function: Method) -> list[ast.AST]:
    """The nodes of ``function``'s own scope: a nested def, lambda or class is listed, its
    inside is not (its names are another scope's)."""
    found: list[ast.AST] = []
    stack: list[ast.AST] = [*function.body]
    while stack:
        node = stack.pop()
        found.append(node)
        if not isinstance(node, _SCOPES):
            stack.extend(ast.iter_child_nodes(node))
    return found


def _none_info_bindings(function: Method, name: str) -> tuple[bool, list[ast.Assign]] | None:
    """The ``name = None`` statements of ``function`` and whether rewriting them is certain:
    every binding of the local is one, no nested scope names it, and every read is the
    info of a returned 4-tuple (no ``is None`` test, no copy elsewhere). None when no
    binding is ``= None``, or another binding may replace it."""
    nones: list[ast.Assign] = []
    certain = not any(isinstance(a, ast.arg) and a.arg == name for a in ast.walk(function.args))
    for node in _walk_own(function):
        if isinstance(node, (ast.Global, ast.Nonlocal)) and name in node.names:
            certain = False
        elif isinstance(node, _SCOPES):
            if any(isinstance(n, ast.Name) and n.id == name for n in ast.walk(node)):
                certain = False
        elif isinstance(node, ast.Assign) and isinstance(node.value, ast.Constant) and node.value.value is None:
            if any(isinstance(t, ast.Name) and t.id == name for t in node.targets):
                nones.append(node)
                if len(node.targets) != 1:
                    certain = False
    if not nones:
        return None
    own = {id(n) for assign in nones for n in assign.targets}
    returned = {
        id(r.value.elts[3])  # type: ignore[union-attr]
        for r in own_returns(function)
        if tuple_len(r.value) == 4
    }
    for node in _walk_own(function):
        if isinstance(node, ast.Name) and node.id == name:
            if isinstance(node.ctx, ast.Load):
                certain = certain and id(node) in returned
            elif id(node) not in own:
                # another binding (``info = {}`` on some path, a loop target, del): whether
                # None reaches the return is the flow's question, not asked here
                return None
        elif isinstance(node, (ast.alias, ast.ExceptHandler, ast.MatchAs, ast.MatchStar)) and name in (
            getattr(node, "asname", None) or getattr(node, "name", None) or "",
        ):
            certain = False
    return certain, nones


def _never_set(assigned: ast.AST | None) -> bool:
    """The one value a flag is given in the step is the literal ``False``."""
    return isinstance(assigned, ast.Constant) and assigned.value is False


def _returns_five(method: Method) -> bool:
    returns = [r for r in own_returns(method) if r.value is not None]
    return bool(returns) and all(tuple_len(r.value) == 5 for r in returns)


def _decide_returns(
    decision: ClassDecision, function: Method, helpers: set[int], blocked: dict[str, str] | None = None, absent: frozenset[str] | set[str] = frozenset()
) -> None:
    returns = own_returns(function)
    if any(tuple_len(r.value) == 5 or returns_five_from_helper(r, decision) for r in returns):
        return  # already the five-value API
    index = decision.function(function)
    limit_hint = step_limit_text(decision, function)
    data_ends, streaks = class_data_ends(decision), class_streaks(decision)
    facts = decision.family.facts
    # No step limit is possible when the class counts nothing: truncated=False is then
    # exact (TimeLimit truncates), an explanation rather than a question.
    no_counter = limit_hint is None and not counts_toward_a_limit(decision)
    plain = (
        "step returns terminated (the old done) and truncated=False: the class counts nothing that could end "
        "an episode on a limit, so truncation is left to TimeLimit (max_episode_steps)"
    )
    tracer = done_tracer(decision)
    for position, ret in enumerate(returns):
        if ret.value is None:
            continue
        if returns_helper(ret, decision, helpers) or is_super_method_call(ret.value, function.name):
            continue  # the helper's (or the base's own hook's) returns carry the contract
        if function.name == "step" and isinstance(ret.value, ast.Name) and hands_on_base_step(ret.value, decision.classdef, function):
            continue  # ``results = super().step(a)`` ... ``return results``: the base's step, handed on
        if is_self_call(ret.value, set(absent) - set(blocked or {})):
            continue  # a hook only subclasses define: reported in decide_step
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
        names = unpacked_helper_names(decision, function, ret)
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
        base = from_unknown_base_step(decision, index, done.id) if isinstance(done, ast.Name) else None
        if base is not None:
            # ``done, False`` would be right only if the base's step kept four values, and
            # ``bool(done) and not truncated, truncated`` only if it returns five: the run
            # cannot tell which, so the return stays and a person decides.
            decision.plan.kept_returns.setdefault(function.name, set()).add(position)
            decision.report(
                ret,
                "GM504",
                f"step returns the done of {base.call}, and {unknown_base_text(decision, base)}: if its step "
                f"returns Gymnasium's five values, return `bool({done.id}) and not truncated, truncated` (its "
                "truncation stays one); if it keeps four, keep this step's unpack and return as they were; not rewritten",
                FixKind.FLAG,
            )
            continue
        decision.plan.step = True
        _decide_none_info(decision, function, ret)
        if isinstance(done, ast.Name) and index.assigns_name(done.id):
            assigned = single_assignment(index, done.id)
            if assigned is not None and split_done(assigned, data_ends, streaks, facts):
                decision.report(
                    ret,
                    "GM504",
                    f"`{done.id}` split: the step-limit test became truncated, the rest terminated",
                    FixKind.ASSIST,
                    tier=split_tier(tracer.trace(done)),
                    question=split_question(assigned),
                )
                continue
        elif split_done(done, data_ends, streaks, facts):
            decision.report(
                ret,
                "GM504",
                "done split: the step-limit test became truncated, the rest terminated",
                FixKind.ASSIST,
                tier=split_tier(tracer.trace(done)),
                question=split_question(done),
            )
            continue
        if isinstance(done, ast.Constant) and done.value is False:
            # This return never ends an episode, on a limit or otherwise: nothing to split.
            decision.report(ret, "GM504", "step returns terminated=False and truncated=False, as its done was False", FixKind.ASSIST, tier=Tier.NOTE)
            continue
        if isinstance(done, ast.Name) and _never_set(single_assignment(index, done.id)):
            # ``done = False`` is the step's only write of the flag: the return is as final as
            # the literal one above, so there is no end of any kind to ask about.
            decision.report(
                ret, "GM504", f"step returns terminated=False and truncated=False, as its `{done.id}` is only ever False", FixKind.ASSIST, tier=Tier.NOTE
            )
            continue
        if isinstance(done, ast.Name) and unpacked_from_inner_step(decision, index, done.id):
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
        if isinstance(done, ast.Name) and (foreign := unpacked_from_foreign_step(decision, index, done.id)) is not None:
            # The step it unpacks is left as it is (its own API, reported there): its done is
            # all this step knows, so it is terminated, as it was for the legacy learner.
            decision.plan.foreign_returns.setdefault(function.name, set()).add(position)
            decision.report(
                ret,
                "GM504",
                f"step returns `{done.id}` as terminated with truncated=False: it comes from "
                f"`{facts.segment(foreign.func)}(...)` (line {foreign.lineno}), which is no Gym step and is left as "
                "it is; split it with the port of that env",
                FixKind.ASSIST,
                tier=Tier.NOTE,
            )
            continue
        if (split := per_agent_split(decision, index, done)) is not None:
            # ``flags = np.stack([done["a"], done["b"]])`` of a PettingZoo parallel step: built
            # from its terminations and from its truncations, so its cut stays a truncation.
            decision.plan.per_agent_returns.setdefault(function.name, {})[position] = split
            decision.report(
                ret,
                "GM504",
                f"step returns `{facts.segment(done)}` built from the per-agent terminations as terminated and from the per-agent "
                "truncations as truncated (the PettingZoo parallel step it calls splits its dones): a cut on the "
                "parallel env's own limit stays a truncation",
                FixKind.ASSIST,
                tier=Tier.NOTE,
            )
            continue
        if reads_parallel_dones(decision, index, done):
            # ``all(...)``, ``and`` of the agents' flags: no agent keeps its own place, so the
            # two dicts give no terminated and truncated of the same shape; the parallel env
            # may cut the episode (``max_cycles``), so no note may say nothing limits it.
            decision.report(
                ret,
                "GM504",
                f"step returns `{facts.segment(done)}` as terminated with truncated=False, but it combines the per-agent dones of "
                "a PettingZoo parallel step, which now come as terminations and truncations (the parallel env's own "
                "cut, such as max_cycles, is a truncation): build terminated from the terminations and truncated from "
                "the truncations by hand",
                FixKind.ASSIST,
                question=("step-done", id(function), facts.segment(done)),
            )
            continue
        if isinstance(done, ast.Name) and (ends := task_ends(decision, index, done.id)) and unpacked_from_inner_step(
            decision, index, done.id, frozenset(id(e) for e in ends)
        ):
            # ``obs, r, done, info = super().step(a)`` then ``if solved: done = True``: the
            # class's own end is a terminal state, on the step the base truncates too; the
            # step it calls keeps its truncation.
            decision.plan.task_end_returns.setdefault(function.name, set()).add(position)
            lines = ", ".join(str(end.lineno) for end in ends)
            decision.report(
                ret,
                "GM504",
                f"step returns the terminated and truncated of the step it calls, and its own ends of the task "
                f"(`{facts.segment(ends[0])}`, line{'s' if len(ends) > 1 else ''} {lines}) set terminated instead of `{done.id}`",
                FixKind.ASSIST,
                tier=Tier.NOTE,
            )
            continue
        if isinstance(done, ast.Name) and (limit := accumulated_limit(function, ret, done.id, data_ends, streaks, facts)) is not None:
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
        if isinstance(done, ast.Name) and (flag := flagged_limit(function, done.id, data_ends, streaks, facts)) is not None:
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
                tier=split_tier(tracer.trace(done)),
                question=split_question(flag.test),
            )
            continue
        traced = tracer.trace(done)
        if traced.cause is Cause.TRUNCATION:
            decision.plan.truncating_returns.setdefault(function.name, set()).add(position)
            _report_truncation(decision, ret, done, traced, function)
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
                else "it holds more than one flag (per-agent flags in a dict, tuple or list) or a value not every way to "
                "which could be followed"
            )
            decision.report(
                ret,
                "GM504",
                f"step returns `{decision.family.facts.segment(done)}` as terminated with truncated=False, but "
                f"{_limits_text(traced)} is a step/time limit among its causes: return that end as truncated, not "
                f"terminated; {what}",
                FixKind.ASSIST,
                # every return of the step ending on the same limits is one split of that
                # step's done, decided once, not once per return statement
                question=("step-limit", id(function), _limits_text(traced), what),
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
        if traced.held and no_counter:
            # The class counts nothing, but the flag is read off an object it holds, which
            # ends episodes by its own rules (step or time limits among them, unseen here):
            # "nothing counts a limit" would not be true, so the split is asked.
            reads = ", ".join(f"`{read.text}` ({read.place()})" for read in traced.held)
            decision.report(
                ret,
                "GM504",
                f"step returns `{facts.segment(done)}` as terminated with truncated=False, but it is read off an "
                f"object the env holds ({reads}), which decides the end by its own rules: if that object ends "
                "episodes on a step or time limit of its own, return that end as truncated, not terminated",
                FixKind.ASSIST,
                question=("step-done", id(function), facts.segment(done)),
            )
            continue
        status = _simulator_status_end(decision, function, done) if limit_hint is None else None
        if status is not None:
            decision.report(
                ret,
                "GM504",
                f"step returns `{facts.segment(done)}` as terminated with truncated=False, but it ends the episode on "
                f"{status}: whatever this class counts, the simulator decides, and an end on its own time or step "
                "limit (one it applies itself or one this class configures) is a truncation: return that status as "
                "truncated, not terminated",
                FixKind.ASSIST,
                question=("step-done", id(function), facts.segment(done)),
            )
            continue
        _report_truncated_false(
            decision, ret, limit_hint, plain if no_counter else None, ("step-done", id(function), facts.segment(done))
        )


# Modules whose upper-case constants are no simulator's statuses.
_NOT_A_SIMULATOR = frozenset({"gym", "gymnasium", "numpy", "math", "sys", "os"})
# A status named as a time-out, one a simulator ends an episode on when its clock runs out.
_TIME_OUT_STATUS = re.compile(r"TIME_?OUT|OUT_OF_TIME|TIME_?LIMIT|TIME_?UP|TRUNCAT|EXPIRED", re.IGNORECASE)


def _simulator_status_end(decision: ClassDecision, function: Method, done: ast.expr) -> str | None:
    """The statuses of a library outside Gym the done is compared with (``status !=
    hfo.IN_GAME``, ``status in (sim.GOAL, sim.OUT_OF_TIME)``), as words for the item, where
    they may hold a limit: a test that ends on every status but the ones it names (the rest
    are the simulator's, unseen here), or one naming a time-out among its statuses. None
    for a done the class computes itself, or one that names only its task's ends."""
    facts = decision.family.facts
    sources: list[ast.AST] = [done]
    if isinstance(done, ast.Name) or is_self_attribute(done):
        text = facts.segment(done)
        sources += [
            node.value
            for node in walk(function)
            if isinstance(node, ast.Assign) and len(node.targets) == 1 and facts.segment(node.targets[0]) == text
        ]
    for source in sources:
        for node in walk(source):
            if not isinstance(node, ast.Compare):
                continue
            if not all(isinstance(op, (ast.Eq, ast.NotEq, ast.In, ast.NotIn, ast.Is, ast.IsNot)) for op in node.ops):
                continue
            constants = [c for operand in (node.left, *node.comparators) for c in _foreign_constants(facts, operand)]
            if not constants:
                continue
            named = ", ".join(f"`{facts.segment(c)}`" for c in constants)
            if any(isinstance(op, (ast.NotEq, ast.NotIn, ast.IsNot)) for op in node.ops):
                return f"every status of the simulator other than {named} (`{facts.segment(node)}`), statuses this code never names"
            timed = [c for c in constants if _TIME_OUT_STATUS.search(c.attr)]
            if timed:
                return f"the simulator's `{facts.segment(timed[0])}` (`{facts.segment(node)}`), a time-out by its name"
    return None


def _foreign_constants(facts: ModuleFacts, operand: ast.expr) -> list[ast.Attribute]:
    """``hfo_py.IN_GAME`` (alone, or in a tuple, list or set): upper-case constants read
    through an imported module other than Gym's, NumPy's and a few standard ones
    (``_NOT_A_SIMULATOR``). The project's own modules are not told apart: a constants module
    of the project imported by an absolute name counts as a simulator's too."""
    items = operand.elts if isinstance(operand, (ast.Tuple, ast.List, ast.Set)) else [operand]
    found = []
    for item in items:
        if not (isinstance(item, ast.Attribute) and item.attr.isupper()):
            continue
        roots = {name.split(".", 1)[0] for name in facts.qualified_names(item.value)}
        if roots and all(root and root not in _NOT_A_SIMULATOR for root in roots):
            found.append(item)
    return found


def done_tracer(decision: ClassDecision) -> DoneTracer:
    """The class's done tracer, with the overrides other modules of the run define."""
    facts = decision.family.facts
    project = decision.family.receivers.project
    classdef = decision.classdef

    def external(name: str, index: int | None) -> list[DoneCause]:
        if project is None:
            return []
        found: list[DoneCause] = []
        for owner in (classdef, *local_subclasses(decision)):
            if facts.parent(owner) is facts.tree:
                found += project.done_overrides(owner.name, name, index)
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


def _report_truncation(decision: ClassDecision, ret: ast.Return, done: ast.expr, traced: DoneCause, function: Method) -> None:
    text = decision.family.facts.segment(done)
    # the same done returned again by the same step is one decision: asked once
    question = ("step-done", id(function), text)
    if traced.elsewhere():
        decision.report(
            ret,
            "GM504",
            f"step returns terminated=False and truncated=`{text}`: every override in the run ends the episode only on "
            f"the step/time limit {_limits_text(traced)}, a truncation; check subclasses outside this run",
            FixKind.ASSIST,
            question=question,
        )
    elif traced.drawn():
        drawn = ", ".join(f"`self.{name}`" for name in traced.drawn())
        decision.report(
            ret,
            "GM504",
            f"step returns terminated=False and truncated=`{text}`: it is True only on {_limits_text(traced)}, whose "
            f"bound ({drawn}) the class draws at random: a horizon drawn per episode may be the task's own length (a "
            "finite-horizon task, its reward paid at that step) rather than a time limit; if reaching it ends the task, "
            "return it as terminated instead",
            FixKind.ASSIST,
            question=question,
        )
    elif not traced.plain():
        decision.report(
            ret,
            "GM504",
            f"step returns terminated=False and truncated=`{text}`: it is True only on {_limits_text(traced)}, a count "
            "step advances on every call compared with a bound (an episode length, a truncation); if reaching it is "
            "the task's goal, return it as terminated instead",
            FixKind.ASSIST,
            question=question,
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


def _bound_text(decision: ClassDecision, end: Limit) -> str:
    """`` (`self.max_step = len(prices) - 1`, line 8)``: where the attribute the test
    compares with is bound to the data's length; "" when the test spells the length."""
    facts = decision.family.facts
    data_ends = class_data_ends(decision)
    for node in walk(decision.classdef):
        if not (isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Attribute)):
            continue
        target = node.targets[0]
        if isinstance(target.value, ast.Name) and target.value.id == "self" and target.attr in data_ends:
            if re.search(rf"\bself\.{re.escape(target.attr)}\b", end.text):
                return f" (`{facts.segment(node)}`, line {node.lineno})"
    return ""
