"""What a class's body alone shows about its instances' contract, with no receiver to
resolve: a step that keeps the legacy four fields (``keeps_legacy_step``), a batched
return of per-env flags (``is_batched_step_return``, ``per_agent_receivers``), a reset
that returns bare observations (``keeps_bare_reset``), a VecEnv-shaped class
(``is_vec_env_shaped``), a method that touches ``self.env`` (``touches_self_env``), a
render() that draws nothing (``renders_nothing``) and the
methods that draw the wrapped env (``wrapped_env_renders``).

Separate from ``receiver_classes.py`` because these are plain functions of a class's
statements (and, for rendering, of the module's facts): they ask ``Receivers`` nothing, so
rules and the run's summaries use them without one, and ``ClassKinds`` builds on them.
"""

from __future__ import annotations

import ast

from gymmigrate.facts.module import FUNCTIONS, ModuleFacts, own_returns, walk


def touches_self_env(classdef: ast.ClassDef) -> bool:
    """Some method of the class reads or sets ``self.env``: the slot a Gym wrapper layer
    keeps its inner env in."""
    return any(
        isinstance(node, ast.Attribute) and node.attr == "env" and isinstance(node.value, ast.Name) and node.value.id == "self"
        for statement in classdef.body
        if isinstance(statement, FUNCTIONS)
        for node in walk(statement)
    )


def keeps_bare_reset(classdef: ast.ClassDef) -> bool:
    """The class defines ``reset`` and one of its returns is a bare value: not a tuple,
    not ``None``, not another env's ``reset(...)`` passed through."""
    for statement in classdef.body:
        if isinstance(statement, FUNCTIONS) and statement.name == "reset":
            for ret in own_returns(statement):
                value = ret.value
                if value is None or isinstance(value, ast.Tuple) or (isinstance(value, ast.Constant) and value.value is None):
                    continue
                if isinstance(value, ast.Call) and isinstance(value.func, ast.Attribute) and value.func.attr == "reset":
                    continue
                return True
    return False


def keeps_legacy_step(classdef: ast.ClassDef) -> bool:
    """The class's own ``step`` returns what no rule migrates: every value it returns is a
    name, a container built in the method, or a call of a plain function (``return
    results`` with ``results = zip(*per_env)``: a batch; GM504 reports it, changes
    nothing). Its step keeps the four-field contract after the run, so the callers whose
    receiver is an instance of it keep unpacking four values: the run is the unit."""
    step = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "step"), None)
    if step is None:
        return False
    values = [r.value for r in own_returns(step) if r.value is not None]
    if not values:
        return False
    handed_on = _bound_to_super_step(step)
    for value in values:
        if isinstance(value, ast.Name) and value.id in handed_on:
            return False  # ``results = super().step(a)`` ... ``return results``: the base's step, migrated with it
        if isinstance(value, ast.Call) and isinstance(value.func, ast.Name) and value.func.id != "super":
            continue  # ``zip(*results)``, ``tuple(batch)``
        if is_batched_step_return(value, step):
            continue  # ``np.stack(obs), np.stack(rews), np.stack(dones), infos``
        if not isinstance(value, (ast.Name, ast.ListComp, ast.GeneratorExp, ast.List)):
            return False  # a tuple literal the rules migrate, a helper's or an inner env's result
    return True


def _bound_to_super_step(step: ast.FunctionDef | ast.AsyncFunctionDef) -> frozenset[str]:
    """The names the step binds once, and whole, to ``super().step(...)``."""
    stores: dict[str, int] = {}
    for node in walk(step):
        if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            stores[node.id] = stores.get(node.id, 0) + 1
    return frozenset(
        node.targets[0].id
        for node in walk(step)
        if isinstance(node, ast.Assign)
        and len(node.targets) == 1
        and isinstance(node.targets[0], ast.Name)
        and stores.get(node.targets[0].id) == 1
        and isinstance(node.value, ast.Call)
        and isinstance(node.value.func, ast.Attribute)
        and node.value.func.attr == "step"
        and isinstance(node.value.func.value, ast.Call)
        and isinstance(node.value.func.value.func, ast.Name)
        and node.value.func.value.func.id == "super"
    )


def handed_on_attribute(classdef: ast.ClassDef) -> str | None:
    """``x`` when the class's own ``step`` and ``reset`` return nothing but
    ``self.x.step(...)`` and ``self.x.reset(...)``: the object in ``self.x`` answers both
    calls in the instance's place. None for any other shape."""
    found: set[str] = set()
    for method in ("step", "reset"):
        function = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == method), None)
        values = [r.value for r in own_returns(function)] if function is not None else []
        if not values:
            return None
        for value in values:
            if not (isinstance(value, ast.Call) and isinstance(value.func, ast.Attribute) and value.func.attr == method):
                return None
            owner = value.func.value
            if not (isinstance(owner, ast.Attribute) and isinstance(owner.value, ast.Name) and owner.value.id == "self"):
                return None
            found.add(owner.attr)
    return found.pop() if len(found) == 1 else None



def property_aliases_of(facts: ModuleFacts, classdef: ast.ClassDef) -> dict[str, str]:
    """Each read-only ``@property`` of the class whose whole body (after a docstring) only
    returns another attribute of ``self`` (``def wrapped_env(self): return
    self._wrapped_env``) -> that attribute: reading the property reads what the attribute
    holds. A property with a setter or other binding of its name in the class, or under a
    module-level ``property`` of the module's own, is none."""
    if facts.module_scope.bindings.get("property"):
        return {}
    named: dict[str, int] = {}
    for statement in classdef.body:
        if isinstance(statement, (*FUNCTIONS, ast.ClassDef)):
            named[statement.name] = named.get(statement.name, 0) + 1
    found: dict[str, str] = {}
    for statement in classdef.body:
        if not (isinstance(statement, FUNCTIONS) and len(statement.decorator_list) == 1 and named[statement.name] == 1):
            continue
        decorator = statement.decorator_list[0]
        params = [*statement.args.posonlyargs, *statement.args.args]
        body = [s for s in statement.body if not (isinstance(s, ast.Expr) and isinstance(s.value, ast.Constant))]
        if not (isinstance(decorator, ast.Name) and decorator.id == "property" and len(params) == 1 and len(body) == 1):
            continue
        returned = body[0].value if isinstance(body[0], ast.Return) else None
        if (
            isinstance(returned, ast.Attribute)
            and isinstance(returned.value, ast.Name)
            and returned.value.id == params[0].arg
            and returned.attr != statement.name
        ):
            found[statement.name] = returned.attr
    return found

# NumPy functions that put per-env values side by side (or give one env's value a batch
# axis): what they return is an array with one entry per env, never one env's flag.
_BATCHING_FUNCTIONS = frozenset({"stack", "vstack", "hstack", "concatenate", "expand_dims", "atleast_1d"})
# ``np.array(x)`` batches only a list of per-env values; of one flag it makes a 0-d array.
_ARRAY_FUNCTIONS = frozenset({"array", "asarray"})


def is_batched_step_return(value: ast.AST | None, step: ast.AST) -> bool:
    """A four-field return whose reward and done are both per-env batches: ``np.stack(rews),
    np.stack(dones)``, ``np.expand_dims(done, 0)``, ``rew[None]``, ``np.array(dones)`` of a
    list filled in the method. Such a step is a batch of envs with its own API (stacked flags,
    no place for a scalar ``truncated``): the rules leave its contract, and its callers',
    as they are (GM504/GM602 report the class once)."""
    if _transposed(value) or (isinstance(value, ast.Name) and _bound_only_to_transposed(value.id, step)):
        return True  # ``return zip(*results)``: the per-env results, one tuple per field
    if not (isinstance(value, ast.Tuple) and len(value.elts) == 4):
        return False
    lists = _lists_filled_in(step)
    return all(_is_batched(element, lists) for element in value.elts[1:3])


def _transposed(value: ast.AST | None) -> bool:
    """``zip(*results)``: a list of per-env results turned into one tuple per field (the
    unpacked form, ``obs, rews, dones, infos = zip(*results)``, is read below)."""
    return (
        isinstance(value, ast.Call)
        and isinstance(value.func, ast.Name)
        and value.func.id == "zip"
        and len(value.args) == 1
        and isinstance(value.args[0], ast.Starred)
        and not value.keywords
    )


def _bound_only_to_transposed(name: str, step: ast.AST) -> bool:
    """Every binding of ``name`` in the step stores a ``zip(*...)`` (``results =
    zip(*[first] + rest)``, then ``return results``)."""
    stores = [n for n in walk(step) if isinstance(n, ast.Name) and n.id == name and isinstance(n.ctx, ast.Store)]
    # a store that is no plain ``name = ...`` (unpacked, a loop target, ``+=``) is left uncounted
    values = [
        node.value
        for node in walk(step)
        if isinstance(node, ast.Assign)
        for target in node.targets
        if isinstance(target, ast.Name) and target.id == name
    ]
    return bool(stores) and len(values) == len(stores) and all(_transposed(v) for v in values)


def _is_batched(expr: ast.expr, lists: frozenset[str]) -> bool:
    # A bare ``[done]`` is not enough: wrappers that make an env look multi-agent return
    # per-agent lists, which GM602 migrates as such.
    if isinstance(expr, ast.Subscript) and _adds_axis(expr.slice):
        return True  # ``rew[None]``
    if isinstance(expr, ast.Name):
        return expr.id in lists
    if not (isinstance(expr, ast.Call) and expr.args):
        return False
    func = expr.func
    name = func.attr if isinstance(func, ast.Attribute) else func.id if isinstance(func, ast.Name) else None
    if name in _BATCHING_FUNCTIONS:
        return True
    if name in _ARRAY_FUNCTIONS:
        first = expr.args[0]
        return isinstance(first, (ast.List, ast.ListComp)) or (isinstance(first, ast.Name) and first.id in lists)
    return False


def _adds_axis(index: ast.expr) -> bool:
    parts = index.elts if isinstance(index, ast.Tuple) else [index]
    return any(
        (isinstance(p, ast.Constant) and p.value is None) or (isinstance(p, ast.Attribute) and p.attr == "newaxis")
        for p in parts
    )


def _lists_filled_in(function: ast.AST) -> frozenset[str]:
    """Names the method fills with one value per env: ``dones.append(done)``, a target
    of ``obs, rews, dones, infos = zip(*results)``, or a list the method starts empty and
    extends (``done_n = []``, then ``done_n += done`` or ``done_n.extend(done)`` for each
    env of a batch of multi-agent envs)."""
    found: set[str] = set(concatenated_lists(function))
    for node in walk(function):
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Attribute)
            and node.func.attr == "append"
            and isinstance(node.func.value, ast.Name)
        ):
            found.add(node.func.value.id)
        elif (
            isinstance(node, ast.Assign)
            and isinstance(node.value, ast.Call)
            and isinstance(node.value.func, ast.Name)
            and node.value.func.id == "zip"
        ):
            for target in node.targets:
                if isinstance(target, (ast.Tuple, ast.List)):
                    found |= {e.id for e in target.elts if isinstance(e, ast.Name)}
    return frozenset(found)


def concatenated_lists(function: ast.AST) -> dict[str, list[ast.expr]]:
    """Lists ``function`` binds to a list display and extends (``xs += value``,
    ``xs.extend(value)``): each such name -> the values it is extended with. Those values
    are iterables (``list += bool`` raises), so per-agent or per-env collections."""
    displays: set[str] = set()
    extended: dict[str, list[ast.expr]] = {}
    for node in walk(function):
        if isinstance(node, ast.Assign):
            targets = [t for target in node.targets for t in _paired_targets(target, node.value)]
            displays |= {name for name, value in targets if isinstance(value, ast.List)}
        elif isinstance(node, ast.AugAssign) and isinstance(node.op, ast.Add) and isinstance(node.target, ast.Name):
            extended.setdefault(node.target.id, []).append(node.value)
        elif (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Attribute)
            and node.func.attr == "extend"
            and isinstance(node.func.value, ast.Name)
            and len(node.args) == 1
        ):
            extended.setdefault(node.func.value.id, []).append(node.args[0])
    return {name: values for name, values in extended.items() if name in displays}


def per_agent_receivers(classdef: ast.ClassDef) -> frozenset[str]:
    """Names a method of the class steps with four targets and whose done it concatenates into
    a list (``obs, reward, done, _ = env.step(a)``, then ``done_n += done``): per-agent envs
    on their own four-field API, whose reset keeps its own return too."""
    found: set[str] = set()
    for method in classdef.body:
        if not isinstance(method, FUNCTIONS):
            continue
        extended = {v.id for values in concatenated_lists(method).values() for v in values if isinstance(v, ast.Name)}
        for node in walk(method):
            if not (isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.value, ast.Call)):
                continue
            target, func = node.targets[0], node.value.func
            if (
                isinstance(target, (ast.Tuple, ast.List))
                and len(target.elts) == 4
                and isinstance(target.elts[2], ast.Name)
                and target.elts[2].id in extended
                and isinstance(func, ast.Attribute)
                and func.attr == "step"
                and isinstance(func.value, ast.Name)
            ):
                found.add(func.value.id)
    return frozenset(found)


def _paired_targets(target: ast.expr, value: ast.expr) -> list[tuple[str, ast.expr]]:
    """``a, b = [], []`` -> ``[("a", []), ("b", [])]``; ``a = []`` -> ``[("a", [])]``."""
    if isinstance(target, ast.Name):
        return [(target.id, value)]
    if isinstance(target, (ast.Tuple, ast.List)) and isinstance(value, (ast.Tuple, ast.List)) and len(target.elts) == len(value.elts):
        return [pair for t, v in zip(target.elts, value.elts) for pair in _paired_targets(t, v)]
    return []


_VEC_METHODS = frozenset({"step_async", "step_wait"})
# ``self.num_envs = len(env_fns)``: baselines and SB3 spell it ``num_envs``, tianshou-style
# vector envs ``env_num``; a class that counts its envs so steps them all at once.
_ENV_COUNTS = frozenset({"num_envs", "env_num", "n_envs"})
# ``step(self, action, id=None)``: a vector env steps (or resets) the envs it is told.
_ENV_ID_PARAMS = frozenset({"id", "ids", "env_id", "env_ids", "indices"})


def is_vec_env_shaped(classdef: ast.ClassDef) -> bool:
    """Defines ``step_async`` and ``step_wait`` (the VecEnv protocol of baselines and SB3), or
    ``step`` in a class that counts its envs (``num_envs``, ``env_num``: its results are
    stacked per env), or ``step`` and ``reset`` that both take the ids of the envs to act
    on in a class made from a list of env factories (``__init__(self, env_fns)``)."""
    methods = {s.name: s for s in classdef.body if isinstance(s, FUNCTIONS)}
    if _VEC_METHODS <= set(methods):
        return True
    if "step" not in methods:
        return False
    if _counts_envs(classdef):
        return True
    init = methods.get("__init__")
    return (
        init is not None
        and "reset" in methods
        and any(a.arg in ("env_fns", "envs") for a in _params(init))
        and all(any(a.arg in _ENV_ID_PARAMS for a in _params(methods[m])) for m in ("step", "reset"))
    )


def _params(function: ast.FunctionDef | ast.AsyncFunctionDef) -> list[ast.arg]:
    args = function.args
    return [*args.posonlyargs, *args.args, *args.kwonlyargs]


def _counts_envs(classdef: ast.ClassDef) -> bool:
    """``num_envs`` (or ``env_num``, ``n_envs``) is a class attribute, a property, or is stored
    on ``self`` in ``__init__``."""
    for statement in classdef.body:
        if isinstance(statement, FUNCTIONS) and statement.name in _ENV_COUNTS and any(
            isinstance(d, ast.Name) and d.id == "property" for d in statement.decorator_list
        ):
            if _returns_own_count(statement):
                return True  # ``@property def n_envs(self): return self._n_envs``
        if isinstance(statement, (ast.Assign, ast.AnnAssign)):
            targets = statement.targets if isinstance(statement, ast.Assign) else [statement.target]
            if any(isinstance(t, ast.Name) and t.id in _ENV_COUNTS for t in targets):
                return True
        if isinstance(statement, FUNCTIONS) and statement.name == "__init__":
            for inner in walk(statement):
                if isinstance(inner, ast.Attribute) and inner.attr in _ENV_COUNTS and isinstance(inner.ctx, ast.Store):
                    if isinstance(inner.value, ast.Name) and inner.value.id == "self":
                        return True
    return False


def _returns_own_count(function: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    """The property returns a count the class keeps itself (``self._n_envs``,
    ``len(self.envs)``). A wrapper that hands on the count of what it holds
    (``return self._env.num_envs if hasattr(self._env, "num_envs") else 1``) wraps one env
    or a batch alike, so it says nothing about stepping several envs at once."""
    returns = [s for s in own_returns(function) if s.value is not None]
    if not returns:
        return False
    for statement in returns:
        value = statement.value
        if isinstance(value, ast.Call) and isinstance(value.func, ast.Name) and value.func.id == "len" and value.args:
            value = value.args[0]
        if not (isinstance(value, ast.Attribute) and isinstance(value.value, ast.Name) and value.value.id == "self"):
            return False
    return True


def renders_nothing(facts: ModuleFacts, classdef: ast.ClassDef, _depth: int = 0) -> bool:
    """The class's render() (its own, else the first base of this module that has one)
    calls no ``render`` and names no ``"render"`` (a worker's command): a stub that logs
    or does nothing, so its callers render no env. False where no render() is found."""
    methods = {s.name: s for s in classdef.body if isinstance(s, FUNCTIONS)}
    render = methods.get("render")
    if render is None:
        if _depth > 4:
            return False
        for base in classdef.bases:
            local = facts.classes.get(base.id) if isinstance(base, ast.Name) else None
            if local is not None and local is not classdef:
                return renders_nothing(facts, local, _depth + 1)
        return False
    for node in walk(render):
        if isinstance(node, ast.Attribute) and node.attr == "render":
            return False
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and "render" in node.value.lower():
            if not _in_log_call(facts, node):
                return False
        if isinstance(node, (ast.Return, ast.Yield)) and getattr(node, "value", None) is not None:
            if not (isinstance(node.value, ast.Constant) and node.value.value is None):
                return False  # it hands something back (a frame)
    return True


def _in_log_call(facts: ModuleFacts, node: ast.AST) -> bool:
    """``logger.warn('Render not defined for %s' % self)``: the word in a message."""
    for ancestor in facts.ancestors(node):
        if isinstance(ancestor, ast.Call):
            name = ancestor.func.attr if isinstance(ancestor.func, ast.Attribute) else getattr(ancestor.func, "id", "")
            return name in ("warn", "warning", "info", "debug", "print", "error")
    return False


def wrapped_env_renders(facts: ModuleFacts, classdef: ast.ClassDef) -> list[str]:
    """The methods (not render) of ``classdef`` that call ``self.env.render(...)``: a
    wrapper that draws the env it wraps as it steps or resets it, in sorted order."""
    methods = set()
    for call in facts.attribute_calls.get("render", ()):
        held = call.func.value  # type: ignore[attr-defined]
        if not (isinstance(held, ast.Attribute) and held.attr == "env" and isinstance(held.value, ast.Name) and held.value.id == "self"):
            continue
        function = facts.enclosing_function(call)
        if function is None or function.name in ("render", "_render") or facts.enclosing_class(call) is not classdef:
            continue
        if facts.parent(function) is classdef:
            methods.add(function.name)
    return sorted(methods)
