"""Gym env classes that follow an API of their own (``own_api_shape``).

Some projects subclass ``gym.Env`` and give ``reset``/``step`` a contract no Gym release
had: RLlib-style multi-agent dicts (``dones["__all__"]``), or one shape per mode of the
env (``if self.single_agent: return obs, r, terminated, truncated, info`` beside ``return
obs_dict, rew_dict, dones, info_dict``). Rewriting such a method to Gymnasium's contract,
or its callers to unpack Gymnasium's tuples, breaks the mode it was not written for; the
run proves the class is not on the plain Gym API, so it and its callers are left as they
are and the class is reported once (``rules/custom_env/env_class.py``).

Decided from the class body alone, like ``class_shapes.keeps_legacy_step``.
"""

from __future__ import annotations

import ast
from collections.abc import Callable, Mapping

from gymmigrate.facts.collection_reads import Shape, collection_read, named
from gymmigrate.facts.module import FUNCTIONS, own_returns, walk

# RLlib's MultiAgentEnv (and the projects written after it) ends an episode for every
# agent with this key of the per-agent done dict.
ALL_AGENTS_KEY = "__all__"


def own_api_shape(classdef: ast.ClassDef) -> str | None:
    """How the class's own ``step``/``reset`` show an API of their own (for a message), or
    None: a step whose done is a dict of per-agent flags, a step that returns five values
    in some branches and four in others, or a reset that returns ``(obs, info)`` in some
    branches and a bare observation in others (without gym 0.22's ``return_info`` flag,
    whose two shapes GM502 settles)."""
    methods = {s.name: s for s in classdef.body if isinstance(s, FUNCTIONS)}
    step = methods.get("step")
    if step is not None:
        values = [r.value for r in own_returns(step) if r.value is not None]
        fours = [v for v in values if _tuple_len(v) == 4]
        if any(_per_agent_flags(v.elts[2], step, methods) for v in fours):  # type: ignore[attr-defined]
            return f'its step returns a dict of per-agent done flags (with `"{ALL_AGENTS_KEY}"`)'
        if fours and any(_tuple_len(v) == 5 for v in values):
            return "its step returns five values in some branches and four in others"
    reset = methods.get("reset")
    if reset is not None and not any(a.arg == "return_info" for a in (*reset.args.args, *reset.args.kwonlyargs)):
        values = [r.value for r in own_returns(reset) if r.value is not None]
        if any(is_info_pair(v) for v in values) and any(_bare_observation(v) for v in values):
            return "its reset returns (obs, info) in some branches and a bare observation in others"
    return None


def is_info_pair(value: ast.expr) -> bool:
    """``(obs, info)``: a two-element tuple whose second element is a dict (a display,
    ``dict(...)``) or named like an info."""
    if not (isinstance(value, ast.Tuple) and len(value.elts) == 2):
        return False
    second = value.elts[1]
    if isinstance(second, (ast.Dict, ast.DictComp)):
        return True
    if isinstance(second, ast.Call) and isinstance(second.func, ast.Name) and second.func.id == "dict":
        return True
    name = second.id if isinstance(second, ast.Name) else second.attr if isinstance(second, ast.Attribute) else ""
    if isinstance(second, ast.Call) and isinstance(second.func, (ast.Name, ast.Attribute)):
        func = second.func
        name = func.id if isinstance(func, ast.Name) else func.attr  # ``self._compute_info()``
    return "info" in name.lower()


def _bare_observation(value: ast.expr) -> bool:
    """A return of one value: not a tuple, not ``None``, not a ``reset(...)`` (a retry,
    the base's or a held env's pair handed on)."""
    if isinstance(value, ast.Tuple) or (isinstance(value, ast.Constant) and value.value is None):
        return False
    return not (isinstance(value, ast.Call) and isinstance(value.func, ast.Attribute) and value.func.attr in ("reset", "_reset"))


def _per_agent_flags(done: ast.expr, step: ast.AST, methods: Mapping[str, ast.AST]) -> bool:
    """``done`` is a dict with the all-agents key: a display, or a name the step indexes
    with it (``truncated = dones["__all__"]``) or binds to such a display or to a method
    of the class that builds one (``dones = self._compute_dones()``)."""
    if isinstance(done, ast.Dict):
        return _has_all_key(done)
    if not isinstance(done, ast.Name):
        return False
    is_done = named(done.id)
    for node in walk(step):
        # only the all-agents key: a dict read by other names (``done["agent_0"]``) is no
        # proof of RLlib's contract, which this report names
        if (read := collection_read(node, is_done)) is not None and read.shape is Shape.KEYED and read.key == ALL_AGENTS_KEY:
            return True
        if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == done.id for t in node.targets):
            value = node.value
            if isinstance(value, ast.Dict) and _has_all_key(value):
                return True
            if (
                isinstance(value, ast.Call)
                and isinstance(value.func, ast.Attribute)
                and isinstance(value.func.value, ast.Name)
                and value.func.value.id == "self"
                and value.func.attr in methods
                and _builds_all_key(methods[value.func.attr])
            ):
                return True
    return False


def _builds_all_key(function: ast.AST) -> bool:
    for node in walk(function):
        if isinstance(node, ast.Subscript) and isinstance(node.ctx, ast.Store) and _is_all_key(node.slice):
            return True
        if isinstance(node, ast.Dict) and _has_all_key(node):
            return True
    return False


def _has_all_key(node: ast.Dict) -> bool:
    return any(key is not None and _is_all_key(key) for key in node.keys)


def _is_all_key(node: ast.AST) -> bool:
    return isinstance(node, ast.Constant) and node.value == ALL_AGENTS_KEY


def _tuple_len(value: ast.AST) -> int | None:
    if isinstance(value, ast.Tuple) and not any(isinstance(e, ast.Starred) for e in value.elts):
        return len(value.elts)
    return None


def gymnasium_flag(classdef: ast.ClassDef) -> str | None:
    """The attribute that picks Gymnasium's shapes in a class of two APIs: its step returns
    five values only under ``if self.<flag>:`` and four values only outside it, and its reset
    (when it defines one) returns ``(obs, info)`` only under the same test and a bare
    observation only outside it. None when the class has no such one flag."""
    methods = {s.name: s for s in classdef.body if isinstance(s, FUNCTIONS)}
    step = methods.get("step")
    if step is None:
        return None
    flags = _split_by_flag(step, lambda v: _tuple_len(v) == 5, lambda v: _tuple_len(v) == 4)
    reset = methods.get("reset")
    if flags and reset is not None:
        flags &= _split_by_flag(reset, is_info_pair, _bare_observation)
    return next(iter(flags)) if len(flags) == 1 else None


def _split_by_flag(function: ast.AST, new: Callable[[ast.expr], bool], old: Callable[[ast.expr], bool]) -> set[str]:
    """The flags ``F`` such that every return of ``function`` that ``new`` accepts sits in
    the body of an ``if self.F:`` and every one ``old`` accepts sits outside such a body
    (and some return of each kind exists)."""
    returns: list[tuple[ast.expr, frozenset[str]]] = []

    def visit(node: ast.AST, under: frozenset[str]) -> None:
        if isinstance(node, (*FUNCTIONS, ast.Lambda, ast.ClassDef)) and node is not function:
            return  # a nested def's returns are its own
        if isinstance(node, ast.Return) and node.value is not None:
            returns.append((node.value, under))
            return
        if isinstance(node, ast.If):
            test = node.test
            flag = test.attr if isinstance(test, ast.Attribute) and isinstance(test.value, ast.Name) and test.value.id == "self" else None
            visit(test, under)
            for child in node.body:
                visit(child, under | {flag} if flag is not None else under)
            for child in node.orelse:
                visit(child, under)
            return
        for inner in ast.iter_child_nodes(node):
            visit(inner, under)

    visit(function, frozenset())
    news = [under for value, under in returns if new(value)]
    olds = [under for value, under in returns if old(value)]
    if not news or not olds:
        return set()
    flags = set.intersection(*(set(u) for u in news))
    return {f for f in flags if not any(f in u for u in olds)}
