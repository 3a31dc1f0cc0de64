"""Where an ``entry_point`` the registry rules cannot resolve comes from (GM808).

``register(id=id, **kwargs)`` in a helper, ``entry_point=target`` from a loop over a table,
``entry_point=_discover("pkg.tasks")[name]``: the class it names is not written at the call.
The run proves the entry point is one of its own when the values that may flow into it, within
the module, hold a string naming a module of the run (``"pkg.tasks"``, ``"pkg.tasks:Maze"``,
``"__main__:Maze"``) or a name of a class of the run. The walk follows a name to its
bindings (assignments, loop and comprehension targets) and a parameter to the arguments the
module's calls of its function pass; anything else (a name from another library, a value
read from a file or the command line) proves nothing.
"""

from __future__ import annotations

import ast
from collections.abc import Callable

from gymmigrate.facts.module import ModuleFacts, walk

# how many expressions one question may visit: a registration's table is short, a
# module's whole data flow is not worth following
_LIMIT = 200


def entry_from_run(
    facts: ModuleFacts,
    call: ast.Call,
    value: ast.expr | None,
    names_run_module: Callable[[str], bool],
    is_run_class: Callable[[ast.Name], bool],
) -> bool:
    """Whether the entry point of ``register(...)`` call ``call`` (``value``: its written
    value, None where ``**kwargs`` carry it) is shown to name a module or class of the run."""
    todo: list[ast.AST] = [value] if value is not None else _forwarded(facts, call)
    seen: set[int] = set()
    while todo and len(seen) < _LIMIT:
        node = todo.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
        for part in walk(node):
            if isinstance(part, ast.Constant) and isinstance(part.value, str) and _names_module(part.value, names_run_module):
                return True
            if isinstance(part, ast.Name) and isinstance(part.ctx, ast.Load):
                if is_run_class(part):
                    return True
                todo.extend(_sources(facts, part))
    return False


def _names_module(text: str, names_run_module: Callable[[str], bool]) -> bool:
    module, colon, _ = text.partition(":")
    if not colon and "." not in module:
        return False  # a bare word is no module path
    return bool(module) and names_run_module(module)


def _forwarded(facts: ModuleFacts, call: ast.Call) -> list[ast.AST]:
    """``register(id=id, **kwargs)`` in a function: the ``entry_point=`` its callers in the
    module pass (and their own ``**`` mappings)."""
    starred = [kw.value for kw in call.keywords if kw.arg is None]
    function = facts.enclosing_function(call)
    if function is None or function.args.kwarg is None:
        return list(starred)
    if not any(isinstance(s, ast.Name) and s.id == function.args.kwarg.arg for s in starred):
        return list(starred)
    found: list[ast.AST] = []
    for caller in _calls_of(facts, function):
        found.extend(kw.value for kw in caller.keywords if kw.arg in ("entry_point", None))
    return found


def _sources(facts: ModuleFacts, name: ast.Name) -> list[ast.AST]:
    found: list[ast.AST] = []
    for binding in facts.bindings_of(name):
        if isinstance(binding, ast.arg):
            function = facts.enclosing(binding, (ast.FunctionDef, ast.AsyncFunctionDef))
            if isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
                found.extend(_arguments_for(facts, function, binding))
            continue
        node: ast.AST | None = binding
        while node is not None and not isinstance(node, (ast.stmt, ast.comprehension)):
            node = facts.parent(node)
        if isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign)) and node.value is not None:
            found.append(node.value)
        elif isinstance(node, (ast.For, ast.AsyncFor, ast.comprehension)):
            found.append(node.iter)
    return found


def _arguments_for(facts: ModuleFacts, function: ast.FunctionDef | ast.AsyncFunctionDef, param: ast.arg) -> list[ast.AST]:
    positional = [*function.args.posonlyargs, *function.args.args]
    index = positional.index(param) if param in positional else None
    found: list[ast.AST] = []
    for caller in _calls_of(facts, function):
        found.extend(kw.value for kw in caller.keywords if kw.arg == param.arg)
        if index is not None and index < len(caller.args):
            found.append(caller.args[index])
    return found


def _calls_of(facts: ModuleFacts, function: ast.FunctionDef | ast.AsyncFunctionDef) -> list[ast.Call]:
    """The module's calls of a module-level function by its name."""
    if facts.enclosing(function, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) is not None:
        return []
    return [
        node
        for node in walk(facts.tree)
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == function.name
    ]
