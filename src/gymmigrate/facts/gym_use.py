"""Whether a module handles Gym envs: it uses Gym's env factories or env classes.

The "this file uses only Gym" fallback (``decisions.decide``) rewrites an untraced
env-like receiver as a Gym env. That guess is only as good as the file's own Gym use:
a module that makes, wraps, registers or subclasses Gym envs passes them around; a
module whose only Gym use is its spaces, errors, a viewer (``classic_control.rendering``),
seeding utilities, ``__version__`` or the logger says nothing about what its env-like
names hold (a project's own multi-agent env, a project VecEnv).
"""

from __future__ import annotations

import ast

from gymmigrate.facts import names as N
from gymmigrate.facts.module import ModuleFacts

# Under gym/gymnasium (prefix stripped): the factories and module-level registry helpers.
_REGISTRY = frozenset({"register", "registry", "spec", "make_vec", "envs.register", "envs.registry", "envs.spec"})


def handles_gym_envs(facts: ModuleFacts) -> bool:
    """The module uses Gym's env factories or env classes, at any scope: ``gym.make`` (or
    ``make`` imported from gym), ``gym.Env`` and the wrapper base classes, ``gym.wrappers.*``,
    ``gym.vector.*``, ``gym.envs.registration`` / ``register``, an env class under
    ``gym.envs``. Computed once per module."""
    return facts.memo(("handles-gym-envs", 0), lambda: _handles_gym_envs(facts))


def names_env_api(qualified: str) -> bool:
    """``qualified`` (a library name) is one of Gym's env factories or env classes."""
    rest = N.strip_gym_prefix(qualified)
    if not rest:
        return False
    if rest in N.GYM_ENV_FACTORIES or rest in N.GYM_ENV_BASE_CLASSES or rest in _REGISTRY:
        return True
    first, _, tail = rest.partition(".")
    if first in ("wrappers", "vector"):
        return not N.GYM_NOT_ENV_MODULES.intersection(rest.split("."))  # not wrappers.monitoring.video_recorder
    if first == "envs" and tail:
        if tail == "registration" or tail.startswith("registration."):
            return True
        *modules, last = tail.split(".")
        # an env class (``envs.classic_control.CartPoleEnv``, ``envs.mujoco.MujocoEnv``); a
        # package (``envs.classic_control``) says nothing until one of its classes is read
        return last[:1].isupper() and not N.GYM_NOT_ENV_MODULES.intersection(modules)
    return False


def _handles_gym_envs(facts: ModuleFacts) -> bool:
    roots: set[str] = set()
    for alias, qualified in facts.imports.items():
        if N.strip_gym_prefix(qualified) is None:
            continue
        if names_env_api(qualified):
            return True  # ``from gym import make``, ``from gym.wrappers import TimeLimit``
        roots.add(alias.asname or alias.name.split(".", 1)[0])
    if not roots:
        return False
    # ``gym.make(...)``, ``class W(gym.Wrapper)``, ``gym.wrappers.TimeLimit``: a read of an
    # attribute chain rooted at a name bound to gym (or one of its modules)
    for nodes in facts.attributes.values():
        for node in nodes:
            root = node.value
            while isinstance(root, ast.Attribute):
                root = root.value
            if not (isinstance(root, ast.Name) and root.id in roots):
                continue
            if any(names_env_api(q) for q in facts.qualified_names(node)):
                return True
    return False
