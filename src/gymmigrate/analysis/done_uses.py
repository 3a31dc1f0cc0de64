"""What a read of the legacy ``done`` flag is for: loop control or data.

After ``obs, r, terminated, truncated, info = env.step(a)`` plus ``done = terminated or
truncated``, a read of ``done`` still means "the episode is over". That is right for
loop control and bookkeeping, and wrong wherever the flag decides whether to bootstrap
from the next state (value targets, masks, replay transitions): there the Gymnasium
migration guide says to use ``terminated`` ("Value Bootstrapping":
``target = reward + (1 - terminated) * gamma * next_value``). This module sorts reads
into those groups by the syntax around them; anything it cannot place is AMBIGUOUS and
gets reported rather than guessed.
"""

from __future__ import annotations

from collections.abc import Callable
from enum import Enum

import libcst as cst
from libcst.helpers import get_full_name_for_node


class DoneUse(str, Enum):
    CONTROL = "loop control"  # if/while tests, break conditions, ``done = done or ...``
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
    }
)
# Method names too common to mean "store a transition" unless the receiver says so.
GENERIC_STORE_METHODS = frozenset({"add", "insert", "put"})
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
DISPLAY_METHODS = frozenset({"debug", "info", "warning", "warn", "log", "write", "add_scalar", "set_postfix", "format"})


def classify_done_read(read: cst.Name, parent_of: Callable[[cst.CSTNode], cst.CSTNode | None]) -> DoneUse:
    """Sort one read of the done flag by what the code around it does with it."""
    node: cst.CSTNode = read
    in_container = False
    while True:
        parent = parent_of(node)
        if parent is None:
            return DoneUse.AMBIGUOUS
        if isinstance(parent, (cst.BooleanOperation, cst.Comparison, cst.ComparisonTarget)):
            node = parent
            continue
        if isinstance(parent, cst.UnaryOperation):
            if isinstance(parent.operator, cst.Not):
                node = parent
                continue
            return DoneUse.DATA  # ``-done``, ``~done``
        if isinstance(parent, cst.BinaryOperation):
            return DoneUse.DATA
        if isinstance(parent, (cst.If, cst.While, cst.IfExp, cst.Assert)) and getattr(parent, "test", None) is node:
            return DoneUse.CONTROL
        if isinstance(parent, (cst.Element, cst.StarredElement, cst.DictElement)):
            if isinstance(parent, cst.DictElement) and parent.key is node:
                return DoneUse.AMBIGUOUS
            node = parent_of(parent) or parent  # the tuple/list/dict itself
            in_container = True
            continue
        if isinstance(parent, cst.Arg):
            call = parent_of(parent)
            return _call_use(call) if isinstance(call, cst.Call) else DoneUse.AMBIGUOUS
        if isinstance(parent, cst.Subscript) and parent.value is node:
            node = parent  # ``dones[i]``: one env's flag is still the flag
            continue
        if isinstance(parent, cst.Attribute) and parent.value is node:
            return _method_use(parent, parent_of)
        if isinstance(parent, cst.Assign) and parent.value is node:
            return _assign_use(parent, read, in_container, node)
        if isinstance(parent, cst.Return):
            return DoneUse.WRAPPER_RETURN if _in_step_method(parent, parent_of) else DoneUse.AMBIGUOUS
        if isinstance(parent, (cst.FormattedStringExpression, cst.Expr)):
            return DoneUse.NEUTRAL
        return DoneUse.AMBIGUOUS


def _call_use(call: cst.Call) -> DoneUse:
    name = get_full_name_for_node(call.func) or ""
    last = name.rsplit(".", 1)[-1]
    if isinstance(call.func, cst.Name) and last in NUMBER_BUILTINS:
        return DoneUse.DATA
    if isinstance(call.func, cst.Name) and last in DISPLAY_FUNCTIONS:
        return DoneUse.NEUTRAL
    if last in TEST_FUNCTIONS:
        return DoneUse.CONTROL
    if isinstance(call.func, cst.Attribute):
        if last in TENSOR_FACTORIES:
            return DoneUse.DATA
        if last in STORE_METHODS and (last not in GENERIC_STORE_METHODS or _looks_like_storage(call.func.value)):
            return DoneUse.DATA
        if last in DISPLAY_METHODS or name.startswith(("logging.", "logger.", "log.")):
            return DoneUse.NEUTRAL
    elif last in TENSOR_FACTORIES:  # ``from numpy import array``
        return DoneUse.DATA
    return DoneUse.AMBIGUOUS


def _looks_like_storage(receiver: cst.BaseExpression) -> bool:
    name = (get_full_name_for_node(receiver) or "").rsplit(".", 1)[-1].lower()
    return any(word in name for word in _STORAGE_WORDS) or bool(_STORAGE_TOKENS & set(name.split("_")))


def _method_use(attribute: cst.Attribute, parent_of: Callable[[cst.CSTNode], cst.CSTNode | None]) -> DoneUse:
    call = parent_of(attribute)
    if not isinstance(call, cst.Call) or call.func is not attribute:
        return DoneUse.AMBIGUOUS
    method = attribute.attr.value
    if method in CONVERSION_METHODS:
        return DoneUse.DATA
    if method in TEST_FUNCTIONS:
        return DoneUse.CONTROL
    if method in COUNTING_METHODS:
        return DoneUse.NEUTRAL
    return DoneUse.AMBIGUOUS


def _assign_use(assign: cst.Assign, read: cst.Name, in_container: bool, value: cst.CSTNode) -> DoneUse:
    targets = [t.target for t in assign.targets]
    if len(targets) == 1 and isinstance(targets[0], cst.Name) and targets[0].value == read.value:
        return DoneUse.CONTROL  # ``done = done or step >= limit``: still the episode-over flag
    if in_container and isinstance(value, (cst.Tuple, cst.List, cst.Dict)):
        return DoneUse.DATA  # ``transition = (s, a, r, s2, done)``
    if all(isinstance(t, cst.Subscript) for t in targets) and value is read:
        return DoneUse.DATA  # ``dones[t] = done``: a rollout array
    return DoneUse.AMBIGUOUS  # ``episode_done = done``: depends on what the new name is for


def _in_step_method(node: cst.CSTNode, parent_of: Callable[[cst.CSTNode], cst.CSTNode | None]) -> bool:
    current = parent_of(node)
    while current is not None and not isinstance(current, (cst.FunctionDef, cst.Lambda)):
        current = parent_of(current)
    return isinstance(current, cst.FunctionDef) and current.name.value == "step"
