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
closure; a method of ``self`` called, for ``self.env``. Reading an attribute of the env
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


class ResetOrder(RuleFamily):
    RULES = RULES

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        # only ``gym.make(...)`` envs are followed: no ``.make`` call, nothing to decide
        return context.profile.imports_gym and bool(facts.attribute_calls.get("make")) and "order_enforce" not in facts.text

    def decide(self) -> None:
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
            if isinstance(first, ast.Call) and isinstance(first.func, ast.Attribute):
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
        statements after ``statement`` in its block; None where another use comes first."""
        block = self._block_of(statement)
        if block is None:
            return None
        for later in block[block.index(statement) + 1 :]:
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
        return None

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
