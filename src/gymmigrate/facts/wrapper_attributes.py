"""What a Gym wrapper class defines for ``self`` (GM604, rules/wrapper_usage/forwarding.py):
a read of ``self.x`` in a wrapper whose class and bases never define ``x`` was legacy
``Wrapper.__getattr__`` forwarding to the wrapped env. ``wrapper_defined`` is the per-module
summary of it for the wrapper classes other modules derive from (``class Task(TrialWrapper)``,
``TrialWrapper`` in ``pkg/core.py``).
"""

from __future__ import annotations

import ast
import weakref

from gymmigrate.facts import names as N
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts, own_returns, walk


def self_defined(classdef: ast.ClassDef) -> set[str]:
    """What a class defines for ``self``: its methods and class-level names, and every
    ``self.x`` it stores anywhere (tuple targets, ``for``, ``with ... as`` included)."""
    # GM604 asks this for every ``self.x`` read in the class: the class is walked once (a
    # tree never changes once parsed), and each caller gets a set of its own.
    names = _SELF_DEFINED.get(classdef)
    if names is None:
        names = _SELF_DEFINED[classdef] = _self_defined(classdef)
    return set(names)


_SELF_DEFINED: weakref.WeakKeyDictionary[ast.ClassDef, set[str]] = weakref.WeakKeyDictionary()
_TAKES_LOOKUP_IN_HAND: weakref.WeakKeyDictionary[ast.ClassDef, bool] = weakref.WeakKeyDictionary()


def _self_defined(classdef: ast.ClassDef) -> set[str]:
    names: set[str] = set()
    for statement in classdef.body:
        if isinstance(statement, (*FUNCTIONS, ast.ClassDef)):
            names.add(statement.name)
        elif isinstance(statement, (ast.Assign, ast.AnnAssign, ast.AugAssign)):
            targets = statement.targets if isinstance(statement, ast.Assign) else [statement.target]
            names.update(n.id for target in targets for n in walk(target) if isinstance(n, ast.Name))
    for node in walk(classdef):
        if isinstance(node, FUNCTIONS):
            names.add(node.name)
        elif isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store) and isinstance(node.value, ast.Name) and node.value.id == "self":
            names.add(node.attr)
    return names


def self_defined_in(function: ast.AST) -> set[str]:
    """Every ``self.x`` that ``function`` stores."""
    return {
        n.attr
        for n in walk(function)
        if isinstance(n, ast.Attribute) and isinstance(n.ctx, ast.Store) and isinstance(n.value, ast.Name) and n.value.id == "self"
    }


# Three questions about attribute lookup on a class, side by side because they sound alike and
# must not be mixed up (each caller needs the one it asks):
# - ``takes_lookup_in_hand``: can what ``self`` has be listed from the class body? Not when the
#   class hooks lookup (``__getattr__``, ``__getattribute__``, ``__init_subclass__``), calls
#   ``setattr`` or touches ``__dict__``: GM604 then never calls a ``self.x`` read forwarding.
# - ``defines_getattr``: may a read of a name the class lacks still answer? Any ``__getattr__``
#   of its own, whatever it returns (where it may lead, a call there is not left as another
#   API's: ``ReceiverClasses.derives_own_api``).
# - ``lookup_forwarded_to``: does every lookup the class cannot answer go on to one object it
#   holds, and which (``self.env``)? Proof enough to take the class for a stand-in of that
#   object (a duck wrapper, ``receiver_classes.duck_wrapper_param``; a render adapter,
#   ``rules/rendering/common.forwards_to_first_argument``).
# GM604's check of ``getattr(self._env, name)`` in a ``__getattr__`` (rules/wrapper_usage/
# getattr_hasattr.py) asks about one call, not a class: which call to rewrite, whatever it reads.


def takes_lookup_in_hand(classdef: ast.ClassDef) -> bool:
    """It defines ``__getattr__``/``__getattribute__``, or sets attributes by name."""
    taken = _TAKES_LOOKUP_IN_HAND.get(classdef)
    if taken is None:
        taken = _TAKES_LOOKUP_IN_HAND[classdef] = _takes_lookup_in_hand(classdef)
    return taken


def _takes_lookup_in_hand(classdef: ast.ClassDef) -> bool:
    for node in walk(classdef):
        if isinstance(node, FUNCTIONS) and node.name in ("__getattr__", "__getattribute__", "__init_subclass__"):
            return True
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "setattr":
            return True
        if isinstance(node, ast.Attribute) and node.attr == "__dict__":
            return True
    return False


def defines_getattr(classdef: ast.ClassDef) -> bool:
    """The class body defines ``__getattr__`` (whatever it returns)."""
    return any(isinstance(s, ast.FunctionDef) and s.name == "__getattr__" for s in classdef.body)


def lookup_forwarded_to(lookup: ast.AST | None) -> str | None:
    """``x`` when ``lookup`` is a ``__getattr__(self, name)`` every return of which hands the
    name on to ``self.x``: ``getattr(self.x, name)`` (a default allowed) as legacy code wrote
    it, or ``self.x.get_wrapper_attr(name)`` as the migration writes it for a Gym env (GM604),
    so that a second run decides as the first did. None for any other function."""
    if not isinstance(lookup, FUNCTIONS):
        return None
    params = [*lookup.args.posonlyargs, *lookup.args.args]
    if len(params) != 2:
        return None
    owner, name = params[0].arg, params[1].arg
    slots = {_forwarded_slot(r.value, owner, name) for r in own_returns(lookup)}
    return slots.pop() if len(slots) == 1 else None  # (a None among them: not every return forwards)


def _forwarded_slot(value: ast.AST | None, owner: str, name: str) -> str | None:
    if not isinstance(value, ast.Call) or value.keywords:
        return None
    if isinstance(value.func, ast.Name) and value.func.id == "getattr" and len(value.args) in (2, 3):
        held, looked_up = value.args[0], value.args[1]
    elif isinstance(value.func, ast.Attribute) and value.func.attr == "get_wrapper_attr" and len(value.args) == 1:
        held, looked_up = value.func.value, value.args[0]
    else:
        return None
    if not (isinstance(looked_up, ast.Name) and looked_up.id == name):
        return None
    if isinstance(held, ast.Attribute) and isinstance(held.value, ast.Name) and held.value.id == owner:
        return held.attr
    return None


def local_wrapper_chain(facts: ModuleFacts, classdef: ast.ClassDef, seen: frozenset[int] = frozenset()) -> list[ast.ClassDef] | None:
    """``classdef`` and the classes of this module it derives from, when every base is one
    of those or a Gym wrapper base class (``Wrapper``...), and none takes attribute lookup
    in hand; else None."""
    if id(classdef) in seen or not classdef.bases or classdef.keywords:
        return None
    chain = [classdef]
    for base in classdef.bases:
        names = {N.strip_gym_prefix(q) for q in facts.qualified_names(base)}
        if names & N.GYM_WRAPPER_BASE_CLASSES:
            continue
        if names & N.GYM_MIXIN_CLASSES:
            # defines no env attribute: the class is still a wrapper of this module's chain
            # (and stays one once the migration adds RecordConstructorArgs to it)
            continue
        local = facts.classes.get(base.id) if isinstance(base, ast.Name) else None
        inner = None if local is None else local_wrapper_chain(facts, local, seen | {id(classdef)})
        if inner is None:
            return None
        chain += inner
    if any(takes_lookup_in_hand(c) for c in chain):
        return None
    return chain


def wrapper_defined(facts: ModuleFacts) -> dict[str, frozenset[str]]:
    """Top-level Gym wrapper classes (bases of this module or Gym's) -> what they and their
    bases define for ``self``."""
    found = {}
    for name, classdef in facts.classes.items():
        chain = local_wrapper_chain(facts, classdef)
        if chain is not None:
            found[name] = frozenset(n for c in chain for n in self_defined(c))
    return found
