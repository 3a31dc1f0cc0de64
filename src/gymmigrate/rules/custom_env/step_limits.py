"""GM504: where a step's done holds a step limit the env counts itself.

Whether the class counts anything that could end an episode on a limit, the first
step-limit test of a step, and the shapes of a done the rewrite splits exactly: a test
joined with ``or`` (``task or self.steps >= self.max_steps``), a limit added on the line
before the return (``done = done or self.t >= T``), or one ``if <limit>: done = True``.
``step.py`` decides with them; ``rebuild.py`` rewrites the shapes they accept.
"""

from __future__ import annotations

import ast
from collections.abc import Hashable

from gymmigrate.facts import names as N
from gymmigrate.facts.done_causes import DoneCause
from gymmigrate.facts.limit_tests import (
    compares_the_action,
    data_end_attributes,
    elapsed_since_step_mark,
    is_local_sign_test,
    is_step_limit,
    streak_attributes,
    unwrap_bool,
)
from gymmigrate.facts.module import ModuleFacts, own_returns, walk
from gymmigrate.facts.step_counts import counts_in, past_the_end
from gymmigrate.findings import Tier
from gymmigrate.rules.custom_env.common import ClassDecision


def class_data_ends(decision: ClassDecision) -> frozenset[str]:
    return data_end_attributes(decision.family.facts, decision.classdef)


def class_streaks(decision: ClassDecision) -> frozenset[str]:
    return streak_attributes(decision.family.facts, decision.classdef)


def counts_toward_a_limit(decision: ClassDecision) -> bool:
    """The class counts something or tests a step limit anywhere (``facts/step_counts.py``),
    or a base of it does: that may end episodes on a limit, so a person decides."""
    facts = decision.family.facts

    def compute() -> bool:
        # The class and its bases of this file, each read the same way (a base that counts
        # nothing adds no limit); a base of another module of the run is read from its
        # module's summary: one that counts nothing, with all its bases, adds no limit either.
        receivers = decision.family.receivers
        seen: set[int] = set()
        todo = [decision.classdef]
        while todo:
            classdef = todo.pop()
            if id(classdef) in seen:
                continue
            seen.add(id(classdef))
            if decision.env.has_run_env_base(classdef) and not _run_bases_quiet(decision, classdef):
                return True
            if counts_in(facts, classdef):
                return True
            todo.extend(base for b in classdef.bases if (base := receivers.local_class(b)) is not None)
        return False

    return facts.memo(("counts-by-constant", id(decision.classdef)), compute)


def _run_bases_quiet(decision: ClassDecision, classdef: ast.ClassDef) -> bool:
    """Every base of ``classdef`` from another module is a class of the run that counts
    nothing, nor does any base of it (``ProjectFacts.quiet_classes``)."""
    facts = decision.family.facts
    project = decision.family.receivers.project
    if project is None:
        return False
    for base in classdef.bases:
        if decision.family.receivers.local_class(base) is not None:
            continue
        names = [q for q in facts.qualified_names(base) if not N.is_library(q)]
        if names and not any(project.counts_no_steps(q) for q in names):
            return False
    return True


def step_limit_text(decision: ClassDecision, function: ast.AST) -> str | None:
    data_ends, streaks = class_data_ends(decision), class_streaks(decision)
    found = [
        c
        for s in function.body  # type: ignore[attr-defined]
        for c in walk(s)
        if isinstance(c, ast.Compare)
        and is_step_limit(c, data_ends, streaks)
        and not is_local_sign_test(decision.family.facts, c)
        and not compares_the_action(decision.family.facts, c)
        and not past_the_end(decision.family.facts, c)
        and not elapsed_since_step_mark(decision.family.facts, c)
    ]
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


def split_question(expr: ast.AST) -> Hashable:
    """The split of one done expression: the same wherever a class of the file (a twin
    subclass's own step) splits the same expression, so the file asks it once."""
    return ("GM504", "split", ast.dump(unwrap_bool(expr)))


def accumulated_limit(
    function: ast.AST, ret: ast.Return, name: str, data_ends: frozenset[str], streaks: frozenset[str], facts: ModuleFacts
) -> ast.Assign | None:
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
    if len(own) != 1 or not limits or not all(limit_test(facts, v, data_ends, streaks) for v in limits):
        return None
    names = [n for n in walk(function) if isinstance(n, ast.Name)]
    if any(n.id in ("terminated", "truncated") for n in names):
        return None
    done = ret.value.elts[2]
    if any(n.id == name and n is not done for n in walk(ret.value) if isinstance(n, ast.Name)):
        return None  # ``float(done)`` as the reward: it reads the flag with the limit in it
    stores = [n for n in names if n.id == name and not isinstance(n.ctx, ast.Load)]
    for store in stores:
        if store is last.targets[0]:
            continue
        statement = next((s for s in walk(function) if isinstance(s, ast.Assign) and store in s.targets), None)
        if statement is None or statement.lineno >= last.lineno:
            return None
        if any(isinstance(n, ast.Compare) and limit_test(facts, n, data_ends, streaks) for n in walk(statement.value)):
            return None
    return last if len(stores) > 1 else None


def flagged_limit(
    function: ast.AST, name: str, data_ends: frozenset[str], streaks: frozenset[str], facts: ModuleFacts
) -> ast.If | None:
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
    for node in walk(function):
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
        if isinstance(s, ast.If) and not s.orelse and len(s.body) == 1 and s.body[0] in stores and limit_test(facts, s.test, data_ends, streaks)
    ]
    if len(limits) != 1 or body.index(limits[0]) < body.index(falses[0]):
        return None
    limit = limits[0]
    for store in stores:
        if store is falses[0] or store is limit.body[0]:
            continue
        parent = next((n for n in walk(function) if isinstance(n, ast.If) and (store in n.body or store in n.orelse)), None)
        if parent is None or any(isinstance(n, ast.Compare) and limit_test(facts, n, data_ends, streaks) for n in walk(parent.test)):
            return None
    if any(ret.lineno <= (limit.end_lineno or limit.lineno) for ret in returns):
        return None
    return limit


def _statement_of(function: ast.AST, target: ast.Name) -> ast.AST | None:
    return next((s for s in walk(function) if isinstance(s, ast.Assign) and target in s.targets), None)


def split_tier(traced: DoneCause) -> Tier | None:
    """A split whose limits are all named as step limits in this module, with no override
    elsewhere in the run, is settled (``self.current_step >= self.ep_length``, ``self.num_step
    >= 100``): a note, by the same test as a done that is only such a limit
    (``step._report_truncation``), a literal bound included: the split gives each cause the
    flag it has, so nothing is left to decide. A limit found only as a count the step
    advances, or with a bound drawn at random, is asked."""
    return Tier.NOTE if traced.limits and traced.plain() else None


def split_done(expr: ast.AST, data_ends: frozenset[str], streaks: frozenset[str], facts: ModuleFacts) -> bool:
    """``bool(task or self.steps >= self.max_steps)`` has a clear step-limit test."""
    return any(limit_test(facts, op, data_ends, streaks) for op in _or_operands(unwrap_bool(expr)))


def limit_test(facts: ModuleFacts, test: ast.AST, data_ends: frozenset[str], streaks: frozenset[str]) -> bool:
    """``is_step_limit``, but not a time since an event the step marks again
    (``elapsed_since_step_mark``): the step's own split and its items name only real limits."""
    return is_step_limit(test, data_ends, streaks) and not elapsed_since_step_mark(facts, test)
