"""What an ``isinstance`` check the code states proves about a name, read by read.

``def run(env): if isinstance(env, str): env = make_env(env) else: if not isinstance(env,
gym.Env): raise ValueError(...)`` and then ``env.step(a)``: the parameter may be an id or
anything, but every path that reaches the step has made ``env`` a Gym env, or checked that
it is one. The bindings alone cannot say so (the parameter reaches the read), so this
module follows the statements of the read's frame in order, with one of three states per
point: the name certainly holds a Gym env (``GYM``), it may hold anything (``OTHER``), or
the point is never reached (``DEAD``: after ``raise``/``return``/``continue``/``break``).

What makes a Gym env: ``isinstance(x, gym.Env)`` (or Gym's ``Wrapper`` classes, or a tuple
of them) true in an ``if``/``assert``; ``not isinstance(...)`` in an ``if`` makes its
``else`` (and what follows a body that cannot fall through) one; an assignment of a value
the receiver analysis calls a Gym env (``env = make_env(env)``). Anything else that binds
the name makes it ``OTHER``; loops, ``with`` and ``try`` that rebind it make their bodies
``OTHER``. Only names some ``isinstance`` call of their scope tests are followed, never a
variable by its spelling. ``and`` in an ``if`` narrows its body by any of its operands.

A second instance follows ``issubclass`` the same way (``check="issubclass"``): where
``issubclass(cls, gym.Env)`` holds on every path, ``cls(...)`` makes a Gym env.

``isinstance_guards`` is the plainer question the space and batched-step analyses ask:
which ``if isinstance(name, classes):`` bodies a node sits in.
"""

from __future__ import annotations

import ast
from collections.abc import Callable, Iterator
from enum import Enum

from gymmigrate.facts import names as N
from gymmigrate.facts.module import COMPREHENSIONS, FUNCTIONS, LOOPS, ModuleFacts, walk

# Gym's env classes: ``isinstance(x, <one of these>)`` is true only of a Gym env
_GYM_ENV_CLASSES = frozenset(
    f"{prefix}{name}"
    for prefix in ("", "core.")
    for name in ("Env", "Wrapper", "ObservationWrapper", "ActionWrapper", "RewardWrapper")
)
_ENDS = (ast.Raise, ast.Return, ast.Continue, ast.Break)


class State(Enum):
    GYM = "gym"
    NOT_GYM = "not gym"
    # an instance of a class shown to be no Gym env (``isinstance(env, PlainEnv)`` holds)
    OTHER_CLASS = "other class"
    OTHER = "other"
    DEAD = "dead"


def _join(first: State, second: State) -> State:
    if first is State.DEAD:
        return second
    if second is State.DEAD:
        return first
    return first if first is second else State.OTHER


class Narrowing:
    """One per file and check. ``value_is_env``: the receiver analysis's answer for an
    assigned value. ``check``: the builtin that states the fact (``isinstance``: the name
    holds a Gym env; ``issubclass``: it holds a Gym env class). ``class_is_env``: for a
    class the check names that is no class of Gym's, whether its instances are Gym envs
    (True: a Gym env class of the run; False: a class shown to be something else, such as
    the project's own plain env class; None: cannot tell)."""

    def __init__(
        self,
        facts: ModuleFacts,
        value_is_env: Callable[[ast.expr], bool],
        check: str = "isinstance",
        class_is_env: Callable[[ast.expr], bool | None] | None = None,
    ) -> None:
        self.facts = facts
        self.value_is_env = value_is_env
        self.check = check
        self.class_is_env = class_is_env
        self._tested: set[tuple[int, str]] | None = None
        self._bound: dict[tuple[int, str], bool] = {}
        self._afters: dict[tuple[int, State, str], State] = {}

    def answers(self) -> int:
        """How many states are kept: they grow as the receiver analysis answers, so a count
        that has not moved means none of its answers changed since."""
        return len(self._afters) + len(self._bound)

    def is_env(self, read: ast.Name) -> bool:
        """Every path to ``read`` has made or checked its name a Gym env."""
        return self._state(read) is State.GYM

    def is_not_env(self, read: ast.Name) -> bool:
        """Every path to ``read`` has passed an ``isinstance(name, gym.Env)`` check that sent
        the Gym envs elsewhere (``if isinstance(env, gym.Env): return GymWrapper(env)``, then
        ``return OtherWrapper(env)``): with legacy Gym, whose vector envs were ``gym.Env``
        too, no Gym env reaches it."""
        return self.check == "isinstance" and self._state(read) is State.NOT_GYM

    def is_other_class(self, read: ast.Name) -> bool:
        """Every path to ``read`` has passed ``isinstance(name, C)`` with ``C`` a class shown
        to be no Gym env (``elif isinstance(env, PlainEnv):``): it holds an instance of ``C``."""
        return self._state(read) is State.OTHER_CLASS

    def other_class_tested(self, read: ast.Name) -> str | None:
        """A class shown to be no Gym env that an ``isinstance`` of ``read``'s frame tests the
        name against (its spelling), or None: the code says the name may hold one."""
        scope = self.facts.scope_of(read)
        excluded = self._excluded_classes(read)
        for call in self.facts.calls_by_name.get("isinstance", ()):
            if (
                len(call.args) == 2
                and isinstance(call.args[0], ast.Name)
                and call.args[0].id == read.id
                and self.facts.scope_of(call.args[0]) is scope
                and isinstance(call.func, ast.Name)
                and self._is_builtin(call.func, "isinstance")
            ):
                for item in self._class_items(call.args[1]):
                    if ast.dump(item) in excluded:
                        continue
                    if not self._is_gym_env_class(item) and self.class_is_env is not None and self.class_is_env(item) is False:
                        return ast.unparse(item)
        return None

    def _excluded_classes(self, read: ast.Name) -> set[str]:
        """The classes ``read`` is known not to be an instance of: it sits in the ``else`` of
        ``if isinstance(name, C):`` (or the body of ``if not isinstance(name, C):``)."""
        excluded: set[str] = set()
        child: ast.AST = self.facts.statement_of(read)
        while True:
            parent = self.facts.parent(child)
            if parent is None or isinstance(parent, (*FUNCTIONS, ast.ClassDef)):
                break
            if isinstance(parent, ast.If):
                test, in_else = parent.test, any(child is s for s in parent.orelse)
                if isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not):
                    test, in_else = test.operand, any(child is s for s in parent.body)
                if (
                    in_else
                    and isinstance(test, ast.Call)
                    and isinstance(test.func, ast.Name)
                    and test.func.id == "isinstance"
                    and len(test.args) == 2
                    and isinstance(test.args[0], ast.Name)
                    and test.args[0].id == read.id
                ):
                    excluded.update(ast.dump(item) for item in self._class_items(test.args[1]))
            child = parent
        return excluded

    def checks_gym_env(self, test: ast.expr, name: str) -> bool:
        """``test`` is true only where ``name`` holds a Gym env (``isinstance(name, gym.Env)``,
        or of Gym's wrapper classes, ``or`` of such checks)."""
        return not (isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not)) and self._checks(test, name) is True

    def _state(self, read: ast.Name) -> State:
        scope = self.facts.scope_of(read)
        while isinstance(scope.node, COMPREHENSIONS) and read.id not in scope.bindings and scope.parent is not None:
            scope = scope.parent  # ``[copy.deepcopy(env) for _ in range(n)]`` runs in the frame around it
        if (id(scope), read.id) not in self._tested_names():
            return State.OTHER
        bound_in, _ = self.facts.resolve(read.id, scope)
        if bound_in is not scope or read.id in scope.declared_global or read.id in scope.declared_nonlocal:
            return State.OTHER  # a name of another frame: its statements do not run in order here
        return self._before(self.facts.statement_of(read), read.id)

    # -- which names ------------------------------------------------------------------------

    def _tested_names(self) -> set[tuple[int, str]]:
        if self._tested is None:
            self._tested = set()
            for call in self.facts.calls_by_name.get(self.check, ()):
                if len(call.args) == 2 and isinstance(call.args[0], ast.Name):
                    self._tested.add((id(self.facts.scope_of(call.args[0])), call.args[0].id))
        return self._tested

    # -- states ----------------------------------------------------------------------------

    def _before(self, statement: ast.stmt, name: str) -> State:
        """The state just before ``statement`` runs."""
        parent = self.facts.parent(statement)
        if parent is None:
            return State.OTHER
        block, field = None, ""
        for field in ("body", "orelse", "finalbody", "handlers"):
            items = getattr(parent, field, None)
            if isinstance(items, list) and any(item is statement for item in items):
                block = items
                break
        if block is None:
            return State.OTHER
        state = self._at_start(parent, field, name)
        for earlier in block:
            if earlier is statement:
                break
            state = self._after(earlier, state, name)
        return State.OTHER if state is State.DEAD else state

    def _at_start(self, holder: ast.AST, field: str, name: str) -> State:
        """The state where the block ``holder.field`` starts."""
        if isinstance(holder, ast.If):
            body, orelse = self._split(holder.test, self._before(holder, name), name)
            return body if field == "body" else orelse
        if isinstance(holder, ast.ExceptHandler):
            handled = self.facts.parent(holder)
            if handled is None:
                return State.OTHER
            holder, field = handled, "handlers"
        if isinstance(holder, (*LOOPS, ast.With, ast.AsyncWith)):
            return State.OTHER if self._binds(holder, name) else self._before(holder, name)
        if isinstance(holder, ast.Try) or type(holder).__name__ == "TryStar":
            if field != "body" and self._binds(holder, name):
                return State.OTHER  # a handler may start after any binding of the body
            return self._before(holder, name)  # type: ignore[arg-type]
        return State.OTHER  # a def, the module, a class body, a match case

    def _run(self, block: list[ast.stmt], state: State, name: str) -> State:
        for statement in block:
            state = self._after(statement, state, name)
            if state is State.DEAD:
                break
        return state

    def _after(self, statement: ast.stmt, state: State, name: str) -> State:
        # every read after a long ``if`` asks about it again: one answer per state
        key = (id(statement), state, name)
        found = self._afters.get(key)
        if found is None:
            found = self._afters[key] = self._compute_after(statement, state, name)
        return found

    def _compute_after(self, statement: ast.stmt, state: State, name: str) -> State:
        if isinstance(statement, _ENDS):
            return State.DEAD
        if isinstance(statement, ast.If):
            body, orelse = self._split(statement.test, state, name)
            return _join(self._run(statement.body, body, name), self._run(statement.orelse, orelse, name))
        if isinstance(statement, ast.Assert) and self._checks(statement.test, name) is True:
            return State.GYM
        if not self._binds(statement, name):
            return state
        if (
            isinstance(statement, ast.Assign)
            and len(statement.targets) == 1
            and isinstance(statement.targets[0], ast.Name)
            and statement.targets[0].id == name
            and not self._binds(statement.value, name)
        ):
            return State.GYM if self.value_is_env(statement.value) else State.OTHER
        return State.OTHER

    def _split(self, test: ast.expr, state: State, name: str) -> tuple[State, State]:
        """The states where the body and the else of ``if test:`` start."""
        if self._binds(test, name):
            return State.OTHER, State.OTHER
        checked = self._checks(test, name)
        if checked is None and self._checks_other_class(test, name):
            # ``elif isinstance(env, PlainEnv):``: its body holds that class's instance; where
            # the check fails, nothing is learnt
            negated = isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not)
            return (state, State.OTHER_CLASS) if negated else (State.OTHER_CLASS, state)
        if checked is None:
            if isinstance(test, ast.BoolOp) and isinstance(test.op, ast.And) and any(
                not isinstance(v, ast.UnaryOp) and self._checks(v, name) is True for v in test.values
            ):
                # ``isinstance(x, type) and issubclass(x, gym.Env)``: the body runs only where
                # every operand holds; the else learns nothing
                return State.GYM, state
            return state, state
        # ``isinstance(x, str)``: its branch holds no env (until it rebinds the name)
        narrowed = State.GYM if checked else State.OTHER
        # where a Gym env check fails, a name that was not known to be one is certainly none
        other = State.NOT_GYM if checked and state is State.OTHER else state
        negated = isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not)
        return (other, narrowed) if negated else (narrowed, other)

    def _checks(self, test: ast.expr, name: str) -> bool | None:
        """``isinstance(name, <Gym env class>)`` (or ``not`` it; ``issubclass`` for that
        check): True; ``isinstance(name, str)``: False; anything else: None."""
        if isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not):
            test = test.operand
        if isinstance(test, ast.BoolOp) and isinstance(test.op, ast.Or):
            # ``isinstance(x, gym.Env) or isinstance(x, gym.Wrapper)``: true only of a Gym env
            # when every operand checks for Gym env classes
            found = [self._checks(value, name) if not isinstance(value, ast.UnaryOp) else None for value in test.values]
            return True if found and all(f is True for f in found) else None
        if not (
            isinstance(test, ast.Call)
            and isinstance(test.func, ast.Name)
            and test.func.id == self.check
            and len(test.args) == 2
            and not test.keywords
            and isinstance(test.args[0], ast.Name)
            and test.args[0].id == name
        ):
            return None
        if not self._is_builtin(test.func, self.check):
            return None
        classes = test.args[1]
        if self.check == "isinstance" and isinstance(classes, ast.Name) and classes.id == "str" and self._is_builtin(classes, "str"):
            return False
        items = self._class_items(classes)
        if items and all(self._is_gym_env_class(item) or self._run_class_is_env(item) is True for item in items):
            # ``isinstance(env, (RLEnv, gym.Env))`` with ``RLEnv`` a Gym env class of the run
            return True
        return None

    def _checks_other_class(self, test: ast.expr, name: str) -> bool:
        """``isinstance(name, C)`` (or ``not`` it) where every class named is shown to be no
        Gym env."""
        if isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not):
            test = test.operand
        if not (
            self.check == "isinstance"
            and isinstance(test, ast.Call)
            and isinstance(test.func, ast.Name)
            and test.func.id == "isinstance"
            and len(test.args) == 2
            and not test.keywords
            and isinstance(test.args[0], ast.Name)
            and test.args[0].id == name
            and self._is_builtin(test.func, "isinstance")
        ):
            return False
        items = self._class_items(test.args[1])
        return bool(items) and all(not self._is_gym_env_class(item) and self._run_class_is_env(item) is False for item in items)

    @staticmethod
    def _class_items(classes: ast.expr) -> list[ast.expr]:
        return list(classes.elts) if isinstance(classes, ast.Tuple) else [classes]

    def _run_class_is_env(self, item: ast.expr) -> bool | None:
        if self.check != "isinstance" or self.class_is_env is None:
            return None
        return self.class_is_env(item)

    def _is_gym_env_class(self, node: ast.expr) -> bool:
        found = self.facts.qualified_names(node)
        return bool(found) and all(N.strip_gym_prefix(q) in _GYM_ENV_CLASSES for q in found)

    def _is_builtin(self, node: ast.Name, builtin: str) -> bool:
        scope, _ = self.facts.resolve(builtin, self.facts.scope_of(node))
        return scope is None

    def _binds(self, node: ast.AST, name: str) -> bool:
        """A binding of ``name`` lies inside ``node`` (one in a nested def too: cautious)."""
        key = (id(node), name)
        found = self._bound.get(key)
        if found is None:
            found = self._bound[key] = self._walk_binds(node, name)
        return found

    @staticmethod
    def _walk_binds(node: ast.AST, name: str) -> bool:
        for inner in walk(node):
            if isinstance(inner, ast.Name) and inner.id == name and not isinstance(inner.ctx, ast.Load):
                return True
            if isinstance(inner, (*FUNCTIONS, ast.ClassDef)) and inner.name == name:
                return True
            if isinstance(inner, ast.alias) and (inner.asname or inner.name.split(".", 1)[0]) == name:
                return True
            if isinstance(inner, ast.ExceptHandler) and inner.name == name:
                return True
        return False


def isinstance_guards(
    facts: ModuleFacts, node: ast.AST, frame_ends: tuple[type[ast.AST], ...]
) -> Iterator[tuple[ast.If, str, ast.expr]]:
    """The ``if isinstance(name, classes):`` statements whose body holds ``node``, innermost
    first, each with the tested name and the classes' expression; the walk stops at the
    first of ``frame_ends`` around ``node`` (each caller says where a check stops holding
    for what it asks)."""
    child, parent = node, facts.parent(node)
    while parent is not None and not isinstance(parent, frame_ends):
        if isinstance(parent, ast.If) and any(child is statement for statement in parent.body):
            test = parent.test
            if (
                isinstance(test, ast.Call)
                and isinstance(test.func, ast.Name)
                and test.func.id == "isinstance"
                and len(test.args) == 2
                and isinstance(test.args[0], ast.Name)
            ):
                yield parent, test.args[0].id, test.args[1]
        child, parent = parent, facts.parent(parent)
