"""GM602: which end conditions a wrapper's ``step`` override adds to the inner ``done``.

Its own step limit (``if self.t >= self.t_max: done = True``), a lost life (baselines'
``EpisodicLifeEnv``: ``done = True`` under a test of the lives, or ``done = done or
lives < self.lives``), or the task's own end (``done = done or info.get("is_success")``),
or none (every change sets it false: ``done = False``, a method of the class whose every
return puts False there); which assignments are only initializers. ``step.py`` decides
from these what the override returns as ``terminated`` and what as ``truncated``.

Separate from ``step.py`` because these are questions about the override's lines alone
(the ``ast``, no plan and no rewrite), read the same way by every case of the rewrite.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Callable

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.done_causes import Cause, combine
from gymmigrate.facts.done_uses import always_false_here, falsy_constant
from gymmigrate.facts.limit_tests import (
    if_setting_true,
    is_self,
    own_task_end,
    streak_attributes,
    unwrap_bool,
)
from gymmigrate.facts.limits import DoneTracer
from gymmigrate.facts.module import FUNCTIONS, own_returns, self_attribute, walk
from gymmigrate.facts.names import strip_gym_prefix
from gymmigrate.facts.per_agent_flags import true_list
from gymmigrate.rules.custom_env.step import is_step_limit
from gymmigrate.rules.step_done.common import StepUnpack
from gymmigrate.rules.wrappers.common import _assigned_names, _single_assign


def _names(expr: ast.AST) -> set[str]:
    return {node.id for node in walk(expr) if isinstance(node, ast.Name)}


def _replaces_inner_end(function: ast.AST, done: ast.expr, inner: set[str], attribute: str | None) -> bool:
    """``done`` is a local of ``function`` whose every assignment is a plain one that reads
    none of the inner step's flags (``inner``, nor ``self.<attribute>`` where the unpack
    stores its done): the override's own flag, returned in place of the inner end rather
    than merged with it (``done or lost_life`` reads it)."""
    if not isinstance(done, ast.Name) or done.id in inner:
        return False
    name, assigned = done.id, 0
    for node in walk(function):
        if isinstance(node, (ast.AugAssign, ast.AnnAssign, ast.NamedExpr, ast.For, ast.AsyncFor, ast.With, ast.AsyncWith, ast.Global, ast.Nonlocal)):
            if name in _names(node):
                return False
        elif isinstance(node, ast.arg) and node.arg == name:
            return False
        elif isinstance(node, ast.Assign) and any(name in _names(target) for target in node.targets):
            if not (len(node.targets) == 1 and isinstance(node.targets[0], ast.Name)):
                return False
            reads = _names(node.value) | {n.attr for n in walk(node.value) if isinstance(n, ast.Attribute)}
            if reads & inner or (attribute is not None and attribute in reads):
                return False
            assigned += 1
    return assigned > 0


def _only_own_step_limit(function: ast.AST, done: ast.expr, flags: tuple[str, str]) -> bool:
    """``self.t >= self.t_max`` returned as done, or a local whose every assignment in
    ``function`` is an initializer (``False``/``None``), a step-limit comparison, or ``True``
    alone under ``if <step limit>:`` (at least one of the last two), none reading the inner
    flags: the override's done is its own step count and nothing else."""
    if is_step_limit(done):
        return not (_names(done) & set(flags))
    if not isinstance(done, ast.Name):
        return False
    name, limits = done.id, 0
    parents = {child: node for node in walk(function) for child in ast.iter_child_nodes(node)}
    for node in walk(function):
        if isinstance(node, (ast.AugAssign, ast.AnnAssign, ast.NamedExpr, ast.For, ast.AsyncFor, ast.With, ast.AsyncWith)):
            targets = [node.target] if not isinstance(node, (ast.With, ast.AsyncWith)) else [
                item.optional_vars for item in node.items if item.optional_vars is not None
            ]
            if any(name in _names(target) for target in targets):
                return False
        elif isinstance(node, (ast.Name,)) and isinstance(node.ctx, ast.Del) and node.id == name:
            return False
        elif isinstance(node, ast.Assign) and any(name in _names(target) for target in node.targets):
            if not (len(node.targets) == 1 and isinstance(node.targets[0], ast.Name)):
                return False
            if _is_initializer(node, name):
                continue
            if _names(node.value) & set(flags):
                return False
            if is_step_limit(node.value) or _set_alone_when(node, parents.get(node), is_step_limit):
                limits += 1
                continue
            return False
    return limits > 0


def _merges_life_loss(function: ast.AST, name: str, done_name: str, flags: tuple[str, str]) -> bool:
    """Every assignment of ``name`` in ``function`` is ``name = done_name`` or ``name =
    done_name or <a test of lives>`` (at least one of the latter), none reading the flags:
    ``name`` is the inner done, or it with a lost life."""
    lives = 0
    for node in walk(function):
        if isinstance(node, (ast.AugAssign, ast.AnnAssign, ast.NamedExpr, ast.For, ast.AsyncFor)):
            if name in _names(node.target):
                return False
        elif isinstance(node, (ast.With, ast.AsyncWith)):
            if any(item.optional_vars is not None and name in _names(item.optional_vars) for item in node.items):
                return False
        elif isinstance(node, ast.Assign) and any(name in _names(target) for target in node.targets):
            if not (len(node.targets) == 1 and isinstance(node.targets[0], ast.Name)):
                return False
            value = node.value
            if _names(value) & set(flags):
                return False
            if isinstance(value, ast.Name) and value.id == done_name:
                continue
            if not (isinstance(value, ast.BoolOp) and isinstance(value.op, ast.Or)):
                return False
            rest = [v for v in value.values if not (isinstance(v, ast.Name) and v.id == done_name)]
            if len(rest) != len(value.values) - 1 or done_name in {n for r in rest for n in _names(r)}:
                return False
            if not all(any(_LIFE_WORDS.search(_identifier(n)) for n in walk(r)) for r in rest):
                return False
            lives += 1
    return lives > 0


def _is_initializer(statement: ast.stmt, name: str) -> bool:
    """``done = None`` / ``done = False`` before a loop (or ``frames, total, done = [], 0.0,
    False``): not a change of the inner result."""
    assign = _single_assign(statement)
    if assign is None:
        return False
    target, value = assign.targets[0], assign.value
    if isinstance(target, ast.Tuple) and isinstance(value, ast.Tuple) and len(target.elts) == len(value.elts):
        pairs = [(t, v) for t, v in zip(target.elts, value.elts, strict=True) if isinstance(t, ast.Name) and t.id == name]
        if len(pairs) != 1:
            return False
        value = pairs[0][1]
    return isinstance(value, ast.Constant) and (value.value is None or value.value is False)


def _sets_done_on_limit(
    line: ast.stmt, name: str, parent: ast.AST | None, per_agent: bool = False, limit: Callable[[ast.AST], bool] = is_step_limit
) -> bool:
    """``if self._elapsed_steps >= self._max_episode_steps: done = True`` or
    ``done = done or self.t >= self.limit``: ``name`` is set only by a step-limit test
    (``limit``). With per-agent flags, ``done = len(obs) * [True]`` there too."""
    if per_agent and isinstance(line, ast.Assign) and len(line.targets) == 1 and true_list(line.value):
        target = line.targets[0]
        return (
            isinstance(target, ast.Name)
            and target.id == name
            and isinstance(parent, ast.If)
            and line in parent.body
            and not parent.orelse
            and limit(parent.test)
        )
    return _sets_done_when(line, name, parent, limit)


def limit_tests(facts: ModuleFacts, classdef: ast.ClassDef | None, overridden: Callable[[str], bool]) -> Callable[[ast.AST], bool]:
    """A test of a step limit in a method of ``classdef``: one that names a step counter
    (``is_step_limit``), or ``self.<m>()`` where ``m`` is a method of the class (or a base of
    this module) every return of which is such a test, overridden nowhere else in the run
    (``overridden``). A counter the class starts over on a condition of the step (a run of
    consecutive steps, ``streak_attributes``) is no step limit: reaching its bound is
    something the task did, a termination."""
    streaks = streak_attributes(facts, classdef) if classdef is not None else frozenset()

    def test(expr: ast.AST) -> bool:
        if is_step_limit(expr, (), streaks):
            return True
        name = _own_call(expr)
        if classdef is None or name is None:
            return False
        tracer = facts.memo(("done-tracer", id(classdef)), lambda: DoneTracer(facts, classdef))
        candidates = tracer.candidates(name)
        if not candidates:
            return False
        found = combine(owner.returns_cause(method, 0) for owner, method in candidates)
        return found.cause is Cause.TRUNCATION and found.plain() and not overridden(name)

    return test


# gym's TimeLimit tested its own limit in ``_past_limit()`` (with a limit in seconds beside the
# one in steps); Gymnasium's TimeLimit has no such method.
_GYM_TIME_LIMIT_TEST = "_past_limit"


def gym_time_limit_test(facts: ModuleFacts, classdef: ast.ClassDef | None) -> Callable[[ast.AST], bool]:
    """``self._past_limit()`` in a subclass of Gym's TimeLimit that does not define it (nor a
    base of this module): the test of the limit its base keeps, a truncation by what that
    wrapper is for, through a method Gymnasium's TimeLimit no longer has."""

    def test(expr: ast.AST) -> bool:
        if classdef is None or _own_call(expr) != _GYM_TIME_LIMIT_TEST:
            return False
        tracer = facts.memo(("done-tracer", id(classdef)), lambda: DoneTracer(facts, classdef))
        return not tracer.defines(_GYM_TIME_LIMIT_TEST) and any(
            strip_gym_prefix(q) in ("wrappers.TimeLimit", "wrappers.time_limit.TimeLimit")
            for base in classdef.bases
            for q in facts.qualified_names(base)
        )

    return test


def _own_call(expr: ast.AST) -> str | None:
    """``m`` of ``self.m()`` (or ``bool(self.m())``), a call with no arguments."""
    expr = unwrap_bool(expr)
    if (
        isinstance(expr, ast.Call)
        and isinstance(expr.func, ast.Attribute)
        and is_self(expr.func.value)
        and not expr.args
        and not expr.keywords
    ):
        return expr.func.attr
    return None


def _sets_done_when(line: ast.stmt, name: str, parent: ast.AST | None, test: Callable[[ast.AST], bool]) -> bool:
    """``if <test>: done = True`` (alone in the ``if``, no ``else``) or ``done = done or
    <test>``: ``name`` is set only where ``test`` holds of the condition."""
    if not (isinstance(line, ast.Assign) and len(line.targets) == 1 and isinstance(line.targets[0], ast.Name)):
        return False
    value = line.value
    if isinstance(value, ast.Constant) and value.value is True:
        return _set_alone_when(line, parent, test)
    if isinstance(value, ast.BoolOp) and isinstance(value.op, ast.Or):
        rest = [v for v in value.values if not (isinstance(v, ast.Name) and v.id == name)]
        return len(rest) == len(value.values) - 1 and all(test(v) for v in rest)
    return False


# ``lives``, ``self.lives``, ``lives_before > lives_after``, ``n_lives``, ``ale.lives()``, ``life_lost``
_LIFE_WORDS = re.compile(r"(?:^|_)lives?(?:_|$)|life", re.IGNORECASE)


def _sets_done_on_life_loss(line: ast.stmt, parent: ast.AST | None) -> bool:
    """``done = True`` alone in an ``if`` that tests the number of lives."""
    return _set_alone_when(line, parent, _tests_lives)


def _tests_lives(expr: ast.AST) -> bool:
    return any(_LIFE_WORDS.search(_identifier(node)) for node in walk(expr))


def _is_lives_test(line: ast.stmt, name: str, flags: set[str]) -> bool:
    """``done = lives == 0`` (game over), ``done = lives < self.lives``: ``name`` set to a
    comparison of the lives alone, reading neither the old done nor the inner flags."""
    if not (isinstance(line, ast.Assign) and len(line.targets) == 1 and isinstance(line.targets[0], ast.Name)):
        return False
    value = line.value
    while isinstance(value, ast.UnaryOp) and isinstance(value.op, ast.Not):
        value = value.operand
    tests = value.values if isinstance(value, ast.BoolOp) else [value]
    return (
        line.targets[0].id == name
        and all(isinstance(test, ast.Compare) for test in tests)
        and _tests_lives(value)
        and not _names(value) & (flags | {name})
    )


def _set_alone_when(line: ast.stmt, parent: ast.AST | None, test: Callable[[ast.AST], bool]) -> bool:
    """``if <test>: done = True`` with no ``else``."""
    branch = if_setting_true(line, parent)
    return branch is not None and line in branch.body and not branch.orelse and test(branch.test)


# what a task's own end is called: ``info["is_success"]``, ``reached_goal``, ``self.crashed``,
# ``self._is_fallen()`` (a robot or an object held that fell: a failure of the task)
_TASK_END_WORDS = re.compile(
    r"success|goal|solved|reached|\bwon\b|\bwin\b|crash|collision|collided|fail|fallen|(?:^|_)(?:fall|fell)(?:_|$)",
    re.IGNORECASE,
)


def _own_task_end(line: ast.stmt, name: str, parent: ast.AST | None, streaks: frozenset[str] = frozenset()) -> bool:
    """``done = done or <task end>`` (the flag anywhere in the ``or``), or ``done = True`` in
    an ``if`` that tests a task end and whose other branch leaves ``done`` as it was: an end
    of the task an env class's step would return as terminated too (``own_task_end``: no
    step limit among its tests). A wrapper is not the task's author, so each test must also
    show the end: a task's own word (success, a goal, a crash), the lives, or the bound of a
    count the step starts over on a condition of its own (``streaks``: consecutive misses,
    a goal held), which only what the agent did reaches."""
    tests = own_task_end(line, name, parent, (), streaks)
    return tests is not None and all(_names_task_end(test) or _tests_lives(test) or _tests_streak(test, streaks) for test in tests)


def _tests_streak(expr: ast.AST, streaks: frozenset[str]) -> bool:
    """A comparison of one of ``streaks`` (``self.missed > self.max_missed``)."""
    return isinstance(expr, ast.Compare) and any(self_attribute(node) in streaks for node in walk(expr))


def _names_task_end(expr: ast.AST) -> bool:
    return any(_TASK_END_WORDS.search(_identifier(node)) for node in walk(expr))


def _identifier(node: ast.AST) -> str:
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        return node.attr
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value
    return ""


def _done_changes(
    lines: list[ast.stmt], name: str, done_line: ast.stmt | None, unpacks: dict[ast.stmt, StepUnpack | None]
) -> list[ast.stmt]:
    """The lines that change ``name`` after the inner step: not the unpack, its ``done =
    ...`` line or an initializer."""
    return [
        line
        for line in lines
        if line not in unpacks and line is not done_line and name in _assigned_names(line) and not _is_initializer(line, name)
    ]


def _only_step_limits(
    facts: ModuleFacts,
    lines: list[ast.stmt],
    name: str,
    done_line: ast.stmt | None,
    unpacks: dict[ast.stmt, StepUnpack | None],
    per_agent: bool = False,
    limit: Callable[[ast.AST], bool] = is_step_limit,
) -> bool:
    """Every change of ``name`` after the inner step is a step-limit test (``limit``) setting it."""
    changes = _done_changes(lines, name, done_line, unpacks)
    return bool(changes) and all(_sets_done_on_limit(line, name, facts.parent(line), per_agent, limit) for line in changes)


def _life_loss_sets(
    facts: ModuleFacts,
    lines: list[ast.stmt],
    name: str,
    done_line: ast.stmt | None,
    unpacks: dict[ast.stmt, StepUnpack | None],
    flags: tuple[str, str],
) -> list[tuple[ast.Assign, str]]:
    """The lines that end the episode on the lives, each with what sets ``terminated``
    after it, when they are the only changes of ``name`` after the inner step; else nothing.
    baselines' ``EpisodicLifeEnv`` (``if lives < self.lives and lives > 0: done = True``)
    sets it True; a game over (``done = lives == 0``) ors its test into it, which keeps an
    end of the inner step on the same line (a lost life or no life left is the game's own
    end, never a time limit)."""
    terminated = flags[0]
    changes = _done_changes(lines, name, done_line, unpacks)
    found: list[tuple[ast.Assign, str]] = []
    for line in changes:
        if _sets_done_on_life_loss(line, facts.parent(line)):
            found.append((line, f"{terminated} = True"))  # type: ignore[arg-type]
        elif _is_lives_test(line, name, set(flags)):
            found.append((line, f"{terminated} = {terminated} or {name}"))  # type: ignore[arg-type]
        else:
            return []
    return found


def _task_end_sets(
    facts: ModuleFacts,
    lines: list[ast.stmt],
    name: str,
    done_line: ast.stmt | None,
    unpacks: dict[ast.stmt, StepUnpack | None],
    classdef: ast.AST | None = None,
) -> list[ast.Assign]:
    """The changes of ``name`` after the inner step, when every one ends the episode on the
    task's own end (``done = done or info.get("is_success")``, ``if reached_goal: done =
    True``, a test of the lives among them); else nothing."""
    changes = _done_changes(lines, name, done_line, unpacks)
    streaks = streak_attributes(facts, classdef) if isinstance(classdef, ast.ClassDef) else frozenset()
    if changes and all(_own_task_end(line, name, facts.parent(line), streaks) for line in changes):
        return changes  # type: ignore[return-value]
    return []


def _clears(
    lines: list[ast.stmt], name: str, done_line: ast.stmt | None, unpacks: dict[ast.stmt, StepUnpack | None]
) -> list[ast.Assign]:
    """``done = False`` (or ``None``) after an inner step (``if self.steps < self.min_len:
    done = False``): the override takes back the episode's end, the inner step's included,
    which ``_is_initializer`` alone would read as a start value. Lines before every inner
    step (a start value, or one a later unpack overwrites) are not among them."""
    found: list[ast.Assign] = []
    seen_unpack = False
    for line in lines:
        if line in unpacks or line is done_line:
            seen_unpack = True
            continue
        if (
            seen_unpack
            and isinstance(line, ast.Assign)
            and len(line.targets) == 1
            and isinstance(line.targets[0], ast.Name)
            and line.targets[0].id == name
            and _is_initializer(line, name)
        ):
            found.append(line)
    return found


def _never_ends(changes: list[ast.stmt], name: str, classdef: ast.ClassDef, facts: ModuleFacts) -> str | None:
    """Where every line that changes ``name`` in the override sets it false (``done =
    False``, or ``obs, done = self.fire()`` with ``fire`` a method of the class whose every
    return puts a false value there): the text naming the source; None otherwise."""
    if not changes:
        return None
    sources = []
    for line in changes:
        if not isinstance(line, ast.Assign) or len(line.targets) != 1:
            return None
        target = line.targets[0]
        if isinstance(target, ast.Name) and target.id == name and falsy_constant(line.value):
            sources.append(f"`{facts.segment(line.value)}`")
            continue
        value = line.value
        if not (
            isinstance(target, ast.Tuple)
            and isinstance(value, ast.Call)
            and isinstance(value.func, ast.Attribute)
            and isinstance(value.func.value, ast.Name)
            and value.func.value.id == "self"
        ):
            return None
        index = next((i for i, e in enumerate(target.elts) if isinstance(e, ast.Name) and e.id == name), None)
        method = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == value.func.attr), None)
        if index is None or method is None:
            return None
        returns = own_returns(method)
        if not returns:
            return None
        for ret in returns:
            if not (isinstance(ret.value, ast.Tuple) and len(ret.value.elts) == len(target.elts)):
                return None
            flag = ret.value.elts[index]
            if not (falsy_constant(flag) or (isinstance(flag, ast.Name) and always_false_here(flag, facts))):
                return None
        sources.append(f"`self.{method.name}()`")
    return ", ".join(dict.fromkeys(sources))


def _own_end_kind(facts: ModuleFacts, function: ast.AST, done: ast.expr, skipped: set[ast.stmt]) -> str:
    """What the override's own ``done`` tests where no inner step's done reaches it:
    "limit" (a step count alone: a truncation), "task" (every test names the task's end or
    the lives: a terminal state), else "unclear". A name is read through its assignments in
    ``function`` (not ``skipped``, the inner step unpacks, nor an initializer); ``done = True``
    through the ``if`` around it."""
    if not isinstance(done, ast.Name):
        tests: list[ast.AST] = [done]
    else:
        tests = []
        for node in walk(function):
            if node in skipped or not (isinstance(node, ast.Assign) and done.id in _assigned_names(node)):
                continue
            if _is_initializer(node, done.id):
                continue
            if len(node.targets) != 1 or not isinstance(node.targets[0], ast.Name):
                return "unclear"
            parent = facts.parent(node)
            if isinstance(node.value, ast.Constant) and node.value.value is True:
                if not (isinstance(parent, ast.If) and node in parent.body):
                    return "unclear"
                tests.append(parent.test)
            else:
                tests.append(node.value)
    if not tests:
        return "unclear"
    if all(is_step_limit(test) for test in tests):
        return "limit"
    if all(_names_task_end(test) or _tests_lives(test) for test in tests):
        return "task"
    return "unclear"
