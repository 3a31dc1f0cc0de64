"""Who made the object an expression holds, where that decides what the rules may do:
a class of the run whose step keeps the legacy contract (``legacy_step_class``), code of
the run itself (``run_defined``: never guessed from a name), or a library other than Gym
(``library_made``: not shown to be a Gym env). ``MadeObjects``, mixed into ``Receivers``.
The evidence that an object is not Gym's (another library, an API of its own, an
annotation) is ``receiver_foreign.py``; the Gym-only library stacks are
``receiver_gym_only.py``; both are bases of ``MadeObjects``.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import names as N
from gymmigrate.facts.class_shapes import is_batched_step_return, keeps_legacy_step
from gymmigrate.facts.creator_tables import entries, lookup, table_display
from gymmigrate.facts.done_uses import builds_record
from gymmigrate.facts.kinds import MAX_DEPTH, EnvKind
from gymmigrate.facts.module import FUNCTIONS, call_argument, own_returns, walk
from gymmigrate.facts.receiver_foreign import ForeignObjects
from gymmigrate.facts.receiver_gym_only import GymOnlyStacks
from gymmigrate.facts.version_checks import reads_version


class MadeObjects(ForeignObjects, GymOnlyStacks):
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
                bindings = self.facts.bindings_of(expr)
                if values is None and len(bindings) == 1 and isinstance(bindings[0], ast.Name):
                    values = self.loop_item_values(bindings[0])  # ``for i, env in enumerate(self.envs)``
            elif isinstance(last, ast.Name):
                values = self.loop_item_values(last)  # ``for env in self.envs:``
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
        for node in walk(statement):
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

    def reset_kept(self, classdef: ast.ClassDef) -> bool:
        """The reset ``classdef``'s instances run stays as it was after the run
        (``keeps_own_reset``): its own, or the one the nearest base of this module (or of the
        run) that has one defines. Such a reset takes no ``seed``/``options``."""
        if any(isinstance(s, FUNCTIONS) and s.name == "reset" for s in classdef.body):
            return self.keeps_own_reset(classdef)
        return self.inherited_reset_kept(classdef)

    def inherited_reset_kept(self, classdef: ast.ClassDef) -> bool:
        """The reset ``super().reset()`` reaches from ``classdef`` (its bases', in order) stays
        as it was after the run, without ``seed``/``options``: a helper of the project's own
        API the run keeps. False where no base of the run has a reset (Gymnasium's Env.reset
        takes the seed) or the first one that has migrates."""
        return self._base_reset_kept(classdef, frozenset({id(classdef)})) is True

    def _base_reset_kept(self, classdef: ast.ClassDef, seen: frozenset[int]) -> bool | None:
        """Whether the first reset of the run among ``classdef``'s bases stays as it was;
        None where none of them (nor their bases) has one."""
        for base in classdef.bases:
            local = self.local_class(base)
            if local is not None:
                if id(local) in seen:
                    continue
                if any(isinstance(s, FUNCTIONS) and s.name == "reset" for s in local.body):
                    return self.keeps_own_reset(local)
                found = self._base_reset_kept(local, seen | {id(local)})
                if found is not None:
                    return found
                continue
            if self.project is None:
                continue
            for qualified in self.qualified_names(base):
                if self.project.keeps_reset(qualified):
                    return True
                if "reset" in self.project.class_methods(qualified):
                    return False
        return None

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
        checks = [n for n in walk(step) if isinstance(n, ast.If) and reads_version(n.test, self.facts)]
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
                if isinstance(func, ast.Subscript):
                    return self._table_run_defined(func)
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

    def _table_run_defined(self, callee: ast.Subscript) -> bool:
        """``MAKERS[key]()`` on a closed table of this module (``facts/creator_tables.py``)
        one of whose creators is a class or def of the run, or a lambda calling one."""
        found = lookup(self.facts, callee)
        display = table_display(self.facts, found[0]) if found is not None and isinstance(found[0], ast.Name) else None
        values = entries(display, found[1]) if display is not None and found is not None else None
        for value in values or ():
            if isinstance(value, ast.Lambda):
                if self.run_defined(value.body):
                    return True
            elif self.local_class(value) is not None or self.local_function(value) is not None:
                return True
            elif any(self._from_run(q) for q in self.qualified_names(value)):
                return True
        return False

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
            for node in walk(self.facts.tree):
                if isinstance(node, ast.Assign):
                    for target in node.targets:
                        if isinstance(target, ast.Subscript) and isinstance(target.value, ast.Name):
                            out.setdefault(target.value.id, []).append(target)
            return out

        return self.facts.memo(("subscript-assigns", 0), compute)
