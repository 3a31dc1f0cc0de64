"""Reads of a rewritten step's ``done`` that only keep an episode's books (GM302).

A running value reset where an episode ended, a flag handed to a method that only tests
it, a flag kept to choose a real reset, a dead ``_step`` hook's return: they need the
episode's end, whatever ended it, so they stay ``terminated or truncated``.
"""

from __future__ import annotations

import ast

from gymmigrate.facts.module import walk
from gymmigrate.rules.step_done.next_state import DoneStep
from gymmigrate.rules.step_done.read_stores import DoneStoreReads
from gymmigrate.rules.step_done.read_uses import resets


class DoneBookkeeping(DoneStoreReads):
    """Reads of ``done`` that only keep the books of an episode (mixed into the family):
    they need the episode's end, whatever ended it, and never meet a next-state value, so
    ``terminated or truncated`` is what they should read and nothing is to decide."""

    def _bookkeeping(self, read: ast.Name, step: DoneStep, owned: bool) -> str | None:
        """What the read does, where the code shows it only keeps the books; else None.
        ``owned``: the step certainly binds the value read (else only a dead hook's return
        counts: whatever its value, Gymnasium never reads it)."""
        statement = self.facts.statement_of(read)
        function = self.facts.enclosing_function(read)
        names = step.names
        if isinstance(statement, ast.Return) and function is not None and function.name == "_step":
            if isinstance(self.facts.parent(function), ast.ClassDef):
                return (
                    "is returned by `_step`, a gym < 0.9 hook Gymnasium never calls: what it returns is decided with "
                    "the hook (GM616: renamed `step`, a second run migrates its contract)"
                )
        if not owned:
            return None
        what = None
        if self._resets_running_value(read, statement):
            what = "only resets a running value (an accumulated return or count) where an episode ended"
        elif (callee := self._tests_only_in_callee(read, step)) is not None:
            what = f"is handed to `{callee}`, which only tests it to close an episode's books"
        elif (flag := self._decides_real_reset(read, statement)) is not None:
            what = f"is kept in `{flag}`, which the class reads only to choose a real reset of the env"
        if what is None:
            return None
        return (
            f"{what}: it stays `{names.terminated} or {names.truncated}`, the episode's end legacy `done` was; no "
            "next-state value depends on it"
        )

    def _decides_real_reset(self, read: ast.Name, statement: ast.AST | None) -> str | None:
        """``self.needs_real_reset = done or info.get(...)`` where every read of the attribute
        in the class is an ``if`` test choosing whether to reset the env (a life-loss wrapper's
        game-over book): it needs the episode's end, however it ended. Returns the attribute's
        text; None otherwise."""
        if not (isinstance(statement, ast.Assign) and len(statement.targets) == 1):
            return None
        target = statement.targets[0]
        value = statement.value
        operands = value.values if isinstance(value, ast.BoolOp) and isinstance(value.op, ast.Or) else [value]
        if read not in operands:
            return None
        if not (isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self"):
            return None
        classdef = self.facts.enclosing_class(statement)
        if classdef is None:
            return None
        loads = [
            node
            for node in self.facts.attributes.get(target.attr, ())
            if isinstance(node.ctx, ast.Load)
            and isinstance(node.value, ast.Name)
            and node.value.id == "self"
            and self.facts.enclosing_class(node) is classdef
        ]
        if not loads:
            return None
        for node in loads:
            test: ast.AST = node
            parent = self.facts.parent(test)
            if isinstance(parent, ast.UnaryOp) and isinstance(parent.op, ast.Not):
                test, parent = parent, self.facts.parent(parent)
            if not (isinstance(parent, ast.If) and parent.test is test and resets(parent)):
                return None
        return self.facts.segment(target)

    def _resets_running_value(self, read: ast.Name, statement: ast.AST | None) -> bool:
        """``self.ret[done] = 0.`` or ``if done: self.ret = 0`` (nothing else in the branch),
        where the target accumulates elsewhere in the class or function (``self.ret =
        self.ret * gamma + r``, ``total += r``): a bootstrap value is computed, not summed."""
        if isinstance(statement, ast.Assign) and len(statement.targets) == 1:
            target = statement.targets[0]
            if isinstance(target, ast.Subscript) and target.slice is read and _constant(statement.value):
                return self._accumulates(target.value, statement)
            return False
        if isinstance(statement, ast.If) and statement.test is read and not statement.orelse:
            return all(
                isinstance(child, ast.Assign)
                and len(child.targets) == 1
                and _constant(child.value)
                and self._accumulates(child.targets[0], statement)
                for child in statement.body
            )
        return False

    def _accumulates(self, target: ast.expr, near: ast.AST) -> bool:
        """``target`` (a name or ``self.x``) is summed into in the class (or function) of ``near``."""
        text = self.facts.segment(target)
        if not text or not isinstance(target, (ast.Name, ast.Attribute)):
            return False
        scope = self.facts.enclosing_class(near) or self.facts.enclosing_function(near)
        if scope is None:
            return False
        for node in walk(scope):
            if isinstance(node, ast.AugAssign) and self.facts.segment(node.target) == text:
                return True
            if (
                isinstance(node, ast.Assign)
                and len(node.targets) == 1
                and self.facts.segment(node.targets[0]) == text
                and isinstance(node.value, ast.BinOp)
                and any(self.facts.segment(n) == text for n in walk(node.value) if isinstance(n, (ast.Name, ast.Attribute)))
            ):
                return True
        return False

    def _tests_only_in_callee(self, read: ast.Name, step: DoneStep) -> str | None:
        """``self.update(ob, rew, done, info)`` where the method (a def of the module) reads
        its flag parameter only as an ``if`` test and never reads the parameter that gets
        the next observation: an episode-statistics hook."""
        call = self.facts.parent(read)
        if not isinstance(call, ast.Call) or read not in call.args or any(isinstance(a, ast.Starred) for a in call.args):
            return None
        function = self.receivers.local_function(call.func) or self.receivers.own_method(call.func)
        if function is None:
            return None
        params = [a.arg for a in (*function.args.posonlyargs, *function.args.args)]
        if isinstance(self.facts.parent(function), ast.ClassDef) and params and isinstance(call.func, ast.Attribute):
            params = params[1:]  # ``self``
        index = call.args.index(read)
        if index >= len(params):
            return None
        flag = params[index]
        observation = step.target.elts[0]
        next_params = {
            params[i]
            for i, argument in enumerate(call.args)
            if i < len(params) and isinstance(argument, ast.Name) and isinstance(observation, ast.Name) and argument.id == observation.id
        }
        if any(isinstance(n, ast.Name) and n.id in next_params for n in walk(function)):
            return None  # it reads the next observation: a target may be computed from it
        reads = [n for n in walk(function) if isinstance(n, ast.Name) and n.id == flag]
        if not reads or any(not isinstance(n.ctx, ast.Load) for n in reads):
            return None
        for node in reads:
            test = self.facts.parent(node)
            if not (isinstance(test, ast.If) and test.test is node):
                return None
        return self.facts.segment(call.func)


def _constant(node: ast.AST) -> bool:
    """``0``, ``0.``, ``False``, ``None``, ``-1``."""
    if isinstance(node, ast.UnaryOp):
        node = node.operand
    return isinstance(node, ast.Constant)
