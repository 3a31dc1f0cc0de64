"""What sits at the bottom of a wrapper stack: ``env = W3(W2(W1(gym.make(...))))``.

GM613 asks whether a wrapper wraps a vector env, GM615 which ``make`` an
AtariPreprocessing sits on, GM611 where the env behind a Monitor was made. All three
follow the same chains of wrapper calls and ``x = ...`` assignments. Answers are
memoized per node, and per resolved (scope, name) for names, and a node whose answer is
being computed counts as "no evidence" when reached again: the dozen ``env = W(env)``
rebindings of a preprocessing function cost one visit each, not one per path.
"""

from __future__ import annotations

import ast
from collections.abc import Callable, Hashable
from typing import TYPE_CHECKING, Protocol

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.kinds import EnvKind, join_kinds
from gymmigrate.facts.receivers import Receivers
from gymmigrate.rules.wrapper_usage.tables import wrapper_rest

if TYPE_CHECKING:
    from gymmigrate.edits.plan import Plan
    from gymmigrate.findings import FixKind, Tier
    from gymmigrate.rules.notes import FamilyNotes


class StacksFamily(Protocol):
    """What the rule groups of this package use of the family that calls them
    (``renames.WrapperRenames``): its facts, plan, reports and wrapper stacks."""

    facts: ModuleFacts
    receivers: Receivers
    plan: Plan
    notes: FamilyNotes
    stacks: WrapperStacks

    def report(
        self,
        node: ast.AST,
        code: str,
        message: str,
        kind: FixKind | None = None,
        tier: Tier | None = None,
        question: Hashable | None = None,
    ) -> None: ...

# Deeper than any real chain of distinct names; beyond it the answer is "unknown".
MAX_DEPTH = 20
_CYCLE = object()  # a node whose answer is being computed: no evidence either way


class WrapperStacks:
    """Follows wrapper stacks of one module; one per family run."""

    def __init__(self, facts: ModuleFacts, receivers: Receivers) -> None:
        self.facts = facts
        self.receivers = receivers
        self._memo: dict[tuple[str, int, str], object] = {}
        self._in_progress: set[tuple[str, int, str]] = set()
        self._depth = 0

    def vector_kind(self, expr: ast.AST) -> EnvKind:
        """Like ``kind_of``, but a single-env wrapper around an env has that env's kind.

        The shared analysis calls every ``gym.wrappers.X(...)`` a single env, which is what
        this rule is about to correct, so ``envs = RecordEpisodeStatistics(envs)`` must not
        hide that ``envs`` was a vector env.
        """
        result = self._follow(expr, "vector-kind", self._vector_kind_step)
        return EnvKind.UNKNOWN if result is _CYCLE or result is None else result  # type: ignore[return-value]

    def _vector_kind_step(self, expr: ast.AST) -> object:
        if isinstance(expr, ast.Call):
            if any(wrapper_rest(q) is not None for q in self.facts.qualified_names(expr.func)):
                first = first_argument(expr)
                if first is not None:
                    return self._follow(first, "vector-kind", self._vector_kind_step)
            return self.receivers.kind_of(expr)
        if isinstance(expr, ast.Name):
            values = self.facts.assigned_values(expr)
            if values is None:
                return self.receivers.kind_of(expr)
            kinds = [self._follow(v, "vector-kind", self._vector_kind_step) for v in values]
            known = [k for k in kinds if k is not _CYCLE]
            if not known:
                return _CYCLE if kinds else EnvKind.UNKNOWN
            return join_kinds(known)  # type: ignore[arg-type]
        return self.receivers.kind_of(expr)

    def make_call(self, expr: ast.AST) -> ast.Call | None:
        """The ``gym.make(...)`` call at the bottom of ``expr``'s wrapper stack, when it is clear."""
        result = self._follow(expr, "make-call", self._make_call_step)
        return result if isinstance(result, ast.Call) else None

    def _make_call_step(self, expr: ast.AST) -> object:
        if isinstance(expr, ast.Call):
            for q in self.facts.qualified_names(expr.func):
                rest = N.strip_gym_prefix(q)
                if rest in N.GYM_ENV_FACTORIES:
                    return expr
                first = first_argument(expr)
                if rest is not None and rest.startswith("wrappers.") and first is not None:
                    return self._follow(first, "make-call", self._make_call_step)
            return None
        if isinstance(expr, ast.Name):
            values = self.facts.assigned_values(expr)
            if values is None:
                return None
            found = [self._follow(v, "make-call", self._make_call_step) for v in values]
            found = [f for f in found if f is not _CYCLE]
            if not found:
                return _CYCLE if values else None
            makes = {id(f): f for f in found if f is not None}
            return next(iter(makes.values())) if len(makes) == 1 and None not in found else None
        return None

    def creation_makes(self, env: ast.expr) -> list[ast.Call]:
        """Every make call ``env`` may come from, through wrappers and assignments; [] if a path is unclear."""
        result = self._follow(env, "creation", self._creation_step)
        return list(result) if isinstance(result, tuple) else []

    def _creation_step(self, expr: ast.AST) -> object:
        if isinstance(expr, ast.Call):
            if is_make(self.facts, expr):
                return (expr,)
            wraps = any(wrapper_rest(q) is not None for q in self.facts.qualified_names(expr.func))
            local = self.receivers.local_class(expr.func)
            if wraps or (local is not None and self.receivers.is_gym_wrapper_class(local)):
                first = first_argument(expr)
                return self._follow(first, "creation", self._creation_step) if first is not None else None
            return None
        if isinstance(expr, ast.Name):
            values = self.facts.assigned_values(expr)
            if not values:
                return None
            found = [self._follow(v, "creation", self._creation_step) for v in values]
            found = [f for f in found if f is not _CYCLE]
            if not found:
                return _CYCLE
            if any(f is None for f in found):
                return None
            makes: dict[int, ast.Call] = {}
            for calls in found:
                if isinstance(calls, tuple):  # each path's make calls (None and cycles are out)
                    for make in calls:
                        makes.setdefault(id(make), make)
            return tuple(makes.values())
        return None

    def _follow(self, expr: ast.AST, fact: str, step: Callable[[ast.AST], object]) -> object:
        """``step(expr)``, memoized per node; a node being computed is a cycle (no evidence).

        Names are memoized by the scope and name they resolve to, so every read of ``env``
        after a dozen ``env = Wrapper(env)`` shares one answer: linear, not exponential.
        """
        if isinstance(expr, ast.Name):
            scope, _ = self.facts.resolve(expr.id, self.facts.scope_of(expr))
            key = (fact, id(scope), expr.id)
        else:
            key = (fact, id(expr), "")
        if key in self._memo:
            return self._memo[key]
        if key in self._in_progress:
            return _CYCLE
        if self._depth > MAX_DEPTH:
            return None
        self._in_progress.add(key)
        self._depth += 1
        try:
            result = step(expr)
        finally:
            self._depth -= 1
            self._in_progress.discard(key)
        if result is not _CYCLE:  # a cycle is an answer only from inside it
            self._memo[key] = result
        return result


def is_make(facts: ModuleFacts, call: ast.Call) -> bool:
    return any(N.strip_gym_prefix(q) in N.GYM_ENV_FACTORIES for q in facts.qualified_names(call.func))


def first_argument(call: ast.Call) -> ast.expr | None:
    """What LibCST called ``call.args[0]``: the first argument, positional or not."""
    if call.args:
        first = call.args[0]
        return first.value if isinstance(first, ast.Starred) else first
    return call.keywords[0].value if call.keywords else None
