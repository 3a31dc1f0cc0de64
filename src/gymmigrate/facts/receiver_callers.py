"""Which calls of a module reach a def: the call sites of a function or a method
(``call_sites``), what a called name holds when it is a construction
(``called_instances``), and the calls that run a class's ``__init__``, its subclasses'
included (``constructions``), with whether the class escapes under another name.

Separate from ``receiver_params.py`` because it answers a question about calls, not about
kinds: what a parameter holds (``receiver_params.py``), what a sequence of thunks returns
(``receiver_thunks.py``), which classes are made where (``receiver_classes.py``) and the
rules that follow a def's arguments all ask it. Part of ``Receivers`` (through
``ParameterKinds``).
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING, cast

from gymmigrate.facts.creator_tables import entries, lookup, table_display
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import FUNCTIONS, call_argument, is_super_call
from gymmigrate.facts.receiver_classes import is_object

if TYPE_CHECKING:
    from gymmigrate.facts.kinds import ReceiverFacade as _Facade
else:
    _Facade = object


class CallerSites(_Facade):
    """The calls that reach a def or build a class (part of ``Receivers``)."""

    def constructions(self, classdef: ast.ClassDef, _seen: frozenset[int] = frozenset()) -> tuple[list[tuple[ast.Call, int]], bool]:
        """The calls of this module that run ``classdef.__init__``, each with how far its
        positional arguments are shifted (1 for ``Base.__init__(self, env)``): the class's own
        calls, the calls of subclasses here that inherit ``__init__``, and the
        ``super().__init__(...)`` / ``Base.__init__(self, ...)`` of subclasses that define
        their own. The flag says another module of the run subclasses it (its calls are not
        known here)."""
        found: list[tuple[ast.Call, int]] = [(call, 0) for call in self.facts.calls_by_name.get(classdef.name, [])]
        elsewhere = (
            self.project is not None
            and self.facts.parent(classdef) is self.facts.tree
            and self.project.subclassed_elsewhere(classdef.name)
            and not self.project.built_through_super_elsewhere(classdef.name)
        )
        for sub in self.facts.classes.values():
            if sub is classdef or id(sub) in _seen or not any(self.local_class(b) is classdef for b in sub.bases):
                continue
            own_init = any(isinstance(s, FUNCTIONS) and s.name == "__init__" for s in sub.body)
            if not own_init:
                inherited, far = self.constructions(sub, _seen | {id(classdef)})
                found += inherited
                # A subclass built in another module (or, with no run to ask, one never built
                # here: other modules may build it) passes arguments this module cannot see.
                if self.project is None:
                    far = far or not inherited
                else:
                    far = far or self.project.built_elsewhere(sub.name)
                elsewhere = elsewhere or far
                continue
            first_base = next((b for b in sub.bases if not is_object(b)), None)
            for call in self.facts.attribute_calls.get("__init__", []):
                if self.facts.enclosing_class(call) is not sub:
                    continue
                owner = call.func.value  # type: ignore[attr-defined]
                if is_super_call(owner):
                    if first_base is not None and self.local_class(first_base) is classdef:
                        found.append((call, 0))
                elif isinstance(owner, ast.Name) and self.local_class(owner) is classdef:
                    found.append((call, 1))  # ``Base.__init__(self, env)``
        # ``Wrapper = DummyVecEnv`` in a def, then only ``Wrapper(envs)``: those calls build it
        # too. ``make(cls=DummyVecEnv)``, an alias passed on or kept at module level: the
        # class is built with arguments the module does not show.
        aliased = self._alias_constructions(classdef)
        if aliased is None:
            return found, True
        return found + [(call, 0) for call in aliased if all(call is not c for c, _ in found)], elsewhere

    def _alias_constructions(self, classdef: ast.ClassDef) -> list[ast.Call] | None:
        """The calls of the class under a def's local alias (``Wrapper = DummyVecEnv``, or
        ``Wrapper = DummyVecEnv if one else SubprocVecEnv``, every read of ``Wrapper`` that
        binding reaches a call of it); None when the module reads the class's name as any
        other value than such an alias, a call, a base, an ``isinstance``/``issubclass``
        argument, an attribute owner or an annotation."""
        return self.facts.memo(("class-alias-calls", id(classdef)), lambda: self._aliases(classdef))

    def _aliases(self, classdef: ast.ClassDef) -> list[ast.Call] | None:
        facts = self.facts
        calls: list[ast.Call] = []
        for node in facts.reads_of(classdef.name):
            alias = self._local_alias_calls(node)
            if alias is not None:
                calls += alias
                continue
            if self._read_escapes(node):
                return None
        return calls

    def _local_alias_calls(self, node: ast.Name) -> list[ast.Call] | None:
        """``Alias = node`` (maybe as a branch of a conditional value) assigned alone to a
        name local to a def, every read of which that binding reaches is the callee of a
        call: those calls. None for any other read."""
        facts = self.facts
        value: ast.AST = node
        parent = facts.parent(node)
        if isinstance(parent, ast.IfExp) and node is not parent.test:
            value, parent = parent, facts.parent(parent)
        if not (isinstance(parent, ast.Assign) and parent.value is value and len(parent.targets) == 1 and isinstance(parent.targets[0], ast.Name)):
            return None
        target = parent.targets[0]
        if facts.enclosing_function(target) is None or facts.scope_of(target) is facts.module_scope:
            return None  # a module-level alias: other modules may import it and build the class
        if facts.resolve(target.id, facts.scope_of(target))[0] is not facts.scope_of(target):
            return None  # ``global`` or ``nonlocal``: bound in another scope
        calls = []
        for read in facts.reads_of(target.id, target):
            call = facts.parent(read)
            if not (isinstance(call, ast.Call) and call.func is read):
                return None
            calls.append(call)
        return calls

    def _read_escapes(self, node: ast.Name) -> bool:
        facts = self.facts
        parent = facts.parent(node)
        if isinstance(parent, ast.Call) and parent.func is node:
            return False
        if isinstance(parent, ast.ClassDef) and node in parent.bases:
            return False
        if isinstance(parent, ast.Attribute):  # ``DummyVecEnv.__init__(self, ...)``, class constants
            return False
        if isinstance(parent, (ast.Tuple, ast.Call)):
            call = facts.parent(parent) if isinstance(parent, ast.Tuple) else parent
            if isinstance(call, ast.Call) and isinstance(call.func, ast.Name) and call.func.id in ("isinstance", "issubclass", "type"):
                return False
            if (
                is_super_call(parent)
                and not facts.bindings_of(cast(ast.Name, parent.func))  # is_super_call saw the name
                and parent.args[:1] == [node]
            ):
                return False  # ``super(Recorder, self).__init__()``: names where lookup starts, builds nothing
        return not _in_annotation(node, facts)

    def call_sites(self, function: ast.AST, classdef: ast.ClassDef | None) -> list[ast.Call]:
        """Calls in this module that reach ``function`` (a method when ``classdef`` is given)."""
        name = function.name  # type: ignore[attr-defined]
        if classdef is None:
            calls = self.facts.calls_by_name.get(name, [])
            module = self.facts.module_scope
            defs = [b for b in module.bindings.get(name, ()) if isinstance(b, FUNCTIONS)]
            if self.facts.parent(function) is self.facts.tree and (len(defs) > 1 or self.facts.functions.get(name) is not function):
                # A def the module defines again (a notebook's cells, run in order): a call of
                # the module's own code reaches the def bound where it runs, the one above it
                # in the text; a call inside a def runs whenever that def is called, so it may
                # reach any of them (``worker()`` calling ``run_episode`` defined in two cells).
                flow = Flow.of(self.facts)
                return [
                    c
                    for c in calls
                    if isinstance(c.func, ast.Name)
                    and self.facts.resolve(name, self.facts.scope_of(c.func))[0] is module
                    and (flow.last_binding_of(c.func) is function or not flow.same_frame(c.func, module))
                ]
            return [c for c in calls if self.local_function(c.func) is function]
        if name == "__init__":
            return list(self.facts.calls_by_name.get(classdef.name, []))
        if name == "__call__":
            # ``evaluate(env, policy)`` where ``evaluate`` holds an instance of the class (bound
            # to ``Evaluator(...)``, or a parameter every call of its def passes one).
            instances: list[ast.Call] = self.facts.memo(("instance-calls", id(classdef)), lambda: self._instance_calls(classdef))
        else:
            instances = []
        # ``self.train(env)`` in the class, and ``Agent().train(env)`` or ``algo.train(env)``
        # with ``algo = Agent()`` in the module: the instances the module makes itself.
        return [
            c
            for c in self.facts.attribute_calls.get(name, [])
            if (isinstance(c.func.value, ast.Name) and self.is_self(c.func.value))  # type: ignore[attr-defined]
            or self._made_instance_of(c.func.value, classdef, name)  # type: ignore[attr-defined]
            or self._unwrapped_of(c.func.value, classdef)  # type: ignore[attr-defined]
        ] + instances

    def argument_sources(self, param: ast.arg, _seen: frozenset[int] = frozenset()) -> frozenset[str] | None:
        """The variables the calls of the run hand on for ``param`` (``Flow.source_of``, each
        with its module), when every call hands on one; None when a call passes anything else
        or leaves the parameter to its default, or when no call is known. Parameters fed only
        the same variables hold the same values: what those are is one question. A call
        handing on a parameter of another def of the module (``helper(env)`` in ``search(env)``)
        passes what that parameter is fed, where its calls are known: the two defs hold one
        object, and ask one question."""
        if _seen:
            return self._argument_sources(param, _seen)
        return self.facts.memo(("argument-sources", id(param)), lambda: self._argument_sources(param, _seen))

    def _table_calls(self, function: ast.AST, classdef: ast.ClassDef | None) -> list[ast.Call]:
        """``SEARCHES[name](env)`` where ``SEARCHES`` is a closed table of this module that
        holds the module-level def ``function``: a call that may reach it, with the same
        arguments as every other def of the table."""
        if classdef is not None or self.facts.functions.get(function.name) is not function:  # type: ignore[attr-defined]
            return []
        found = []
        for call in self.facts.lookup_calls:
            table = lookup(self.facts, cast(ast.Subscript, call.func))
            if table is None or table[1] is not None or not isinstance(table[0], ast.Name):
                continue
            display = table_display(self.facts, table[0])
            values = entries(display, None) if display is not None else None
            if values and any(isinstance(v, ast.Name) and self.facts.bindings_of(v) == [function] for v in values):
                found.append(call)
        return found

    def _handed_parameter(self, argument: ast.Name, flow: Flow) -> ast.arg | None:
        """The parameter ``argument`` reads, where it is its one binding (a def's parameter
        the def never rebinds), else None."""
        bindings = flow.reaching(argument) or self.facts.bindings_of(argument)
        if len(bindings) == 1 and isinstance(bindings[0], ast.arg) and self.facts.bindings_of(argument) == bindings:
            return bindings[0]
        return None

    def _argument_sources(self, param: ast.arg, _seen: frozenset[int] = frozenset()) -> frozenset[str] | None:
        slot = self.facts.parameter_slot(param)
        if slot is None:
            return None
        function, classdef, position = slot
        if classdef is not None and function.name == "__init__":
            return None  # a constructor's calls are every construction of its class
        flow = Flow.of(self.facts)
        here = self.project.path if self.project is not None else ""
        found: set[str] = set()
        for call in [*self.call_sites(function, classdef), *self._table_calls(function, classdef)]:
            argument = call_argument(call, position, param.arg)
            source = flow.source_of(argument) if isinstance(argument, ast.Name) else None
            if source is None:
                return None
            handed = self._handed_parameter(argument, flow) if isinstance(argument, ast.Name) else None
            if handed is not None and id(handed) not in _seen and handed is not param:
                upstream = self.argument_sources(handed, _seen | {id(param)})
                if upstream is not None:
                    found.update(upstream)
                    continue
            found.add(f"{here}|{source}")
        owner = classdef if classdef is not None else function
        if self.project is not None and self.facts.parent(owner) is self.facts.tree:
            qualname = f"{classdef.name}.{function.name}" if classdef is not None else function.name
            external = self.project.param_sources(qualname, param.arg)
            if None in external:
                return None
            found.update(source for source in external if source is not None)
        return frozenset(found) or None

    def _instance_calls(self, classdef: ast.ClassDef) -> list[ast.Call]:
        found = []
        for calls in self.facts.calls_by_name.values():
            for call in calls:
                values = self.called_instances(call.func)
                if values and all(self._made_instance_of(v, classdef, "__call__") for v in values):
                    found.append(call)
        return found

    def called_instances(self, func: ast.expr) -> list[ast.expr]:
        """What a called name holds, where that is a construction: the values of a name
        every binding of which is an assignment of a call (``evaluate = Evaluator(3)``), or,
        for a parameter of a top-level def, those of the name (or the call) every call of the
        def in the module passes there (``train(env, evaluate)``). Empty when unclear."""
        if not isinstance(func, ast.Name):
            return []
        bindings = self.facts.bindings_of(func)
        if len(bindings) == 1 and isinstance(bindings[0], ast.arg):
            param = bindings[0]
            function = self.facts.parent(self.facts.parent(param))
            if not isinstance(function, FUNCTIONS) or self.facts.functions.get(function.name) is not function:
                return []
            positional = [*function.args.posonlyargs, *function.args.args]
            position = next((i for i, p in enumerate(positional) if p is param), None)
            values: list[ast.expr] = []
            for call in self.call_sites(function, None):
                argument = call_argument(call, position, param.arg)
                if argument is None:
                    return []
                found = self.facts.assigned_values(argument, sole_target=True) if isinstance(argument, ast.Name) else [argument]
                if not found or not all(isinstance(v, ast.Call) for v in found):
                    return []
                values.extend(found)
            return values
        found = self.facts.assigned_values(func, sole_target=True)
        return found if found is not None and all(isinstance(v, ast.Call) for v in found) else []

    def _unwrapped_of(self, owner: ast.AST, classdef: ast.ClassDef) -> bool:
        """``x.unwrapped.set_top(self)`` with ``set_top`` a method of this module's Gym env
        class: ``unwrapped`` is the env under every wrapper, and a method only the run's env
        classes define is theirs (a wrapper registering itself with the env it wraps)."""
        return (
            isinstance(owner, ast.Attribute)
            and owner.attr == "unwrapped"
            and not self.is_gym_wrapper_class(classdef)
            and self.class_kind(classdef) is EnvKind.GYM_ENV
        )

    def _made_instance_of(self, owner: ast.AST, classdef: ast.ClassDef, method: str) -> bool:
        """``owner`` is ``Cls(...)`` or a name every binding of which is ``Cls(...)``, with
        ``Cls`` this module's ``classdef`` or a subclass here that inherits ``method``."""
        if isinstance(owner, ast.Name):
            bindings = self.facts.bindings_of(owner)
            values = []
            for binding in bindings:
                assign = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
                if not (isinstance(assign, ast.Assign) and assign.targets == [binding]):
                    return False
                values.append(assign.value)
            return bool(values) and all(self._made_instance_of(v, classdef, method) for v in values)
        if not isinstance(owner, ast.Call):
            return False
        made = self.local_class(owner.func)
        seen: set[int] = set()
        while made is not None and made is not classdef and id(made) not in seen:
            seen.add(id(made))
            if any(isinstance(st, FUNCTIONS) and st.name == method for st in made.body):
                return False  # the subclass has a method of its own
            bases = [b for b in made.bases if not is_object(b)]
            made = self.local_class(bases[0]) if len(bases) == 1 else None
        return made is classdef


def _in_annotation(node: ast.AST, facts) -> bool:
    """``node`` sits in an annotation (of an argument, a return or an assignment)."""
    child, parent = node, facts.parent(node)
    while parent is not None and not isinstance(parent, ast.stmt):
        if isinstance(parent, ast.arg) and parent.annotation is child:
            return True
        child, parent = parent, facts.parent(parent)
    if isinstance(parent, ast.AnnAssign) and parent.annotation is child:
        return True
    if isinstance(parent, (ast.FunctionDef, ast.AsyncFunctionDef)) and parent.returns is child:
        return True
    return False
