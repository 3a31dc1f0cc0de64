"""Which Gym spaces an env class leaves unset once it is constructed, and which classes a
module's registrations make (GM511).

gym 0.21's ``Env`` had ``action_space = None`` and ``observation_space = None``, so an env
class that never set one still had the attribute. Gymnasium's ``Env`` only annotates them,
and the ``PassiveEnvChecker`` that ``gymnasium.make`` puts around every env asserts both
the moment ``make`` has built it: ``AttributeError: The environment must specify an
observation space``. What matters is what the class (with its bases) has set by then:
a class attribute or a def of that name, or a store in ``__init__`` and in the methods it
calls on ``self``; a store in ``reset`` alone comes too late.

Where the class's code cannot show that (a decorator, a metaclass, ``__getattr__``,
``self`` handed to code of its own, a base that is neither Gym's ``Env``, a mixin that sets
nothing, nor a class of the run), the answer is None: the question is not asked.
"""

from __future__ import annotations

import ast
from collections.abc import Iterator

from gymmigrate.facts import names as N
from gymmigrate.facts.module import (
    FUNCTIONS,
    ModuleFacts,
    call_argument,
    own_entry_point,
    string_value,
    walk,
)
from gymmigrate.facts.module_summary import OWN
from gymmigrate.facts.receivers import Receivers

SPACES = ("action_space", "observation_space")
_ALL = frozenset(SPACES)
# Bases whose construction sets no space: gym's Env itself (its spaces were class-level
# ``None``s, which Gymnasium no longer has) and mixins that set none.
_ENV_ROOTS = frozenset({"Env", "core.Env"})
_INERT_GYM = frozenset({"utils.EzPickle", "utils.ezpickle.EzPickle"})
_INERT = frozenset({"abc.ABC", "typing.Generic"})
_DYNAMIC = frozenset({"__getattr__", "__getattribute__"})


def own_unset_spaces(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> tuple[frozenset[str], tuple[str, ...]] | None:
    """(the spaces ``classdef``'s own code leaves unset once constructed, its bases of the
    run: ``@Name`` for a class of this module, else the qualified name), or None when the
    class's code cannot show it (see the module's docstring)."""
    return facts.memo(("own-unset-spaces", id(classdef)), lambda: _own_unset(facts, receivers, classdef))


def _own_unset(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> tuple[frozenset[str], tuple[str, ...]] | None:
    if classdef.decorator_list or classdef.keywords:
        return None  # a decorator (``@dataclass``) or a metaclass may set anything
    bases: list[str] = []
    for base in classdef.bases:
        local = receivers.local_class(base)
        if local is not None:
            if local is not classdef:
                bases.append(OWN + local.name)
            continue
        if isinstance(base, ast.Name) and base.id == "object" and not facts.bindings_of(base):
            continue
        qualified = facts.qualified_names(base)
        if len(qualified) != 1:
            return None
        name = next(iter(qualified))
        rest = N.strip_gym_prefix(name)
        if rest is not None:
            if rest in _ENV_ROOTS or rest in _INERT_GYM:
                continue
            return None  # a library env of gym's (``MujocoEnv``) sets its own spaces
        if name in _INERT:
            continue
        if N.is_library(name) or "." not in name:
            return None
        bases.append(name)
    unset = set(SPACES)
    methods = {s.name: s for s in classdef.body if isinstance(s, FUNCTIONS)}
    if _DYNAMIC & methods.keys():
        return None
    for statement in classdef.body:
        unset -= _class_level_names(statement)
    for method in _construction(methods):
        found = _stored(method)
        if found is None:
            return None
        unset -= found
    if unset:
        # ``Sim.observation_space = Box(...)`` after the class, at module level
        for space in tuple(unset):
            for attribute in facts.attributes.get(space, ()):
                if isinstance(attribute.ctx, ast.Store) and isinstance(attribute.value, ast.Name) and attribute.value.id == classdef.name:
                    unset.discard(space)
    return frozenset(unset), tuple(bases)


def _class_level_names(statement: ast.stmt) -> set[str]:
    """The spaces a statement of the class body binds: ``observation_space = ...``, an
    annotation (a dataclass field), a def or property of that name."""
    if isinstance(statement, (*FUNCTIONS, ast.ClassDef)):
        return {statement.name} & _ALL
    targets: list[ast.expr] = []
    if isinstance(statement, ast.Assign):
        targets = list(statement.targets)
    elif isinstance(statement, (ast.AnnAssign, ast.AugAssign)):
        targets = [statement.target]
    names = {n.id for t in targets for n in walk(t) if isinstance(n, ast.Name)}
    if isinstance(statement, (ast.If, ast.Try, ast.With)):
        for child in ast.iter_child_nodes(statement):
            if isinstance(child, ast.stmt):
                names |= _class_level_names(child)
    return names & _ALL


def _construction(methods: dict[str, ast.FunctionDef | ast.AsyncFunctionDef]) -> Iterator[ast.FunctionDef | ast.AsyncFunctionDef]:
    """``__init__`` and the methods of the class it calls on ``self``, at any depth."""
    todo = ["__init__"]
    seen: set[str] = set()
    while todo:
        name = todo.pop()
        method = methods.get(name)
        if name in seen or method is None:
            continue
        seen.add(name)
        yield method
        for node in walk(method):
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and isinstance(node.func.value, ast.Name) and node.func.value.id == "self":
                todo.append(node.func.attr)


def _stored(method: ast.FunctionDef | ast.AsyncFunctionDef) -> set[str] | None:
    """The spaces ``method`` stores on any object (``self.observation_space = ...``,
    ``setattr(self, "action_space", ...)``); None when it may store any attribute
    (``setattr`` with a computed name, ``__dict__``, ``vars(self)``, ``self`` handed to
    code that is no base's ``__init__``)."""
    found: set[str] = set()
    for node in walk(method):
        if isinstance(node, ast.Attribute):
            if node.attr in _ALL and isinstance(node.ctx, (ast.Store, ast.Del)):
                found.add(node.attr)
            elif node.attr == "__dict__":
                return None
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in ("setattr", "vars"):
            if node.func.id == "vars":
                return None
            name = string_value(node.args[1]) if len(node.args) > 1 else None
            if name is None:
                return None
            found |= {name} & _ALL
        elif isinstance(node, ast.Call) and _hands_self_on(node):
            return None
    return found


def _hands_self_on(call: ast.Call) -> bool:
    """``self`` as an argument of a call that is not ``super(...)`` nor a base's
    ``Base.__init__(self, ...)`` (which the walk over the bases covers)."""
    if not any(isinstance(a, ast.Name) and a.id == "self" for a in (*call.args, *(k.value for k in call.keywords))):
        return False
    func = call.func
    if isinstance(func, ast.Name) and func.id in ("super", "setattr", "getattr", "hasattr", "isinstance", "id", "type", "print", "repr", "str"):
        return False
    return not (isinstance(func, ast.Attribute) and func.attr == "__init__")


def local_unset_spaces(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> frozenset[str] | None:
    """The spaces ``classdef`` leaves unset with its bases, where every base is Gym's ``Env``,
    a mixin that sets none, or a class of this module; None otherwise."""
    return _local(facts, receivers, classdef, frozenset())


def _local(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef, seen: frozenset[int]) -> frozenset[str] | None:
    own = own_unset_spaces(facts, receivers, classdef)
    if own is None or id(classdef) in seen:
        return None
    unset, bases = own
    for base in bases:
        local = facts.classes.get(base[len(OWN) :]) if base.startswith(OWN) else None
        inherited = _local(facts, receivers, local, seen | {id(classdef)}) if local is not None else None
        if inherited is None:
            return None
        unset &= inherited
    return unset


def runs_base_init(classdef: ast.ClassDef) -> bool:
    """Building ``classdef`` runs its base's ``__init__``: it has none of its own, or its own
    calls ``super().__init__(...)`` or ``Base.__init__(self, ...)``. A space the base sets
    in its construction is then set on this class too."""
    init = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "__init__"), None)
    if init is None:
        return True
    for node in walk(init):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "__init__":
            held = node.func.value
            if isinstance(held, ast.Call) and isinstance(held.func, ast.Name) and held.func.id == "super":
                return True
            if isinstance(held, ast.Name) and node.args and isinstance(node.args[0], ast.Name) and node.args[0].id == "self":
                return True
    return False


def local_unset_owner(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> ast.ClassDef:
    """The highest class of this module above ``classdef`` (itself where none) that leaves
    every space ``classdef`` leaves unset, through single bases whose ``__init__`` each
    class runs: setting the spaces there sets them for ``classdef``, so GM511 asks there."""
    spaces = local_unset_spaces(facts, receivers, classdef) or frozenset()
    owner = classdef
    seen = {id(classdef)}
    while spaces and runs_base_init(owner):
        own = own_unset_spaces(facts, receivers, owner)
        if own is None or len(own[1]) != 1 or not own[1][0].startswith(OWN):
            break
        base = facts.classes.get(own[1][0][len(OWN) :])
        if base is None or id(base) in seen or not spaces <= (local_unset_spaces(facts, receivers, base) or frozenset()):
            break
        seen.add(id(base))
        owner = base
    return owner


def module_unset_spaces(facts: ModuleFacts, receivers: Receivers) -> dict[str, tuple[tuple[str, ...], tuple[str, ...]]]:
    """``ModuleSummary.unset_spaces``: each top-level class whose own code leaves a space
    unset, with its bases of the run (the join intersects what they leave unset)."""
    found = {}
    for name, classdef in facts.classes.items():
        own = own_unset_spaces(facts, receivers, classdef)
        if own is not None and own[0]:
            found[name] = (tuple(sorted(own[0])), own[1])
    return found


def def_builds(facts: ModuleFacts, receivers: Receivers) -> dict[str, tuple[str, ...]]:
    """``ModuleSummary.def_builds``: each top-level def with the classes it may construct,
    as this module spells them (``@Name`` for its own, else the qualified name of a name of
    the run), through the defs of this module it calls. A def that stores a space on what
    it builds (``env.observation_space = ...``) builds nothing this question is about."""
    memo: dict[str, frozenset[str] | None] = {}

    def builds(name: str) -> frozenset[str] | None:
        if name in memo:
            return memo[name] or frozenset()
        memo[name] = None  # a cycle of defs adds nothing
        function = facts.functions[name]
        found: set[str] = set()
        for node in walk(function):
            if isinstance(node, ast.Attribute) and node.attr in _ALL and isinstance(node.ctx, ast.Store):
                memo[name] = frozenset()
                return frozenset()
            if not isinstance(node, ast.Call):
                continue
            local = receivers.local_class(node.func)
            if local is not None:
                found.add(OWN + local.name)
                continue
            called = receivers.local_function(node.func)
            if called is not None:
                found |= builds(called.name) or frozenset()
                continue
            qualified = facts.qualified_names(node.func)
            if len(qualified) == 1 and "." in (q := next(iter(qualified))) and not N.is_library(q):
                found.add(q)
        memo[name] = frozenset(found)
        return memo[name]

    result = {}
    for name in facts.functions:
        built = builds(name)
        if built:
            result[name] = tuple(sorted(built))
    return result


def _checked_registrations(facts: ModuleFacts) -> Iterator[ast.expr | None]:
    """The entry points of the module's Gym ``register(...)`` calls that leave the env
    checker on: no ``disable_env_checker=`` (nor ``**kwargs`` that may hold it)."""
    for call in (*facts.calls_by_name.get("register", ()), *facts.attribute_calls.get("register", ())):
        if not any((N.strip_gym_prefix(q) or "").endswith("register") for q in facts.qualified_names(call.func)):
            continue
        if any(k.arg is None or k.arg == "disable_env_checker" for k in call.keywords):
            continue
        yield call_argument(call, 1, "entry_point")


def checked_entries(facts: ModuleFacts) -> tuple[str, ...]:
    """``ModuleSummary.checked_entries``: the literal entry points (``"pkg.envs:make_env"``,
    ``":Sim"`` for ``__name__ + ":Sim"``) of registrations that leave the env checker on."""
    found = []
    for entry in _checked_registrations(facts):
        text = string_value(entry) if entry is not None else None
        text = text if text is not None else own_entry_point(entry)
        if text is not None and text.count(":") == 1:
            found.append(text)
    return tuple(found)


def registered_here(facts: ModuleFacts, receivers: Receivers, module: str | None) -> frozenset[str]:
    """The classes of this module that its own ``register(...)`` calls make with the env
    checker on: an entry point naming a class or def of the module (``entry_point=Sim``,
    ``"__main__:Sim"``, ``__name__ + ":Sim"``, ``"<module>:Sim"`` where ``module`` is this
    module's dotted name in the run), a def counting for the classes of the module it builds."""
    found: set[str] = set()
    builds = def_builds(facts, receivers)
    for entry in _checked_registrations(facts):
        name: str | None = None
        if isinstance(entry, ast.Name):
            named = receivers.local_class(entry) or receivers.local_function(entry)
            name = named.name if named is not None else None
        else:
            text = string_value(entry) if entry is not None else None
            text = text if text is not None else own_entry_point(entry)
            if text is not None and text.count(":") == 1:
                where, _, name = text.partition(":")
                if where not in ("", "__main__") and where != module:
                    name = None
        if name is None:
            continue
        if name in facts.classes:
            found.add(name)
        found |= {b[len(OWN) :] for b in builds.get(name, ()) if b.startswith(OWN)}
    return frozenset(found)
