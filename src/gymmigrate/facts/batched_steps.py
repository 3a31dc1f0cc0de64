"""Step unpacks whose done flags are read one per env: a batched step (an SB3 VecEnv, a
list of envs), where a single env's ``terminated or truncated`` would be wrong. Both the
step's unpack (rules/step_done/unpack.py, GM301) and the resets of the same untraced
receiver in the same function (rules/reset_seed/resets.py, GM201) decide on it: the pair
is one decision, both rewritten or both reported.
"""

from __future__ import annotations

import ast

from gymmigrate.facts.collection_reads import (
    CollectionRead,
    Shape,
    collection_read,
    same_node,
)
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.module import ModuleFacts
from gymmigrate.facts.narrowing import isinstance_guards


def under_batch_check(facts: ModuleFacts, node: ast.AST, fields: set[str]) -> bool:
    """``node`` is in the body of ``if isinstance(<one of fields>, list)`` (or ``tuple``):
    the code tells a batched result from one env's there."""
    return any(
        tested in fields and isinstance(classes, ast.Name) and classes.id in ("list", "tuple")
        for _, tested, classes in isinstance_guards(facts, node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.Module))
    )


def done_read_per_env(facts: ModuleFacts, done_target: ast.expr, unpacked: ast.Tuple | ast.List | None = None) -> bool:
    """The done flags are read one per env (``zip(..., dones)``, ``for d in dones``,
    ``dones[i]``). A read under ``if isinstance(info, list):`` testing a field of the same
    unpack (``unpacked``) does not count: a Gym env's step never takes that branch (code
    written for an env or an SB3 VecEnv, which returns a list of infos)."""
    if not isinstance(done_target, ast.Name):
        return False
    fields = {e.id for e in unpacked.elts if isinstance(e, ast.Name)} if unpacked is not None else set()
    for read in Flow.of(facts).reads(done_target):
        if fields and under_batch_check(facts, read, fields):
            continue
        parent = facts.parent(read)
        if parent is not None and _per_env(collection_read(parent, same_node(read))):
            return True
    return False


# Builtins that raise on one flag (``len(True)``): only an iterable of flags goes through.
_ITERABLE_BUILTINS = frozenset({"zip", "enumerate", "len", "any", "all", "sum", "list"})


def _per_env(read: CollectionRead | None) -> bool:
    """A read that one env's flag (a bool) would raise on: indexed, keyed, iterated or
    handed to an iterable builtin. A yes leaves the step unrewritten, so the reads one flag
    may take too do not count: a type test (``isinstance(done, bool)``) or an array's
    method (NumPy's ``bool_`` has ``.any()``)."""
    if read is None:
        return False
    if read.shape is Shape.PASSED:
        return read.callee in _ITERABLE_BUILTINS
    return read.shape in (Shape.INDEXED, Shape.KEYED, Shape.ITERATED)


def steps_batched(facts: ModuleFacts, receiver: ast.Name) -> bool:
    """``receiver`` is stepped in the same function with four unpacked values whose done is
    read one per env (or named ``dones``, or the receiver ``envs``: the tests of GM301's
    ``looks_vectorised``)."""
    function = facts.enclosing_function(receiver)
    for call in facts.attribute_calls.get("step", ()):
        value = call.func.value if isinstance(call.func, ast.Attribute) else None
        if not (isinstance(value, ast.Name) and value.id == receiver.id) or facts.enclosing_function(call) is not function:
            continue
        assign = facts.parent(call)
        if not (isinstance(assign, ast.Assign) and len(assign.targets) == 1 and isinstance(assign.targets[0], (ast.Tuple, ast.List))):
            continue
        target = assign.targets[0]
        if len(target.elts) != 4:
            continue
        done = target.elts[2]
        plural = receiver.id.lower().endswith(("envs", "environments"))
        if plural or (isinstance(done, ast.Name) and done.id.endswith("dones")) or done_read_per_env(facts, done, target):
            return True
    return False
