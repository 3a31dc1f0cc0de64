"""The calls a module makes into other modules of the run, with the ``EnvKind`` of each
argument (``CallSummary``): what the join (``facts/project.py``) needs to tell the kinds a
run's defs are passed. The callee is a qualified name of the run, ``@name`` for a def of
this module, or ``?.name`` for a method of an unknown owner; an argument it cannot classify
here is a reference (``new:``, ``param:``) the join resolves.
"""

from __future__ import annotations

import ast
import builtins
import re
from collections.abc import Iterable
from typing import cast

from gymmigrate.facts import names as N
from gymmigrate.facts.creator_tables import lookup, table_display
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.mode_handovers import handed_make
from gymmigrate.facts.module import (
    FUNCTIONS,
    ModuleFacts,
    call_argument,
    is_super_call,
    own_returns,
    string_value,
)
from gymmigrate.facts.module_summary import (
    GUARD_KINDS,
    HELD,
    KNOWN,
    NEW,
    OWN,
    PARAM,
    REF,
    TABLE,
    UNRESOLVED,
    CallSummary,
    Kind,
)
from gymmigrate.facts.receiver_classes import is_object
from gymmigrate.facts.receivers import Receivers
from gymmigrate.facts.summaries.classes import held_params

_BUILTINS = frozenset(dir(builtins))

# A call with no arguments: what a library creator handed on gives when called.
_NO_ARGUMENTS = ast.Call(func=ast.Name(id="_", ctx=ast.Load()), args=[], keywords=[])

# ``PongNoFrameskip-v4``, ``ALE/Pong-v5``, ``mod:Name-v0``: what the summaries keep of string arguments.
_ENV_ID = re.compile(r"(?:[\w.]+:)?(?:\w+/)?[\w.-]+-v\d+")


class CallSummarizer:
    """The calls of one module into the run, and what they pass."""

    def __init__(self, facts: ModuleFacts, receivers: Receivers) -> None:
        self.facts = facts
        self.receivers = receivers

    def calls(self) -> list[CallSummary]:
        """Every call of a name, then every call of an attribute, in the module's index order."""
        calls = [c for calls in self.facts.calls_by_name.values() for call in calls for c in self._name_calls(call)]
        calls += [c for call in (c for calls in self.facts.attribute_calls.values() for c in calls) for c in self._method_calls(call)]
        calls += [c for call in self.facts.lookup_calls for c in self._lookup_calls(call)]
        return calls

    def _lookup_calls(self, call: ast.Call) -> list[CallSummary]:
        """``AGENTS[kind](params, env_class=...)``: a call through a closed table of creators
        reaches each class or def the table holds. A table of this module: one call of each of
        its names (this module's own, ``@``, or another module's of the run); a table imported
        from the run: one call the join hands to each (``table:<qualified>``)."""
        found = lookup(self.facts, cast(ast.Subscript, call.func))
        if found is None or found[1] is not None:
            return []
        table = found[0]
        display = table_display(self.facts, table) if isinstance(table, ast.Name) else None
        if display is None:
            qualified = self.facts.qualified_names(table)
            if len(qualified) != 1 or N.is_library(name := next(iter(qualified))):
                return []
            return [self._arguments(call, TABLE + name)]
        values = display.values if isinstance(display, ast.Dict) else display.elts
        targets = set()
        for value in values:
            if not isinstance(value, (ast.Name, ast.Attribute)):
                continue
            own = self._own_target(value)
            run_names = [q for q in self.facts.qualified_names(value) if not N.is_library(q)]
            target = own if own is not None else run_names[0] if len(run_names) == 1 else None
            if target is not None:
                targets.add(target)
        return [self._arguments(call, target) for target in sorted(targets)]

    def inherited_id_calls(self) -> list[CallSummary]:
        """``self.check(environment="LunarLander-v2")`` in a class that does not define
        ``check``, whose first base of the run (imported) may: the call with its env id
        literals, for ``ModuleSummary.inherited_id_calls`` only (no other join sees it, so
        what the run knows of the base's parameters is unchanged)."""
        found = []
        for calls in self.facts.attribute_calls.values():
            for call in calls:
                func = call.func
                if not isinstance(func, ast.Attribute) or not isinstance(func.value, ast.Name) or not self.receivers.is_self(func.value):
                    continue
                classdef = self.facts.enclosing_class(call)
                if classdef is None or self.facts.parent(classdef) is not self.facts.tree or self.receivers.own_method(func) is not None:
                    continue
                for base in classdef.bases:
                    qualified = self.facts.qualified_names(base)
                    if len(qualified) == 1 and not N.is_library(name := next(iter(qualified))):
                        summary = self._arguments(call, f"{name}.{func.attr}")
                        if summary.ids:
                            found.append(summary)
                        break
        return found

    def _call(self, call: ast.Call) -> CallSummary | None:
        target = self._target(call.func)
        if target is None:
            return None
        summary = self._arguments(call, target)
        if target.startswith(UNRESOLVED):
            kinds = {*summary.args, *(k for _, k in summary.keywords)}
            return summary if kinds & GUARD_KINDS else None
        return summary

    def _name_calls(self, call: ast.Call) -> list[CallSummary]:
        """``Agent(env)``; with ``Agent`` imported from several modules of the run
        (``from agents.dqn import Agent`` in one branch, ``from agents.a2c import Agent`` in
        another), one call of each: every binding may be the one called."""
        found = self._call(call)
        if found is not None:
            return [found]
        if self._own_target(call.func) is not None:
            return []
        targets = sorted({q for q in self.facts.qualified_names(call.func) if not N.is_library(q)})
        if not targets:
            chosen = self._chosen_callables(call.func)  # ``Agent = SacAgent if x else SharedAgent``
            return [self._arguments(call, target) for target in chosen]
        if len(targets) < 2 or len(targets) != len(self.facts.qualified_names(call.func)):
            return []  # a library binding among them: not all of the run's
        return [self._arguments(call, target) for target in targets]

    def _chosen_callables(self, func: ast.expr) -> list[str]:
        """The run's callables a local name is bound to, every binding an alias of one or a
        choice between them (``Agent = A if shared else B``, ``Agent = A``): each qualified
        through the imports; empty when any alternative is something else."""
        if not isinstance(func, ast.Name):
            return []
        bindings = self.facts.bindings_of(func)
        values: list[ast.expr] = []
        for binding in bindings:
            parent = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
            if not (isinstance(parent, ast.Assign) and parent.targets == [binding]):
                return []
            values.append(parent.value)
        found: set[str] = set()
        while values:
            value = values.pop()
            if isinstance(value, ast.IfExp):
                values += [value.body, value.orelse]
                continue
            if not isinstance(value, (ast.Name, ast.Attribute)):
                return []
            qualified = self.facts.qualified_names(value)
            if len(qualified) != 1 or N.is_library(next(iter(qualified))):
                return []
            found |= qualified
        return sorted(found) if bindings else []

    def passes_init_up(self) -> frozenset[str]:
        """Top-level classes whose ``__init__`` calls ``super().__init__(...)`` of a base of
        another module of the run (``ModuleSummary.passes_init_up``)."""
        found = set()
        for call in self.facts.attribute_calls.get("__init__", ()):
            function = self.facts.enclosing_function(call)
            classdef = self.facts.enclosing_class(call)
            if function is None or function.name != "__init__" or classdef is None:
                continue
            if self._super_base(call.func.value) is not None:  # type: ignore[attr-defined]
                found.add(classdef.name)
        return frozenset(found)

    def _method_calls(self, call: ast.Call) -> list[CallSummary]:
        """``x.fit(env)``; with ``x`` bound to instances of several classes of the run
        (``algo = DDQN(...)`` in one branch, ``algo = A2C(...)`` in another), one call of
        each class's method."""
        found = self._call(call)
        if found is not None or not isinstance(call.func, ast.Attribute) or not isinstance(call.func.value, ast.Name):
            return [found] if found is not None else []
        made = self._made_by_run_call(call.func.value)
        if made is None or "|" not in made:
            return []
        return [self._arguments(call, f"{cls}.{call.func.attr}") for cls in made.split("|")]

    def _target(self, func: ast.expr) -> str | None:
        """The qualified callee in another module, ``@name`` for a def of this module
        (``@Agent.fit`` for ``self.fit(...)``), ``?.name`` for a method of an unknown
        owner, None for library calls."""
        own = self._own_target(func)
        if own is not None:
            return own
        qualified = self.facts.qualified_names(func)
        if qualified:
            found = sorted(q for q in qualified if not N.is_library(q))
            return found[0] if len(found) == 1 else None
        if isinstance(func, ast.Name):
            return self._instance_call_target(func) or self._star_target(func)
        if not isinstance(func, ast.Attribute):
            return None
        owner = func.value
        if isinstance(owner, ast.Name) and self.receivers.is_self(owner):
            return None  # a method the class does not define (inherited)
        base = self._super_base(owner)
        if base is not None:
            return f"{base}.{func.attr}"  # ``super().__init__(env)`` in a subclass of a run's class
        if self._super_of_library(owner):
            return None  # the library's method: no def of the run is called
        if self._super_of_own_class(owner):
            return None  # a method of a class of this module, which reads its own calls itself
        cls = self.instance_class(owner)
        if cls is not None:
            return f"{cls}.{func.attr}" if not N.is_library(cls) else None
        return UNRESOLVED + func.attr

    def _super_class(self, owner: ast.expr) -> ast.ClassDef | None:
        """The class in whose method ``owner`` is ``super()`` (or ``super(Cls, self)``);
        None for anything else, a ``super`` of the module's own, or one outside a method."""
        if not (is_super_call(owner) and not owner.keywords):
            return None
        # is_super_call saw the name ``super``; only its binding is left to ask about
        if self.facts.bindings_of(cast(ast.Name, owner.func)) or len(owner.args) not in (0, 2):
            return None  # a ``super`` of the module's own
        function = self.facts.enclosing_function(owner)
        classdef = self.facts.enclosing_class(owner)
        if function is None or classdef is None or self.facts.parent(function) is not classdef:
            return None
        if owner.args and not (isinstance(owner.args[0], ast.Name) and owner.args[0].id == classdef.name):
            return None
        return classdef

    def _super_base(self, owner: ast.expr) -> str | None:
        """For ``super()`` (or ``super(Cls, self)``) in a method of a top-level class whose
        first base is a class of another module of the run (``class SacAgent(BaseAgent)``,
        ``BaseAgent`` imported): that base, qualified through the imports; else None."""
        classdef = self._super_class(owner)
        if classdef is None or self.facts.parent(classdef) is not self.facts.tree:
            return None
        first = next((b for b in classdef.bases if not is_object(b)), None)
        qualified = self.facts.qualified_names(first) if first is not None else set()
        return next(iter(qualified)) if len(qualified) == 1 and not N.is_library(next(iter(qualified))) else None

    def _super_of_library(self, owner: ast.expr) -> bool:
        """``super().__init__(env=env)`` in a method of a class whose every base is a
        library's (``class Runner(AbstractEnvRunner)``) or ``object``: the call reaches that
        library's method. As an unresolved ``?.__init__`` the join handed its arguments to
        every ``__init__`` of the run, a VecEnv to a proxy class built around a Gym env."""
        classdef = self._super_class(owner)
        if classdef is None:
            return False
        for base in classdef.bases:
            if is_object(base):
                continue
            qualified = self.facts.qualified_names(base)
            if not qualified or not all(N.is_library(q) for q in qualified):
                return False  # a class of the run, or one this module cannot name
        return True

    def _super_of_own_class(self, owner: ast.expr) -> bool:
        """``super().__init__(env)`` (or ``super(Cls, self)``) in a method of a class whose
        first base is a class of this module: the call reaches that class's method, whose
        constructions the module reads itself (``Receivers.constructions``). As an unresolved
        ``?.__init__`` the join handed its arguments to every ``__init__`` of the run."""
        classdef = self._super_class(owner)
        if classdef is None:
            return False
        first = next((b for b in classdef.bases if not is_object(b)), None)
        return first is not None and self.receivers.local_class(first) is not None

    def _star_target(self, func: ast.Name) -> str | None:
        """``calc(env)`` where ``calc`` is bound in this module by nothing but one star import
        of a module of the run (``from helpers import *``): ``helpers.calc``, which the join
        resolves to that module's def (or finds undefined there, and drops). Builtins, and
        a name several star imports may bring, have no target."""
        if func.id in _BUILTINS or self.facts.bindings_of(func):
            return None
        stars = [star for star in self.facts.star_imports if star.strip(".") and not N.is_library(star.lstrip("."))]
        if len(stars) != 1 or len(self.facts.star_imports) != 1:
            return None
        return f"{stars[0]}.{func.id}"

    def _instance_call_target(self, func: ast.Name) -> str | None:
        """``Evaluator.__call__`` (qualified through the imports) for ``evaluate(env)``,
        where ``evaluate`` holds an instance of a class of the run every way it is bound
        (``evaluate = Evaluator(3)``, or passed so to the def whose parameter it is)."""
        held = self._run_class_of(self.receivers.called_instances(func))
        return None if held is None else f"{held}.__call__"

    def _own_target(self, func: ast.expr) -> str | None:
        function = self.receivers.local_function(func)
        if function is not None:
            return OWN + function.name
        classdef = self.receivers.local_class(func)
        if classdef is not None:
            return OWN + f"{classdef.name}.__init__"
        method = self.receivers.own_method(func)
        if method is not None:
            owner = self.facts.parent(method)
            # own_method takes the def from the class body, so owner is always that ClassDef
            if isinstance(owner, ast.ClassDef) and self.facts.parent(owner) is self.facts.tree:
                return OWN + f"{owner.name}.{method.name}"
        return None

    def instance_class(self, owner: ast.expr) -> str | None:
        """``Agent`` (qualified through the imports) for ``Agent(...)``, a name or a
        ``self.x`` every binding of which is ``Agent(...)``; None otherwise."""
        if isinstance(owner, ast.Call):
            found = self.facts.qualified_names(owner.func)
            return next(iter(found)) if len(found) == 1 else None
        if isinstance(owner, ast.Name):
            # One answer per set of bindings: a name read n times is resolved once.
            bindings = self.facts.bindings_of(owner)
            if not bindings:
                return None  # (an empty list is a fresh object: its id is no key)
            return self.facts.memo(("instance-class", id(bindings)), lambda: self._class_of_bindings(bindings))
        if isinstance(owner, ast.Attribute) and isinstance(owner.value, ast.Name) and self.receivers.is_self(owner.value):
            values = list(self.receivers.self_attribute_values(owner, owner.attr))
        else:
            return None
        return self._class_of_values(values)

    def reaching_instance_class(self, owner: ast.expr) -> str | None:
        """``instance_class`` of the value a read of a name gets where the flow tells the
        bindings apart (``env = Car()``, ``env.seed(s)``, then ``env = Monitor(env)``: the
        seed call gets the car, as the rewriting rules see it); ``instance_class`` otherwise."""
        if isinstance(owner, ast.Name):
            values = self._reaching_values(owner)
            if values:
                return self._class_of_values(values)
        return self.instance_class(owner)

    def _class_of_bindings(self, bindings: list[ast.AST]) -> str | None:
        values = []
        for binding in bindings:
            parent = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
            if not isinstance(parent, ast.Assign):
                return None
            values.append(parent.value)
        return self._class_of_values(values)

    def _class_of_values(self, values: list[ast.expr]) -> str | None:
        classes = {self.instance_class(v) if isinstance(v, ast.Call) else None for v in values}
        return classes.pop() if len(classes) == 1 else None

    def _arguments(self, call: ast.Call, target: str) -> CallSummary:
        args: list[Kind] = []
        open_ended = False
        for argument in call.args:
            if isinstance(argument, ast.Starred):
                open_ended = True
                break
            args.append(self._kind(argument))
        keywords = []
        for keyword in call.keywords:
            if keyword.arg is None:
                open_ended = True
            else:
                keywords.append((keyword.arg, self._kind(keyword.value)))
        ids = [(str(i), text) for i, a in enumerate(call.args) if (text := self._env_id(a)) is not None]
        ids += [(k.arg, text) for k in call.keywords if k.arg is not None and (text := self._env_id(k.value)) is not None]
        thunks = [(str(i), self._thunks_kind(a)) for i, a in enumerate(call.args) if self.receivers.is_thunk_list(a)]
        thunks += [(k.arg, self._thunks_kind(k.value)) for k in call.keywords if k.arg is not None and self.receivers.is_thunk_list(k.value)]
        listed = [(str(i), a) for i, a in enumerate(call.args)] + [(k.arg, k.value) for k in call.keywords if k.arg is not None]
        stacks = [(slot, stack) for slot, a in listed if self.receivers.is_thunk_list(a) and (stack := self._thunks_stack(a)) is not None]
        flow = Flow.of(self.facts)
        positional = [(str(i), a) for i, a in enumerate(call.args[: len(args)])]  # up to a starred one
        slots = positional + [(k.arg, k.value) for k in call.keywords if k.arg is not None]
        made = [(slot, *found) for slot, value in slots if (found := handed_make(self.facts, value, call, self._is_run_call)) is not None]
        sources = [(slot, source) for slot, a in slots if isinstance(a, ast.Name) and (source := flow.source_of(a)) is not None]
        items = [(slot, kind) for slot, a in slots if (kind := self._items_kind(a)) is not None]
        creators = [(slot, kind) for slot, a in slots if (kind := self._creator(a, 0)) is not None]
        holders = [(slot, held) for slot, a in slots if (held := self._instance_of_run_class(a)) is not None]
        return CallSummary(
            target,
            tuple(args),
            tuple(keywords),
            open_ended,
            tuple(ids),
            getattr(call, "lineno", 0),
            tuple(thunks),
            made=tuple(made),
            sources=tuple(sources),
            items=tuple(items),
            creators=tuple(creators),
            thunk_stacks=tuple(stacks),
            holders=tuple(holders),
            up=isinstance(call.func, ast.Attribute) and self._super_base(call.func.value) is not None,
        )

    def _instance_of_run_class(self, argument: ast.expr) -> str | None:
        """The class of the run ``argument`` is an instance of (``CallSummary.holders``):
        ``@Name`` for a top-level class of this module, the qualified name of one it imports;
        ``Holder(name)``, or a name every binding reaching the call builds one. None otherwise."""
        values = self._reaching_values(argument) if isinstance(argument, ast.Name) else [argument]
        return self._run_class_of(values or ())

    def _run_class_of(self, values: Iterable[ast.expr]) -> str | None:
        """The one class of the run every value is a construction of: ``@Name`` for a
        top-level class of this module, the qualified name of one it imports. None otherwise."""
        classes: set[str] = set()
        for value in values:
            if not isinstance(value, ast.Call):
                return None
            local = self.receivers.local_class(value.func)
            if local is not None:
                if self.facts.classes.get(local.name) is not local:
                    return None
                classes.add(OWN + local.name)
                continue
            found = [q for q in self.facts.qualified_names(value.func) if not N.is_library(q)]
            if len(found) != 1 or "." not in found[0]:
                return None
            classes.add(found[0])
        return classes.pop() if len(classes) == 1 else None

    def _creator(self, argument: ast.expr, depth: int) -> Kind | None:
        """What calling ``argument`` gives, where it is a creator handed on (``CallSummary.creators``):
        a class or def (a kind this module settles, ``ref:`` for one of another module of the
        run), a lookup in a closed table of them (``table:`` for a table of another module), a
        name bound once to one of those, or a parameter of the calling def (``param:``). None
        for anything else."""
        if isinstance(argument, ast.Name):
            bindings = self.facts.bindings_of(argument)
            if len(bindings) == 1 and isinstance(bindings[0], ast.arg):
                return self._parameter_of_def(argument)
            values = self.facts.assigned_values(argument, sole_target=True)
            if values is not None and len(values) == 1 and depth < 3:
                return self._creator(values[0], depth + 1)
        if isinstance(argument, ast.Subscript):
            found = lookup(self.facts, argument)
            if found is None or found[1] is not None:
                return None
            if isinstance(found[0], ast.Name) and table_display(self.facts, found[0]) is not None:
                kind = self.receivers.returned_kind(argument)
                return kind if kind is not EnvKind.UNKNOWN else None
            qualified = self.facts.qualified_names(found[0])
            return TABLE + qualified.pop() if len(qualified) == 1 and not N.is_library(next(iter(qualified))) else None
        if not isinstance(argument, (ast.Name, ast.Attribute)):
            return None
        if self.receivers.local_class(argument) is not None or self.receivers.local_function(argument) is not None:
            kind = self.receivers.returned_kind(argument)
            return kind if kind is not EnvKind.UNKNOWN else None
        qualified = self.facts.qualified_names(argument)
        if len(qualified) != 1:
            return None
        name = next(iter(qualified))
        if not N.is_library(name):
            return REF + name
        return self.receivers.kind_from_qualified(name, _NO_ARGUMENTS)  # ``gym.make``, a Gym env class

    def _items_kind(self, argument: ast.expr) -> Kind | None:
        """The one kind of every item of a list argument the module shows (``[Vec(fns) for
        l in range(n)]``, or ``self.envs`` bound to it); None for anything else, items of
        several kinds, or items that are no env at all (a list of thunks says what calling
        them gives: ``CallSummary.thunks``)."""
        if self.receivers.kind_of(argument) is not EnvKind.NOT_ENV:
            return None
        values = self.receivers.item_values(argument)
        if not values:
            return None
        kinds = {self._kind(value) for value in values}
        kind = kinds.pop() if len(kinds) == 1 else None
        return None if kind in (None, EnvKind.NOT_ENV, EnvKind.UNKNOWN) else kind

    def _is_run_call(self, call: ast.Call) -> bool:
        """A call of another module of the run that the join resolves (not this module's own
        def, not a method of an unknown owner)."""
        target = self._target(call.func)
        return target is not None and not target.startswith((OWN, UNRESOLVED))

    def _thunks_kind(self, argument: ast.expr) -> Kind:
        """What calling each item of a list of thunks returns; ``ref:<qualified>`` when they
        are all calls of one def imported from the run, which the join asks."""
        imported = self.receivers.imported_thunk_factory(argument)
        if imported is not None and not N.is_library(imported):
            return REF + imported
        kind = self.receivers.thunk_list_kind(argument)
        if kind is EnvKind.UNKNOWN and (own := self.receivers.own_thunk_factory(argument)) is not None:
            # ``[make_env(i) ...]`` with this module's ``make_env`` whose thunks build a class
            # of another module of the run: the join says what that class is
            return REF + OWN + own
        return kind

    def _thunks_stack(self, argument: ast.expr) -> str | None:
        """The Gym-only stack every item of a list of thunks makes an env of; ``ref:<qualified>``
        when every env they return is made by one def of another module of the run, whose
        stack the join asks (``ModuleSummary.gym_only_makers``)."""
        stack = self.receivers.thunk_list_stack(argument)
        if stack is not None:
            return stack
        maker = self.receivers.thunk_list_maker(argument)
        return REF + maker if maker is not None and not N.is_library(maker) else None

    def _env_id(self, argument: ast.expr) -> str | None:
        """An env id the argument certainly is: a literal ``"Name-v4"``, or a module-level
        name bound once to one (``ENV = "PongNoFrameskip-v4"``)."""
        if isinstance(argument, ast.Name):
            bindings = self.facts.module_scope.bindings.get(argument.id, [])
            if self.facts.bindings_of(argument) != bindings or len(bindings) != 1:
                return None
            assign = self.facts.parent(bindings[0])
            if not (isinstance(assign, ast.Assign) and assign.targets == [bindings[0]]):
                return None
            argument = assign.value
        text = string_value(argument) if isinstance(argument, ast.Constant) else None
        return text if text is not None and _ENV_ID.fullmatch(text) else None

    def _kind(self, argument: ast.expr) -> Kind:
        """The argument's kind; ``new:agent.GridEnv`` for an instance of a class this
        module imports, which the join resolves against the env classes of the run."""
        kind = self.receivers.kind_of(argument)
        kept = self.receivers.legacy_step_class(argument) if kind is EnvKind.GYM_ENV else None
        if kept is not None and self.facts.classes.get(kept) is not None:
            # An instance of this module's class whose step and reset keep their own contract:
            # ``new:@Name`` resolves to the kind the class has, and tells the def it is given
            # to that its calls keep that contract (``ProjectFacts.kept_params``).
            return NEW + OWN + kept
        if kind is EnvKind.NOT_ENV and self._env_like_instance(argument, 0):
            # The project's own reset/step object (``Holder(Board())``): not NOT_ENV, which
            # a Gym env passed by another caller outweighs in the join; the def is asked about.
            return EnvKind.OWN_API
        if kind is EnvKind.UNKNOWN and isinstance(argument, ast.Call):
            found = [q for q in self.facts.qualified_names(argument.func) if not N.is_library(q)]
            if len(found) == 1:
                return NEW + found[0]
            own = self._own_factory(argument.func)
            if own is not None:
                return NEW + own  # ``Holder(create_env(name))``: what the run says ``create_env`` gives
        if kind is EnvKind.UNKNOWN and isinstance(argument, ast.Attribute):
            held = self._held_attribute(argument)
            if held is not None:
                return held  # ``evaluate(policy, self.test_env)``: what the class's constructions pass
        if kind is EnvKind.UNKNOWN and isinstance(argument, ast.Name):
            parameter = self._parameter_of_def(argument)
            if parameter is not None:
                return parameter
            made = self._made_by_run_call(argument) or self._made_by_passed_class(argument) or self._made_here_or_by_run(argument)
            if made is not None:
                return NEW + made  # ``env = pkg.make_benchmark(...)``; ``run(env)``
        return kind

    def _made_by_passed_class(self, name: ast.Name) -> str | None:
        """``env_instance = env_class(config)`` in a top-level def that this module's every
        call passes classes imported from the run for ``env_class`` (``test(env_class=
        TradeEnv)``): those classes' names, joined by ``|``, for the join to resolve."""
        bindings = self.facts.bindings_of(name)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.Name):
            return None
        statement = self.facts.parent(bindings[0])
        if not (isinstance(statement, ast.Assign) and statement.targets == [bindings[0]] and isinstance(statement.value, ast.Call)):
            return None
        func = statement.value.func
        params = self.facts.bindings_of(func) if isinstance(func, ast.Name) else []
        if len(params) != 1 or not isinstance(params[0], ast.arg):
            return None
        param = params[0]
        function = self.facts.parent(self.facts.parent(param))
        if not isinstance(function, FUNCTIONS) or self.facts.functions.get(function.name) is not function:
            return None  # a top-level def: its call sites are this module's own
        if function.args.vararg is not None or function.args.kwarg is not None:
            return None
        positional = [*function.args.posonlyargs, *function.args.args]
        position = next((i for i, p in enumerate(positional) if p is param), None)
        found: set[str] = set()
        calls = self.receivers.call_sites(function, None)
        for call in calls:
            argument = call_argument(call, position, param.arg)
            if argument is None:
                return None
            qualified = [q for q in self.facts.qualified_names(argument) if not N.is_library(q)]
            if len(qualified) != 1 or "." not in qualified[0]:
                return None
            found.add(qualified[0])
        return "|".join(sorted(found)) if found else None

    def _made_by_run_call(self, name: ast.Name) -> str | None:
        """The names of the run (imported, no library's) the bindings of ``name`` call,
        joined by ``|``: ``env = nasim.make_benchmark(...)``, or ``env = AtariEnvironment(args)``
        in one branch and ``env = Environment(gym.make(id))`` in the other; None when a
        binding calls anything else."""
        values = self._reaching_values(name)
        if values is None:
            return None
        found: set[str] = set()
        for value in values:
            if not isinstance(value, ast.Call):
                return None
            qualified = [q for q in self.facts.qualified_names(value.func) if not N.is_library(q)]
            if len(qualified) != 1 or "." not in qualified[0]:
                own = self._own_factory(value.func)
                if own is None:
                    return None
                qualified = [own]
            found.add(qualified[0])
        return "|".join(sorted(found)) if found else None

    def _reaching_values(self, name: ast.Name) -> list[ast.expr] | None:
        """The values of the ``name = ...`` bindings that may reach this read of ``name``
        (``env = Car()`` then ``env = Recorder(env)``: the read in ``Recorder(env)`` gets the
        car, a read after it the recorder); every binding's where the flow cannot tell them
        apart; None when one binds it otherwise."""
        reaching = Flow.of(self.facts).reaching(name)
        if not reaching:
            return self.facts.assigned_values(name, sole_target=True)
        values: list[ast.expr] = []
        for binding in reaching:
            parent = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
            if not (isinstance(parent, ast.Assign) and parent.targets == [binding]):
                return None
            values.append(parent.value)
        return values

    def _made_here_or_by_run(self, name: ast.Name) -> str | None:
        """``env = gym.make(...)`` in some branches and ``env = Reacher()`` (a class of
        another module of the run) in others: the run's names joined by ``|`` with the kinds
        this module settles itself (``=GYM_ENV``), for the join to resolve as one; None when
        a binding is anything else, or when no binding calls a name of the run."""
        found = self._makers(name)
        if found is None:
            return None
        made, known = found
        return "|".join(sorted(made) + sorted(known)) if made and known else None

    def reaching_makers(self, name: ast.Name) -> str | None:
        """What made the values that reach this read of ``name``, for the join to resolve
        as one: the run's names (``A()`` in one branch, ``B()`` in another) joined by ``|``
        with the kinds this module settles itself (``=GYM_ENV``); None when a value is
        anything else, or when no value calls a name of the run."""
        found = self._makers(name)
        if found is None or not found[0]:
            return None
        made, known = found
        return "|".join(sorted(made) + sorted(known))

    def _makers(self, name: ast.Name) -> tuple[set[str], set[str]] | None:
        """(the run's names, the kinds settled here) of the values reaching ``name``."""
        values = self._reaching_values(name)
        if values is None:
            return None
        made: set[str] = set()
        known: set[str] = set()
        for value in values:
            kind = self.receivers.kind_of(value)
            if kind is not EnvKind.UNKNOWN:
                known.add(KNOWN + kind.name)
                continue
            if not isinstance(value, ast.Call):
                return None
            qualified = [q for q in self.facts.qualified_names(value.func) if not N.is_library(q)]
            own = self._own_factory(value.func) if len(qualified) != 1 or "." not in qualified[0] else None
            if own is None and (len(qualified) != 1 or "." not in qualified[0]):
                return None
            made.add(own or qualified[0])
        return made, known

    def _env_like_instance(self, value: ast.expr, depth: int) -> bool:
        """An instance of a plain class of this module with a reset or step of its own:
        ``Board()``, a name bound to one, or a def of this module returning one."""
        if depth > 4:
            return False
        if isinstance(value, ast.Name):
            bindings = self.facts.bindings_of(value)
            statements = [self.facts.parent(b) for b in bindings if isinstance(b, ast.Name)]
            values = [s.value for s in statements if isinstance(s, ast.Assign)]
            return bool(values) and len(values) == len(bindings) and any(self._env_like_instance(v, depth + 1) for v in values)
        if not isinstance(value, ast.Call):
            return False
        classdef = self.receivers.local_class(value.func)
        if classdef is not None:
            return self.receivers.class_kind(classdef) is EnvKind.NOT_ENV and any(
                isinstance(s, FUNCTIONS) and s.name in ("reset", "step") for s in classdef.body
            )
        function = self.receivers.local_function(value.func)
        return function is not None and any(
            r.value is not None and self._env_like_instance(r.value, depth + 1) for r in own_returns(function)
        )

    def _own_factory(self, func: ast.expr) -> str | None:
        """``@create_env`` for a top-level def of this module whose returns its own module
        cannot classify (``return wrappers.wrap(wrappers.make_atari(name))``, calls of
        another module of the run), or a top-level class of it whose bases are another
        module's (``class Pusher(MujocoEnv, MultitaskEnv)``): the join knows what calling it
        gives (``call_kinds``)."""
        function = self.receivers.local_function(func)
        if function is not None:
            return OWN + function.name if self.facts.functions.get(function.name) is function else None
        classdef = self.receivers.local_class(func)
        if classdef is None or self.facts.classes.get(classdef.name) is not classdef:
            return None
        return OWN + classdef.name

    def _held_attribute(self, attribute: ast.Attribute) -> str | None:
        """``held:Trainer.__init__:test_env`` for ``self.test_env`` read in a method of a
        top-level plain class that stores it only from that ``__init__`` parameter
        (``ModuleSummary.held_params``), when ``self`` is an instance of that class alone: no
        class here derives from it and the module hands the class on nowhere (its
        constructions are the calls the join sees). The join gives it what those pass."""
        owner = attribute.value
        if not (isinstance(owner, ast.Name) and self.receivers.is_self(owner)):
            return None
        classdef = self.facts.enclosing_class(attribute)
        if classdef is None or self.facts.classes.get(classdef.name) is not classdef:
            return None
        held = self.facts.memo(("held-params", 0), lambda: held_params(self.facts, self.receivers))
        param = held.get(classdef.name, {}).get(attribute.attr)
        if param is None:
            return None
        if any(self.receivers.local_class(base) is classdef for other in self.facts.all_classes for base in other.bases):
            return None  # a subclass here may be built with arguments the join does not see
        if self.receivers.constructions(classdef)[1]:
            return None  # the class escapes under another name
        return f"{HELD}{classdef.name}.__init__:{param}"

    def _parameter_of_def(self, name: ast.Name) -> str | None:
        """``param:Agent.fit:env`` when ``name`` is only ever the parameter ``env`` of a def
        the summary lists: the join gives it the kinds the run passes there."""
        bindings = self.facts.bindings_of(name)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.arg):
            return None
        function = self.facts.parent(self.facts.parent(bindings[0]))
        if not isinstance(function, FUNCTIONS):
            return None
        holder = self.facts.parent(function)
        if holder is self.facts.tree:
            qualname = function.name
        elif isinstance(holder, ast.ClassDef) and self.facts.parent(holder) is self.facts.tree:
            qualname = f"{holder.name}.{function.name}"
        else:
            return None
        return f"{PARAM}{qualname}:{name.id}"
