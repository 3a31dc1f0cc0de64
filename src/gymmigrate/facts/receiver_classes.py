"""What a class of the module is: its instances' ``EnvKind`` from its bases
(``ClassKinds``, mixed into ``Receivers``: Gym wrappers, a wrapper around a Gym-only
library's object, ``super()`` calls), and the duck wrappers it proves from a class's
forwarding to ``self.env``. The shape predicates that decide from a class's body alone (a
VecEnv-shaped class, a reset that returns bare observations, a step that keeps the legacy
four-field contract) are in ``class_shapes.py``.
"""

from __future__ import annotations

import ast
import weakref
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, cast

from gymmigrate.facts import names as N
from gymmigrate.facts.batched_steps import done_read_per_env
from gymmigrate.facts.class_shapes import (
    is_vec_env_shaped,
    keeps_bare_reset,
    keeps_legacy_step,
    touches_self_env,
)
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import (
    FUNCTIONS,
    ModuleFacts,
    call_argument,
    is_super_call,
    named_class_call,
    own_returns,
    self_attribute,
    unsubscripted,
    walk,
)
from gymmigrate.facts.own_api import own_api_shape
from gymmigrate.facts.wrapper_attributes import defines_getattr, lookup_forwarded_to

if TYPE_CHECKING:
    from gymmigrate.facts.kinds import ReceiverFacade as _Facade
else:
    _Facade = object


class ClassKinds(_Facade):
    """The kinds of the module's classes and of ``super()`` receivers (part of ``Receivers``)."""

    def class_kind(self, classdef: ast.ClassDef) -> EnvKind:
        """The kind of instances of a class defined in this module, from its bases; a class
        with no library base that steps many envs at once (``step_async``/``step_wait``,
        baselines' ``SubprocVecEnv`` copied into a project) is a VecEnv."""
        # ``abc.ABC`` says nothing about what a class is, as ``object`` does not: a project's
        # ``class VecEnv(ABC)`` with step_async/step_wait is a VecEnv, as without it
        kinds = [self._base_kind(base) for base in classdef.bases if not is_object(base) and not self._abstract_base(base)]
        useful = [k for k in kinds if k not in (EnvKind.UNKNOWN, EnvKind.NOT_ENV)]
        if useful and useful[0] is EnvKind.GYM_ENV and (
                self.wraps_gym_only(classdef) is not None or self.wraps_pz_parallel(classdef)):
            # A wrapper around an object of a Gym-only library (gym_unity's batched envs): that
            # object keeps gym's API, so neither the wrapper nor its callers are Gymnasium code.
            return EnvKind.UNKNOWN
        if useful and useful[0] is EnvKind.GYM_ENV and self.own_batch(classdef):
            # Not a wrapper layer (no ``self.env``, no base ``__init__``): a batch of the
            # project's own, stepped as a VecEnv is (four fields, per-env flags).
            return EnvKind.SB3_VEC
        if useful and useful[0] is EnvKind.GYM_ENV and self.wraps_vec_env(classdef):
            # A Gym wrapper the run puts only around VecEnvs: its instances answer as the
            # VecEnv does (four-field step, reset with no seed), and are left as VecEnvs are.
            return EnvKind.SB3_VEC
        if useful:
            if useful[0] is EnvKind.GYM_VEC and keeps_bare_reset(classdef):
                # A vector env subclass whose own reset returns the bare observations (no
                # rule changes a vector env's reset): its callers are on that contract, so
                # its instances are not rewritten as Gymnasium vector envs; reported.
                return EnvKind.UNKNOWN
            if useful[0] is EnvKind.GYM_ENV and self.own_api(classdef) is not None:
                return EnvKind.OWN_API
            return useful[0]
        if not kinds and self.is_duck_wrapper(classdef):
            return EnvKind.GYM_ENV  # a plain class around a Gym env that forwards to it
        if all(k is EnvKind.NOT_ENV for k in kinds) and is_vec_env_shaped(classdef):
            return EnvKind.SB3_VEC
        if kinds and any(self._own_api_base(b) for b in classdef.bases):
            # ``class Preprocess(AtariPreprocessing)`` of tf_agents, ``class Stacker(Adapter)``
            # of a dm_env adapter of another module of the run: that API's env, not Gym's
            return EnvKind.NOT_ENV
        return EnvKind.NOT_ENV if not kinds else EnvKind.UNKNOWN

    def _abstract_base(self, base: ast.AST) -> bool:
        return any(q in ("abc.ABC", "typing.Generic") for q in self.qualified_names(base))

    def own_api(self, classdef: ast.ClassDef) -> str | None:
        """How an env class (no wrapper: GM602 has those) shows an API of its own
        (``own_api_shape``), or None."""
        if self.is_gym_wrapper_class(classdef):
            return None
        return self.facts.memo(("own-api", id(classdef)), lambda: own_api_shape(classdef))

    def wraps_gym_only(self, classdef: ast.ClassDef) -> str | None:
        """A Gym wrapper class of this module that a construction here wraps around an object
        a Gym-only library makes (``BatchWrapper(UnityEnv(...))`` of gym_unity, directly or
        through other wrappers of the module): that library's callable, else None. The
        object keeps gym's API (a four-field step, per-agent arrays), so the wrapper is not
        migrated, and it is reported (``rules/wrappers``)."""
        return self.facts.memo(("wraps-gym-only", id(classdef)), lambda: self._wraps_gym_only(classdef), while_computing=None)

    def _wraps_gym_only(self, classdef: ast.ClassDef) -> str | None:
        if not self.is_gym_wrapper_class(classdef):
            return None
        for call in self.facts.calls_by_name.get(classdef.name, ()):
            found = self._gym_only_inside(call_argument(call, 0, "env"), 0)
            if found is not None:
                return found
        return None

    def wraps_pz_parallel(self, classdef: ast.ClassDef) -> bool:
        """A subclass of a Gym wrapper class that a construction of this module puts around a
        PettingZoo parallel env (``ListView(pistonball_v6.parallel_env())``): gym's Wrapper took
        any object, Gymnasium's refuses one that is no ``gymnasium.Env`` (TypeError). Its
        ``self.env`` is that parallel env (per-agent dicts, PettingZoo's own reset and step),
        and the class returns what it builds from them: neither it nor its callers are Gym
        code; the class is reported (``rules/wrappers``)."""
        return bool(self.facts.memo(("wraps-pz-parallel", id(classdef)), lambda: self._wraps_pz_parallel(classdef),
                                    while_computing=False))

    def _wraps_pz_parallel(self, classdef: ast.ClassDef) -> bool:
        if not self.has_gym_wrapper_base(classdef):
            return False
        constructions, _ = self.constructions(classdef)
        wrapped = [call_argument(call, shift, "env") for call, shift in constructions]
        # every construction the module shows passes one (a Gym env at another would make
        # the class serve both: left to the Gym rules, which report what they cannot do)
        return bool(wrapped) and all(
            value is not None and self.kind_of(value) is EnvKind.PZ_PARALLEL for value in wrapped)

    def wraps_vec_env(self, classdef: ast.ClassDef) -> bool:
        """A subclass of a Gym wrapper class around which the run puts only VecEnvs (baselines'
        or SB3's, the project's own copy or subclass): every construction the run shows hands
        its constructor one, or, where the run constructs it nowhere, its own methods take
        what ``self.env.step_wait()`` gives apart. gym's Wrapper took any object; Gymnasium's
        refuses one that is no ``gymnasium.Env`` (TypeError). Its ``self.env`` is that VecEnv
        (four-field step, reset with no seed), so neither the class nor the calls on its
        instances are Gym code: they are left, and the class is reported (``rules/wrappers``)."""
        return self._wrapped_vec_env(classdef) == "all"

    def wraps_vec_env_sometimes(self, classdef: ast.ClassDef) -> bool:
        """Some constructions of the run hand the wrapper class a VecEnv, others a Gym env:
        one class cannot be both Gymnasium's wrapper and the VecEnv's (reported)."""
        return self._wrapped_vec_env(classdef) == "some"

    def _wrapped_vec_env(self, classdef: ast.ClassDef) -> str:
        """``all`` (every construction hands it a VecEnv), ``some`` (others a Gym env), or
        empty (none does, or some hand what the run cannot tell)."""
        found = self._vec_wrapped.get(id(classdef))
        if found is not None:
            return found
        if classdef in self._vec_wrapping:
            self._cuts += 1  # ``env = Stats(env)`` asks its own class back: no evidence, and not kept
            return ""
        cuts = self._cuts
        self._vec_wrapping.add(classdef)
        try:
            answer = self._wrapped_vec_kinds(classdef)
        finally:
            self._vec_wrapping.discard(classdef)
        # an answer cut short by a question still open above is asked again (``kind_of``'s rule)
        if self._cuts == cuts or not (self._in_progress or self._vec_wrapping):
            self._vec_wrapped[id(classdef)] = answer
        return answer

    def _wrapped_vec_kinds(self, classdef: ast.ClassDef) -> str:
        if not self.has_gym_wrapper_base(classdef):
            return ""
        init = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "__init__"), None)
        params = [*init.args.posonlyargs, *init.args.args][1:] if init is not None else []
        name = params[0].arg if params else "env"
        constructions, elsewhere = self.constructions(classdef)
        kinds: list[EnvKind] = []
        # a subclass of this module that is itself a VecEnv wrapper (reported on its own) puts
        # this class around VecEnvs too, but says nothing of its other constructions
        through_vec_subclass = 0
        for call, shift in constructions:
            sub = self.facts.enclosing_class(call)
            if sub is not None and any(self.local_class(b) is classdef for b in sub.bases) and self.wraps_vec_env(sub):
                through_vec_subclass += 1
                continue
            argument = call_argument(call, shift, name)
            kinds.append(self.kind_of(argument) if argument is not None else EnvKind.UNKNOWN)
        if self.project is not None and self.facts.parent(classdef) is self.facts.tree:
            kinds += self.project.param_kinds(f"{classdef.name}.__init__", name)
        if elsewhere:
            kinds.append(EnvKind.UNKNOWN)  # a subclass built in another module, with what it passes there
        if not kinds and not through_vec_subclass:
            # constructed nowhere in the run: its own methods say what it wraps, where they
            # unpack a VecEnv's step_wait() on ``self.env``
            return "all" if self.project is not None and _unpacks_inner_step_wait(classdef) else ""
        if all(k is EnvKind.SB3_VEC for k in kinds):
            return "all"
        if EnvKind.SB3_VEC in kinds and any(k.is_gym for k in kinds):
            return "some"
        return ""

    def _gym_only_inside(self, expr: ast.expr | None, depth: int) -> str | None:
        if expr is None or depth > 4:
            return None
        if isinstance(expr, ast.Call) and isinstance(expr.func, ast.Name):
            inner = self.local_class(expr.func)
            if inner is not None:  # another wrapper of the module around it
                return self._gym_only_inside(call_argument(expr, 0, "env"), depth + 1) if self.is_gym_wrapper_class(inner) else None
        if isinstance(expr, ast.Name):
            flow = Flow.of(self.facts)
            own = self.facts.statement_of(expr)
            last = flow.last_binding_of(expr)
            if last is not None and isinstance(own, ast.Assign) and self.facts.statement_of(last) is own:
                # ``env = Wrapper(env)`` in a factory: the read sees the assignment above it
                # (``env = make(...)``), followed back to what made the env
                above = flow.binding_above(expr, own)
                statement = self.facts.statement_of(above) if above is not None else None
                if isinstance(statement, ast.Assign) and isinstance(statement.value, ast.Call):
                    if self.local_class(statement.value.func) is not None:
                        return self._gym_only_inside(statement.value, depth + 1)
                    made = self.library_made(statement.value)
                    return made if made is not None and made.split(".", 1)[0] in N.GYM_ONLY_PACKAGES else None
                return None
            dominating = self._dominating_binding(expr)
            statement = self.facts.statement_of(dominating) if dominating is not None else None
            if isinstance(statement, ast.Assign) and isinstance(statement.value, ast.Call) and self.local_class(statement.value.func) is not None:
                return self._gym_only_inside(statement.value, depth + 1)
        made = self.library_made(expr)
        return made if made is not None and made.split(".", 1)[0] in N.GYM_ONLY_PACKAGES else None

    def statement_seen(self, read: ast.Name) -> ast.stmt | None:
        """The assignment whose value ``read`` sees; in ``env = Wrapper(env)`` that is the
        assignment above it in the block (``env = make(...)``), not the statement itself,
        so a chain of rebindings in a factory is followed back to what made the env."""
        own = self.facts.statement_of(read)
        flow = Flow.of(self.facts)
        last = flow.last_binding_of(read)
        if last is not None and isinstance(own, ast.stmt) and self.facts.statement_of(last) is own:
            above = flow.binding_above(read, own)
            return self.facts.statement_of(above) if above is not None else None
        statement = self.facts.statement_of(last) if last is not None else None
        if not isinstance(statement, ast.stmt) or isinstance(statement, (ast.For, ast.AsyncFor, ast.With, ast.AsyncWith)):
            return None
        return statement if flow.dominates(statement, read, read) else None

    def base_methods(self, classdef: ast.ClassDef) -> frozenset[str]:
        """The methods the class's bases of the run define: this module's, at any depth, and
        other modules' (with their own bases) through the run's facts. gym < 0.9's ``_step``
        is the project's own hook, not a dead one, where such a base defines ``step``
        (custom envs, GM504; wrappers, GM616)."""
        return self.facts.memo(("base-methods", id(classdef)), lambda: self._base_methods(classdef), while_computing=frozenset())

    def _base_methods(self, classdef: ast.ClassDef) -> frozenset[str]:
        found: set[str] = set()
        seen = {id(classdef)}
        todo = [classdef]
        while todo:
            for base in todo.pop().bases:
                local = self.local_class(base)
                if local is not None:
                    if id(local) not in seen:
                        seen.add(id(local))
                        found.update(s.name for s in local.body if isinstance(s, (ast.FunctionDef, ast.AsyncFunctionDef)))
                        todo.append(local)
                elif self.project is not None:
                    for qualified in self.facts.qualified_names(base):
                        found |= self.project.class_methods(qualified)
        return frozenset(found)

    def wraps_legacy_step(self, classdef: ast.ClassDef) -> str | None:
        """A Gym wrapper class of this module that a construction here puts around an instance
        of a class whose step keeps its four fields (a batch of envs: ``Stats(Batch(...))``,
        directly or through another such wrapper): that class's name, else None. The wrapped
        step still returns four values, so the wrapper's own step keeps them too (its callers
        with it), and it is reported (``rules/wrappers``)."""
        return self.facts.memo(("wraps-legacy-step", id(classdef)), lambda: self._wraps_legacy_step(classdef), while_computing=None)

    def _wraps_legacy_step(self, classdef: ast.ClassDef) -> str | None:
        if not self.is_gym_wrapper_class(classdef):
            return None
        for call in self.facts.calls_by_name.get(classdef.name, ()):
            inner = call_argument(call, 0, "env")
            found = self.legacy_step_class(inner) if inner is not None else None
            if found is not None:
                return found
        return None

    def is_gym_wrapper_class(self, classdef: ast.ClassDef, _seen: frozenset[int] = frozenset()) -> bool:
        """A subclass of a Gym wrapper (through classes of the module), or a duck wrapper
        the run proves (``is_duck_wrapper``)."""
        if self.is_duck_wrapper(classdef):
            return True
        if self.own_batch(classdef):
            return False  # no layer over an env: a batch of its own on the wrapper base
        return self.has_gym_wrapper_base(classdef, _seen)

    def own_batch(self, classdef: ast.ClassDef) -> bool:
        """A class on a Gym wrapper base (not ``gym.Env``'s: an env class holds what it
        steps as it likes) that ``own_batch_on_wrapper_base`` shows is a batch of its own."""
        return bool(
            self.facts.memo(
                ("own-batch", id(classdef)),
                lambda: own_batch_on_wrapper_base(self.facts, classdef) and self.has_gym_wrapper_base(classdef),
                while_computing=False,
            )
        )

    def is_duck_wrapper(self, classdef: ast.ClassDef) -> bool:
        """A plain class (no base but ``object``) that stores a constructor parameter in
        ``self.env`` and forwards to it (``__getattr__`` giving ``getattr(self.env, name)``,
        or a ``step``/``reset`` returning what ``self.env.step``/``self.env.reset`` give),
        where every construction of the run passes a Gym env: it is a Gym wrapper in all
        but name, and is migrated as one with its callers (the run is the unit)."""
        return bool(self.facts.memo(("duck-wrapper", id(classdef)), lambda: self._is_duck_wrapper(classdef), while_computing=None))

    def _is_duck_wrapper(self, classdef: ast.ClassDef) -> bool:
        param = duck_wrapper_param(classdef)
        return param is not None and self._param_kind(param) is EnvKind.GYM_ENV

    def unproved_duck_wrapper(self, classdef: ast.ClassDef) -> bool:
        """Shaped as a duck wrapper, but the run does not prove every construction passes a
        Gym env (some may: what they pass is unknown, or mixed): the class and its callers are
        left alone and the class is reported."""
        param = duck_wrapper_param(classdef)
        return param is not None and not self.is_duck_wrapper(classdef) and self._param_kind(param) is EnvKind.UNKNOWN

    def built_nowhere(self, classdef: ast.ClassDef) -> bool:
        """A top-level class that no code of a run of several modules builds or hands on: its
        module reads its name nowhere (no call, no value), and no other module of the run
        calls it, derives from it or reads it as a value. No env reaches its methods in the
        run, so nothing there is to migrate with it. False for a file run alone (the
        modules that would build it are not seen)."""
        project = self.project
        if project is None or self.facts.classes.get(classdef.name) is not classdef:
            return False
        if self.facts.reads_of(classdef.name):
            return False
        return not (
            project.built_elsewhere(classdef.name)
            or project.subclassed_elsewhere(classdef.name)
            or project.handed_on(classdef.name)
            or project.handed_on(f"{classdef.name}.__init__")  # the join names a class by its constructor
        )

    def has_gym_wrapper_base(self, classdef: ast.ClassDef, _seen: frozenset[int] = frozenset()) -> bool:
        return any(self.is_gym_wrapper_base(classdef, base, _seen) for base in classdef.bases)

    def is_gym_wrapper_base(self, classdef: ast.ClassDef, base: ast.expr, _seen: frozenset[int] = frozenset()) -> bool:
        """``base`` (one of ``classdef``'s bases) is a Gym wrapper class, Gym's own or one of the run."""
        for q in self.qualified_names(base):
            rest = N.strip_gym_prefix(q)
            if rest is not None and (rest in N.GYM_WRAPPER_BASE_CLASSES or N.is_wrapper_class_path(rest) or rest.startswith("wrappers.vector.")):
                return True
            if rest is None and self.project is not None and self.project.is_wrapper_class(q):
                return True  # a Gym wrapper class of another module of the run (``pkg.TrialWrapper``)
        local = self.local_class(base)
        if local is not None and local is not classdef and id(local) not in _seen:
            if self.is_gym_wrapper_class(local, _seen | {id(classdef)}):
                return True
        return False

    def forwards_inner_contract(self, classdef: ast.ClassDef) -> bool:
        """A Gym wrapper whose step and reset hand on what the wrapped env's give, unchanged:
        derived from Gym's ``Wrapper`` or ``ActionWrapper`` only, and its own ``step`` and
        ``reset``, where it defines them, return ``self.env.step(...)`` / ``self.env.reset(...)``
        on every path. Put around an env kept on the legacy API, it keeps that API."""
        if not classdef.bases or classdef.keywords:
            return False
        for base in classdef.bases:
            names = {N.strip_gym_prefix(q) for q in self.qualified_names(base)}
            if not names or not names <= _FORWARDING_BASES:
                return False
        methods = {s.name: s for s in classdef.body if isinstance(s, FUNCTIONS)}
        # a step or reset it does not define is Gym's base's, which forwards
        return all(name not in methods or _returns_inner(methods[name], name) for name in ("step", "reset"))

    def local_class(self, func: ast.AST) -> ast.ClassDef | None:
        if not isinstance(func, ast.Name):
            return None
        found = self.facts.classes.get(func.id)
        if found is not None or not self.facts.all_classes:
            return found
        # A class defined in a def (a test's ``class TaskEnv(pkg.TrialEnv)`` and its
        # ``TaskEnv()`` below): the one class statement that binds the name where it is read.
        bindings = self.facts.bindings_of(func)
        return bindings[0] if len(bindings) == 1 and isinstance(bindings[0], ast.ClassDef) else None

    def local_lineage(
        self, classdef: ast.ClassDef, follows: Callable[[ast.ClassDef], bool] | None = None
    ) -> Iterator[ast.ClassDef]:
        """``classdef`` and the classes of this module it derives from, each once (depth
        first, a class before its bases). ``follows``: whether to go on to the bases of a
        class (GM503: one that defines its own ``seed()`` hides those above it)."""
        seen: set[int] = set()
        pending = [classdef]
        while pending:
            current = pending.pop()
            if id(current) in seen:
                continue
            seen.add(id(current))
            yield current
            if follows is None or follows(current):
                pending.extend(base for b in current.bases if (base := self.local_class(unsubscripted(b))) is not None)

    def local_function(self, func: ast.AST) -> ast.FunctionDef | ast.AsyncFunctionDef | None:
        return self.facts.functions.get(func.id) if isinstance(func, ast.Name) else None

    def super_kind(self, receiver: ast.AST) -> EnvKind | None:
        """``super().step(a)`` inside a Gym wrapper or env subclass is the wrapped Gym call;
        so is ``Base.step(self, a)`` naming one of the class's own bases."""
        if not is_super_call(receiver):
            return self._explicit_base_kind(receiver)
        classdef = self.facts.enclosing_class(receiver)
        if classdef is None:
            return None
        if self.is_gym_wrapper_class(classdef):
            if self.wraps_pz_parallel(classdef):
                return None  # the wrapped parallel env: `self.env` says so
            if self.wraps_vec_env(classdef):
                return EnvKind.SB3_VEC  # the VecEnv every construction wraps
            return None if self.wraps_gym_only(classdef) is not None else EnvKind.GYM_ENV
        kind = self.class_kind(classdef)
        if kind is EnvKind.NOT_ENV and any(self._own_api_base(b) for b in classdef.bases):
            return kind  # the base of a library with its own env API (tf_agents): left alone
        if kind is EnvKind.OWN_API:
            return kind  # a class on a contract of its own: its super() calls stay as they are
        return kind if kind.is_gym else None

    def derives_own_api(self, classdef: ast.ClassDef) -> bool:
        """The class derives from a library class with an env API of its own (a dm_env
        adapter of the project): its instances are that API's envs, whatever they hold.
        Not one that forwards unknown attributes (``__getattr__``, its own or a base's of
        this module): ``adapter.render(mode)`` then reaches the Gym env it holds, so other
        modules must not take its instances for another API's envs and leave such calls."""
        return any(self._own_api_base(b) for b in classdef.bases) and not self._forwards_attributes(classdef)

    def _forwards_attributes(self, classdef: ast.ClassDef, depth: int = 0) -> bool:
        """It or a base of this module defines ``__getattr__``, wherever that leads (the
        questions about lookup side by side: ``facts/wrapper_attributes.py``)."""
        if defines_getattr(classdef):
            return True
        if depth > 4:
            return False
        for base in classdef.bases:
            local = self.local_class(base)
            if local is not None and self._forwards_attributes(local, depth + 1):
                return True
        return False

    def _own_api_base(self, base: ast.AST, depth: int = 0) -> bool:
        """A class of a library with an env API of its own (``dm_env.Environment``), or a
        class of this module or of another module of the run derived from one (``class
        Adapter(Wrapper)`` with ``class Wrapper(dm_env.Environment)``)."""
        if any(N.has_own_env_api(q) for q in self.qualified_names(base)):
            return True
        local = self.local_class(base)
        if local is None:
            # a class of another module of the run that derives one (``adapters.Adapter``)
            project = self.project
            return project is not None and any(project.derives_own_api(q) for q in self.qualified_names(base))
        if depth > 4:
            return False
        return any(self._own_api_base(b, depth + 1) for b in local.bases)

    def _explicit_base_kind(self, receiver: ast.AST) -> EnvKind | None:
        """``Base.step(self, a)`` naming a base of the method's class, the class itself or a
        class of this module it derives from (``Cls.step(self, a)``): a call of that class's
        step on this instance, whose contract is that class's once migrated."""
        if not isinstance(receiver, (ast.Name, ast.Attribute)):
            return None
        method = self.facts.parent(receiver)
        call = self.facts.parent(method) if isinstance(method, ast.Attribute) else None
        if not (isinstance(call, ast.Call) and call.func is method and isinstance(method, ast.Attribute)):
            return None
        function = self.facts.enclosing_function(call)
        classdef = self.facts.enclosing_class(call)
        if function is None or classdef is None or self.facts.parent(function) is not classdef:
            return None
        base = named_class_call(call, method.attr, function, classdef.bases)
        if base is not None:
            kind = self._base_kind(base)
            return kind if kind.is_gym else None
        lineage = {c.name: c for c in self.local_lineage(classdef)}
        spelled = [ast.Name(id=name, ctx=ast.Load()) for name in lineage]
        named = named_class_call(call, method.attr, function, spelled)
        if not isinstance(named, ast.Name):
            return None
        local = lineage[named.id]
        if keeps_legacy_step(local):
            return None  # that class's step keeps four fields: so does this call of it
        kind = self.facts.memo(("class-kind", id(local)), lambda: self.class_kind(local), while_computing=EnvKind.UNKNOWN)
        return kind if kind.is_gym else None

    def checked_class_is_env(self, cls: ast.expr) -> bool | None:
        """Whether instances of the class an ``isinstance`` names are Gym envs: True for a Gym
        env class (of Gym's, or of the run deriving one), False for a class shown to be
        something else (the run's own plain env class, another library's env), None when the
        run cannot tell."""
        kind = self._base_kind(cls)
        if kind is EnvKind.UNKNOWN and self.project is not None:
            # ``_base_kind`` passes over a class of another module that is no env
            found = {self.project.call_kind(q) for q in self.qualified_names(cls)} - {None}
            if found == {EnvKind.NOT_ENV}:
                kind = EnvKind.NOT_ENV
        if kind is EnvKind.GYM_ENV:
            # a wrapper class of the run may wrap anything (GM604 asks what is forwarded
            # under its check): only an env class of the run says what the object is
            local = self.local_class(cls)
            if local is not None:
                return None if self.is_gym_wrapper_class(local) else True
            project = self.project
            if project is None or any(project.wrapper_class(q) for q in self.qualified_names(cls)):
                return None
            return True if any(project.call_kind(q) is EnvKind.GYM_ENV for q in self.qualified_names(cls)) else None
        if kind in (EnvKind.UNKNOWN, EnvKind.GYM_VEC, EnvKind.OWN_API):
            return None
        return False

    def _base_kind(self, base: ast.AST) -> EnvKind:
        for q in self.qualified_names(base):
            rest = N.strip_gym_prefix(q)
            if rest is not None:
                if rest in N.GYM_ENV_BASE_CLASSES or N.is_wrapper_class_path(rest) or rest.startswith("wrappers.vector."):
                    return EnvKind.GYM_ENV
                if rest.startswith("vector."):
                    return EnvKind.GYM_VEC
                if N.is_builtin_env_class_path(rest):
                    # one of Gym's own env classes (``cartpole.CartPoleEnv``): a Gym env
                    return EnvKind.GYM_ENV
            other = other_library_class_kind(q)
            if other is not None:
                return other
        if self.project is not None:
            for q in self.qualified_names(base):
                found = self.project.call_kind(q)  # an env class of another module of the run
                if found is not None and found not in (EnvKind.UNKNOWN, EnvKind.NOT_ENV):
                    return found
        local = self.local_class(base)
        if local is not None:
            # Class cycles (``class A(B)`` / ``class B(A)``) add no evidence.
            return self.facts.memo(("class-kind", id(local)), lambda: self.class_kind(local), while_computing=EnvKind.UNKNOWN)
        return EnvKind.UNKNOWN


def duck_wrapper_param(classdef: ast.ClassDef) -> ast.arg | None:
    """The ``__init__`` parameter a duck wrapper holds (``duck_wrapper_slot``), or None."""
    slot = duck_wrapper_slot(classdef)
    return slot[0] if slot is not None else None


def duck_wrapper_attribute(classdef: ast.ClassDef) -> str | None:
    """The attribute a duck wrapper keeps its env in (``self.env``, ``self.environment``), or None."""
    slot = duck_wrapper_slot(classdef)
    return slot[1] if slot is not None else None


def duck_wrapper_slot(classdef: ast.ClassDef) -> tuple[ast.arg, str] | None:
    """The class's slot (``_duck_wrapper_slot``), decided once per class: every receiver
    question about the class's instances asks it again."""
    known = _DUCK_SLOTS.get(classdef, _UNDECIDED)
    if known is _UNDECIDED:
        known = _DUCK_SLOTS[classdef] = _duck_wrapper_slot(classdef)
    return cast("tuple[ast.arg, str] | None", known)


_UNDECIDED = object()
_DUCK_SLOTS: weakref.WeakKeyDictionary[ast.ClassDef, object] = weakref.WeakKeyDictionary()


def _duck_wrapper_slot(classdef: ast.ClassDef) -> tuple[ast.arg, str] | None:
    """The ``__init__`` parameter a plain class stores in an attribute (its only store
    there), with that attribute, when the class forwards to it: ``__getattr__`` returns
    ``getattr(self.env, name)``, or ``step`` returns ``self.env.step(...)`` or the four
    names it unpacks from it, or ``reset`` returns ``self.env.reset(...)``; or, in any
    attribute, when the class stands for the env it holds: it offers the env's spaces itself
    and keeps the held env's legacy contract in its place (``_legacy_contract``: a
    preprocessing class that skips frames and builds its observations itself). A helper
    with only a reset and a step of its own around an env keeps its own contract. ``env``
    is asked first. None for any other class."""
    if classdef.keywords or not all(is_object(b) for b in classdef.bases):
        return None
    methods = {s.name: s for s in classdef.body if isinstance(s, FUNCTIONS)}
    init = methods.get("__init__")
    if init is None:
        return None
    params = [*init.args.posonlyargs, *init.args.args][1:]
    stores: dict[str, list[ast.stmt]] = {}
    for node in walk(classdef):
        if isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign)):
            for target in node.targets if isinstance(node, ast.Assign) else [node.target]:
                attribute = self_attribute(target)
                if attribute is not None:
                    stores.setdefault(attribute, []).append(node)
    for attribute in sorted(stores, key=lambda name: name != "env"):
        found = stores[attribute]
        if len(found) != 1 or not isinstance(found[0], ast.Assign) or not isinstance(found[0].value, ast.Name):
            continue
        param = next((p for p in params if p.arg == found[0].value.id), None)
        if param is None or _enclosing_def(classdef, found[0]) is not init:
            continue
        forwards = attribute == "env" and (
            lookup_forwarded_to(methods.get("__getattr__")) == attribute
            or _returns_inner(methods.get("step"), "step", attribute)
            or _returns_inner(methods.get("reset"), "reset", attribute)
        )
        if forwards or (_offers_spaces(classdef, methods) and _legacy_contract(methods.get("step"), methods.get("reset"), attribute)):
            return param, attribute
    return None


def _unpacks_inner_step_wait(classdef: ast.ClassDef) -> bool:
    """A method of the class itself assigns what ``self.env.step_wait()`` gives to names
    (``obs, rews, news, infos = self.env.step_wait()``): it reads a VecEnv's results, which
    only a VecEnv gives (a ``return self.env.step_wait()`` only hands on what it gets)."""
    for statement in classdef.body:
        if not isinstance(statement, FUNCTIONS):
            continue
        for node in walk(statement):
            if isinstance(node, ast.Assign) and _inner_call(node.value, "step_wait"):
                return True
    return False



def _legacy_contract(step: ast.AST | None, reset: ast.AST | None, attribute: str) -> bool:
    """The class keeps the held env's legacy contract without handing its results on as
    they are: its ``step`` unpacks four values from ``self.<attribute>.step(...)`` and every
    return of it is four values, and its ``reset`` calls ``self.<attribute>.reset(...)`` and
    returns a value. Its callers unpack what a Gym env of the old API gives, so it stands for
    that env; a class with a contract of its own (a step of three values, a reset returning
    nothing) is not one."""
    if not isinstance(step, FUNCTIONS) or not isinstance(reset, FUNCTIONS):
        return False
    unpacks = any(
        isinstance(node, ast.Assign) and _inner_call(node.value, "step", attribute) and len(node.targets) == 1
        and _four(node.targets[0])
        for node in walk(step)
    )
    steps = [r.value for r in own_returns(step)]
    resets = [r.value for r in own_returns(reset)]
    return (
        unpacks and bool(steps) and bool(resets)
        and all(_four(value) for value in steps)
        and all(value is not None for value in resets)
        and any(_inner_call(node, "reset", attribute) for node in walk(reset))
    )


def _offers_spaces(classdef: ast.ClassDef, methods: dict[str, ast.FunctionDef | ast.AsyncFunctionDef]) -> bool:
    """The class gives its users an env's spaces itself (``action_space`` and
    ``observation_space`` as methods or properties, or stored on ``self``): it presents an
    env's whole surface, not a helper's own reset/step contract around one."""
    stored = {name for node in walk(classdef) if isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store)
              and (name := self_attribute(node)) is not None}
    return all(space in methods or space in stored for space in ("action_space", "observation_space"))


def _four(node: ast.AST | None) -> bool:
    return isinstance(node, (ast.Tuple, ast.List)) and len(node.elts) == 4 and not any(isinstance(e, ast.Starred) for e in node.elts)


def _is_self_env(node: ast.AST, attribute: str = "env") -> bool:
    return self_attribute(node) == attribute


def _enclosing_def(classdef: ast.ClassDef, node: ast.AST) -> ast.AST | None:
    for statement in classdef.body:
        if isinstance(statement, FUNCTIONS) and any(inner is node for inner in walk(statement)):
            return statement
    return None


def _inner_call(value: ast.AST | None, method: str, attribute: str = "env") -> bool:
    return (
        isinstance(value, ast.Call) and isinstance(value.func, ast.Attribute) and value.func.attr == method
        and _is_self_env(value.func.value, attribute)
    )


def _returns_inner(function: ast.AST | None, method: str, attribute: str = "env") -> bool:
    """Every return of ``function`` is ``self.<attribute>.<method>(...)``, or (for ``step``) a
    tuple of four names unpacked from it in the method."""
    if function is None:
        return False
    unpacked: set[str] = set()
    for node in walk(function):
        if isinstance(node, ast.Assign) and _inner_call(node.value, method, attribute) and len(node.targets) == 1:
            target = node.targets[0]
            if isinstance(target, (ast.Tuple, ast.List)) and len(target.elts) == 4:
                unpacked |= {e.id for e in target.elts if isinstance(e, ast.Name)}
    values = [r.value for r in own_returns(function)]
    if not values:
        return False
    for value in values:
        if _inner_call(value, method, attribute):
            continue
        if method == "step" and isinstance(value, ast.Tuple) and len(value.elts) == 4 and unpacked:
            if all(isinstance(e, ast.Name) and e.id in unpacked for e in value.elts):
                continue
        return False
    return True


# Gym's bases whose step and reset hand on the wrapped env's results (ObservationWrapper and
# RewardWrapper unpack five values in Gymnasium), and Gym's mixins, which change neither
# (``RecordConstructorArgs`` is what the migration adds to a wrapper taking arguments)
_FORWARDING_BASES = frozenset({"Wrapper", "core.Wrapper", "ActionWrapper", "core.ActionWrapper"}) | N.GYM_MIXIN_CLASSES


def is_object(base: ast.AST) -> bool:
    return isinstance(base, ast.Name) and base.id == "object"


def other_library_class_kind(qualified: str) -> EnvKind | None:
    """Kind of an SB3, PettingZoo, tf_agents or RLlib class named in an annotation or a base list."""
    if N.has_own_env_api(qualified):
        return EnvKind.NOT_ENV
    if qualified.startswith(N.SB3_VEC_PREFIXES):
        return EnvKind.SB3_VEC
    if qualified in N.PZ_AEC_BASES:
        return EnvKind.PZ_AEC
    if qualified in N.PZ_PARALLEL_BASES:
        return EnvKind.PZ_PARALLEL
    return None


def own_batch_on_wrapper_base(facts: ModuleFacts, classdef: ast.ClassDef) -> bool:
    """A class on a Gym wrapper base that is no wrapper layer but a batch of its own: its
    ``__init__`` never runs the base's (so no ``self.env`` is set), none of its methods
    touches ``self.env``, and its ``step`` unpacks another object's four-field step and
    reads that done one flag per env (``for i, new in enumerate(news)``). Its step and its
    callers keep the batch's four fields, and nothing forwards attribute reads to an inner
    env it does not have. A layer that sets ``self.env`` or calls the base ``__init__`` is a
    Gym wrapper, whatever it steps."""
    methods = {s.name: s for s in classdef.body if isinstance(s, FUNCTIONS)}
    init, step = methods.get("__init__"), methods.get("step")
    if init is None or step is None:
        return False
    for node in walk(init):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "__init__":
            return False  # ``super().__init__(env)`` / ``Base.__init__(self, env)``: a layer
    if touches_self_env(classdef):
        return False
    for node in walk(step):
        if not (isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], (ast.Tuple, ast.List))):
            continue
        target, value = node.targets[0], node.value
        if len(target.elts) != 4 or not (isinstance(value, ast.Call) and isinstance(value.func, ast.Attribute) and value.func.attr == "step"):
            continue
        if done_read_per_env(facts, target.elts[2], target):
            return True
    return False
