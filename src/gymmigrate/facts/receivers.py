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

This module holds the façade, ``Receivers``, and the classification of expressions. The
families of questions it also answers are mixed in from their own modules:
``receiver_bindings.py`` (what a name holds, from its bindings), ``receiver_wrapping.py``
(which calls hand on the env they are given), ``receiver_classes.py`` (what a class of
the module is, from its bases; its shape alone is ``class_shapes.py``),
``receiver_params.py`` (what a parameter holds; with ``receiver_callers.py``, which calls
reach a def, and ``receiver_thunks.py``, what passed thunks return),
``receiver_origins.py`` (who made an object: a legacy-step class, the run itself, another
library; with ``receiver_foreign.py``, what shows an object is not Gym's, and
``receiver_gym_only.py``, the Gym-only library stacks); ``pytest_params.py`` reads
what pytest passes a test. Two helpers it owns answer narrower questions:
``callables.py`` (what calling a factory returns) and ``self_attributes.py`` (``self.x``).
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING, NamedTuple

from gymmigrate.facts import names as N
from gymmigrate.facts import same_tests
from gymmigrate.facts.callables import CallableKinds
from gymmigrate.facts.env_specs import is_spec_make
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.kinds import MAX_DEPTH, WORK_BUDGET, EnvKind, join_kinds
from gymmigrate.facts.module import (
    FUNCTIONS,
    ModuleFacts,
    call_argument,
    own_entry_point,
    own_returns,
)
from gymmigrate.facts.narrowing import Narrowing
from gymmigrate.facts.pytest_params import requested_fixtures
from gymmigrate.facts.receiver_bindings import BindingKinds
from gymmigrate.facts.receiver_classes import ClassKinds
from gymmigrate.facts.receiver_origins import MadeObjects
from gymmigrate.facts.receiver_params import ParameterKinds
from gymmigrate.facts.receiver_wrapping import WrappingCalls
from gymmigrate.facts.self_attributes import SelfAttributes, class_self_stores

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


class _CutAnswer(NamedTuple):
    """An "unknown" of ``kind_of`` cut short by the questions open above it: what the
    analysis looked like when it was asked (``Receivers._mark``), and what computing it
    did besides answering, to be done again when it is reused."""

    mark: tuple[int, ...]
    cuts: int
    effects: tuple[tuple[dict, object, object], ...]


class Receivers(BindingKinds, WrappingCalls, ClassKinds, ParameterKinds, MadeObjects):
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
        self._cuts = 0  # answers cut short by a cycle (or the depth bound) so far
        # (expression, questions open, classes being asked, depth) -> its cut-short answer
        self._cut_answers: dict[tuple[ast.AST, frozenset[ast.AST], frozenset[ast.ClassDef], int], _CutAnswer] = {}
        # stores into the tables of what callers pass (``note``), in order, while a question is open
        self._effects: list[tuple[dict, object, object]] = []
        self._name_kinds: dict[int, EnvKind] = {}  # id(bindings list) -> kind, see _classify_name
        self._mixed: set[int] = set()  # bindings lists whose kinds disagree
        self._vec_wrapped: dict[int, str] = {}  # id(Gym wrapper class) -> what it wraps (``wraps_vec_env``)
        self._vec_wrapping: set[ast.ClassDef] = set()  # those being asked now
        # parameters whose callers pass a Gym env and another kind of env: (gym kinds, others)
        self._mixed_params: dict[ast.arg, tuple[list[str], list[str]]] = {}
        # of those, the parameters that may hold the project's own object beside a Gym env
        # (``env = Walker()`` in one branch, ``gym.make(...)`` in another): what they hand on
        self._own_mixed_params: dict[ast.arg, tuple[list[str], list[str]]] = {}
        # of those, the parameters whose other kinds come only from test modules: their callers there
        self._test_double_params: dict[ast.arg, list[str]] = {}
        self.depth = 0  # shared with the helpers: one bound on the whole chain of questions
        self._work = 0  # questions opened since the outermost open one was asked
        self._given_up = False  # the outermost open question ran past WORK_BUDGET
        self.callables = CallableKinds(self, project)
        self.narrowing = Narrowing(
            facts, lambda value: self.kind_of(value) is EnvKind.GYM_ENV, class_is_env=self.checked_class_is_env
        )
        self.class_narrowing = Narrowing(facts, lambda value: False, check="issubclass")
        self.attributes = SelfAttributes(self)

    # -- the helpers' answers, under the names rules ask ----------------------------------

    def own_method(self, func: ast.AST) -> ast.FunctionDef | ast.AsyncFunctionDef | None:
        return self.callables.own_method(func)

    def returned_kind(self, callee: ast.AST) -> EnvKind:
        return self.callables.returned_kind(callee)

    def is_self(self, name: ast.Name) -> bool:
        return self.attributes.is_self(name)

    def self_stores(self, classdef: ast.ClassDef) -> dict[str, list[ast.expr]]:
        return class_self_stores(self.facts, classdef)

    def self_attribute_values(self, attr: ast.AST, name: str) -> list[ast.expr]:
        return self.attributes.self_attribute_values(attr, name)

    # -- public -------------------------------------------------------------------------

    def kind_of(self, expr: ast.AST) -> EnvKind:
        cached = self._cache.get(expr)
        if cached is not None:
            return cached
        if expr in self._in_progress or self.depth > MAX_DEPTH:
            self._cuts += 1
            return EnvKind.UNKNOWN  # a cycle such as ``env = wrap(env)``: no new evidence
        if self._given_up:
            return EnvKind.UNKNOWN  # unwinding a question given up (below)
        self._work = self._work + 1 if self._in_progress else 1
        if self._work > WORK_BUDGET:
            self._given_up = True
            return EnvKind.UNKNOWN
        # An answer cut short is not kept (below), yet the same question comes back with the
        # same questions open: a def passing its parameter on at k calls of itself asks each
        # call's argument again under every order of the others, k! paths. What an answer can
        # depend on is the questions open (and the classes being asked, and the depth) and
        # the answers kept so far; while those are the same, computing it again gives the
        # same "unknown" and does the same stores, so it is reused with them, and the paths
        # collapse to the sets of open questions. Only an answer whose computation kept
        # nothing new is reused: then the analysis it saw is the one it left.
        frontier = None
        if self._in_progress:
            frontier = (expr, frozenset(self._in_progress), frozenset(self._vec_wrapping), self.depth)
            known = self._cut_answers.get(frontier)
            if known is not None and known.mark == self._mark():
                self._cuts += known.cuts
                for table, key, value in known.effects:
                    self.note(table, key, value)
                return EnvKind.UNKNOWN
        mark = self._mark() if frontier is not None else ()
        effects = len(self._effects)
        self._in_progress.add(expr)
        self.depth += 1
        cuts = self._cuts
        try:
            kind = self._classify(expr)
        finally:
            self.depth -= 1
            self._in_progress.discard(expr)
        if self._given_up:
            # Every question open when the budget ran out is kept as "unknown", so the
            # questions asked after it do not spend the budget on the same paths again.
            self._cache[expr] = EnvKind.UNKNOWN
            if not self._in_progress:
                self._given_up = False
                self._effects.clear()
            return EnvKind.UNKNOWN
        if kind is EnvKind.UNKNOWN and self._cuts != cuts and self._in_progress:
            # "Unknown" only because a question still open above was cut short (``env =
            # wrap(env, clip)`` asked while ``wrap``'s parameter is): the open question may
            # settle it, so it is asked again later rather than kept.
            if frontier is not None and self._mark() == mark:
                self._cut_answers[frontier] = _CutAnswer(mark, self._cuts - cuts, tuple(self._effects[effects:]))
            return kind
        if not self._in_progress:
            self._effects.clear()  # no question is open to reuse them
        self._cache[expr] = kind
        return kind

    def note(self, table: dict, key: object, value: object) -> None:
        """Store ``value`` under ``key`` in one of the tables filled on the way to an answer
        (``_mixed_params``): recorded, so a reused answer stores it again."""
        table[key] = value
        if self._in_progress:
            self._effects.append((table, key, value))

    def _mark(self) -> tuple[int, ...]:
        """The sizes of everything kept that an answer may read: they only grow, so equal
        sizes mean nothing kept has changed."""
        return (
            len(self._cache),
            len(self._name_kinds),
            len(self._mixed),
            len(self._vec_wrapped),
            self.facts.memo_writes,
            self.narrowing.answers(),
            self.class_narrowing.answers(),
        )

    def qualified_names(self, node: ast.AST) -> set[str]:
        return self.facts.qualified_names(node)

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
        if isinstance(func, ast.Attribute) and func.attr == "get_env":
            accessed = self._get_env_kind(func)
            if accessed is not None:
                return accessed
        # gym.spec(id).make()
        if isinstance(func, ast.Attribute) and func.attr == "make" and isinstance(func.value, ast.Call):
            if any(N.strip_gym_prefix(q) in ("spec", "envs.spec") for q in self.qualified_names(func.value.func)):
                return EnvKind.GYM_ENV
        # spec.make() on one of the registry's EnvSpecs
        if is_spec_make(self.facts, self.project, call):
            return EnvKind.GYM_ENV
        requested = requested_fixtures(self.facts, call)
        if requested is not None:
            return self.requested_fixture_kind(requested)  # pytest's ``request.getfixturevalue("env")``
        if (
            len(call.args) == 1
            and not call.keywords
            and not isinstance(call.args[0], ast.Starred)
            and self.qualified_names(func) & {"copy.deepcopy", "copy.copy"}
        ):
            return self.kind_of(call.args[0])  # a copy of an env is an env of the same kind
        kinds = [k for k in (self.kind_from_qualified(q, call) for q in self.qualified_names(func)) if k is not None]
        if kinds:
            return join_kinds(kinds)
        if self.library_wrapper_class(func):
            return EnvKind.GYM_ENV  # ``ImgObsWrapper(env)``: a Gym wrapper of an env library, as gym's own
        wrapped = self.wrapped_argument(call)
        if wrapped is not None:
            inner = self.kind_of(wrapped)
            if inner is EnvKind.GYM_ENV:
                return EnvKind.GYM_ENV  # ``wrap_deepmind(env)``: the Gym env it takes, maybe in Gym wrappers
            if inner is EnvKind.SB3_VEC:
                return EnvKind.SB3_VEC  # a VecEnv, maybe in wrapper classes of the run: they answer as it does
        if self._run_wrapper_around_vec_env(call):
            return EnvKind.SB3_VEC
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
            kind = self.class_kind(local_class)
            if kind is EnvKind.UNKNOWN and self._registered_class(local_class):
                # a class of a library base (``class Game(NESEnv)``) the run registers with
                # Gym's registry: a Gym env, as ``make`` of its id gives one
                return EnvKind.GYM_ENV
            return kind
        local_function = self.local_function(func)
        if local_function is not None:
            return self.returns_kind(local_function)
        own = self.own_method(func)
        if own is not None:
            return self.facts.memo(("returned-kind", id(own)), lambda: self.returns_kind(own), while_computing=EnvKind.UNKNOWN)
        if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name) and self.is_self(func.value):
            # ``self.make_env_fn(...)`` with ``self.make_env_fn = make_env_fn`` stored from a
            # parameter or a factory: what calling each stored callable returns.
            stored = self.self_attribute_values(func, func.attr)
            if stored:
                return join_kinds(self.returned_kind(value) for value in stored)
            handed = self.attributes.handed_up(func)
            if handed is not None:
                # ``self.env_class(...)`` stored by a base of another module from what this
                # class's ``__init__`` hands up: what calling that parameter's values gives
                return self.returned_kind(handed.argument)
        if isinstance(func, ast.Subscript):
            return self.returned_kind(func)  # ``self.env_fns[i]()``: an item of a list of thunks
        if isinstance(func, ast.Call):
            return self.called_factory_kind(func)  # ``get_creator(name)(config)``: what its thunk returns
        if isinstance(func, ast.Name):
            # ``make_env = lambda: gym.make(...)``, a nested ``def thunk()``, an ``env_fn``
            # parameter: what calling the name returns.
            kind = self.returned_kind(func)
            if kind is EnvKind.UNKNOWN and self.class_narrowing.is_env(func):
                # ``if issubclass(env_cls, gym.Env): env = env_cls(**kwargs)``: an instance
                # of a class the code has checked is a Gym env class
                return EnvKind.GYM_ENV
            return kind
        if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name):
            held = self.callables.held_callable_kind(func)  # ``env_fn_wrapper.x()`` in a worker
            if held is not EnvKind.UNKNOWN:
                return held
        if isinstance(func, ast.Attribute) and func.attr == "learn" and self.kind_of(func.value) is EnvKind.SB3_MODEL:
            return EnvKind.SB3_MODEL  # ``PPO(...).learn(n)``: an algorithm's ``learn`` returns the algorithm
        # ``VecNormalize.load(...)`` is a classmethod call on a known class.
        if isinstance(func, ast.Attribute):
            owner = self.qualified_names(func.value)
            if any(q.startswith(N.SB3_VEC_PREFIXES) for q in owner):
                return EnvKind.SB3_VEC
            if any(q.startswith(N.SB3_PACKAGES) for q in owner) and func.attr == "load":
                return EnvKind.SB3_MODEL
        return EnvKind.UNKNOWN

    def _get_env_kind(self, func: ast.Attribute) -> EnvKind | None:
        """``x.get_env()``: Stable-Baselines' ``BaseAlgorithm.get_env`` (its VecEnv) only where
        the run proves ``x`` an algorithm (``PPO(...)``, ``PPO.load(...)``, a callback's
        ``self.model``, ``self`` in a subclass of one); a method of that name on the project's
        own object is no accessor of a library: None, so the call is followed as any other
        call of the class's own method (``self.get_env()``, an instance of a class of this
        module). Otherwise unknown: the name alone decides nothing."""
        owner = func.value
        if isinstance(owner, ast.Name) and self.is_self(owner):
            if self.own_method(func) is not None:
                return None
            classdef = self.facts.enclosing_class(func)
            if classdef is not None and self.attributes.set_by_library_base(classdef, "env") is EnvKind.SB3_VEC:
                return EnvKind.SB3_VEC
            return EnvKind.UNKNOWN
        if self.kind_of(owner) is EnvKind.SB3_MODEL:
            return EnvKind.SB3_VEC
        methods = self.instance_methods(owner, func.attr)
        if methods:
            return join_kinds(
                self.facts.memo(("returned-kind", id(m)), lambda m=m: self.returns_kind(m), while_computing=EnvKind.UNKNOWN)
                for m in methods
            )
        return EnvKind.UNKNOWN

    def instance_methods(self, owner: ast.expr, name: str) -> list[ast.FunctionDef | ast.AsyncFunctionDef]:
        """The ``def name`` of each class of this module that ``owner`` is bound to an
        instance of (``g = Builder()``, in every binding), or none when one binding is anything
        else or its class does not define ``name`` itself."""
        if not isinstance(owner, ast.Name):
            return []
        bindings = self.facts.bindings_of(owner)
        found: list[ast.FunctionDef | ast.AsyncFunctionDef] = []
        for binding in bindings:
            statement = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
            if not (isinstance(statement, ast.Assign) and statement.targets == [binding] and isinstance(statement.value, ast.Call)):
                return []
            classdef = self.local_class(statement.value.func)
            if classdef is None:
                return []
            method = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == name), None)
            if method is None:
                return []
            found.append(method)
        return found

    def _closure_self(self, name: ast.Name) -> bool:
        """``self`` read in a def nested in a method: that method's first parameter."""
        bindings = self.facts.bindings_of(name)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.arg):
            return False
        function = self.facts.parent(self.facts.parent(bindings[0]))
        if not (isinstance(function, FUNCTIONS) and self.facts.is_method(function)):
            return False
        params = [*function.args.posonlyargs, *function.args.args]
        return bool(params) and params[0] is bindings[0] and self.facts.enclosing_function(name) is not function

    def _run_wrapper_around_vec_env(self, call: ast.Call) -> bool:
        """``Stats(venv)``: a Gym wrapper class of the run (this module's or another's) put
        around a VecEnv. gym's Wrapper took any object and handed on what it gives; the
        instance answers as that VecEnv does (a four-field step, reset with no seed), whatever
        the class does elsewhere. Gym's own wrappers are not of the run: not these."""
        argument = call_argument(call, 0, "env")
        if argument is None or isinstance(argument, ast.Starred):
            return False
        local = self.local_class(call.func)
        if local is not None:
            of_run = self.has_gym_wrapper_base(local)
        else:
            project = self.project
            of_run = project is not None and any(project.is_wrapper_class(q) for q in self.qualified_names(call.func))
        return of_run and self.kind_of(argument) is EnvKind.SB3_VEC

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
        if package in N.PZ_MOVED_PACKAGES:
            # a family that left PettingZoo (``mpe2.simple_v3.parallel_env()``) still makes
            # PettingZoo envs: the second pass reads the imports PZ111 rewrote
            if qualified.endswith(N.PZ_PARALLEL_SUFFIXES):
                return EnvKind.PZ_PARALLEL
            return EnvKind.PZ_AEC if qualified.endswith(N.PZ_AEC_SUFFIXES) else None
        if package == N.SUPERSUIT_PACKAGE:
            return self._supersuit_kind(qualified, call)
        if package in N.NOT_ENV_PACKAGES or N.has_own_env_api(qualified):
            return EnvKind.NOT_ENV  # (RLlib's multi-agent envs: per-agent dicts, never Gym's API)
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
        if name == "env" and isinstance(attr.value, ast.Name) and self._closure_self(attr.value):
            classdef = self.facts.enclosing_class(attr)
            if classdef is not None and self.wraps_vec_env(classdef):
                # ``def step(action): ... self.env.step(action)`` defined in ``__init__``: the
                # method's ``self``, whose ``env`` is the VecEnv every construction wraps
                return EnvKind.SB3_VEC
        if name in ("env", "unwrapped"):
            owner = self.kind_of(attr.value)
            if owner is EnvKind.SB3_MODEL and name == "env":
                return EnvKind.SB3_VEC
            if owner is EnvKind.SB3_VEC and name == "unwrapped":
                return EnvKind.SB3_VEC  # every VecEnv family's ``unwrapped`` is the innermost VecEnv
            if owner is EnvKind.GYM_ENV:
                return EnvKind.GYM_ENV
        if any(N.top_package(q) in N.NOT_ENV_PACKAGES for q in self.qualified_names(attr)):
            return EnvKind.NOT_ENV
        if isinstance(attr.value, ast.Name):
            return self._held_kind(attr.value, name)
        return EnvKind.UNKNOWN

    def _held_kind(self, holder: ast.Name, name: str) -> EnvKind:
        """``holder.gym_env`` with every binding of ``holder`` a construction of one plain
        class (``holder = Environment(gym_env)``) that stores the attribute from its
        ``__init__`` parameter: a Gym env when every construction passes one (this module's
        class: its stores' kinds; the run's: ``ProjectView.held_kind``). Else unknown."""
        bindings = self.facts.bindings_of(holder)
        if len(bindings) == 1 and isinstance(bindings[0], ast.arg):
            # ``env = env_fn_wrapper.x`` in a worker the module spawns with
            # ``Process(target=worker, args=(..., Holder(gym.make(...))))``
            parent = self.facts.parent(holder)
            return self.callables.held_value_kind(parent) if isinstance(parent, ast.Attribute) and parent.attr == name else EnvKind.UNKNOWN
        calls = []
        for binding in bindings:
            statement = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
            if not (isinstance(statement, ast.Assign) and statement.targets == [binding] and isinstance(statement.value, ast.Call)):
                return EnvKind.UNKNOWN
            calls.append(statement.value)
        kinds: set[EnvKind] = set()
        for call in calls:
            classdef = self.local_class(call.func)
            if classdef is not None:
                values = self.self_stores(classdef).get(name, [])
                if self.class_kind(classdef) is not EnvKind.NOT_ENV or not values:
                    return EnvKind.UNKNOWN
                kinds.update(self.kind_of(value) for value in values)
                continue
            qualified = self.qualified_names(call.func)
            found = self.project.held_kind(next(iter(qualified)), name) if self.project is not None and len(qualified) == 1 else None
            kinds.add(found or EnvKind.UNKNOWN)
        return EnvKind.GYM_ENV if kinds == {EnvKind.GYM_ENV} else EnvKind.UNKNOWN

    def mixed_callers(self, expr: ast.AST, _depth: int = 0) -> str | None:
        """Also: ``expr`` a name bound to a Gym env in one place and to an object of the
        project's own class in another, both reaching this read (``_join_bindings``)."""
        if isinstance(expr, ast.Name) and self.kind_of(expr) is EnvKind.UNKNOWN:
            bindings = self.facts.bindings_of(expr)
            reaching = Flow.of(self.facts).reaching(expr)
            if reaching:
                cut = same_tests.excluded(self.facts, expr, reaching)
                bindings = [b for b in reaching if id(b) not in cut]
            gym = [b for b in bindings if self.binding_kind(b) in (EnvKind.GYM_ENV, EnvKind.GYM_VEC)]
            own = [(b, call) for b in bindings if (call := self._own_object(b)) is not None]
            if gym and own:
                made = self.facts.segment(own[0][1].func)
                kind = self.binding_kind(gym[0])
                assert kind is not None
                return (
                    f"it holds a {kind.value} (line {gym[0].lineno}) or an object of the project's own "  # type: ignore[attr-defined]
                    f"`{made}` (line {own[0][0].lineno}), and no test repeated around this call tells which"  # type: ignore[attr-defined]
                )
        return super().mixed_callers(expr, _depth)


    def _registered_class(self, classdef: ast.ClassDef) -> bool:
        """The run registers ``classdef`` as an ``entry_point`` with the Gym registry (a file
        checked alone: ``register(..., entry_point=__name__ + ":Class")`` in this module)."""
        if self.project is not None:
            return self.project.registered_here(classdef.name)
        for call in (*self.facts.calls_by_name.get("register", ()), *self.facts.attribute_calls.get("register", ())):
            if not any(N.strip_gym_prefix(q) in ("register", "envs.register", "envs.registration.register") for q in self.qualified_names(call.func)):
                continue
            if own_entry_point(call_argument(call, 1, "entry_point")) == ":" + classdef.name:
                return True
        return False

    def returns_kind(self, function: ast.AST) -> EnvKind:
        values = [r.value for r in own_returns(function) if r.value is not None]
        if not values:
            return EnvKind.NOT_ENV
        return join_kinds(self.kind_of(value) for value in values)
