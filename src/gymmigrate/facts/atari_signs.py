"""Top-level defs and classes of a module that use what only an Atari env has (GM106).

``wrap_deepmind(env)`` in ``atari_wrappers.py`` builds ``NoopResetEnv(env)``, whose
``__init__`` asserts ``env.unwrapped.get_action_meanings()[0] == "NOOP"``: a module that
makes an env and hands it there makes Atari envs, which need ``import ale_py`` since
Gymnasium 1.0. The signs are those ``rules/env_ids/ids.py`` reads in one module: the
``ale`` interface, ``get_action_meanings()``, a ``"NoFrameskip"`` constant; a def or class
that calls another of the module with a sign has one too.
"""

from __future__ import annotations

import ast

from gymmigrate.facts.module import ModuleFacts, walk

_SIGN_ATTRIBUTES = frozenset({"ale", "get_action_meanings"})


def self_stored(classdef: ast.AST | None) -> frozenset[str]:
    """The attributes a class stores on ``self`` (``self.ale = self.game.player``)."""
    if not isinstance(classdef, ast.ClassDef):
        return frozenset()
    return frozenset(
        node.attr
        for node in walk(classdef)
        if isinstance(node, ast.Attribute)
        and isinstance(node.ctx, ast.Store)
        and isinstance(node.value, ast.Name)
        and node.value.id == "self"
    )


def reads_atari_interface(node: ast.AST, own: frozenset[str]) -> bool:
    """``env.unwrapped.ale``, ``self.env.get_action_meanings``: a read of what only an Atari
    env has. Not a store, and not ``self.ale`` in a class that stores ``self.ale`` itself
    (``own``): an attribute of the class's own (a game keeping an ``ale`` alias for
    ``lives()``) says nothing about the Arcade Learning Environment."""
    if not (isinstance(node, ast.Attribute) and node.attr in _SIGN_ATTRIBUTES and isinstance(node.ctx, ast.Load)):
        return False
    return not (isinstance(node.value, ast.Name) and node.value.id == "self" and node.attr in own)


def has_own_sign(definition: ast.AST) -> bool:
    own = frozenset().union(*(self_stored(n) for n in walk(definition) if isinstance(n, ast.ClassDef)))
    for node in walk(definition):
        if reads_atari_interface(node, own):
            return True
        if isinstance(node, ast.Constant) and node.value == "NoFrameskip":
            return True
    return False


def atari_users(facts: ModuleFacts) -> frozenset[str]:
    """Names of the top-level defs and classes with a sign, directly or through another."""
    definitions: dict[str, ast.AST] = {**facts.functions, **facts.classes}
    definitions = {name: d for name, d in definitions.items() if facts.parent(d) is facts.tree}
    found = {name for name, d in definitions.items() if has_own_sign(d)}
    if not found:
        return frozenset()
    calls: dict[str, set[str]] = {
        name: {n.func.id for n in walk(d) if isinstance(n, ast.Call) and isinstance(n.func, ast.Name) and n.func.id in definitions}
        for name, d in definitions.items()
    }
    changed = True
    while changed:  # the closure: at most one pass per definition
        changed = False
        for name, called in calls.items():
            if name not in found and called & found:
                found.add(name)
                changed = True
    return frozenset(found)


def under_condition(facts: ModuleFacts, node: ast.AST, function: ast.AST) -> bool:
    """``node`` runs only on one branch of a test inside ``function`` (the body of an ``if``,
    a branch of a conditional expression or of ``and``/``or``); a test itself always runs."""
    child = node
    for ancestor in facts.ancestors(node):
        if ancestor is function:
            return False
        if isinstance(ancestor, (ast.If, ast.IfExp, ast.While)) and child is not ancestor.test:
            return True
        if isinstance(ancestor, ast.BoolOp) and child is not ancestor.values[0]:
            return True
        if isinstance(ancestor, ast.ExceptHandler):
            return True
        child = ancestor
    return False
