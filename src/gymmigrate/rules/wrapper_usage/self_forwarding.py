"""Reads of ``self.x`` in a Gym wrapper class's own methods (GM604) that legacy
``Wrapper.__getattr__`` answered from the wrapped env: the class (and the wrapper
classes it derives from, ``EnvOrigins.wrapper_chain``) defines no ``x``, or defines it
only by a statement that reads it first. Part of ``forwarding.WrapperForwarding``.
"""

from __future__ import annotations

import ast
from typing import Protocol

from gymmigrate.facts import names as N
from gymmigrate.facts.module import FUNCTIONS, walk
from gymmigrate.facts.wrapper_attributes import (
    self_defined,
    self_defined_in,
    takes_lookup_in_hand,
)
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.wrapper_usage.atari_limits import Family
from gymmigrate.rules.wrapper_usage.forwarding_edits import (
    replace_with_get_wrapper_attr,
    self_env,
)
from gymmigrate.rules.wrapper_usage.origins import EnvOrigins
from gymmigrate.rules.wrapper_usage.tables import SAFE_ATTRIBUTES


class ForwardingFamily(Family, Protocol):
    """What these checks use of ``WrapperForwarding``."""

    origins: EnvOrigins


# Methods of Gymnasium's wrapper base classes besides SAFE_ATTRIBUTES (a subclass overrides them).
_WRAPPER_OWN = SAFE_ATTRIBUTES | {"observation", "action", "reward", "reverse_action", "env_is_wrapped"}


def self_forwarding(family: ForwardingFamily, attr: ast.Attribute) -> None:
    """``self.get_frame()`` in a method of a Gym wrapper class that defines no
    ``get_frame``: legacy ``Wrapper.__getattr__`` found it on the wrapped env (never a
    private name: gym refused those); ``self.get_wrapper_attr("get_frame")`` searches
    this wrapper, then the ones below it and the base env, as forwarding did."""
    name = attr.attr
    parent = family.facts.parent(attr)
    augmented = isinstance(parent, ast.AugAssign) and parent.target is attr  # ``self.x += 1`` reads it too
    if not (isinstance(attr.ctx, ast.Load) or augmented) or name.startswith("_") or name in _WRAPPER_OWN:
        return
    function = family.facts.enclosing_function(attr)
    classdef = family.facts.enclosing_class(attr)
    if function is None or classdef is None or family.facts.parent(function) is not classdef:
        return
    args = function.args.posonlyargs + function.args.args
    static = any(isinstance(d, ast.Name) and d.id in ("staticmethod", "classmethod") for d in function.decorator_list)
    if not args or args[0].arg != "self" or static:
        return
    imported: set[str] = set()
    chain = wrapper_chain(family, classdef, frozenset(), imported)
    if chain is None or name in imported:
        return
    if any(name in self_defined(local) for local in chain):
        read_before_own_write(family, attr, chain)
        return
    if augmented:
        return  # never stored but through ``+=``: reported where it is (_read_before_own_write's case)
    if family.receivers.wraps_vec_env(classdef):
        return  # no Gymnasium wrapper either (GM602 at the class): what it reads is the VecEnv's, left
    if family.receivers.wraps_pz_parallel(classdef):
        # no Gymnasium wrapper (GM602 at the class): the attribute is the parallel env's, on `self.env`
        # whatever base the class takes instead
        family.report(attr, "GM604", f"attribute forwarding is gone: `{name}` is the wrapped parallel env's, "
                    f"read as `self.env.{name}`", tier=Tier.NOTE)
        family.plan.replace(attr, lambda node: node.with_changes(value=self_env()))
        return
    family.report(
        attr,
        "GM604",
        f"attribute forwarding is gone in Gymnasium 1.0: this wrapper class defines no `{name}`, which gym found on "
        f"the wrapped env; `self.get_wrapper_attr(\"{name}\")` searches the wrappers and the base env as forwarding did",
        tier=Tier.NOTE,
    )
    replace_with_get_wrapper_attr(family.facts, family.plan, attr, name)


def read_before_own_write(family: ForwardingFamily, attr: ast.Attribute, chain: list[ast.ClassDef]) -> None:
    """``self.ob = f(self.ob)`` in a wrapper method, ``ob`` stored by no ``__init__`` of
    the chain and defined by no method or class-level name: until the statement first
    runs, gym found the read on the wrapped env. ``self.get_wrapper_attr("ob")`` looks
    at the wrapper first, then below it, as forwarding did, whichever call it is.
    ``self.ob += x`` (in place on the env's value, then stored here) is reported. Only
    where every store of ``ob`` reads it too: a store elsewhere may run first."""
    name = attr.attr
    for local in chain:
        for item in local.body:
            if isinstance(item, (*FUNCTIONS, ast.ClassDef)) and item.name == name:
                return
            if isinstance(item, (ast.Assign, ast.AnnAssign)) and any(
                isinstance(n, ast.Name) and n.id == name
                for t in (item.targets if isinstance(item, ast.Assign) else [item.target])
                for n in walk(t)
            ):
                return
            if isinstance(item, FUNCTIONS) and item.name == "__init__" and name in self_defined_in(item):
                return
        # every store of it must read it too (``self.n = self.n + 1``, ``self.n += 1``):
        # one elsewhere (``reset`` setting ``self.n = 0``) may well run first
        for node in walk(local):
            if not (isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store) and node.attr == name):
                continue
            if not (isinstance(node.value, ast.Name) and node.value.id == "self"):
                continue
            store = next((a for a in family.facts.ancestors(node) if isinstance(a, ast.stmt)), None)
            if isinstance(store, ast.AugAssign):
                continue
            if not (isinstance(store, ast.Assign) and _reads_self_attribute(store.value, name)):
                return
    statement = next((a for a in family.facts.ancestors(attr) if isinstance(a, ast.stmt)), None)
    if isinstance(statement, ast.AugAssign):
        if attr is statement.target:
            family.report(
                attr,
                "GM604",
                f"attribute forwarding is gone in Gymnasium 1.0: until this line first runs, `self.{name}` is not "
                f"this wrapper's, and gym read (and changed in place) the wrapped env's; read it with "
                f'`self.get_wrapper_attr("{name}")` and assign the result, or set `self.{name}` in __init__',
                FixKind.FLAG,
            )
        return
    if not isinstance(statement, ast.Assign) or not any(
        isinstance(t, ast.Attribute) and t.attr == name and isinstance(t.value, ast.Name) and t.value.id == "self"
        for target in statement.targets
        for t in walk(target)
    ):
        return
    family.report(
        attr,
        "GM604",
        f"attribute forwarding is gone in Gymnasium 1.0: until this line first runs, the wrapper has no `{name}` "
        f'of its own and gym read the wrapped env\'s; `self.get_wrapper_attr("{name}")` reads its own once set, '
        "else the env's, as forwarding did",
        tier=Tier.NOTE,
    )
    replace_with_get_wrapper_attr(family.facts, family.plan, attr, name)


def _reads_self_attribute(node: ast.AST, name: str) -> bool:
    return any(
        isinstance(n, ast.Attribute) and n.attr == name and isinstance(n.ctx, ast.Load) and isinstance(n.value, ast.Name) and n.value.id == "self"
        for n in walk(node)
    )


def wrapper_chain(family: ForwardingFamily, classdef: ast.ClassDef, seen: frozenset[int], imported: set[str]) -> list[ast.ClassDef] | None:
    """``classdef`` and the classes of this module it derives from, when every base is
    one of those, a Gym wrapper base class (``Wrapper``, ``ObservationWrapper``...) or a
    wrapper class of another module of the run whose definitions the run knows (added to
    ``imported``: ``class Task(TrialWrapper)``), at least one is, and none takes
    attribute lookup in hand; else None."""
    if id(classdef) in seen or not classdef.bases or classdef.keywords:
        return None
    chain = [classdef]
    gym_base = False
    view = family.receivers.project
    for base in classdef.bases:
        qualified = family.facts.qualified_names(base)
        names = {N.strip_gym_prefix(q) for q in qualified}
        if names & N.GYM_WRAPPER_BASE_CLASSES:
            gym_base = True
            continue
        known = [view.wrapper_defined(q) for q in qualified] if view is not None else []
        if len(known) == 1 and known[0] is not None:
            imported |= known[0]
            gym_base = True
            continue
        local = family.receivers.local_class(base)
        inner = None if local is None else wrapper_chain(family, local, seen | {id(classdef)}, imported)
        if inner is None:
            return None
        chain += inner
        gym_base = True
    if not gym_base or any(takes_lookup_in_hand(local) for local in chain):
        return None
    return chain
