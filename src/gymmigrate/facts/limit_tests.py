"""What a test of a step or time limit looks like, on one expression: a comparison of a
step or time counter with a bound (``STEP_LIMIT_WORD``, ``is_step_limit``), not a period nor
the end of the env's data (``is_end_of_data``, ``data_end_attributes``), and the small
shapes the step rules and ``DoneTracer`` (limits.py) share around it (``if <test>: done =
True``, ``bool(x)``, ``counter < limit``, dm_env's ``time_step.last()``).
"""

from __future__ import annotations

import ast
import re
from collections.abc import Collection
from typing import TypeVar

from gymmigrate.facts.env_classes import identifiers
from gymmigrate.facts.module import ModuleFacts, own_returns, self_attribute, walk
from gymmigrate.facts.self_attributes import class_self_stores, self_stores

# A word that counts steps or time (matched on the lower-cased identifier: ``MAX_STEPS``
# too). ``cycles``, ``frames`` and ``num_moves`` are how PettingZoo's envs count theirs
# (``self.frames >= self.max_cycles``); a bare ``moves`` is often a list of legal moves.
STEP_LIMIT_WORD = re.compile(
    r"(^|_)(t|ts|step|steps|timestep|timesteps|tick|ticks|iter|iters|iteration|iterations|horizon|"
    r"time|time_limit|seconds|secs|ep_len|episode_len|episode_length|counter|cycle|cycles|frame|frames|num_moves|n_moves)(_|$)"
)
LIMIT_OPS = (ast.Gt, ast.GtE, ast.Lt, ast.LtE, ast.Eq)


def is_periodic(expr: ast.AST) -> bool:
    """``self.t % FREQ == 0``: a test that comes true every so many steps, not a limit."""
    return any(isinstance(node, ast.BinOp) and isinstance(node.op, ast.Mod) for node in walk(expr))


def is_step_limit(expr: ast.AST, data_ends: Collection[str] = (), streaks: Collection[str] = ()) -> bool:
    """A comparison that names a step or time counter (``self.steps >= self.max_steps``),
    unless it tests the end of the env's data (``is_end_of_data``; ``data_ends``: the
    class's attributes bound to its data's length) or a run of consecutive steps
    (``streaks``: the class's counters that start over, ``streak_attributes``)."""
    if not isinstance(expr, ast.Compare) or not all(isinstance(op, LIMIT_OPS) for op in expr.ops):
        return False
    if is_periodic(expr) or is_end_of_data(expr, data_ends):
        return False
    if streaks and any(self_attribute(_minus_constant(side)) in streaks for side in (expr.left, *expr.comparators)):
        return False
    return any(STEP_LIMIT_WORD.search(word.lower()) and "beyond" not in word for word in identifiers(expr))


def self_field(node: ast.AST | None) -> tuple[str, str] | None:
    """A value the instance keeps from step to step, with the word that names it: ``self.n``
    (``("n", "n")``), or one named entry of a dict it holds, ``self.state["count"]``
    (``("state['count']", "count")``), which counts the same way. None for anything else,
    an entry of a number index among them (``self.pos[1]``: a coordinate)."""
    name = self_attribute(node)
    if name is not None:
        return name, name
    if isinstance(node, ast.Subscript) and isinstance(node.slice, ast.Constant) and isinstance(node.slice.value, str):
        holder = self_attribute(node.value)
        if holder is not None:
            return f"{holder}[{node.slice.value!r}]", node.slice.value
    return None


def is_local_sign_test(facts: ModuleFacts, test: ast.Compare) -> bool:
    """``time_to_sleep > 0`` on a name only the enclosing function assigns: a value of
    this one call (a delay, a margin), not a counter, which a step limit needs to keep
    from step to step on the instance, whatever the name says."""
    if len(test.ops) != 1:
        return False
    left, right = test.left, test.comparators[0]
    name = left if _is_zero(right) else right if _is_zero(left) else None
    if not isinstance(name, ast.Name):
        return False
    function = facts.enclosing_function(test)
    bindings = facts.bindings_of(name)
    return (
        function is not None
        and bool(bindings)
        and all(not isinstance(b, ast.arg) and facts.enclosing_function(b) is function for b in bindings)
    )


def compares_the_action(facts: ModuleFacts, test: ast.Compare) -> bool:
    """``self.queued_step == action`` in ``step``: a side is a parameter of the step itself
    (the action the agent chose), never a count the env keeps nor its bound, whatever the
    other side is called: a comparison of values, not a step limit."""
    function = facts.enclosing_function(test)
    if function is None or function.name != "step":
        return False
    parameters = {a.arg for a in (*function.args.posonlyargs, *function.args.args, *function.args.kwonlyargs)[1:]}
    return any(
        isinstance(side, ast.Name)
        and side.id in parameters
        and all(isinstance(b, ast.arg) for b in facts.bindings_of(side))
        for side in (test.left, *test.comparators)
    )


def _is_zero(expr: ast.AST) -> bool:
    return isinstance(expr, ast.Constant) and isinstance(expr.value, (int, float)) and not isinstance(expr.value, bool) and expr.value == 0


def _minus_constant(expr: ast.AST) -> ast.AST:
    """``x - 1`` (or ``x + 1``) -> ``x``: an index's offset from a length."""
    while isinstance(expr, ast.BinOp) and isinstance(expr.op, (ast.Add, ast.Sub)) and _number(expr.right):
        expr = expr.left
    return expr


def _number(expr: ast.AST) -> bool:
    return isinstance(expr, ast.Constant) and isinstance(expr.value, (int, float)) and not isinstance(expr.value, bool)


def is_data_length(expr: ast.AST) -> bool:
    """``len(x)``, ``x.shape[0]``, either minus a constant (``len(self.df.index.unique()) - 1``):
    the length of something the env holds, here the end of its data, not a step budget."""
    expr = _minus_constant(expr)
    if isinstance(expr, ast.Call):
        return isinstance(expr.func, ast.Name) and expr.func.id == "len" and len(expr.args) == 1 and not expr.keywords
    return (
        isinstance(expr, ast.Subscript)
        and isinstance(expr.value, ast.Attribute)
        and expr.value.attr == "shape"
        and isinstance(expr.slice, ast.Constant)
        and expr.slice.value == 0
    )


def is_end_of_data(expr: ast.AST, data_ends: Collection[str] = ()) -> bool:
    """``self.day == self.max_step`` where the class binds ``self.max_step`` only to a data
    length (``data_ends``), or ``self.t >= len(self.prices) - 1``: the counter reaches the
    last row of the env's data, after which the episode cannot go on. A terminal state (legacy
    learners did not bootstrap there), not a time limit, whatever the names say. Not when the
    other side is itself a budget (``len(self.history) >= self.max_steps``, ``>= 200``)."""
    if not isinstance(expr, ast.Compare) or len(expr.ops) != 1 or not isinstance(expr.ops[0], LIMIT_OPS):
        return False

    def bound(side: ast.AST) -> bool:
        name = self_attribute(_minus_constant(side))
        return is_data_length(side) or (name is not None and name in data_ends)

    sides = (expr.left, expr.comparators[0])
    return any(bound(a) and not bound(b) and not is_data_length(b) and not _is_bound_name(b) for a, b in (sides, sides[::-1]))


def data_end_attributes(facts: ModuleFacts, classdef: ast.ClassDef) -> frozenset[str]:
    """The attributes every store of which in ``classdef`` is a data length
    (``self.max_step = self.price_ary.shape[0] - 1``): the end of the env's data, whatever
    the attribute is called. One store of anything else (a parameter, a constant) and the
    attribute may be a step budget: it is not one of these."""

    def compute() -> frozenset[str]:
        found = set()
        for name, attrs in facts.attributes.items():
            if not any(isinstance(a.ctx, ast.Store) and is_self(a.value) and facts.enclosing_class(a) is classdef for a in attrs):
                continue
            values = self_stores(facts, classdef, name)
            if values and all(is_data_length(v) for v in values):
                found.add(name)
        return frozenset(found)

    return facts.memo(("data-end-attributes", id(classdef)), compute)


def streak_attributes(facts: ModuleFacts, classdef: ast.ClassDef) -> frozenset[str]:
    """The attributes ``classdef`` counts only while something holds and starts over when it
    does not: ``self.n = self.n + 1 if landed else 0``, or ``if landed: self.n += 1`` with
    ``else: self.n = 0``. Such a count is a run of consecutive steps (legs on the pad for a
    second, a goal held), not the episode's steps: reaching its bound is something the task
    did, never a time limit, whatever the attribute is called. A count that every step
    advances is no streak, nor one that starts over only at a bound of its own (a wrap,
    ``if self.t >= T: self.t = 0``) or at the episode's end (``if done: self.t = 0``, the
    test reading what the method returns as its done)."""

    def compute() -> frozenset[str]:
        found = set()
        for node in walk(classdef):
            test: ast.expr
            stores: dict[str, tuple[ast.AST, ast.AST]]
            if isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.value, ast.IfExp):
                name = self_attribute(node.targets[0])
                test, stores = node.value.test, {name: (node.value.body, node.value.orelse)} if name is not None else {}
            elif isinstance(node, ast.If) and node.orelse:
                counted, otherwise = _block_stores(node.body), _block_stores(node.orelse)
                test, stores = node.test, {name: (counted[name], otherwise[name]) for name in counted.keys() & otherwise.keys()}
            else:
                continue
            for name, values in stores.items():
                if _reads_attribute(test, name) or _reads_done(facts, node, test):
                    continue
                if _counts_or_restarts(values, name):
                    found.add(name)
        return frozenset(found)

    return facts.memo(("streak-attributes", id(classdef)), compute)


def _reads_attribute(test: ast.AST, name: str) -> bool:
    return any(self_attribute(node) == name for node in walk(test))


def _reads_done(facts: ModuleFacts, node: ast.AST, test: ast.AST) -> bool:
    """``test`` reads a name or ``self`` attribute that the method holding ``node`` returns
    as its done (the third of four values): the episode's end."""
    function = facts.enclosing_function(node)
    if function is None:
        return False
    returned = {
        part.id if isinstance(part, ast.Name) else self_attribute(part)
        for ret in own_returns(function)
        if isinstance(ret.value, ast.Tuple) and len(ret.value.elts) == 4
        for part in walk(ret.value.elts[2])
    } - {None}
    return any((n.id if isinstance(n, ast.Name) else self_attribute(n)) in returned for n in walk(test))


def _counts_or_restarts(values: tuple[ast.AST, ast.AST], name: str) -> bool:
    """One value advances ``self.<name>`` by a number, the other is a number (a restart)."""
    first, second = values
    return any(_advances(a, name) and _number(b) for a, b in ((first, second), (second, first)))


def _advances(value: ast.AST, name: str) -> bool:
    """``self.<name> + 1`` (or minus a number): the value of a count one step on."""
    return (
        isinstance(value, ast.BinOp)
        and isinstance(value.op, (ast.Add, ast.Sub))
        and self_attribute(value.left) == name
        and _number(value.right)
    )


def _block_stores(block: list[ast.stmt]) -> dict[str, ast.AST]:
    """The ``self`` attributes the statements of ``block`` store to, each with the value its
    last store gives it (``self.n += 1`` gives ``self.n + 1``)."""
    found: dict[str, ast.AST] = {}
    for statement in block:
        if isinstance(statement, ast.AugAssign) and (name := self_attribute(statement.target)) is not None:
            found[name] = ast.BinOp(left=statement.target, op=statement.op, right=statement.value)
        elif isinstance(statement, ast.Assign) and len(statement.targets) == 1 and (name := self_attribute(statement.targets[0])) is not None:
            found[name] = statement.value
    return found


def if_setting_true(line: ast.AST, parent: ast.AST | None) -> ast.If | None:
    """The ``if`` of ``if <test>: done = True`` (a plain name set to ``True`` in a branch of
    ``parent``): what the "done is set when ..." checks of the step rules share (a task's own
    end in an env's step, a step limit or a lost life in a wrapper's), each with its own test
    and its own demand on the other branch. None for any other line."""
    if not (
        isinstance(line, ast.Assign)
        and len(line.targets) == 1
        and isinstance(line.targets[0], ast.Name)
        and isinstance(line.value, ast.Constant)
        and line.value.value is True
        and isinstance(parent, ast.If)
        and (line in parent.body or line in parent.orelse)
    ):
        return None
    return parent


def added_end_tests(line: ast.AST, name: str, parent: ast.AST | None) -> list[ast.expr] | None:
    """The tests of the end of its own that ``line`` adds to the flag ``name``, which it leaves
    as it was otherwise: ``name = True`` in one branch of an ``if`` whose other branch binds
    no ``name`` (``[<the if's test>]``), or ``name = name or <a> or <b>``, the flag anywhere
    in the ``or`` and read nowhere else in it (``[<a>, <b>]``). None for any other line: an
    ``if`` that sets the flag both ways decides it, it adds no end to it."""
    branch = if_setting_true(line, parent)
    if branch is not None:
        if line.targets[0].id != name:  # type: ignore[attr-defined]
            return None
        other = branch.orelse if line in branch.body else branch.body
        binds = any(isinstance(n, ast.Name) and n.id == name and isinstance(n.ctx, ast.Store) for s in other for n in walk(s))
        return None if binds else [branch.test]
    if not (isinstance(line, ast.Assign) and len(line.targets) == 1 and isinstance(line.targets[0], ast.Name)):
        return None
    value = line.value
    if line.targets[0].id != name or not (isinstance(value, ast.BoolOp) and isinstance(value.op, ast.Or)):
        return None
    rest = [v for v in value.values if not (isinstance(v, ast.Name) and v.id == name)]
    if len(rest) != len(value.values) - 1 or any(isinstance(n, ast.Name) and n.id == name for v in rest for n in walk(v)):
        return None
    return rest


def own_task_end(
    line: ast.AST, name: str, parent: ast.AST | None, data_ends: Collection[str] = (), streaks: Collection[str] = ()
) -> list[ast.expr] | None:
    """The tests of the end of the task that ``line`` adds to the flag ``name``
    (``added_end_tests``), where none compares a step or time counter with its bound: an
    end on a step limit or a budget is a truncation, whatever else its test reads, never a
    terminal state. The step overrides of env classes (GM504) and of wrappers (GM602) share
    it; a wrapper, which does not define the task, also asks its tests to show the end."""
    tests = added_end_tests(line, name, parent)
    if tests is None or any(isinstance(n, ast.Compare) and is_step_limit(n, data_ends, streaks) for t in tests for n in walk(t)):
        return None
    return tests


_AnyNode = TypeVar("_AnyNode", bound=ast.AST)


def unwrap_bool(expr: _AnyNode) -> _AnyNode | ast.expr:
    """``bool(x)`` -> ``x``; anything else as it is."""
    if (
        isinstance(expr, ast.Call)
        and isinstance(expr.func, ast.Name)
        and expr.func.id == "bool"
        and len(expr.args) == 1
        and not expr.keywords
        and not isinstance(expr.args[0], ast.Starred)
    ):
        return expr.args[0]
    return expr


def or_operands(expr: ast.expr) -> list[ast.expr]:
    if isinstance(expr, ast.BoolOp) and isinstance(expr.op, ast.Or):
        return [operand for value in expr.values for operand in or_operands(value)]
    return [expr]


def is_self(node: ast.AST) -> bool:
    return isinstance(node, ast.Name) and node.id == "self"


def under_limit(test: ast.AST) -> bool:
    """``counter < limit`` (or ``limit > counter``): true while the episode (or match) goes on."""
    if not (isinstance(test, ast.Compare) and len(test.ops) == 1):
        return False
    left_is_limit = _is_bound_name(test.left)
    if isinstance(test.ops[0], (ast.Lt, ast.LtE)):
        return not left_is_limit
    if isinstance(test.ops[0], (ast.Gt, ast.GtE)):
        return left_is_limit
    return False


def _is_bound_name(expr: ast.AST) -> bool:
    """A limit rather than a counter: a number, a CONSTANT, or a name that says max/limit."""
    if isinstance(expr, ast.Constant):
        return True
    name = expr.attr if isinstance(expr, ast.Attribute) else expr.id if isinstance(expr, ast.Name) else ""
    return name.isupper() or any(word in name.lower() for word in ("max", "limit", "horizon"))


def is_limit_setting_test(expr: ast.AST) -> bool:
    """``self.t_limit > 0``, ``self.max_steps == 0``: a bound compared with zero, which asks
    whether a limit is set (a mode of the env), not whether a count has reached it."""
    if not (isinstance(expr, ast.Compare) and len(expr.ops) == 1):
        return False
    left, right = expr.left, expr.comparators[0]
    bound = left if _is_zero(right) else right if _is_zero(left) else None
    return bound is not None and not isinstance(bound, ast.Constant) and _is_bound_name(bound)


def limit_under_guard(expr: ast.AST) -> ast.expr | None:
    """``self.max_steps is not None and self.t >= self.max_steps`` (or ``self.max_steps and
    ...``): the one operand of an ``and`` beside tests that only ask whether a value it reads
    is set; that operand is the test itself, which cannot hold while the value is unset."""
    if not (isinstance(expr, ast.BoolOp) and isinstance(expr.op, ast.And)):
        return None
    guards: list[str] = []
    rest: list[ast.expr] = []
    for operand in expr.values:
        guarded = _presence_test(operand)
        if guarded is not None:
            guards.append(guarded)
        else:
            rest.append(operand)
    if len(rest) != 1 or not guards:
        return None
    read = {ast.unparse(node) for node in walk(rest[0]) if isinstance(node, (ast.Name, ast.Attribute))}
    return rest[0] if all(guard in read for guard in guards) else None


def _presence_test(expr: ast.expr) -> str | None:
    """``x is not None`` or a bare ``x`` / ``self.x``: the text of what it asks to be set."""
    if isinstance(expr, (ast.Name, ast.Attribute)):
        return ast.unparse(expr)
    if (
        isinstance(expr, ast.Compare)
        and len(expr.ops) == 1
        and isinstance(expr.ops[0], ast.IsNot)
        and isinstance(expr.comparators[0], ast.Constant)
        and expr.comparators[0].value is None
        and isinstance(expr.left, (ast.Name, ast.Attribute))
    ):
        return ast.unparse(expr.left)
    return None


# Draws of a random number: NumPy's and the standard library's modules, and the generators
# envs keep (``self.np_random.integers``, ``self.rng.random``).
_RANDOM_MODULES = ("numpy.random.", "random.", "torch.rand")
_GENERATOR_WORD = re.compile(r"(^|_)(rng|np_random|random_state|generator|random)$")


def draws_at_random(facts: ModuleFacts, expr: ast.AST) -> bool:
    """``expr`` calls a random draw anywhere in it."""
    for node in walk(expr):
        if not isinstance(node, ast.Call):
            continue
        if any(q.startswith(_RANDOM_MODULES) for q in facts.qualified_names(node.func)):
            return True
        owner = node.func.value if isinstance(node.func, ast.Attribute) else None
        while isinstance(owner, ast.Attribute):
            if _GENERATOR_WORD.search(owner.attr.lower()):
                return True
            owner = owner.value
        if isinstance(owner, ast.Name) and _GENERATOR_WORD.search(owner.id.lower()):
            return True
    return False


def random_bound(facts: ModuleFacts, classdef: ast.ClassDef, test: ast.Compare) -> list[str]:
    """The attributes of the bound side of the limit ``test`` that the class sets from a
    random draw (``self.horizon = 6 + np.random.randint(10)``): a horizon drawn per episode,
    which may be the task's own length. The other side must not start from the same draw
    (``self.t = self.start`` against ``self.start + self.length``: a random start, a fixed
    length). Empty for anything else."""
    if len(test.ops) != 1:
        return []
    sides = (test.left, test.comparators[0])
    attributes = [{a for node in walk(side) if (a := self_attribute(node)) is not None} for side in sides]
    drawn = [
        {a for a in names if any(draws_at_random(facts, value) for value in self_stores(facts, classdef, a) or ())} for names in attributes
    ]
    for index in (0, 1):
        other = attributes[1 - index]
        if drawn[index] and not drawn[1 - index]:
            starts = [value for a in other for value in class_self_stores(facts, classdef).get(a, ())]
            if any(self_attribute(node) in drawn[index] for value in starts for node in walk(value)):
                return []
            return sorted(drawn[index])
    return []


def is_dm_env_last(facts: ModuleFacts, call: ast.Call) -> bool:
    """``time_step.last()`` in a module that uses dm_control or dm_env: the ``TimeStep``'s
    end of episode, which dm_control's environments also signal at their time limit."""
    return (
        isinstance(call.func, ast.Attribute)
        and call.func.attr == "last"
        and not call.args
        and not call.keywords
        and ("dm_control" in facts.text or "dm_env" in facts.text)
    )


def elapsed_since_step_mark(facts: ModuleFacts, test: ast.AST) -> bool:
    """``lost = time.time() - self.seen_at`` then ``lost > 5``, where the method holding the
    test also moves ``self.seen_at`` (on the step the target is seen): the value is the time
    since an event of the task, which starts over within the episode, like a streak of
    steps; an episode's own clock is marked only where it begins (reset), never by the step
    that reads it. The local's every binding is such a difference, in the same method."""
    if not isinstance(test, ast.Compare):
        return False
    function = facts.enclosing_function(test)
    if function is None:
        return False
    moved = {
        name
        for node in walk(function)
        if isinstance(node, ast.Assign)
        for target in node.targets
        if (name := self_attribute(target)) is not None
    }
    for side in (test.left, *test.comparators):
        if not isinstance(side, ast.Name):
            continue
        bindings = facts.bindings_of(side)
        if bindings and all(_difference_from(facts, binding, function, moved) for binding in bindings):
            return True
    return False


def _difference_from(facts: ModuleFacts, binding: ast.AST, function: ast.AST, moved: set[str]) -> bool:
    holder = facts.parent(binding)
    if not (isinstance(holder, ast.Assign) and holder.targets == [binding]) or facts.enclosing_function(binding) is not function:
        return False
    value = holder.value
    return isinstance(value, ast.BinOp) and isinstance(value.op, ast.Sub) and self_attribute(value.right) in moved
