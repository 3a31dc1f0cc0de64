"""Who made the object an expression holds, where that decides what the rules may do:
a class of the run whose step keeps the legacy contract (``legacy_step_class``), code of
the run itself (``run_defined``: never guessed from a name), or a library other than Gym
(``library_made``: not shown to be a Gym env). ``MadeObjects``, mixed into ``Receivers``.
"""

from __future__ import annotations

import ast
import sys
from typing import TYPE_CHECKING

from gymmigrate.facts import names as N
from gymmigrate.facts.callables import optional_of, parse_annotation, string_names
from gymmigrate.facts.done_uses import builds_record
from gymmigrate.facts.gym_use import handles_gym_envs
from gymmigrate.facts.kinds import MAX_DEPTH, EnvKind
from gymmigrate.facts.module import FUNCTIONS, call_argument, own_returns
from gymmigrate.facts.receiver_classes import is_batched_step_return, keeps_legacy_step
from gymmigrate.facts.version_checks import reads_version

if TYPE_CHECKING:
    from gymmigrate.facts.kinds import ReceiverFacade as _Facade
else:
    _Facade = object


class MadeObjects(_Facade):
    """Where an expression's object comes from (part of ``Receivers``)."""

    def legacy_step_class(self, expr: ast.AST) -> str | None:
        """The class of the run whose instance ``expr`` certainly holds, when that class's
        step keeps the four-field contract (``keeps_legacy_step``; another module's through
        ``ProjectView.keeps_legacy_step``): every value that reaches ``expr`` is made by it."""
        return self.facts.memo(("legacy-step-class", id(expr)), lambda: self._legacy_step_class(expr), while_computing=None)

    def _legacy_step_class(self, expr: ast.AST) -> str | None:
        values: list[ast.expr]
        if isinstance(expr, ast.Call):
            values = [expr]
        elif isinstance(expr, ast.Name):
            last = self._dominating_binding(expr)
            reaching = self.values_reaching(expr) if last is None else None
            if reaching is not None:
                # ``env = Outer(env)`` after ``env = Kept(env)``, or after ``if ...: env = Skip(env)``:
                # every value that may reach the read (the nearest one above names the class)
                found = {self._legacy_step_maker(value) for value in reaching}
                return None if None in found else self._legacy_step_maker(reaching[0])
            bindings = [last] if last is not None else self.facts.bindings_of(expr)
            values = []
            kept: set[str] = set()
            for binding in bindings:
                if isinstance(binding, ast.arg):
                    # A parameter every caller of the run feeds such an instance (a parameter
                    # fed one and another env is reported: ``ParameterKinds._param_kind``).
                    names, other = self.param_kept_classes(binding)
                    if other or not names:
                        return None  # several such classes are all kept: still their contract
                    kept |= names
                    continue
                parent = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
                if not (isinstance(parent, (ast.Assign, ast.AnnAssign)) and parent.value is not None):
                    return None
                values.append(parent.value)
            if kept:
                found = {self._legacy_step_maker(value) for value in values} | kept
                return None if None in found else min(found)  # type: ignore[type-var]
        elif isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and self.is_self(expr.value):
            classdef = self.facts.enclosing_class(expr)
            if expr.attr == "env" and classdef is not None and (wrapped := self.wraps_legacy_step(classdef)) is not None:
                return wrapped  # a wrapper this module puts around such a class: ``self.env`` is it
            values = self.self_attribute_values(expr, expr.attr)
        else:
            return None
        found = {self._legacy_step_maker(value) for value in values}
        return min(found) if values and None not in found else None  # type: ignore[type-var]

    def _legacy_step_maker(self, value: ast.expr) -> str | None:
        if isinstance(value, ast.Name):
            return self.legacy_step_class(value)  # ``self.sampler = sampler``: what the name holds
        if not isinstance(value, ast.Call):
            return None
        local = self.local_class(value.func)
        if local is not None:
            # A wrapper of the project's own protocol (``own_record_wrapper``): its instances'
            # step and reset calls read that protocol and stay as they are too.
            if self.own_record_wrapper(local) or self.class_keeps_legacy_step(local):
                return local.name
            return self._forwarded_legacy(value) if self.is_gym_wrapper_class(local) and self.forwards_inner_contract(local) else None
        function = self.local_function(value.func)
        if function is not None:
            # a factory of this module (``wrap(env)``) returning such an instance on every path
            returned = [r.value for r in own_returns(function)]
            found = {self.legacy_step_class(r) if r is not None else None for r in returned}
            return found.pop() if len(found) == 1 and returned else None
        if self.project is not None:
            for qualified in self.qualified_names(value.func):
                if self.project.keeps_legacy_step(qualified):
                    return qualified.rsplit(".", 1)[-1]
            if any(self.project.forwards_inner_contract(q) for q in self.qualified_names(value.func)):
                return self._forwarded_legacy(value)
        return None

    def _forwarded_legacy(self, value: ast.Call) -> str | None:
        """``Outer(env)``, Outer a Gym wrapper handing on its env's step and reset results
        (``forwards_inner_contract``): the class kept on the legacy API ``env`` holds, if any."""
        inner = call_argument(value, 0, "env")
        return self.legacy_step_class(inner) if inner is not None else None

    def seed_holder(self, expr: ast.expr) -> str | None:
        """Where the object ``expr`` holds gets a ``seed()`` method: "own" when the outermost
        class defines it, "inner" when a class inside its Gym wrapper chain does (Gymnasium's
        wrappers forward no ``seed``: ``get_wrapper_attr("seed")`` reaches it), None when the
        run cannot show one on every value that reaches ``expr``."""
        return self.facts.memo(("seed-holder", id(expr)), lambda: self._seed_holder(expr), while_computing=None)

    def _seed_holder(self, expr: ast.expr) -> str | None:
        values: list[ast.expr] | None = None
        if isinstance(expr, ast.Name):
            last = self._dominating_binding(expr)
            statement = self.facts.statement_of(last) if last is not None else None
            if isinstance(statement, ast.Assign) and len(statement.targets) == 1:
                values = [statement.value]
            elif last is None:
                values = self.values_reaching(expr)
        elif isinstance(expr, ast.Call):
            local = self.local_class(expr.func)
            function = self.local_function(expr.func)
            if local is not None:
                if any(isinstance(s, FUNCTIONS) and s.name == "seed" for s in local.body):
                    return "own"
                return self._seed_inside(expr) if self.is_gym_wrapper_class(local) else None
            if function is not None:
                values = [r.value for r in own_returns(function) if r.value is not None]
                if len(values) != len(own_returns(function)):
                    return None
            elif self.project is not None:
                for qualified in self.qualified_names(expr.func):
                    holder = self.project.seed_holder(qualified)
                    if holder is not None:
                        return holder
                    if self.project.is_wrapper_class(qualified):
                        return self._seed_inside(expr)
        if not values:
            return None
        found = {self.seed_holder(value) for value in values}
        return None if None in found else "own" if found == {"own"} else "inner"

    def _seed_inside(self, call: ast.Call) -> str | None:
        """``Outer(env)``: "inner" when ``env`` holds a seed() somewhere."""
        inner = call_argument(call, 0, "env")
        return "inner" if inner is not None and self.seed_holder(inner) is not None else None

    def legacy_dependencies(self) -> dict[str, str]:
        """``ModuleSummary.legacy_if``: for each top-level Gym wrapper class whose every
        construction here wraps, and each top-level def whose every return is, an instance
        of one imported name (through wrapper classes and defs of this module, ``env =
        Outer(env)`` chains followed), that name as imported (imported names put around it
        first: ``a.Outer>b.Kept``). Whether it keeps its legacy
        contract is known only across the run."""
        found: dict[str, str] = {}
        for name, classdef in self.facts.classes.items():
            calls = self.facts.calls_by_name.get(name, [])
            if calls and self.is_gym_wrapper_class(classdef):
                inner = {self.imported_maker(a) if (a := call_argument(call, 0, "env")) is not None else None for call in calls}
                if len(inner) == 1 and None not in inner:
                    found[name] = inner.pop()  # type: ignore[assignment]
        for name, function in self.facts.functions.items():
            returned = {self.imported_maker(r.value) if r.value is not None else None for r in own_returns(function)}
            if len(returned) == 1 and None not in returned:
                found[name] = returned.pop()  # type: ignore[assignment]
        return found

    def imported_maker(self, expr: ast.expr) -> str | None:
        """The imported name (as imported, not Gym's) whose instance ``expr`` certainly holds,
        through Gym wrapper classes and defs of this module put around it."""
        return self.facts.memo(("imported-maker", id(expr)), lambda: self._imported_maker(expr), while_computing=None)

    def _imported_maker(self, expr: ast.expr) -> str | None:
        values: list[ast.expr] | None
        if isinstance(expr, ast.Name):
            last = self._dominating_binding(expr)
            statement = self.facts.statement_of(last) if last is not None else None
            if isinstance(statement, ast.Assign) and len(statement.targets) == 1:
                values = [statement.value]
            else:
                values = self.values_reaching(expr) if last is None else None
        elif isinstance(expr, ast.Call):
            local = self.local_class(expr.func)
            function = self.local_function(expr.func)
            if local is not None:
                inner = call_argument(expr, 0, "env") if self.is_gym_wrapper_class(local) else None
                values = [inner] if inner is not None else None
            elif function is not None:
                values = [r.value for r in own_returns(function) if r.value is not None] or None
                if values is not None and len(values) != len(own_returns(function)):
                    return None
            else:
                names = {q for q in self.qualified_names(expr.func) if N.strip_gym_prefix(q) is None}
                if len(names) != 1:
                    return None
                # ``Outer(Kept(env))`` with both imported: ``a.Outer>b.Kept``, whether Outer hands
                # on what Kept gives is known only across the run (``project_contracts``)
                inner = call_argument(expr, 0, "env")
                deeper = self.imported_maker(inner) if inner is not None else None
                return f"{names.pop()}>{deeper}" if deeper is not None else names.pop()
        else:
            return None
        if not values:
            return None
        found = {self.imported_maker(value) for value in values}
        return found.pop() if len(found) == 1 and None not in found else None

    def values_reaching(self, read: ast.Name) -> list[ast.expr] | None:
        """The values of ``read``'s variable that may reach it, nearest first, in straight code
        of one function: walking back through the statement lists that enclose the read, the
        nearest plain assignment above, and every assignment inside the compound statements
        passed on the way (``if ...: env = Skip(env)``, which may or may not run). A read in
        the value of an assignment that rebinds it (``env = Outer(env)``) sees the values
        above. None when a binding on the way is no plain assignment (a parameter, a loop
        target), a loop around the read rebinds it, or no assignment above dominates."""
        return self.facts.memo(("values-reaching", id(read)), lambda: self._values_reaching(read), while_computing=None)

    def _values_reaching(self, read: ast.Name) -> list[ast.expr] | None:
        scope = self.facts.scope_of(read)
        values: list[ast.expr] = []
        node: ast.AST = self.facts.statement_of(read)
        for _ in range(64):
            holder = self.facts.parent(node)
            if holder is None or isinstance(holder, (ast.Lambda, ast.ClassDef, ast.ExceptHandler)):
                return None
            if isinstance(holder, (ast.For, ast.AsyncFor, ast.While)) and self._binds_in(holder, read.id, scope) != []:
                return None  # a value of the previous iteration may reach the read
            block = next((b for b in ("body", "orelse", "finalbody") if node in (getattr(holder, b, None) or ())), None)
            if block is None:
                return None
            statements = getattr(holder, block)
            for statement in reversed(statements[: statements.index(node)]):
                targets = statement.targets if isinstance(statement, ast.Assign) else None
                if targets and len(targets) == 1 and isinstance(targets[0], ast.Name) and targets[0].id == read.id:
                    values.append(statement.value)
                    return values
                inner = self._binds_in(statement, read.id, scope)
                if inner is None:
                    return None
                values.extend(inner)
            if isinstance(holder, (*FUNCTIONS, ast.Module)):
                return None  # the top of the function: no assignment above dominates
            node = holder
        return None

    def _binds_in(self, statement: ast.AST, name: str, scope: object) -> list[ast.expr] | None:
        """The values assigned to ``name`` (of ``scope``) inside ``statement``, or None when
        one of its bindings there is no plain single-target assignment."""
        values: list[ast.expr] = []
        for node in ast.walk(statement):
            if isinstance(node, ast.Name) and node.id == name and isinstance(node.ctx, ast.Store) and self.facts.scope_of(node) is scope:
                parent = self.facts.parent(node)
                if not (isinstance(parent, ast.Assign) and parent.targets == [node]):
                    return None
                values.append(parent.value)
            elif isinstance(node, (*FUNCTIONS, ast.ClassDef)) and node.name == name:
                return None
            elif isinstance(node, ast.alias) and (node.asname or node.name.split(".")[0]) == name:
                return None
        return values

    def class_keeps_legacy_step(self, classdef: ast.ClassDef, seen: frozenset[int] = frozenset()) -> bool:
        """The step ``classdef``'s instances run keeps its legacy contract: its own, or the
        one a base of this module (or of the run) defines when it defines none."""
        if id(classdef) in seen or self.class_kind(classdef) is not EnvKind.GYM_ENV:
            return False
        if self.wraps_legacy_step(classdef) is not None:
            return True  # its step passes on the four fields of the batch it wraps
        seen = seen | {id(classdef)}
        if any(isinstance(s, FUNCTIONS) and s.name == "step" for s in classdef.body):
            return keeps_legacy_step(classdef)
        for base in classdef.bases:
            local = self.local_class(base)
            if local is not None:
                return self.class_keeps_legacy_step(local, seen)
            if self.project is not None and any(self.project.keeps_legacy_step(q) for q in self.qualified_names(base)):
                return True
        return False

    def keeps_own_reset(self, classdef: ast.ClassDef) -> bool:
        """The class keeps its reset with the four-field step the run keeps: an env class whose
        step keeps its legacy contract (``class_keeps_legacy_step``), a Gym wrapper whose own
        step returns a batch's stacked flags, or one put around such a batch. A reset of
        Gymnasium's beside that step would match neither API, and its callers would break."""
        if self.own_record_wrapper(classdef):
            return True
        if self.is_gym_wrapper_class(classdef) and self.legacy_by_version(classdef):
            return True
        if not self.class_keeps_legacy_step(classdef):
            return False
        if not self.is_gym_wrapper_class(classdef) or self.wraps_legacy_step(classdef) is not None:
            return True
        step = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "step"), None)
        return step is not None and any(is_batched_step_return(r.value, step) for r in own_returns(step))

    def own_record_wrapper(self, classdef: ast.ClassDef) -> bool:
        """A Gym wrapper of the project's own protocol (``_steps_own_record``): its instances'
        step and reset calls read that protocol and stay as they are, wherever the run shows
        they hold one (a parameter every caller feeds one too: ``ParameterKinds``). A wrapper
        that presents the legacy API on purpose behind a gym version check
        (``legacy_by_version``) is one too: its callers read four values on Gymnasium as well."""
        return self.is_gym_wrapper_class(classdef) and (self._steps_own_record(classdef) or self.legacy_by_version(classdef))

    def _steps_own_record(self, classdef: ast.ClassDef) -> bool:
        """A Gym wrapper that speaks the project's own protocol: its step returns a record of
        the run (``EnvStep(o, r, d, info)``, never a tuple) and its reset the bare observation
        (no pair). Its callers read that record and that observation, so only its calls of the
        wrapped env change; its reset keeps returning the observation."""
        methods = {s.name: s for s in classdef.body if isinstance(s, FUNCTIONS)}
        step, reset = methods.get("step"), methods.get("reset")
        if step is None or reset is None:
            return False
        returns = [r.value for r in own_returns(step)]
        if not returns or not all(isinstance(v, ast.Call) and builds_record(v, self.facts) for v in returns):
            return False
        return not any(isinstance(r.value, ast.Tuple) and len(r.value.elts) == 2 for r in own_returns(reset))

    def legacy_by_version(self, classdef: ast.ClassDef) -> bool:
        """A Gym wrapper that presents the legacy API whatever gym is installed: its step
        branches on a ``gym.__version__`` check (``reads_version``) and returns four values on
        every path, and its own reset never returns a pair. Its
        callers read that API on purpose: its step, its reset and their calls stay as they are
        (only the branch the check picks runs; GM108 reports the check)."""
        methods = {s.name: s for s in classdef.body if isinstance(s, FUNCTIONS)}
        step = methods.get("step")
        if step is None:
            return False
        checks = [n for n in ast.walk(step) if isinstance(n, ast.If) and reads_version(n.test, self.facts)]
        returns = [r.value for r in own_returns(step)]
        if not checks or not returns or not all(isinstance(v, ast.Tuple) and len(v.elts) == 4 for v in returns):
            return False
        reset = methods.get("reset")  # without one, Gymnasium's inherited reset returns the pair
        return reset is not None and not any(isinstance(r.value, ast.Tuple) and len(r.value.elts) == 2 for r in own_returns(reset))

    def in_legacy_by_version_method(self, node: ast.AST) -> bool:
        """``node`` is in the step or reset of a ``legacy_by_version`` class: both branches of
        its version check already speak the API of the gym they run on."""
        function = self.facts.enclosing_function(node)
        classdef = self.facts.parent(function) if function is not None else None
        return (
            function is not None and function.name in ("step", "reset") and isinstance(classdef, ast.ClassDef)
            and self.is_gym_wrapper_class(classdef) and self.legacy_by_version(classdef)
        )

    def run_defined(self, expr: ast.AST) -> bool:
        """``expr`` holds (or may hold) an object the run itself makes: an instance of a class
        or the return of a def of this file, or a name imported from a module of the run. The
        run knows that code, so its kind is never guessed from a name."""
        return self.facts.memo(("run-defined", id(expr)), lambda: self._run_defined(expr), while_computing=False)

    def _run_defined(self, expr: ast.AST) -> bool:
        if self.depth > MAX_DEPTH:
            return False
        self.depth += 1
        try:
            if isinstance(expr, ast.Call):
                func = expr.func
                if self.local_class(func) is not None or self.local_function(func) is not None or self.own_method(func) is not None:
                    return True
                return any(self._from_run(q) for q in self.qualified_names(func)) or (
                    isinstance(func, ast.Attribute) and self.run_defined(func.value)
                )
            if isinstance(expr, ast.Name):
                for binding in self.facts.bindings_of(expr):
                    if isinstance(binding, ast.alias) and self._from_run(self.facts.imports[binding]):
                        return True
                    parent = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
                    if isinstance(parent, (ast.Assign, ast.NamedExpr)) and self.run_defined(parent.value):
                        return True
                    if isinstance(parent, (ast.For, ast.AsyncFor, ast.comprehension)) and parent.target is binding:
                        if self.run_defined(parent.iter):  # an item of a list that holds the run's objects
                            return True
                return any(self.run_defined(v) for v in self._items_stored(expr))
            if isinstance(expr, ast.Attribute):
                if isinstance(expr.value, ast.Name) and self.is_self(expr.value):
                    values = self.self_attribute_values(expr, expr.attr)
                    return any(self.run_defined(v) for v in values) or any(self.run_defined(v) for v in self._items_stored(expr))
                return self.run_defined(expr.value)
            if isinstance(expr, ast.Subscript):
                return self.run_defined(expr.value)
            if isinstance(expr, (ast.List, ast.Tuple)):
                return any(self.run_defined(el.value if isinstance(el, ast.Starred) else el) for el in expr.elts)
            if isinstance(expr, (ast.ListComp, ast.GeneratorExp)):
                return self.run_defined(expr.elt)
            return False
        finally:
            self.depth -= 1

    def own_api_holder(self, expr: ast.AST) -> str | None:
        """``self.X`` of a class that is no Gym class, derives from a base with an env API of
        its own, and forwards that API to ``self.X``: a method of the class named like a
        method of that base (``reset`` or its hook ``_reset``) calls the same method on
        ``self.X``. The base is a class of the run that is not a Gym env and declares that
        method (``class Wrapper(Environment)`` where ``Environment.reset`` returns the
        states only), or a class of a library with its own env API (tf_agents'
        ``PyEnvironment`` wrappers, whose reset gives a TimeStep). What such a class holds
        is not shown to be a Gym env by the file's imports: a description for the message,
        else None.

        A fact of the receiver, not of the call: where the class forwards its ``reset`` or
        ``step`` so, every call on ``self.X`` in it gets the same answer (``reset`` is never
        left while ``step`` is rewritten on the "this file uses only Gym" guess); another
        method (``close``, ``render``) forwarded so speaks for its own call only. ``decide``
        asks it only for a receiver whose kind is unknown: proved a Gym env, it is rewritten."""
        if not (isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and self.is_self(expr.value)):
            return None
        classdef = self.facts.enclosing_class(expr)
        if classdef is None:
            return None
        attribute = expr.attr
        forwarded = self.facts.memo((f"own-api-forwarded:{attribute}", id(classdef)), lambda: self._own_api_forwarded(classdef, attribute))
        called = self.facts.parent(expr)
        function = self.facts.enclosing_function(expr)
        own = next((f for f in forwarded if f[0] is function and isinstance(called, ast.Attribute) and f[1] == called.attr), None)
        found = own or next((f for f in forwarded if f[1].lstrip("_") in ("reset", "step")), None)
        if found is None:
            return None
        return f"`{classdef.name}`, whose `{found[0].name}` forwards to it and which derives from `{found[2]}`, an env API other than Gym's"

    def _own_api_forwarded(self, classdef: ast.ClassDef, attribute: str) -> list[tuple[ast.AST, str, str]]:
        """(method, forwarded method, base) for each method of ``classdef`` that calls its
        namesake on ``self.<attribute>`` where a base shows that method with an env API
        other than Gym's (``_own_api_base_name``), in source order."""
        if self.is_gym_wrapper_class(classdef) or self._known_kind(classdef) not in (EnvKind.UNKNOWN, EnvKind.NOT_ENV):
            return []
        found: list[tuple[ast.AST, str, str]] = []
        for held in self.facts.attributes.get(attribute, ()):
            called = self.facts.parent(held)
            function = self.facts.enclosing_function(held)
            call = self.facts.parent(called) if called is not None else None
            if not (
                isinstance(held.value, ast.Name) and self.is_self(held.value)
                and isinstance(called, ast.Attribute) and called.value is held
                and isinstance(call, ast.Call) and call.func is called
                and function is not None and self.facts.parent(function) is classdef
                and function.name.lstrip("_") == called.attr.lstrip("_")
            ):
                continue
            base = self._own_api_base_name(classdef, called.attr)
            if base is not None:
                found.append((function, called.attr, base))
        return sorted(found, key=lambda f: (f[0].lineno, f[1]))  # type: ignore[attr-defined]

    def _known_kind(self, classdef: ast.ClassDef) -> EnvKind:
        return self.facts.memo(("class-kind", id(classdef)), lambda: self.class_kind(classdef), while_computing=EnvKind.UNKNOWN)

    def _own_api_base_name(self, classdef: ast.ClassDef, method: str) -> str | None:
        """The first base (through the module's classes) that shows an env API other than
        Gym's with ``method`` (``_own_api_holder``), or None."""
        wanted = {method.lstrip("_"), "_" + method.lstrip("_")}
        seen = {id(classdef)}
        todo = [classdef]
        while todo:
            for base in todo.pop().bases:
                if self._own_api_base(base):
                    return self.facts.segment(base)
                local = self.local_class(base)
                if local is not None:
                    if id(local) in seen or self.is_gym_wrapper_class(local):
                        continue
                    seen.add(id(local))
                    if self._known_kind(local) not in (EnvKind.UNKNOWN, EnvKind.NOT_ENV):
                        continue
                    if any(isinstance(s, FUNCTIONS) and s.name in wanted for s in local.body):
                        return local.name
                    todo.append(local)
                elif self.project is not None:
                    for qualified in self.qualified_names(base):
                        if (
                            self._from_run(qualified)
                            and self.project.call_kind(qualified) in (None, EnvKind.UNKNOWN, EnvKind.NOT_ENV)
                            and not self.project.is_wrapper_class(qualified)
                            and self.project.class_methods(qualified) & wanted
                        ):
                            return self.facts.segment(base)
        return None

    def _items_stored(self, container: ast.expr) -> list[ast.expr]:
        """Values written into the list ``container`` (``envs[i] = X``) under any name that
        holds the same list: ``self.envs = envs = [...]`` followed by ``envs[i] = X`` puts X
        in ``self.envs`` too."""
        holders: list[ast.Name] = []
        if isinstance(container, ast.Name):
            holders.append(container)
        values = [container]
        if isinstance(container, ast.Attribute) and isinstance(container.value, ast.Name) and self.is_self(container.value):
            values = self.self_attribute_values(container, container.attr)
        for value in values:
            statement = self.facts.parent(value)
            if isinstance(statement, ast.Assign) and statement.value is value:
                holders += [t for t in statement.targets if isinstance(t, ast.Name)]
        found: list[ast.expr] = []
        for holder in holders:
            same = {id(b) for b in self.facts.bindings_of(holder)} | {id(holder)}
            for store in self._subscript_assigns().get(holder.id, ()):
                if same & {id(b) for b in self.facts.bindings_of(store.value)}:  # type: ignore[arg-type]
                    parent = self.facts.parent(store)
                    if isinstance(parent, ast.Assign):
                        found.append(parent.value)
        return found

    def _subscript_assigns(self) -> dict[str, list[ast.Subscript]]:
        """``name[...] = value`` targets of this module, by name."""

        def compute() -> dict[str, list[ast.Subscript]]:
            out: dict[str, list[ast.Subscript]] = {}
            for node in ast.walk(self.facts.tree):
                if isinstance(node, ast.Assign):
                    for target in node.targets:
                        if isinstance(target, ast.Subscript) and isinstance(target.value, ast.Name):
                            out.setdefault(target.value.id, []).append(target)
            return out

        return self.facts.memo(("subscript-assigns", 0), compute)

    def gym_only_stack(self, expr: ast.AST) -> str | None:
        """The Gym-only library stack (GM107: ``nes_py`` for ``gym_super_mario_bros``) that
        makes every value ``expr`` may hold, followed through the run's own code: its
        wrapper classes around that library's env (``wraps_gym_only``), its factories
        (``def make_env(): ...; return Skip(JoypadSpace(env))``, here or in another module of
        the run), its lists of such envs (``self.envs[i]``). Such an env keeps gym's API
        until that stack is ported, so its resets and steps are that decision's, or None."""
        return self.facts.memo(("gym-only-stack", id(expr)), lambda: self._gym_only_stack(expr), while_computing=None)

    def _gym_only_stack(self, expr: ast.AST) -> str | None:
        if self.depth > MAX_DEPTH:
            return None
        self.depth += 1
        try:
            return self._agreed(self._stack_values(expr))
        finally:
            self.depth -= 1

    @staticmethod
    def _agreed(stacks: list[str | None]) -> str | None:
        found = set(stacks)
        return found.pop() if len(found) == 1 and None not in found else None

    def _stack_values(self, expr: ast.AST) -> list[str | None]:
        """One answer per value ``expr`` may hold (None: not shown to be the stack's)."""
        if isinstance(expr, ast.Call):
            return [self._call_stack(expr)]
        if isinstance(expr, ast.Name):
            answers: list[str | None] = []
            for binding in self.facts.bindings_of(expr):
                parent = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
                if isinstance(parent, ast.Assign) and binding in parent.targets:
                    answers.append(self.gym_only_stack(parent.value))
                elif isinstance(parent, (ast.For, ast.AsyncFor, ast.comprehension)) and parent.target is binding:
                    answers.append(self.gym_only_stack(parent.iter))  # an item of a list of them
                else:
                    return [None]  # a parameter, an import, an unpacking: not known here
            return answers or [None]
        if isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and self.is_self(expr.value):
            values = self.self_attribute_values(expr, expr.attr)
            return [self.gym_only_stack(v) for v in values] or [None]
        if isinstance(expr, ast.Subscript):
            return [self.gym_only_stack(expr.value)]  # ``self.envs[i]``: one of the list
        if isinstance(expr, (ast.List, ast.Tuple)) and expr.elts:
            return [self.gym_only_stack(el) for el in expr.elts]
        if isinstance(expr, (ast.ListComp, ast.GeneratorExp)):
            return [self.gym_only_stack(expr.elt)]
        return [None]

    def returns_gym_only_stack(self, function: ast.AST) -> str | None:
        """The Gym-only stack every return of ``function`` comes from (``gym_only_stack``)."""
        returns = own_returns(function)
        if not returns or any(r.value is None for r in returns):
            return None
        return self._agreed([self.gym_only_stack(r.value) for r in returns if r.value is not None])

    def _call_stack(self, call: ast.Call) -> str | None:
        classdef = self.local_class(call.func)
        if classdef is not None:
            made = self.wraps_gym_only(classdef)  # the run's wrapper around the library's env
            top = made.split(".", 1)[0] if made is not None else None
            return N.gym_only_stack(top) if top in N.GYM_ONLY_PACKAGES else None
        function = self.local_function(call.func)
        if function is not None:
            return self.returns_gym_only_stack(function)
        stacks: set[str | None] = set()
        for qualified in self.qualified_names(call.func):
            top = qualified.split(".", 1)[0]
            if top in N.GYM_ONLY_PACKAGES:
                stacks.add(N.gym_only_stack(top))
            elif self.project is not None:
                stacks.add(self.project.gym_only_maker(qualified))  # a factory of another module of the run
            else:
                stacks.add(None)
        return self._agreed(list(stacks))

    def library_made(self, expr: ast.AST) -> str | None:
        """The callable of a library other than Gym that made ``expr`` (``env =
        suite_gym.load(...)`` of tf_agents: ``tf_agents.environments.suite_gym.load``), or
        None. Such an object is not shown to be a Gym env by a file using only Gym."""
        return self.facts.memo(("library-made", id(expr)), lambda: self._library_made(expr), while_computing=None)

    def _library_made(self, expr: ast.AST) -> str | None:
        if self.depth > MAX_DEPTH:
            return None
        self.depth += 1
        try:
            if isinstance(expr, ast.Call):
                imported = set(self.facts.imports.values())
                for qualified in sorted(self.qualified_names(expr.func)):
                    top = qualified.split(".", 1)[0]
                    if (
                        top not in ("gym", "gymnasium")
                        and top not in sys.stdlib_module_names
                        and any(qualified == m or qualified.startswith(m + ".") for m in imported)
                        and not self._from_run(qualified)
                    ):
                        return qualified
                return None
            if isinstance(expr, ast.Name):
                last = self._dominating_binding(expr)  # the one binding this read can reach
                if last is not None:
                    statement = self.facts.statement_of(last)
                    return self.library_made(statement.value) if isinstance(statement, ast.Assign) else None
                found = []
                for binding in self.facts.bindings_of(expr):
                    parent = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
                    if not (isinstance(parent, ast.Assign) and binding in parent.targets):
                        return None
                    found.append(self.library_made(parent.value))
                return found[0] if found and all(f is not None for f in found) else None
            if isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and self.is_self(expr.value):
                # ``self._env = suite.load(...)`` in ``__init__``: every value the class stores
                values = self.self_attribute_values(expr, expr.attr)
                made = [self.library_made(value) for value in values]
                return made[0] if made and all(m is not None for m in made) else None
            return None
        finally:
            self.depth -= 1

    def _from_run(self, qualified: str) -> bool:
        if qualified.startswith("."):
            return True  # a relative import: a module of the project
        return self.project is not None and self.project.defines(qualified)

    def handles_gym_envs(self) -> bool:
        """The module handles Gym envs (``gym_use.handles_gym_envs``), or defines a class the
        run shows to be a Gym env or wrapper (``class Schedule(TrialWrapper)`` where
        ``TrialWrapper``, of another module, derives ``gym.Wrapper``): only then may the "this
        file uses only Gym" fallback guess that an untraced env-like name holds a Gym env.
        (The seed summaries, which know no other module, ask the module fact alone: they
        differ only for a seed call outside a seed() method of such a module, where the
        first run keeps the env classes' seed() with a GM503 item.)"""
        return self.facts.memo(("handles-gym-envs-run", 0), self._handles_gym_envs, while_computing=False)

    def _handles_gym_envs(self) -> bool:
        if handles_gym_envs(self.facts):
            return True
        return any(self.is_gym_wrapper_class(c) or self._known_kind(c) in (EnvKind.GYM_ENV, EnvKind.GYM_VEC) for c in self.facts.all_classes)

    def annotated_class(self, expr: ast.AST) -> str | None:
        """The annotation, as written, of a binding that reaches ``expr`` (``def __init__(self,
        environment: VecEnv)`` then ``self.environment = environment``; ``env: MyEnv = ...``)
        when it names a class the run does not show to be a Gym env (a project class that is
        no ``gym.Env``, a name of an unknown module). The code says what the object is, and
        it is not Gym's: a file's imports do not outweigh that. None without one."""
        return self.facts.memo(("annotated-class", id(expr)), lambda: self._annotated_class(expr, 0), while_computing=None)

    def _annotated_class(self, expr: ast.AST, depth: int) -> str | None:
        if depth > 4:
            return None
        annotations: list[ast.expr] = []
        values: list[ast.expr] = []
        if isinstance(expr, ast.Name):
            for binding in self.facts.bindings_of(expr):
                if isinstance(binding, ast.arg) and binding.annotation is not None:
                    annotations.append(binding.annotation)
                parent = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
                if isinstance(parent, ast.AnnAssign) and parent.target is binding:
                    annotations.append(parent.annotation)
                elif isinstance(parent, ast.Assign) and binding in parent.targets:
                    values.append(parent.value)
        elif isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and self.is_self(expr.value):
            classdef = self.facts.enclosing_class(expr)
            for node in self.facts.attributes.get(expr.attr, ()):
                parent = self.facts.parent(node)
                if (
                    isinstance(parent, ast.AnnAssign) and parent.target is node and isinstance(node.value, ast.Name)
                    and self.is_self(node.value) and self.facts.enclosing_class(node) is classdef
                ):
                    annotations.append(parent.annotation)  # ``self.env: VecEnv = env``
            values = self.self_attribute_values(expr, expr.attr)
        for annotation in annotations:
            if self._names_other_class(annotation):
                return self.facts.segment(annotation)
        for value in values:
            if isinstance(value, (ast.Name, ast.Attribute)):
                found = self._annotated_class(value, depth + 1)
                if found is not None:
                    return found
        return None

    def _names_other_class(self, annotation: ast.AST) -> bool:
        """``annotation`` names a class not shown to be a Gym env: not Gym's own, not ``Any``
        or another ``typing`` form, not ``object``."""
        if self.annotation_kind(annotation) in (EnvKind.GYM_ENV, EnvKind.GYM_VEC):
            return False
        optional = optional_of(annotation, self.qualified_names)
        if optional is not None:
            return self._names_other_class(optional)  # ``Optional[VecEnv]``
        target: ast.AST | None = annotation
        string = isinstance(annotation, ast.Constant) and isinstance(annotation.value, str)
        if string:
            target = parse_annotation(annotation.value)  # type: ignore[attr-defined]  # ``env: "MyEnv"``
        if not isinstance(target, (ast.Name, ast.Attribute)):
            return False  # ``Optional[...]``, ``Union[...]``, a string that is not a dotted name
        names = string_names(self.facts, target) if string else self.qualified_names(target)
        if any(N.strip_gym_prefix(q) is not None or q.split(".", 1)[0] in ("typing", "typing_extensions", "builtins") for q in names):
            return False
        return not (isinstance(target, ast.Name) and target.id in ("object", "Any") and not names)
