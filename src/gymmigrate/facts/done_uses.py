"""What a read of the legacy ``done`` flag is for: loop control or data.

After ``obs, r, terminated, truncated, info = env.step(a)`` plus ``done = terminated or
truncated``, a read of ``done`` still means "the episode is over". That is right for
loop control and bookkeeping, and wrong wherever the flag decides whether to bootstrap
from the next state (value targets, masks, replay transitions): there the Gymnasium
migration guide says to use ``terminated`` ("Value Bootstrapping":
``target = reward + (1 - terminated) * gamma * next_value``). This module sorts reads
into those groups by the syntax around them; anything it cannot place is AMBIGUOUS and
gets reported rather than guessed. The walk goes up from the read through ``ast``
parents, a few levels at most, and its answer is memoized per read.
"""

from __future__ import annotations

import ast
from enum import Enum

from gymmigrate.facts.module import FUNCTIONS, ModuleFacts, full_name, walk


class DoneUse(str, Enum):
    CONTROL = "loop control"  # if/while tests, break conditions, ``done = done or ...``, assertions
    NEUTRAL = "display"  # print, logging, f-strings: the episode-over meaning is right
    DATA = "value"  # arithmetic, tensors, replay writes: bootstrapping needs ``terminated``
    WRAPPER_RETURN = "wrapper return"  # ``return obs, r, done, info`` in a step(): the wrapper rules' job
    AMBIGUOUS = "unknown"


# Methods that store a transition (replay buffers, rollout lists, Keras-style agents).
STORE_METHODS = frozenset(
    {
        "add",
        "push",
        "store",
        "append",
        "insert",
        "put",
        "store_transition",
        "add_transition",
        "append_transition",
        "add_experience",
        "add_sample",
        "remember",
        "memorize",
        "memorise",
        "extend",  # ``self.transition.extend([next_state, reward, done])``
    }
)
# Method names too common to mean "store a transition" unless the receiver says so.
GENERIC_STORE_METHODS = frozenset({"add", "insert", "put", "extend"})
_STORAGE_WORDS = ("buffer", "memory", "replay", "storage", "rollout", "experience", "transition", "queue")
_STORAGE_TOKENS = frozenset({"rb", "mem", "per", "her"})  # whole ``_``-separated parts only
# Calls that turn the flag into a number or a tensor (the value feeds arithmetic).
TENSOR_FACTORIES = frozenset(
    {
        "tensor",
        "Tensor",
        "FloatTensor",
        "BoolTensor",
        "ByteTensor",
        "LongTensor",
        "as_tensor",
        "from_numpy",
        "array",
        "asarray",
        "float16",
        "float32",
        "float64",
        "int32",
        "int64",
        "uint8",
        "constant",
        "convert_to_tensor",
    }
)
NUMBER_BUILTINS = frozenset({"float", "int"})
CONVERSION_METHODS = frozenset({"float", "double", "int", "long", "astype", "to", "type"})
# Reductions used to decide whether any episode ended (vector loops).
TEST_FUNCTIONS = frozenset({"any", "all", "nonzero", "flatnonzero", "where", "bool"})
# Counting finished episodes (``finished += dones.sum()``) is bookkeeping, not a target.
COUNTING_METHODS = frozenset({"sum", "count_nonzero"})
DISPLAY_FUNCTIONS = frozenset({"print", "str", "repr", "format", "pprint", "isinstance", "type"})
# Attributes that describe what the flag is (its class, dtype, shape), never its value: a
# test on them picks a code path, as ``isinstance(done, bool)`` does.
_TYPE_ATTRIBUTES = frozenset({"__class__", "dtype", "shape", "ndim"})
DISPLAY_METHODS = frozenset({"debug", "info", "warning", "warn", "log", "write", "add_scalar", "set_postfix", "format"})


def classify_done_read(read: ast.Name, facts: ModuleFacts) -> DoneUse:
    """Sort one read of the done flag by what the code around it does with it."""
    return facts.memo(("done-use", id(read)), lambda: _classify(read, facts))


def _classify(read: ast.Name, facts: ModuleFacts) -> DoneUse:
    if isinstance(facts.statement_of(read), ast.Assert):
        return DoneUse.CONTROL  # ``assert dones.dtype == np.bool_``: a check, never a target
    node: ast.AST = read
    in_container = False
    while True:
        parent = facts.parent(node)
        if parent is None:
            return DoneUse.AMBIGUOUS
        if isinstance(parent, (ast.BoolOp, ast.Compare)):
            node = parent
            continue
        if isinstance(parent, ast.UnaryOp):
            if isinstance(parent.op, ast.Not):
                node = parent
                continue
            return DoneUse.DATA  # ``-done``, ``~done``
        if isinstance(parent, ast.BinOp):
            return DoneUse.DATA
        if isinstance(parent, (ast.If, ast.While, ast.IfExp, ast.Assert)) and parent.test is node:
            return DoneUse.CONTROL
        if isinstance(parent, ast.Starred):
            holder = facts.parent(parent)
            if isinstance(holder, ast.Call):  # ``f(*done)``: an argument
                return _call_use(holder)
            node = holder or parent  # ``(*done, x)``: the tuple/list itself
            in_container = True
            continue
        if isinstance(parent, (ast.Tuple, ast.List, ast.Set)):
            node = parent
            in_container = True
            continue
        if isinstance(parent, ast.Dict):
            index = next((i for i, value in enumerate(parent.values) if value is node), None)
            if index is None or parent.keys[index] is None:
                return DoneUse.AMBIGUOUS  # a key, or ``**done``
            node = parent
            in_container = True
            continue
        if isinstance(parent, ast.For) and parent.iter is node and not in_container:
            loop = _loop_variable_use(parent, parent.target, facts)  # ``for d in dones: if d: ...``
            if loop is not None:
                return loop
        if (
            isinstance(parent, ast.Call)
            and isinstance(parent.func, ast.Name)
            and parent.func.id == "enumerate"
            and parent.args[:1] == [node]
            and not in_container
            and isinstance(loop_node := facts.parent(parent), ast.For)
            and loop_node.iter is parent
            and isinstance(loop_node.target, ast.Tuple)
            and len(loop_node.target.elts) == 2
        ):
            loop = _loop_variable_use(loop_node, loop_node.target.elts[1], facts)  # ``for i, d in enumerate(dones)``
            if loop is not None:
                return loop
        if isinstance(parent, ast.keyword):
            call = facts.parent(parent)
            if isinstance(call, ast.Call) and builds_record(call, facts):
                node, in_container = call, True
                continue
            return _call_use(call) if isinstance(call, ast.Call) else DoneUse.AMBIGUOUS
        if isinstance(parent, ast.Call) and parent.func is not node and builds_record(parent, facts):
            node, in_container = parent, True  # ``Experience(s, a, r, done, s2)``: a transition record
            continue
        if isinstance(parent, ast.Call):
            return DoneUse.AMBIGUOUS if parent.func is node else _call_use(parent)
        if isinstance(parent, ast.Subscript) and parent.value is node:
            node = parent  # ``dones[i]``: one env's flag is still the flag
            continue
        if isinstance(parent, ast.Attribute) and parent.value is node and parent.attr in _TYPE_ATTRIBUTES:
            return DoneUse.NEUTRAL  # ``done.__class__.__name__``, ``dones.dtype``: its type, not its value
        if isinstance(parent, ast.Attribute) and parent.value is node:
            return _method_use(parent, facts)
        if isinstance(parent, ast.Assign) and parent.value is node:
            return _assign_use(parent, read, in_container, node)
        if isinstance(parent, ast.Return):
            return DoneUse.WRAPPER_RETURN if _in_step_method(parent, facts) else DoneUse.AMBIGUOUS
        if isinstance(parent, (ast.FormattedValue, ast.Expr)):
            return DoneUse.NEUTRAL
        return DoneUse.AMBIGUOUS


def _loop_variable_use(loop: ast.For, target: ast.expr, facts: ModuleFacts) -> DoneUse | None:
    """A loop over the done flags whose variable only decides control flow (``if d: ...``,
    e.g. picking each finished env's final observation) is control flow itself; None when
    the variable is used otherwise (its reads decide as before)."""
    if not isinstance(target, ast.Name):
        return None
    reads = [
        node
        for statement in loop.body
        for node in walk(statement)
        if isinstance(node, ast.Name) and node.id == target.id
    ]
    if not reads or any(not isinstance(node.ctx, ast.Load) for node in reads):
        return None
    if all(classify_done_read(node, facts) in (DoneUse.CONTROL, DoneUse.NEUTRAL) for node in reads):
        return DoneUse.CONTROL
    return None


def _call_use(call: ast.Call) -> DoneUse:
    name = full_name(call.func) or ""
    last = name.rsplit(".", 1)[-1]
    if last in NUMBER_BUILTINS and (isinstance(call.func, ast.Name) or name.startswith(("np.", "numpy."))):
        return DoneUse.DATA  # ``float(done)``, numpy's old alias ``np.float(done)``
    if isinstance(call.func, ast.Name) and last in DISPLAY_FUNCTIONS:
        return DoneUse.NEUTRAL
    if last in TEST_FUNCTIONS or last.startswith("assert"):
        return DoneUse.CONTROL  # ``self.assertTrue(done)``, ``np.testing.assert_equal``: checks
    if isinstance(call.func, ast.Attribute):
        if last in TENSOR_FACTORIES:
            return DoneUse.DATA
        if last in STORE_METHODS and (last not in GENERIC_STORE_METHODS or _looks_like_storage(call.func.value)):
            return DoneUse.DATA
        if last in DISPLAY_METHODS or name.startswith(("logging.", "logger.", "log.")):
            return DoneUse.NEUTRAL
    elif last in TENSOR_FACTORIES:  # ``from numpy import array``
        return DoneUse.DATA
    return DoneUse.AMBIGUOUS


_RECORD_FACTORIES = frozenset({"namedtuple", "NamedTuple"})


def builds_record(call: ast.Call, facts: ModuleFacts) -> bool:
    """``Experience(state, action, reward, done, new_state)``: a call of a record class of
    this module, at module level or in a def (a ``namedtuple``, a ``NamedTuple`` or a
    ``@dataclass``), or of another module of the run (``from .memory import Transition``),
    whose fields hold the values as a tuple would."""
    if isinstance(call.func, ast.Name) and call.func.id in _record_classes(facts):
        return True
    return isinstance(call.func, (ast.Name, ast.Attribute)) and any(facts.is_run_record(q) for q in facts.qualified_names(call.func))


def top_level_records(tree: ast.Module) -> frozenset[str]:
    """The module-level record classes of ``tree`` (``ModuleSummary.record_classes``)."""
    names: set[str] = set()
    for statement in tree.body:
        if isinstance(statement, ast.Assign) and _is_record_factory_call(statement.value):
            names.update(t.id for t in statement.targets if isinstance(t, ast.Name))
        elif isinstance(statement, ast.ClassDef) and _is_record_class(statement):
            names.add(statement.name)
    return frozenset(names)


def _is_record_factory_call(value: ast.AST) -> bool:
    return isinstance(value, ast.Call) and (full_name(value.func) or "").rsplit(".", 1)[-1] in _RECORD_FACTORIES


def _is_record_class(statement: ast.ClassDef) -> bool:
    return any((full_name(base) or "").rsplit(".", 1)[-1] == "NamedTuple" for base in statement.bases) or any(
        (full_name(d.func if isinstance(d, ast.Call) else d) or "").rsplit(".", 1)[-1] == "dataclass" for d in statement.decorator_list
    )


def _record_classes(facts: ModuleFacts) -> frozenset[str]:
    def compute() -> frozenset[str]:
        names: set[str] = set()
        # module level or local to a def (``Transition = namedtuple(...)`` inside ``train``)
        for statement in walk(facts.tree):
            if isinstance(statement, ast.Assign) and _is_record_factory_call(statement.value):
                names.update(t.id for t in statement.targets if isinstance(t, ast.Name))
            elif isinstance(statement, ast.ClassDef) and _is_record_class(statement):
                names.add(statement.name)
        return frozenset(names)

    return facts.memo(("record-classes", id(facts.tree)), compute)


def _looks_like_storage(receiver: ast.expr) -> bool:
    name = (full_name(receiver) or "").rsplit(".", 1)[-1].lower()
    return any(word in name for word in _STORAGE_WORDS) or bool(_STORAGE_TOKENS & set(name.split("_")))


def _method_use(attribute: ast.Attribute, facts: ModuleFacts) -> DoneUse:
    call = facts.parent(attribute)
    if not isinstance(call, ast.Call) or call.func is not attribute:
        return DoneUse.AMBIGUOUS
    method = attribute.attr
    if method in CONVERSION_METHODS:
        return DoneUse.DATA
    if method in TEST_FUNCTIONS:
        return DoneUse.CONTROL
    if method in COUNTING_METHODS:
        return DoneUse.NEUTRAL
    return DoneUse.AMBIGUOUS


def _assign_use(assign: ast.Assign, read: ast.expr, in_container: bool, value: ast.AST) -> DoneUse:
    targets = assign.targets
    # ``done = done or step >= limit`` (``self.done = self.done or ...``): still the episode-over flag.
    if len(targets) == 1 and ast.dump(targets[0], annotate_fields=False).replace("Store()", "Load()") == ast.dump(read, annotate_fields=False):
        return DoneUse.CONTROL
    if in_container and isinstance(value, (ast.Tuple, ast.List, ast.Dict, ast.Call)):
        return DoneUse.DATA  # ``transition = (s, a, r, s2, done)``, ``exp = Experience(...)``
    either = isinstance(value, ast.BoolOp) and isinstance(value.op, ast.Or)
    if (value is read or either) and any(_is_bookkeeping(t) for t in targets):
        # ``info["real_done"] = done``, ``self.was_real_done = done``, ``real_done =
        # info.get("was_real_done") or done``: game over
        return DoneUse.NEUTRAL
    if all(isinstance(t, ast.Subscript) for t in targets) and value is read:
        return DoneUse.DATA  # ``dones[t] = done``: a rollout array
    return DoneUse.AMBIGUOUS  # ``episode_done = done``: depends on what the new name is for


_BOOKKEEPING_WORDS = ("real_done", "game_over", "gameover", "episode_over", "all_done")


def _is_bookkeeping(target: ast.expr) -> bool:
    """A record of the episode (or game) being over: a string-keyed entry (``info["real_done"]``)
    or a name that says game over (``self.was_real_done``). ``done`` is the right value there."""
    if isinstance(target, ast.Subscript):
        key = target.slice
        return isinstance(key, ast.Constant) and isinstance(key.value, str)
    name = (full_name(target) or "").rsplit(".", 1)[-1].lower()
    return any(word in name for word in _BOOKKEEPING_WORDS)


def multiplies_bare(read: ast.expr, parent_of) -> bool:
    """``q_next * gamma * done``: the flag itself (or one element of it, or it as a number:
    ``dones[i]``, ``float(done)``, ``done.float()``) is a factor. That is no mask, which reads
    ``1 - done`` / ``~done`` / ``not done``: the legacy code bootstraps only when the episode
    ends, and ``terminated`` there would drop the bootstrap on a time-limit truncation.
    ``parent_of`` gives a node's parent."""
    node: ast.AST = read
    while True:
        parent = parent_of(node)
        if isinstance(parent, ast.Subscript) and parent.value is node:
            node = parent
        elif isinstance(parent, ast.Call) and parent.args[:1] == [node] and not parent.keywords[1:]:
            last = (full_name(parent.func) or "").rsplit(".", 1)[-1]
            if last not in NUMBER_BUILTINS and last not in TENSOR_FACTORIES:
                return False
            node = parent
        elif isinstance(parent, ast.Attribute) and parent.value is node and parent.attr in CONVERSION_METHODS:
            call = parent_of(parent)
            if not (isinstance(call, ast.Call) and call.func is parent):
                return False
            node = call
        else:
            return isinstance(parent, ast.BinOp) and isinstance(parent.op, (ast.Mult, ast.MatMult))


def falsy_constant(node: ast.AST) -> bool:
    return isinstance(node, ast.Constant) and not node.value and not isinstance(node.value, str)


def always_false_here(read: ast.Name, facts: ModuleFacts) -> bool:
    """``if done: obs = env.reset(); done = False`` right before the statement of ``read``
    (``return obs, done``): whichever way the ``if`` went, the name holds a false value
    there (it was false, or the branch set it so). A constant false also counts."""
    statement = facts.statement_of(read)
    holder = facts.parent(statement)
    block = next(
        (b for field in ("body", "orelse", "finalbody") if isinstance(b := getattr(holder, field, None), list) and statement in b),
        None,
    )
    if block is None or block.index(statement) == 0:
        return False
    before = block[block.index(statement) - 1]
    return (
        isinstance(before, ast.If)
        and not before.orelse
        and isinstance(before.test, ast.Name)
        and before.test.id == read.id
        and isinstance(last := before.body[-1], ast.Assign)
        and len(last.targets) == 1
        and isinstance(last.targets[0], ast.Name)
        and last.targets[0].id == read.id
        and falsy_constant(last.value)
        and not any(isinstance(n, (ast.Return, ast.Break, ast.Continue, ast.Raise)) for n in walk(before))
    )


def value_site(read: ast.AST, facts: ModuleFacts) -> ast.AST:
    """The one value ``read`` is part of: the whole expression up to its statement (a TD
    target, a stored transition, the arguments of a store call), or one element of a
    parallel assignment (``next_obs, next_done = f(next_obs), g(done)``: two values)."""
    node = read
    while True:
        parent = facts.parent(node)
        if parent is None or isinstance(parent, (ast.Lambda, ast.comprehension)):
            return node
        if isinstance(parent, (ast.Tuple, ast.List)):
            holder = facts.parent(parent)
            if (
                isinstance(holder, ast.Assign)
                and holder.value is parent
                and len(holder.targets) == 1
                and isinstance(holder.targets[0], (ast.Tuple, ast.List))
                and len(holder.targets[0].elts) == len(parent.elts)
            ):
                return node
        if isinstance(parent, ast.stmt):
            return node
        node = parent


def stored_in_sequence(read: ast.AST, facts: ModuleFacts) -> bool:
    """The flag goes into a per-step sequence (``dones.append(done)``, ``dones[t] = done``,
    ``buffer.store(v, r, done)``, ``next_done = torch.Tensor(done)``), not into an expression
    that uses it right away."""
    site = value_site(read, facts)
    if isinstance(site, ast.Call):
        last = (full_name(site.func) or "").rsplit(".", 1)[-1]
        if last in STORE_METHODS:
            return True
    statement = facts.statement_of(read)
    if isinstance(statement, ast.Assign):
        if any(isinstance(t, ast.Subscript) for t in statement.targets):
            return True
        return not any(isinstance(n, (ast.BinOp, ast.UnaryOp)) for n in walk(site))
    return False


def loaded_names(node: ast.AST) -> set[str]:
    return {n.id for n in walk(node) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load)}


def _in_step_method(node: ast.AST, facts: ModuleFacts) -> bool:
    function = facts.enclosing(node, (*FUNCTIONS, ast.Lambda))
    return isinstance(function, FUNCTIONS) and function.name == "step"
