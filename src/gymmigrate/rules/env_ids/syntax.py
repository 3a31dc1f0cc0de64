"""Where env ids and the registry appear in a module: the ast questions both families ask.

Which calls take an env id, which argument carries it, which string literals can be
rewritten in place, what names the Gym registry and which name the module imports
Gymnasium under. Answers come from ``ModuleFacts`` (imports, bindings, source lines).
"""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N

# Functions under gym/gymnasium whose first argument (or ``id=``) is an env id.
ID_FUNCTIONS = frozenset({"make", "make_vec", "vector.make", "spec", "envs.make", "envs.spec", "envs.registration.make", "envs.registration.spec"})
# Functions whose result is made with ``**kwargs`` forwarded to the env constructor.
FORWARDS_KWARGS = frozenset({"make", "make_vec", "vector.make", "envs.make", "envs.registration.make"})
# Stable-Baselines3 helpers that call gym.make(env_id) themselves.
SB3_ID_FUNCTIONS = frozenset(
    {
        "stable_baselines3.common.env_util.make_vec_env",
        "stable_baselines3.common.env_util.make_atari_env",
        "stable_baselines3.common.cmd_util.make_vec_env",
        "stable_baselines3.common.cmd_util.make_atari_env",
    }
)
REGISTRY_NAMES = frozenset({"registry", "envs.registry", "envs.registration.registry"})
ID_KEYWORDS = ("id", "env_id")


def is_registry(facts: ModuleFacts, expr: ast.AST) -> bool:
    """``gym.envs.registry``, ``registry`` imported from ``gym.envs.registration``..."""
    if not isinstance(expr, (ast.Name, ast.Attribute)):
        return False
    return any(N.strip_gym_prefix(q) in REGISTRY_NAMES for q in facts.qualified_names(expr))


def id_argument(call: ast.Call) -> ast.expr | None:
    """The argument that carries the env id: ``id=`` / ``env_id=``, else the first positional."""
    for kw in call.keywords:
        if kw.arg in ID_KEYWORDS:
            return kw.value
    positional = [a for a in call.args if not isinstance(a, ast.Starred)]
    return positional[0] if positional else None


def gym_alias(facts: ModuleFacts) -> str | None:
    """The name a top-level ``import gymnasium [as gym]`` (else ``import gym``) binds.

    The import rules turn ``import gym`` into ``import gymnasium as gym``, so either
    spelling gives the name the migrated module calls Gymnasium by.
    """
    return _module_alias(facts.tree, "gymnasium") or _module_alias(facts.tree, "gym")


def _module_alias(tree: ast.Module, package: str) -> str | None:
    for statement in tree.body:
        if isinstance(statement, ast.Import):
            for alias in statement.names:
                if alias.name == package:
                    return alias.asname or package
    return None


def plain_string(facts: ModuleFacts, node: ast.AST) -> str | None:
    """The text of a single string literal written without escapes (None for anything else).

    Only such a literal can be rewritten by replacing the text between its quotes:
    bytes, f-strings, implicitly concatenated literals and escapes are left alone.
    """
    if not (isinstance(node, ast.Constant) and isinstance(node.value, str)):
        return None
    source = facts.segment(node)
    prefix_length = len(source) - len(source.lstrip("rRuUbBfF"))
    prefix, rest = source[:prefix_length], source[prefix_length:]
    if "b" in prefix.lower():
        return None
    quote = rest[:3] if rest[:3] in ('"""', "'''") else rest[:1]
    if not quote or len(rest) < 2 * len(quote) or not rest.endswith(quote):
        return None
    raw = rest[len(quote) : -len(quote)]
    return node.value if raw == node.value else None


def split_module_prefix(text: str) -> tuple[str, str]:
    """``("ale_py:", "ALE/Pong-v5")`` for ``"ale_py:ALE/Pong-v5"``: the module a ``make`` imports first, and the id."""
    if ":" in text:
        module, env_id = text.split(":", 1)
        return module + ":", env_id
    return "", text


def leading_literal(value: ast.expr) -> ast.Constant | None:
    """The string literal a built id starts with: ``"dm2gym:" + name``, ``f"procgen:{game}"``,
    ``"procgen:procgen-{}-v0".format(game)``; None for anything else."""
    if isinstance(value, ast.BinOp) and isinstance(value.op, (ast.Add, ast.Mod)):
        while isinstance(value, ast.BinOp) and isinstance(value.op, ast.Add):
            value = value.left
        if isinstance(value, ast.BinOp) and isinstance(value.op, ast.Mod):
            value = value.left
    elif isinstance(value, ast.JoinedStr) and value.values:
        value = value.values[0]
    elif isinstance(value, ast.Call) and isinstance(value.func, ast.Attribute) and value.func.attr == "format":
        value = value.func.value
    else:
        return None
    return value if isinstance(value, ast.Constant) and isinstance(value.value, str) else None
