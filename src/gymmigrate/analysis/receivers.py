"""Receiver classification: what kind of object is ``x`` in ``x.step(a)``?

The same text (``x.reset()``, ``x.step(a)``, ``x.seed(s)``) has different correct
answers for a Gym env, a Gym vector env, a Stable-Baselines3 VecEnv, a PettingZoo env
or an optimiser. Rules that rewrite those calls ask this module first.

The analysis is syntactic and per module, and it decides from where a name comes
from, never from its spelling: it follows assignments (through LibCST's scope
analysis), ``self.x = ...`` stores in the same class, returns of functions defined in
the module, and arguments at every call site of a function whose parameter is used.
When the evidence disagrees or runs out, the answer is ``UNKNOWN`` and callers
report instead of guessing.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Iterable, Mapping
from enum import Enum

import libcst as cst
from libcst.metadata import (
    Assignment,
    ParentNodeProvider,
    QualifiedName,
    QualifiedNameProvider,
    ScopeProvider,
)

from gymmigrate.analysis import names as N
from gymmigrate.analysis.syntax import own_return_values

try:  # LibCST resolves some providers lazily
    from libcst._metadata_dependent import LazyValue
except ImportError:  # pragma: no cover
    LazyValue = ()  # type: ignore[assignment,misc]


def _metadata(mapping: Mapping[cst.CSTNode, object], node: cst.CSTNode) -> object:
    value = mapping.get(node)
    if LazyValue and isinstance(value, LazyValue):
        value = value()
    return value


class EnvKind(str, Enum):
    GYM_ENV = "Gym env"
    GYM_VEC = "Gym vector env"
    SB3_VEC = "Stable-Baselines3 VecEnv"
    SB3_MODEL = "Stable-Baselines3 model"
    PZ_AEC = "PettingZoo AEC env"
    PZ_PARALLEL = "PettingZoo parallel env"
    NOT_ENV = "not an env"
    UNKNOWN = "unknown"

    @property
    def is_gym(self) -> bool:
        return self in (EnvKind.GYM_ENV, EnvKind.GYM_VEC)


METADATA = (ScopeProvider, ParentNodeProvider, QualifiedNameProvider)


def join_kinds(kinds: Iterable[EnvKind]) -> EnvKind:
    """Combine the kinds of every binding of one name.

    A guard kind wins (one SB3 binding is enough to leave the call alone); otherwise
    the bindings must agree.
    """
    found = set(kinds)
    if not found:
        return EnvKind.UNKNOWN
    if EnvKind.SB3_VEC in found:
        return EnvKind.SB3_VEC
    if len(found) == 1:
        return found.pop()
    found.discard(EnvKind.NOT_ENV)  # e.g. ``env = None`` before ``env = gym.make(...)``
    if len(found) == 1:
        return found.pop()
    return EnvKind.UNKNOWN


class ReceiverAnalysis:
    """Classifies expressions of one module. Build one per transformer pass."""

    def __init__(self, module: cst.Module, metadata: Mapping[type, Mapping[cst.CSTNode, object]]) -> None:
        self._module = module
        self._metadata = metadata  # providers are looked up on first use (they may be lazy)
        self._cache: dict[int, EnvKind] = {}
        self._in_progress: set[int] = set()
        self._calls_by_name: dict[str, list[cst.Call]] | None = None
        self._classes: dict[str, cst.ClassDef] | None = None
        self._functions: dict[str, cst.FunctionDef] | None = None
        self._self_stores: dict[int, dict[str, list[cst.BaseExpression]]] = {}
        self._returns: dict[int, list[cst.BaseExpression]] = {}

    @property
    def _scopes(self) -> Mapping[cst.CSTNode, object]:
        return self._metadata[ScopeProvider]

    def scope_of(self, node: cst.CSTNode) -> object:
        """LibCST's scope of ``node`` (None for nodes outside the analysed tree)."""
        return _metadata(self._scopes, node)

    @property
    def _parents(self) -> Mapping[cst.CSTNode, object]:
        return self._metadata[ParentNodeProvider]

    @property
    def _qualnames(self) -> Mapping[cst.CSTNode, object]:
        return self._metadata[QualifiedNameProvider]

    # -- public -----------------------------------------------------------------

    def kind_of(self, expr: cst.BaseExpression) -> EnvKind:
        key = id(expr)
        if key in self._cache:
            return self._cache[key]
        if key in self._in_progress:  # a cycle such as ``env = wrap(env)``: no new evidence
            return EnvKind.UNKNOWN
        self._in_progress.add(key)
        try:
            kind = self._classify(expr)
        finally:
            self._in_progress.discard(key)
        self._cache[key] = kind
        return kind

    def qualified_names(self, node: cst.CSTNode) -> set[str]:
        found: Iterable[QualifiedName] = _metadata(self._qualnames, node) or ()  # type: ignore[assignment]
        return {q.name for q in found}

    def class_kind(self, classdef: cst.ClassDef) -> EnvKind:
        """The kind of instances of a class defined in this module, from its bases."""
        kinds = []
        for base in classdef.bases:
            kinds.append(self._base_kind(base.value))
        useful = [k for k in kinds if k not in (EnvKind.UNKNOWN, EnvKind.NOT_ENV)]
        return useful[0] if useful else EnvKind.NOT_ENV if not kinds else EnvKind.UNKNOWN

    def is_gym_wrapper_class(self, classdef: cst.ClassDef) -> bool:
        for base in classdef.bases:
            for q in self.qualified_names(base.value):
                rest = N.strip_gym_prefix(q)
                if rest is not None and (rest in N.GYM_WRAPPER_BASE_CLASSES or rest.startswith("wrappers.")):
                    return True
            local = self.local_class(base.value)
            if local is not None and local is not classdef and self.is_gym_wrapper_class(local):
                return True
        return False

    def parent(self, node: cst.CSTNode) -> cst.CSTNode | None:
        return _metadata(self._parents, node)  # type: ignore[return-value]

    def enclosing(self, node: cst.CSTNode, kind: type[cst.CSTNode]) -> cst.CSTNode | None:
        current = self.parent(node)
        while current is not None and not isinstance(current, kind):
            current = self.parent(current)
        return current

    # -- classification -----------------------------------------------------------

    def _classify(self, expr: cst.BaseExpression) -> EnvKind:
        if isinstance(expr, cst.Name):
            return self._classify_name(expr)
        if isinstance(expr, cst.Call):
            return self._classify_call(expr)
        if isinstance(expr, cst.Attribute):
            return self._classify_attribute(expr)
        if isinstance(expr, cst.Subscript):
            return self._element_kind(expr.value)
        if isinstance(expr, (cst.IfExp,)):
            return join_kinds([self.kind_of(expr.body), self.kind_of(expr.orelse)])
        if isinstance(expr, cst.NamedExpr):
            return self.kind_of(expr.value)
        if isinstance(
            expr,
            (
                cst.BaseNumber,
                cst.BaseString,
                cst.List,
                cst.Tuple,
                cst.Dict,
                cst.Set,
                cst.ListComp,
                cst.DictComp,
                cst.SetComp,
                cst.GeneratorExp,
                cst.Lambda,
                cst.BinaryOperation,
                cst.UnaryOperation,
                cst.Comparison,
                cst.BooleanOperation,
            ),
        ):
            return EnvKind.NOT_ENV
        return EnvKind.UNKNOWN

    def _classify_call(self, call: cst.Call) -> EnvKind:
        func = call.func
        # model.get_env() on anything: Stable-Baselines3's accessor for its VecEnv.
        if isinstance(func, cst.Attribute) and func.attr.value == "get_env":
            return EnvKind.SB3_VEC
        # gym.spec(id).make()
        if isinstance(func, cst.Attribute) and func.attr.value == "make" and isinstance(func.value, cst.Call):
            if any(N.strip_gym_prefix(q) in ("spec", "envs.spec") for q in self.qualified_names(func.value.func)):
                return EnvKind.GYM_ENV
        qualified = self.qualified_names(func)
        kinds = [self._kind_from_qualified(q, call) for q in qualified]
        kinds = [k for k in kinds if k is not None]
        if kinds:
            return join_kinds(kinds)
        local_class = self.local_class(func)
        if local_class is not None:
            return self.class_kind(local_class)
        local_function = self.local_function(func)
        if local_function is not None:
            return self._returns_kind(local_function)
        # Methods of known objects: ``env.unwrapped`` style accessors are attributes, but
        # ``VecNormalize.load(...)`` is a classmethod call.
        if isinstance(func, cst.Attribute):
            owner = self.qualified_names(func.value)
            if any(q.startswith(N.SB3_VEC_PREFIXES) for q in owner):
                return EnvKind.SB3_VEC
            if any(q.startswith(N.SB3_PACKAGES) for q in owner) and func.attr.value == "load":
                return EnvKind.SB3_MODEL
        return EnvKind.UNKNOWN

    def _kind_from_qualified(self, qualified: str, call: cst.Call) -> EnvKind | None:
        rest = N.strip_gym_prefix(qualified)
        if rest is not None:
            if rest in N.GYM_VEC_FACTORIES or rest.startswith(N.GYM_VEC_PREFIXES):
                return EnvKind.GYM_VEC
            if rest in N.GYM_ENV_FACTORIES:
                return EnvKind.GYM_ENV
            if rest.startswith(N.GYM_ENV_CLASS_PREFIXES) and rest.rsplit(".", 1)[-1][:1].isupper():
                return EnvKind.GYM_ENV
            return EnvKind.NOT_ENV
        if qualified in N.SB3_VEC_FACTORIES or qualified.startswith(N.SB3_VEC_PREFIXES):
            return EnvKind.SB3_VEC
        package = N.top_package(qualified)
        if package in N.SB3_PACKAGES:
            name = qualified.rsplit(".", 1)[-1]
            if name.isupper() or name in ("HER", "RecurrentPPO", "MaskablePPO", "QRDQN", "TQC", "TRPO", "ARS"):
                return EnvKind.SB3_MODEL
            return None
        if package == N.PETTINGZOO_PACKAGE:
            if qualified in N.PZ_PARALLEL_FACTORIES or qualified.endswith(N.PZ_PARALLEL_SUFFIXES):
                return EnvKind.PZ_PARALLEL
            if qualified in N.PZ_AEC_FACTORIES or qualified.endswith(N.PZ_AEC_SUFFIXES):
                return EnvKind.PZ_AEC
            if qualified == "pettingzoo.make" and call.args:
                first = call.args[0].value
                if isinstance(first, cst.SimpleString):
                    return EnvKind.PZ_PARALLEL if "parallel" in first.value else EnvKind.PZ_AEC
            if ".wrappers." in qualified:
                return EnvKind.PZ_AEC
            return None
        if package in N.NOT_ENV_PACKAGES:
            return EnvKind.NOT_ENV
        return None

    def _classify_attribute(self, attr: cst.Attribute) -> EnvKind:
        name = attr.attr.value
        if name == "training_env":
            return EnvKind.SB3_VEC
        if isinstance(attr.value, cst.Name) and self._is_self(attr.value):
            return self._self_attribute_kind(attr, name)
        if name in ("env", "unwrapped"):
            owner = self.kind_of(attr.value)
            if owner is EnvKind.SB3_MODEL and name == "env":
                return EnvKind.SB3_VEC
            if owner is EnvKind.GYM_ENV:
                return EnvKind.GYM_ENV
        qualified = self.qualified_names(attr)
        if any(N.top_package(q) in N.NOT_ENV_PACKAGES for q in qualified):
            return EnvKind.NOT_ENV
        return EnvKind.UNKNOWN

    def _classify_name(self, name: cst.Name) -> EnvKind:
        scope = _metadata(self._scopes, name)
        if scope is None:
            return EnvKind.UNKNOWN
        kinds = []
        for assignment in scope[name.value]:  # type: ignore[index]
            if not isinstance(assignment, Assignment):
                kinds.append(EnvKind.NOT_ENV)  # imports and builtins are modules/functions
                continue
            kind = self._assignment_kind(assignment.node)
            if kind is not None:
                kinds.append(kind)
        return join_kinds(kinds)

    def _assignment_kind(self, target: cst.CSTNode) -> EnvKind | None:
        if isinstance(target, (cst.FunctionDef, cst.ClassDef)):
            return EnvKind.NOT_ENV
        if isinstance(target, cst.Param):
            return self._param_kind(target)
        if not isinstance(target, cst.Name):
            return EnvKind.UNKNOWN
        parent = self.parent(target)
        if isinstance(parent, cst.AssignTarget):
            assign = self.parent(parent)
            if isinstance(assign, cst.Assign):
                return self.kind_of(assign.value)
        if isinstance(parent, cst.AnnAssign):
            if parent.value is not None:
                return self.kind_of(parent.value)
            return self._annotation_kind(parent.annotation.annotation)
        if isinstance(parent, cst.NamedExpr):
            return self.kind_of(parent.value)
        if isinstance(parent, cst.AsName):
            item = self.parent(parent)
            if isinstance(item, cst.WithItem):
                return self.kind_of(item.item)
            return EnvKind.NOT_ENV
        if isinstance(parent, (cst.For, cst.CompFor)) and parent.target is target:
            return self._element_kind(parent.iter)
        if isinstance(parent, cst.Element):
            return self._unpacked_kind(target, parent)
        if isinstance(parent, cst.AugAssign):
            return None
        return EnvKind.UNKNOWN

    def _unpacked_kind(self, target: cst.Name, element: cst.Element) -> EnvKind:
        container = self.parent(element)
        if not isinstance(container, (cst.Tuple, cst.List)):
            return EnvKind.UNKNOWN
        index = next(i for i, el in enumerate(container.elements) if el is element)
        holder = self.parent(container)
        value: cst.BaseExpression | None = None
        if isinstance(holder, cst.AssignTarget):
            assign = self.parent(holder)
            if isinstance(assign, cst.Assign):
                value = assign.value
        elif isinstance(holder, (cst.For, cst.CompFor)):
            # ``for i, env in enumerate(envs)`` and ``for env, name in zip(envs, names)``
            iterable = holder.iter
            if isinstance(iterable, cst.Call) and isinstance(iterable.func, cst.Name):
                if iterable.func.value == "enumerate" and index == 1 and iterable.args:
                    return self._element_kind(iterable.args[0].value)
                if iterable.func.value == "zip" and index < len(iterable.args):
                    return self._element_kind(iterable.args[index].value)
            return EnvKind.UNKNOWN
        if isinstance(value, (cst.Tuple, cst.List)) and len(value.elements) == len(container.elements):
            if not any(isinstance(el, cst.StarredElement) for el in value.elements):
                return self.kind_of(value.elements[index].value)
        if value is not None and not isinstance(value, (cst.Tuple, cst.List)):
            # ``obs, info = env.reset()``: the targets are values returned by a call, not envs
            # unless the call is a local function returning a tuple of envs.
            local = self.local_function(value.func) if isinstance(value, cst.Call) else None
            if local is None:
                return EnvKind.NOT_ENV if isinstance(value, cst.Call) and self._is_env_method_call(value) else EnvKind.UNKNOWN
        return EnvKind.UNKNOWN

    def _is_env_method_call(self, call: cst.Call) -> bool:
        return isinstance(call.func, cst.Attribute) and call.func.attr.value in ("reset", "step", "last")

    def _element_kind(self, container: cst.BaseExpression) -> EnvKind:
        """Kind of the items of a list/tuple of envs (``envs[i]``, ``for env in envs``)."""
        if isinstance(container, (cst.List, cst.Tuple, cst.Set)):
            return join_kinds(
                self.kind_of(el.value) for el in container.elements if not isinstance(el, cst.StarredElement)
            )
        if isinstance(container, (cst.ListComp, cst.GeneratorExp, cst.SetComp)):
            return self.kind_of(container.elt)
        if isinstance(container, cst.Name):
            scope = _metadata(self._scopes, container)
            if scope is None:
                return EnvKind.UNKNOWN
            kinds = []
            for assignment in scope[container.value]:  # type: ignore[index]
                if isinstance(assignment, Assignment) and isinstance(assignment.node, cst.Name):
                    parent = self.parent(assignment.node)
                    if isinstance(parent, cst.AssignTarget):
                        assign = self.parent(parent)
                        if isinstance(assign, cst.Assign):
                            kinds.append(self._element_kind(assign.value))
                            continue
                kinds.append(EnvKind.UNKNOWN)
            return join_kinds(kinds)
        if isinstance(container, cst.Attribute) and isinstance(container.value, cst.Name):
            if self._is_self(container.value):
                values = self._self_attribute_values(container, container.attr.value)
                return join_kinds(self._element_kind(v) for v in values) if values else EnvKind.UNKNOWN
        return EnvKind.UNKNOWN

    # -- parameters ---------------------------------------------------------------

    def _param_kind(self, param: cst.Param) -> EnvKind:
        if param.annotation is not None:
            kind = self._annotation_kind(param.annotation.annotation)
            if kind is not EnvKind.UNKNOWN:
                return kind
        function = self.enclosing(param, cst.FunctionDef)
        if not isinstance(function, cst.FunctionDef):
            return EnvKind.UNKNOWN
        params = list(function.params.posonly_params) + list(function.params.params)
        name = param.name.value
        classdef = self.enclosing(function, cst.ClassDef)
        is_method = isinstance(classdef, cst.ClassDef) and self.parent(self.parent(function)) is classdef
        if is_method and params and params[0] is param:
            return EnvKind.NOT_ENV  # self / cls
        if is_method and name == "env" and function.name.value == "__init__" and self.is_gym_wrapper_class(classdef):
            return EnvKind.GYM_ENV
        position = next((i for i, p in enumerate(params) if p is param), None)
        if position is not None and is_method:
            position -= 1  # calls do not pass self
        calls = self.call_sites(function, classdef if is_method else None)
        if not calls:
            return EnvKind.UNKNOWN
        kinds = []
        for call in calls:
            argument = call_argument(call, position, name)
            if argument is None:
                if param.default is not None:
                    continue
                kinds.append(EnvKind.UNKNOWN)
            else:
                kinds.append(self.kind_of(argument))
        return join_kinds(kinds)

    def _annotation_kind(self, annotation: cst.BaseExpression) -> EnvKind:
        for q in self.qualified_names(annotation):
            rest = N.strip_gym_prefix(q)
            if rest in N.GYM_ENV_BASE_CLASSES:
                return EnvKind.GYM_ENV
            if rest is not None and (rest.startswith("vector.") and rest.endswith("Env")):
                return EnvKind.GYM_VEC
            other = _other_library_class_kind(q)
            if other is not None:
                return other
        return EnvKind.UNKNOWN

    def call_sites(self, function: cst.FunctionDef, classdef: cst.ClassDef | None) -> list[cst.Call]:
        if self._calls_by_name is None:
            collector = _CallCollector()
            self._module.visit(collector)
            self._calls_by_name = collector.calls
        name = function.name.value
        calls = self._calls_by_name.get(name, [])
        if classdef is None:
            return [c for c in calls if isinstance(c.func, cst.Name) and self.local_function(c.func) is function]
        if name == "__init__":
            return [c for c in self._calls_by_name.get(classdef.name.value, []) if isinstance(c.func, cst.Name)]
        return [c for c in calls if isinstance(c.func, cst.Attribute) and isinstance(c.func.value, cst.Name) and self._is_self(c.func.value)]

    # -- self attributes ------------------------------------------------------------

    def _is_self(self, name: cst.Name) -> bool:
        function = self.enclosing(name, cst.FunctionDef)
        if not isinstance(function, cst.FunctionDef):
            return False
        params = list(function.params.posonly_params) + list(function.params.params)
        return bool(params) and params[0].name.value == name.value and name.value in ("self", "cls")

    def _self_attribute_kind(self, attr: cst.Attribute, name: str) -> EnvKind:
        classdef = self.enclosing(attr, cst.ClassDef)
        if not isinstance(classdef, cst.ClassDef):
            return EnvKind.UNKNOWN
        if name == "env" and self.is_gym_wrapper_class(classdef):
            return EnvKind.GYM_ENV
        if name == "training_env" or (name == "model" and self._is_sb3_callback(classdef)):
            return EnvKind.SB3_VEC if name == "training_env" else EnvKind.SB3_MODEL
        values = self._self_attribute_values(attr, name)
        if not values:
            return EnvKind.UNKNOWN
        return join_kinds(self.kind_of(value) for value in values)

    def _self_attribute_values(self, attr: cst.Attribute, name: str) -> list[cst.BaseExpression]:
        classdef = self.enclosing(attr, cst.ClassDef)
        if not isinstance(classdef, cst.ClassDef):
            return []
        # One walk per class, not per attribute read: env classes read dozens of self.x.
        stores = self._self_stores.get(id(classdef))
        if stores is None:
            collector = _SelfStoreCollector()
            classdef.visit(collector)
            stores = self._self_stores[id(classdef)] = collector.values
        return stores.get(name, [])

    def _is_sb3_callback(self, classdef: cst.ClassDef) -> bool:
        return any(q in N.SB3_CALLBACK_BASES for base in classdef.bases for q in self.qualified_names(base.value))

    # -- local definitions ------------------------------------------------------------

    def _definitions(self) -> tuple[dict[str, cst.ClassDef], dict[str, cst.FunctionDef]]:
        if self._classes is None or self._functions is None:
            classes: dict[str, cst.ClassDef] = {}
            functions: dict[str, cst.FunctionDef] = {}
            for statement in self._module.body:
                if isinstance(statement, cst.ClassDef):
                    classes[statement.name.value] = statement
                elif isinstance(statement, cst.FunctionDef):
                    functions[statement.name.value] = statement
            self._classes, self._functions = classes, functions
        return self._classes, self._functions

    def local_class(self, func: cst.BaseExpression) -> cst.ClassDef | None:
        if not isinstance(func, cst.Name):
            return None
        return self._definitions()[0].get(func.value)

    def local_function(self, func: cst.BaseExpression) -> cst.FunctionDef | None:
        if not isinstance(func, cst.Name):
            return None
        return self._definitions()[1].get(func.value)

    def _base_kind(self, base: cst.BaseExpression) -> EnvKind:
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
        local = self.local_class(base)
        if local is not None:
            return self.class_kind(local)
        return EnvKind.UNKNOWN

    def _returns_kind(self, function: cst.FunctionDef) -> EnvKind:
        values = self._returns.get(id(function))
        if values is None:
            values = self._returns[id(function)] = own_return_values(function)
        if not values:
            return EnvKind.NOT_ENV
        return join_kinds(self.kind_of(value) for value in values)


def _other_library_class_kind(qualified: str) -> EnvKind | None:
    """Kind of an SB3 or PettingZoo class named in an annotation or a base list."""
    if qualified.startswith(N.SB3_VEC_PREFIXES):
        return EnvKind.SB3_VEC
    if qualified in N.PZ_AEC_BASES:
        return EnvKind.PZ_AEC
    if qualified in N.PZ_PARALLEL_BASES:
        return EnvKind.PZ_PARALLEL
    return None


def call_argument(call: cst.Call, position: int | None, name: str) -> cst.BaseExpression | None:
    positional = [a for a in call.args if a.keyword is None and a.star == ""]
    for arg in call.args:
        if arg.keyword is not None and arg.keyword.value == name:
            return arg.value
    if position is not None and 0 <= position < len(positional):
        if any(a.star for a in call.args[: position + 1]):
            return None
        return positional[position].value
    return None


class _CallCollector(cst.CSTVisitor):
    def __init__(self) -> None:
        self.calls: dict[str, list[cst.Call]] = defaultdict(list)

    def visit_Call(self, node: cst.Call) -> None:
        func = node.func
        if isinstance(func, cst.Name):
            self.calls[func.value].append(node)
        elif isinstance(func, cst.Attribute):
            self.calls[func.attr.value].append(node)


class _SelfStoreCollector(cst.CSTVisitor):
    """Values stored to ``self.<name>`` anywhere in a class body (not nested classes), by name."""

    def __init__(self) -> None:
        self.values: dict[str, list[cst.BaseExpression]] = defaultdict(list)
        self._depth = 0

    def visit_ClassDef(self, node: cst.ClassDef) -> bool:
        self._depth += 1
        return self._depth == 1

    def leave_ClassDef(self, original_node: cst.ClassDef) -> None:
        self._depth -= 1

    @staticmethod
    def _stored_name(target: cst.BaseExpression) -> str | None:
        if isinstance(target, cst.Attribute) and isinstance(target.value, cst.Name) and target.value.value == "self":
            return target.attr.value
        return None

    def visit_Assign(self, node: cst.Assign) -> None:
        for target in node.targets:
            name = self._stored_name(target.target)
            if name is not None:
                self.values[name].append(node.value)
            elif isinstance(target.target, (cst.Tuple, cst.List)) and isinstance(node.value, (cst.Tuple, cst.List)):
                for el, value in zip(target.target.elements, node.value.elements):
                    name = self._stored_name(el.value)
                    if name is not None:
                        self.values[name].append(value.value)

    def visit_AnnAssign(self, node: cst.AnnAssign) -> None:
        name = self._stored_name(node.target)
        if name is not None and node.value is not None:
            self.values[name].append(node.value)


