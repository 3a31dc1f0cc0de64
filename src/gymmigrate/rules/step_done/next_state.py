"""GM302's ground truth: what a rewritten step's next state is, and which value reads of
its ``done`` mask bootstrapping from it.

``DoneStep`` is one four-target step whose done target is a name. The next state is
the step's observation target and the names computed from it after the step
(``next_state = np.reshape(next_state, shape)``); a read of ``done`` masks it when the
same transition or target reads that state (``r + gamma * (1 - done) * V(s2)``,
``memory.push(s, a, r, s2, done)``), also through a callee of the run that masks it there
(``facts/bootstrap.py``). Only such a read can become ``terminated``.
"""

from __future__ import annotations

import ast
import re
from dataclasses import dataclass

from gymmigrate.facts.bootstrap import next_state_factors, next_state_masks
from gymmigrate.facts.done_uses import (
    STORE_METHODS,
    loaded_names,
    multiplies_bare,
    stored_in_sequence,
    value_site,
)
from gymmigrate.facts.flow import bound_names, start
from gymmigrate.facts.module import FUNCTIONS, LOOPS, full_name, walk
from gymmigrate.rules.step_done.common import StepFamilyBase, StepNames


@dataclass(frozen=True)
class DoneStep:
    """A rewritten step whose done target is a name: its reads are planned together."""

    assign: ast.Assign
    done: ast.Name
    names: StepNames
    target: ast.Tuple | ast.List  # ``assign``'s only target, the unpacked values


class NextStateReads(StepFamilyBase):
    """Which reads of a step's ``done`` mask bootstrapping from its next state (mixed into the family)."""

    def _derived_names(self, step: DoneStep) -> set[str]:
        """The step's observation target and every name assigned, anywhere in its function,
        from an expression that reads one of them (in source order, without flow)."""

        def compute() -> set[str]:
            first = step.target.elts[0]
            if not isinstance(first, ast.Name) or first.id == "_":
                return set()
            names = {first.id}
            function = self.facts.enclosing_function(step.assign) or self.facts.tree
            assigns = sorted(
                (n for n in walk(function) if isinstance(n, ast.Assign) and n is not step.assign),
                key=lambda n: (n.lineno, n.col_offset),
            )
            for assign in assigns:
                if loaded_names(assign.value) & names:
                    names.update(name for target in assign.targets for name in bound_names(target))
            return names

        return self.facts.memo(("derived-next-names", id(step.assign)), compute)

    def _masks_next_state(self, read: ast.Name, step: DoneStep) -> bool:
        """Does this value read mask bootstrapping from the step's own next observation?

        Only there is ``terminated`` right: the transition stores the next state, or the
        target computes its value (``r + gamma * (1 - done) * V(s2)``, also through one
        name: ``mask = 1 - done``). A flag stored per step without the next state (an
        on-policy rollout whose GAE reads ``values[k + 1]`` of the following step) marks
        the episode boundary: after a reset that value belongs to the next episode, so
        the flag stays ``terminated or truncated``.
        """
        next_names = self._next_state_names(step)
        if not next_names:
            return False
        facts = self.facts
        if multiplies_bare(read, facts.parent):
            return False  # ``q(s2) * gamma * done``: an inverted mask (``_bare_factor``)
        site = value_site(read, facts)
        if repacks_step(facts.parent(read), read, step):
            return False  # ``(obs, reward, done, info)`` passed on: the step's own result, not a transition
        if self._reads_next_state(site, step, next_names):
            return True
        statement = facts.statement_of(read)
        function = facts.enclosing_function(step.assign) or facts.tree
        if isinstance(statement, ast.Assign) and site is statement.value and not isinstance(site, (ast.Dict, ast.Tuple, ast.List, ast.Set)):
            # ``mask = 1 - done`` read by a target that also reads the next state. A record
            # that holds the flag as one field (``exp = {"state": s, "terminal": done}``) is
            # no mask: a statement that reads it beside the next state (``exp["r"] = v(s2)``,
            # ``return exp, s2``) computes nothing from the flag.
            targets = {t.id for t in statement.targets if isinstance(t, ast.Name)}
            if targets and any(
                targets & names and names & next_names for names in self._statement_reads(function).values()
            ):
                return True
        if stored_in_sequence(read, facts):
            # separate lists: ``next_states.append(s2)`` beside ``dones.append(done)``
            return facts.memo(
                ("stores-next-state", id(step.assign)),
                lambda: any(self._stores_next_state(node, step, next_names) for node in walk(function)),
            )
        return False

    def _callee_masks(self, read: ast.Name, step: DoneStep) -> str | None:
        """The callee's text when ``read`` is an argument of a call that also passes the
        step's next state, and the callee (a def of this module, or of another module of
        the run) masks bootstrapping from that parameter with this one
        (``facts/bootstrap.py``). None when the call passes no next state or the callee
        cannot be followed: then the read is decided as before."""
        call = self.facts.parent(read)
        if isinstance(call, ast.keyword):
            call = self.facts.parent(call)
        if not isinstance(call, ast.Call) or call.func is read or any(isinstance(a, ast.Starred) for a in call.args):
            return None
        next_names = self._next_state_names(step)
        if not next_names:
            return None
        passed_next = [
            argument
            for argument in [*call.args, *(k.value for k in call.keywords)]
            if argument is not read and isinstance(argument, ast.Name) and self._reads_next_state(argument, step, next_names)
        ]
        if not passed_next:
            return None
        found = self._callee_signature(call.func)
        if found is None:
            return None
        params, masks = found

        def param_of(argument: ast.expr) -> str | None:
            for index, value in enumerate(call.args):
                if value is argument:
                    return params[index] if index < len(params) else None
            for keyword in call.keywords:
                if keyword.value is argument:
                    return keyword.arg
            return None

        flag = param_of(read)
        if flag is None or not any((flag, param_of(argument)) in masks for argument in passed_next):
            return None
        return self.facts.segment(call.func)

    def _bare_factor(self, read: ast.Name, step: DoneStep) -> str | None:
        """Where ``read`` is a bare factor of a value of the step's next state, the text that
        says so (``reward + q(s2) * gamma * done``, or a def of the file that computes that
        from its arguments): the legacy code bootstraps only at an episode's end, and
        ``terminated`` there would stop it bootstrapping on a time-limit truncation. None
        otherwise."""
        next_names = self._next_state_names(step)
        if not next_names:
            return None
        facts = self.facts
        if multiplies_bare(read, facts.parent):
            site = value_site(read, facts)
            if self._reads_next_state(site, step, next_names):
                return f"multiplies a value of the next state `{facts.segment(step.target.elts[0])}` here"
            return None
        call = facts.parent(read)
        if not isinstance(call, ast.Call) or read not in call.args or any(isinstance(a, ast.Starred) for a in call.args):
            return None
        function = self.receivers.local_function(call.func) or self.receivers.own_method(call.func)
        if function is None:
            return None
        params = tuple(a.arg for a in (*function.args.posonlyargs, *function.args.args))
        if isinstance(facts.parent(function), ast.ClassDef):
            params = params[1:]
        index = call.args.index(read)
        if index >= len(params):
            return None
        factors = next_state_factors(function)
        for position, argument in enumerate(call.args):
            if (
                position < len(params)
                and argument is not read
                and self._reads_next_state(argument, step, next_names)
                and (params[index], params[position]) in factors
            ):
                return (
                    f"is passed with the next state to `{facts.segment(call.func)}`, which multiplies a value of that "
                    f"state by it (line {function.lineno})"
                )
        return None

    def _callee_signature(self, func: ast.expr) -> tuple[tuple[str, ...], frozenset[tuple[str, str]]] | None:
        """The parameters a call binds by position (``self`` left out) and the callee's
        bootstrap masks; None when the callee cannot be followed."""
        function = self.receivers.local_function(func) or self.receivers.own_method(func)
        method = function is not None and isinstance(self.facts.parent(function), ast.ClassDef)
        if function is None and isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name):
            classes = self._instance_classes(func.value)
            if len(classes) == 1:
                classdef = next(iter(classes))
                if isinstance(classdef, ast.ClassDef):
                    function = next(
                        (s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == func.attr), None
                    )
                    method = True
                elif self.receivers.project is not None:
                    found = self.receivers.project.bootstrap_masks(f"{classdef}.{func.attr}")
                    return None if found is None else (found[0][1:], found[1])
        if function is None and self.receivers.project is not None and isinstance(func, ast.Name):
            qualified = self.facts.qualified_names(func)
            if len(qualified) == 1:
                found = self.receivers.project.bootstrap_masks(next(iter(qualified)))
                return found
        if function is None:
            return None
        params = tuple(a.arg for a in (*function.args.posonlyargs, *function.args.args))
        return (params[1:] if method else params), next_state_masks(function)

    def _instance_classes(self, owner: ast.Name) -> set[ast.ClassDef | str]:
        """What every binding of ``owner`` constructs: a class of this module, or the
        qualified name of an imported one (``agent = Agent(...)``)."""
        found: set[ast.ClassDef | str] = set()
        bindings = self.facts.bindings_of(owner)
        if not bindings:
            return found
        for binding in bindings:
            assign = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
            if not (isinstance(assign, ast.Assign) and isinstance(assign.value, ast.Call) and assign.targets == [binding]):
                return set()
            local = self.receivers.local_class(assign.value.func)
            if local is not None:
                found.add(local)
                continue
            qualified = self.facts.qualified_names(assign.value.func)
            if len(qualified) != 1:
                return set()
            found.add(next(iter(qualified)))
        return found

    def _reads_next_state(self, site: ast.AST, step: DoneStep, next_names: set[str]) -> bool:
        """``site`` reads the step's next state: a name of ``next_names`` whose binding before
        the read comes after the step. ``remember(obs, a, r, done)`` before ``obs = obs_`` reads
        the state the step started from (an on-policy rollout), not the next one."""
        steps_after = self._next_state_bindings(step)
        for node in walk(site):
            if isinstance(node, ast.Name) and node.id in next_names and isinstance(node.ctx, ast.Load):
                binding = self.flow.last_binding_of(node)
                if binding is not None and id(self.facts.statement_of(binding)) in steps_after:
                    return True
        return False

    def _next_state_bindings(self, step: DoneStep) -> set[int]:
        """The statements that bind a next-state name: the step and the assignments after it."""
        self._next_state_names(step)
        return self.facts.memo(("next-state-bindings", id(step.assign)), lambda: {id(step.assign)})

    def _next_state_names(self, step: DoneStep) -> set[str]:
        """The step's observation target and the names computed from it in the same function."""
        return self.facts.memo(("next-state-names", id(step.assign)), lambda: self._compute_next_state_names(step))

    def _compute_next_state_names(self, step: DoneStep) -> set[str]:
        first = step.target.elts[0]
        if not isinstance(first, ast.Name) or first.id == "_":
            return set()
        names = {first.id}
        bindings = self.facts.memo(("next-state-bindings", id(step.assign)), lambda: {id(step.assign)})
        function = self.facts.enclosing_function(step.assign) or self.facts.tree

        def sees_step(node: ast.Name, statement: ast.stmt) -> bool:
            if node.id == first.id and self.flow.dominates(step.assign, node, first):
                return True
            # ``next_state = np.reshape(next_state, shape)`` right after the step, then
            # ``next_state = np.append(state[:, :, 1:], next_state[..., None], axis=2)``
            # (frame stacking): each read sees the step's value or one computed from it
            # just above, the statement's own binding comes after it
            above = self.flow.binding_above(node, statement)
            holder: ast.AST | None = statement
            while above is None and isinstance(holder := self.facts.parent(holder), (ast.If, ast.With)):
                # ``if use_norm: s_ = norm(s_)``: the read sees what was bound above the ``if``
                above = self.flow.binding_above(node, holder)
            return above is not None and id(self.facts.statement_of(above)) in bindings

        def after_step(value: ast.AST, statement: ast.stmt) -> bool:  # reads this step's observation, not an earlier one
            return any(
                isinstance(node, ast.Name) and node.id in names and isinstance(node.ctx, ast.Load) and sees_step(node, statement)
                for node in walk(value)
            )

        # in source order, so a chain of reassignments is followed link by link
        assigns = sorted(
            (node for node in walk(function) if isinstance(node, ast.Assign)), key=lambda node: start(node)
        )
        for node in assigns:
            if node is not step.assign and len(node.targets) == 1:
                target = node.targets[0]
                if isinstance(target, ast.Name) and after_step(node.value, node):
                    names.add(target.id)
                    bindings.add(id(node))
                elif isinstance(target, (ast.Tuple, ast.List)) and isinstance(node.value, (ast.Tuple, ast.List)):
                    for element, value in zip(target.elts, node.value.elts):
                        if isinstance(element, ast.Name) and after_step(value, node):
                            names.add(element.id)
                            bindings.add(id(node))
        return names

    def _statement_reads(self, function: ast.AST) -> dict[int, set[str]]:
        def compute() -> dict[int, set[str]]:
            return {
                id(node): loaded_names(node)
                for node in walk(function)
                if isinstance(node, ast.stmt) and not isinstance(node, (*LOOPS, ast.If, ast.With, ast.Try, *FUNCTIONS))
            }

        return self.facts.memo(("statement-reads", id(function)), compute)

    def _stores_next_state(self, node: ast.AST, step: DoneStep, next_names: set[str]) -> bool:
        """``next_states.append(s2)`` or ``next_obs_buf[t] = s2`` that runs after the step, in its
        iteration: a replay memory kept in separate arrays. The store or the value must say
        "next state" (``next_``, ``new_``, ``s2``, ``s_``): a trajectory log that records each
        step's observation (``observations.append(obs)``) is not a replay memory."""
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr in STORE_METHODS:
            values: list[ast.AST] = list(node.args)
            store = node.func.value
        elif isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Subscript):
            values = [node.value]
            store = node.targets[0].value
        else:
            return False
        first = step.target.elts[0]
        if not isinstance(first, ast.Name):
            return False  # then ``next_names`` is empty: nothing below could match
        for value in values:
            for name in walk(value):
                if isinstance(name, ast.Name) and name.id in next_names and isinstance(name.ctx, ast.Load):
                    if not (says_next(name.id) or says_next(full_name(store) or "")):
                        continue
                    if name.id != first.id or self.flow.dominates(step.assign, name, first):
                        return True
        return False


_NEXT_WORDS = re.compile(r"(^|_|\.)(next|new)|next_?$|(^|_|\.)(s|o|obs|state|x)(2|_|p|tp1|_tp1|_next|_prime)$", re.IGNORECASE)


def says_next(name: str) -> bool:
    """``next_states``, ``new_obs``, ``s2``, ``s_``, ``obs_tp1``, ``self.next_obs_buf``."""
    last = name.rsplit(".", 1)[-1]
    return bool(_NEXT_WORDS.search(last)) or last.endswith("2")


def repacks_step(site: ast.AST | None, read: ast.Name, step: DoneStep) -> bool:
    """``(obs, reward, done, info)`` with the step's own four targets in their places: the
    legacy step result handed on (a worker's reply), whose done is the episode's end."""
    if not (isinstance(site, ast.Tuple) and len(site.elts) == len(step.target.elts) == 4 and site.elts[2] is read):
        return False
    return all(
        isinstance(mine, ast.Name) and isinstance(theirs, ast.Name) and mine.id == theirs.id
        for mine, theirs in zip(site.elts, step.target.elts)
    )
