"""What a module's top-level defs and names tell the run: each def's signature, the defs
that mask bootstrapping with a flag parameter, the defs that return a ``make(...)``
result, the imported names of the run it hands on uncalled, and its ``register`` calls."""

from __future__ import annotations

import ast
import re
from collections.abc import Mapping

from gymmigrate.facts import names as N
from gymmigrate.facts.bootstrap import next_state_masks
from gymmigrate.facts.module import (
    FUNCTIONS,
    ModuleFacts,
    call_argument,
    own_entry_point,
    own_returns,
    string_value,
    walk,
)
from gymmigrate.facts.module_summary import Signature
from gymmigrate.facts.receivers import Receivers


def signature(function: ast.FunctionDef | ast.AsyncFunctionDef, is_method: bool) -> Signature:
    args = function.args
    positional = [*args.posonlyargs, *args.args]
    with_default = positional[len(positional) - len(args.defaults) :]
    defaults = {a.arg for a in with_default}
    defaults |= {a.arg for a, d in zip(args.kwonlyargs, args.kw_defaults) if d is not None}
    params = tuple(a.arg for a in (*positional, *args.kwonlyargs))
    return Signature(params, frozenset(defaults), is_method)


def bootstrap_masks(facts: ModuleFacts) -> dict[str, frozenset[tuple[str, str]]]:
    """Top-level defs and methods of top-level classes whose flag parameter masks
    bootstrapping from a next-state parameter (``facts/bootstrap.py``)."""
    return masks_of(facts.functions, facts.classes)


def masks_of(
    functions: Mapping[str, ast.FunctionDef | ast.AsyncFunctionDef], classes: Mapping[str, ast.ClassDef]
) -> dict[str, frozenset[tuple[str, str]]]:
    found: dict[str, frozenset[tuple[str, str]]] = {}
    defs = list(functions.items())
    defs += [
        (f"{name}.{statement.name}", statement)
        for name, classdef in classes.items()
        for statement in classdef.body
        if isinstance(statement, FUNCTIONS)
    ]
    for qualname, function in defs:
        masks = next_state_masks(function)
        if masks:
            found[qualname] = masks
    return found


def made_factories(facts: ModuleFacts, receivers: Receivers | None = None) -> frozenset[str]:
    """Top-level defs every return of which is a ``make(...)`` result, maybe wrapped in Gym
    wrappers and kept in a local name first (``env = gym.make(key); env.seed(s); return env``);
    with ``receivers``, the module's own Gym wrapper classes around a made env count as Gym
    wrappers too (``env = FireReset(env)``)."""
    found = set()
    for name, function in facts.functions.items():
        values = [r.value for r in own_returns(function)]
        if values and all(v is not None and _made(facts, v, function, 0, receivers) for v in values):
            found.add(name)
    return frozenset(found)


def made_thunks(facts: ModuleFacts, receivers: Receivers) -> dict[str, tuple[int, int] | None]:
    """Top-level defs that return a thunk of their own on every path, whole (None) or as
    one item of a tuple (``return create_env, env_name``: (index, size)), every return of
    which is a ``make(...)`` result, as ``made_factories`` reads one
    (``ModuleSummary.made_thunks``). A thunk returning anything else (the project's own
    object, a call of another module) gives none."""
    found: dict[str, tuple[int, int] | None] = {}
    for name, function in facts.functions.items():
        item = receivers.thunk_item(function)
        thunks = [r.value for r in own_returns(function)] if item is None else receivers.returned_items(function, *item)
        if not thunks or any(t is None for t in thunks):
            continue
        returned: list[ast.expr] = []
        for thunk in thunks:
            values = receivers.thunk_returns(thunk)  # type: ignore[arg-type]
            if not values or any(not isinstance(v, ast.expr) for v in values):
                returned = []
                break
            returned += values  # type: ignore[arg-type]
        if returned and all(_made(facts, v, facts.enclosing_function(v) or v, 0, receivers) for v in returned):
            found[name] = item
    return found


def made_value(facts: ModuleFacts, value: ast.expr, function: ast.AST, receivers: Receivers | None = None) -> bool:
    """``value``, returned by ``function`` (a def or a lambda), is a ``make(...)`` result,
    maybe wrapped in Gym wrappers (as ``made_factories``)."""
    return _made(facts, value, function, 0, receivers)


def _made(facts: ModuleFacts, value: ast.expr, function: ast.AST, depth: int, receivers: Receivers | None = None) -> bool:
    if depth > 8:
        return False
    if isinstance(value, ast.Call):
        for q in facts.qualified_names(value.func):
            rest = N.strip_gym_prefix(q)
            if rest in N.GYM_ENV_FACTORIES:
                return True
        if _is_gym_wrapper(facts, value.func, receivers) and value.args:
            return _made(facts, value.args[0], function, depth + 1, receivers)  # a wrapper around a made env
        return False
    if not isinstance(value, ast.Name):
        return False
    bindings = facts.bindings_of(value)
    if not bindings:
        return False
    for binding in bindings:
        assign = facts.parent(binding) if isinstance(binding, ast.Name) else None
        if not (isinstance(assign, ast.Assign) and assign.targets == [binding]) or facts.enclosing_function(assign) is not function:
            return False
        wrapped = assign.value.args[0] if isinstance(assign.value, ast.Call) and assign.value.args else None
        if isinstance(wrapped, ast.Name) and wrapped.id == value.id and _is_gym_wrapper(facts, assign.value.func, receivers):  # type: ignore[attr-defined]
            continue  # ``env = TimeLimit(env)``: as made as the env's other values
        if not _made(facts, assign.value, function, depth + 1, receivers):
            return False
    return True


def _is_gym_wrapper(facts: ModuleFacts, func: ast.expr, receivers: Receivers | None = None) -> bool:
    if receivers is not None:
        local = receivers.local_class(func)
        if local is not None:
            return receivers.is_gym_wrapper_class(local)
    for q in facts.qualified_names(func):
        rest = N.strip_gym_prefix(q)
        if rest is not None and rest.startswith("wrappers.") and not rest.startswith("wrappers.vector."):
            return True
    return False


def handed_on(facts: ModuleFacts) -> frozenset[str]:
    """``ModuleSummary.handed_on``: imported names of the run (``make_env``, ``wrappers.make_env``)
    read anywhere in the module other than as the callee of a call."""
    imported = {}
    for name, bindings in facts.module_scope.bindings.items():
        if len(bindings) == 1 and isinstance(bindings[0], ast.alias):
            qualified = facts.imports.get(bindings[0])
            if qualified is not None and not N.is_library(qualified):
                imported[name] = qualified
    found = set()
    for scope in facts.scopes.values() if imported else ():
        for name in imported.keys() & scope.reads.keys():
            qualified = imported[name]
            for read in scope.reads[name]:
                node: ast.AST = read
                parent = facts.parent(read)
                shown = qualified
                if isinstance(parent, ast.Attribute) and parent.value is read:
                    node, shown = parent, f"{qualified}.{parent.attr}"
                    parent = facts.parent(parent)
                if not (isinstance(parent, ast.Call) and parent.func is node):
                    found.add(shown)
    return frozenset(found)


# What loading an earlier run's policy, weights or normaliser looks like: the called name.
_LOADS_SAVED_STATE = frozenset({"load_state_dict", "load_weights", "load_model", "from_pretrained", "restore", "load_from_checkpoint"})


def loads_saved_state(tree: ast.AST) -> bool:
    """Does the program load what an earlier run saved? Calls only: a commented-out
    ``torch.load`` (a notebook's old cell) or one quoted in a docstring loads nothing.
    tf_agents' ``suite_gym.load("CartPole-v1")`` (``suite_atari``, ``suite_mujoco``...)
    makes an env: it loads nothing either."""
    for node in walk(tree):
        if not isinstance(node, ast.Call):
            continue
        func = node.func
        name = func.attr if isinstance(func, ast.Attribute) else func.id if isinstance(func, ast.Name) else ""
        if name in _LOADS_SAVED_STATE:
            return True
        if isinstance(func, ast.Attribute) and name == "load":
            owner = func.value
            owner_name = owner.attr if isinstance(owner, ast.Attribute) else owner.id if isinstance(owner, ast.Name) else ""
            if not owner_name.startswith("suite_"):
                return True
    return False


# Modules whose own ``load`` reads a saved model (a plain ``import`` binding them)
_MODEL_LOADING_MODULES = frozenset({"torch", "joblib", "keras", "tensorflow", "tf"})


def loads_model_for_the_run(tree: ast.AST) -> bool:
    """A load another module's env ids may answer to: an ML library's or an object's load
    (``torch.load``, ``PPO.load``, ``solution.load``, ``load_state_dict``). A plain module's
    data reader (``pickle.load`` of a map, ``pyglet.image.load``, ``json.load``) is the
    module's own business: only a program that makes the id itself is asked for it
    (``loads_saved_state``)."""
    modules = {
        (alias.asname or alias.name).split(".")[0]
        for node in walk(tree)
        if isinstance(node, ast.Import)
        for alias in node.names
        if (alias.asname or alias.name).split(".")[0] not in _MODEL_LOADING_MODULES
    }
    for node in walk(tree):
        if not (isinstance(node, ast.Call) and isinstance(node.func, (ast.Attribute, ast.Name))):
            continue
        func = node.func
        name = func.attr if isinstance(func, ast.Attribute) else func.id
        if name in _LOADS_SAVED_STATE:
            return True
        if isinstance(func, ast.Attribute) and name == "load":
            root = func.value
            while isinstance(root, ast.Attribute):
                root = root.value
            if not (isinstance(root, ast.Name) and (root.id in modules or root.id.startswith("suite_"))):
                return True
    return False


def registrations(facts: ModuleFacts) -> tuple[tuple[str | None, str], ...]:
    """``register(id=..., entry_point="pkg.mod:Class")`` calls: (the id if a literal, the entry point)."""
    found = []
    for call in (*facts.calls_by_name.get("register", ()), *facts.attribute_calls.get("register", ())):
        entry = call_argument(call, 1, "entry_point")
        text = string_value(entry) if entry is not None else own_entry_point(entry)
        if text is None or ":" not in text:
            continue
        env_id = call_argument(call, 0, "id")
        found.append((string_value(env_id) if env_id is not None else None, text))
    return tuple(found)


# gym's and Gymnasium's registry functions (after the package name)
_REGISTER = frozenset({"register", "envs.register", "envs.registration.register"})


def registered_ids(facts: ModuleFacts) -> tuple[str | None, ...]:
    """The ids of the module's Gym ``register(id=..., ...)`` calls (None: not a literal),
    whatever their entry point (a string, the class itself, one read from data)."""
    found = []
    for call in (*facts.calls_by_name.get("register", ()), *facts.attribute_calls.get("register", ())):
        gym_register = any(N.strip_gym_prefix(q) in _REGISTER for q in facts.qualified_names(call.func))
        if not gym_register and call_argument(call, 1, "entry_point") is None:
            continue  # ``atexit.register(f)``: not the registry
        env_id = call_argument(call, 0, "id")
        found.append(string_value(env_id) if env_id is not None else None)
    return tuple(found)


_ID_SHAPE = re.compile(r"^(?:[\w.]+:)?[\w./-]+-v\d+$")
_MAKE = frozenset({"make", "envs.make", "envs.registration.make", "make_vec"})


def named_ids(facts: ModuleFacts) -> tuple[frozenset[str], bool]:
    """(the env-id-shaped strings of the module other than the ids its own ``register()``
    calls pass, without a ``pkg:`` prefix; whether a Gym ``make(...)`` of the module passes
    an id that is no string literal): what the run may make, for GM511."""
    registered = {
        id(argument)
        for call in (*facts.calls_by_name.get("register", ()), *facts.attribute_calls.get("register", ()))
        if (argument := call_argument(call, 0, "id")) is not None
    }
    named = frozenset(
        node.value.rsplit(":", 1)[-1]
        for node in facts.strings
        if isinstance(node.value, str) and id(node) not in registered and _ID_SHAPE.match(node.value)
    )
    opaque = False
    for call in (*facts.calls_by_name.get("make", ()), *facts.attribute_calls.get("make", ()), *facts.attribute_calls.get("make_vec", ())):
        if not any(N.strip_gym_prefix(q) in _MAKE for q in facts.qualified_names(call.func)):
            continue
        argument = call_argument(call, 0, "id")
        if argument is None or string_value(argument) is None:
            opaque = True
    return named, opaque


def gym_only_makers(facts: ModuleFacts, receivers: Receivers) -> dict[str, str]:
    """Top-level defs that return envs of a Gym-only stack (``ModuleSummary.gym_only_makers``);
    only a module that imports such a library can define one."""
    if not any(q.split(".", 1)[0] in N.GYM_ONLY_PACKAGES for q in facts.imports.values()):
        return {}
    found = {}
    for name, function in facts.functions.items():
        stack = receivers.returns_gym_only_stack(function)
        if stack is not None:
            found[name] = stack
    return found


def opaque_registrations(facts: ModuleFacts) -> bool:
    """A Gym ``register(id=..., entry_point=...)`` call whose entry point is no literal
    (``entry_point=env["entry_point"]`` from a JSON file)."""
    for call in (*facts.calls_by_name.get("register", ()), *facts.attribute_calls.get("register", ())):
        if not any(q in ("gym.register", "gym.envs.register", "gym.envs.registration.register") for q in facts.qualified_names(call.func)):
            continue
        entry = call_argument(call, 1, "entry_point")
        if entry is not None and string_value(entry) is None and not isinstance(entry, (ast.Name, ast.Attribute)):
            return True
    return False
