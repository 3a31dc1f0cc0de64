"""Which classes count something that could end an episode on a step limit (GM504).

A custom env's step that returns ``truncated=False`` is a review item unless the class
cannot end episodes on a limit of its own: it counts nothing by a constant (no
``self.steps += 1``, ``self.rounds -= 1``, ``t = t + 1``) and tests no step limit, nor do
its bases. ``counts_in`` reads one class's own body; each module's summary records it per
top-level class with the class's bases, so a subclass in another module can read a base
of the run the same way (``ProjectFacts.quiet_classes``, the classes of the run that
count nothing, with every base they have).
"""

from __future__ import annotations

import ast

from gymmigrate.facts import names as N
from gymmigrate.facts.env_classes import identifiers
from gymmigrate.facts.limit_tests import (
    STEP_LIMIT_WORD,
    compares_the_action,
    data_end_attributes,
    is_local_sign_test,
    is_step_limit,
    self_field,
    streak_attributes,
)
from gymmigrate.facts.module import (
    FUNCTIONS,
    LOOPS,
    ModuleFacts,
    own_returns,
    self_attribute,
    walk,
)
from gymmigrate.facts.receivers import Receivers

# class -> (its own body counts, its bases of this module, the qualified names of its
# other bases that are no library's)
Counting = dict[str, tuple[bool, tuple[str, ...], tuple[str, ...]]]


def step_counting(facts: ModuleFacts, receivers: Receivers) -> Counting:
    """For each top-level class: whether its own body counts (``counts_in``)
    and its bases, for the join to read a class across modules."""
    found: Counting = {}
    for name, classdef in facts.classes.items():
        local: list[str] = []
        other: list[str] = []
        for base in classdef.bases:
            own = receivers.local_class(base)
            if own is not None:
                local.append(own.name)
                continue
            other.extend(q for q in facts.qualified_names(base) if not N.is_library(q))
        found[name] = (counts_in(facts, classdef), tuple(local), tuple(sorted(set(other))))
    return found


def counts_in(facts: ModuleFacts, classdef: ast.ClassDef) -> bool:
    """``classdef`` itself (its own body) counts something (``self.steps += 1``,
    ``self.rounds -= 1``, ``t = t + 1``, ``self.time += self.dt``) or tests a step limit.
    Physics updates (``self.x += dx``) are not counts, nor is an attribute the class never
    reads (``self.steps += 1`` kept for statistics) or reads only as a phase
    (``self.steps % 10``), one it moves both ways
    (``self.index += 1`` and ``self.index = max(self.index - 1, 0)``: a position), or one
    that starts over whenever it does not count (a run of consecutive steps,
    ``limit_tests.streak_attributes``)."""
    data_ends = data_end_attributes(facts, classdef)
    streaks = streak_attributes(facts, classdef)  # runs of consecutive steps, no episode's count
    # A name moved by a constant both ways (``pos -= 1`` for one action, ``pos += 1``
    # for another) is a position, not a count: it cannot run up to a limit by itself.
    directions: dict[str, set[bool]] = {}
    for node in walk(classdef):
        if isinstance(node, ast.AugAssign) and isinstance(node.op, (ast.Add, ast.Sub)) and _is_number(node.value):
            up = isinstance(node.op, ast.Add) == (node.value.value >= 0)  # type: ignore[attr-defined]
            directions.setdefault(facts.segment(node.target), set()).add(up)
        elif isinstance(node, ast.Assign) and isinstance(node.value, ast.BinOp) and _self_step(facts, node):
            # ``self.vel = self.vel + 1`` for one action, ``- 1`` for the other: the same
            # both ways as the augmented form
            value = node.value
            up = isinstance(value.op, ast.Add) == (value.right.value >= 0)  # type: ignore[attr-defined]
            directions.setdefault(facts.segment(node.targets[0]), set()).add(up)
    unreached = _methods_step_never_runs(classdef)
    for node in walk(classdef):
        if isinstance(node, ast.AugAssign) and _local_of(facts, node.target, unreached):
            continue  # ``countdown -= 1`` in ``__init__``: a local of a call step never makes
        if isinstance(node, ast.AugAssign) and isinstance(node.op, (ast.Add, ast.Sub)) and self_attribute(node.target) not in streaks:
            counted = (
                _is_number(node.value)
                and (not isinstance(node.target, ast.Subscript) or self_field(node.target) is not None)
                and len(directions.get(facts.segment(node.target), ())) < 2
            )
            if counted or any(STEP_LIMIT_WORD.search(w) for w in identifiers(node.target)):
                if not _idle_attribute(facts, node.target, classdef) and not _moved_once_per_call(facts, node.target) and not past_the_end(facts, node):
                    # `self.steps += 1`, `self.t += self.dt`, `self.state["count"] += 1` (a named
                    # entry counts as an attribute does); not `self.pos[1] += 1`
                    return True
        if (
            isinstance(node, ast.Compare)
            and is_step_limit(node, data_ends, streaks)
            and not is_local_sign_test(facts, node)
            and not compares_the_action(facts, node)
            and not past_the_end(facts, node)
        ):
            return True  # a step-limit test in a helper (`def _done(self): return self.t > 200`)
        if (
            isinstance(node, ast.Assign)
            and _self_step(facts, node)
            and not _local_of(facts, node.targets[0], unreached)
            and len(directions.get(facts.segment(node.targets[0]), ())) < 2
            and self_attribute(node.targets[0]) not in streaks
            and not _moved_once_per_call(facts, node.targets[0])
            and not past_the_end(facts, node)
        ):
            return True  # `self.t = self.t + 1`
    return False


def _self_step(facts: ModuleFacts, node: ast.AST) -> bool:
    """``x = x + <number>`` (or ``- <number>``)."""
    return (
        isinstance(node, ast.Assign)
        and len(node.targets) == 1
        and isinstance(node.value, ast.BinOp)
        and isinstance(node.value.op, (ast.Add, ast.Sub))
        and _is_number(node.value.right)
        and facts.segment(node.value.left) == facts.segment(node.targets[0])
    )


def _methods_step_never_runs(classdef: ast.ClassDef) -> set[int]:
    """The methods of ``classdef`` (by ``id``) that its ``step`` never calls, through
    ``self.<method>(...)`` at any depth; none when the class defines no step (a base's
    step may call any of them) or hands a method on (a callback may run anywhere)."""
    methods = {m.name: m for m in classdef.body if isinstance(m, FUNCTIONS)}
    if not any(name in methods for name in ("step", "_step")):
        return set()
    called = {id(n.func) for n in walk(classdef) if isinstance(n, ast.Call)}
    if any(self_attribute(n) in methods and id(n) not in called for n in walk(classdef)):
        return set()
    reached: set[int] = set()
    todo = [m for name, m in methods.items() if name in ("step", "_step")]
    while todo:
        method = todo.pop()
        if id(method) in reached:
            continue
        reached.add(id(method))
        todo += [methods[n.func.attr] for n in walk(method) if isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute) and self_attribute(n.func) in methods]
    return {id(m) for m in methods.values() if id(m) not in reached}


def _local_of(facts: ModuleFacts, target: ast.AST, methods: set[int]) -> bool:
    """``target`` is a plain local of one of ``methods`` (or of a def inside one): it lives
    for that call only."""
    if not methods or not isinstance(target, ast.Name):
        return False
    scope = facts.scope_of(target)
    if target.id in scope.declared_global or target.id in scope.declared_nonlocal:
        return False
    return any(id(ancestor) in methods for ancestor in facts.ancestors(target))


def _idle_attribute(facts: ModuleFacts, target: ast.expr, classdef: ast.ClassDef) -> bool:
    """``self.<name>`` that cannot limit an episode: the module never reads it
    but to count it, or it also moves it the other way or back from its own value
    (a position). Only attributes of the class itself and named entries of them; anything
    else may count."""
    if isinstance(target, ast.Subscript) and self_field(target) is not None:
        return _idle_entry(facts, target)
    if not (isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self"):
        return False
    directions: set[type] = set()
    reads = 0
    for attr in facts.attributes.get(target.attr, ()):
        holder = facts.parent(attr)
        if isinstance(attr.ctx, ast.Load):
            if not _self_update(holder, target.attr) and not _period_of(holder, attr):
                reads += 1  # a read anywhere in the module (``env.steps`` in a script) may limit
            continue
        if not classdef.lineno <= attr.lineno <= (classdef.end_lineno or attr.lineno):
            continue  # another class's writes of the same name (its position is not this count)
        if _wraps(facts, holder, target.attr):
            return True  # ``if self.i > len(self.data) - 1: self.i = 0``: it cycles, it never runs out
        if isinstance(holder, ast.AugAssign):
            directions.add(type(holder.op))
        elif isinstance(holder, ast.Assign) and any(
            isinstance(n, ast.Attribute) and n.attr == target.attr and isinstance(n.value, ast.Name) and n.value.id == "self"
            for n in walk(holder.value)
        ) and not _self_update(holder.value, target.attr):
            return True  # ``self.index = max(self.index - 1, 0)``: moved back, a position
    if len(directions) > 1:
        return True  # ``+=`` and ``-=``: a position
    return reads == 0


def past_the_end(facts: ModuleFacts, node: ast.AST) -> bool:
    """``node`` runs only in the branch of a step where the done it returns already holds
    (``if not done: ... else: self.steps_after_fall += 1``): a count there counts the steps
    taken after the episode ended, and a test there is asked after it ended; neither can
    end it."""
    function = facts.enclosing_function(node)
    if function is None:
        return False
    flag = _returned_flag(function)
    if flag is None:
        return False
    child = node
    for parent in facts.ancestors(node):
        if parent is function:
            return False
        if isinstance(parent, ast.If) and child is not parent.test:
            test, holds = parent.test, child in parent.body
            if isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not):
                test, holds = test.operand, not holds
            if isinstance(test, ast.Name) and test.id == flag and holds:
                # the flag is final there: nothing binds it again below the test
                scope = facts.scopes.get(function)
                bindings = scope.bindings.get(flag, []) if scope is not None else []
                return bool(bindings) and all(getattr(b, "lineno", parent.lineno) < parent.lineno for b in bindings)
        child = parent
    return False


def _returned_flag(function: ast.AST) -> str | None:
    """The name every return of a step gives as its done (the third of four or five values)."""
    names = set()
    for ret in own_returns(function):
        value = ret.value
        if not (isinstance(value, ast.Tuple) and len(value.elts) in (4, 5) and isinstance(value.elts[2], ast.Name)):
            return None
        names.add(value.elts[2].id)
    return names.pop() if len(names) == 1 else None


def _idle_entry(facts: ModuleFacts, target: ast.Subscript) -> bool:
    """``self.state["count"]`` that the module never reads but to count it: no other read of
    that entry, nor of the whole dict (which may hand the entry on: a copy, a return)."""
    holder = target.value
    key = target.slice.value  # type: ignore[attr-defined]
    text = facts.segment(target)
    for attr in facts.attributes.get(holder.attr, ()):  # type: ignore[attr-defined]
        if not (isinstance(attr.ctx, ast.Load) and isinstance(attr.value, ast.Name) and attr.value.id == "self"):
            continue
        entry = facts.parent(attr)
        if not (isinstance(entry, ast.Subscript) and entry.value is attr):
            return False  # the whole dict is read
        if not (isinstance(entry.slice, ast.Constant) and entry.slice.value == key) or not isinstance(entry.ctx, ast.Load):
            continue  # another entry, or a store of this one
        update = facts.parent(entry)
        statement = facts.parent(update) if isinstance(update, ast.BinOp) and update.left is entry else None
        if not (isinstance(statement, ast.Assign) and [facts.segment(t) for t in statement.targets] == [text]):
            return False  # read, not only advanced (``self.state["count"] = self.state["count"] + 1``)
    return True


def _moved_once_per_call(facts: ModuleFacts, target: ast.expr) -> bool:
    """A local of a method moved outside any loop of it (``if angle > 1: angle -= 2``) and
    never stored whole elsewhere: it moves once per call and starts afresh at the next, a
    correction of a value rather than a count, which must persist from step to step (an
    attribute, a global) or run in a loop."""
    if not isinstance(target, ast.Name):
        return False
    scope = facts.scope_of(target)
    if target.id in scope.declared_global or target.id in scope.declared_nonlocal:
        return False
    for ancestor in facts.ancestors(target):
        if isinstance(ancestor, LOOPS):
            return False
        if isinstance(ancestor, FUNCTIONS):
            # ``t = self.t; t += 1; self.t = t``: the attribute persists what the local counts
            return not any(
                isinstance(node, ast.Assign) and isinstance(node.value, ast.Name) and node.value.id == target.id
                for node in walk(ancestor)
            )
    return False  # a class body or the module: a count of its own


def _period_of(holder: ast.AST | None, attr: ast.Attribute) -> bool:
    """``self.n % k``: the count read as a phase (every k-th step draws a particle), which
    comes round again and again and so can end nothing."""
    return isinstance(holder, ast.BinOp) and isinstance(holder.op, ast.Mod) and holder.left is attr


def _wraps(facts: ModuleFacts, holder: ast.AST | None, name: str) -> bool:
    """``if <test of self.<name>>: self.<name> = <number>`` and nothing else in that branch:
    the count starts over where it would run out, so it cannot end an episode itself (a
    branch that also ends the episode, ``done = True``, is no wrap)."""
    if not (isinstance(holder, ast.Assign) and len(holder.targets) == 1 and _is_number(holder.value)):
        return False
    branch = facts.parent(holder)
    return (
        isinstance(branch, ast.If)
        and branch.body == [holder]
        and not branch.orelse
        and any(isinstance(n, ast.Attribute) and n.attr == name and isinstance(n.value, ast.Name) and n.value.id == "self" for n in walk(branch.test))
    )


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
