"""What kind of object a receiver is (``EnvKind``), and how the kinds of several
bindings of one name join. Every receiver question in the facts and the rules is
answered in these terms."""

from __future__ import annotations

import ast
from collections.abc import Iterable
from enum import Enum
from typing import TYPE_CHECKING, Protocol

if TYPE_CHECKING:
    from gymmigrate.facts.callables import CallableKinds
    from gymmigrate.facts.module import ModuleFacts
    from gymmigrate.facts.project_view import ProjectView
    from gymmigrate.facts.self_attributes import SelfAttributes

# Deeper than any real chain of rebindings; beyond it the answer is "unknown", which
# callers report. Keeps recursion far from the interpreter's limit.
MAX_DEPTH = 120


class EnvKind(str, Enum):
    GYM_ENV = "Gym env"
    GYM_VEC = "Gym vector env"
    SB3_VEC = "VecEnv (Stable-Baselines3, stable_baselines 2.x or OpenAI baselines)"
    SB3_MODEL = "Stable-Baselines3 model"
    PZ_AEC = "PettingZoo AEC env"
    PZ_PARALLEL = "PettingZoo parallel env"
    # A Gym env class of the run whose own reset/step follow a contract of their own
    # (per-agent dicts, one shape per mode: ``facts/own_api.py``): neither Gym's nor
    # Gymnasium's, so no call on one is rewritten.
    OWN_API = "Gym env with an API of its own"
    NOT_ENV = "not an env"
    UNKNOWN = "unknown"

    @property
    def is_gym(self) -> bool:
        return self in (EnvKind.GYM_ENV, EnvKind.GYM_VEC)


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


class ReceiverQueries(Protocol):
    """What the receiver analysis answers its helpers (``facts.callables``,
    ``facts.self_attributes``): they ask back through this, never import it."""

    facts: ModuleFacts
    depth: int

    def kind_of(self, expr: ast.AST) -> EnvKind: ...
    def qualified_names(self, node: ast.AST) -> set[str]: ...
    def class_kind(self, classdef: ast.ClassDef) -> EnvKind: ...
    def is_gym_wrapper_class(self, classdef: ast.ClassDef) -> bool: ...
    def forwards_inner_contract(self, classdef: ast.ClassDef) -> bool: ...
    def unproved_duck_wrapper(self, classdef: ast.ClassDef) -> bool: ...
    def wraps_gym_only(self, classdef: ast.ClassDef) -> str | None: ...
    def wraps_pz_parallel(self, classdef: ast.ClassDef) -> bool: ...
    def wraps_legacy_step(self, classdef: ast.ClassDef) -> str | None: ...
    def local_class(self, func: ast.AST) -> ast.ClassDef | None: ...
    def local_function(self, func: ast.AST) -> ast.FunctionDef | ast.AsyncFunctionDef | None: ...
    def call_sites(self, function: ast.AST, classdef: ast.ClassDef | None) -> list[ast.Call]: ...
    def returns_kind(self, function: ast.AST) -> EnvKind: ...
    def kind_from_qualified(self, qualified: str, call: ast.Call) -> EnvKind | None: ...
    def annotation_kind(self, annotation: ast.AST) -> EnvKind: ...
    def annotation_names_kind(self, names: set[str]) -> EnvKind: ...
    def is_self(self, name: ast.Name) -> bool: ...
    def self_attribute_values(self, attr: ast.AST, name: str) -> list[ast.expr]: ...
    def thunks_returned_kind(self, param: ast.arg) -> EnvKind: ...


class ReceiverFacade(ReceiverQueries, Protocol):
    """What the families mixed into ``Receivers`` (``receiver_classes.py``,
    ``receiver_params.py``, ``receiver_callers.py``, ``receiver_thunks.py``,
    ``receiver_origins.py``, ``receiver_foreign.py``, ``receiver_gym_only.py``) ask of the
    whole: type-checking only, each mixin derives from it under ``TYPE_CHECKING`` and from
    ``object`` at run time."""

    project: ProjectView | None
    callables: CallableKinds
    attributes: SelfAttributes

    def own_method(self, func: ast.AST) -> ast.FunctionDef | ast.AsyncFunctionDef | None: ...
    def self_attribute_values(self, attr: ast.AST, name: str) -> list[ast.expr]: ...
    def _dominating_binding(self, name: ast.Name) -> ast.AST | None: ...
    def library_made(self, expr: ast.AST) -> str | None: ...
    def _own_api_base(self, base: ast.AST) -> bool: ...
    def legacy_step_class(self, expr: ast.AST) -> str | None: ...
    def seed_holder(self, expr: ast.expr) -> str | None: ...
    def _makes_gym_wrapper(self, value: ast.expr) -> bool: ...
    def _param_kind(self, param: ast.arg) -> EnvKind: ...
    def param_kept_classes(self, param: ast.arg) -> tuple[frozenset[str], bool]: ...
    def class_keeps_legacy_step(self, classdef: ast.ClassDef, seen: frozenset[int] = frozenset()) -> bool: ...
    def annotation_kept_class(self, annotation: ast.AST) -> str | None: ...
    def own_record_wrapper(self, classdef: ast.ClassDef) -> bool: ...
    def constructions(
        self, classdef: ast.ClassDef, _seen: frozenset[int] = frozenset()
    ) -> tuple[list[tuple[ast.Call, int]], bool]: ...
