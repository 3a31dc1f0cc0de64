"""An env made with a run class's constructor in one module and rendered in another
(GM402 across modules).

``env = Game(rom)`` then ``play(env)`` (cli.py), where ``def play(env)`` (play.py) calls
``env.render()`` bare: legacy gym drew that render in "human" mode; Gymnasium draws only
when the env is made with a ``render_mode``. The render's module cannot reach the
constructor, and the constructor's module does not see the render. Each module records
its side: the parameters a def renders bare and hands nowhere (``bare_render_params``),
and the calls that pass an env built right there by an imported class
(``handed_constructions``). The join (``join``) pairs them: where every call of such a
def passes an env built that way by a class whose migrated ``__init__`` takes
``render_mode``, that constructor gets ``render_mode="human"`` and the render is settled.
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.facts import names as N
from gymmigrate.facts.module import ModuleFacts, walk

if TYPE_CHECKING:
    from gymmigrate.facts.module_summary import CallSummary, ModuleSummary
    from gymmigrate.facts.project import ProjectFacts

# (call line, the argument's slot: its position as a string or its keyword, the class's
# qualified name, the construction's line and column)
Handed = tuple[int, str, str, int, int]


def bare_render_params(facts: ModuleFacts) -> frozenset[tuple[str, str]]:
    """(def, parameter) of the module's top-level defs whose parameter is rendered bare
    (``env.render()``, in no ``if``) at least once and otherwise only has attributes read
    (``env.reset()``, ``env.action_space``): no render of it elsewhere, no other mode."""
    found: set[tuple[str, str]] = set()
    for function in facts.tree.body:
        if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        params = [a.arg for a in (*function.args.posonlyargs, *function.args.args, *function.args.kwonlyargs)]
        for param in params:
            if _rendered_bare_only(facts, function, param):
                found.add((function.name, param))
    return frozenset(found)


def _rendered_bare_only(facts: ModuleFacts, function: ast.FunctionDef | ast.AsyncFunctionDef, param: str) -> bool:
    renders = 0
    for node in walk(function):
        if not (isinstance(node, ast.Name) and node.id == param):
            continue
        if not isinstance(node.ctx, ast.Load):
            return False  # rebound: another value may be rendered under the same name
        if facts.enclosing_function(node) is not function:
            return False  # read in a nested def or lambda
        holder = facts.parent(node)
        if not (isinstance(holder, ast.Attribute) and holder.value is node):
            return False  # handed on (``run(env)``, ``self.env = env``): rendered elsewhere maybe
        if holder.attr != "render":
            continue
        call = facts.parent(holder)
        if not (isinstance(call, ast.Call) and call.func is holder and not call.args and not call.keywords):
            return False  # a render with a mode, or ``env.render`` passed on
        if _under_if(facts, call, function):
            return False  # a render under a flag: its mode depends on that flag
        renders += 1
    return renders > 0


def _under_if(facts: ModuleFacts, node: ast.AST, function: ast.AST) -> bool:
    current = facts.parent(node)
    while current is not None and current is not function:
        if isinstance(current, (ast.If, ast.IfExp, ast.BoolOp)):
            return True
        current = facts.parent(current)
    return False


def handed_constructions(facts: ModuleFacts, calls: tuple[CallSummary, ...]) -> tuple[Handed, ...]:
    """The calls (of ``calls``: those the summary records) that pass a name bound once, in
    their def, to ``C(...)`` of an imported class, with no ``render_mode`` or ``**`` given,
    the name read nowhere else but for attributes other than ``render``."""
    lines = {call.line for call in calls}
    found: list[Handed] = []
    for node in walk(facts.tree):
        if not (isinstance(node, ast.Call) and node.lineno in lines):
            continue
        slots: list[tuple[str, ast.expr]] = []
        for index, argument in enumerate(node.args):
            if isinstance(argument, ast.Starred):
                break  # later positions are unknown
            slots.append((str(index), argument))
        slots += [(k.arg, k.value) for k in node.keywords if k.arg is not None]
        for slot, value in slots:
            made = _construction(facts, value, node)
            if made is not None:
                qualified, construction = made
                found.append((node.lineno, slot, qualified, construction.lineno, construction.col_offset))
    return tuple(found)


def _construction(facts: ModuleFacts, value: ast.expr, call: ast.Call) -> tuple[str, ast.Call] | None:
    if not isinstance(value, ast.Name):
        return None
    function = facts.enclosing_function(call)
    if function is None:
        return None
    bindings = facts.bindings_of(value)
    if len(bindings) != 1 or not isinstance(bindings[0], ast.Name):
        return None
    statement = facts.parent(bindings[0])
    if not (isinstance(statement, ast.Assign) and len(statement.targets) == 1 and statement.targets[0] is bindings[0]):
        return None
    made = statement.value
    if not isinstance(made, ast.Call) or facts.enclosing_function(statement) is not function:
        return None
    if any(k.arg is None or k.arg == "render_mode" for k in made.keywords) or any(isinstance(a, ast.Starred) for a in made.args):
        return None
    names = [q for q in facts.qualified_names(made.func) if not N.is_library(q)]
    if len(names) != 1:
        return None
    for node in walk(function):
        if isinstance(node, ast.Name) and node.id == value.id and isinstance(node.ctx, ast.Load) and node is not value:
            holder = facts.parent(node)
            if not (isinstance(holder, ast.Attribute) and holder.attr != "render"):
                return None  # handed elsewhere too, or rendered here: decided here or there
    return names[0], made


def join(facts: ProjectFacts, by_path: dict[str, ModuleSummary], calls_to: dict[tuple[str, str], list[tuple[str, CallSummary]]]) -> None:
    """``facts.render_mode_constructions``: (path, line, column) of each constructor that
    gets ``render_mode="human"``; ``facts.settled_renders``: (path, def, parameter) -> the
    places (``cli.py:5``) whose constructors give it, for every call of the def."""
    for key, callers in facts.gym_env_callers.items():
        path, qualname, param = key
        summary = by_path.get(path)
        if summary is None or (qualname, param) not in summary.bare_render_params or path in facts.blocked:
            continue
        calls = calls_to.get((path, qualname), [])
        if any(caller == path for caller, _ in calls) or len(calls) != len(callers):
            continue  # called in its own module too, or with something else than a Gym env
        signature = summary.defs[qualname]
        slots = {param}
        if param in signature.params:
            slots.add(str(signature.params.index(param)))
        places: list[tuple[str, int, int]] = []
        for caller, line in callers:
            if caller in facts.blocked:
                break
            found = [
                (caller, made_line, column)
                for call_line, slot, qualified, made_line, column in by_path[caller].handed_constructions
                if call_line == line and slot in slots and _takes_render_mode(facts, qualified, caller)
            ]
            if len(found) != 1:
                break
            places.append(found[0])
        else:
            facts.render_mode_constructions.update(places)
            facts.settled_renders[key] = tuple(places)


def _takes_render_mode(facts: ProjectFacts, qualified: str, importer: str) -> bool:
    split = facts._split(qualified, importer)
    return split is not None and split[1] in facts.render_mode_classes.get(split[0], ())
