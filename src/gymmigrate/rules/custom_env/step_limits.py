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

from gymmigrate.facts.env_classes import identifiers
from gymmigrate.facts.limits import (
    DoneCause,
    data_end_attributes,
    is_step_limit,
    unwrap_bool,
)
from gymmigrate.facts.module import own_returns
from gymmigrate.findings import Tier
from gymmigrate.rules.custom_env.common import ClassDecision
from gymmigrate.rules.custom_env.plans import STEP_LIMIT_WORD


def class_data_ends(decision: ClassDecision) -> frozenset[str]:
    return data_end_attributes(decision.family.facts, decision.classdef)


def counts_toward_a_limit(decision: ClassDecision) -> bool:
    """The class counts something (``self.steps += 1``, ``self.rounds -= 1``, ``t = t + 1``,
    ``self.time += self.dt``) or tests a step limit anywhere: that may end episodes on a
    limit, so a person decides. Physics updates (``self.x += dx``) are not counts, nor is
    an attribute the class never reads (``self.steps += 1`` kept for statistics) or one it
    moves both ways (``self.index += 1`` and ``self.index = max(self.index - 1, 0)``: a
    position, not a count)."""
    facts = decision.family.facts

    def compute() -> bool:
        # The class and its bases of this file, each read the same way (a base that counts
        # nothing adds no limit); a base of another module of the run may count steps for it.
        receivers = decision.family.receivers
        seen: set[int] = set()
        todo = [decision.classdef]
        while todo:
            classdef = todo.pop()
            if id(classdef) in seen:
                continue
            seen.add(id(classdef))
            if decision.env.has_run_env_base(classdef) or _counts_in(decision, classdef):
                return True
            todo.extend(base for b in classdef.bases if (base := receivers.local_class(b)) is not None)
        return False

    return facts.memo(("counts-by-constant", id(decision.classdef)), compute)


def _counts_in(decision: ClassDecision, classdef: ast.ClassDef) -> bool:
    """``classdef`` itself (its own body) counts something or tests a step limit."""
    facts = decision.family.facts
    data_ends = data_end_attributes(facts, classdef)
    # A name moved by a constant both ways (``pos -= 1`` for one action, ``pos += 1``
    # for another) is a position, not a count: it cannot run up to a limit by itself.
    directions: dict[str, set[bool]] = {}
    for node in ast.walk(classdef):
        if isinstance(node, ast.AugAssign) and isinstance(node.op, (ast.Add, ast.Sub)) and _is_number(node.value):
            up = isinstance(node.op, ast.Add) == (node.value.value >= 0)  # type: ignore[attr-defined]
            directions.setdefault(facts.segment(node.target), set()).add(up)
    for node in ast.walk(classdef):
        if isinstance(node, ast.AugAssign) and isinstance(node.op, (ast.Add, ast.Sub)):
            counted = (
                _is_number(node.value)
                and not isinstance(node.target, ast.Subscript)
                and len(directions.get(facts.segment(node.target), ())) < 2
            )
            if counted or any(STEP_LIMIT_WORD.search(w) for w in identifiers(node.target)):
                if not _idle_attribute(decision, node.target, classdef):
                    return True  # `self.steps += 1`, `self.t += self.dt`; not `self.pos[1] += 1`
        if isinstance(node, ast.Compare) and is_step_limit(node, data_ends):
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


def _idle_attribute(decision: ClassDecision, target: ast.expr, classdef: ast.ClassDef) -> bool:
    """``self.<name>`` that cannot limit an episode: the module never reads it
    but to count it, or it also moves it the other way or back from its own value
    (a position). Only attributes of the class itself; anything else may count."""
    if not (isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self"):
        return False
    facts = decision.family.facts
    directions: set[type] = set()
    reads = 0
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


def step_limit_text(decision: ClassDecision, function: ast.AST) -> str | None:
    data_ends = class_data_ends(decision)
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


def split_question(expr: ast.AST) -> Hashable:
    """The split of one done expression: the same wherever a class of the file (a twin
    subclass's own step) splits the same expression, so the file asks it once."""
    return ("GM504", "split", ast.dump(unwrap_bool(expr)))


def accumulated_limit(function: ast.AST, ret: ast.Return, name: str, data_ends: frozenset[str]) -> ast.Assign | None:
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


def flagged_limit(function: ast.AST, name: str, data_ends: frozenset[str]) -> ast.If | None:
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


def split_tier(traced: DoneCause, split: ast.AST, data_ends: frozenset[str]) -> Tier | None:
    """A split whose limits are all named as step limits in this module, with no override
    elsewhere in the run, and compared with a bound the env holds rather than a literal, is
    settled (``self.current_step >= self.ep_length``): a note, as for a done that is only such
    a limit (``step._report_truncation``). ``self.t >= 2`` may be the game's own length: asked."""
    limits = [op for op in _or_operands(unwrap_bool(split)) if is_step_limit(op, data_ends)]
    literal = any(
        isinstance(side, ast.Constant) for op in limits if isinstance(op, ast.Compare) for side in (op.left, *op.comparators)
    )
    return Tier.NOTE if traced.limits and traced.plain() and not literal else None


def split_done(expr: ast.AST, data_ends: frozenset[str] = frozenset()) -> bool:
    """``bool(task or self.steps >= self.max_steps)`` has a clear step-limit test."""
    return any(is_step_limit(op, data_ends) for op in _or_operands(unwrap_bool(expr)))
