"""Which attributes an instance of a class certainly has once constructed: those its class
body binds, and those its ``__init__`` stores on ``self`` on every path that creates the
object, with the methods ``__init__`` calls on ``self`` and the base ``__init__`` it hands
up to (``super().__init__(...)``, ``Base.__init__(self, ...)``), along the class's bases.

GM604 asks it of the class a ``make`` builds: ``set_wrapper_attr("x", v)`` sets ``x`` on
the layer that has it, so where the env itself has ``x`` (and no layer make adds does) the
write lands on the env, as the legacy write to the bare env did. GM507 asks it of a bare
env: ``env.reward_range`` works where the env's class stores ``reward_range`` itself.

Each module describes its top-level classes (``ClassStores``, in ``ModuleSummary``); the
join follows bases across modules (``project_classes.join_init_attributes``), and a file
processed alone follows its own classes (``local_init_attributes``). A path through
``__init__`` that raises creates no object, so only ``return`` cuts what is certain. Bases
are followed while each class has one base: there the method resolution order is the
chain itself; beyond a class with several bases, or one of a library, nothing is added.
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TypeVar

from gymmigrate.facts import names as N
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts, walk

SUPER = "super"  # ``super().__init__(...)``: the next class of the chain
UNKNOWN_BASE = ""  # a base of a library, or one the module cannot name
MAX_CHAIN = 50


@dataclass(frozen=True)
class MethodStores:
    """What one method certainly does before it returns: the attributes it stores on
    ``self``, the methods it calls on ``self``, and the base ``__init__`` it hands up to
    (``SUPER``, or a base as ``ClassStores.bases`` spells it)."""

    stores: frozenset[str] = frozenset()
    calls: frozenset[str] = frozenset()
    ups: frozenset[str] = frozenset()


# A method that certainly does none of these (most): one shared record, pickled once per summary.
NOTHING = MethodStores()


@dataclass(frozen=True)
class ClassStores:
    """One top-level class: its bases (``@Name`` for a class of the module, the qualified
    name of an imported one, ``UNKNOWN_BASE`` otherwise), the names its body binds (class
    attributes and methods), and what each of its methods certainly does."""

    bases: tuple[str, ...]
    body: frozenset[str]
    methods: dict[str, MethodStores] = field(default_factory=dict)


def module_class_stores(facts: ModuleFacts) -> dict[str, ClassStores]:
    """``ModuleSummary.class_stores``: every top-level class of the module."""
    return facts.memo(("init_attributes.module", 0), lambda: {name: _class_stores(facts, c) for name, c in facts.classes.items()})


def _class_stores(facts: ModuleFacts, classdef: ast.ClassDef) -> ClassStores:
    bases = []
    for base in classdef.bases:
        if isinstance(base, ast.Name) and facts.classes.get(base.id) is not None and facts.classes[base.id] is not classdef:
            bases.append("@" + base.id)
            continue
        qualified = [q for q in facts.qualified_names(base) if not N.is_library(q)]
        bases.append(qualified[0] if len(qualified) == 1 else UNKNOWN_BASE)
    body: set[str] = set()
    methods: dict[str, MethodStores] = {}
    for statement in classdef.body:
        if isinstance(statement, FUNCTIONS):
            body.add(statement.name)
            methods[statement.name] = _method_stores(facts, classdef, tuple(bases), statement)
        elif isinstance(statement, ast.Assign):
            body.update(t.id for t in statement.targets if isinstance(t, ast.Name))
        elif isinstance(statement, ast.AnnAssign) and statement.value is not None and isinstance(statement.target, ast.Name):
            body.add(statement.target.id)
    return ClassStores(tuple(bases), frozenset(body), methods)


def _method_stores(
    facts: ModuleFacts, classdef: ast.ClassDef, bases: tuple[str, ...], function: ast.FunctionDef | ast.AsyncFunctionDef
) -> MethodStores:
    params = [*function.args.posonlyargs, *function.args.args]
    if not params or any(isinstance(d, ast.Name) and d.id in ("staticmethod", "classmethod") for d in function.decorator_list):
        return NOTHING
    path = _Block(facts, classdef, bases, params[0].arg).run(function.body)
    if not (path.stores or path.calls or path.ups):
        return NOTHING
    return MethodStores(frozenset(path.stores), frozenset(path.calls), frozenset(path.ups))


@dataclass
class _Path:
    """What every path through a block that leaves it (falling through or returning)
    certainly did; ``falls``: some path reaches its end; ``returned``: some path returned
    inside it (past that, nothing more is certain)."""

    stores: set[str] = field(default_factory=set)
    calls: set[str] = field(default_factory=set)
    ups: set[str] = field(default_factory=set)
    falls: bool = True
    returned: bool = False


def _meet(paths: list[_Path]) -> _Path:
    """Branches joined: what every branch that leaves did. A branch that always raises
    creates no object, so it does not count."""
    live = [p for p in paths if p.falls or p.returned]
    if not live:
        return _Path(falls=False)
    return _Path(
        set.intersection(*(p.stores for p in live)),
        set.intersection(*(p.calls for p in live)),
        set.intersection(*(p.ups for p in live)),
        falls=any(p.falls for p in live),
        returned=any(p.returned for p in live),
    )


class _Block:
    """The certain effects of one method's statements on ``self``."""

    def __init__(self, facts: ModuleFacts, classdef: ast.ClassDef, bases: tuple[str, ...], self_name: str) -> None:
        self.facts = facts
        self.classdef = classdef
        self.bases = bases
        self.self_name = self_name

    def run(self, statements: list[ast.stmt]) -> _Path:
        path = _Path()
        for statement in statements:
            step = self._statement(statement)
            path.stores |= step.stores
            path.calls |= step.calls
            path.ups |= step.ups
            path.returned = path.returned or step.returned
            if step.returned or not step.falls:
                path.falls = step.falls
                return path
        return path

    def _statement(self, statement: ast.stmt) -> _Path:
        if isinstance(statement, ast.Return):
            return _Path(falls=False, returned=True)
        if isinstance(statement, ast.Raise):
            return _Path(falls=False)
        if isinstance(statement, ast.If):
            return _meet([self.run(statement.body), self.run(statement.orelse)])
        if isinstance(statement, (ast.With, ast.AsyncWith)) and not any(self._suppresses(item.context_expr) for item in statement.items):
            return self.run(statement.body)
        if isinstance(statement, ast.Try):
            met = _meet([self.run([*statement.body, *statement.orelse]), *(self.run(h.body) for h in statement.handlers)])
            final = self.run(statement.finalbody)  # runs on every path
            met.stores |= final.stores
            met.calls |= final.calls
            met.ups |= final.ups
            met.returned = met.returned or final.returned
            return met
        if isinstance(statement, (*FUNCTIONS, ast.ClassDef)):
            return _Path()
        if isinstance(statement, (ast.Assign, ast.AnnAssign, ast.Expr)):
            return self._simple(statement)
        # a loop, a match, a with that may swallow an exception: what it does may not
        # happen, and a return in it may
        return _Path(returned=any(isinstance(node, ast.Return) for node in walk(statement)))

    def _suppresses(self, expr: ast.expr) -> bool:
        return isinstance(expr, ast.Call) and any(q.rsplit(".", 1)[-1] == "suppress" for q in self.facts.qualified_names(expr.func))

    def _simple(self, statement: ast.Assign | ast.AnnAssign | ast.Expr) -> _Path:
        path = _Path()
        if isinstance(statement, ast.Assign):
            targets = statement.targets
        elif isinstance(statement, ast.AnnAssign) and statement.value is not None:
            targets = [statement.target]
        else:
            targets = []
        for target in targets:
            for element in _elements(target):
                if isinstance(element, ast.Attribute) and self._is_self(element.value):
                    path.stores.add(element.attr)
        if isinstance(statement.value, ast.Call):
            self._call(statement.value, path)
        return path

    def _call(self, call: ast.Call, path: _Path) -> None:
        func = call.func
        if isinstance(func, ast.Name) and func.id == "setattr" and len(call.args) == 3 and self._is_self(call.args[0]):
            name = call.args[1]
            if isinstance(name, ast.Constant) and isinstance(name.value, str):
                path.stores.add(name.value)
            return
        if not isinstance(func, ast.Attribute):
            return
        if self._is_self(func.value):
            path.calls.add(func.attr)
            return
        if func.attr != "__init__":
            return
        owner = func.value
        if isinstance(owner, ast.Call) and isinstance(owner.func, ast.Name) and owner.func.id == "super":
            # ``super()`` or ``super(ThisClass, self)``: the next class of the chain
            if not owner.args or (isinstance(owner.args[0], ast.Name) and owner.args[0].id == self.classdef.name):
                path.ups.add(SUPER)
            return
        if call.args and self._is_self(call.args[0]):
            for position, base in enumerate(self.classdef.bases):
                if ast.dump(base) == ast.dump(owner):
                    path.ups.add(self.bases[position])

    def _is_self(self, node: ast.AST) -> bool:
        return isinstance(node, ast.Name) and node.id == self.self_name


def _elements(target: ast.expr) -> list[ast.expr]:
    if isinstance(target, (ast.Tuple, ast.List)):
        return [e for element in target.elts for e in _elements(element)]
    return [target]


Key = TypeVar("Key")


def certain_attributes(start: Key, lookup: Callable[[Key], ClassStores | None], resolve: Callable[[Key, str], Key | None]) -> frozenset[str]:
    """What an instance of class ``start`` certainly has once constructed: ``lookup`` gives
    a class's ``ClassStores``, ``resolve`` the class a base spelled in one names (None
    where the run does not define it)."""
    chain = _chain(start, lookup, resolve)
    classes = [lookup(key) for key in chain]
    found: set[str] = set()
    for stores in classes:
        if stores is not None:
            found |= stores.body
    open_methods: set[tuple[int, str]] = set()

    def defining(index: int | None, name: str) -> int | None:
        """Where ``name`` is found from ``chain[index]`` up (the chain is the start of the MRO)."""
        for position in range(index if index is not None else len(chain), len(chain)):
            stores = classes[position]
            if stores is not None and name in stores.methods:
                return position
        return None

    def runs(position: int, name: str) -> set[str]:
        if (position, name) in open_methods:
            return set()  # a method reached again while it runs adds nothing new
        open_methods.add((position, name))
        method = classes[position].methods[name]  # type: ignore[union-attr]
        stored = set(method.stores)
        for called in method.calls:
            where = defining(0, called)  # ``self.setup()`` is looked up on the instance's class
            if where is not None:
                stored |= runs(where, called)
        for up in method.ups:
            target = position + 1 if up == SUPER else _index_of(chain, resolve(chain[position], up))
            where = defining(target, "__init__")
            if where is not None:
                stored |= runs(where, "__init__")
        open_methods.discard((position, name))
        return stored

    where = defining(0, "__init__")
    if where is not None:
        found |= runs(where, "__init__")
    return frozenset(found)


def _index_of(chain: list[Key], key: Key | None) -> int | None:
    return chain.index(key) if key is not None and key in chain else None


def _chain(start: Key, lookup: Callable[[Key], ClassStores | None], resolve: Callable[[Key, str], Key | None]) -> list[Key]:
    """``start`` and its bases while each class has one base the run defines."""
    chain = [start]
    while len(chain) < MAX_CHAIN:
        stores = lookup(chain[-1])
        if stores is None or len(stores.bases) != 1 or stores.bases[0] == UNKNOWN_BASE:
            break
        base = resolve(chain[-1], stores.bases[0])
        if base is None or base in chain:
            break
        chain.append(base)
    return chain


def local_init_attributes(facts: ModuleFacts, classdef: ast.ClassDef) -> frozenset[str]:
    """``certain_attributes`` of a top-level class of a file processed alone: its bases of
    the module followed, imported ones not."""
    if facts.classes.get(classdef.name) is not classdef:
        return frozenset()
    stores = module_class_stores(facts)

    def resolve(_key: str, base: str) -> str | None:
        return base[1:] if base.startswith("@") and base[1:] in stores else None

    return facts.memo(("init_attributes.local", id(classdef)), lambda: certain_attributes(classdef.name, stores.get, resolve))
