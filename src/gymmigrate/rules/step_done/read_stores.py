"""Where a read of a rewritten step's ``done`` stores the flag (GM302).

What the store's readers do with it (``facts/stored_readers.py``), a rollout store handed
the step's reward and flag but no next state, an episode's store whose last flag masks the
value handed on with it (``train(memory, critic(s2))`` under ``if done:``), and whether a
store may hold the next state after all. ``read_reports`` turns the answers into findings.
"""

from __future__ import annotations

import ast

from gymmigrate.facts.bootstrap import episode_flushes
from gymmigrate.facts.done_uses import loaded_names, value_site
from gymmigrate.facts.flow import end, start
from gymmigrate.facts.module import FUNCTIONS, walk
from gymmigrate.facts.stored_readers import Reader, stored_flag_readers
from gymmigrate.rules.step_done.next_state import DoneStep, says_next
from gymmigrate.rules.step_done.read_uses import DoneReadUses


class DoneStoreReads(DoneReadUses):
    """Where a read of ``done`` stores the flag (mixed into the family)."""

    def _stored_flag_readers(self, read: ast.Name) -> list[Reader]:
        """The readers this module shows of the flag ``read`` stores: in a record or tuple
        built here (``memories.append(Memory(..., done=done))``), or by the callee of this
        module it is passed to (``agent.add(s, a, s2, r, done)`` whose body stores it). They
        say whether the stored flag masks a next-state value or marks the episode boundary
        (``facts/stored_readers.py``); empty when none is visible."""
        found = stored_flag_readers(read, self.facts)
        if found:
            return found
        callee = self._flag_callee(read)
        if callee is None:
            return []
        function, flag = callee
        flushes = self._callee_flushes(read)
        if flushes:
            # ``if done: ...; self.window = deque(maxlen=n)`` in the callee: the flag ends the
            # episode's state there, and every other read of it in the callee (stored beside
            # the next state) is taken as the mask it may be.
            tests = {id(n) for test in flushes for n in walk(test.test)}
            return [Reader(test.test, "boundary") for test in flushes] + [
                Reader(node, "mask")
                for node in walk(function)
                if isinstance(node, ast.Name) and node.id == flag and isinstance(node.ctx, ast.Load) and id(node) not in tests
            ]
        return [
            reader
            for node in walk(function)
            if isinstance(node, ast.Name) and node.id == flag and isinstance(node.ctx, ast.Load)
            for reader in stored_flag_readers(node, self.facts)
        ]

    def _callee_flushes(self, read: ast.Name) -> list[ast.If]:
        """The branches of the callee of this module ``read`` is passed to that test the flag
        and empty the callee's state kept across calls (``facts/bootstrap.py``)."""
        callee = self._flag_callee(read)
        return [] if callee is None else episode_flushes(*callee)

    def _flag_callee(self, read: ast.Name) -> tuple[ast.FunctionDef | ast.AsyncFunctionDef, str] | None:
        """The def of this module ``read`` is passed to and the parameter it binds; None when
        the callee cannot be followed."""
        call = self.facts.parent(read)
        if isinstance(call, ast.keyword):
            call = self.facts.parent(call)
        if not isinstance(call, ast.Call) or call.func is read or any(isinstance(a, ast.Starred) for a in call.args):
            return None
        function = self.receivers.local_function(call.func) or self.receivers.own_method(call.func)
        method = function is not None and isinstance(self.facts.parent(function), ast.ClassDef)
        if function is None and isinstance(call.func, ast.Attribute) and isinstance(call.func.value, ast.Name):
            classes = self._instance_classes(call.func.value)
            classdef = next(iter(classes)) if len(classes) == 1 else None
            if isinstance(classdef, ast.ClassDef):
                function = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == call.func.attr), None)
                method = True
        if function is None:
            return None
        params = [a.arg for a in (*function.args.posonlyargs, *function.args.args)]
        params = params[1:] if method else params
        if read in call.args:
            index = call.args.index(read)
            flag = params[index] if index < len(params) else None
        else:
            flag = next((k.arg for k in call.keywords if k.value is read), None)
        return None if flag is None else (function, flag)

    def _zero_tails(self, step: DoneStep, function: ast.AST) -> list[int]:
        """The lines, in ``function``, of ``if done:`` branches that ``step`` binds the flag
        of and that close a trajectory with a last value of 0: a call handing on a
        container the branch empties together with a zero (``store(trajectory, 0)``, then
        ``trajectory = []``), or a zero appended to a list the function appends per-step
        values to (``values.append(0)`` beside ``values.append(v)``)."""
        found: list[int] = []
        for branch in walk(function):
            if not (isinstance(branch, ast.If) and isinstance(branch.test, ast.Name) and branch.test.id == step.done.id):
                continue
            if self._dominating_step(branch.test, step.done) is not step.assign:
                continue
            emptied = {
                name
                for statement in branch.body
                for node in walk(statement)
                for name in _emptied_names(node)
            }
            for statement in branch.body:
                for node in walk(statement):
                    if not isinstance(node, ast.Call) or not any(_zero(a) for a in [*node.args, *(k.value for k in node.keywords)]):
                        continue
                    handed = any(n.id in emptied for a in node.args if not _zero(a) for n in walk(a) if isinstance(n, ast.Name))
                    if handed or self._zero_appended_to_values(node, function):
                        found.append(node.lineno)
        return sorted(set(found))

    @staticmethod
    def _zero_appended_to_values(call: ast.Call, function: ast.AST) -> bool:
        """``values.append(0)`` where ``function`` also appends a computed value to
        ``values`` (``values.append(v)``): the zero is the trajectory's last value."""
        func = call.func
        if not (isinstance(func, ast.Attribute) and func.attr == "append" and isinstance(func.value, ast.Name) and len(call.args) == 1):
            return False
        owner = func.value.id
        return any(
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Attribute)
            and node.func.attr == "append"
            and isinstance(node.func.value, ast.Name)
            and node.func.value.id == owner
            and len(node.args) == 1
            and not isinstance(node.args[0], ast.Constant)
            for node in walk(function)
        )

    def _stores_step_without_next_state(self, read: ast.Name, step: DoneStep) -> bool:
        """``memory.store_memory(obs, value, reward, done)``: a call that hands on the step's
        reward and flag but no next state (``obs`` still holds the state the step started
        from). Whatever the callee does, it cannot bootstrap from the next state with this
        flag: a rollout store, where the flag is the episode boundary."""
        call = self.facts.parent(read)
        if isinstance(call, ast.keyword):
            call = self.facts.parent(call)
        if not isinstance(call, ast.Call) or call.func is read or any(isinstance(a, ast.Starred) for a in call.args):
            return False
        reward = step.target.elts[1] if len(step.target.elts) > 1 else None
        if not isinstance(reward, ast.Name):
            return False
        arguments = [*call.args, *(k.value for k in call.keywords)]
        if not any(isinstance(a, ast.Name) and a.id == reward.id for a in arguments):
            return False
        next_names = self._next_state_names(step)
        return not any(a is not read and self._reads_next_state(a, step, next_names) for a in arguments)

    def _episode_store_with_tail(self, read: ast.Name, step: DoneStep) -> tuple[str, ast.Call, ast.Call | ast.Assign | ast.Delete] | None:
        """``memory.append((r, done))`` where, under ``if done:``, the code hands ``memory`` on
        together with a value of the step's next state (``train(memory, critic(s2))``) and
        empties it (``memory.clear()``, ``memory = []``): the store holds one episode, and
        its last flag can only mask that final value, a bootstrap. The container's name, the
        hand-on call and the emptying statement; else None."""
        node: ast.AST = read
        parent = self.facts.parent(node)
        container = None
        while parent is not None and not isinstance(parent, ast.stmt):
            if isinstance(parent, ast.Call) and isinstance(parent.func, ast.Attribute) and node is not parent.func:
                if isinstance(parent.func.value, ast.Name):
                    container = parent.func.value.id
                break
            node, parent = parent, self.facts.parent(parent)
        if container is None:
            return None
        function = self.facts.enclosing_function(step.assign) or self.facts.tree
        next_names = self._next_state_names(step)
        if not next_names:
            return None
        for test in walk(function):
            if not (isinstance(test, ast.If) and _tests_flag(test.test, step.done.id)):
                continue
            handed = emptied = None
            # ``last = critic(next_state)`` in the branch, then ``train(memory, last)``
            tail_values = {
                statement.targets[0].id
                for statement in test.body
                if isinstance(statement, ast.Assign)
                and len(statement.targets) == 1
                and isinstance(statement.targets[0], ast.Name)
                and self._reads_next_state(statement.value, step, next_names)
            }
            for statement in test.body:
                for inner in walk(statement):
                    if isinstance(inner, ast.Call) and any(isinstance(a, ast.Name) and a.id == container for a in inner.args):
                        if any(
                            (isinstance(a, ast.Name) and a.id in tail_values)
                            or (not isinstance(a, ast.Name) and self._reads_next_state(a, step, next_names))
                            for a in inner.args
                        ):
                            handed = inner
                    if isinstance(inner, (ast.Call, ast.Assign, ast.Delete)) and _empties(inner, container):
                        emptied = inner
            if handed is not None and emptied is not None:
                return container, handed, emptied
        return None

    def _callee_masks_tail(self, handed: ast.Call, container: str) -> str | None:
        """``train(memory, last)`` calls a def of this module that walks ``memory`` (``for
        i, (_, r, done) in enumerate(memory.reversed())``) and discounts the value it was
        handed through the stored flags (``q = r + gamma * q * (1.0 - done)``): the stored
        flag masks bootstrapping from that value. The def's name, or None."""
        func = handed.func
        if not isinstance(func, ast.Name) or handed.keywords or any(isinstance(a, ast.Starred) for a in handed.args):
            return None
        function = self.facts.functions.get(func.id)
        if function is None or self.facts.bindings_of(func) != [function]:
            return None
        params = [a.arg for a in (*function.args.posonlyargs, *function.args.args)]
        if len(handed.args) > len(params):
            return None
        stores = [params[i] for i, a in enumerate(handed.args) if isinstance(a, ast.Name) and a.id == container]
        values = {params[i] for i, a in enumerate(handed.args) if not (isinstance(a, ast.Name) and a.id == container)}
        if len(stores) != 1:
            return None
        for loop in walk(function):
            if not (isinstance(loop, ast.For) and any(isinstance(n, ast.Name) and n.id == stores[0] for n in walk(loop.iter))):
                continue
            flags = {n.id for n in walk(loop.target) if isinstance(n, ast.Name)}
            for statement in walk(loop):
                if not (isinstance(statement, ast.Assign) and len(statement.targets) == 1 and isinstance(statement.targets[0], ast.Name)):
                    continue
                value = statement.targets[0].id
                if value not in values or not any(isinstance(n, ast.Name) and n.id == value for n in walk(statement.value)):
                    continue
                if any(_one_minus(n, flags) for n in walk(statement.value)):
                    return func.id
        return None

    def _may_store_next_state(self, read: ast.Name, step: DoneStep) -> bool:
        """The store beside ``read`` holds a value that may be the step's next state in a way
        not followed (``frames.append(obs)``, then ``state = np.stack(frames)``): a name that
        says so (``next_state``, ``s_``), or one bound after the step
        from something else than its reward, flag or info. Then "stored without the next
        state" would be a guess: the read is a question, not a note."""
        site = value_site(read, self.facts)
        if isinstance(site, ast.Call):
            values: list[ast.AST] = [*site.args, *(k.value for k in site.keywords)]
        else:
            values = [site]
        step_values = {e.id for e in step.target.elts[1:] if isinstance(e, ast.Name)}
        function = self.facts.enclosing_function(step.assign)
        for value in values:
            for node in walk(value):
                if not (isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load)) or node.id == read.id:
                    continue
                if says_next(node.id):
                    return True
                binding = self.flow.last_binding_of(node)
                statement = self.facts.statement_of(binding) if binding is not None else None
                if (
                    isinstance(statement, (ast.Assign, ast.AnnAssign, ast.AugAssign))
                    and statement is not step.assign
                    and start(statement) > end(step.assign)
                    and self.facts.enclosing_function(statement) is function
                    and statement.value is not None
                    and not (loaded_names(statement.value) & step_values)
                    and not self._flag_of_other_things(statement.value, step)
                    and not self._from_before_the_step(statement.value, step)
                ):
                    return True
        return False

    def _flag_of_other_things(self, value: ast.expr, step: DoneStep) -> bool:
        """``lost = lives_now < lives_before``, ``not alive``: a comparison or a negation (a
        flag stored beside the done, e.g. a lost life) that reads neither the step's
        observation nor a name bound from it (``frame > 128`` may be a binarized next
        state): a truth value about something else, not the next state."""
        if not (isinstance(value, ast.Compare) or (isinstance(value, ast.UnaryOp) and isinstance(value.op, ast.Not))):
            return False
        observation = step.target.elts[0]
        if not isinstance(observation, ast.Name):
            return False
        for node in walk(value):
            if not (isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load)):
                continue
            if node.id == observation.id:
                return False
            binding = self.flow.last_binding_of(node)
            statement = self.facts.statement_of(binding) if binding is not None else None
            if statement is not None and start(statement) > end(step.assign) and observation.id in loaded_names(statement):
                return False
        return True

    def _from_before_the_step(self, value: ast.expr, step: DoneStep) -> bool:
        """``v = self.vf(torch.Tensor(obs))`` after the step, ``obs`` still the state the step
        started from: every name the value reads was last bound before the step and nothing
        after it changes them in place, and it reads nothing of the stepped env (``self.env.x``
        may be its new state): the value cannot be the next state."""
        receiver = step.assign.value.func.value if isinstance(step.assign.value, ast.Call) and isinstance(step.assign.value.func, ast.Attribute) else None
        if receiver is None:
            return False
        env = self.facts.segment(receiver)
        observation = step.target.elts[0]
        for node in walk(value):
            if isinstance(node, ast.Attribute) and self.facts.segment(node).startswith(env):
                return False
            if not (isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load)):
                continue
            if isinstance(observation, ast.Name) and node.id == observation.id:
                return False
            binding = self.flow.last_binding_of(node)
            if binding is not None and start(binding) > end(step.assign):
                return False
            if self._changed_after(node.id, step):
                return False
        return True

    def _changed_after(self, name: str, step: DoneStep) -> bool:
        """``frames.append(next_obs)`` or ``buf[i] = x`` after the step: ``name`` changed in place."""
        function = self.facts.enclosing_function(step.assign) or self.facts.tree
        for node in walk(function):
            if not hasattr(node, "lineno") or start(node) <= end(step.assign):
                continue
            if (
                isinstance(node, ast.Call)
                and isinstance(node.func, ast.Attribute)
                and isinstance(node.func.value, ast.Name)
                and node.func.value.id == name
                and node.func.attr in _IN_PLACE_CHANGES
            ):
                return True
            if isinstance(node, ast.Subscript) and isinstance(node.ctx, ast.Store) and isinstance(node.value, ast.Name) and node.value.id == name:
                return True
        return False


# Methods that change their object in place (``frames.append(next_obs)``): a name changed so
# after the step may hold the next state whatever it was bound to.
_IN_PLACE_CHANGES = frozenset({"append", "extend", "insert", "appendleft", "extendleft", "update", "add", "put", "push", "copy_", "fill_", "__setitem__"})


def _empties(node: ast.AST, container: str) -> bool:
    """``container.clear()``, ``container = []``, ``del container[:]``."""
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "clear":
        return isinstance(node.func.value, ast.Name) and node.func.value.id == container and not node.args
    if isinstance(node, ast.Assign) and len(node.targets) == 1:
        target = node.targets[0]
        return isinstance(target, ast.Name) and target.id == container and isinstance(node.value, ast.List) and not node.value.elts
    if isinstance(node, ast.Delete) and len(node.targets) == 1:
        target = node.targets[0]
        return (
            isinstance(target, ast.Subscript)
            and isinstance(target.value, ast.Name)
            and target.value.id == container
            and isinstance(target.slice, ast.Slice)
        )
    return False


def _emptied_names(node: ast.AST) -> list[str]:
    """The name ``node`` empties: ``name = []``, ``name.clear()``, ``del name[:]``."""
    if isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name):
        name = node.targets[0].id
        return [name] if _empties(node, name) else []
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and isinstance(node.func.value, ast.Name):
        name = node.func.value.id
        return [name] if _empties(node, name) else []
    if isinstance(node, ast.Delete) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Subscript):
        value = node.targets[0].value
        return [value.id] if isinstance(value, ast.Name) and _empties(node, value.id) else []
    return []


def _zero(node: ast.AST) -> bool:
    """``0``, ``0.0``: a last value of zero (``True``/``False`` are flags, not values)."""
    return isinstance(node, ast.Constant) and type(node.value) in (int, float) and node.value == 0


def _tests_flag(test: ast.expr, flag: str) -> bool:
    """``if done:`` or ``if done or steps % n == 0:`` (a flush at the end and between)."""
    if isinstance(test, ast.Name):
        return test.id == flag
    return isinstance(test, ast.BoolOp) and isinstance(test.op, ast.Or) and any(isinstance(v, ast.Name) and v.id == flag for v in test.values)


def _one_minus(node: ast.AST, flags: set[str]) -> bool:
    """``1 - done`` / ``1.0 - done`` on a flag of ``flags``: the mask that zeroes what follows."""
    return (
        isinstance(node, ast.BinOp)
        and isinstance(node.op, ast.Sub)
        and isinstance(node.left, ast.Constant)
        and node.left.value == 1
        and isinstance(node.right, ast.Name)
        and node.right.id in flags
    )
