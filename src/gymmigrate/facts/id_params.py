"""Which parameters of a module's defs carry an env id to a Gym id call of the module
(``ModuleSummary.id_params``): ``make(name)`` in ``def build(name)``, ``make(self.env_id)``
with ``self.env_id = env_id`` stored by ``__init__``, and the parameters of the module's
defs that hand theirs on to one of those (``self.check(level)`` -> ``build(level)``). A
literal another module passes there is an id to rename at its call (GM803-GM805).
"""

from __future__ import annotations

import ast
from collections import defaultdict

from gymmigrate.facts import names as N
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts, call_argument, walk
from gymmigrate.facts.receivers import Receivers

Function = ast.FunctionDef | ast.AsyncFunctionDef

# ``gym.make(id)``, ``gym.spec(id)``...: the calls whose first argument (or ``id=``) is an id.
GYM_ID_FUNCTIONS = frozenset({"make", "make_vec", "vector.make", "spec", "envs.make", "envs.spec", "envs.registration.make", "envs.registration.spec"})
ID_KEYWORDS = ("id", "env_id")
# builtins that read a value and hand on none of it
_INSPECTING_BUILTINS = frozenset({"print", "len", "isinstance", "hash", "id", "type", "bool"})
# how many defs a parameter is followed back through (as ``IdSites`` does within a module)
_HOPS = 4


def id_parameters(facts: ModuleFacts, receivers: Receivers) -> dict[str, frozenset[str]]:
    """``{"Worker.__init__": {"env_id"}, "build": {"name"}}``: qualname -> its id parameters."""
    found: dict[str, set[str]] = defaultdict(set)
    work: list[tuple[Function, str, int]] = []

    def add(function: Function, param: str, depth: int) -> None:
        qualname = def_qualname(facts, function)
        if qualname is not None and param not in found[qualname] and depth <= _HOPS:
            found[qualname].add(param)
            work.append((function, param, depth))

    for node in walk(facts.tree):
        if isinstance(node, ast.Call) and _takes_id(facts, node):
            argument = _id_argument(node)
            for function, param in _params_behind(facts, receivers, argument):
                add(function, param, 0)
    while work:
        function, param, depth = work.pop()
        for call, position in _callers(facts, receivers, function, param):
            argument = call_argument(call, position, param)
            for caller, passed in _params_behind(facts, receivers, argument, stored=False):
                add(caller, passed, depth + 1)
    return {qualname: frozenset(params) for qualname, params in found.items() if params}


def _takes_id(facts: ModuleFacts, call: ast.Call) -> bool:
    return any(N.strip_gym_prefix(q) in GYM_ID_FUNCTIONS for q in facts.qualified_names(call.func))


def _id_argument(call: ast.Call) -> ast.expr | None:
    for keyword in call.keywords:
        if keyword.arg in ID_KEYWORDS:
            return keyword.value
    positional = [a for a in call.args if not isinstance(a, ast.Starred)]
    return positional[0] if positional else None


def _params_behind(facts: ModuleFacts, receivers: Receivers, value: ast.expr | None, stored: bool = True) -> list[tuple[Function, str]]:
    """The parameter a value certainly is (a name bound only as that parameter), or for
    ``self.attr`` the ``__init__`` parameters every store of the attribute takes."""
    if isinstance(value, ast.Name):
        bindings = facts.bindings_of(value)
        if len(bindings) == 1 and isinstance(bindings[0], ast.arg):
            function = facts.parent(facts.parent(bindings[0]))
            if isinstance(function, FUNCTIONS):
                return [(function, bindings[0].arg)]
        return []
    if stored and isinstance(value, ast.Attribute) and isinstance(value.value, ast.Name) and value.value.id == "self":
        found = []
        for stored_value in receivers.self_attribute_values(value, value.attr):
            for function, param in _params_behind(facts, receivers, stored_value, stored=False):
                if function.name == "__init__":
                    found.append((function, param))
        return found
    return []


def def_qualname(facts: ModuleFacts, function: Function) -> str | None:
    owner = facts.parent(function)
    if owner is facts.tree:
        return function.name
    if isinstance(owner, ast.ClassDef) and facts.parent(owner) is facts.tree:
        return f"{owner.name}.{function.name}"
    return None


def _callers(facts: ModuleFacts, receivers: Receivers, function: Function, param: str) -> list[tuple[ast.Call, int | None]]:
    """The module's calls of ``function`` and the position ``param`` takes in them."""
    params = [*function.args.posonlyargs, *function.args.args]
    names = [p.arg for p in params]
    position: int | None = names.index(param) if param in names else None
    owner = facts.parent(function)
    if owner is facts.tree:
        return [(call, position) for call in facts.calls_by_name.get(function.name, [])]
    if not (isinstance(owner, ast.ClassDef) and facts.parent(owner) is facts.tree):
        return []
    position = position - 1 if position else None  # ``self`` is not passed
    if function.name == "__init__":
        return [(call, position) for call in facts.calls_by_name.get(owner.name, [])]
    return [(call, position) for call in facts.attribute_calls.get(function.name, []) if receivers.own_method(call.func) is function]


def escaping_parameters(facts: ModuleFacts) -> dict[str, frozenset[str]]:
    """``{"Helper.check": {"environment"}}``: per def and method, its parameters whose value
    goes on somewhere (an argument of a call, stored, returned or yielded as it is, put in a
    container, bound to another name). Any other parameter is only used where it is
    (``"runs of " + label``): a literal passed there never reaches a make."""
    found: dict[str, frozenset[str]] = {}
    for function in [*facts.functions.values(), *(s for c in facts.classes.values() for s in c.body if isinstance(s, FUNCTIONS))]:
        qualname = def_qualname(facts, function)
        if qualname is None:
            continue
        params = {a.arg: a for a in (*function.args.posonlyargs, *function.args.args, *function.args.kwonlyargs)}
        going = set()
        for node in walk(function):
            if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load) and node.id in params and node.id not in going:
                if _goes_on(facts, node):
                    going.add(node.id)
        found[qualname] = frozenset(going)
    return found


def _goes_on(facts: ModuleFacts, read: ast.Name) -> bool:
    parent = facts.parent(read)
    if isinstance(parent, ast.keyword):
        return True
    if isinstance(parent, ast.Call):
        func = parent.func
        if isinstance(func, ast.Name) and func.id in _INSPECTING_BUILTINS and not facts.bindings_of(func):
            return False  # ``print(title)``, ``len(title)``: the text goes no further
        return read is not func
    if isinstance(parent, (ast.Starred, ast.List, ast.Tuple, ast.Set, ast.Dict, ast.Return, ast.Yield, ast.YieldFrom, ast.IfExp, ast.NamedExpr)):
        return True
    if isinstance(parent, (ast.Assign, ast.AnnAssign, ast.AugAssign)):
        return read is parent.value
    if isinstance(parent, (ast.Lambda, ast.comprehension)):
        return True
    if isinstance(parent, ast.Attribute):  # ``name.strip()`` may hand on the same text
        return isinstance(facts.parent(parent), ast.Call)
    if isinstance(parent, ast.FormattedValue):  # ``f"{name}"`` alone is the same text
        joined = facts.parent(parent)
        return isinstance(joined, ast.JoinedStr) and len(joined.values) == 1
    return False
