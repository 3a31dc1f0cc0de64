"""What calling something returns, and what annotations say: the receiver analysis's
view of callables (``Receivers`` mixes this in).

``env = make_env()`` is a Gym env when ``make_env`` is a lambda or a def (nested ones
too) that returns one, a name bound to such a callable, ``functools.partial(gym.make,
...)``, a method of the same class (``self.make_env()``), or an ``env_fn`` parameter
annotated ``Callable[[], gym.Env]`` or given such callables at every call site.
Annotations count in every spelling real code uses: ``gym.Env``, ``"gym.Env"``,
``Optional[gym.Env]``, ``gym.Env | None``. Each answer is memoized per node, or per set
of bindings for names, so a factory called n times is followed once.
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.facts import names as N
from gymmigrate.facts.creation_shapes import argument_for
from gymmigrate.facts.creator_tables import entries, lookup, table_display
from gymmigrate.facts.kinds import (
    MAX_DEPTH,
    EnvKind,
    ReceiverQueries,
    agreed_kind,
    join_kinds,
)
from gymmigrate.facts.module import (
    FUNCTIONS,
    ModuleFacts,
    call_argument,
    own_returns,
    walk,
)

if TYPE_CHECKING:
    from gymmigrate.facts.project_view import ProjectView


class CallableKinds:
    """What calling a callable returns, for ``Receivers`` (which owns one and answers the
    kind questions it asks back). Also holds the hook of facts across files
    (``external_param_kinds``)."""

    def __init__(self, receivers: ReceiverQueries, project: ProjectView | None) -> None:
        self.receivers = receivers
        self.facts: ModuleFacts = receivers.facts
        self.project = project

    def own_method(self, func: ast.AST) -> ast.FunctionDef | ast.AsyncFunctionDef | None:
        """``self.make_env`` in a method (also ``self.__class__.make_env``,
        ``type(self).make_env``: a classmethod or staticmethod reached through the class of
        ``self``): the class's own ``def make_env``."""
        if not (isinstance(func, ast.Attribute) and self._is_self_or_its_class(func.value)):
            return None
        classdef = self.facts.enclosing_class(func)
        if classdef is None:
            return None
        methods = self.facts.memo(
            ("own-methods", id(classdef)), lambda: {s.name: s for s in classdef.body if isinstance(s, FUNCTIONS)}
        )
        return methods.get(func.attr)

    def _is_self_or_its_class(self, node: ast.expr) -> bool:
        if isinstance(node, ast.Attribute) and node.attr == "__class__":
            node = node.value
        elif (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Name)
            and node.func.id == "type"
            and len(node.args) == 1
            and not node.keywords
            and self.facts.resolve("type", self.facts.scope_of(node.func))[0] is None
        ):
            node = node.args[0]
        return isinstance(node, ast.Name) and self.receivers.is_self(node)

    def external_param_kinds(self, function: ast.AST, classdef: ast.ClassDef | None, param: str) -> list[EnvKind]:
        """What the other modules of the run pass for ``param`` (none when checked alone)."""
        if self.project is None:
            return []
        name = function.name  # type: ignore[attr-defined]
        if classdef is None:
            if self.facts.parent(function) is not self.facts.tree:
                return []
            return self.project.param_kinds(name, param)
        if self.facts.parent(classdef) is not self.facts.tree:
            return []
        return self.project.param_kinds(f"{classdef.name}.{name}", param)

    def external_item_kinds(self, function: ast.AST, classdef: ast.ClassDef | None, param: str) -> list[EnvKind]:
        """Per call from another module of the run, the kind of every item of the list it
        passes for ``param`` (``ProjectView.item_kinds``; none when checked alone)."""
        if self.project is None:
            return []
        name = function.name  # type: ignore[attr-defined]
        if classdef is None:
            return self.project.item_kinds(name, param) if self.facts.parent(function) is self.facts.tree else []
        return self.project.item_kinds(f"{classdef.name}.{name}", param) if self.facts.parent(classdef) is self.facts.tree else []

    def returned_kind(self, callee: ast.AST) -> EnvKind:
        """The kind of what calling ``callee`` returns: a lambda's body, the returns of a
        def, through names bound to either, and through parameters annotated
        ``Callable[[], gym.Env]`` or passed such callables at every call site."""
        return self.facts.memo(("returned-kind", id(callee)), lambda: self._returned_kind(callee), while_computing=EnvKind.UNKNOWN)

    def _returned_kind(self, callee: ast.AST) -> EnvKind:
        if self.receivers.depth > MAX_DEPTH:
            return EnvKind.UNKNOWN
        if isinstance(callee, ast.Lambda):
            return self.receivers.kind_of(callee.body)
        if isinstance(callee, FUNCTIONS):
            return self.receivers.returns_kind(callee)
        if isinstance(callee, ast.Call) and any(q in ("functools.partial",) for q in self.receivers.qualified_names(callee.func)) and callee.args:
            return self.kind_of_call_to(callee.args[0], callee)
        if isinstance(callee, ast.Call):
            # ``create = make_creator(params)`` then ``create()``: what the thunk it returns gives
            return self.receivers.called_factory_kind(callee)
        if isinstance(callee, ast.Subscript):
            table = self._table_returned_kind(callee)
            if table is not None:
                return table
            index = callee.slice
            if isinstance(callee.value, ast.Call) and isinstance(index, ast.Constant) and type(index.value) is int:
                # ``make_creator(params)[0]``: the thunk every return of the factory holds there
                item = self.receivers.called_item_kind(callee.value, index.value, None)
                if item is not EnvKind.UNKNOWN:
                    return item
            # ``self.env_fns[i]()``: what calling an item of the sequence returns
            return self._item_returned_kind(callee.value)
        if isinstance(callee, ast.Attribute):
            # ``make = gym.make`` then ``make(...)``: what the library callable returns.
            return self.kind_of_call_to(callee, _NO_ARGUMENTS) if self.receivers.qualified_names(callee) else EnvKind.UNKNOWN
        if not isinstance(callee, ast.Name):
            return EnvKind.UNKNOWN
        local = self.receivers.local_function(callee) or self.receivers.local_class(callee)
        if local is not None and isinstance(local, FUNCTIONS):
            return self.receivers.returns_kind(local)
        if local is not None:
            return self.receivers.class_kind(local)
        if self.receivers.qualified_names(callee):
            # An imported callable bound again (``make = gym.make``): what it returns.
            kinds = [k for k in (self.receivers.kind_from_qualified(q, _NO_ARGUMENTS) for q in self.receivers.qualified_names(callee)) if k is not None]
            if not kinds and self.project is not None:
                # ``run(env_class=TradeEnv)`` with the class imported from another module of
                # the run: what its instances are (``ProjectFacts.call_kinds``).
                kinds = [k for k in (self.project.call_kind(q) for q in self.receivers.qualified_names(callee)) if k is not None]
            return join_kinds(kinds) if kinds else EnvKind.UNKNOWN
        bindings = self.facts.bindings_of(callee)
        if not bindings:
            return EnvKind.UNKNOWN
        # One answer per set of bindings, not per call: ``make_env()`` called n times.
        return self.facts.memo(("returned-kind-bindings", id(bindings)), lambda: self._bindings_returned_kind(bindings), while_computing=EnvKind.UNKNOWN)

    def _table_returned_kind(self, callee: ast.Subscript) -> EnvKind | None:
        """``CREATORS[name](**cfg)``, ``ENVS[key]["make"]()``: what calling every value (or
        record's field) of a closed table of this module or of another module of the run
        returns (``facts/creator_tables.py``), when they all agree; None when ``callee`` reads
        no such table."""
        found = lookup(self.facts, callee)
        if found is None:
            return None
        table, field = found
        if isinstance(table, ast.Name):
            display = table_display(self.facts, table)
            if display is not None:
                values = entries(display, field)
                if values is None or (self.project is not None and self.project.table_altered(table.id)):
                    return EnvKind.UNKNOWN
                return agreed_kind(self.returned_kind(value) for value in values)
        if self.project is None:
            return None
        kinds = [k for k in (self.project.table_kind(q, field) for q in self.receivers.qualified_names(table)) if k is not None]
        return join_kinds(kinds) if kinds else None

    def _bindings_returned_kind(self, bindings: list[ast.AST]) -> EnvKind:
        kinds: list[EnvKind] = []
        self.receivers.depth += 1
        try:
            for binding in bindings:
                kinds.append(self._binding_returned_kind(binding))
        finally:
            self.receivers.depth -= 1
        return join_kinds(kinds)

    def kind_of_call_to(self, callee: ast.AST, call: ast.Call) -> EnvKind:
        """``functools.partial(gym.make, "CartPole-v1")``: the kind ``callee(...)`` returns."""
        kinds = [k for k in (self.receivers.kind_from_qualified(q, call) for q in self.receivers.qualified_names(callee)) if k is not None]
        if kinds:
            return join_kinds(kinds)
        return EnvKind.UNKNOWN if isinstance(callee, ast.Attribute) else self.returned_kind(callee)

    def _binding_returned_kind(self, binding: ast.AST) -> EnvKind:
        if isinstance(binding, FUNCTIONS):
            return self.receivers.returns_kind(binding)
        if isinstance(binding, ast.arg):
            return self._param_returned_kind(binding)
        parent = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
        if isinstance(parent, (ast.Assign, ast.NamedExpr)) or (isinstance(parent, ast.AnnAssign) and parent.value is not None):
            return self.returned_kind(parent.value)  # type: ignore[arg-type]
        if isinstance(parent, ast.Tuple) and not any(isinstance(e, ast.Starred) for e in parent.elts):
            assign = self.facts.parent(parent)
            if isinstance(assign, ast.Assign) and assign.targets == [parent]:
                return self._unpacked_returned_kind(assign.value, parent.elts.index(binding), len(parent.elts))  # type: ignore[arg-type]
        if isinstance(parent, ast.AnnAssign):
            return self.callable_annotation_kind(parent.annotation)
        container = self.loop_container(binding)
        if container is not None:
            return self._item_returned_kind(container)
        return EnvKind.UNKNOWN

    def loop_container(self, binding: ast.AST) -> ast.expr | None:
        """The sequence a loop variable takes its items from: ``env_fns`` for ``fn`` in ``for
        fn in env_fns`` (a comprehension too) and in ``for remote, fn in zip(remotes,
        env_fns)``. None for any other binding."""
        parent = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
        if isinstance(parent, (ast.For, ast.comprehension)) and parent.target is binding:
            return parent.iter
        if isinstance(parent, ast.Tuple) and not any(isinstance(e, ast.Starred) for e in parent.elts):
            # ``for remote, fn in zip(remotes, env_fns)``: an item of the zipped sequence
            loop = self.facts.parent(parent)
            if isinstance(loop, (ast.For, ast.comprehension)) and loop.target is parent:
                iterable, index = loop.iter, parent.elts.index(binding)  # type: ignore[arg-type]
                if (
                    isinstance(iterable, ast.Call)
                    and isinstance(iterable.func, ast.Name)
                    and iterable.func.id == "zip"
                    and not self.facts.bindings_of(iterable.func)
                    and not iterable.keywords
                    and index < len(iterable.args)
                    and not any(isinstance(a, ast.Starred) for a in iterable.args)
                ):
                    return iterable.args[index]
        return None

    def thunk_list_param(self, callee: ast.expr) -> ast.arg | None:
        """The unannotated parameter holding the list of thunks that ``callee`` is an item of
        (``fn`` in ``for fn in env_fns``, or zipped with others), where its calls pass lists
        of thunks (``Receivers.thunks_returned_kind``); None for anything else."""
        if not isinstance(callee, ast.Name):
            return None
        bindings = self.facts.bindings_of(callee)
        container = self.loop_container(bindings[0]) if len(bindings) == 1 else None
        if not isinstance(container, ast.Name):
            return None
        params = self.facts.bindings_of(container)
        return params[0] if len(params) == 1 and isinstance(params[0], ast.arg) and params[0].annotation is None else None

    def held_callable_kind(self, attr: ast.Attribute) -> EnvKind:
        """``env = env_fn_wrapper.x()`` in ``def worker(remote, env_fn_wrapper)``, a def this
        module only hands to ``Process(target=worker, args=(..., Holder(fn)))`` (or calls):
        what calling the callable that a class of the module stores on ``x`` from its
        constructor parameter returns, for every such call. Unknown otherwise."""
        stored = self.held_values(attr)
        if stored is None:
            return EnvKind.UNKNOWN
        kinds = [self.returned_kind(value) for value in stored]
        return join_kinds(kinds) if EnvKind.UNKNOWN not in kinds else EnvKind.UNKNOWN

    def held_value_kind(self, attr: ast.Attribute) -> EnvKind:
        """``env = env_fn_wrapper.x`` in such a worker, where the holder carries the env itself
        (``Process(target=worker, args=(..., Holder(gym.make(...))))``): the kind of what every
        spawn or call stores there. Unknown otherwise."""
        stored = self.held_values(attr)
        if stored is None:
            return EnvKind.UNKNOWN
        kinds = [self.receivers.kind_of(value) for value in stored]
        return join_kinds(kinds) if EnvKind.UNKNOWN not in kinds else EnvKind.UNKNOWN

    def held_values(self, attr: ast.Attribute) -> list[ast.expr] | None:
        """What the holder parameter of such a worker carries on ``attr``, for every call or
        spawn of the worker (``held_callable_kind``); None when one is not shown."""
        holder = attr.value
        if not isinstance(holder, ast.Name):
            return None
        bindings = self.facts.bindings_of(holder)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.arg):
            return None
        param = bindings[0]
        function = self.facts.parent(self.facts.parent(param))
        if not isinstance(function, FUNCTIONS) or self.facts.parent(function) is not self.facts.tree:
            return None
        if self.external_param_kinds(function, None, param.arg):
            return None  # called from other modules too
        params = [*function.args.posonlyargs, *function.args.args]
        if param not in params:
            return None
        position = params.index(param)
        direct = self.receivers.call_sites(function, None)
        spawns = self._spawns_of(function)
        # Every read of the def is one of those calls or spawns: a def handed elsewhere
        # (``pool.map(worker, ...)``, ``Process(target=worker, kwargs=...)``) gets arguments
        # the module does not show.
        uses = {id(c.func) for c in direct} | {id(target) for _, target, _ in spawns}
        if any(id(read) not in uses for read in self.facts.reads_of(function.name, function)):
            return None
        arguments: list[ast.expr | None] = [call_argument(c, position, param.arg) for c in direct]
        for _, _, handed in spawns:
            if not isinstance(handed, ast.Tuple) or any(isinstance(e, ast.Starred) for e in handed.elts):
                return None
            arguments.append(handed.elts[position] if position < len(handed.elts) else None)
        if not arguments:
            return None
        found = []
        for argument in arguments:
            stored = self._stored_by_holder(argument, attr.attr)
            if stored is None:
                return None
            found.append(stored)
        return found

    def _spawns_of(self, function: ast.AST) -> list[tuple[ast.Call, ast.expr, ast.expr | None]]:
        """Calls handing ``function`` on as the target of a process or thread, each with the
        read of the def and what it passes as the target's arguments (None when not a
        tuple the call shows): ``Process(target=worker, args=(...))`` (any callee: these two
        keywords), and ``Process(None, worker, None, (...))`` on ``multiprocessing``'s or
        ``threading``'s own classes (``ctx.Process`` of ``get_context(...)`` too). The
        module's calls are walked once per def."""
        return self.facts.memo(("spawns-of", id(function)), lambda: self._find_spawns(function))

    def _find_spawns(self, function: ast.AST) -> list[tuple[ast.Call, ast.expr, ast.expr | None]]:
        found = []
        # ``Process(...)`` and ``mp.Process(...)``/``ctx.Process(...)`` alike
        for calls in (*self.facts.calls_by_name.values(), *self.facts.attribute_calls.values()):
            for call in calls:
                positional = self._spawner(call.func) and not any(isinstance(a, ast.Starred) for a in call.args)
                target = next((k.value for k in call.keywords if k.arg == "target"), None)
                if target is None and positional and len(call.args) > 1:
                    target = call.args[1]
                if target is None or self.receivers.local_function(target) is not function:
                    continue
                handed = next((k.value for k in call.keywords if k.arg == "args"), None)
                if handed is None and positional and len(call.args) > 3:
                    handed = call.args[3]
                if handed is None and not positional and not any(k.arg == "kwargs" for k in call.keywords):
                    continue  # ``target=`` of a call of no known signature, no ``args=``: not a spawn
                found.append((call, target, handed))
        return found

    def _spawner(self, func: ast.expr) -> bool:
        """``Process``/``Thread`` of ``multiprocessing``, ``torch.multiprocessing`` or
        ``threading`` (``group, target, name, args`` by position), or ``ctx.Process`` with
        ``ctx`` bound only to ``multiprocessing.get_context(...)``."""
        if self.receivers.qualified_names(func) & _SPAWNERS:
            return True
        if not (isinstance(func, ast.Attribute) and func.attr == "Process" and isinstance(func.value, ast.Name)):
            return False
        values = self.facts.assigned_values(func.value, sole_target=True)
        return bool(values) and all(
            isinstance(v, ast.Call) and self.receivers.qualified_names(v.func) & _CONTEXTS for v in values  # type: ignore[union-attr]
        )

    def _stored_by_holder(self, argument: ast.expr | None, attribute: str) -> ast.expr | None:
        """``Holder(fn)`` with ``Holder.__init__`` storing that parameter on ``self.<attribute>``
        unchanged: ``fn``. ``Holder`` is a class of this module, a plain class of another
        module of the run (``ProjectView.held_slot``: the project's own copy of a pickling
        wrapper) or a library's pickling wrapper (``names.PICKLING_HOLDERS``: baselines'
        ``CloudpickleWrapper``). None for anything else."""
        if not isinstance(argument, ast.Call):
            return None
        classdef = self.receivers.local_class(argument.func)
        if classdef is None:
            slot = self._holder_slot(argument.func, attribute)
            return None if slot is None else argument_for(argument, *slot)
        init = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "__init__"), None)
        if init is None:
            return None
        stores = [
            target
            for node in walk(init)
            if isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign))
            for target in (node.targets if isinstance(node, ast.Assign) else [node.target])
            if isinstance(target, ast.Attribute) and target.attr == attribute
        ]
        if len(stores) != 1:
            return None
        assign = self.facts.parent(stores[0])
        value = assign.value if isinstance(assign, ast.Assign) and assign.targets == [stores[0]] else None
        if not (isinstance(value, ast.Name) and isinstance(stores[0].value, ast.Name) and stores[0].value.id == "self"):
            return None
        params = [*init.args.posonlyargs, *init.args.args]
        param = next((p for p in params[1:] if p.arg == value.id and p in self.facts.bindings_of(value)), None)
        if param is None:
            return None
        return call_argument(argument, params.index(param) - 1, param.arg)

    def _holder_slot(self, func: ast.expr, attribute: str) -> tuple[str, int] | None:
        """The constructor parameter (name, position) that the imported holder class ``func``
        stores on ``attribute`` unchanged, when every name it may be agrees; None otherwise."""
        slots: set[tuple[str, int] | None] = set()
        for qualified in self.receivers.qualified_names(func):
            library = N.PICKLING_HOLDERS.get(qualified)
            if library is not None:
                slots.add(library[1:] if library[0] == attribute else None)
            else:
                slots.add(self.project.held_slot(qualified, attribute) if self.project is not None else None)
        return slots.pop() if len(slots) == 1 else None

    def _unpacked_returned_kind(self, value: ast.expr, index: int, size: int) -> EnvKind:
        """``make_env_fn, kargs = get_make_env_fn(...)`` where the def of this module returns
        ``inner_fn, kargs`` on every path: what calling the ``index``-th item returns."""
        if not isinstance(value, ast.Call):
            return EnvKind.UNKNOWN
        function = self.receivers.local_function(value.func)
        if function is None:
            # a def of another module of the run returning ``create_env, env_name``
            return self.receivers.called_item_kind(value, index, size)
        returned = [r.value for r in own_returns(function)]
        if not returned or not all(isinstance(r, ast.Tuple) and len(r.elts) == size for r in returned):
            return EnvKind.UNKNOWN
        return join_kinds(self.returned_kind(r.elts[index]) for r in returned)  # type: ignore[union-attr]

    def _item_returned_kind(self, container: ast.expr) -> EnvKind:
        """``for fn in env_fns`` with ``env_fns: List[Callable[[], gym.Env]]`` a parameter:
        what calling one of its items returns."""
        if isinstance(container, ast.Attribute) and isinstance(container.value, ast.Name) and self.receivers.is_self(container.value):
            # ``for fn in self.env_fns`` with ``self.env_fns = env_fns`` stored from a parameter
            stored = self.receivers.self_attribute_values(container, container.attr)
            if not stored or not all(isinstance(value, ast.Name) for value in stored):
                return EnvKind.UNKNOWN
            return join_kinds(self._item_returned_kind(value) for value in stored)
        if not isinstance(container, ast.Name):
            return EnvKind.UNKNOWN
        bindings = self.facts.bindings_of(container)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.arg):
            return EnvKind.UNKNOWN
        if bindings[0].annotation is None:
            # ``env_fns`` unannotated: the thunks this module's calls pass
            return self.receivers.thunks_returned_kind(bindings[0])
        annotation = bindings[0].annotation
        if not isinstance(annotation, ast.Subscript):
            return EnvKind.UNKNOWN
        owner = self.receivers.qualified_names(annotation.value) | (
            {annotation.value.id} if isinstance(annotation.value, ast.Name) and not self.facts.bindings_of(annotation.value) else set()
        )
        if not owner & _SEQUENCES:
            return EnvKind.UNKNOWN
        return self.callable_annotation_kind(annotation.slice)

    def _param_returned_kind(self, param: ast.arg) -> EnvKind:
        if param.annotation is not None:
            kind = self.callable_annotation_kind(param.annotation)
            if kind is not EnvKind.UNKNOWN:
                return kind
        function = self.facts.parent(self.facts.parent(param))
        if not isinstance(function, FUNCTIONS):
            return EnvKind.UNKNOWN
        classdef = self.facts.parent(function)
        is_method = isinstance(classdef, ast.ClassDef) and self.facts.is_method(function)
        params = [*function.args.posonlyargs, *function.args.args]
        position = next((i for i, p in enumerate(params) if p is param), None)
        if is_method and position is not None:
            if position == 0:
                return EnvKind.UNKNOWN
            position -= 1
        external = self._external_creator_kinds(function, classdef if is_method else None, param.arg)  # type: ignore[arg-type]
        if external:
            return self._run_creator_kind(function, classdef if is_method else None, param, position, external)  # type: ignore[arg-type]
        calls = self.receivers.call_sites(function, classdef if is_method else None)  # type: ignore[arg-type]
        kinds = []
        for call in calls:
            argument = call_argument(call, position, param.arg)
            if argument is None:
                argument = self._splatted_argument(call, param.arg)
            kinds.append(EnvKind.UNKNOWN if argument is None else self.returned_kind(argument))
        return join_kinds(kinds) if kinds else EnvKind.UNKNOWN

    def _external_creator_kinds(self, function: ast.AST, classdef: ast.ClassDef | None, param: str) -> list[EnvKind]:
        """What calling the class (or other creator) each call of another module of the run
        passes for ``param`` gives (``ProjectView.creator_kinds``; none when checked alone)."""
        if self.project is None:
            return []
        name = function.name  # type: ignore[attr-defined]
        if classdef is None:
            return self.project.creator_kinds(name, param) if self.facts.parent(function) is self.facts.tree else []
        return self.project.creator_kinds(f"{classdef.name}.{name}", param) if self.facts.parent(classdef) is self.facts.tree else []

    def _run_creator_kind(
        self, function: ast.FunctionDef | ast.AsyncFunctionDef, classdef: ast.ClassDef | None, param: ast.arg, position: int | None, external: list[EnvKind]
    ) -> EnvKind:
        """``env_class`` (or ``self.env_class`` stored from it) that other modules of the run
        pass classes to (``Runner(params, env_class=ENVS[name])``): what calling them gives,
        with this module's own calls (every construction, for an ``__init__``), where all
        agree: the project's own classes make no env, Gym env classes a Gym env; classes of
        several kinds, or a call this run does not show, leave it unknown."""
        kinds = list(external)
        if classdef is not None and function.name == "__init__":
            constructions, elsewhere = self.receivers.constructions(classdef)
            if elsewhere:
                return EnvKind.UNKNOWN
            calls = [(call, shift) for call, shift in constructions]
        else:
            calls = [(call, 0) for call in self.receivers.call_sites(function, classdef)]
        for call, shift in calls:
            argument = call_argument(call, None if position is None else position + shift, param.arg)
            if isinstance(argument, ast.Name) and param in self.facts.bindings_of(argument):
                continue  # the def passing its own parameter on: what its callers pass
            kinds.append(EnvKind.UNKNOWN if argument is None else self.returned_kind(argument))
        return agreed_kind(kinds)

    def _splatted_argument(self, call: ast.Call, name: str) -> ast.expr | None:
        """``f(**kwargs)`` where ``kwargs = dict(name=value, ...)`` (or a dict display with the
        key ``"name"``) is bound once: ``value``."""
        for keyword in call.keywords:
            if keyword.arg is not None or not isinstance(keyword.value, ast.Name):
                continue
            bindings = self.facts.bindings_of(keyword.value)
            if len(bindings) != 1 or not isinstance(bindings[0], ast.Name):
                continue
            assign = self.facts.parent(bindings[0])
            if not (isinstance(assign, ast.Assign) and len(assign.targets) == 1 and assign.targets[0] is bindings[0]):
                continue
            value = assign.value
            if (
                isinstance(value, ast.Call)
                and isinstance(value.func, ast.Name)
                and value.func.id == "dict"
                and not self.facts.bindings_of(value.func)  # the builtin
            ):
                if not value.args:
                    found = [kw.value for kw in value.keywords if kw.arg == name]
                    if len(found) == 1:
                        return found[0]
            elif isinstance(value, ast.Dict):
                found = [
                    v for k, v in zip(value.keys, value.values) if isinstance(k, ast.Constant) and k.value == name
                ]
                if len(found) == 1:
                    return found[0]
        return None

    def callable_annotation_kind(self, annotation: ast.AST, parsed: bool = False) -> EnvKind:
        """``Callable[[], gym.Env]`` (typing or collections.abc, or as a string): the kind it returns."""
        if isinstance(annotation, ast.Constant) and isinstance(annotation.value, str):
            inner = parse_annotation(annotation.value)
            return self.callable_annotation_kind(inner, parsed=True) if inner is not None else EnvKind.UNKNOWN
        optional = None if parsed else optional_of(annotation, self.receivers.qualified_names)
        if optional is not None:
            return self.callable_annotation_kind(optional)  # ``Optional[Callable[[], gym.Env]]``
        if not isinstance(annotation, ast.Subscript):
            return EnvKind.UNKNOWN
        owner = string_names(self.facts, annotation.value) if parsed else self.receivers.qualified_names(annotation.value)
        if not owner & {"typing.Callable", "collections.abc.Callable"}:
            return EnvKind.UNKNOWN
        given = annotation.slice
        if not (isinstance(given, ast.Tuple) and len(given.elts) == 2):
            return EnvKind.UNKNOWN
        returned = given.elts[1]
        return self.receivers.annotation_names_kind(string_names(self.facts, returned)) if parsed else self.receivers.annotation_kind(returned)



# Classes whose constructor takes ``group, target, name, args`` by position.
_SPAWNERS = frozenset(
    {"multiprocessing.Process", "multiprocessing.context.Process", "torch.multiprocessing.Process", "threading.Thread"}
)
_CONTEXTS = frozenset({"multiprocessing.get_context", "torch.multiprocessing.get_context"})

# ``List[...]``, ``Sequence[...]``, ``list[...]``: a parameter that holds items of one type.
_SEQUENCES = frozenset(
    {"typing.List", "typing.Sequence", "typing.Iterable", "collections.abc.Sequence", "collections.abc.Iterable", "list", "tuple"}
)

# A call with no arguments: what a library callable returns when the call is not at hand.
_NO_ARGUMENTS = ast.Call(func=ast.Name(id="_", ctx=ast.Load()), args=[], keywords=[])


def parse_annotation(text: str) -> ast.expr | None:
    try:
        return ast.parse(text.strip(), mode="eval").body
    except SyntaxError:
        return None


def string_names(facts: ModuleFacts, expr: ast.AST | None) -> set[str]:
    """Qualified names of a dotted name parsed from a string annotation, through the
    module's own imports (the parsed nodes have no scope of their own)."""
    parts: list[str] = []
    while isinstance(expr, ast.Attribute):
        parts.append(expr.attr)
        expr = expr.value
    if not isinstance(expr, ast.Name):
        return set()
    rest = "".join(f".{p}" for p in reversed(parts))
    return {facts.imports[b] + rest for b in facts.module_scope.bindings.get(expr.id, ()) if isinstance(b, ast.alias)}


def optional_of(annotation: ast.AST, qualified_names) -> ast.AST | None:
    """``Optional[X]`` or ``X | None``: X."""
    if isinstance(annotation, ast.BinOp) and isinstance(annotation.op, ast.BitOr):
        for one, other in ((annotation.left, annotation.right), (annotation.right, annotation.left)):
            if isinstance(other, ast.Constant) and other.value is None:
                return one
    if isinstance(annotation, ast.Subscript) and "typing.Optional" in qualified_names(annotation.value):
        return annotation.slice
    return None

def union_members(annotation: ast.AST, qualified_names) -> list[ast.AST] | None:
    """The members of ``Union[X, Y]`` or ``X | Y`` (``None`` left out), else None."""
    if isinstance(annotation, ast.BinOp) and isinstance(annotation.op, ast.BitOr):
        members: list[ast.AST] = []
        for side in (annotation.left, annotation.right):
            inner = union_members(side, qualified_names) if isinstance(side, ast.BinOp) else None
            members += inner if inner is not None else [side]
        return [m for m in members if not (isinstance(m, ast.Constant) and m.value is None)]
    if isinstance(annotation, ast.Subscript) and "typing.Union" in qualified_names(annotation.value):
        items = annotation.slice.elts if isinstance(annotation.slice, ast.Tuple) else [annotation.slice]
        return [m for m in items if not (isinstance(m, ast.Constant) and m.value is None)]
    return None
