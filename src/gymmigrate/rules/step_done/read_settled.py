"""What the code around a read of a rewritten step's ``done`` settles by its shape (GM302):
a test that chooses the transition's discount, a ``TimeLimit.truncated`` test that
already tells a time-limit end apart, a flag sent with the observation of the next
episode's reset, ``done and not <time-limit key>``, a flag in the four fields of a step
the run keeps, and the reads of a ``self.<attr>`` the step stores.

Separate from ``read_reports.py`` because these only answer questions about the code
around a read, and report nothing: ``read_reports`` turns the answers into findings.
``DoneSettledReads`` sits right above ``DoneBookkeeping`` in the family's resolution order.
"""

from __future__ import annotations

import ast

from gymmigrate.facts.class_shapes import is_batched_step_return, keeps_legacy_step
from gymmigrate.facts.done_uses import (
    DoneUse,
    classify_done_read,
    loaded_names,
)
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.module import own_returns, walk
from gymmigrate.rules.step_done.bookkeeping import DoneBookkeeping
from gymmigrate.rules.step_done.common import TIME_LIMIT_KEY
from gymmigrate.rules.step_done.next_state import DoneStep


class DoneSettledReads(DoneBookkeeping):
    """Questions about the code around a read of ``done`` (mixed into the family)."""

    def _discount_test(self, read: ast.expr) -> bool:
        """``if done: return ts.termination(obs, r)`` (or a 0 where the other return has the
        discount): the test of ``read`` chooses the transition's discount."""
        test: ast.AST = read
        parent = self.facts.parent(test)
        if isinstance(parent, ast.UnaryOp) and isinstance(parent.op, ast.Not):
            test, parent = parent, self.facts.parent(parent)
        return isinstance(parent, ast.If) and parent.test is test and _chooses_discount(parent, self.facts.enclosing_function(parent))

    def _split_by_time_limit(self, read: ast.Name, step: DoneStep) -> bool:
        """``if done:`` whose body tells a time-limit end apart from a terminal one by the
        step's ``info["TimeLimit.truncated"]`` (directly, or through a name bound from it
        alone in that body) before choosing the discount: GM303 makes that test
        ``truncated and not terminated``, so the body already ends a truncated transition with
        its discount kept and a terminated one without: nothing is left to decide."""
        branch = self.facts.parent(read)
        info = step.target.elts[-1] if step.target.elts else None
        if not (isinstance(branch, ast.If) and branch.test is read and isinstance(info, ast.Name)):
            return False
        flags: set[str] = set()
        for statement in branch.body:
            if (
                isinstance(statement, ast.Assign)
                and len(statement.targets) == 1
                and isinstance(statement.targets[0], ast.Name)
                and _only_time_limit_key(statement.value, info.id)
            ):
                flags.add(statement.targets[0].id)
                continue
            if isinstance(statement, ast.If):
                test = statement.test
                if (isinstance(test, ast.Name) and test.id in flags) or _only_time_limit_key(test, info.id):
                    return True
            if any(name in flags or name == info.id for name in _names_bound_within(statement)):
                return False  # the flag (or info) changes before the test
        return False

    def _self_attribute_data_reads(self, near: ast.AST, target: ast.expr) -> list[ast.Attribute]:
        """Reads of ``self.<attr>`` (``target``) in the class around ``near`` that feed a value."""
        if not (isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self"):
            return []
        classdef = self.facts.enclosing_class(near)
        if classdef is None:
            return []
        return [
            node
            for node in self.facts.attributes.get(target.attr, ())
            if isinstance(node, ast.Attribute)
            and isinstance(node.ctx, ast.Load)
            and isinstance(node.value, ast.Name)
            and node.value.id == "self"
            and self.facts.enclosing_class(node) is classdef
            and classify_done_read(node, self.facts) is DoneUse.DATA  # type: ignore[arg-type]
        ]

    def _sibling_block(self, statement: ast.stmt) -> list[ast.stmt] | None:
        """The statement list that holds ``statement`` directly."""
        found = Flow.of(self.facts).block_of(statement)
        return found[0] if found is not None else None

    def _valued_after_reset(self, read: ast.Name, step: DoneStep) -> tuple[str, ast.If] | None:
        """``R = 0.0 if done else v(state)`` after the step's loop, whose body ends the episode
        with ``if done: state = env.reset()`` (nothing after it rebinding either name): when
        the flag read is true, the state a bootstrap would value is the next episode's first
        one, so only the episode's end can guard it. The valued name and that ``if``; None
        when the code does not show it."""
        facts = self.facts
        node: ast.AST = read
        parent = facts.parent(node)
        negated = False
        if isinstance(parent, ast.UnaryOp) and isinstance(parent.op, ast.Not):
            node, negated, parent = parent, True, facts.parent(parent)
        if isinstance(parent, ast.IfExp) and parent.test is node:
            valued: list[ast.AST] = [parent.body if negated else parent.orelse]
        elif isinstance(parent, ast.If) and parent.test is node:
            valued = list(parent.body if negated else parent.orelse)
        else:
            return None
        derived = self._derived_names(step)
        names = {n.id for part in valued for n in walk(part) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load)}
        names &= derived
        block = self._sibling_block(step.assign)
        holder = facts.parent(step.assign)
        if not names or block is None or not isinstance(holder, (ast.For, ast.While, ast.AsyncFor)):
            return None
        if any(ancestor is holder for ancestor in facts.ancestors(read)):
            return None  # read inside the step's loop: the flag may come from before the reset
        later = block[block.index(step.assign) + 1 :]
        # Any input of the value replaced is enough: the value is then not the final state's
        # (``model((state, hx))`` with ``state`` reset; ``hx`` is the recurrent memory).
        for name in sorted(names):
            for index, statement in enumerate(later):
                if _replaces_on_done(statement, step.done.id, name):
                    if any({step.done.id, name} & _names_bound_within(s) for s in later[index + 1 :]):
                        break
                    return name, statement  # type: ignore[return-value]
        return None

    def _sent_with_reset_observation(self, read: ast.Name, step: DoneStep) -> bool:
        """``pipe.send((obs, reward, done, info, total))`` after
        ``if done: obs = env.reset()`` in the same block as the step: the observation sent
        with a true flag is the new episode's, so no receiver can bootstrap from the final
        one. No other element may read the observation."""
        site = self.facts.parent(read)
        holder = self.facts.parent(site) if isinstance(site, ast.Tuple) else None
        # a call's only argument (a return of the step's values is a step of its own: GM504)
        if not isinstance(holder, ast.Call) or holder.args != [site] or holder.keywords:
            return False
        first = step.target.elts[0] if step.target.elts else None
        if not isinstance(first, ast.Name):
            return False
        observation = first.id
        if not any(isinstance(e, ast.Name) and e.id == observation for e in site.elts):  # type: ignore[union-attr]
            return False
        if any(observation in loaded_names(e) for e in site.elts if not (isinstance(e, ast.Name) and e.id == observation)):  # type: ignore[union-attr]
            return False
        block = self._sibling_block(step.assign)
        statement = self.facts.statement_of(read)
        if block is None or statement not in block:
            return False
        between = block[block.index(step.assign) + 1 : block.index(statement)]
        if any(observation in _names_bound_within(s) for s in between if not _resets_on_done(s, step.done.id, observation)):
            return False
        return any(_resets_on_done(s, step.done.id, observation) for s in between)

    def _and_not_truncation(self, read: ast.Name, step: DoneStep) -> bool:
        """``failure = done and not limited`` where ``limited`` is bound once, after the step
        in its block, from the step's info's ``'TimeLimit.truncated'`` alone: the run turns
        that into the step's truncated (without terminated), so the expression is exactly
        ``terminated``."""
        parent = self.facts.parent(read)
        if not (isinstance(parent, ast.BoolOp) and isinstance(parent.op, ast.And) and len(parent.values) == 2 and parent.values[0] is read):
            return False
        other = parent.values[1]
        if not (isinstance(other, ast.UnaryOp) and isinstance(other.op, ast.Not) and isinstance(other.operand, ast.Name)):
            return False
        info = step.target.elts[-1] if step.target.elts else None
        if not isinstance(info, ast.Name):
            return False
        block = self._sibling_block(step.assign)
        statement = self.facts.statement_of(read)
        if block is None or statement not in block:
            return False
        between = block[block.index(step.assign) + 1 : block.index(statement)]
        flag = other.operand.id
        binders = [s for s in between if flag in _names_bound_within(s)]
        if len(binders) != 1 or not isinstance(binders[0], ast.Assign) or len(binders[0].targets) != 1:
            return False
        if any(read.id in _names_bound_within(s) for s in between):
            return False
        return _only_time_limit_key(binders[0].value, info.id)

    def _in_kept_batch_return(self, read: ast.Name) -> bool:
        """``read`` is in a stacked return of a step that keeps its four fields (a batch)."""
        statement = self.facts.statement_of(read)
        function = self.facts.enclosing_function(read)
        classdef = self.facts.enclosing_class(read)
        return (
            isinstance(statement, ast.Return)
            and function is not None
            and classdef is not None
            and function.name == "step"
            and keeps_legacy_step(classdef)
            and is_batched_step_return(statement.value, function)
        )

    def _in_kept_step_result(self, read: ast.Name) -> bool:
        """``read`` is the done of an ``(obs, reward, done, info)`` tuple that the ``step`` of a
        class keeping its four fields returns, directly or through one name it returns."""
        site = self.facts.parent(read)
        function = self.facts.enclosing_function(read)
        classdef = self.facts.enclosing_class(read)
        if not (
            isinstance(site, ast.Tuple)
            and len(site.elts) == 4
            and site.elts[2] is read
            and function is not None
            and classdef is not None
            and function.name == "step"
            and self.facts.parent(function) is classdef
            and keeps_legacy_step(classdef)
        ):
            return False
        statement = self.facts.statement_of(read)
        if isinstance(statement, ast.Return):
            return True
        if not (isinstance(statement, ast.Assign) and len(statement.targets) == 1 and isinstance(statement.targets[0], ast.Name)):
            return False
        name = statement.targets[0].id
        return any(isinstance(r.value, ast.Name) and r.value.id == name for r in own_returns(function))


def _names_bound_within(statement: ast.stmt) -> set[str]:
    """The names a statement (and the statements inside it) binds."""
    return {
        node.id for node in walk(statement) if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store)
    }


def _replaces_on_done(statement: ast.stmt, done: str, name: str) -> bool:
    """``if done: ...; name = prepro(env.reset())``: the body binds ``name`` (alone, or first of
    an unpack) from a value that calls some ``x.reset(...)``, unconditionally."""
    if not (isinstance(statement, ast.If) and isinstance(statement.test, ast.Name) and statement.test.id == done):
        return False
    for inner in statement.body:
        if not isinstance(inner, ast.Assign) or len(inner.targets) != 1:
            continue
        target = inner.targets[0]
        if isinstance(target, (ast.Tuple, ast.List)) and target.elts:
            target = target.elts[0]
        if isinstance(target, ast.Name) and target.id == name and any(
            isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute) and n.func.attr == "reset" for n in walk(inner.value)
        ):
            return True
    return False


def _resets_on_done(statement: ast.stmt, done: str, observation: str) -> bool:
    """``if done: observation = env.reset()`` (or ``env.reset()[0]``, or the first of an unpack)."""
    if not (isinstance(statement, ast.If) and isinstance(statement.test, ast.Name) and statement.test.id == done):
        return False
    for inner in statement.body:
        if not isinstance(inner, ast.Assign) or len(inner.targets) != 1:
            continue
        target, value = inner.targets[0], inner.value
        if isinstance(target, ast.Tuple) and target.elts:
            target = target.elts[0]
        if isinstance(value, ast.Subscript):
            value = value.value
        if (
            isinstance(target, ast.Name)
            and target.id == observation
            and isinstance(value, ast.Call)
            and isinstance(value.func, ast.Attribute)
            and value.func.attr == "reset"
        ):
            return True
    return False


def _only_time_limit_key(value: ast.expr, info: str) -> bool:
    """``info['TimeLimit.truncated']``, ``info.get('TimeLimit.truncated', False)``, or
    ``'TimeLimit.truncated' in info and`` one of them: a lookup of that key of ``info``,
    which GM303 replaces by ``truncated and not terminated`` (a bare membership test
    becomes ``truncated`` alone, and ``done and not truncated`` is not ``terminated``)."""
    if isinstance(value, ast.BoolOp) and isinstance(value.op, ast.And):
        parts = value.values
        return any(_time_limit_lookup(p, info) for p in parts) and all(
            _time_limit_lookup(p, info) or _time_limit_membership(p, info) for p in parts
        )
    return _time_limit_lookup(value, info)


def _is_key(node: ast.AST) -> bool:
    return isinstance(node, ast.Constant) and node.value == TIME_LIMIT_KEY


def _time_limit_lookup(node: ast.expr, info: str) -> bool:
    if isinstance(node, ast.Subscript):
        return isinstance(node.value, ast.Name) and node.value.id == info and _is_key(node.slice)
    return (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and node.func.attr == "get"
        and isinstance(node.func.value, ast.Name)
        and node.func.value.id == info
        and bool(node.args)
        and _is_key(node.args[0])
        and all(isinstance(a, ast.Constant) and a.value in (False, None) for a in node.args[1:])
    )


def _time_limit_membership(node: ast.expr, info: str) -> bool:
    return (
        isinstance(node, ast.Compare)
        and len(node.ops) == 1
        and isinstance(node.ops[0], ast.In)
        and _is_key(node.left)
        and isinstance(node.comparators[0], ast.Name)
        and node.comparators[0].id == info
    )


def _chooses_discount(branch: ast.If, function: ast.AST | None) -> bool:
    """One side of ``branch`` ends the transition without a discount: a ``termination(...)``
    call (dm_env, tf_agents), a ``discount``-named store of 0, or a returned tuple with 0
    where another return of ``function`` puts a ``discount``-named value."""
    discount_slots = {
        index
        for ret in (own_returns(function) if function is not None else [])
        if isinstance(ret.value, ast.Tuple)
        for index, element in enumerate(ret.value.elts)
        if any("discount" in _word(n).lower() for n in walk(element))
    }
    for statement in [*branch.body, *branch.orelse]:
        for node in walk(statement):
            if isinstance(node, ast.Call) and _word(node.func) == "termination":
                return True
            if isinstance(node, ast.Assign) and _zero(node.value) and any("discount" in _word(t).lower() for t in node.targets):
                return True
            if isinstance(node, ast.Return) and isinstance(node.value, ast.Tuple):
                if any(_zero(e) and i in discount_slots for i, e in enumerate(node.value.elts)):
                    return True
    return False


def _word(node: ast.AST) -> str:
    return node.id if isinstance(node, ast.Name) else node.attr if isinstance(node, ast.Attribute) else ""


def _zero(node: ast.AST) -> bool:
    return isinstance(node, ast.Constant) and not isinstance(node.value, bool) and node.value == 0
