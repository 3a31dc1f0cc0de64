"""How one expression reads a step's ``done`` as a collection of flags (one per env, one
per agent) rather than as one flag: ``done[i]``, ``done["__all__"]``, ``for d in done``,
``all(done)``, ``zip(obs, done)``, ``len(done)``, ``np.logical_or(a, done)``,
``done.any()``, ``done.tolist()``, ``isinstance(done, (list, tuple))``.

The shapes are named here once; which of them proves what is the asker's question, so
each asker picks its own (a vector env's array answers ``done.any()``, a list of agents'
flags does not):

- ``facts/batched_steps.py`` (``done_read_per_env``): may an untraced receiver be a
  batched env? Its reads, through the flow, by the builtins that take any iterable.
- ``facts/per_agent_flags.py`` (``per_agent_done``): a list (or dict) of agents' flags?
  Builtins and type tests for a list only; an array's methods are a sign against.
- ``rules/step_done/unpack.py`` (``reads_as_batch``): must ``done`` be joined element by
  element? Indexing, iteration, any type test, and NumPy's element-wise calls.
- ``rules/wrappers/step_inner.py`` (``_reads_per_agent``): does a wrapper's step return a
  reduction of its inner step's per-agent flags? Indexing, iteration, the reducing builtins,
  and a dict's own views (``done.values()``).
- ``facts/own_api.py`` (``_per_agent_flags``): does a step return RLlib's dict of agents'
  flags? Only the all-agents key (``done["__all__"]``).
"""

from __future__ import annotations

import ast
from collections.abc import Callable, Collection
from dataclasses import dataclass
from enum import Enum


class Shape(str, Enum):
    INDEXED = "indexed"  # ``done[i]``, ``done[1:]``
    KEYED = "keyed"  # ``done["__all__"]``: flags by a name (RLlib's dict of agents)
    ITERATED = "iterated"  # ``for d in done``, ``[... for d in done]``, ``async for``
    PASSED = "passed"  # ``all(done)``, ``zip(obs, done)``, ``len(done)``: an argument of a plain name's call
    METHOD = "method"  # ``done.any()``, ``done.tolist()``: a call of its own method
    ARRAY_CALL = "array call"  # ``np.any(done)``, ``np.logical_or(a, done)``: an argument of an attribute's call
    TYPE_TEST = "type test"  # ``isinstance(done, ...)``


@dataclass(frozen=True)
class CollectionRead:
    """One read of ``done`` as a collection. ``callee``: the called name for PASSED, METHOD
    and ARRAY_CALL (``all``, ``tolist``, ``logical_or``); ``only_argument``: ``done`` is the
    call's one positional argument (``all(done)``, not ``all(done, x)``); ``types``:
    ``isinstance``'s second argument, None when the call does not have exactly two;
    ``key``: the name a KEYED read takes (``__all__``)."""

    shape: Shape
    callee: str = ""
    only_argument: bool = False
    types: ast.expr | None = None
    key: str = ""


def named(name: str) -> Callable[[ast.AST], bool]:
    """Whether a node is the variable ``name``: a scope's walk asks it of every node."""

    def is_name(node: ast.AST) -> bool:
        return isinstance(node, ast.Name) and node.id == name

    return is_name


def named_in(names: Collection[str]) -> Callable[[ast.AST], bool]:
    """Whether a node is one of the variables ``names``: a done and the flags split from
    it (``done``, ``terminated``, ``truncated``) asked about together."""

    def is_one(node: ast.AST) -> bool:
        return isinstance(node, ast.Name) and node.id in names

    return is_one


def same_node(read: ast.AST) -> Callable[[ast.AST], bool]:
    """Whether a node is ``read`` itself: a question about one read the flow traced."""

    def is_read(node: ast.AST) -> bool:
        return node is read

    return is_read


def collection_read(node: ast.AST, is_done: Callable[[ast.AST], bool]) -> CollectionRead | None:
    """How ``node`` reads the done (the nodes ``is_done`` accepts: one read, or every
    occurrence of a name) as a collection, or None. ``node`` is the expression around the
    done (the subscript, the loop, the call), so a walk of a scope can ask every node."""
    if isinstance(node, ast.Subscript):
        if not is_done(node.value):
            return None
        key = node.slice
        if isinstance(key, ast.Constant) and isinstance(key.value, str):
            return CollectionRead(Shape.KEYED, key=key.value)
        return CollectionRead(Shape.INDEXED)
    if isinstance(node, (ast.For, ast.AsyncFor, ast.comprehension)):
        return CollectionRead(Shape.ITERATED) if is_done(node.iter) else None
    if not isinstance(node, ast.Call):
        return None
    func, args = node.func, node.args
    if isinstance(func, ast.Name):
        if func.id == "isinstance" and args and is_done(args[0]):
            return CollectionRead(Shape.TYPE_TEST, types=args[1] if len(args) == 2 else None)
        if any(is_done(a) for a in args):
            return CollectionRead(Shape.PASSED, func.id, only_argument=len(args) == 1)
    elif isinstance(func, ast.Attribute):
        if is_done(func.value):
            return CollectionRead(Shape.METHOD, func.attr)
        if any(is_done(a) for a in args):
            return CollectionRead(Shape.ARRAY_CALL, func.attr, only_argument=len(args) == 1)
    return None
