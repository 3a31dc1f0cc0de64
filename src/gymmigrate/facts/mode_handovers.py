"""A frame mode asked in one module of an env made in another (GM401 across modules).

``env = gym.make(id)`` then ``Player(env)`` (main.py), where ``Player`` (player.py) stores
the env and calls ``self.env.render(mode="rgb_array")``: Gymnasium fixes the mode when the
env is made, so ``render_mode="rgb_array"`` belongs at that make and the call becomes
``render()``. Neither module sees both: each records its side, and the join pairs them.

The rendering side (``param_renders``): per parameter of a top-level def, or per
constructor parameter a plain class holds in ``self.x``, the one literal frame mode its
renders ask (``""`` for an env never rendered there), when the env goes nowhere else (only
its attributes are read: no render elsewhere can ask another mode). The making side
(``handed_make``, kept on each ``CallSummary``): an argument made right there by
``gym.make`` with no ``render_mode``, the env reaching nothing in that module but calls
into other modules of the run (an instance built on it only the owner of method calls,
whose attribute cannot hand it on). The join
(``join``) gives the make the mode where every call it is handed to settles one mode, and
settles a parameter where every call of its def passes such a make.

Human renders are not moved: a human-mode env draws inside every step, which legacy code
did not always do (``rules/render_schedule.py`` decides that where the make is in reach).
"""

from __future__ import annotations

import ast
from collections import defaultdict
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

from gymmigrate.facts import names as N
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts, Scope, keyword, string_value

if TYPE_CHECKING:
    from gymmigrate.facts.module_summary import CallSummary, HandedMake, ModuleSummary
    from gymmigrate.facts.project import ProjectFacts
    from gymmigrate.facts.receivers import Receivers

# Modes that only return what they draw: moving them to the make changes nothing else.
_NOT_MOVED = frozenset({"human", "single_rgb_array"})
# Attributes whose value is the env itself (or its base): a read of one hands the env on.
_SAME_ENV = frozenset({"render", "env", "unwrapped"})


def rendered_param(facts: ModuleFacts, receivers: Receivers, receiver: ast.expr) -> tuple[str, str] | None:
    """(qualname, parameter) whose argument ``receiver`` is: a parameter of a top-level def
    read as its only binding, or ``self.x`` of a top-level plain class that stores it only
    from a parameter of its ``__init__`` and that no class of the module derives from (its
    constructions are the calls the run sees). None otherwise."""
    if isinstance(receiver, ast.Name):
        bindings = facts.bindings_of(receiver)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.arg):
            return None
        function = facts.parent(facts.parent(bindings[0]))
        if not isinstance(function, FUNCTIONS) or facts.functions.get(function.name) is not function:
            return None
        return function.name, bindings[0].arg
    if not (isinstance(receiver, ast.Attribute) and isinstance(receiver.value, ast.Name) and receivers.is_self(receiver.value)):
        return None
    classdef = facts.enclosing_class(receiver)
    if classdef is None or facts.classes.get(classdef.name) is not classdef:
        return None
    param = _held_param(facts, receivers, classdef, receiver.attr)
    return None if param is None else (f"{classdef.name}.__init__", param)


def _held_param(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef, attribute: str) -> str | None:
    init = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "__init__"), None)
    values = receivers.self_stores(classdef).get(attribute, [])
    if init is None or len(values) != 1 or not isinstance(values[0], ast.Name) or facts.enclosing_function(values[0]) is not init:
        return None
    bindings = facts.bindings_of(values[0])
    if len(bindings) != 1 or not isinstance(bindings[0], ast.arg) or bindings[0] not in init.args.args[1:]:
        return None
    if any(receivers.local_class(base) is classdef for other in facts.all_classes for base in other.bases):
        return None
    return bindings[0].arg


def param_renders(facts: ModuleFacts, receivers: Receivers) -> tuple[tuple[str, str, str], ...]:
    """``ModuleSummary.param_renders``: (qualname, parameter, mode) for each parameter of a
    top-level def, and each ``__init__`` parameter a top-level plain class holds, whose env
    is only read for its attributes (here: in the def, or as ``self.x`` in the class), its
    renders all asking one literal frame mode (``""``: never rendered)."""
    found: list[tuple[str, str, str]] = []
    for name, function in facts.functions.items():
        for arg in (*function.args.posonlyargs, *function.args.args):
            reads = _reads_of_param(facts, function, arg)
            if any(facts.bindings_of(read) != [arg] for read in reads):
                continue  # rebound somewhere: another object under the same name
            mode = _only_rendered_in(facts, reads)
            if mode is not None:
                found.append((name, arg.arg, mode))
    for name, classdef in facts.classes.items():
        if receivers.class_kind(classdef) is not EnvKind.NOT_ENV:
            continue  # an env or a wrapper: its ``self.env`` is not a held argument
        for attribute in receivers.self_stores(classdef):
            param = _held_param(facts, receivers, classdef, attribute)
            if param is None:
                continue
            init = next(s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "__init__")
            arg = next(a for a in init.args.args if a.arg == param)
            stored = receivers.self_stores(classdef)[attribute][0]
            if any(read is not stored and not _attribute_owner(facts, read) for read in _reads_of_param(facts, init, arg)):
                continue  # the argument itself goes somewhere else too
            if _hands_self_on(facts, classdef):
                break  # what the instance holds may be rendered wherever it goes
            # every ``x.<attribute>`` read of the module (an instance's ``player.env`` too, a
            # closure's ``self.env``) but another class's own ``self.<attribute>``
            held_reads = [
                a
                for a in facts.attributes.get(attribute, ())
                if isinstance(a.value, ast.Name)
                and not isinstance(a.ctx, ast.Store)
                and not (receivers.is_self(a.value) and facts.enclosing_class(a) is not classdef)
            ]
            mode = _only_rendered_in(facts, held_reads)
            if mode is not None:
                found.append((f"{name}.__init__", param, mode))
    return tuple(found)


def _hands_self_on(facts: ModuleFacts, classdef: ast.ClassDef) -> bool:
    """A method of the class reads its ``self`` as anything but the owner of an attribute
    (``register(self)``, ``return self``), ``super()`` aside."""
    for method in classdef.body:
        if not isinstance(method, FUNCTIONS) or not method.args.args:
            continue
        if any(isinstance(d, ast.Name) and d.id in ("staticmethod", "classmethod") for d in method.decorator_list):
            continue  # its first parameter is no instance
        first = method.args.args[0]
        if any(not isinstance(facts.parent(read), ast.Attribute) for read in _reads_of_param(facts, method, first)):
            return True
    return False


def _reads_of_param(facts: ModuleFacts, function: ast.FunctionDef | ast.AsyncFunctionDef, arg: ast.arg) -> list[ast.Name]:
    """The reads of ``arg`` that may see it: in the scope of ``function`` and the scopes
    nested in it (closures), never elsewhere, so a module with many defs of one parameter
    name is not read once per def."""
    children: dict[int, list[Scope]] = facts.memo(("child-scopes", 0), lambda: _child_scopes(facts))
    found: list[ast.Name] = []
    todo = [facts.scopes[function]] if function in facts.scopes else []
    while todo:
        scope = todo.pop()
        found += [read for read in scope.reads.get(arg.arg, ()) if arg in facts.bindings_of(read)]
        todo += children.get(id(scope), ())
    return found


def _child_scopes(facts: ModuleFacts) -> dict[int, list[Scope]]:
    children: dict[int, list[Scope]] = defaultdict(list)
    for scope in facts.scopes.values():
        if scope.parent is not None:
            children[id(scope.parent)].append(scope)
    return children


def _attribute_owner(facts: ModuleFacts, read: ast.expr) -> bool:
    parent = facts.parent(read)
    return isinstance(parent, ast.Attribute) and parent.value is read and parent.attr not in _SAME_ENV


def _only_rendered_in(facts: ModuleFacts, reads: Sequence[ast.expr]) -> str | None:
    """The one literal mode the renders among ``reads`` ask, ``""`` for none; None when a
    read hands the env on, or a render asks no literal frame mode, or two ask different ones."""
    modes: set[str] = set()
    for read in reads:
        parent = facts.parent(read)
        if not (isinstance(parent, ast.Attribute) and parent.value is read):
            return None
        if parent.attr in ("env", "unwrapped"):
            return None
        if parent.attr != "render":
            continue
        call = facts.parent(parent)
        if not (isinstance(call, ast.Call) and call.func is parent):
            return None  # ``env.render`` fetched and called elsewhere
        mode = render_mode_literal(call)
        if mode is None or mode in _NOT_MOVED:
            return None
        modes.add(mode)
    if len(modes) > 1:
        return None
    return modes.pop() if modes else ""


def render_mode_literal(call: ast.Call) -> str | None:
    """The literal mode ``render(mode="x")`` / ``render("x")`` passes, when that is all it passes."""
    given = [*call.args, *(k.value for k in call.keywords)]
    if len(given) != 1 or (call.keywords and call.keywords[0].arg != "mode") or isinstance(given[0], ast.Starred):
        return None
    return string_value(given[0]) if isinstance(given[0], ast.Constant) else None


def handed_make(
    facts: ModuleFacts, argument: ast.expr, call: ast.Call, is_run_call: Callable[[ast.Call], bool]
) -> tuple[int, int, str | None, int, str, bool] | None:
    """``Player(env)`` with ``env = gym.make(id)`` (bound once, or the make itself as the
    argument): (the make's line, column, its id when a literal, how many calls of the run
    this module hands the env to, the name when bound at module level, whether what ``call``
    gives is only the owner of method calls: ``player = Player(env)``, ``player.evaluate()``),
    when the make gives no ``render_mode`` (nor ``**``), and the env reaches nothing here but
    attribute reads other than itself (``env.observation_space``, ``env.reset()``) and calls
    of the run (``is_run_call``): no render or recorder of this module can ask the make a
    mode. None otherwise."""
    reads: Sequence[ast.expr] = [argument]
    binding: ast.AST | None = None
    if isinstance(argument, ast.Call):
        make, name = argument, ""
    elif isinstance(argument, ast.Name):
        bindings = facts.bindings_of(argument)
        statement = facts.parent(bindings[0]) if len(bindings) == 1 else None
        if not (isinstance(statement, ast.Assign) and statement.targets == bindings and isinstance(statement.value, ast.Call)):
            return None
        make, binding = statement.value, bindings[0]
        name = argument.id if facts.enclosing_function(statement) is None else ""
    else:
        return None
    if not any(N.strip_gym_prefix(q) in N.GYM_ENV_FACTORIES for q in facts.qualified_names(make.func)):
        return None
    if keyword(make, "render_mode") is not None or any(k.arg is None for k in make.keywords) or any(isinstance(a, ast.Starred) for a in make.args):
        return None
    if isinstance(argument, ast.Name):
        reads = facts.reads_of(argument.id, binding)
    handings = 0
    for read in reads:
        parent = facts.parent(read)
        if isinstance(parent, ast.Attribute) and parent.value is read and parent.attr not in _SAME_ENV:
            continue
        if isinstance(parent, ast.keyword):
            parent = facts.parent(parent)
        if not (isinstance(parent, ast.Call) and parent.func is not read and is_run_call(parent)):
            return None
        handings += 1
    env_id = make.args[0] if make.args else None
    literal = string_value(env_id) if isinstance(env_id, ast.Constant) else None
    if literal is None and (facts.calls_by_name.get("register") or facts.attribute_calls.get("register")):
        return None  # a class this module registers may be what the make builds
    return make.lineno, make.col_offset, literal, handings, name, _result_only_called(facts, call)


def _result_only_called(facts: ModuleFacts, call: ast.Call) -> bool:
    """What ``call`` gives is dropped, or only the owner of method calls other than render
    (``Play(env).evaluate()``, ``player = Play(env)`` then ``player.evaluate()``)."""
    parent = facts.parent(call)
    if isinstance(parent, ast.Expr):
        return True
    if isinstance(parent, ast.Attribute):
        return _method_owner(facts, call)
    if not (isinstance(parent, ast.Assign) and len(parent.targets) == 1 and isinstance(parent.targets[0], ast.Name)):
        return False
    target = parent.targets[0]
    return all(_method_owner(facts, read) for read in facts.reads_of(target.id, target))


def _method_owner(facts: ModuleFacts, node: ast.expr) -> bool:
    attribute = facts.parent(node)
    called = facts.parent(attribute)
    return (
        isinstance(attribute, ast.Attribute)
        and attribute.value is node
        and attribute.attr != "render"
        and isinstance(called, ast.Call)
        and called.func is attribute
    )


def join(
    facts: ProjectFacts,
    by_path: dict[str, ModuleSummary],
    calls_to: dict[tuple[str, str], list[tuple[str, CallSummary]]],
    subclassed: set[tuple[str, str]],
) -> None:
    """``facts.handed_render_modes``: (path, line, column) of each make that gets a mode for
    the renders of the calls it is handed to; ``facts.settled_mode_renders``: (path, def,
    parameter) -> (mode, the makes) where every call of the def passes such a make."""
    profiles = {
        (path, qualname, param): mode
        for path, summary in by_path.items()
        if path not in facts.blocked
        for qualname, param, mode in summary.param_renders
        if not (qualname.endswith(".__init__") and (path, qualname.split(".", 1)[0]) in subclassed)
    }
    imported = {q for summary in by_path.values() for q in summary.imported}
    handed: dict[tuple[str, int, int], list[str | None]] = defaultdict(list)  # make -> each handing's mode
    expected: dict[tuple[str, int, int], HandedMake] = {}
    fed: dict[tuple[str, str, str], list[tuple[str, int, int] | None]] = defaultdict(list)  # key -> each call's make
    for (path, qualname), calls in calls_to.items():
        signature = by_path[path].defs[qualname]
        params = list(signature.params[1:] if signature.is_method else signature.params)
        for caller, call in calls:
            made = {entry[0]: entry for entry in call.made}
            given = dict(call.keywords)
            for index, param in enumerate(params):
                key = (path, qualname, param)
                slot = str(index) if index < len(call.args) else param if param in given else None
                entry = made.get(slot) if slot is not None and caller != path else None
                if entry is not None:
                    where = (caller, entry[1], entry[2])
                    expected[where] = entry
                    # an instance holding the env hands it on through its attribute unless it
                    # is only the owner of method calls; a def's result cannot be the env
                    # (its profile reads only the env's attributes)
                    held = qualname.endswith(".__init__")
                    handed[where].append(profiles.get(key) if entry[6] or not held else None)
                if key in profiles:
                    fed[key].append((caller, entry[1], entry[2]) if entry is not None else None)
    candidates: dict[tuple[str, int, int], str] = {}
    for where, modes in handed.items():
        caller = where[0]
        _, _, _, env_id, count, name, _ = expected[where]
        if caller in facts.blocked or len(modes) != count or None in modes:
            continue
        asked = {mode for mode in modes if mode}
        if len(asked) != 1 or _taken_elsewhere(facts, by_path, caller, name, imported) or _no_render_mode(facts, caller, env_id):
            continue
        candidates[where] = asked.pop()
    while True:
        settled = {
            key: makes
            for key, makes in fed.items()
            if profiles[key] and all(m is not None and candidates.get(m) == profiles[key] for m in makes)
        }
        kept = {
            where: mode
            for where, mode in candidates.items()
            if all(key in settled for key, makes in fed.items() if profiles[key] and where in makes)
        }
        if kept == candidates:
            break
        candidates = kept
    facts.handed_render_modes = candidates
    facts.settled_mode_renders = {key: (profiles[key], tuple(m for m in makes if m is not None)) for key, makes in settled.items()}


def _taken_elsewhere(facts: ProjectFacts, by_path: dict[str, ModuleSummary], path: str, name: str, imported: set[str]) -> bool:
    """A module-level name another module of the run may import (and render)."""
    if not name:
        return False
    return any(f"{module}.{name}" in imported for module, where in facts.modules.items() if where == path)


def _no_render_mode(facts: ProjectFacts, path: str, env_id: str | None) -> bool:
    """The make may build a class of the run that takes no ``render_mode`` (registered
    without it, or behind a registry of data the run cannot read)."""
    ids = facts.no_render_mode_ids
    return (ids.get(env_id) if env_id is not None else bool(ids)) or path in facts.opaque_kept_renders  # type: ignore[return-value]
