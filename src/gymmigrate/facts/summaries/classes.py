"""What a module's top-level classes tell the run: the space classes their ``action_space``
and ``observation_space`` are made of, which certainly are no Spaces, the attributes a
plain class holds from its constructor, the subclasses of the run's classes with what
they override, hand on (``render_mode``) and say of their done values, and the env
classes whose render(mode) may stay the project's own."""

from __future__ import annotations

import ast
from collections.abc import Iterator
from functools import partial
from typing import TYPE_CHECKING

from gymmigrate.facts import names as N
from gymmigrate.facts.class_shapes import (
    handed_on_attribute,
    property_aliases_of,
    wrapped_env_renders,
)
from gymmigrate.facts.done_causes import Cause, DoneCause
from gymmigrate.facts.env_classes import (
    UNDERSCORE_HOOKS,
    EnvClasses,
    class_level_bindings,
    hook_renames,
    is_super_method_call,
    mode_can_stay_optional,
)
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.limits import DoneTracer
from gymmigrate.facts.module import (
    FUNCTIONS,
    ModuleFacts,
    is_super_call,
    own_returns,
    unsubscripted,
    walk,
)
from gymmigrate.facts.module_summary import OWN
from gymmigrate.facts.receivers import Receivers
from gymmigrate.facts.render_modes import (
    mode_handed_on,
    mode_may_reach,
    modeless_render,
    own_object,
    passes_mode,
)
from gymmigrate.facts.step_hooks import ENV_API

if TYPE_CHECKING:  # the calls summarizer reads this module's held_params: a type only here
    from gymmigrate.facts.summaries.calls import CallSummarizer

_SPACE_ATTRIBUTES = ("action_space", "observation_space")


def space_calls(facts: ModuleFacts, receivers: Receivers) -> dict[str, tuple[tuple[str, str], ...]]:
    """``self.action_space = C(...)`` / ``self.observation_space = C(...)`` in the methods
    of each top-level class: (attribute, ``C`` qualified, or ``@C`` for a class here)."""
    found: dict[str, tuple[tuple[str, str], ...]] = {}
    for name, classdef in facts.classes.items():
        stores = receivers.self_stores(classdef)
        calls = []
        for attribute in _SPACE_ATTRIBUTES:
            for value in stores.get(attribute, ()):
                if not isinstance(value, ast.Call):
                    continue
                local = receivers.local_class(value.func)
                if local is not None:
                    calls.append((attribute, OWN + local.name))
                    continue
                qualified = [q for q in facts.qualified_names(value.func) if not N.is_library(q)]
                if len(qualified) == 1:
                    calls.append((attribute, qualified[0]))
        if calls:
            found[name] = tuple(calls)
    return found


_PLAIN_BASES = frozenset({"list", "tuple", "dict", "object"})


def plain_classes(facts: ModuleFacts) -> dict[str, str]:
    """Top-level classes that certainly are not Spaces: no base, or only builtin
    containers (``class MultiAgentActionSpace(list)``), with what they derive from."""
    found = {}
    for name, classdef in facts.classes.items():
        if classdef.keywords or classdef.decorator_list:
            continue  # a metaclass or a decorator may make it anything
        bases = []
        for base in classdef.bases:
            if not (isinstance(base, ast.Name) and base.id in _PLAIN_BASES and not facts.module_scope.bindings.get(base.id)):
                break
            bases.append(base.id)
        else:
            found[name] = ", ".join(bases) or "object"
    return found


def plain_roots(tree: ast.Module) -> frozenset[str]:
    """Top-level classes whose bases are only ``object`` or ``abc.ABC`` (or with the
    ``ABCMeta`` metaclass), undecorated: an interface of the project, no library's class.
    Read from the bare tree: a module with no Gym code has no ``ModuleFacts``."""
    abc_names: dict[str, str] = {}  # local name -> "ABC" / "ABCMeta" / "abc"
    for statement in tree.body:
        if isinstance(statement, ast.ImportFrom) and statement.module == "abc" and not statement.level:
            abc_names.update((a.asname or a.name, a.name) for a in statement.names if a.name in ("ABC", "ABCMeta"))
        elif isinstance(statement, ast.Import):
            abc_names.update((a.asname or a.name, "abc") for a in statement.names if a.name == "abc")

    def is_abc(node: ast.expr, name: str) -> bool:
        if isinstance(node, ast.Name):
            return abc_names.get(node.id) == name
        return (
            isinstance(node, ast.Attribute) and node.attr == name
            and isinstance(node.value, ast.Name) and abc_names.get(node.value.id) == "abc"
        )

    found = set()
    for statement in tree.body:
        if not isinstance(statement, ast.ClassDef) or statement.decorator_list:
            continue
        if any(k.arg != "metaclass" or not is_abc(k.value, "ABCMeta") for k in statement.keywords):
            continue
        if all((isinstance(b, ast.Name) and b.id == "object") or is_abc(b, "ABC") for b in statement.bases):
            found.add(statement.name)
    return frozenset(found)


def held_params(facts: ModuleFacts, receivers: Receivers) -> dict[str, dict[str, str]]:
    """``ModuleSummary.held_params``: per top-level plain class, the attributes its methods
    store only from a parameter of its ``__init__`` that nothing rebinds."""
    found: dict[str, dict[str, str]] = {}
    for name, classdef in facts.classes.items():
        if receivers.class_kind(classdef) is not EnvKind.NOT_ENV:
            continue
        held = _held_from_init(facts, receivers, classdef)
        if held:
            found[name] = held
    return found


def init_held(facts: ModuleFacts, receivers: Receivers) -> dict[str, dict[str, tuple[str, bool]]]:
    """``ModuleSummary.init_held``: per top-level class of any kind, each attribute its
    methods store only from a parameter of its ``__init__`` -> (that parameter, whether the
    class is a Gym env wrapper written by hand around it). A subclass handing its own
    parameter up to that ``__init__`` holds in the attribute what its constructions pass,
    also where it reads it through a property returning it (``property_aliases``;
    ``SelfAttributes.handed_up``).

    A wrapper written by hand: a Gym env class whose own ``step`` and ``reset`` return the
    attribute's (``handed_on_attribute``), as ``gym.Wrapper`` does with ``self.env``; the
    Gym contract its instances keep is the held object's, so that object is a Gym env."""
    found: dict[str, dict[str, tuple[str, bool]]] = {}
    for name, classdef in facts.classes.items():
        params = _held_from_init(facts, receivers, classdef)
        if not params:
            continue
        handed_on = handed_on_attribute(classdef) if receivers.class_kind(classdef) is EnvKind.GYM_ENV else None
        found[name] = {attribute: (param, attribute == handed_on) for attribute, param in params.items()}
    return found


def _held_from_init(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> dict[str, str]:
    """The attributes ``classdef``'s methods store only from a parameter of its ``__init__``
    that nothing rebinds -> that parameter."""
    init = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "__init__"), None)
    if init is None:
        return {}
    params = {a.arg for a in (*init.args.posonlyargs, *init.args.args[1:], *init.args.kwonlyargs)}
    held = {}
    for attribute, stored in receivers.self_stores(classdef).items():
        # ``__setstate__`` restores what pickling saved (a pickling wrapper's
        # ``self.x = pickle.loads(ob)``): the same object, not another value
        values = [v for v in stored if getattr(facts.enclosing_function(v), "name", None) != "__setstate__"]
        if len(values) != 1 or not isinstance(values[0], ast.Name) or values[0].id not in params:
            continue
        bindings = facts.bindings_of(values[0])
        if len(bindings) == 1 and isinstance(bindings[0], ast.arg) and facts.enclosing_function(values[0]) is init:
            held[attribute] = values[0].id
    return held


_DRIVING_METHODS = ("reset", "step")


# What an attribute holds that a subclass may drive without the base driving it: an env of
# a known API (a base's ``self.env = gym.make(env_id)`` that only its subclasses step).
_ENV_KINDS = frozenset({EnvKind.GYM_ENV, EnvKind.GYM_VEC, EnvKind.SB3_VEC, EnvKind.PZ_AEC, EnvKind.PZ_PARALLEL, EnvKind.OWN_API})


def driven_kinds(facts: ModuleFacts, receivers: Receivers) -> dict[str, dict[str, EnvKind]]:
    """``ModuleSummary.driven_kinds``: per top-level class, the attributes it resets or
    steps, or holds an env of a known API in, whose every store in the class is a call this
    module classifies: not a name or an attribute, whose object a subclass's construction
    may choose."""
    found: dict[str, dict[str, EnvKind]] = {}
    for name, holder in facts.classes.items():
        for attribute, values in receivers.self_stores(holder).items():
            if not values or not all(isinstance(v, ast.Call) for v in values):
                continue
            node = next(
                (
                    a
                    for a in facts.attributes.get(attribute, ())
                    if isinstance(a.value, ast.Name) and receivers.is_self(a.value) and facts.enclosing_class(a) is holder
                ),
                None,
            )
            kind = receivers.kind_of(node) if node is not None else EnvKind.UNKNOWN
            if kind in _ENV_KINDS:
                found.setdefault(name, {})[attribute] = kind
    for method in _DRIVING_METHODS:
        for call in facts.attribute_calls.get(method, ()):
            held = call.func.value if isinstance(call.func, ast.Attribute) else None
            if not (isinstance(held, ast.Attribute) and isinstance(held.value, ast.Name) and receivers.is_self(held.value)):
                continue
            classdef = facts.enclosing_class(call)
            if classdef is None or facts.classes.get(classdef.name) is not classdef or held.attr in found.get(classdef.name, {}):
                continue
            values = receivers.self_stores(classdef).get(held.attr, [])
            if not values or not all(isinstance(v, ast.Call) for v in values):
                continue
            kind = receivers.kind_of(held)
            if kind is not EnvKind.UNKNOWN:
                found.setdefault(classdef.name, {})[held.attr] = kind
    return found


def stored_attributes(facts: ModuleFacts, receivers: Receivers) -> dict[str, frozenset[str]]:
    """``ModuleSummary.stored_attributes``: per top-level class with an imported base of the
    run, the attributes it stores on ``self``, with those its bases of this module store
    (their ``__init__`` may be the one that runs)."""
    found: dict[str, frozenset[str]] = {}
    for name, classdef in facts.classes.items():
        if not any(not N.is_library(q) for base in classdef.bases for q in facts.qualified_names(base)):
            continue
        found[name] = frozenset(attr for current in receivers.local_lineage(classdef) for attr in receivers.self_stores(current))
    return found


def render_mode_heirs(facts: ModuleFacts, receivers: Receivers) -> tuple[tuple[str, tuple[str, ...], bool], ...]:
    """Top-level classes with a base of the run (imported, or ``@Name`` of this module):
    (name, bases, whether its constructor hands ``render_mode`` on once its base takes it:
    no ``__init__`` of its own, ``**kwargs``, or one ``__init__`` call of a base that
    custom_env/render.py gives ``render_mode=render_mode``)."""
    found = []
    for name, classdef in facts.classes.items():
        bases = _run_bases(facts, receivers, classdef)
        if not bases:
            continue
        init = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "__init__"), None)
        # A module that never names gym is decided too when a base is an env class of
        # another module of the run (EnvClassFamily.may_fire); the join only follows such
        # bases (``thread_render_mode``), so the text of this module does not decide.
        if init is None or init.args.kwarg is not None:
            passes_on = True
        elif receivers.own_api(classdef) is not None:
            # Left whole on its API of its own (custom_env/env_class.py): its __init__ never
            # gets the parameter, so its subclasses must not pass it (a TypeError).
            passes_on = False
        else:
            calls = [n for n in walk(init) if isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute) and n.func.attr == "__init__"]
            passes_on = len(calls) == 1 and all(k.arg is not None for k in calls[0].keywords)
        found.append((name, tuple(sorted(bases)), passes_on))
    return tuple(found)


def _run_bases(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> list[str]:
    """The class's bases that may be classes of the run, in the order it names them:
    ``@Name`` for one of this module, the qualified name of an imported one."""
    bases = []
    for spelled in classdef.bases:
        base = unsubscripted(spelled)  # ``Base[T]``: the subclass inherits Base's methods
        local = receivers.local_class(base)
        if local is not None and local is not classdef:
            bases.append(OWN + local.name)
        else:
            bases.extend(q for q in facts.qualified_names(base) if not N.is_library(q))
    return bases


def run_bases(facts: ModuleFacts, receivers: Receivers) -> dict[str, tuple[str, ...]]:
    """``ModuleSummary.run_bases``: per top-level class with a base of the run, those bases
    in declaration order (a method is looked up in the first that defines it)."""
    found = {}
    for name, classdef in facts.classes.items():
        bases = _run_bases(facts, receivers, classdef)
        if bases:
            found[name] = tuple(bases)
    return found


def _method_attribute_calls(classdef: ast.ClassDef) -> Iterator[tuple[ast.Call, ast.Attribute]]:
    """The ``x.m(...)`` calls in the class's own methods (nested defs included), each with
    its ``x.m``."""
    for statement in classdef.body:
        if isinstance(statement, FUNCTIONS):
            for node in walk(statement):
                if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
                    yield node, node.func


def super_calls(facts: ModuleFacts) -> dict[str, frozenset[str]]:
    """``ModuleSummary.super_calls``: per top-level class, the methods its own methods call
    on a base: ``super().m(...)``, ``super(Cls, self).m(...)`` or ``Base.m(self, ...)``
    naming one of its bases as it spells them. What they reach is the nearest base above
    the class defining ``m``, never the class's own."""
    found: dict[str, frozenset[str]] = {}
    for name, classdef in facts.classes.items():
        spelled = {ast.unparse(base) for base in classdef.bases}
        called = frozenset(
            func.attr
            for node, func in _method_attribute_calls(classdef)
            if is_super_call(func.value) or (_called_with_self(node, func) and ast.unparse(func.value) in spelled)
        )
        if called:
            found[name] = called
    return found


def named_class_calls(facts: ModuleFacts) -> dict[str, frozenset[str]]:
    """``ModuleSummary.named_class_calls``: per top-level class, the methods its own methods
    call as ``Cls.m(self, ...)`` naming any class: unlike ``super()``, such a call can skip
    past the classes its MRO puts first (a grandbase's ``reset`` past its base's)."""
    found: dict[str, frozenset[str]] = {}
    for name, classdef in facts.classes.items():
        called = frozenset(func.attr for node, func in _method_attribute_calls(classdef) if _called_with_self(node, func))
        if called:
            found[name] = called
    return found


def _called_with_self(node: ast.Call, func: ast.Attribute) -> bool:
    return (
        bool(node.args)
        and isinstance(node.args[0], ast.Name)
        and node.args[0].id == "self"
        and isinstance(func.value, (ast.Name, ast.Attribute))
        and not (isinstance(func.value, ast.Name) and func.value.id == "self")
    )


def renamed_hooks(facts: ModuleFacts, receivers: Receivers) -> dict[str, frozenset[str]]:
    """``ModuleSummary.renamed_hooks``: per top-level class that is no Gym wrapper, the gym
    <= 0.9 hooks (``_reset``) it renames on this module's knowledge (``hook_renames``: no
    public name in the class or its bases here). The join drops those whose public name a
    base in another module defines, and keeps only env classes of the run. A class that
    publishes a hook (``reset = _reset``) keeps them all, and is not listed."""
    found: dict[str, frozenset[str]] = {}
    for name, classdef in facts.classes.items():
        if receivers.is_gym_wrapper_class(classdef):
            continue
        methods = {s.name: s for s in classdef.body if isinstance(s, FUNCTIONS)}
        if not any(old in methods for old in UNDERSCORE_HOOKS) or class_level_bindings(classdef, methods)[0]:
            continue
        renames = hook_renames(classdef, methods, partial(receivers.base_methods, classdef))
        if renames:
            found[name] = frozenset(renames.values())
    return found


def subclasses(facts: ModuleFacts) -> tuple[tuple[str, tuple[str, ...], tuple[str, ...]], ...]:
    """Top-level classes with an imported base: (name, the bases' qualified names, the
    methods it defines). The join finds which methods of the run's classes are overridden
    in other modules (method contracts follow their class: rules/custom_env/hooks.py)."""
    found = []
    for name, classdef in facts.classes.items():
        bases = tuple(sorted(q for base in classdef.bases for q in facts.qualified_names(base) if not N.is_library(q)))
        if bases:
            methods = tuple(s.name for s in classdef.body if isinstance(s, FUNCTIONS))
            found.append((name, bases, methods))
    return tuple(found)


def contains_calls(facts: ModuleFacts) -> tuple[tuple[str, int], ...]:
    """``ModuleSummary.contains_calls``: ``x.contains(value)`` (a space's one-argument
    membership test), by the name its receiver is read by, with the line."""
    found = []
    for call in facts.attribute_calls.get("contains", ()):
        receiver = call.func.value  # type: ignore[attr-defined]
        name = receiver.attr if isinstance(receiver, ast.Attribute) else receiver.id if isinstance(receiver, ast.Name) else None
        if name is not None and len(call.args) == 1 and not call.keywords and not isinstance(call.args[0], ast.Starred):
            found.append((name, call.lineno))
    return tuple(found)


# What ``env.model`` is on a mujoco-py MujocoEnv and on no object of the ``mujoco`` bindings
# Gymnasium's MujocoEnv holds (``mujoco.MjModel`` has no ``data``, no ``*_names``, no
# ``*_name2id``): mujoco-py 0.5's ``model.data`` and the name tables of mujoco-py <= 2.
_MUJOCO_PY_MODEL = frozenset({"data", "geom_names", "body_names", "joint_names", "site_names", "actuator_names", "camera_names", "sensor_names"})
_MUJOCO_PY_MODEL_SUFFIXES = ("_name2id", "_id2name")
# The old base's methods an object built on it answered and Gymnasium's MujocoEnv does not.
_MUJOCO_PY_METHODS = ("_render", "_get_viewer")


def mujoco_py_uses(facts: ModuleFacts) -> tuple[int, ...]:
    """``ModuleSummary.mujoco_py_uses``: the lines reading the mujoco-py MujocoEnv's own API
    (``x.model.data``, ``x.model.geom_names``, ``x.data._wrapped``) on an object other than
    ``self`` (a class's own reads are its own item) or an MjSim (``sim.model``: mujoco-py
    itself, which does not change); and the old base's ``_render`` / ``_get_viewer`` called on
    an object read that way in the module."""
    lines: set[int] = set()
    objects: set[str] = set()
    for name, nodes in facts.attributes.items():
        if name in _MUJOCO_PY_MODEL or name.endswith(_MUJOCO_PY_MODEL_SUFFIXES):
            holder_attr = "model"
        elif name == "_wrapped":
            holder_attr = "data"
        else:
            continue
        for node in nodes:
            holder = node.value
            if not (isinstance(holder, ast.Attribute) and holder.attr == holder_attr):
                continue
            owner = holder.value
            if (isinstance(owner, ast.Name) and owner.id in ("self", "sim")) or (isinstance(owner, ast.Attribute) and owner.attr == "sim"):
                continue
            lines.add(node.lineno)
            objects.add(ast.dump(owner))
    for method in _MUJOCO_PY_METHODS:
        for call in facts.attribute_calls.get(method, ()):
            if ast.dump(call.func.value) in objects:  # type: ignore[attr-defined]
                lines.add(call.lineno)
    return tuple(sorted(lines))


def instance_calls(facts: ModuleFacts) -> frozenset[str]:
    """``ModuleSummary.instance_calls``: the methods the module calls on a receiver that
    is neither ``self`` nor ``super()`` (``env.postprocess(...)``, ``self.env.observe()``):
    whatever object that is, a class of the run defining the name may be the one called."""
    return frozenset(
        name
        for name, calls in facts.attribute_calls.items()
        if any(
            not (isinstance(call.func.value, ast.Name) and call.func.value.id == "self")  # type: ignore[attr-defined]
            and not is_super_method_call(call, name)
            for call in calls
        )
    )


def self_calls(facts: ModuleFacts) -> dict[str, frozenset[str]]:
    """``ModuleSummary.self_calls``: per top-level class, the ``self.<name>(...)`` its
    methods call (nested defs included: a closure's ``self`` is the instance too)."""
    found: dict[str, frozenset[str]] = {}
    for name, classdef in facts.classes.items():
        called = frozenset(
            func.attr
            for _, func in _method_attribute_calls(classdef)
            if isinstance(func.value, ast.Name) and func.value.id == "self"
        )
        if called:
            found[name] = called
    return found


def done_methods(facts: ModuleFacts) -> tuple[dict[str, dict[str, DoneCause]], dict[str, dict[str, tuple[DoneCause, ...]]]]:
    """For each class with an imported base, why its methods' values are True: a subclass's
    ``def _computeDone(self): return self.t > self.T`` tells its base class in another
    module that the done of its ``step`` is a step limit (facts/limits.py). Second, for the
    methods that return tuples (``return rewards, done``), why each of their values is True:
    a base's ``rewards, over = self.score(infos)`` reads one of them. A parameter is
    what the tracer cannot see into: what the base passes stays in the base's module."""
    found: dict[str, dict[str, DoneCause]] = {}
    items: dict[str, dict[str, tuple[DoneCause, ...]]] = {}
    for name, classdef in facts.classes.items():
        if not any(not N.is_library(q) for base in classdef.bases for q in facts.qualified_names(base)):
            continue
        tracer = DoneTracer(facts, classdef)
        methods = {}
        for statement in classdef.body:
            if not isinstance(statement, FUNCTIONS) or not any(r.value is not None for r in own_returns(statement)):
                continue
            if statement.name in ENV_API or statement.name.startswith("__"):
                continue  # the env's own API and dunders: no helper a base's step asks for its done
            try:
                methods[statement.name] = tracer.returns_cause(statement, 0)
                returned = tracer.returned_items(statement)
            except RecursionError:  # a pathological nesting: the override counts as untraced
                methods[statement.name] = DoneCause(Cause.UNKNOWN)
                continue
            if returned:
                items.setdefault(name, {})[statement.name] = returned
        if methods:
            found[name] = methods
    return found, items


def mode_renders(facts: ModuleFacts) -> dict[str, tuple[int, str]]:
    """Classes with an imported base, no render() of their own, that call
    ``self.render(mode)`` or ``super().render(mode)``: (line, call) of the first. The join
    tells the base's module, whose render() keeps ``mode`` for them (custom_env/render.py)."""
    found: dict[str, tuple[int, str]] = {}
    for name, classdef in facts.classes.items():
        if not any(not N.is_library(q) for base in classdef.bases for q in facts.qualified_names(base)):
            continue
        if any(isinstance(s, FUNCTIONS) and s.name == "render" for s in classdef.body):
            continue  # its calls reach its own render(), decided with the class
        for node in walk(classdef):
            if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "render"):
                continue
            receiver = node.func.value
            own = (isinstance(receiver, ast.Name) and receiver.id == "self") or is_super_method_call(node, "render")
            if own and facts.enclosing_class(node) is classdef and passes_mode(node, facts):
                found[name] = (node.lineno, facts.segment(node))
                break
    return found


def fixed_mode_renders(facts: ModuleFacts) -> frozenset[str]:
    """Classes whose ``render(self, mode)`` cannot keep ``mode`` as an optional parameter."""
    return frozenset(
        name
        for name, classdef in facts.classes.items()
        for method in classdef.body
        if isinstance(method, FUNCTIONS) and method.name == "render" and "mode" in [a.arg for a in method.args.args] and not mode_can_stay_optional(method)
    )


def varargs_renders(facts: ModuleFacts) -> frozenset[str]:
    """Classes whose own ``render(self, *args, ...)`` names no ``mode``: GM405 leaves it as it
    is, so a mode passed to it still reaches whatever it hands its arguments to."""
    return frozenset(
        name
        for name, classdef in facts.classes.items()
        for method in classdef.body
        if isinstance(method, FUNCTIONS) and method.name == "render" and takes_mode_unnamed(method)
    )


def takes_mode_unnamed(method: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    """``def render(self, *args, **kwargs)``: a ``*args`` and no parameter named ``mode``."""
    names = [a.arg for a in (*method.args.posonlyargs, *method.args.args, *method.args.kwonlyargs)]
    return method.args.vararg is not None and "mode" not in names


def default_mode_renders(facts: ModuleFacts) -> frozenset[str]:
    """Classes whose own ``render(self, mode=<default>, ...)`` gives ``mode`` a default."""
    found = set()
    for name, classdef in facts.classes.items():
        for method in classdef.body:
            if isinstance(method, FUNCTIONS) and method.name == "render":
                params = [a.arg for a in method.args.args]
                first_default = len(params) - len(method.args.defaults)
                if "mode" in params and params.index("mode") >= first_default:
                    found.add(name)
    return frozenset(found)


def own_renders(facts: ModuleFacts, receivers: Receivers, calls: CallSummarizer) -> tuple[tuple[str, tuple[str, ...]], ...]:
    """``ModuleSummary.own_renders``: the top-level env classes whose render(mode) only hands
    its mode on (``mode_handed_on``) and that no render call here passes a mode to, with
    what made each object it hands the mode to: "" for one this module shows to be its own
    and no env, else the class of the run every store of it builds (the join checks it)."""
    found = []
    env = EnvClasses.of(facts, receivers)
    for name, classdef in facts.classes.items():
        handed = mode_handed_on(facts, classdef)
        if handed is None or not env.is_custom_env(classdef) or mode_may_reach(facts, receivers, classdef):
            continue
        makers = []
        for call in handed:
            receiver = call.func.value  # type: ignore[attr-defined]
            maker = "" if own_object(receivers, call) else calls.instance_class(receiver)
            if maker is None or (maker and N.is_library(maker)):
                break
            makers.append(maker)
        else:
            found.append((name, tuple(makers)))
    return tuple(found)


def modeless_renders(facts: ModuleFacts, receivers: Receivers) -> frozenset[str]:
    """``ModuleSummary.modeless_renders``: the top-level env classes whose render() no render
    mode changes (``modeless_render``)."""
    return frozenset(name for name, classdef in facts.classes.items() if modeless_render(facts, receivers, classdef))


def rendering_wrappers(facts: ModuleFacts, receivers: Receivers) -> frozenset[str]:
    """The module's Gym wrapper classes whose reset/step render the env they wrap."""
    return frozenset(
        name for name, classdef in facts.classes.items() if receivers.is_gym_wrapper_class(classdef) and wrapped_env_renders(facts, classdef)
    )


def held_env_render_forward(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> ast.Call | None:
    """The bare ``self.<x>.render()`` the class's own render() makes, when the class is
    no Gym env nor wrapper (a holder of an env: ``self.env = gym.make(...)``): that
    forward is the render site whose make gets (or is asked) the mode, so a caller's
    ``holder.render()`` repeats its decision. None for any other shape."""
    render = next((m for m in classdef.body if isinstance(m, FUNCTIONS) and m.name == "render"), None)
    if render is None or receivers.is_gym_wrapper_class(classdef):
        return None
    kind = receivers.class_kind(classdef)
    if kind not in (EnvKind.NOT_ENV, EnvKind.UNKNOWN):
        return None
    if kind is EnvKind.UNKNOWN and EnvClasses.of(facts, receivers).is_custom_env(classdef):
        return None
    for call in facts.attribute_calls.get("render", []):
        func = call.func
        if (
            facts.enclosing_function(call) is render
            and not (call.args or call.keywords)  # a forward of its callers' arguments makes them the sites
            and isinstance(func, ast.Attribute)
            and isinstance(func.value, ast.Attribute)
            and isinstance(func.value.value, ast.Name)
            and func.value.value.id == "self"
            and (kind is EnvKind.NOT_ENV or receivers.kind_of(func.value) is EnvKind.GYM_ENV)
        ):
            return call
    return None


def render_forwards(facts: ModuleFacts, receivers: Receivers) -> dict[str, int]:
    """The module's classes whose render() forwards bare to the env they hold, with the
    line of that forward (``held_env_render_forward``)."""
    found: dict[str, int] = {}
    for name, classdef in facts.classes.items():
        call = held_env_render_forward(facts, receivers, classdef)
        if call is not None:
            found[name] = call.lineno
    return found


def property_aliases(facts: ModuleFacts) -> dict[str, dict[str, str]]:
    """``ModuleSummary.property_aliases``: per top-level class, each read-only ``@property``
    that only returns another attribute of ``self`` -> that attribute
    (``class_shapes.property_aliases_of``): a subclass reading the property reads what the
    attribute holds."""
    return {name: aliases for name, classdef in facts.classes.items() if (aliases := property_aliases_of(facts, classdef))}
