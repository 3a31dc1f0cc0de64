"""A step's ``done`` that is a list of per-agent flags, proven by how its own scope uses it.

Multi-agent envs of the Gym era (rware, lbforaging, ma-gym) return ``done`` as one flag
per agent, and code over them says so: ``all(done)``, ``any(done)``, ``zip(obs, done)``,
``for d in done``, ``done[i]``, ``isinstance(done, Iterable)`` or ``done = len(obs) *
[True]``; a dict of agents' flags by its string keys (``done["__all__"]``). Once such a step returns terminated and truncated, ``terminated or truncated``
is the terminated list (the truncation is dropped), ``terminated | truncated`` raises on
lists and ``done and not terminated`` is always false: the flags must be combined agent
by agent (rules/step_done/unpack.py, rules/wrappers/step.py).

Signs of something else keep the name out: an attribute of it (``done.any()``: an array;
``done.values()``: a dict, proven only by its keys), arithmetic on it (``1 - done``, ``~done``: an array), or a type test for another class
(``isinstance(done, bool)``, ``isinstance(done, np.ndarray)``).
"""

from __future__ import annotations

import ast
from dataclasses import dataclass

from gymmigrate.facts.collection_reads import (
    CollectionRead,
    Shape,
    collection_read,
    named,
)

# Type tests that say "a list of flags" (``isinstance(done, Iterable)``).
_LIST_TYPES = frozenset({"list", "tuple", "Iterable", "Sequence", "Collection", "MutableSequence"})
# Builtins that take the flags alone (``all(done)``, ``enumerate(done)``); ``zip`` counts with
# the agents' other values beside them (``zip(obs, done)``). Narrower than a batch's set
# (facts/batched_steps.py): a yes here joins the flags with NumPy agent by agent.
_REDUCTIONS = frozenset({"all", "any", "enumerate"})


@dataclass(frozen=True)
class PerAgent:
    """``done`` is per-agent; ``guard`` is the code's own type test (``Iterable``,
    ``(list, tuple)``) when it also handles a single flag, else None; ``by_name``: a dict
    of agents' flags (``done["__all__"]``, RLlib's shape), not a list."""

    guard: str | None = None
    by_name: bool = False


def _type_names(node: ast.expr) -> list[str]:
    elements = node.elts if isinstance(node, ast.Tuple) else [node]
    names = []
    for element in elements:
        if isinstance(element, ast.Name):
            names.append(element.id)
        elif isinstance(element, ast.Attribute):
            names.append(element.attr)
        else:
            names.append("")
    return names


def _takes_agents(read: CollectionRead) -> bool:
    return read.callee == "zip" or (read.callee in _REDUCTIONS and read.only_argument)


def _true_list(value: ast.expr) -> bool:
    """``len(obs) * [True]``, ``[True] * n``, ``[True for _ in obs]``, ``[True, True]``, and
    the same as a tuple (``(True, True)``, ``tuple([True for _ in obs])``)."""
    if isinstance(value, ast.BinOp) and isinstance(value.op, ast.Mult):
        return any(_true_list(side) for side in (value.left, value.right))
    if isinstance(value, (ast.List, ast.Tuple)):
        return bool(value.elts) and all(isinstance(e, ast.Constant) and e.value is True for e in value.elts)
    if isinstance(value, (ast.ListComp, ast.GeneratorExp)):
        return isinstance(value.elt, ast.Constant) and value.elt.value is True
    if isinstance(value, ast.Call) and isinstance(value.func, ast.Name) and value.func.id in ("tuple", "list"):
        return len(value.args) == 1 and not value.keywords and _true_list(value.args[0])
    return False


def true_list(value: ast.expr) -> bool:
    """A list of ``True`` flags, one per agent (``len(obs) * [True]``)."""
    return _true_list(value)


def per_agent_done(scope: ast.AST, name: str) -> PerAgent | None:
    """How ``scope`` (a function or module) uses ``name``: per-agent flags (``PerAgent``)
    or not shown (None)."""
    evidence = False
    by_name = False
    guard: str | None = None
    is_done = named(name)
    for node in _walk_unguarded(scope, name):
        if isinstance(node, ast.Attribute) and _is(node.value, name):
            return None  # ``done.any()``, ``done.values()``: an array or a dict
        if isinstance(node, ast.BinOp) and (_is(node.left, name) or _is(node.right, name)):
            return None  # ``1 - done``: an array
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.Invert) and _is(node.operand, name):
            return None
        if isinstance(node, ast.Assign) and any(_is(t, name) for t in node.targets) and _true_list(node.value):
            evidence = True
            continue
        read = collection_read(node, is_done)
        if read is None:
            continue
        if read.shape is Shape.KEYED:
            by_name = True  # ``done["__all__"]``: a dict of agents
        elif read.shape is Shape.TYPE_TEST:
            if read.types is None:
                continue
            if not all(t in _LIST_TYPES for t in _type_names(read.types)):
                return None  # ``isinstance(done, bool)``: one flag or an array
            guard = ast.unparse(read.types)
            evidence = True
        elif read.shape in (Shape.INDEXED, Shape.ITERATED) or (read.shape is Shape.PASSED and _takes_agents(read)):
            evidence = True
    if by_name:
        # a dict of agents: read by index or type-tested too is a shape not known here
        return PerAgent(by_name=True) if not evidence and guard is None else None
    return PerAgent(guard) if evidence else None


def _walk_unguarded(scope: ast.AST, name: str):
    """The nodes of ``scope``, but not the body of ``if isinstance(info, list):`` (a test of
    another name: a branch for a batch of envs, as an SB3 VecEnv's list of infos, where
    ``done[0]`` is env 0's flag, not an agent's)."""
    pending = [scope]
    while pending:
        node = pending.pop()
        yield node
        if isinstance(node, ast.If) and _tests_other_type(node.test, name):
            pending.append(node.test)
            pending.extend(node.orelse)
            continue
        pending.extend(ast.iter_child_nodes(node))


def _tests_other_type(test: ast.expr, name: str) -> bool:
    return (
        isinstance(test, ast.Call)
        and isinstance(test.func, ast.Name)
        and test.func.id == "isinstance"
        and len(test.args) == 2
        and not _is(test.args[0], name)
    )


def _is(node: ast.AST, name: str) -> bool:
    return isinstance(node, ast.Name) and node.id == name
