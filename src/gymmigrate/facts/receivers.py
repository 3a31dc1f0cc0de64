"""Receiver classification: what kind of object is ``x`` in ``x.step(a)``?

The same text (``x.reset()``, ``x.step(a)``, ``x.seed(s)``) has different correct
answers for a Gym env, a Gym vector env, a VecEnv (Stable-Baselines3, stable_baselines
2.x or OpenAI baselines), a PettingZoo env or an optimiser. Rules that rewrite those calls ask this module first.

The analysis decides from where a name comes from, never from its spelling: it
follows assignments, ``self.x = ...`` stores in the same class, returns of functions
defined in the module, and arguments at every call site of a function whose parameter
is used. When the evidence disagrees or runs out, the answer is ``UNKNOWN`` and
callers report instead of guessing.

Every answer is memoized per node, and a node whose answer is being computed counts as
"no evidence" when reached again, so rebinding chains (``env = Wrapper(env)`` a dozen
times) cost linear time.
"""

from __future__ import annotations

import ast
import sys
from typing import TYPE_CHECKING

from gymmigrate.facts import names as N
from gymmigrate.facts.callables import (
    CallableKinds,
    optional_of,
    parse_annotation,
    string_names,
)
from gymmigrate.facts.env_specs import is_spec_make
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.kinds import MAX_DEPTH, EnvKind, join_kinds
from gymmigrate.facts.module import (
    FUNCTIONS,
    ModuleFacts,
    call_argument,
    own_returns,
    string_value,
)
from gymmigrate.facts.self_attributes import SelfAttributes

if TYPE_CHECKING:
    from gymmigrate.facts.project_view import ProjectView



_NOT_ENV_EXPRESSIONS = (
    ast.Constant,
    ast.List,
    ast.Tuple,
    ast.Dict,
    ast.Set,
    ast.ListComp,
    ast.DictComp,
    ast.SetComp,
    ast.GeneratorExp,
    ast.Lambda,
    ast.BinOp,
    ast.UnaryOp,
    ast.Compare,
    ast.BoolOp,
    ast.JoinedStr,
)


class Receivers:
    """Classifies expressions of one module. One per file, shared by every rule.

    Two helpers answer the narrower questions and ask this object back for kinds:
    ``callables`` (what calling a factory returns) and ``attributes`` (what ``self.x``
    holds).
    """

    def __init__(self, facts: ModuleFacts, project: ProjectView | None = None) -> None:
        self.facts = facts
        self.project = project  # the run's facts across files (facts/project.py), if any
        self._cache: dict[ast.AST, EnvKind] = {}
        self._in_progress: set[ast.AST] = set()
        self._name_kinds: dict[int, EnvKind] = {}  # id(bindings list) -> kind, see _classify_name
        self._mixed: set[int] = set()  # bindings lists whose kinds disagree
        # parameters whose callers pass a Gym env and another kind of env: (gym kinds, others)
        self._mixed_params: dict[ast.arg, tuple[list[str], list[str]]] = {}
        self.depth = 0  # shared with the helpers: one bound on the whole chain of questions
        self.callables = CallableKinds(self, project)
        self.attributes = SelfAttributes(self)

    # -- the helpers' answers, under the names rules ask ----------------------------------

    def own_method(self, func: ast.AST) -> ast.FunctionDef | ast.AsyncFunctionDef | None:
        return self.callables.own_method(func)

    def returned_kind(self, callee: ast.AST) -> EnvKind:
        return self.callables.returned_kind(callee)

    def is_self(self, name: ast.Name) -> bool:
        return self.attributes.is_self(name)

    def self_stores(self, classdef: ast.ClassDef) -> dict[str, list[ast.expr]]:
        return self.attributes.self_stores(classdef)

    def self_attribute_values(self, attr: ast.AST, name: str) -> list[ast.expr]:
        return self.attributes.self_attribute_values(attr, name)

    # -- public -------------------------------------------------------------------------

    def kind_of(self, expr: ast.AST) -> EnvKind:
        cached = self._cache.get(expr)
        if cached is not None:
            return cached
        if expr in self._in_progress or self.depth > MAX_DEPTH:
            return EnvKind.UNKNOWN  # a cycle such as ``env = wrap(env)``: no new evidence
        self._in_progress.add(expr)
        self.depth += 1
        try:
            kind = self._classify(expr)
        finally:
            self.depth -= 1
            self._in_progress.discard(expr)
        self._cache[expr] = kind
        return kind

    def qualified_names(self, node: ast.AST) -> set[str]:
        return self.facts.qualified_names(node)

    def class_kind(self, classdef: ast.ClassDef) -> EnvKind:
        """The kind of instances of a class defined in this module, from its bases; a class
        with no library base that steps many envs at once (``step_async``/``step_wait``,
        baselines' ``SubprocVecEnv`` copied into a project) is a VecEnv."""
        kinds = [self._base_kind(base) for base in classdef.bases if not _is_object(base)]
        useful = [k for k in kinds if k not in (EnvKind.UNKNOWN, EnvKind.NOT_ENV)]
        if useful and useful[0] is EnvKind.GYM_ENV and self.wraps_gym_only(classdef) is not None:
            # A wrapper around an object of a Gym-only library (gym_unity's batched envs): that
            # object keeps gym's API, so neither the wrapper nor its callers are Gymnasium code.
            return EnvKind.UNKNOWN
        if useful:
            if useful[0] is EnvKind.GYM_VEC and _keeps_bare_reset(classdef):
                # A vector env subclass whose own reset returns the bare observations (no
                # rule changes a vector env's reset): its callers are on that contract, so
                # its instances are not rewritten as Gymnasium vector envs; reported.
                return EnvKind.UNKNOWN
            return useful[0]
        if all(k is EnvKind.NOT_ENV for k in kinds) and _is_vec_env_shaped(classdef):
            return EnvKind.SB3_VEC
        return EnvKind.NOT_ENV if not kinds else EnvKind.UNKNOWN

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

    def _gym_only_inside(self, expr: ast.expr | None, depth: int) -> str | None:
        if expr is None or depth > 4:
            return None
        if isinstance(expr, ast.Call) and isinstance(expr.func, ast.Name):
            inner = self.local_class(expr.func)
            if inner is not None:  # another wrapper of the module around it
                return self._gym_only_inside(call_argument(expr, 0, "env"), depth + 1) if self.is_gym_wrapper_class(inner) else None
        if isinstance(expr, ast.Name):
            last = self._dominating_binding(expr)
            statement = self.facts.statement_of(last) if last is not None else None
            if isinstance(statement, ast.Assign) and isinstance(statement.value, ast.Call) and self.local_class(statement.value.func) is not None:
                return self._gym_only_inside(statement.value, depth + 1)
        made = self.library_made(expr)
        return made if made is not None and made.split(".", 1)[0] in N.GYM_ONLY_PACKAGES else None

    def is_gym_wrapper_class(self, classdef: ast.ClassDef, _seen: frozenset[int] = frozenset()) -> bool:
        for base in classdef.bases:
            for q in self.qualified_names(base):
                rest = N.strip_gym_prefix(q)
                if rest is not None and (rest in N.GYM_WRAPPER_BASE_CLASSES or rest.startswith("wrappers.")):
                    return True
            local = self.local_class(base)
            if local is not None and local is not classdef and id(local) not in _seen:
                if self.is_gym_wrapper_class(local, _seen | {id(classdef)}):
                    return True
        return False

    def local_class(self, func: ast.AST) -> ast.ClassDef | None:
        return self.facts.classes.get(func.id) if isinstance(func, ast.Name) else None

    def local_function(self, func: ast.AST) -> ast.FunctionDef | ast.AsyncFunctionDef | None:
        return self.facts.functions.get(func.id) if isinstance(func, ast.Name) else None

    def super_kind(self, receiver: ast.AST) -> EnvKind | None:
        """``super().step(a)`` inside a Gym wrapper or env subclass is the wrapped Gym call;
        so is ``Base.step(self, a)`` naming one of the class's own bases."""
        if not (isinstance(receiver, ast.Call) and isinstance(receiver.func, ast.Name) and receiver.func.id == "super"):
            return self._explicit_base_kind(receiver)
        classdef = self.facts.enclosing_class(receiver)
        if classdef is None:
            return None
        if self.is_gym_wrapper_class(classdef):
            return None if self.wraps_gym_only(classdef) is not None else EnvKind.GYM_ENV
        kind = self.class_kind(classdef)
        return kind if kind.is_gym else None

    def _explicit_base_kind(self, receiver: ast.AST) -> EnvKind | None:
        if not isinstance(receiver, (ast.Name, ast.Attribute)):
            return None
        method = self.facts.parent(receiver)
        call = self.facts.parent(method) if isinstance(method, ast.Attribute) else None
        if not (isinstance(call, ast.Call) and call.func is method and call.args):
            return None
        first = call.args[0]
        function = self.facts.enclosing_function(call)
        classdef = self.facts.enclosing_class(call)
        if function is None or classdef is None or self.facts.parent(function) is not classdef:
            return None
        params = function.args.posonlyargs + function.args.args
        if not (params and isinstance(first, ast.Name) and first.id == params[0].arg):
            return None
        text = ast.dump(receiver)
        base = next((b for b in classdef.bases if ast.dump(b) == text), None)
        if base is None:
            return None
        kind = self._base_kind(base)
        return kind if kind.is_gym else None

    # -- classification -----------------------------------------------------------------

    def _classify(self, expr: ast.AST) -> EnvKind:
        if isinstance(expr, ast.Name):
            return self._classify_name(expr)
        if isinstance(expr, ast.Call):
            return self._classify_call(expr)
        if isinstance(expr, ast.Attribute):
            return self._classify_attribute(expr)
        if isinstance(expr, ast.Subscript):
            return self._element_kind(expr.value)
        if isinstance(expr, ast.IfExp):
            return join_kinds([self.kind_of(expr.body), self.kind_of(expr.orelse)])
        if isinstance(expr, ast.NamedExpr):
            return self.kind_of(expr.value)
        if isinstance(expr, ast.Await):
            return EnvKind.UNKNOWN
        if isinstance(expr, _NOT_ENV_EXPRESSIONS):
            return EnvKind.NOT_ENV
        return EnvKind.UNKNOWN

    def _classify_call(self, call: ast.Call) -> EnvKind:
        func = call.func
        # model.get_env() on anything: Stable-Baselines3's accessor for its VecEnv.
        if isinstance(func, ast.Attribute) and func.attr == "get_env":
            return EnvKind.SB3_VEC
        # gym.spec(id).make()
        if isinstance(func, ast.Attribute) and func.attr == "make" and isinstance(func.value, ast.Call):
            if any(N.strip_gym_prefix(q) in ("spec", "envs.spec") for q in self.qualified_names(func.value.func)):
                return EnvKind.GYM_ENV
        # spec.make() on one of the registry's EnvSpecs
        if is_spec_make(self.facts, self.project, call):
            return EnvKind.GYM_ENV
        kinds = [k for k in (self.kind_from_qualified(q, call) for q in self.qualified_names(func)) if k is not None]
        if kinds:
            return join_kinds(kinds)
        wrapped = self.wrapped_argument(call)
        if wrapped is not None and self.kind_of(wrapped) is EnvKind.GYM_ENV:
            return EnvKind.GYM_ENV  # ``wrap_deepmind(env)``: the Gym env it takes, maybe in Gym wrappers
        if self.project is not None:
            # A class or factory of another module of the run (re-exports and subclasses
            # followed): its instances or its returns.
            found = [k for k in (self.project.call_kind(q) for q in self.qualified_names(func)) if k is not None]
            if found:
                return join_kinds(found)
            if isinstance(func, ast.Name) and not self.facts.bindings_of(func) and self.facts.star_imports:
                star = self.project.star_call_kind(func.id, self.facts.star_imports)  # ``from utils.wrappers import *``
                if star is not None:
                    return star
        local_class = self.local_class(func)
        if local_class is not None:
            return self.class_kind(local_class)
        local_function = self.local_function(func)
        if local_function is not None:
            return self.returns_kind(local_function)
        own = self.own_method(func)
        if own is not None:
            return self.facts.memo(("returned-kind", id(own)), lambda: self.returns_kind(own), while_computing=EnvKind.UNKNOWN)
        if isinstance(func, ast.Name):
            # ``make_env = lambda: gym.make(...)``, a nested ``def thunk()``, an ``env_fn``
            # parameter: what calling the name returns.
            return self.returned_kind(func)
        # ``VecNormalize.load(...)`` is a classmethod call on a known class.
        if isinstance(func, ast.Attribute):
            owner = self.qualified_names(func.value)
            if any(q.startswith(N.SB3_VEC_PREFIXES) for q in owner):
                return EnvKind.SB3_VEC
            if any(q.startswith(N.SB3_PACKAGES) for q in owner) and func.attr == "load":
                return EnvKind.SB3_MODEL
        return EnvKind.UNKNOWN

    def kind_from_qualified(self, qualified: str, call: ast.Call) -> EnvKind | None:
        rest = N.strip_gym_prefix(qualified)
        if rest is not None:
            if rest in N.GYM_VEC_FACTORIES or rest.startswith(N.GYM_VEC_PREFIXES):
                return EnvKind.GYM_VEC
            if rest in N.GYM_ENV_FACTORIES:
                return EnvKind.GYM_ENV
            if rest.startswith(N.GYM_ENV_CLASS_PREFIXES) and rest.rsplit(".", 1)[-1][:1].isupper():
                *modules, last = rest.split(".")
                if last in N.GYM_NOT_ENV_CLASSES or N.GYM_NOT_ENV_MODULES.intersection(modules):
                    return EnvKind.NOT_ENV
                return EnvKind.GYM_ENV
            return EnvKind.NOT_ENV
        if qualified in N.SB3_VEC_FACTORIES or qualified.startswith(N.SB3_VEC_PREFIXES):
            return EnvKind.SB3_VEC
        if qualified in N.SB3_ENV_WRAPPERS or (
            qualified.startswith(N.SB3_ENV_WRAPPER_PREFIXES) and qualified.rsplit(".", 1)[-1][:1].isupper()
        ):
            return EnvKind.GYM_ENV
        package = N.top_package(qualified)
        if package in N.SB3_PACKAGES:
            name = qualified.rsplit(".", 1)[-1]
            if name.isupper() or name in N.SB3_MODEL_CLASSES:
                return EnvKind.SB3_MODEL
            return None
        if package == N.PETTINGZOO_PACKAGE:
            if qualified in N.PZ_PARALLEL_FACTORIES or qualified.endswith(N.PZ_PARALLEL_SUFFIXES):
                return EnvKind.PZ_PARALLEL
            if qualified in N.PZ_AEC_FACTORIES or qualified.endswith(N.PZ_AEC_SUFFIXES):
                return EnvKind.PZ_AEC
            if qualified == "pettingzoo.make" and call.args:
                first = call.args[0]
                if isinstance(first, ast.Constant) and isinstance(first.value, str):
                    return EnvKind.PZ_PARALLEL if "parallel" in first.value else EnvKind.PZ_AEC
            if ".wrappers." in qualified:
                return EnvKind.PZ_PARALLEL if "Parallel" in qualified.rsplit(".", 1)[-1] else EnvKind.PZ_AEC
            return None
        if package == N.SUPERSUIT_PACKAGE:
            return self._supersuit_kind(qualified, call)
        if package in N.NOT_ENV_PACKAGES:
            return EnvKind.NOT_ENV
        return None

    def _kind_keeping_inner(self, value: ast.expr) -> ast.expr | None:
        """The env a SuperSuit wrapper call wraps (its result has that env's kind), else None."""
        if not isinstance(value, ast.Call):
            return None
        for q in self.qualified_names(value.func):
            if N.top_package(q) == N.SUPERSUIT_PACKAGE and "vec_env" not in q.rsplit(".", 1)[-1]:
                return call_argument(value, 0, "env")
        return None

    def _supersuit_kind(self, qualified: str, call: ast.Call) -> EnvKind | None:
        """SuperSuit: vector conversions give VecEnvs with their own API (left alone, like
        SB3's); every other wrapper keeps the kind of the env it wraps."""
        if "vec_env" in qualified.rsplit(".", 1)[-1]:
            return EnvKind.SB3_VEC
        inner = call_argument(call, 0, "env")
        if inner is None:
            return None
        kind = self.kind_of(inner)
        return kind if kind is not EnvKind.UNKNOWN else None

    def _classify_attribute(self, attr: ast.Attribute) -> EnvKind:
        name = attr.attr
        if name == "training_env":
            return EnvKind.SB3_VEC
        if isinstance(attr.value, ast.Name) and self.is_self(attr.value):
            return self.attributes.self_attribute_kind(attr, name)
        if name in ("env", "unwrapped"):
            owner = self.kind_of(attr.value)
            if owner is EnvKind.SB3_MODEL and name == "env":
                return EnvKind.SB3_VEC
            if owner is EnvKind.GYM_ENV:
                return EnvKind.GYM_ENV
        if any(N.top_package(q) in N.NOT_ENV_PACKAGES for q in self.qualified_names(attr)):
            return EnvKind.NOT_ENV
        return EnvKind.UNKNOWN

    def _classify_name(self, name: ast.Name) -> EnvKind:
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
            shared = join_kinds(kinds)
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
        return shared

    def _dominating_binding(self, name: ast.Name) -> ast.AST | None:
        flow = Flow.of(self.facts)
        last = flow.last_binding_of(name)
        if not isinstance(last, ast.Name):
            return None
        statement = self.facts.statement_of(last)
        if not (isinstance(statement, (ast.Assign, ast.AnnAssign)) and statement.value is not None):
            return None
        rebinds = any(isinstance(n, ast.Name) and n.id == name.id for n in ast.walk(statement.value))
        if rebinds and not (self._makes_gym_wrapper(statement.value) or self.wrapped_argument(statement.value) is not None):
            return None  # ``env = wrap(env)``: its kind rests on the earlier values too
        return last if flow.dominates(statement, name, name) else None

    def _makes_gym_wrapper(self, value: ast.expr) -> bool:
        """``Wrapper(env, ...)`` with a Gym wrapper class (Gymnasium's, this module's, or
        another module's of the run): a Gym env whatever ``env`` was."""
        if not isinstance(value, ast.Call):
            return False
        for q in self.qualified_names(value.func):
            rest = N.strip_gym_prefix(q)
            if rest is not None and (rest in N.GYM_WRAPPER_BASE_CLASSES or (rest.startswith("wrappers.") and not rest.startswith("wrappers.vector."))):
                return True
            if self.project is not None and self.project.is_wrapper_class(q):
                return True
        if isinstance(value.func, ast.Name) and self.project is not None and not self.facts.bindings_of(value.func):
            return self.project.star_wrapper_class(value.func.id, self.facts.star_imports)
        local = self.local_class(value.func)
        return local is not None and self.is_gym_wrapper_class(local)

    def wrapped_argument(self, value: ast.AST) -> ast.expr | None:
        """The env ``value`` hands on: its first argument, where it calls a def of the run
        that returns that argument or Gym wrappers around it (``def wrap_deepmind(env):
        if clip: env = ClipReward(env); return env``; ``ProjectView.wraps_argument``)."""
        if not (isinstance(value, ast.Call) and value.args and not isinstance(value.args[0], ast.Starred)):
            return None
        local = self.local_function(value.func)
        if local is not None:
            return value.args[0] if self.wraps_argument(local) else None
        if self.project is not None and any(self.project.wraps_argument(q) for q in self.qualified_names(value.func)):
            return value.args[0]
        return None

    def wraps_argument(self, function: ast.AST) -> bool:
        """Every return of the top-level def ``function`` is its first parameter, maybe
        rebound to Gym wrappers around it (or to what another such def of the module gives)."""
        return bool(self.facts.memo(("wraps-argument", id(function)), lambda: self._wraps_argument(function), while_computing=False))

    def _wraps_argument(self, function: ast.AST) -> bool:
        if not isinstance(function, FUNCTIONS) or self.facts.parent(function) is not self.facts.tree:
            return False
        positional = [*function.args.posonlyargs, *function.args.args]
        if not positional:
            return False
        values = [r.value for r in own_returns(function)]
        return bool(values) and all(v is not None and self._hands_on_param(v, positional[0], function, 0) for v in values)

    def _hands_on_param(self, value: ast.expr, param: ast.arg, function: ast.AST, depth: int) -> bool:
        if depth > MAX_DEPTH:
            return False
        if isinstance(value, ast.Call):
            if not value.args or isinstance(value.args[0], ast.Starred):
                return False
            local = self.local_function(value.func)
            hands_on = self._makes_gym_wrapper(value) or (local is not None and local is not function and self.wraps_argument(local))
            return hands_on and self._hands_on_param(value.args[0], param, function, depth + 1)
        if not (isinstance(value, ast.Name) and value.id == param.arg):
            return False
        for binding in self.facts.bindings_of(value):
            if binding is param:
                continue
            assign = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
            if not (isinstance(assign, ast.Assign) and assign.targets == [binding]):
                return False
            if self.facts.enclosing_function(assign) is not function:
                return False
            if not self._hands_on_param(assign.value, param, function, depth + 1):
                return False
        return True

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
            if isinstance(value, ast.Attribute) and value.attr == "unwrapped" and isinstance(value.value, ast.Name) and value.value.id == binding.id:
                return None  # ``env = env.unwrapped``: the same env, its kind unchanged
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
        return EnvKind.UNKNOWN

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
                else:
                    kinds.append(EnvKind.UNKNOWN)
            return join_kinds(kinds)
        if isinstance(container, ast.Attribute) and isinstance(container.value, ast.Name):
            if self.is_self(container.value):
                values = self.self_attribute_values(container, container.attr)
                return join_kinds(self._element_kind_memo(v) for v in values) if values else EnvKind.UNKNOWN
        return EnvKind.UNKNOWN

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

    # -- parameters ---------------------------------------------------------------------

    def _param_kind(self, param: ast.arg) -> EnvKind:
        if param.annotation is not None:
            kind = self.annotation_kind(param.annotation)
            if kind is not EnvKind.UNKNOWN:
                return kind
        function = self.facts.parent(self.facts.parent(param))  # arg -> arguments -> def
        if not isinstance(function, FUNCTIONS):
            return EnvKind.UNKNOWN
        params = [*function.args.posonlyargs, *function.args.args]
        name = param.arg
        classdef = self.facts.parent(function)
        is_method = isinstance(classdef, ast.ClassDef) and self.facts.is_method(function)
        if is_method and params and params[0] is param:
            return EnvKind.NOT_ENV  # self / cls
        if is_method and name == "env" and function.name == "__init__" and self.is_gym_wrapper_class(classdef):  # type: ignore[arg-type]
            return EnvKind.NOT_ENV if self.wraps_gym_only(classdef) is not None else EnvKind.GYM_ENV  # type: ignore[arg-type]
        position = next((i for i, p in enumerate(params) if p is param), None)
        if position is not None and is_method:
            position -= 1  # calls do not pass self
        external = self.callables.external_param_kinds(function, classdef if is_method else None, name)  # type: ignore[arg-type]
        if is_method and function.name == "__init__":
            # A constructor parameter: every call that runs this ``__init__`` (subclasses too).
            constructions, elsewhere = self.constructions(classdef)  # type: ignore[arg-type]
            if elsewhere:
                external = [*external, EnvKind.UNKNOWN]
            calls = [call for call, _ in constructions]
            shifts = {id(call): shift for call, shift in constructions}
        else:
            calls = self.call_sites(function, classdef if is_method else None)  # type: ignore[arg-type]
            shifts = {}
        if not calls and not external:
            fixtures = self.param_fixtures(function, name) if not is_method else []
            if fixtures:
                return join_kinds(self._fixture_kind(fixture) for fixture in fixtures)
            values = self.param_values(function, name) if not is_method else None
            if values:
                return join_kinds(self.kind_of(value) for value in values)
            return EnvKind.UNKNOWN
        defaults = _default_of(function, param)
        kinds = list(external)
        for call in calls:
            shift = shifts.get(id(call), 0)
            argument = call_argument(call, None if position is None else position + shift, name)
            if argument is None:
                if defaults and not any(k.arg is None for k in call.keywords):
                    continue
                kinds.append(EnvKind.UNKNOWN)  # not passed (or maybe in ``**kwargs``)
            else:
                kinds.append(self.kind_of(argument))
        gym = {k for k in kinds if k.is_gym}
        others = {k for k in kinds if k not in (EnvKind.NOT_ENV, EnvKind.UNKNOWN) and not k.is_gym}
        if gym and others:
            # Some callers pass a Gym env, others a VecEnv or a PettingZoo env: the same code
            # serves both, so no rewrite is right for all of them; reported (``mixed_callers``).
            self._mixed_params[param] = (sorted(k.value for k in gym), sorted(k.value for k in others))
            return EnvKind.UNKNOWN
        return join_kinds(kinds)

    def constructions(self, classdef: ast.ClassDef, _seen: frozenset[int] = frozenset()) -> tuple[list[tuple[ast.Call, int]], bool]:
        """The calls of this module that run ``classdef.__init__``, each with how far its
        positional arguments are shifted (1 for ``Base.__init__(self, env)``): the class's own
        calls, the calls of subclasses here that inherit ``__init__``, and the
        ``super().__init__(...)`` / ``Base.__init__(self, ...)`` of subclasses that define
        their own. The flag says another module of the run subclasses it (its calls are not
        known here)."""
        found: list[tuple[ast.Call, int]] = [(call, 0) for call in self.facts.calls_by_name.get(classdef.name, [])]
        elsewhere = self.project is not None and self.facts.parent(classdef) is self.facts.tree and self.project.subclassed_elsewhere(classdef.name)
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
            first_base = next((b for b in sub.bases if not _is_object(b)), None)
            for call in self.facts.attribute_calls.get("__init__", []):
                if self.facts.enclosing_class(call) is not sub:
                    continue
                owner = call.func.value  # type: ignore[attr-defined]
                if isinstance(owner, ast.Call) and isinstance(owner.func, ast.Name) and owner.func.id == "super":
                    if first_base is not None and self.local_class(first_base) is classdef:
                        found.append((call, 0))
                elif isinstance(owner, ast.Name) and self.local_class(owner) is classdef:
                    found.append((call, 1))  # ``Base.__init__(self, env)``
        return found, elsewhere

    def mixed_callers(self, expr: ast.AST, _depth: int = 0) -> str | None:
        """Why ``expr`` (a parameter, ``self.x`` stored from one, or a name bound to either)
        has no single kind: its callers pass a Gym env at some sites and another kind of env
        at others. None when that is not the reason."""
        if _depth > 4:
            return None
        self.kind_of(expr)  # fills ``_mixed_params`` on the way
        values: list[ast.AST] = []
        if isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and self.is_self(expr.value):
            classdef = self.facts.enclosing_class(expr)
            values = list(self.self_attribute_values(expr, expr.attr))
            if not values and classdef is not None:
                values = list(self.attributes.inherited_values(classdef, expr.attr))
        elif isinstance(expr, ast.Name):
            for binding in self.facts.bindings_of(expr):
                if isinstance(binding, ast.arg) and binding in self._mixed_params:
                    gym, others = self._mixed_params[binding]
                    return f"its callers pass a {' or '.join(gym)} at some sites and a {' or '.join(others)} at others"
                parent = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
                if isinstance(parent, ast.Assign):
                    values.append(parent.value)
        for value in values:
            found = self.mixed_callers(value, _depth + 1)
            if found is not None:
                return found
        return None

    def annotation_kind(self, annotation: ast.AST) -> EnvKind:
        if isinstance(annotation, ast.Constant) and isinstance(annotation.value, str):
            parsed = parse_annotation(annotation.value)  # ``env: "gym.Env"``
            return self.annotation_names_kind(string_names(self.facts, parsed)) if parsed is not None else EnvKind.UNKNOWN
        optional = optional_of(annotation, self.qualified_names)
        if optional is not None:
            return self.annotation_kind(optional)
        local = self.local_class(annotation)
        if local is not None:
            # ``def test_x(env: Warehouse)`` with Warehouse defined here; a class of the run
            # that is no env (``model_env: ModelEnv``) is the project's own object: left alone.
            return self.class_kind(local)
        return self.annotation_names_kind(self.qualified_names(annotation))

    def annotation_names_kind(self, names: set[str]) -> EnvKind:
        for q in names:
            rest = N.strip_gym_prefix(q)
            if rest in N.GYM_ENV_BASE_CLASSES:
                return EnvKind.GYM_ENV
            if rest is not None and rest.startswith("wrappers.") and not rest.startswith("wrappers.vector."):
                return EnvKind.GYM_ENV  # ``env: gym.wrappers.TimeLimit``: a wrapper class is a Gym env
            if rest is not None and rest.startswith("vector.") and rest.endswith("Env"):
                return EnvKind.GYM_VEC
            other = _other_library_class_kind(q)
            if other is not None:
                return other
            if self.project is not None:
                found = self.project.call_kind(q)  # a class of another module of the run
                if found is not None:
                    return found
        return EnvKind.UNKNOWN

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
            bindings = [last] if last is not None else self.facts.bindings_of(expr)
            values = []
            for binding in bindings:
                parent = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
                if not (isinstance(parent, (ast.Assign, ast.AnnAssign)) and parent.value is not None):
                    return None
                values.append(parent.value)
        elif isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and self.is_self(expr.value):
            values = self.self_attribute_values(expr, expr.attr)
        else:
            return None
        found = {self._legacy_step_maker(value) for value in values}
        return found.pop() if len(found) == 1 and values else None

    def _legacy_step_maker(self, value: ast.expr) -> str | None:
        if not isinstance(value, ast.Call):
            return None
        local = self.local_class(value.func)
        if local is not None:
            return local.name if self.class_keeps_legacy_step(local) else None
        if self.project is not None:
            for qualified in self.qualified_names(value.func):
                if self.project.keeps_legacy_step(qualified):
                    return qualified.rsplit(".", 1)[-1]
        return None

    def class_keeps_legacy_step(self, classdef: ast.ClassDef, seen: frozenset[int] = frozenset()) -> bool:
        """The step ``classdef``'s instances run keeps its legacy contract: its own, or the
        one a base of this module (or of the run) defines when it defines none."""
        if id(classdef) in seen or self.class_kind(classdef) is not EnvKind.GYM_ENV:
            return False
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

    def call_sites(self, function: ast.AST, classdef: ast.ClassDef | None) -> list[ast.Call]:
        """Calls in this module that reach ``function`` (a method when ``classdef`` is given)."""
        name = function.name  # type: ignore[attr-defined]
        if classdef is None:
            return [
                c
                for c in self.facts.calls_by_name.get(name, [])
                if self.local_function(c.func) is function
            ]
        if name == "__init__":
            return list(self.facts.calls_by_name.get(classdef.name, []))
        return [
            c
            for c in self.facts.attribute_calls.get(name, [])
            if isinstance(c.func.value, ast.Name) and self.is_self(c.func.value)  # type: ignore[attr-defined]
        ]

    def _base_kind(self, base: ast.AST) -> EnvKind:
        for q in self.qualified_names(base):
            rest = N.strip_gym_prefix(q)
            if rest is not None:
                if rest in N.GYM_ENV_BASE_CLASSES or rest.startswith("wrappers."):
                    return EnvKind.GYM_ENV
                if rest.startswith("vector."):
                    return EnvKind.GYM_VEC
            other = _other_library_class_kind(q)
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

    def pytest_fixture(self, name: str) -> ast.FunctionDef | ast.AsyncFunctionDef | None:
        """The module's ``@pytest.fixture`` function called ``name``: pytest passes what it
        returns (or yields) to a test's parameter of that name."""
        function = self.facts.functions.get(name)
        if function is None:
            return None
        for decorator in function.decorator_list:
            target = decorator.func if isinstance(decorator, ast.Call) else decorator
            if any(q in ("pytest.fixture", "_pytest.fixtures.fixture") for q in self.qualified_names(target)):
                return function
        return None

    def param_fixtures(self, function: ast.FunctionDef | ast.AsyncFunctionDef, name: str) -> list[ast.FunctionDef | ast.AsyncFunctionDef]:
        """The module's pytest fixtures that give a test's parameter ``name`` its values:
        the fixture of that name, or, where the test is parametrized over that name with
        ``fixture_ref`` (pytest-cases: ``@parametrize("env", [fixture_ref(env_4),
        fixture_ref(env_10)])``), every fixture referred to; empty when any value is
        something else."""
        for decorator in function.decorator_list:
            if not (isinstance(decorator, ast.Call) and len(decorator.args) >= 2):
                continue
            if not any(q.endswith("parametrize") for q in self.qualified_names(decorator.func)):
                continue
            argnames = string_value(decorator.args[0])
            if argnames is None or [n.strip() for n in argnames.split(",")] != [name]:
                continue
            values = decorator.args[1]
            if not isinstance(values, (ast.List, ast.Tuple)) or not values.elts:
                return []
            found = []
            for value in values.elts:
                if not (isinstance(value, ast.Call) and len(value.args) == 1):
                    return []
                referred = value.args[0]
                if not (
                    any(q.endswith("fixture_ref") for q in self.qualified_names(value.func))
                    and isinstance(referred, ast.Name)
                    and (fixture := self.pytest_fixture(referred.id)) is not None
                ):
                    return []
                found.append(fixture)
            return found
        fixture = self.pytest_fixture(name)
        return [fixture] if fixture is not None else []

    def param_values(self, function: ast.FunctionDef | ast.AsyncFunctionDef, name: str) -> list[ast.expr] | None:
        """What ``@pytest.mark.parametrize`` gives a test's parameter ``name``: the values of
        a list or tuple display written in the decorator, or bound once in this module to a
        name the decorator reads (``wrappers = [wrap(make_env()), ...]``), or the element of
        a comprehension; with several argnames (``"env, n"``) the item at the parameter's
        place in each tuple. ``pytest.param(value, id=...)`` gives its value. None when any
        value cannot be read so (a starred item, a list extended elsewhere, ``indirect``)."""
        for decorator in function.decorator_list:
            if not (isinstance(decorator, ast.Call) and len(decorator.args) >= 2):
                continue
            if not any(q.endswith("parametrize") for q in self.qualified_names(decorator.func)):
                continue
            argnames = _argnames(decorator.args[0])
            if argnames is None or name not in argnames:
                continue
            if any(k.arg == "indirect" for k in decorator.keywords):
                return None
            container = self._param_container(decorator.args[1])
            if container is None:
                return None
            if isinstance(container, (ast.ListComp, ast.GeneratorExp)):
                rows: list[ast.expr] = [container.elt]
            else:
                rows = list(container.elts)
            index = argnames.index(name)
            values: list[ast.expr] = []
            for row in rows:
                if isinstance(row, ast.Call) and any(q.endswith("pytest.param") for q in self.qualified_names(row.func)):
                    items: list[ast.expr] | None = list(row.args)
                elif len(argnames) == 1:
                    items = [row]
                elif isinstance(row, (ast.Tuple, ast.List)):
                    items = list(row.elts)
                else:
                    items = None
                if items is None or len(items) != len(argnames) or any(isinstance(i, ast.Starred) for i in items):
                    return None
                values.append(items[index])
            return values
        return None

    def _param_container(self, values: ast.expr) -> ast.List | ast.Tuple | ast.ListComp | ast.GeneratorExp | None:
        """The display a parametrize decorator's values come from (see ``param_values``)."""
        if isinstance(values, (ast.List, ast.Tuple, ast.ListComp, ast.GeneratorExp)):
            return values
        if not isinstance(values, ast.Name):
            return None
        bindings = self.facts.bindings_of(values)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.Name):
            return None
        statement = self.facts.parent(bindings[0])
        if not (isinstance(statement, ast.Assign) and statement.targets == [bindings[0]]):
            return None
        if not isinstance(statement.value, (ast.List, ast.Tuple, ast.ListComp)):
            return None
        # ``wrappers.append(...)`` or ``wrappers[0] = ...`` elsewhere add values the display does not show.
        for attr in _MUTATORS:
            if any(isinstance(a.value, ast.Name) and a.value.id == values.id for a in self.facts.attributes.get(attr, ())):
                return None
        if values.id in self.facts.memo(("subscript-stores", 0), self._subscript_stores):
            return None
        return statement.value

    def _subscript_stores(self) -> frozenset[str]:
        """Names of this module written through a subscript (``xs[0] = v``, ``del xs[0]``)."""
        return frozenset(
            node.value.id
            for node in ast.walk(self.facts.tree)
            if isinstance(node, ast.Subscript) and isinstance(node.ctx, (ast.Store, ast.Del)) and isinstance(node.value, ast.Name)
        )

    def fixture_values(self, fixture: ast.FunctionDef | ast.AsyncFunctionDef) -> list[ast.expr]:
        """What a fixture gives its tests: what it yields, else what it returns."""
        yielded = [
            node.value
            for node in ast.walk(fixture)
            if isinstance(node, ast.Yield) and node.value is not None and self.facts.enclosing_function(node) is fixture
        ]
        return yielded or [r.value for r in own_returns(fixture) if r.value is not None]

    def _fixture_kind(self, fixture: ast.FunctionDef | ast.AsyncFunctionDef) -> EnvKind:
        values = self.fixture_values(fixture)
        return join_kinds(self.kind_of(value) for value in values) if values else EnvKind.NOT_ENV

    def returns_kind(self, function: ast.AST) -> EnvKind:
        values = [r.value for r in own_returns(function) if r.value is not None]
        if not values:
            return EnvKind.NOT_ENV
        return join_kinds(self.kind_of(value) for value in values)


_MUTATORS = frozenset({"append", "extend", "insert", "__setitem__", "__iadd__"})


def _argnames(node: ast.AST) -> list[str] | None:
    """A parametrize decorator's argnames: ``"env"``, ``"env, n"`` or ``("env", "n")``."""
    text = string_value(node)
    if text is not None:
        return [n.strip() for n in text.split(",") if n.strip()]
    if isinstance(node, (ast.List, ast.Tuple)):
        names = [string_value(el) for el in node.elts]
        return None if any(n is None for n in names) else names  # type: ignore[return-value]
    return None


def _keeps_bare_reset(classdef: ast.ClassDef) -> bool:
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
    for value in values:
        if isinstance(value, ast.Call) and isinstance(value.func, ast.Name) and value.func.id != "super":
            continue  # ``zip(*results)``, ``tuple(batch)``
        if not isinstance(value, (ast.Name, ast.ListComp, ast.GeneratorExp, ast.List)):
            return False  # a tuple literal the rules migrate, a helper's or an inner env's result
    return True


def _is_object(base: ast.AST) -> bool:
    return isinstance(base, ast.Name) and base.id == "object"


_VEC_METHODS = frozenset({"step_async", "step_wait"})
# ``self.num_envs = len(env_fns)``: baselines and SB3 spell it ``num_envs``, tianshou-style
# vector envs ``env_num``; a class that counts its envs so steps them all at once.
_ENV_COUNTS = frozenset({"num_envs", "env_num", "n_envs"})
# ``step(self, action, id=None)``: a vector env steps (or resets) the envs it is told.
_ENV_ID_PARAMS = frozenset({"id", "ids", "env_id", "env_ids", "indices"})


def _is_vec_env_shaped(classdef: ast.ClassDef) -> bool:
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
    """``num_envs`` (or ``env_num``) is a class attribute or is stored on ``self`` in ``__init__``."""
    for statement in classdef.body:
        if isinstance(statement, (ast.Assign, ast.AnnAssign)):
            targets = statement.targets if isinstance(statement, ast.Assign) else [statement.target]
            if any(isinstance(t, ast.Name) and t.id in _ENV_COUNTS for t in targets):
                return True
        if isinstance(statement, FUNCTIONS) and statement.name == "__init__":
            for inner in ast.walk(statement):
                if isinstance(inner, ast.Attribute) and inner.attr in _ENV_COUNTS and isinstance(inner.ctx, ast.Store):
                    if isinstance(inner.value, ast.Name) and inner.value.id == "self":
                        return True
    return False


def _is_env_method_call(call: ast.Call) -> bool:
    return isinstance(call.func, ast.Attribute) and call.func.attr in ("reset", "step", "last")


def _default_of(function: ast.AST, param: ast.arg) -> bool:
    """Whether ``param`` has a default value."""
    args = function.args  # type: ignore[attr-defined]
    positional = [*args.posonlyargs, *args.args]
    if param in positional:
        return positional.index(param) >= len(positional) - len(args.defaults)
    if param in args.kwonlyargs:
        return args.kw_defaults[args.kwonlyargs.index(param)] is not None
    return False


def _other_library_class_kind(qualified: str) -> EnvKind | None:
    """Kind of an SB3 or PettingZoo class named in an annotation or a base list."""
    if qualified.startswith(N.SB3_VEC_PREFIXES):
        return EnvKind.SB3_VEC
    if qualified in N.PZ_AEC_BASES:
        return EnvKind.PZ_AEC
    if qualified in N.PZ_PARALLEL_BASES:
        return EnvKind.PZ_PARALLEL
    return None
