"""Facts about user-defined environment classes, shared by the custom-env and RNG passes.

A class is a *custom env* when it subclasses ``gym.Env`` (or ``gymnasium.Env``), a
built-in env class under ``gym.envs`` (``CartPoleEnv``, ``MujocoEnv``...), or another
custom env of the same module, and is not a wrapper (wrappers keep their own rules).
"""

from __future__ import annotations

import libcst as cst
import libcst.matchers as m

from gymmigrate.analysis import names as N
from gymmigrate.analysis.receivers import EnvKind, ReceiverAnalysis

# Qualified names (without the gym/gymnasium prefix) of the mujoco-py era base class.
MUJOCO_BASES = frozenset({"envs.mujoco.MujocoEnv", "envs.mujoco.mujoco_env.MujocoEnv", "envs.mujoco.MuJocoPyEnv"})

SUPER_CALL = m.Call(func=m.Name("super"))


def is_custom_env_class(analysis: ReceiverAnalysis, classdef: cst.ClassDef, _seen: frozenset[int] = frozenset()) -> bool:
    if id(classdef) in _seen or analysis.is_gym_wrapper_class(classdef):
        return False
    if analysis.class_kind(classdef) is EnvKind.GYM_ENV:
        return True
    seen = _seen | {id(classdef)}
    for base in classdef.bases:
        if any(_is_builtin_env_class(q) for q in analysis.qualified_names(base.value)):
            return True
        local = analysis.local_class(base.value)
        if local is not None and is_custom_env_class(analysis, local, seen):
            return True
    return False


def extends_gym_env_directly(analysis: ReceiverAnalysis, classdef: cst.ClassDef) -> bool:
    """A base is ``gym.Env`` / ``gymnasium.Env`` itself (so ``super().reset`` only seeds)."""
    return any(
        N.strip_gym_prefix(q) in ("Env", "core.Env", "GoalEnv", "core.GoalEnv")
        for base in classdef.bases
        for q in analysis.qualified_names(base.value)
    )


def has_local_env_base(analysis: ReceiverAnalysis, classdef: cst.ClassDef) -> bool:
    """The class extends another env class of this module (so ``__init__`` comes from there)."""
    return any(analysis.local_class(base.value) is not None for base in classdef.bases)


def _is_builtin_env_class(qualified: str) -> bool:
    rest = N.strip_gym_prefix(qualified)
    if rest is None or not rest.startswith("envs."):
        return False
    return rest.rsplit(".", 1)[-1][:1].isupper() and rest.endswith("Env")


def mujoco_base(analysis: ReceiverAnalysis, classdef: cst.ClassDef) -> bool:
    for base in classdef.bases:
        for q in analysis.qualified_names(base.value):
            if N.strip_gym_prefix(q) in MUJOCO_BASES:
                return True
    return False


def class_methods(classdef: cst.ClassDef) -> dict[str, cst.FunctionDef]:
    body = classdef.body
    if not isinstance(body, cst.IndentedBlock):
        return {}
    return {stmt.name.value: stmt for stmt in body.body if isinstance(stmt, cst.FunctionDef)}


def is_super_method_call(node: cst.CSTNode, method: str) -> bool:
    """``super().method(...)`` or ``super(Cls, self).method(...)``."""
    return m.matches(node, m.Call(func=m.Attribute(value=SUPER_CALL, attr=m.Name(method))))


def is_seeding_np_random(analysis: ReceiverAnalysis, call: cst.CSTNode) -> bool:
    """A call of ``gym.utils.seeding.np_random`` / ``gymnasium.utils.seeding.np_random``."""
    if not isinstance(call, cst.Call):
        return False
    return any(N.strip_gym_prefix(q) == "utils.seeding.np_random" for q in analysis.qualified_names(call.func))
