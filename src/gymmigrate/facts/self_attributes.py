"""``self.x`` in a class: what the receiver analysis knows of attributes
(``Receivers`` mixes this in).

``self.env`` in a ``gym.Wrapper`` is the wrapped env; ``self.training_env`` in a
Stable-Baselines3 callback is a VecEnv; any other ``self.x`` has the kind of every value
the class stores to it (``self.x = ...`` in any method, not in nested classes), which
one walk per class collects.
"""

from __future__ import annotations

import ast
import weakref
from collections import defaultdict
from functools import partial
from typing import TYPE_CHECKING, NamedTuple

from gymmigrate.facts import names as N
from gymmigrate.facts.class_shapes import property_aliases_of
from gymmigrate.facts.kinds import EnvKind, ReceiverQueries, join_kinds
from gymmigrate.facts.module import (
    FUNCTIONS,
    call_argument,
    is_super_call,
    named_class_call,
    self_attribute,
    statements_in,
    walk,
)
from gymmigrate.facts.receiver_classes import duck_wrapper_attribute

if TYPE_CHECKING:
    from gymmigrate.facts.module import ModuleFacts


class HandedUp(NamedTuple):
    """What ``SelfAttributes.handed_up`` finds a subclass holds in an attribute its base of
    another module of the run stores from its ``__init__``."""

    argument: ast.Name  # the read of the subclass's own parameter in the call handing it up
    handed_on: bool  # that base is a Gym env wrapper written by hand around the attribute


class SelfAttributes:
    """What ``self.x`` holds, for ``Receivers`` (which owns one and answers the kind
    questions it asks back)."""

    def __init__(self, receivers: ReceiverQueries) -> None:
        self.receivers = receivers
        self.facts: ModuleFacts = receivers.facts

    def is_self(self, name: ast.Name) -> bool:
        if name.id not in ("self", "cls"):
            return False
        function = self.facts.enclosing_function(name)
        if function is None:
            return False
        params = [*function.args.posonlyargs, *function.args.args]
        return bool(params) and params[0].arg == name.id

    def self_attribute_kind(self, attr: ast.Attribute, name: str) -> EnvKind:
        classdef = self.facts.enclosing_class(attr)
        if classdef is None:
            return EnvKind.UNKNOWN
        held = _wrapped_attribute(classdef)
        if name == held and self.receivers.is_gym_wrapper_class(classdef):
            # around a Gym-only library's object (gym_unity) the wrapped env keeps gym's API: left alone (GM602 reports the class)
            if self.receivers.wraps_pz_parallel(classdef):
                return EnvKind.PZ_PARALLEL  # what every construction wraps (GM602 reports the class)
            if self.receivers.wraps_vec_env(classdef):
                return EnvKind.SB3_VEC  # likewise a VecEnv (GM602 reports the class)
            return EnvKind.NOT_ENV if self.receivers.wraps_gym_only(classdef) is not None else EnvKind.GYM_ENV
        if name == held and self.receivers.unproved_duck_wrapper(classdef):
            # a duck wrapper the run cannot prove wraps Gym envs: left whole (GM602 reports it)
            return EnvKind.NOT_ENV
        if name == "training_env":
            return EnvKind.SB3_VEC
        if name == "model" and self._is_sb3_callback(classdef):
            return EnvKind.SB3_MODEL
        # ``saved = self.env`` ... ``self.env = saved`` (a wrapper put on for a while and taken
        # off again) stores back a value the attribute already held: no new evidence.
        values = [v for v in self.self_attribute_values(attr, name) if not self._copies_attribute(v, name)]
        own = self._own_constructions_kind(classdef, name, values)
        if own is not None:
            return own
        values = values or [v for v in self.inherited_values(classdef, name) if not self._copies_attribute(v, name)]
        if all(_placeholder(v) for v in values):
            # ``self.env = None`` in a base (or no store there) that its subclasses fill: a
            # method of the base runs on their instances, so it holds what they store
            below = self._stored_below(classdef, name)
            if below:
                return join_kinds([self._value_kind(value, self.facts.enclosing_class(value) or classdef) for value in below])
        if not values:
            handed = self.handed_up(attr)
            if handed is not None:
                # ``self._wrapped_env`` that a base of another module stores from the
                # parameter this class's ``__init__`` hands up: what its constructions pass;
                # where they do not settle it, a Gym env when that base is a Gym env whose
                # step and reset are the held object's (the object keeps its contract)
                kind = self.receivers.kind_of(handed.argument)
                if kind is EnvKind.UNKNOWN and handed.handed_on:
                    return EnvKind.GYM_ENV
                if kind is not EnvKind.UNKNOWN:
                    return kind
            if name == "env" and self._is_pettingzoo_wrapper(classdef):
                return self.receivers.class_kind(classdef)
            library = self.set_by_library_base(classdef, name)
            if library is not None:
                return library
            return self._driven_by_run_base(classdef, name)
        kind = join_kinds([self._value_kind(value, classdef) for value in values])
        if kind is EnvKind.UNKNOWN:
            # ``self._env = gym.make(id)`` and, lines below in the same method,
            # ``self._env = Preprocess(self._env.env)``: that read sees the make, whatever
            # the attribute holds afterwards
            seen = store_seen(self.facts, attr, name)
            if seen is not None and self._value_kind(seen, classdef) is EnvKind.GYM_ENV:
                return EnvKind.GYM_ENV
        return kind

    def set_by_library_base(self, classdef: ast.ClassDef, name: str) -> EnvKind | None:
        """``self.env`` (and a runner's ``self.model``) that neither the class nor a base of
        the module stores, in a subclass of a Stable-Baselines or baselines algorithm or
        runner (``class MySAC(SAC)``, ``class Runner(AbstractEnvRunner)``): that library's
        ``__init__`` stored it, so it is the library's VecEnv (its own legacy API, decided
        once by the library's item) and the runner's model. None for any other attribute
        or base."""
        if name not in ("env", "model"):
            return None
        roles: set[str] = set()
        for base in classdef.bases:
            for q in self.receivers.qualified_names(base):
                if N.top_package(q) not in N.SB3_PACKAGES:
                    continue
                last = q.rsplit(".", 1)[-1]
                if last.endswith(N.SB_RUNNER_BASE_SUFFIX):
                    roles.add("runner")
                elif last.isupper() or last in N.SB3_MODEL_CLASSES or last.endswith(N.SB_ALGORITHM_BASE_SUFFIXES):
                    roles.add("algorithm")
        if name == "env" and roles:
            return EnvKind.SB3_VEC
        if name == "model" and roles == {"runner"}:
            return EnvKind.SB3_MODEL
        return None

    def _driven_by_run_base(self, classdef: ast.ClassDef, name: str) -> EnvKind:
        """``self.env.step(a)`` in ``class Shared(RLlibMPE)`` that never stores ``self.env``,
        with ``RLlibMPE`` of another module of the run storing and stepping it: what that
        module settles it to be (``ProjectView.driven_kind``), the one base that says."""
        project = getattr(self.receivers, "project", None)
        if project is None:
            return EnvKind.UNKNOWN
        kinds = {
            kind
            for base in classdef.bases
            for q in self.receivers.qualified_names(base)
            if (kind := project.driven_kind(q, name)) is not None
        }
        return kinds.pop() if len(kinds) == 1 else EnvKind.UNKNOWN

    def _stored_below(self, classdef: ast.ClassDef, name: str) -> list[ast.expr]:
        """What the subclasses of ``classdef`` in this module, at any depth, store to
        ``self.<name>`` (placeholders aside), where ``classdef`` and those subclasses are
        subclassed in no other module of the run: every instance a method of ``classdef``
        runs on is one of theirs (or holds the placeholder). Empty where another module
        derives from one of them (its stores are not seen here) or none stores it."""
        project = getattr(self.receivers, "project", None)
        below: list[ast.ClassDef] = []
        pending = [classdef]
        while pending:
            current = pending.pop()
            if project is not None and project.subclassed_elsewhere(current.name):
                return []
            for sub in self.facts.all_classes:
                if sub is not current and sub not in below and any(self.receivers.local_class(b) is current for b in sub.bases):
                    below.append(sub)
                    pending.append(sub)
        return [
            value
            for sub in below
            for value in class_self_stores(self.facts, sub).get(name, [])
            if not _placeholder(value) and not self._copies_attribute(value, name)
        ]

    def inherited_values(self, classdef: ast.ClassDef, name: str, _seen: frozenset[int] = frozenset()) -> list[ast.expr]:
        """Values stored to ``self.<name>`` by the classes of this module that ``classdef``
        derives from (``class Child(Base)`` reading the ``self.env`` that ``Base.__init__``
        stores), when ``classdef`` itself never stores it."""
        found: list[ast.expr] = []
        for base in classdef.bases:
            local = self.receivers.local_class(base)
            if local is None or local is classdef or id(local) in _seen:
                continue
            found += class_self_stores(self.facts, local).get(name, []) or self.inherited_values(local, name, _seen | {id(classdef)})
        return found

    def handed_up(self, attr: ast.Attribute) -> HandedUp | None:
        """``self.env_class`` in a class that never stores it, whose ``__init__`` (its own, or
        that of the nearest base of this module defining one) hands its own parameter up to
        a base of another module of the run, with ``super().__init__(..., env_class=env_class)``
        (the first base: the next class of the order ``super()`` follows) or
        ``Base.__init__(self, ...)``, at the slot of the parameter that base stores on
        ``self.env_class`` and nothing else (``ProjectView.init_held``): the read of that
        parameter in the call, whose values are the attribute's, and whether that base is a
        Gym env wrapper written by hand around the attribute. The same for ``self.inner``, a
        property of these classes or of their bases of the run that only returns
        ``self._inner`` (``property_alias``), where the class stores no ``_inner`` itself.
        None otherwise."""
        project = getattr(self.receivers, "project", None)
        classdef = self.facts.enclosing_class(attr)
        if project is None or classdef is None or not isinstance(attr.value, ast.Name) or not self.is_self(attr.value):
            return None
        stored = self.property_alias(classdef, attr.attr) or attr.attr
        if stored != attr.attr and self._stored_in_hierarchy(classdef, stored, set()):
            return None  # the property returns what this class stores there itself
        seen: set[int] = set()
        init = None
        while id(classdef) not in seen:
            seen.add(id(classdef))
            init = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "__init__"), None)
            if init is not None:
                break
            base = self.receivers.local_class(classdef.bases[0]) if len(classdef.bases) == 1 else None
            if base is None:
                return None
            classdef = base  # the nearest base here whose ``__init__`` its constructions run
        if init is None or not classdef.bases:
            return None
        found = []
        for call in self.facts.attribute_calls.get("__init__", ()):
            if self.facts.enclosing_function(call) is not init:
                continue
            called: ast.expr | None
            if is_super_call(call.func.value):  # type: ignore[attr-defined]
                called, shift = classdef.bases[0], 0
            else:
                called, shift = named_class_call(call, "__init__", init, classdef.bases), 1
                if called is None:
                    return None  # another ``__init__`` called here: not the one shape this reads
            if self.receivers.local_class(called) is not None:
                continue  # a base of this module: its stores are the class's own (``self_attribute_values``)
            qualified = self.receivers.qualified_names(called)
            held = project.init_held(next(iter(qualified)), stored) if len(qualified) == 1 else None
            if held is not None:
                found.append((call, shift, held))
        if len(found) != 1:
            return None
        call, shift, held = found[0]
        argument = call_argument(call, held.position + shift, held.param)
        params = [*init.args.posonlyargs, *init.args.args[1:], *init.args.kwonlyargs]
        if not isinstance(argument, ast.Name):
            return None
        bindings = self.facts.bindings_of(argument)
        if len(bindings) != 1 or bindings[0] not in params or self.facts.enclosing_function(argument) is not init:
            return None
        return HandedUp(argument, held.handed_on)

    def property_alias(self, classdef: ast.ClassDef, name: str) -> str | None:
        """The attribute of ``self`` that a read-only property ``name`` of ``classdef``, of a
        class of this module it derives from, or of their bases of the run only returns
        (``def inner(self): return self._inner``; ``class_shapes.property_aliases_of``,
        ``ProjectView.property_alias``). None where no such property is found."""
        project = getattr(self.receivers, "project", None)
        seen: set[int] = set()
        pending = [classdef]
        while pending:
            current = pending.pop(0)
            if id(current) in seen:
                continue
            seen.add(id(current))
            own = self.facts.memo(("property-aliases", id(current)), partial(property_aliases_of, self.facts, current))
            if name in own:
                return own[name]
            for base in current.bases:
                local = self.receivers.local_class(base)
                if local is not None:
                    pending.append(local)
                    continue
                if project is None:
                    continue
                for qualified in self.receivers.qualified_names(base):
                    alias = project.property_alias(qualified, name)
                    if alias is not None:
                        return alias
        return None

    def _copies_attribute(self, value: ast.expr, name: str) -> bool:
        """``value`` is ``self.<name>`` itself, or a local name every binding of which is
        assigned ``self.<name>``."""
        if self._is_self_attribute(value, name):
            return True
        if not isinstance(value, ast.Name):
            return False
        bindings = self.facts.bindings_of(value)
        if not bindings:
            return False
        for binding in bindings:
            statement = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
            if not (isinstance(statement, ast.Assign) and statement.targets == [binding] and self._is_self_attribute(statement.value, name)):
                return False
        return True

    def _own_constructions_kind(self, classdef: ast.ClassDef, name: str, values: list[ast.expr]) -> EnvKind | None:
        """``self._env`` in a subclass with no ``__init__`` of its own, where a base of this
        module stores the parameter of its ``__init__`` (``class IsaacWrapper(Wrapper)``,
        ``Wrapper.__init__`` storing ``self._env = env``): what this subclass's own
        constructions pass, not what every subclass's do. A dispatcher that builds
        ``GymWrapper(env)`` for Gym envs and ``IsaacWrapper(env)`` for the rest gives each
        its own; a construction in such a def outside the Gym branch (``if isinstance(env,
        gym.Env): return GymWrapper(env)``, then ``return IsaacWrapper(env)``, or under
        ``wrapper == "isaac"``) gets no Gym env: its legacy callers sent them elsewhere. Only a settled "no Gym env" is answered (every construction passes what
        is no env: ``NOT_ENV``); None where that is not the shape, some construction is not
        seen, or they pass anything else (the stores' join answers then)."""
        if not values or name in class_self_stores(self.facts, classdef):
            return None  # the class stores it itself
        if any(isinstance(s, FUNCTIONS) and s.name == "__init__" for s in classdef.body):
            return None
        # Decided once per class and attribute: classes that build one another from the same
        # held attribute (``Subgoal(self.bot)`` in each subclass of ``Subgoal``) would
        # otherwise ask it again along every order of their construction sites. While it is
        # being decided, the question asked back settles nothing (None: the stores' join).
        return self.facts.memo(
            (f"own-constructions:{name}", id(classdef)),
            partial(self._decide_own_constructions, classdef, values),
            while_computing=None,
        )

    def _decide_own_constructions(self, classdef: ast.ClassDef, values: list[ast.expr]) -> EnvKind | None:
        positions: set[tuple[int, str]] = set()
        for value in values:
            bindings = self.facts.bindings_of(value) if isinstance(value, ast.Name) else []
            if len(bindings) != 1 or not isinstance(bindings[0], ast.arg):
                return None
            init = self.facts.enclosing_function(value)
            params = [*init.args.posonlyargs, *init.args.args] if isinstance(init, FUNCTIONS) and init.name == "__init__" else []
            if bindings[0] not in params:
                return None
            positions.add((params.index(bindings[0]) - 1, bindings[0].arg))
        if len(positions) != 1:
            return None
        position, param = positions.pop()
        project = getattr(self.receivers, "project", None)
        if project is not None and project.built_elsewhere(classdef.name):
            return None
        calls, elsewhere = self.receivers.constructions(classdef)
        if elsewhere or not calls or any(shift for _, shift in calls):
            return None
        kinds = []
        for call, _ in calls:
            if self.receivers.sent_past_gym_check(call, classdef):
                # ``wrap(env)`` sends Gym envs to another class: this one gets the others
                kinds.append(EnvKind.NOT_ENV)
                continue
            argument = call_argument(call, position, param)
            if argument is None:
                return None
            kinds.append(self.receivers.kind_of(argument))
        return EnvKind.NOT_ENV if all(k is EnvKind.NOT_ENV for k in kinds) else None

    def _is_self_attribute(self, value: ast.AST, name: str) -> bool:
        return isinstance(value, ast.Attribute) and value.attr == name and isinstance(value.value, ast.Name) and self.is_self(value.value)

    def _value_kind(self, value: ast.expr, classdef: ast.ClassDef) -> EnvKind:
        """``self._top = self`` in an env class: the attribute is the env itself."""
        if isinstance(value, ast.Name) and self.is_self(value) and self.facts.enclosing_class(value) is classdef:
            if self.receivers.is_gym_wrapper_class(classdef):
                return EnvKind.GYM_ENV
            kind = self.receivers.class_kind(classdef)
            return kind if kind is not EnvKind.NOT_ENV else EnvKind.UNKNOWN
        return self.receivers.kind_of(value)

    def _is_pettingzoo_wrapper(self, classdef: ast.ClassDef) -> bool:
        return any(q in N.PZ_WRAPPER_BASES for base in classdef.bases for q in self.receivers.qualified_names(base))

    def self_attribute_values(self, attr: ast.AST, name: str) -> list[ast.expr]:
        """Values stored to ``self.<name>`` in the class that encloses ``attr``; where it
        stores none, in the nearest base class of this module that does (``self.env`` of an
        ``AsyncCollector(Collector)`` is what ``Collector.__init__`` stored)."""
        classdef = self.facts.enclosing_class(attr)
        if classdef is None:
            return []
        return self._stored_in_hierarchy(classdef, name, set())

    def _stored_in_hierarchy(self, classdef: ast.ClassDef, name: str, seen: set[int]) -> list[ast.expr]:
        """Stores of the class; if it has none, those of its bases of this module (the
        attribute an inherited ``__init__`` sets: ``AsyncCollector(Collector)`` reads
        ``self.env`` that ``Collector.__init__`` stores), so both read the same object."""
        seen.add(id(classdef))
        values = class_self_stores(self.facts, classdef).get(name, [])
        if values:
            return values
        found: list[ast.expr] = []
        for base in classdef.bases:
            local = self.receivers.local_class(base)
            if local is not None and id(local) not in seen:
                found.extend(self._stored_in_hierarchy(local, name, seen))
        return found

    def _is_sb3_callback(self, classdef: ast.ClassDef) -> bool:
        return any(q in N.SB3_CALLBACK_BASES for base in classdef.bases for q in self.receivers.qualified_names(base))


_TRIES: tuple[type[ast.AST], ...] = tuple(t for t in (ast.Try, getattr(ast, "TryStar", None)) if t is not None)


def store_seen(facts: ModuleFacts, read: ast.Attribute, name: str) -> ast.expr | None:
    """The value of ``self.<name> = value`` that ``read`` (a load of ``self.<name>``) sees
    for certain: that assignment stands before the read in the same method, in the read's
    block or one around it, and nothing between them may store the attribute again (no
    other store of it, no call of a method of ``self``), nor a loop around the read once
    more. None when the method shows no such store."""
    function = facts.enclosing_function(read)
    if function is None or isinstance(read.ctx, (ast.Store, ast.Del)):
        return None
    node: ast.AST | None = facts.statement_of(read)
    while node is not None and node is not function:
        parent = facts.parent(node)
        block = _block_of(parent, node)
        if parent is None or block is None:
            return None
        for statement in reversed(block[: block.index(node)]):
            if isinstance(statement, ast.Assign) and len(statement.targets) == 1 and self_attribute(statement.targets[0]) == name:
                return statement.value
            if _may_store(statement, name):
                return None
        if isinstance(parent, (ast.For, ast.AsyncFor, ast.While)) and _may_store(parent, name):
            return None  # the loop's next turn sees its own store
        if isinstance(parent, _TRIES) and not any(item is node for item in getattr(parent, "body", ())) and _may_store(parent, name):
            return None  # a handler or a finally may run after part of the try stored it
        if isinstance(parent, (*FUNCTIONS, ast.ClassDef, ast.Lambda)) and parent is not function:
            return None
        node = parent
    return None


def _placeholder(value: ast.expr) -> bool:
    """``None`` stored until the real object comes (``self.env = None`` in a base's
    ``__init__``)."""
    return isinstance(value, ast.Constant) and value.value is None


def _block_of(parent: ast.AST | None, node: ast.AST) -> list[ast.AST] | None:
    for field in ("body", "orelse", "finalbody", "handlers"):
        block = getattr(parent, field, None)
        if isinstance(block, list) and any(item is node for item in block):
            return block
    return None


def _may_store(statement: ast.AST, name: str) -> bool:
    """``statement`` stores ``self.<name>``, or calls a method of ``self``, which might."""
    for node in walk(statement):
        if isinstance(node, ast.Attribute) and isinstance(node.ctx, (ast.Store, ast.Del)) and self_attribute(node) == name:
            return True
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and isinstance(node.func.value, ast.Name) and node.func.value.id == "self":
            return True
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "setattr":
            return True
    return False


def _wrapped_attribute(classdef: ast.ClassDef) -> str:
    """Where a wrapper keeps the env it wraps: ``self.env``, or the attribute a duck wrapper
    holds it in (``self.environment``)."""
    return duck_wrapper_attribute(classdef) or "env"


def class_self_stores(facts: ModuleFacts, classdef: ast.ClassDef) -> dict[str, list[ast.expr]]:
    """Values stored to ``self.x`` anywhere in a class (not nested classes), by name, in
    source order: the values each store pairs with (``self.a, self.b = 1, 2`` stores both;
    ``self.a, self.b = pair()``, ``self.t += 1`` or ``for self.i in ...`` store none).

    One walk per class, not per attribute read: env classes read dozens of ``self.x``.
    """
    return facts.memo(("self-stores", id(classdef)), lambda: _collect_self_stores(classdef))


def self_stores(facts: ModuleFacts, classdef: ast.ClassDef, name: str) -> list[ast.expr] | None:
    """Every value ``self.<name> = value`` stores in ``classdef``'s own methods; None when
    some store of ``self.<name>`` there is anything else (an augmented assignment, a tuple,
    chained or annotated target, a loop target).

    ``class_self_stores`` with one difference that matters: the done tracer
    (``facts/limits.py``) must know that ``self.t = 0`` beside ``self.t += 1`` is a counter,
    not a constant, where the receiver analysis takes the values it can pair and lets the
    other stores go.
    """
    for attr in facts.attributes.get(name, ()):
        if isinstance(attr.ctx, ast.Store) and self_attribute(attr) is not None and facts.enclosing_class(attr) is classdef:
            holder = facts.parent(attr)
            if not (isinstance(holder, ast.Assign) and holder.targets == [attr]):
                return None
    return list(class_self_stores(facts, classdef).get(name, []))


def binds_self_attribute(classdef: ast.ClassDef, attribute: str) -> bool:
    """Some code of ``classdef`` (nested classes too) assigns ``self.<attribute>``, or
    through it: ``self.<attribute>`` anywhere in the target of an assignment, an
    annotation or an augmented assignment.

    Not ``attribute in class_self_stores(...)``: that keeps the values a store pairs with,
    and leaves out the writes that give none (``self.env, self.eval_env = make_pair()``,
    ``self.env += ...``, ``self.env: Env``, ``self.env.seed = ...``). The question here is
    whether the class has a hand in the attribute at all (``rules/base.py`` pins the
    decision on ``self.env`` to the class that binds it).
    """
    return attribute in _self_attributes_bound(classdef)


# The attributes each class binds, read once per class: the rules ask about one attribute
# after another (every receiver ``self.x`` of the module), and a walk of the class per
# question cost a sixth of a large run. Weak keys: a tree dropped is forgotten with it.
_BOUND_BY_CLASS: weakref.WeakKeyDictionary[ast.ClassDef, frozenset[str]] = weakref.WeakKeyDictionary()


def _self_attributes_bound(classdef: ast.ClassDef) -> frozenset[str]:
    bound = _BOUND_BY_CLASS.get(classdef)
    if bound is None:
        found: set[str] = set()
        for node in walk(classdef):
            targets: list[ast.expr] = []
            if isinstance(node, ast.Assign):
                targets = list(node.targets)
            elif isinstance(node, (ast.AnnAssign, ast.AugAssign)):
                targets = [node.target]
            for target in targets:
                for sub in walk(target):
                    if isinstance(sub, ast.Attribute) and isinstance(sub.value, ast.Name) and sub.value.id == "self":
                        found.add(sub.attr)
        bound = _BOUND_BY_CLASS[classdef] = frozenset(found)
    return bound


def _collect_self_stores(classdef: ast.ClassDef) -> dict[str, list[ast.expr]]:
    values: dict[str, list[ast.expr]] = defaultdict(list)
    stack: list[ast.AST] = list(classdef.body)
    while stack:
        node = stack.pop()
        if isinstance(node, ast.ClassDef):
            continue
        if isinstance(node, ast.Assign):
            for target in node.targets:
                name = self_attribute(target)
                if name is not None:
                    values[name].append(node.value)
                elif isinstance(target, (ast.Tuple, ast.List)) and isinstance(node.value, (ast.Tuple, ast.List)):
                    for element, value in zip(target.elts, node.value.elts):
                        name = self_attribute(element)
                        if name is not None:
                            values[name].append(value)
        elif isinstance(node, ast.AnnAssign) and node.value is not None:
            name = self_attribute(node.target)
            if name is not None:
                values[name].append(node.value)
        stack.extend(statements_in(node))  # assignments are statements: no expression walk
    for stored in values.values():
        stored.sort(key=lambda v: (v.lineno, v.col_offset))
    return values
