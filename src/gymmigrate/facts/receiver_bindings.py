"""What a name holds, from its bindings (``BindingKinds``, mixed into ``Receivers``): the
kind each binding stores (an assignment, a loop over a list of envs, an unpacked tuple a
def returns), how the kinds of a name's bindings join, and which bindings a read can see
where they disagree (the last binding before it, those that reach it), with the items of
lists and tuples of envs.

Separate from ``receivers.py`` because it answers one question of the façade's, what a
name is, from the flow of its bindings; ``Receivers`` classifies the other expressions
(calls, attributes) and asks this back for names. First of ``Receivers``' bases, so its
methods resolve as they did when ``Receivers`` defined them.
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from typing import TYPE_CHECKING

from gymmigrate.facts import same_tests
from gymmigrate.facts.creation_shapes import (
    NO_NEW_ITEMS,
    holds_no_items,
    items_added_in_place,
)
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.kinds import MAX_DEPTH, EnvKind, join_kinds
from gymmigrate.facts.module import (
    FUNCTIONS,
    call_argument,
    own_returns,
    param_default,
    walk,
)
from gymmigrate.facts.receiver_classes import duck_wrapper_param

if TYPE_CHECKING:
    from gymmigrate.facts.kinds import ReceiverFacade as _Facade
else:
    _Facade = object


# Builtins that read a list without adding to it: a list handed to one keeps the items the
# module shows.
_READING_BUILTINS = frozenset({"len", "enumerate", "zip", "list", "tuple", "sorted", "reversed", "iter", "print"})


class BindingKinds(_Facade):
    """The kinds of names from their bindings (part of ``Receivers``)."""

    def _classify_name(self, name: ast.Name) -> EnvKind:
        kind = self._classify_bindings(name)
        if kind is EnvKind.UNKNOWN and self.narrowing.is_env(name):
            # ``if isinstance(env, str): env = make(env)`` / ``assert isinstance(env, gym.Env)``
            # before the read: what the bindings could not tell, the code has checked or made.
            # A kind they do tell stays (gym's VectorEnv passed ``isinstance(x, gym.Env)``).
            return EnvKind.GYM_ENV
        if kind is EnvKind.UNKNOWN and self.narrowing.is_other_class(name):
            # ``elif isinstance(env, PlainEnv):`` around the read: an instance of a class shown
            # to be no Gym env, with that class's own API
            return EnvKind.NOT_ENV
        if kind in (EnvKind.UNKNOWN, EnvKind.GYM_ENV, EnvKind.GYM_VEC) and self.narrowing.is_not_env(name):
            # ``if isinstance(env, gym.Env): return GymWrapper(env)`` before the read: the
            # legacy code sent every Gym env (its vector envs too) elsewhere, so what reaches
            # here is no Gym env, whatever the callers pass now (GM708 reports the check a
            # Gymnasium vector env fails)
            return EnvKind.NOT_ENV
        return kind

    def _classify_bindings(self, name: ast.Name) -> EnvKind:
        bindings = self.facts.bindings_of(name)
        if not bindings:
            return EnvKind.UNKNOWN  # a builtin or a name this module never binds
        # Every read that sees the same bindings has the same kind: n reads of a name
        # rebound n times cost n, not n * n. Only an answer computed with nothing else in
        # progress is shared (deeper ones may be partial, cut short by a cycle).
        key = id(bindings)
        shared = self._name_kinds.get(key)
        if shared is None:
            kinds = set()
            for binding in bindings:
                kind = self.binding_kind(binding)
                if kind is not None:
                    kinds.add(kind)
            shared = self._join_bindings(bindings, kinds)
            if len(kinds) > 1:
                self._mixed.add(key)
            if self.depth == 1:
                self._name_kinds[key] = shared
        if key in self._mixed:
            # The bindings disagree (``env`` a VecEnv first, a Gym env later): a read that
            # only the last binding before it can reach has that binding's kind.
            last = self._dominating_binding(name)
            if last is not None:
                kind = self.binding_kind(last)
                if kind is not None and kind is not EnvKind.UNKNOWN:
                    return kind
            # Else only the bindings that may reach it: ``env = lib.make(...)`` overwritten by
            # ``env = ClipAction(env)`` before the read, ``env = Mask(env)`` after it.
            reaching = Flow.of(self.facts).reaching(name)
            if reaching:
                # ``if MODE == "arm": env = Arm() elif ...: env = gym.make(...)``, read again under
                # the same unchanged tests: the bindings of the other branches cannot reach it.
                cut = same_tests.excluded(self.facts, name, reaching)
                reaching = [b for b in reaching if id(b) not in cut]
            if reaching and len(reaching) < len(bindings):
                kinds = {k for k in (self._reaching_kind(b) for b in reaching) if k is not None}
                if kinds:
                    return self._join_bindings(reaching, kinds)
        return shared

    def _join_bindings(self, bindings: list[ast.AST], kinds: set[EnvKind]) -> EnvKind:
        """``join_kinds``, except that an object of a class the run defines (not a Gym env)
        is no placeholder like ``env = None``: next to a Gym env it leaves the kind unknown,
        so calls that may reach the project's own ``reset``/``step`` are never rewritten."""
        joined = join_kinds(kinds)
        if joined is EnvKind.UNKNOWN or EnvKind.NOT_ENV not in kinds or len(kinds) == 1:
            return joined
        return EnvKind.UNKNOWN if any(self._own_object(b) is not None for b in bindings) else joined

    def _own_object(self, binding: ast.AST) -> ast.Call | None:
        """The call of the run's own code (not a Gym env) that ``binding`` stores, if any."""
        statement = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
        value = statement.value if isinstance(statement, (ast.Assign, ast.AnnAssign, ast.NamedExpr)) else None
        if isinstance(value, ast.Call) and self.binding_kind(binding) is EnvKind.NOT_ENV and self.run_defined(value):
            return value
        return None

    def _reaching_kind(self, binding: ast.AST) -> EnvKind | None:
        """A binding's kind, where it decides a read alone: ``env = Recorder(env)`` of a plain
        class proves nothing about what it holds (UNKNOWN); a Gym wrapper around it does, and
        so does any other kind the class settles (``envs = VecScale(envs)`` of an SB3
        ``VecEnvWrapper`` is a VecEnv)."""
        kind = self.binding_kind(binding)
        statement = self.facts.statement_of(binding)
        if isinstance(binding, ast.Name) and isinstance(statement, ast.Assign) and kind is EnvKind.NOT_ENV:
            if any(isinstance(n, ast.Name) and n.id == binding.id for n in walk(statement.value)):
                return EnvKind.UNKNOWN
        return kind

    def _dominating_binding(self, name: ast.Name) -> ast.AST | None:
        flow = Flow.of(self.facts)
        last = flow.last_binding_of(name)
        if not isinstance(last, ast.Name):
            return None
        statement = self.facts.statement_of(last)
        if not (isinstance(statement, (ast.Assign, ast.AnnAssign)) and statement.value is not None):
            return None
        rebinds = any(isinstance(n, ast.Name) and n.id == name.id for n in walk(statement.value))
        if rebinds and not (
            self._makes_gym_wrapper(statement.value)
            or self.wrapped_argument(statement.value) is not None
            or self._makes_own_api_env(statement.value)
        ):
            return None  # ``env = wrap(env)``: its kind rests on the earlier values too
        return last if flow.dominates(statement, name, name) else None

    def _duck_rewrap(self, value: ast.expr, name: str) -> bool:
        """``env = Recorder(env)``: ``name`` rebound to an instance of a class of this module
        shaped as a duck wrapper (``duck_wrapper_param``) built around ``name`` itself, which
        the run proves to be one (or is proving now: this very binding is then one of the
        constructions it asks about, and adds no evidence of its own). It holds that env,
        migrated with it, so the name keeps the env's kind."""
        if not isinstance(value, ast.Call):
            return False
        classdef = self.local_class(value.func)
        param = duck_wrapper_param(classdef) if classdef is not None else None
        if classdef is None or param is None:
            return False
        init = next(s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "__init__")
        position = [*init.args.posonlyargs, *init.args.args].index(param) - 1  # calls pass no ``self``
        argument = call_argument(value, position, param.arg)
        if not (isinstance(argument, ast.Name) and argument.id == name):
            return False
        return self.facts.computing(("duck-wrapper", id(classdef))) or self.is_duck_wrapper(classdef)

    def handed_wrappers(self, value: ast.expr) -> list[ast.expr] | None:
        """``w(env)`` with ``w`` the variable of a loop over a list (``for w in wrappers``) or
        an item of one (``wrappers[i](env, **kwargs[i])``), where the run shows every item that
        list can hold and each names a Gym wrapper class: those items (none where every caller
        hands in an empty list, or none at all). None for any other call, and where one item
        is anything else or not shown (a caller of this module's def passing a list it builds
        elsewhere, a call from outside the module)."""
        if not (isinstance(value, ast.Call) and value.args and not isinstance(value.args[0], ast.Starred)):
            return None
        func = value.func
        container: ast.AST | None = None
        if isinstance(func, ast.Subscript):
            container = func.value
        elif isinstance(func, ast.Name):
            bindings = self.facts.bindings_of(func)
            loop = self.facts.parent(bindings[0]) if len(bindings) == 1 else None
            if isinstance(loop, (ast.For, ast.AsyncFor)) and loop.target is bindings[0]:
                container = loop.iter
        items = self._handed_items(container, 0) if container is not None else None
        if items is None or not all(self.names_gym_wrapper_class(item) for item in items):
            return None
        return items

    def _handed_items(self, container: ast.AST, depth: int) -> list[ast.expr] | None:
        """Every item a list, tuple or array can hold, where the module shows them all: a
        display (empty too), ``list``/``tuple``/numpy's ``array`` of one, a name bound only to
        those, a parameter of a def of this module from what each of its calls passes (its
        default where a call passes nothing); None otherwise."""
        if depth > 6:
            return None
        if isinstance(container, (ast.List, ast.Tuple)):
            return None if any(isinstance(el, ast.Starred) for el in container.elts) else list(container.elts)
        if isinstance(container, ast.Call) and len(container.args) <= 1 and not container.keywords:
            names = self.qualified_names(container.func)
            if isinstance(container.func, ast.Name) and container.func.id in ("list", "tuple") and not self.facts.bindings_of(container.func):
                names = names | {container.func.id}
            if names & {"list", "tuple", "numpy.array", "numpy.asarray"}:
                return self._handed_items(container.args[0], depth + 1) if container.args else []
            return None
        if not isinstance(container, ast.Name):
            return None
        return self._through_bindings(
            container, lambda value: self._handed_items(value, depth + 1), lambda param: self._param_handed_items(param, depth)
        )

    def _through_bindings(
        self,
        name: ast.Name,
        of_value: Callable[[ast.expr], list[ast.expr] | None],
        of_param: Callable[[ast.arg], list[ast.expr] | None],
    ) -> list[ast.expr] | None:
        """What every binding of ``name`` gives: ``of_value`` of a plain assignment's value,
        ``of_param`` of a parameter; None where one binding is anything else or gives None."""
        bindings = self.facts.bindings_of(name)
        if not bindings:
            return None
        values: list[ast.expr] = []
        for binding in bindings:
            parent = self.facts.parent(binding)
            if isinstance(binding, ast.Name) and isinstance(parent, ast.Assign) and parent.targets == [binding]:
                found = of_value(parent.value)
            elif isinstance(binding, ast.arg):
                found = of_param(binding)
            else:
                found = None
            if found is None:
                return None
            values += found
        return values

    def _param_handed_items(self, param: ast.arg, depth: int) -> list[ast.expr] | None:
        slot = self.facts.parameter_slot(param)
        if slot is None or slot[1] is not None:
            return None
        function, _, position = slot
        if self.callables.external_param_kinds(function, None, param.arg):
            return None  # a module the run holds passes its own list: not shown here
        calls = self.call_sites(function, None)
        if not calls:
            return None
        values: list[ast.expr] = []
        for call in calls:
            argument = call_argument(call, position, param.arg)
            if argument is None:
                if any(isinstance(a, ast.Starred) for a in call.args) or any(kw.arg is None for kw in call.keywords):
                    return None  # ``*args``/``**kwargs`` may pass it
                argument = param_default(function, param)
                if argument is None:
                    return None
            found = self._handed_items(argument, depth + 1)
            if found is None:
                return None
            values += found
        return values

    def binding_kind(self, binding: ast.AST) -> EnvKind | None:
        """The kind of value one binding stores (None: it adds no evidence, e.g. ``+=``)."""
        if isinstance(binding, (ast.alias, *FUNCTIONS, ast.ClassDef, ast.ExceptHandler)):
            return EnvKind.NOT_ENV  # modules, functions, classes, exceptions
        if isinstance(binding, ast.arg):
            return self._param_kind(binding)
        if not isinstance(binding, ast.Name):
            return EnvKind.UNKNOWN
        parent = self.facts.parent(binding)
        if isinstance(parent, ast.Assign):
            inner = self._kind_keeping_inner(parent.value)
            if isinstance(inner, ast.Name) and inner.id == binding.id:
                return None  # ``env = supersuit.dtype_v0(env, ...)``: env keeps its kind, no new evidence
            value = parent.value
            if self._duck_rewrap(value, binding.id):
                return None  # ``env = Recorder(env)``: a proxy the run proves, around the same env
            if isinstance(value, ast.Attribute) and value.attr == "unwrapped" and isinstance(value.value, ast.Name) and value.value.id == binding.id:
                return None  # ``env = env.unwrapped``: the same env, its kind unchanged
            wrappers = self.handed_wrappers(value) if _rewraps(value, binding.id) else None
            if wrappers is not None:
                # ``for w in wrappers: env = w(env)``: a Gym wrapper around the env is a Gym
                # env; with no wrapper handed in at all the loop never runs and the name
                # keeps what it held
                return EnvKind.GYM_ENV if wrappers else None
            return self.kind_of(parent.value)
        if isinstance(parent, ast.AnnAssign):
            if parent.value is not None:
                return self.kind_of(parent.value)
            return self.annotation_kind(parent.annotation)
        if isinstance(parent, ast.NamedExpr):
            return self.kind_of(parent.value)
        if isinstance(parent, ast.withitem):
            return self.kind_of(parent.context_expr)
        if isinstance(parent, (ast.For, ast.AsyncFor, ast.comprehension)) and parent.target is binding:
            return self._element_kind(parent.iter)
        if isinstance(parent, (ast.Tuple, ast.List)):
            return self._unpacked_kind(binding, parent)
        if isinstance(parent, (ast.AugAssign, ast.Delete)):
            return None  # ``del env`` unbinds: it adds no value of another kind
        return EnvKind.UNKNOWN

    def _unpacked_kind(self, target: ast.Name, container: ast.Tuple | ast.List) -> EnvKind:
        index = next(i for i, el in enumerate(container.elts) if el is target)
        holder = self.facts.parent(container)
        value: ast.AST | None = None
        if isinstance(holder, ast.Assign):
            value = holder.value
        elif isinstance(holder, (ast.For, ast.AsyncFor, ast.comprehension)) and holder.target is container:
            # ``for i, env in enumerate(envs)`` and ``for env, name in zip(envs, names)``
            iterable = holder.iter
            if isinstance(iterable, ast.Call) and isinstance(iterable.func, ast.Name):
                if iterable.func.id == "enumerate" and index == 1 and iterable.args:
                    return self._element_kind(iterable.args[0])
                if iterable.func.id == "zip" and index < len(iterable.args):
                    return self._element_kind(iterable.args[index])
            if isinstance(iterable, ast.Name):
                # ``for name, env in envs`` over a list of pairs the code builds
                # (``envs.append((name, env))``): the item at this place of every pair
                pairs = self._name_list_items(iterable)
                width = len(container.elts)
                if pairs and all(
                    isinstance(p, (ast.Tuple, ast.List)) and len(p.elts) == width and not any(isinstance(e, ast.Starred) for e in p.elts)
                    for p in pairs
                ):
                    return join_kinds(self.kind_of(p.elts[index]) for p in pairs)  # type: ignore[attr-defined]
            return EnvKind.UNKNOWN
        if isinstance(value, (ast.Tuple, ast.List)) and len(value.elts) == len(container.elts):
            if not any(isinstance(el, ast.Starred) for el in value.elts):
                return self.kind_of(value.elts[index])
        if value is not None and not isinstance(value, (ast.Tuple, ast.List)):
            # ``obs, info = env.reset()``: the targets are values returned by a call, not envs
            # unless the call is a local function returning a tuple of envs.
            local = self.local_function(value.func) if isinstance(value, ast.Call) else None
            if local is None and isinstance(value, ast.Call) and _is_env_method_call(value):
                return EnvKind.NOT_ENV
            if isinstance(local, FUNCTIONS) and not any(isinstance(el, ast.Starred) for el in container.elts):
                # ``env, agent = env_agent_config(cfg)`` where the def ends ``return env, agent``:
                # the item at this place of every tuple it returns.
                return self.returned_item_kind(local, index, len(container.elts))
            if local is None and isinstance(value, ast.Call) and not any(isinstance(el, ast.Starred) for el in container.elts):
                return self._named_methods_item_kind(value, index, len(container.elts))
        return EnvKind.UNKNOWN

    def _named_methods_item_kind(self, call: ast.Call, index: int, width: int) -> EnvKind:
        """``venv, obs = environment.get_sb_env()`` on an owner not traced, where every
        method of that name in the module's classes returns a vector env at this place
        (``return DummyVecEnv([lambda: self]), obs``): that vector env, which keeps its
        batch API; any other answer is no answer."""
        if not isinstance(call.func, ast.Attribute) or call.func.attr.startswith("__"):
            return EnvKind.UNKNOWN
        name = call.func.attr
        methods = [
            statement
            for classdef in self.facts.classes.values()
            for statement in classdef.body
            if isinstance(statement, FUNCTIONS) and statement.name == name
        ]
        if not methods:
            return EnvKind.UNKNOWN
        kinds = {self.returned_item_kind(method, index, width) for method in methods}
        if len(kinds) == 1 and kinds <= {EnvKind.SB3_VEC, EnvKind.GYM_VEC}:
            return kinds.pop()
        return EnvKind.UNKNOWN

    def returned_item_kind(self, function: ast.AST, index: int, width: int) -> EnvKind:
        """The kind of item ``index`` of what ``function`` returns, when every return is a
        tuple display of ``width`` items (anything else: unknown)."""
        values = [r.value for r in own_returns(function)]
        if not values:
            return EnvKind.UNKNOWN
        items = []
        for value in values:
            if not (isinstance(value, (ast.Tuple, ast.List)) and len(value.elts) == width):
                return EnvKind.UNKNOWN
            if any(isinstance(el, ast.Starred) for el in value.elts):
                return EnvKind.UNKNOWN
            items.append(value.elts[index])
        return join_kinds(self.kind_of(item) for item in items)

    def _element_kind(self, container: ast.AST) -> EnvKind:
        """Kind of the items of a list/tuple of envs (``envs[i]``, ``for env in envs``)."""
        if isinstance(container, (ast.List, ast.Tuple, ast.Set)):
            return join_kinds(self.kind_of(el) for el in container.elts if not isinstance(el, ast.Starred))
        if isinstance(container, (ast.ListComp, ast.GeneratorExp, ast.SetComp)):
            return self.kind_of(container.elt)
        if isinstance(container, ast.Name):
            bindings = self.facts.bindings_of(container)
            if not bindings:
                return EnvKind.UNKNOWN
            kinds = []
            for binding in bindings:
                parent = self.facts.parent(binding)
                if isinstance(binding, ast.Name) and isinstance(parent, ast.Assign):
                    kinds.append(self._element_kind_memo(parent.value))
                elif isinstance(binding, ast.arg):
                    kinds.append(self._param_element_kind(binding))
                else:
                    kinds.append(EnvKind.UNKNOWN)
            joined = join_kinds(kinds)
            if joined is EnvKind.UNKNOWN:
                # ``envs = []``, then ``envs.append(env)`` in a loop: the items it is given
                items = self._name_list_items(container)
                if items:
                    return join_kinds(self.kind_of(item) for item in items)
            return joined
        if isinstance(container, ast.Attribute) and isinstance(container.value, ast.Name):
            if self.is_self(container.value):
                values = self.self_attribute_values(container, container.attr)
                classdef = self.facts.enclosing_class(container)
                added = items_added_in_place(classdef, container.attr) if classdef is not None else None
                if not values or added is None or not any(added):
                    return join_kinds(self._element_kind_memo(v) for v in values) if values else EnvKind.UNKNOWN
                # ``self.envs = []`` then ``self.envs.append(OwnEnv(...))`` in the class: the items
                # are what it is given in place (an empty display or None holds none)
                items, containers = added
                kinds = [self._element_kind_memo(v) for v in (*values, *containers) if not holds_no_items(v)]
                kinds += [self.kind_of(item) for item in items]
                return join_kinds(kinds)
        return EnvKind.UNKNOWN

    def _name_list_items(self, container: ast.Name) -> list[ast.expr] | None:
        """The items of the list a name holds, where each binding of it is a list display and
        its scope adds items only with ``append``/``insert`` on it (``envs = []``, then
        ``envs.append((name, env))``): every item the run shows, or None."""
        bindings = self.facts.bindings_of(container)
        if not bindings:
            return None
        # reads that see the same bindings share one list (``bindings_of``): one answer for them
        return self.facts.memo(("name-list-items", id(bindings)), lambda: self._collect_name_list_items(container, bindings), while_computing=None)

    def _collect_name_list_items(self, container: ast.Name, bindings: list[ast.AST]) -> list[ast.expr] | None:
        items: list[ast.expr] = []
        for binding in bindings:
            parent = self.facts.parent(binding)
            if not (isinstance(binding, ast.Name) and isinstance(parent, ast.Assign) and parent.targets == [binding]):
                return None
            if not isinstance(parent.value, (ast.List, ast.Tuple)) or any(isinstance(e, ast.Starred) for e in parent.value.elts):
                return None
            items += parent.value.elts
        scope = self.facts.scope_of(container).node
        wanted = {id(b) for b in bindings}
        for node in walk(scope):
            if not (isinstance(node, ast.Name) and node.id == container.id and isinstance(node.ctx, ast.Load)):
                continue
            if {id(b) for b in self.facts.bindings_of(node)} != wanted:
                continue  # another variable of the same spelling (a def's own local)
            holder = self.facts.parent(node)
            if isinstance(holder, ast.Attribute) and holder.value is node:
                call = self.facts.parent(holder)
                if not (isinstance(call, ast.Call) and call.func is holder):
                    return None  # ``envs.extend``, a bound method handed on: items not shown
                if holder.attr == "append" and len(call.args) == 1 and not call.keywords:
                    items.append(call.args[0])
                elif holder.attr == "insert" and len(call.args) == 2 and not call.keywords:
                    items.append(call.args[1])
                elif holder.attr not in NO_NEW_ITEMS:
                    return None
            elif isinstance(holder, ast.Subscript) and holder.value is node:
                if not isinstance(holder.ctx, ast.Load):
                    return None  # ``envs[i] = ...``: an item the reads above do not show
            elif isinstance(holder, (ast.For, ast.AsyncFor, ast.comprehension)) and holder.iter is node:
                continue
            elif isinstance(holder, ast.Call) and self._stored_untouched(holder, node):
                continue  # ``Batch(envs)`` keeping the list as it is: its items are these
            elif not (isinstance(holder, ast.Call) and isinstance(holder.func, ast.Name) and holder.func.id in _READING_BUILTINS):
                return None  # handed on (``fill(envs)``), stored elsewhere: items may come from there
        return items

    def _stored_untouched(self, call: ast.Call, argument: ast.expr) -> bool:
        """``call`` builds a class of this module (no class here derives from it) whose
        ``__init__`` only stores the parameter ``argument`` lands on as ``self.<attr>``, and
        the class adds no items to that attribute in place: the list keeps the items given."""
        classdef = self.local_class(call.func)
        if classdef is None or any(isinstance(a, ast.Starred) for a in call.args) or argument not in call.args:
            return False
        if any(self.local_class(b) is classdef for sub in self.facts.classes.values() for b in sub.bases):
            return False
        init = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "__init__"), None)
        params = [*init.args.posonlyargs, *init.args.args] if init is not None else []
        position = call.args.index(argument) + 1  # calls pass no ``self``
        if init is None or position >= len(params):
            return False
        name = params[position].arg
        attrs = []
        for node in walk(init):
            if isinstance(node, ast.Name) and node.id == name and not isinstance(node.ctx, ast.Load):
                return False  # rebound in ``__init__``
            if isinstance(node, ast.Name) and node.id == name:
                statement = self.facts.parent(node)
                target = statement.targets[0] if isinstance(statement, ast.Assign) and len(statement.targets) == 1 else None
                stored = isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and self.is_self(target.value)
                if not (stored and isinstance(statement, ast.Assign) and statement.value is node):
                    return False  # read another way (``fill(envs)``, ``envs.append``): items may change
                attrs.append(target.attr)  # type: ignore[union-attr]
        return bool(attrs) and all((added := items_added_in_place(classdef, attr)) is not None and not any(added) for attr in attrs)

    def _param_element_kind(self, param: ast.arg) -> EnvKind:
        """The items of the list a parameter holds (``def __init__(self, envs)`` then
        ``self.envs = envs``), from what every call of its def in this module passes
        (``SerialVecEnv([Wrapper(gym.make(i)) for i in ids])``). Unknown when a call passes
        none, or another module calls the def: what that one passes is not seen here."""
        arguments = self._param_arguments(param)
        if arguments is None:
            return self._external_element_kind(param)
        return join_kinds(EnvKind.UNKNOWN if a is None else self._element_kind_memo(a) for a in arguments)

    def _external_element_kind(self, param: ast.arg) -> EnvKind:
        """The items of the list a parameter holds where only other modules of the run call
        its def (``Rollout(envs=self.envs)`` with ``self.envs = [OwnVecEnv(fns) for ...]``):
        the kind every one of those calls shows its items have; unknown where one shows none
        or the module calls the def itself too."""
        slot = self.facts.parameter_slot(param)
        if slot is None:
            return EnvKind.UNKNOWN
        function, classdef, _ = slot
        kinds = self.callables.external_item_kinds(function, classdef, param.arg)
        if not kinds or EnvKind.UNKNOWN in kinds:
            return EnvKind.UNKNOWN
        if classdef is not None and function.name == "__init__":
            local = bool(self.constructions(classdef)[0])
        elif classdef is None:
            local = bool(self.call_sites(function, None))
        else:
            return EnvKind.UNKNOWN
        return EnvKind.UNKNOWN if local else join_kinds(kinds)

    def loop_item_values(self, binding: ast.Name, _depth: int = 0) -> list[ast.expr] | None:
        """The expressions that make the items a loop variable takes (``for env in
        self.envs``, ``for i, env in enumerate(envs)``, comprehensions too), where the run
        shows every one; None otherwise."""
        parent = self.facts.parent(binding)
        iterable: ast.AST | None = None
        if isinstance(parent, (ast.For, ast.AsyncFor, ast.comprehension)) and parent.target is binding:
            iterable = parent.iter
        elif isinstance(parent, ast.Tuple):
            holder = self.facts.parent(parent)
            if isinstance(holder, (ast.For, ast.AsyncFor, ast.comprehension)) and holder.target is parent:
                call = holder.iter
                index = next(i for i, el in enumerate(parent.elts) if el is binding)
                if isinstance(call, ast.Call) and isinstance(call.func, ast.Name) and call.func.id == "enumerate" and index == 1 and call.args:
                    iterable = call.args[0]
        return self.item_values(iterable, _depth) if iterable is not None else None

    def item_values(self, container: ast.AST, _depth: int = 0) -> list[ast.expr] | None:
        """The expressions that make the items of a list (as ``_element_kind`` follows it:
        a display, a comprehension's item, a name or ``self.x`` bound to one, a parameter
        every call of its def in this module passes one); None where one is not shown."""
        if _depth > 6:
            return None
        if isinstance(container, (ast.List, ast.Tuple, ast.Set)):
            if any(isinstance(el, ast.Starred) for el in container.elts):
                return None
            return list(container.elts) or None
        if isinstance(container, (ast.ListComp, ast.GeneratorExp, ast.SetComp)):
            return [container.elt]
        values: list[ast.expr] = []
        if isinstance(container, ast.Name):
            return self._through_bindings(
                container, lambda value: self.item_values(value, _depth + 1), lambda param: self._param_item_values(param, _depth)
            )
        if isinstance(container, ast.Attribute) and isinstance(container.value, ast.Name) and self.is_self(container.value):
            stored = self.self_attribute_values(container, container.attr)
            if not stored:
                return None
            for value in stored:
                found = self.item_values(value, _depth + 1)
                if found is None:
                    return None
                values += found
            return values
        return None

    def _param_item_values(self, param: ast.arg, _depth: int) -> list[ast.expr] | None:
        calls = self._param_arguments(param)
        if calls is None:
            return None
        values: list[ast.expr] = []
        for argument in calls:
            found = self.item_values(argument, _depth + 1) if argument is not None else None
            if found is None:
                return None
            values += found
        return values

    def _param_arguments(self, param: ast.arg) -> list[ast.expr | None] | None:
        """What every call of the def of ``param`` in this module passes for it (None for a
        call that passes nothing); None when a call elsewhere, or none at all, is known."""
        slot = self.facts.parameter_slot(param)
        if slot is None:
            return None
        function, classdef, position = slot
        if self.callables.external_param_kinds(function, classdef, param.arg):
            return None
        if classdef is not None and function.name == "__init__":
            constructions, elsewhere = self.constructions(classdef)
            if elsewhere:
                return None
            calls = list(constructions)
        elif classdef is not None:
            return None
        else:
            calls = [(call, 0) for call in self.call_sites(function, None)]
        if not calls:
            return None
        return [call_argument(call, position + shift, param.arg) for call, shift in calls]

    def _element_kind_memo(self, container: ast.AST) -> EnvKind:
        key = ("element-kind", id(container))
        cached = self.facts.peek(key)
        if cached is not None:
            return cached  # type: ignore[return-value]
        if self.depth > MAX_DEPTH:
            return EnvKind.UNKNOWN  # not memoized: a shallower question may still answer it

        def compute() -> EnvKind:
            self.depth += 1
            try:
                return self._element_kind(container)
            finally:
                self.depth -= 1

        return self.facts.memo(key, compute, while_computing=EnvKind.UNKNOWN)


def _is_env_method_call(call: ast.Call) -> bool:
    return isinstance(call.func, ast.Attribute) and call.func.attr in ("reset", "step", "last")


def _rewraps(value: ast.expr, name: str) -> bool:
    """``value`` is a call whose first argument is ``name`` itself (``env = w(env)``)."""
    return isinstance(value, ast.Call) and bool(value.args) and isinstance(value.args[0], ast.Name) and value.args[0].id == name
