"""GM618: a ``RecordEpisodeStatistics`` subclass that keeps its own statistics gets back the
state gym 0.26's base set for it.

gym 0.26's ``RecordEpisodeStatistics`` served one env and vector envs alike: ``__init__``
set ``num_envs = getattr(env, "num_envs", 1)``, ``is_vector_env = getattr(env,
"is_vector_env", False)`` and ``t0 = time.perf_counter()``, and ``reset`` set
``episode_returns``/``episode_lengths`` to zero arrays of ``num_envs`` entries. Gymnasium
1.x split it: ``gymnasium.wrappers.RecordEpisodeStatistics`` wraps one env and keeps plain
numbers (``episode_returns = 0``, no ``num_envs``, ``is_vector_env`` or ``t0``), and
``gymnasium.wrappers.vector.RecordEpisodeStatistics`` wraps vector envs. A subclass that
reads the 0.26 state fails with ``AttributeError: ... has no attribute 'num_envs'``, or on
``self.episode_lengths[i]`` of an ``int``.

Where the subclass overrides ``step`` and never calls the base's (it computes the
statistics itself, often a copy of 0.26's ``step`` extended to vector rewards), the base
only ever contributes its ``__init__`` and ``reset`` state, so that state is restored in
the subclass, as gym 0.26 set it:

* after the ``super().__init__(...)`` statement of its ``__init__``: whichever of
  ``self.num_envs``, ``self.is_vector_env`` and ``self.t0`` the class reads, with 0.26's
  own expressions (``getattr`` on the wrapped env: 1 and False for a Gymnasium env);
* after the statement of its ``reset`` that calls ``super().reset(...)``: zero arrays for
  whichever of ``self.episode_returns``/``self.episode_lengths`` the class reads and that
  reset does not assign itself (a class without a ``reset`` gets one).

The class stays a single-env wrapper: Gymnasium 1.x's ``Wrapper`` raises ``TypeError`` on a
vector env, so a use on one is reported where it is seen (GM708); the vector base is
another class with other state, and whether the same subclass may serve both is the
author's call. Anything else (a subclass that calls the base's ``step``, whose 1.x version
updates the plain numbers; no ``super().__init__`` statement; a ``reset`` that returns the
base's call directly) stays reported for a port by hand.

Sources: gym 0.26.2 ``wrappers/record_episode_statistics.py``; Gymnasium 1.4
``wrappers/common.py`` (``RecordEpisodeStatistics``) and ``wrappers/vector/common.py``.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass

from gymmigrate.facts.module import FUNCTIONS, is_super_call, walk

BASE = "RecordEpisodeStatistics"
# What gym 0.26's __init__ set that Gymnasium 1.x's does not, as 0.26 computed it.
INIT_STATE = {
    "num_envs": 'getattr(self.env, "num_envs", 1)',
    "is_vector_env": 'getattr(self.env, "is_vector_env", False)',
    "t0": "{time}.perf_counter()",
}
# What gym 0.26's reset set: per-env arrays where 1.x keeps numbers.
RESET_STATE = {
    "episode_returns": "{np}.zeros(self.num_envs, dtype={np}.float32)",
    "episode_lengths": "{np}.zeros(self.num_envs, dtype={np}.int32)",
}


@dataclass(frozen=True)
class Restoration:
    """Where the 0.26 state goes back, and which of it."""

    init_anchor: ast.stmt  # the super().__init__(...) statement
    init_names: tuple[str, ...]
    reset_anchor: ast.stmt | None  # the statement calling super().reset(...); None: add a reset
    reset_names: tuple[str, ...]
    last: ast.stmt  # the class body's last statement (where a new reset goes)


def plan_restoration(classdef: ast.ClassDef, read: set[str]) -> tuple[Restoration | None, str]:
    """The restoration of a subclass of gym's RecordEpisodeStatistics that reads the gone
    state ``read``; else None and why not."""
    methods = {s.name: s for s in classdef.body if isinstance(s, FUNCTIONS)}
    step = methods.get("step")
    if step is None:
        return None, "it keeps the base's `step`, whose 1.x version updates other state"
    if _calls_base(step, "step"):
        return None, "its `step` calls the base's, whose 1.x version updates other state"
    init = methods.get("__init__")
    init_anchor = next((s for s in init.body if _is_base_call(s, "__init__")), None) if init is not None else None
    if init_anchor is None:
        return None, "its `__init__` has no `super().__init__(...)` statement to restore the state after"
    reset_names: tuple[str, ...] = tuple(name for name in RESET_STATE if name in _self_reads(classdef))
    reset = methods.get("reset")
    reset_anchor = None
    if reset is not None and reset_names:
        index = next((i for i, s in enumerate(reset.body) if _is_base_call(s, "reset")), None)
        if index is None or isinstance(reset.body[index], ast.Return):
            return None, "its `reset` does not call `super().reset(...)` in a statement of its own"
        reset_anchor = reset.body[index]
        assigned_after = {
            target.attr
            for statement in reset.body[index + 1 :]
            if isinstance(statement, ast.Assign)
            for target in statement.targets
            if isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self"
        }
        reset_names = tuple(name for name in reset_names if name not in assigned_after)
    init_names = tuple(name for name in INIT_STATE if name in read or (name == "num_envs" and reset_names))
    return Restoration(init_anchor, init_names, reset_anchor, reset_names, classdef.body[-1]), ""


def init_lines(names: tuple[str, ...], time_name: str) -> list[str]:
    return [f"self.{name} = {INIT_STATE[name].format(time=time_name)}\n" for name in names]


def reset_lines(names: tuple[str, ...], np_name: str) -> list[str]:
    return [f"self.{name} = {RESET_STATE[name].format(np=np_name)}\n" for name in names]


def reset_method(names: tuple[str, ...], np_name: str) -> str:
    body = "".join(f"    {line}" for line in reset_lines(names, np_name))
    return (
        "def reset(self, *, seed=None, options=None):\n"
        "    obs, info = super().reset(seed=seed, options=options)\n"
        f"{body}"
        "    return obs, info\n"
    )


def _self_reads(classdef: ast.ClassDef) -> set[str]:
    return {
        node.attr
        for node in walk(classdef)
        if isinstance(node, ast.Attribute)
        and isinstance(node.value, ast.Name)
        and node.value.id == "self"
        and not isinstance(node.ctx, ast.Store)
    }


def _is_base(node: ast.AST) -> bool:
    """``super()``, ``super(Cls, self)`` or the base named ``RecordEpisodeStatistics``."""
    if is_super_call(node):
        return True
    name = node.attr if isinstance(node, ast.Attribute) else node.id if isinstance(node, ast.Name) else None
    return name == BASE


def _base_call(node: ast.AST, method: str) -> bool:
    return (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and node.func.attr == method
        and _is_base(node.func.value)
    )


def _calls_base(function: ast.AST, method: str) -> bool:
    return any(_base_call(node, method) for node in walk(function))


def _is_base_call(statement: ast.stmt, method: str) -> bool:
    """A top-level statement of a method whose value is the base's ``method`` call."""
    if isinstance(statement, (ast.Expr, ast.Assign, ast.Return, ast.AnnAssign)) and statement.value is not None:
        return _base_call(statement.value, method)
    return False
