"""What a read of a rewritten step's ``done`` is for, where the code shows it (GM302).

Beyond the masks of ``next_state``: the flag choosing a bootstrap target
(``R = 0.0 if done else v(s2)``), the None mask of the PyTorch DQN tutorial
(``next_state = None if done else s2``), a separate bootstrap flag computed from it
(``dw = done and not truncated``), the step's result handed on whole (an env-like
reply), and a flag only ever used to end a loop. Where the flag is stored (a rollout
store without the next state, an episode's store) is ``read_stores``; a read that only
keeps an episode's books is ``bookkeeping``. Each answers a question; ``read_reports``
turns the answers into findings.
"""

from __future__ import annotations

import ast

from gymmigrate.facts.done_uses import (
    DoneUse,
    classify_done_read,
    loaded_names,
)
from gymmigrate.facts.flow import bound_names, end, start
from gymmigrate.facts.limit_tests import if_setting_true, is_step_limit
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts, walk
from gymmigrate.rules.step_done.next_state import DoneStep, NextStateReads


class DoneReadUses(NextStateReads):
    """What a read of ``done`` is for, beyond the next-state masks (mixed into the family)."""

    def _dominating_step(self, read: ast.Name, done: ast.Name) -> ast.Assign | None:
        """The four-target step that certainly binds the value ``read`` sees, if any.

        Only the statement holding the last binding before the read can dominate it, so
        one lookup replaces a test against every step.
        """
        binding = self.flow.last_binding_before(read, done)
        if binding is None:
            return None
        step = self.facts.statement_of(binding)
        if (
            step in self.legacy_unpacks
            and any(done.id in bound_names(t) for t in step.targets)
            and (self.flow.dominates(step, read, done) or self.flow.left_by_loop(step, read))
        ):
            return step
        return None

    def _step_past_own_limit(self, read: ast.Name, done: ast.Name) -> tuple[ast.Assign, ast.If] | None:
        """``obs2, r, done, info = env.step(a)``, then ``if <step limit>: done = True`` (the
        loop's own cap, alone in its ``if``), then ``read``: the step that dominates the cap
        and the read, and the cap's ``if``. The cap only ends the episode on a count, a
        truncation, which a bootstrap mask leaves out as it leaves out the env's own."""
        binding = self.flow.last_binding_before(read, done)
        if binding is None:
            return None
        line = self.facts.statement_of(binding)
        cap = if_setting_true(line, self.facts.parent(line))
        if cap is None or cap.orelse or cap.body != [line] or not is_step_limit(cap.test):
            return None
        if not self.flow.dominates(cap, read, done):
            return None
        step = self._dominating_step(cap.test, done)  # type: ignore[arg-type]
        return None if step is None else (step, cap)

    def _bootstrap_choice(self, read: ast.Name, step: DoneStep, dominated: bool) -> bool | None:
        """``R = 0.0 if done else v(s2)``, ``if done: y = r`` / ``else: y = r + gamma * q(s2)``,
        ``if not done: y += gamma * q(s2)``: the flag chooses between a value computed from
        the step's next state and one that is not, so it masks bootstrapping from that state.
        Returns whether the test can simply read ``terminated`` (a conditional expression, or
        branches that only assign: a ``break`` there is loop control, which stays ``done``);
        None when the flag makes no such choice. A None on the done side is the next state
        itself (``_none_mask``). ``dominated``: the step certainly binds the flag read, and
        the next state is what the step's observation certainly gave; otherwise any name
        computed from that observation counts (the read is reported, never rewritten)."""
        facts = self.facts
        node: ast.AST = read
        negated = False
        parent = facts.parent(node)
        if isinstance(parent, ast.UnaryOp) and isinstance(parent.op, ast.Not):
            node, negated, parent = parent, True, facts.parent(parent)
        if dominated:
            next_names = self._next_state_names(step)

            def reads(parts: list[ast.AST]) -> bool:
                return any(self._reads_next_state(part, step, next_names) for part in parts)
        else:
            next_names = self._derived_names(step)

            def reads(parts: list[ast.AST]) -> bool:
                return any(n.id in next_names for part in parts for n in walk(part) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load))

        if not next_names:
            return None
        if isinstance(parent, ast.IfExp) and parent.test is node:
            when_done, otherwise = (parent.orelse, parent.body) if negated else (parent.body, parent.orelse)
            # ``state = env.reset() if done else obs``: the next state itself, or a new episode
            if isinstance(otherwise, ast.Name) or _is_none(when_done) or resets(when_done):
                return None
            statement = facts.statement_of(parent)
            if (
                isinstance(statement, ast.Assign)
                and statement.value is parent
                and (carried := {t.id for t in statement.targets if isinstance(t, ast.Name)})
                and carried & loaded_names(otherwise)
                and not carried & loaded_names(when_done)
            ):
                # ``hx = zeros if done else hx.detach()``: the value carried from the previous
                # step (a recurrent state, a running sum) restarts with the episode, no target
                return None
            if not reads([otherwise]) or reads([when_done]):
                return None
            return True
        if isinstance(parent, ast.If) and parent.test is node:
            done_branch, other = (parent.orelse, parent.body) if negated else (parent.body, parent.orelse)
            if any(isinstance(s, ast.Assign) and _is_none(s.value) for s in done_branch) or any(map(resets, done_branch)):
                return None  # ``if done: next_state = None`` (the None mask), ``if done: obs = env.reset()``
            # One target chosen both ways (``if done: y = r`` / ``else: y = r + gamma * q(s2)``), or
            # only added to when not done (``if not done: y += gamma * q(s2)``): a value, not a
            # state to go on from (``if not done: state = preprocess(s2)``).
            chosen = {name for s in done_branch if isinstance(s, (ast.Assign, ast.AnnAssign)) for name in _assigned(s)}
            computed: list[ast.AST] = [
                s.value
                for s in other
                if ((isinstance(s, (ast.Assign, ast.AnnAssign)) and _assigned(s) & chosen) or (not done_branch and isinstance(s, ast.AugAssign)))
                and s.value is not None
                and not isinstance(s.value, ast.Name)
            ]
            if not reads(computed) or reads(list(done_branch)):
                return None
            return all(isinstance(s, (ast.Assign, ast.AugAssign, ast.AnnAssign, ast.Pass)) for s in [*done_branch, *other])
        return None

    def _none_mask(self, read: ast.Name, step: DoneStep) -> tuple[str, bool, str | None] | None:
        """``next_state = None if done else s2`` or ``if done: next_state = None`` (the PyTorch
        DQN tutorial's terminal transition): the flag decides whether the transition stored
        afterwards has a next state to bootstrap from. Returns the masked name and whether the
        test can simply read ``terminated``: only when the branches do nothing but assign
        (a ``break`` there is loop control, which must stay ``done``), and the callee that also
        reads the None as the episode's end (then the test stays ``done``). None: not such a mask."""
        facts = self.facts
        node: ast.AST = read
        negated = False
        parent = facts.parent(node)
        if isinstance(parent, ast.UnaryOp) and isinstance(parent.op, ast.Not):
            node, negated, parent = parent, True, facts.parent(parent)
        next_names = self._next_state_names(step)
        if isinstance(parent, ast.IfExp) and parent.test is node:
            when_done = parent.orelse if negated else parent.body
            statement = facts.statement_of(parent)
            if not (_is_none(when_done) and isinstance(statement, ast.Assign) and statement.value is parent):
                return None
            targets = [t.id for t in statement.targets if isinstance(t, ast.Name)]
            if len(targets) != 1 or targets[0] not in next_names or not self._stored_later(statement, targets[0]):
                return None
            boundary = self._none_ends_episode_in_callee(statement, targets[0])
            return targets[0], boundary is None, boundary
        if isinstance(parent, ast.If) and parent.test is node:
            done_branch, other = (parent.orelse, parent.body) if negated else (parent.body, parent.orelse)
            masked = [
                s.targets[0].id
                for s in done_branch
                if isinstance(s, ast.Assign) and len(s.targets) == 1 and isinstance(s.targets[0], ast.Name) and _is_none(s.value)
            ]
            masked = [name for name in masked if name in next_names and self._stored_later(parent, name)]
            if not masked:
                return None
            simple = all(isinstance(s, (ast.Assign, ast.AnnAssign, ast.Pass)) for s in [*done_branch, *other])
            boundary = self._none_ends_episode_in_callee(parent, masked[0])
            return masked[0], simple and boundary is None, boundary
        return None

    def _none_ends_episode_in_callee(self, statement: ast.stmt, name: str) -> str | None:
        """A def of the module that ``name`` is handed to after ``statement`` (``agent.train(s,
        a, r, s2)``) and that also reads its None as the episode's end: the None test joined
        with another condition (``if s2 is None or len(self.memory) >= n``: flush an n-step
        buffer), or its None branch resetting the object's state (``self.memory = []``). Then
        the None is a boundary as well as a mask, and a truncation must set it too. Returns
        the callee's text; None when no such callee is found."""
        function = self.facts.enclosing_function(statement) or self.facts.tree
        for call in walk(function):
            if not isinstance(call, ast.Call) or call.lineno <= statement.lineno:
                continue
            positions = [i for i, arg in enumerate(call.args) if isinstance(arg, ast.Name) and arg.id == name]
            if not positions or any(isinstance(a, ast.Starred) for a in call.args[: positions[0]]):
                continue
            callee = self._module_def(call.func)
            if callee is None:
                continue
            params = [a.arg for a in (*callee.args.posonlyargs, *callee.args.args)]
            if isinstance(self.facts.parent(callee), ast.ClassDef) and isinstance(call.func, ast.Attribute) and params:
                params = params[1:]  # ``self``
            if positions[0] < len(params) and _tests_none_as_boundary(callee, params[positions[0]]):
                return self.facts.segment(call.func)
        return None

    def _module_def(self, func: ast.AST) -> ast.FunctionDef | ast.AsyncFunctionDef | None:
        """The def a call runs, where the module shows it: a function of the module, the
        class's own method, or ``obj.method`` when one class of the module alone defines it."""
        found = self.receivers.local_function(func) or self.receivers.own_method(func)
        if found is not None or not isinstance(func, ast.Attribute):
            return found
        methods = [
            s
            for node in walk(self.facts.tree)
            if isinstance(node, ast.ClassDef)
            for s in node.body
            if isinstance(s, FUNCTIONS) and s.name == func.attr
        ]
        return methods[0] if len(methods) == 1 else None

    def _stored_later(self, statement: ast.stmt, name: str) -> bool:
        """``name`` is handed on after ``statement`` in the same function, as an argument
        (``memory.push(state, action, next_state, r)``, ``agent.update(s, a, r, s2)``), and never
        tested (``if state is None: reset``: then None means "start a new episode", not a
        terminal transition)."""
        function = self.facts.enclosing_function(statement) or self.facts.tree
        stored = False
        for node in walk(function):
            if isinstance(node, (ast.If, ast.While, ast.IfExp)) and name in loaded_names(node.test):
                return False
            if (
                isinstance(node, ast.Call)
                and node.lineno > statement.lineno
                and not (isinstance(node.func, ast.Name) and node.func.id in _NOT_TRANSITIONS)
                and any(_passes(arg, name) for arg in [*node.args, *(k.value for k in node.keywords)])
            ):
                stored = True
        return stored

    def _beside_bootstrap_flag(self, read: ast.Name, step: DoneStep) -> str | None:
        """``store_transition(s, a, r, s2, terminal, done)`` where ``terminal`` (or ``dw``) is
        computed from ``done`` after the step together with something else (``if done and
        steps != limit: terminal = True``, ``dw = done and not truncated``): the code already
        keeps a separate bootstrap mask, so ``done`` beside it in the same call or tuple is the
        episode boundary (an n-step cut, the end of a rollout). The name of that flag, or None."""
        facts = self.facts
        holder: ast.AST | None = facts.parent(read)
        if isinstance(holder, ast.keyword):
            holder = facts.parent(holder)
        if not isinstance(holder, (ast.Call, ast.Tuple, ast.List)) or getattr(holder, "func", None) is read:
            return None
        values = [*holder.args, *(k.value for k in holder.keywords)] if isinstance(holder, ast.Call) else holder.elts
        function = facts.enclosing_function(step.assign) or facts.tree
        for value in values:
            if value is read or not isinstance(value, ast.Name) or value.id == read.id:
                continue
            if self._computed_from_done(value, step, function):
                return value.id
        return None

    def _computed_from_done(self, flag: ast.Name, step: DoneStep, function: ast.AST) -> bool:
        """``flag`` is bound after the step, in its function, from a value or under a test
        that reads ``done`` with something else (``done and steps != limit``)."""
        done = step.done.id
        for binding in self.flow.bindings(flag):
            statement = self.facts.statement_of(binding)
            if not isinstance(binding, ast.Name) or statement is None or start(statement) <= end(step.assign):
                continue  # ``terminal = False`` before the loop: not what the step decides
            if (self.facts.enclosing_function(statement) or self.facts.tree) is not function:
                continue
            value = getattr(statement, "value", None)
            if value is not None and any(_joins_done(node, done) for node in walk(value)):
                return True  # ``dw = done and steps != limit``, ``terminal = True if done and ... else False``
            for ancestor in self.facts.ancestors(binding):
                if ancestor is function:
                    break
                if (
                    isinstance(ancestor, ast.If)
                    and _joins_done(ancestor.test, done)
                    and isinstance(value, ast.Constant)
                    and value.value in (True, False)  # also 1, 0, 1.0, 0.0
                ):
                    return True  # ``if done and steps != limit: terminal = True`` (not ``reward = -1`` there)
        return False

    def _hands_step_on(self, read: ast.Name, step: DoneStep) -> bool:
        """``return agent_state, terminal, agent_reward`` or ``pipe.send((obs, reward, done,
        info))``: the flag in one tuple with the step's observation and reward (or values
        computed from them), returned or sent as a call's only argument. The step's result
        is handed on, an env-like reply: its receiver reads the flag as the episode's end."""
        site = self.facts.parent(read)
        if not isinstance(site, ast.Tuple):
            return False
        holder = self.facts.parent(site)
        if isinstance(holder, ast.Call):
            if holder.args != [site] or holder.keywords or holder.func is site:
                return False
        elif not isinstance(holder, ast.Return):
            return False
        elements = step.target.elts
        if len(elements) < 2 or not all(isinstance(e, ast.Name) for e in elements[:2]):
            return False
        observation, reward = elements[0].id, elements[1].id  # type: ignore[attr-defined]
        function = self.facts.enclosing_function(step.assign) or self.facts.tree
        derived = {observation: {observation}, reward: {reward}}
        for node in walk(function):
            if isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name):
                for names in derived.values():
                    if loaded_names(node.value) & names:
                        names.add(node.targets[0].id)
        others = [loaded_names(e) for e in site.elts if e is not read]
        if not (any(n & derived[observation] for n in others) and any(n & derived[reward] for n in others)):
            return False
        # every value is the step's (``reward``, ``info``) or set after it from the step
        # (``agent_state = featurize(state)``, the auto-reset ``obs = env.reset()``): a
        # transition (``(obs, action, next_obs, reward, done)``) holds the state before it
        return all(self._from_step(e, step) for e in site.elts if e is not read)

    def _from_step(self, value: ast.expr, step: DoneStep) -> bool:
        step_names = {e.id for e in step.target.elts if isinstance(e, ast.Name)}
        for node in walk(value):
            if not (isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load)):
                continue
            binding = self.flow.last_binding_of(node)
            statement = self.facts.statement_of(binding) if binding is not None else None
            if statement is step.assign:
                return True
            if (
                isinstance(statement, ast.Assign)
                and start(statement) > end(step.assign)
                and self.facts.enclosing_function(statement) is self.facts.enclosing_function(step.assign)
                and (loaded_names(statement.value) & step_names or node.id in step_names)
            ):
                return True
        return False

    def _only_ends_or_unread(self, read: ast.Name) -> str | None:
        """What the code shows the flag is for, when that settles it: returned by a def of the
        file whose every caller unpacks the result and reads the flag only to end a loop
        (``if done: break``), stored in a list of the function that nothing reads
        (``episode.append(Transition(..., done=done))``), or folded into a flag of the
        episode that only ends a loop or nothing reads (``over |= done``). None otherwise."""
        node: ast.AST = read
        parent = self.facts.parent(node)
        if isinstance(parent, ast.Tuple) and isinstance(self.facts.parent(parent), ast.Return):
            return self._returned_for_loop_exit(read, parent)
        folded = _folded_into(self.facts.statement_of(read), read)
        if folded is not None:
            return self._folded_flag_use(folded)
        while parent is not None and not isinstance(parent, ast.stmt):
            if (
                isinstance(parent, ast.Call)
                and isinstance(parent.func, ast.Attribute)
                and parent.func.attr in ("append", "extend", "insert")
                and node is not parent.func
                and isinstance(parent.func.value, ast.Name)
                and isinstance(self.facts.parent(parent), ast.Expr)
            ):
                return self._unread_list(parent.func.value)
            node, parent = parent, self.facts.parent(parent)
        return None

    def _folded_flag_use(self, flag: ast.Name) -> str | None:
        """``over |= done`` (or ``over = over or done``): where every binding of ``over`` in
        its function is a constant or such a fold, and every other read of it ends a loop
        (``while not over``, ``if over: break``), ``over`` is whether the episode ended, its
        books; what it says, or None when it may feed anything else."""
        scope = self.flow.binding_scope(flag)
        if scope is None or self._declared_outside(flag, flag.id):
            return None
        for binding in scope.bindings.get(flag.id, ()):
            statement = self.facts.statement_of(binding) if isinstance(binding, ast.Name) else None
            if statement is None:
                return None
            if not _constant_binding(statement, binding) and _folded_into(statement, None, flag.id) is None:
                return None
        uses = [use for use in self.flow.reads(flag) if _folded_into(self.facts.statement_of(use), None, flag.id) is None]
        if not uses:
            return f"is only folded into `{flag.id}`, which nothing reads"
        if all(_ends_loop(self.facts, use) for use in uses):
            return f"is only folded into `{flag.id}`, which is read only to end a loop"
        return None

    def _unwrapped_for_loop_exit(self, read: ast.Name) -> str | None:
        """``done = done[0] if isinstance(done, list) else done``: the flag rebound to itself
        or one element of it (no arithmetic, nothing else read), and every other read of the
        name in the function only ends a loop or shows it (``while not done:``), so whatever
        it holds is the episode's end. None otherwise."""
        statement = self.facts.statement_of(read)
        if not (isinstance(statement, ast.Assign) and _unwraps(statement, read.id)):
            return None
        target = statement.targets[0]
        if not isinstance(target, ast.Name):
            return None
        uses = [use for use in self.flow.reads(target) if not _unwraps(self.facts.statement_of(use), read.id)]
        if not uses or any(classify_done_read(use, self.facts) not in (DoneUse.CONTROL, DoneUse.NEUTRAL) for use in uses):
            return None
        for use in uses:
            holder = self.facts.parent(use)
            if isinstance(holder, ast.UnaryOp):
                holder = self.facts.parent(holder)
            if not isinstance(holder, ast.While) and classify_done_read(use, self.facts) is DoneUse.CONTROL:
                return None  # an ``if`` may choose a value (a bootstrap): only loop tests here
        return "is only unwrapped here, and the name is read only to end a loop"

    def _returned_for_loop_exit(self, read: ast.Name, values: ast.Tuple) -> str | None:
        function = self.facts.enclosing_function(read)
        if not isinstance(function, FUNCTIONS):
            return None
        unpacks = self._caller_unpacks(read)
        if unpacks is None:
            return None
        # A call whose result is dropped (``helper(env, a)`` as a statement) reads no flag:
        # with every other call an unpack that only ends a loop, nothing bootstraps from it.
        calls = self._helper_calls(read, function)
        discarded = [call for call in calls if isinstance(self.facts.parent(call), ast.Expr)]
        if not unpacks[0] and len(unpacks[1]) + len(discarded) != len(calls):
            return None
        if not unpacks[1] and not discarded:
            return None
        for unpacked in unpacks[1]:
            uses = self.flow.reads(unpacked.done)
            if any(classify_done_read(use, self.facts) not in (DoneUse.CONTROL, DoneUse.NEUTRAL) for use in uses):
                return None
            # ``if done: y = r`` / ``else: y = r + gamma * v(s2)`` in the caller is a test too,
            # but it chooses whether to bootstrap from the next state the helper returned:
            # no loop exit alone.
            if any(self._bootstrap_choice(use, unpacked, dominated=True) is not None for use in uses):
                return None
        if discarded:
            return f"is returned by `{function.name}`, whose callers drop it or read it only to end their loop"
        return f"is returned by `{function.name}`, whose callers read it only to end their loop"

    def _helper_calls(self, read: ast.Name, function: ast.FunctionDef | ast.AsyncFunctionDef) -> list[ast.Call]:
        """The calls of the def returning ``read`` that ``_caller_unpacks`` looks at."""
        if self.facts.enclosing_class(read) is not None:
            return list(self._own_method_calls(function))
        return list(self.facts.calls_by_name.get(function.name, []))

    def _caller_unpacks(self, read: ast.Name) -> tuple[bool, list[DoneStep]] | None:
        """``return s2, r, done, info`` (in any order) from a def of the file: each call of it
        in the file (``self.<method>(...)`` for a method, see ``_own_method_calls``) that
        unpacks the result into as many names, seen as a step whose done is the name in the
        flag's place and whose next state (its target's first element) is the name in the
        place of the returned observation. Whether every call is such an unpack, and those
        unpacks; None when ``read`` is not returned in a tuple by a def."""
        parent = self.facts.parent(read)
        if not (isinstance(parent, ast.Tuple) and isinstance(self.facts.parent(parent), ast.Return)):
            return None
        function = self.facts.enclosing_function(read)
        if not isinstance(function, FUNCTIONS):
            return None
        values = parent

        def compute() -> tuple[bool, list[DoneStep]]:
            index = next(i for i, value in enumerate(values.elts) if value is read)
            step = self._step_binding(read)
            observation = self._returned_observation(values, read, step) if step is not None else None
            calls = self._helper_calls(read, function)
            every = True
            found: list[DoneStep] = []
            for call in calls:
                assign = self.facts.parent(call)
                target = assign.targets[0] if isinstance(assign, ast.Assign) and assign.value is call and len(assign.targets) == 1 else None
                if not isinstance(target, (ast.Tuple, ast.List)) or len(target.elts) != len(values.elts):
                    every = False
                    continue
                flag = target.elts[index]
                if not isinstance(flag, ast.Name):
                    every = False
                    continue
                if observation:  # the returned observation first, where a step's next state is
                    elements = list(target.elts)
                    elements[0], elements[observation] = elements[observation], elements[0]
                    target = ast.Tuple(elts=elements, ctx=ast.Store())
                found.append(DoneStep(assign, flag, None, target))  # type: ignore[arg-type]
            return every, found

        return self.facts.memo(("caller-unpacks", id(read)), compute)

    def _step_binding(self, read: ast.Name) -> DoneStep | None:
        """The rewritten step whose ``done`` certainly binds ``read``, as a ``DoneStep``."""
        owner = self._dominating_step(read, read)
        if owner is None:
            return None
        target = owner.targets[0]
        if not isinstance(target, (ast.Tuple, ast.List)) or not isinstance(target.elts[2], ast.Name):
            return None
        return DoneStep(owner, target.elts[2], None, target)  # type: ignore[arg-type]

    def _returned_observation(self, values: ast.Tuple, read: ast.Name, step: DoneStep) -> int | None:
        """Where ``return r, done, s2, info`` puts the step's next state: the index of the one
        element that reads it, if exactly one does."""
        next_names = self._next_state_names(step)
        found = [
            i
            for i, value in enumerate(values.elts)
            if value is not read and isinstance(value, ast.Name) and self._reads_next_state(value, step, next_names)
        ]
        return found[0] if len(found) == 1 else None

    def _own_method_calls(self, function: ast.AST) -> list[ast.Call]:
        """``self.<method>(...)`` in the class that defines ``function`` (a method of it), when
        nothing else in the module calls a method of that name (``agent.<method>(...)``
        could not be told apart); empty otherwise."""
        classdef = self.facts.parent(function)
        if not isinstance(classdef, ast.ClassDef):
            return []
        name = function.name  # type: ignore[attr-defined]
        found: list[ast.Call] = []
        for node in walk(self.facts.tree):
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == name:
                owner = node.func.value
                caller = self.facts.enclosing_class(node)
                if not (isinstance(owner, ast.Name) and owner.id == "self" and caller is not None):
                    return []
                if caller is not classdef:
                    if any(isinstance(s, FUNCTIONS) and s.name == name for s in caller.body):
                        continue  # another class's own method of that name (``self`` is that class)
                    return []
                found.append(node)
            elif isinstance(node, ast.Attribute) and node.attr == name and not isinstance(self.facts.parent(node), ast.Call):
                return []  # the bound method handed on (a callback): its callers are unknown
        return found

    def _returned_to_bootstrap_choice(self, read: ast.Name) -> tuple[str, ast.Name] | None:
        """``return s2, r, done, info`` from a def of the file, and a caller that unpacks the
        result and tests the flag to choose a value computed from the returned next state
        (``if done: y = r`` / ``else: y = r + gamma * v(s2)``): the def's name and that test."""
        unpacks = self._caller_unpacks(read)
        function = self.facts.enclosing_function(read)
        if unpacks is None or not isinstance(function, FUNCTIONS) or self.facts.enclosing_class(read) is not None:
            return None
        for unpacked in unpacks[1]:
            for use in self.flow.reads(unpacked.done):
                if self._bootstrap_choice(use, unpacked, dominated=True) is not None:
                    return function.name, use
        return None

    def _returned_to_store(self, read: ast.Name) -> tuple[str, ast.Name, str] | None:
        """``return r, done, s2, info`` from a def of the file, and a caller that unpacks the
        result and stores the flag with the returned next state (``memory.add(s, a, r, s2,
        done)``) or hands both to a def that masks one with the other: the def's name, the
        caller's read of the flag and the caller's name of the next state."""
        unpacks = self._caller_unpacks(read)
        function = self.facts.enclosing_function(read)
        if unpacks is None or not isinstance(function, FUNCTIONS):
            return None
        for unpacked in unpacks[1]:
            first = unpacked.target.elts[0]
            if not isinstance(first, ast.Name):
                continue
            for use in self.flow.reads(unpacked.done):
                if classify_done_read(use, self.facts) is DoneUse.CONTROL or isinstance(self.facts.statement_of(use), ast.Return):
                    continue  # loop control, or handed on again (a step's own result): not a store
                if self._masks_next_state(use, unpacked) or self._callee_masks(use, unpacked) is not None:
                    return function.name, use, first.id
        return None

    def _unread_list(self, name: ast.Name) -> str | None:
        """``episode`` bound only to new lists in a function and only ever appended to."""
        scope = self.flow.binding_scope(name)
        if scope is None or self.facts.enclosing_function(name) is None or self._declared_outside(name, name.id):
            return None
        bindings = scope.bindings.get(name.id, ())
        for binding in bindings:
            assign = self.facts.parent(binding)
            if not (
                isinstance(binding, ast.Name)
                and isinstance(assign, ast.Assign)
                and assign.targets == [binding]
                and isinstance(assign.value, (ast.List, ast.ListComp))
            ):
                return None
        for use in self.flow.reads(name):
            method = self.facts.parent(use)
            call = self.facts.parent(method)
            if not (
                isinstance(method, ast.Attribute)
                and method.attr in ("append", "extend", "insert")
                and isinstance(call, ast.Call)
                and call.func is method
                and isinstance(self.facts.parent(call), ast.Expr)
            ):
                return None
        return f"is stored in `{name.id}`, which nothing reads"

    def _declared_outside(self, node: ast.AST, name: str) -> bool:
        function = self.facts.enclosing_function(node)
        if function is None:
            return False
        scope = self.facts.scopes[function]
        return name in scope.declared_global or name in scope.declared_nonlocal


def _tests_none_as_boundary(function: ast.AST, param: str) -> bool:
    """``function`` tests ``param is None`` (or ``is not None``) together with another
    condition, or resets its object's state on the None side (``self.memory = []``,
    ``self.buffer.clear()``): the None ends something, beyond choosing a stored value."""
    parents = {id(child): node for node in walk(function) for child in ast.iter_child_nodes(node)}
    for node in walk(function):
        if not (
            isinstance(node, ast.Compare)
            and isinstance(node.left, ast.Name)
            and node.left.id == param
            and len(node.ops) == 1
            and isinstance(node.ops[0], (ast.Is, ast.IsNot))
            and _is_none(node.comparators[0])
        ):
            continue
        parent = parents.get(id(node))
        if isinstance(parent, ast.BoolOp):
            return True
        if isinstance(parent, ast.If) and parent.test is node:
            branch = parent.body if isinstance(node.ops[0], ast.Is) else parent.orelse
            for statement in branch:
                for inner in walk(statement):
                    if isinstance(inner, (ast.Assign, ast.AugAssign)) and any(
                        isinstance(t, ast.Attribute) and isinstance(t.value, ast.Name) and t.value.id == "self"
                        for t in (inner.targets if isinstance(inner, ast.Assign) else [inner.target])
                    ):
                        return True
                    if isinstance(inner, ast.Call) and isinstance(inner.func, ast.Attribute) and inner.func.attr == "clear":
                        return True
    return False


def _joins_done(test: ast.AST, done: str) -> bool:
    """``done and steps != limit``, ``done and not info.get(...)``: ``done`` read together
    with another condition (``done`` alone, or negated, is the flag itself); also as a
    choice, ``float(done) if steps < limit else 0``, which is that ``and`` written out."""
    if isinstance(test, ast.IfExp):
        branches = (test.body, test.orelse)
        return (
            done not in loaded_names(test.test)
            and any(done in loaded_names(b) for b in branches)
            and any(isinstance(b, ast.Constant) and b.value in (False, 0) for b in branches)
        )
    if not isinstance(test, ast.BoolOp) or not isinstance(test.op, ast.And):
        return False
    return done in loaded_names(test) and any(done not in loaded_names(v) for v in test.values)


# Calls that show or test a value rather than take a transition.
_NOT_TRANSITIONS = frozenset({"print", "repr", "str", "len", "isinstance", "type", "id"})


def _passes(argument: ast.expr, name: str) -> bool:
    """The argument is ``name``, or a tuple or list that holds it (a transition)."""
    if isinstance(argument, (ast.Tuple, ast.List)):
        return any(_passes(element, name) for element in argument.elts)
    return isinstance(argument, ast.Name) and argument.id == name


def _folded_into(statement: ast.AST | None, read: ast.Name | None, name: str | None = None) -> ast.Name | None:
    """The flag ``x`` of ``x |= read`` or ``x = x or read`` (``read`` None: any value; ``name``:
    only a flag of that name); None for any other statement."""
    target: ast.expr
    if isinstance(statement, ast.AugAssign) and isinstance(statement.op, ast.BitOr):
        target, values = statement.target, [statement.value]
    elif (
        isinstance(statement, ast.Assign)
        and len(statement.targets) == 1
        and isinstance(statement.value, ast.BoolOp)
        and isinstance(statement.value.op, ast.Or)
    ):
        target, values = statement.targets[0], statement.value.values
        if not any(isinstance(v, ast.Name) and isinstance(target, ast.Name) and v.id == target.id for v in values):
            return None
    else:
        return None
    if not isinstance(target, ast.Name) or (name is not None and target.id != name):
        return None
    if read is not None and not any(v is read for v in values):
        return None
    return target


def _constant_binding(statement: ast.AST, binding: ast.AST) -> bool:
    """``over = False``, or ``over, total = False, 0.0``: ``binding`` is given a constant."""
    if not (isinstance(statement, ast.Assign) and len(statement.targets) == 1):
        return False
    target, value = statement.targets[0], statement.value
    if target is binding:
        return isinstance(value, ast.Constant)
    return (
        isinstance(target, (ast.Tuple, ast.List))
        and isinstance(value, (ast.Tuple, ast.List))
        and len(target.elts) == len(value.elts)
        and any(t is binding and isinstance(v, ast.Constant) for t, v in zip(target.elts, value.elts, strict=True))
    )


def _ends_loop(facts: ModuleFacts, use: ast.Name) -> bool:
    """``while not over:`` or ``if over: break`` (only leaving, no ``else``)."""
    test: ast.AST = use
    holder = facts.parent(test)
    if isinstance(holder, ast.UnaryOp) and isinstance(holder.op, ast.Not):
        test, holder = holder, facts.parent(holder)
    if isinstance(holder, ast.While) and holder.test is test:
        return True
    return (
        isinstance(holder, ast.If)
        and holder.test is test
        and not holder.orelse
        and all(isinstance(s, ast.Break) or (isinstance(s, ast.Return) and s.value is None) for s in holder.body)
    )


# Names a flag's unwrapping may call besides the flag itself (``done[0] if isinstance(done, list) else done``).
_SHAPE_NAMES = frozenset({"isinstance", "list", "tuple", "bool", "len", "any", "all"})


def _unwraps(statement: ast.AST | None, name: str) -> bool:
    """``name = name[0] if isinstance(name, list) else name``: the flag rebound to itself or
    an element of it, reading nothing else but a few shape tests."""
    if not (
        isinstance(statement, ast.Assign)
        and len(statement.targets) == 1
        and isinstance(statement.targets[0], ast.Name)
        and statement.targets[0].id == name
    ):
        return False
    value = statement.value
    if any(isinstance(n, (ast.BinOp, ast.Lambda, ast.NamedExpr, ast.Attribute)) for n in walk(value)):
        return False
    return name in loaded_names(value) and not loaded_names(value) - {name, *_SHAPE_NAMES}


def _assigned(statement: ast.Assign | ast.AnnAssign) -> set[str]:
    targets = statement.targets if isinstance(statement, ast.Assign) else [statement.target]
    return {name for target in targets for name in bound_names(target)}


def resets(node: ast.AST) -> bool:
    """``node`` calls some ``x.reset(...)``: the flag starts a new episode there."""
    return any(isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute) and n.func.attr == "reset" for n in walk(node))


def _is_none(node: ast.AST) -> bool:
    return isinstance(node, ast.Constant) and node.value is None
