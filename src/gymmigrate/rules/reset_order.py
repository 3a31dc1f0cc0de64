"""GM209: an env ``gym.make`` made, stepped or rendered before its first ``reset()``.

Gymnasium's ``make`` wraps every env in ``OrderEnforcing``, whose ``step()`` and ``render()``
raise ``ResetNeeded`` until ``reset()`` has been called (Gymnasium 1.4
``wrappers/common.py::OrderEnforcing``). Gym before 0.21 let a program step an env its
``__init__`` had built: tests that make an env and step it at once, demos that render
first. The step itself is rewritten as any other (GM301); the order is reported at the
first ``step()``/``render()`` of the make's env, and not rewritten: a ``reset()`` inserted
after the make may draw from the env's random stream or build another first state than
``__init__`` did.

Flow-sensitive in the block that holds ``env = gym.make(...)`` (or ``self.env = ...`` in a
method): the statements after it are read in order, and the first one that uses the env
decides. A step or render there, before anything else of the env, is reported. Anything
else ends the search without an item, where a reset may have run: a ``reset()`` (or a
legacy ``seed()``, which becomes one) anywhere in the statement, even only in a branch or on
a later pass of the loop that steps; the env handed to a helper, rebound, or reached by a
closure; a method of ``self`` called, for ``self.env``. A make that ends its branch of an
``if`` unused is followed past the ``if`` where every branch binds the name to such a make. Reading an attribute of the env
(``env.action_space``) or calling another of its methods resets no wrapper (only the
wrapper's own ``reset()`` lets it step) and is passed over. A module-level env that a function of the module reads is left alone (the
function may reset it between). A file that spells ``order_enforce`` (a registration that
turns the wrapper off) is left alone.
"""

from __future__ import annotations

import ast
from collections.abc import Iterator
from itertools import takewhile

from gymmigrate.facts.flow import Flow
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts, walk
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext, Rule, RuleFamily

RULES = (
    Rule(
        "GM209",
        "step or render before reset",
        FixKind.FLAG,
        "An env `gym.make` made that is stepped or rendered before any `reset()` is reported: "
        "Gymnasium's `make` adds `OrderEnforcing`, which raises `ResetNeeded`.",
    ),
)

_ORDERED = frozenset({"step", "render"})
_SCOPES = (*FUNCTIONS, ast.Lambda, ast.ClassDef)
_RESETS = frozenset({"reset", "seed"})  # a legacy seed() becomes reset(seed=...) (GM203)
_READ = object()  # a use of the env that cannot reset it
_OPEN = object()  # the statements ran out with the env neither used nor reset


class ResetOrder(RuleFamily):
    RULES = RULES

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        # only ``gym.make(...)`` envs are followed: no ``.make`` call, nothing to decide
        return context.profile.imports_gym and bool(facts.attribute_calls.get("make")) and "order_enforce" not in facts.text

    def decide(self) -> None:
        reported: set[int] = set()  # one item per call: the makes of an if's branches reach the same render
        for call in self.facts.attribute_calls.get("make", ()):
            if self.facts.qualified_names(call.func) != {"gym.make"}:
                continue
            statement = self.facts.parent(call)
            if not (isinstance(statement, ast.Assign) and statement.value is call and len(statement.targets) == 1):
                continue
            target = statement.targets[0]
            if isinstance(target, ast.Name):
                if self.facts.enclosing_function(statement) is None and self._read_by_a_function(target):
                    continue
            elif not (isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and self.receivers.is_self(target.value)):
                continue
            first = self._first_use_before_reset(statement, target)
            if isinstance(first, ast.Call) and isinstance(first.func, ast.Attribute) and id(first) not in reported:
                reported.add(id(first))
                method = first.func.attr
                self.report(
                    first,
                    "GM209",
                    f"{method}() before any reset() of the env gym.make made at line {call.lineno}: Gymnasium's make adds "
                    "OrderEnforcing, which raises ResetNeeded here; call env.reset() first (the first episode's state may "
                    "differ from the one __init__ built, and a reset may draw from the env's random stream)",
                )

    def _first_use_before_reset(self, statement: ast.stmt, target: ast.expr) -> ast.Call | object | None:
        """The ``step``/``render`` call that is the first use of ``target``'s env in the
        statements after ``statement`` in its block (and, for a make in a branch of an
        ``if`` whose every branch makes the env, after the ``if``); None where another use
        comes first."""
        block = self._block_of(statement)
        if block is None:
            return None
        found = self._scan(block[block.index(statement) + 1 :], target)
        if found is _OPEN and isinstance(target, ast.Name):
            found = self._after_branches(statement, target)
        return None if found is _OPEN else found

    def _scan(self, statements: list[ast.stmt], target: ast.expr) -> ast.Call | object | None:
        """The first use of the env in ``statements`` that decides: a step/render call, None
        for a use where a reset may run, ``_OPEN`` where nothing uses the env."""
        for later in statements:
            if self._stores(later, target):
                return None
            for node in self._uses(later, target):
                if any(isinstance(a, _SCOPES) for a in self._ancestors_within(node, later)):
                    return None  # a closure holds it: it may run, and reset, at any time
                found = self._event(node, target)
                if found is _READ:
                    continue
                if found is not None and self._reset_on_an_earlier_pass(node, later, target):
                    return None
                return found
        return _OPEN

    def _after_branches(self, statement: ast.stmt, target: ast.Name) -> ast.Call | object | None:
        """For a make that ends its branch of an ``if`` unused: where every branch of the
        ``if`` (through ``elif``) likewise binds the name to an unused make, the env after
        the ``if`` is a fresh make whichever branch ran, so the search goes on after it."""
        current: ast.stmt = statement
        while True:
            holder = self.facts.parent(current)
            if not isinstance(holder, ast.If) or not self._every_branch_makes(holder, target):
                return None
            block = self._block_of(holder)
            if block is None:
                return None
            found = self._scan(block[block.index(holder) + 1 :], target)
            if found is not _OPEN:
                return found
            current = holder

    def _every_branch_makes(self, branching: ast.If, target: ast.Name) -> bool:
        """Each branch of ``branching`` ends with ``target`` bound by ``gym.make`` and unused
        since. A missing ``else`` counts only where no other binding of the name can reach
        past the ``if`` (none before it in its scope, and no loop around it to bring a
        later one back): the name is then unbound on that path, and a use raises anyway."""
        for branch in (branching.body, branching.orelse):
            if not branch:
                if not self._nothing_else_binds(branching, target):
                    return False
                continue
            last = branch[-1]
            if isinstance(last, ast.If) and self._every_branch_makes(last, target):
                continue
            makes = [i for i, s in enumerate(branch) if self._is_make_of(s, target.id)]
            if not makes or self._scan(branch[makes[-1] + 1 :], branch[makes[-1]].targets[0]) is not _OPEN:  # type: ignore[attr-defined]
                return False
        return True

    def _is_make_of(self, statement: ast.stmt, name: str) -> bool:
        return (
            isinstance(statement, ast.Assign)
            and len(statement.targets) == 1
            and isinstance(statement.targets[0], ast.Name)
            and statement.targets[0].id == name
            and isinstance(statement.value, ast.Call)
            and self.facts.qualified_names(statement.value.func) == {"gym.make"}
        )

    def _nothing_else_binds(self, branching: ast.If, target: ast.Name) -> bool:
        parent = self.facts.parent(branching)
        while isinstance(parent, ast.If) and parent.orelse == [branching]:  # an elif: judge the whole chain
            branching, parent = parent, self.facts.parent(parent)
        scope = self.facts.enclosing_function(branching)
        if scope is not None and any(a.arg == target.id for a in ast.walk(scope.args) if isinstance(a, ast.arg)):
            return False  # a parameter reaches the branch that makes nothing
        if any(isinstance(a, (ast.For, ast.AsyncFor, ast.While)) for a in takewhile(lambda a: a is not scope, self.facts.ancestors(branching))):
            return False
        for node in walk(scope if scope is not None else self.facts.tree):
            if isinstance(node, ast.Name) and node.id == target.id and not isinstance(node.ctx, ast.Load):
                if self.facts.enclosing_function(node) is scope and node.lineno <= (branching.end_lineno or branching.lineno):
                    parent = self.facts.parent(node)
                    if not (isinstance(parent, ast.stmt) and self._is_make_of(parent, target.id) and self._within(parent, branching)):
                        return False
        return True

    def _within(self, node: ast.AST, outer: ast.AST) -> bool:
        return any(a is outer for a in self.facts.ancestors(node))

    def _reset_on_an_earlier_pass(self, name: ast.Name, statement: ast.stmt, target: ast.expr) -> bool:
        """A loop around the step (within ``statement``) also uses the env otherwise than to
        step, render or read it: a pass before may have reset it (a worker that steps or
        resets as its commands say)."""
        for loop in self._ancestors_within(name, statement):
            if not isinstance(loop, (ast.For, ast.AsyncFor, ast.While)):
                continue
            if any(self._event(other, target) is None for other in self._uses(loop, target)):
                return True
        if isinstance(statement, (ast.For, ast.AsyncFor, ast.While)):
            return any(self._event(other, target) is None for other in self._uses(statement, target))
        return False

    def _block_of(self, statement: ast.stmt) -> list[ast.stmt] | None:
        found = Flow.of(self.facts).block_of(statement)
        return found[0] if found is not None else None

    def _uses(self, statement: ast.stmt, target: ast.expr) -> list[ast.Name]:
        """Reads of the env's name (of ``self``, for ``self.env``) in ``statement``, in source order."""
        name = target.value.id if isinstance(target, ast.Attribute) else target.id  # type: ignore[attr-defined]
        found = [n for n in ast.walk(statement) if isinstance(n, ast.Name) and n.id == name and isinstance(n.ctx, ast.Load)]
        if isinstance(target, ast.Name):
            found = [n for n in found if target in self.facts.bindings_of(n)]
        return sorted(found, key=lambda n: (n.lineno, n.col_offset))

    def _event(self, name: ast.Name, target: ast.expr) -> ast.Call | object | None:
        """What a read of the env's name (of ``self``) does: ``_READ`` where it resets nothing
        (an attribute read, ``env.action_space``, ``self.size``, or a call of another method
        of the env); the call for ``env.step(...)``/``env.render(...)``; None for anything
        else (a reset or seed, the env handed on, a method of ``self`` called), where a reset
        may run."""
        parent = self.facts.parent(name)
        if not (isinstance(parent, ast.Attribute) and parent.value is name):
            return None
        member: ast.AST | None = parent
        if isinstance(target, ast.Attribute):
            if parent.attr != target.attr:
                return None if self._called(parent) else _READ
            member = self.facts.parent(parent)
            if not (isinstance(member, ast.Attribute) and member.value is parent):
                return None
        assert isinstance(member, ast.Attribute)
        if not self._called(member):
            return _READ
        if member.attr in _ORDERED:
            return self.facts.parent(member)
        # Only the wrapper's own reset() lets it step: another method of the env (its own,
        # forwarded) resets no wrapper, even where it resets the env inside.
        return None if member.attr in _RESETS else _READ

    def _called(self, attribute: ast.Attribute) -> bool:
        call = self.facts.parent(attribute)
        return isinstance(call, ast.Call) and call.func is attribute

    def _stores(self, statement: ast.stmt, target: ast.expr) -> bool:
        for node in ast.walk(statement):
            if isinstance(target, ast.Name) and isinstance(node, ast.Name) and node.id == target.id and not isinstance(node.ctx, ast.Load):
                return True
            if (
                isinstance(target, ast.Attribute)
                and isinstance(node, ast.Attribute)
                and not isinstance(node.ctx, ast.Load)
                and node.attr == target.attr
                and isinstance(node.value, ast.Name)
                and node.value.id == target.value.id  # type: ignore[attr-defined]
            ):
                return True
        return False

    def _ancestors_within(self, node: ast.AST, statement: ast.stmt) -> Iterator[ast.AST]:
        return takewhile(lambda ancestor: ancestor is not statement, self.facts.ancestors(node))

    def _read_by_a_function(self, target: ast.Name) -> bool:
        """A def or class body of the module reads the module-level name ``target`` binds."""
        for node in walk(self.facts.tree):
            if isinstance(node, ast.Name) and node.id == target.id and isinstance(node.ctx, ast.Load):
                if self.facts.enclosing_function(node) is None and self.facts.enclosing_class(node) is None:
                    continue
                if any(isinstance(b, ast.Name) and b.id == target.id and self.facts.enclosing_function(b) is None for b in self.facts.bindings_of(node)):
                    return True
        return False
