"""PettingZoo receivers: is ``x`` an AEC env, a parallel env, or neither?

``Receivers.kind_of`` already knows PettingZoo's factories (``rps_v2.env()``,
``.parallel_env()``, ``.raw_env()``, ``pettingzoo.make``), its conversions, wrappers and
base classes, and SuperSuit's wrappers. This module adds the one piece of evidence that
is not about where a value comes from: ``for agent in x.agent_iter():`` only exists on
AEC envs, so an otherwise unknown ``x`` iterated that way is one (a function parameter
``env`` in a training loop, for instance).
"""

from __future__ import annotations

import ast

from gymmigrate.facts import names as N
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import ModuleFacts, full_name, is_super_call
from gymmigrate.facts.receivers import Receivers

PETTINGZOO_KINDS = (EnvKind.PZ_AEC, EnvKind.PZ_PARALLEL)


class MultiAgent:
    """PettingZoo classification for one module (``MultiAgent.of``: one per file)."""

    def __init__(self, facts: ModuleFacts, receivers: Receivers) -> None:
        self.facts = facts
        self.receivers = receivers
        # Evidence from ``x.agent_iter()``: the bindings a name read sees (shared by every
        # read that sees them), or the spelling of an attribute chain in its class.
        self._iterated_bindings: set[int] = set()
        self._iterated_attributes: set[tuple[int, str]] = set()
        for call in facts.attribute_calls.get("agent_iter", ()):
            receiver = call.func.value  # type: ignore[attr-defined]
            if isinstance(receiver, ast.Name):
                bindings = facts.bindings_of(receiver)
                if bindings:
                    self._iterated_bindings.add(id(bindings))
            elif isinstance(receiver, ast.Attribute):
                self._iterated_attributes.add(self._attribute_key(receiver))

    @classmethod
    def of(cls, facts: ModuleFacts, receivers: Receivers) -> MultiAgent:
        return facts.memo(("multi-agent", id(facts.tree)), lambda: cls(facts, receivers))

    def kind(self, expr: ast.AST) -> EnvKind | None:
        """``PZ_AEC`` or ``PZ_PARALLEL`` when ``expr`` is known to be that env, else None."""
        if self._parallel_wrapper_super(expr):
            return EnvKind.PZ_PARALLEL
        kind = self.receivers.kind_of(expr)
        if kind in PETTINGZOO_KINDS:
            return kind
        if kind is not EnvKind.UNKNOWN:
            return None
        if self._made_by_wrapper_fn(expr):
            return EnvKind.PZ_PARALLEL
        if isinstance(expr, ast.Name):
            bindings = self.facts.bindings_of(expr)
            if bindings and id(bindings) in self._iterated_bindings and not self._known_otherwise(bindings):
                return EnvKind.PZ_AEC
        elif isinstance(expr, ast.Attribute) and self._attribute_key(expr) in self._iterated_attributes:
            return EnvKind.PZ_AEC
        return None

    def _parallel_wrapper_super(self, expr: ast.AST) -> bool:
        """``super()`` in a method of a subclass of PettingZoo's ``BaseParallelWrapper``: the
        base's methods hand the wrapped parallel env's calls on (``reset`` returns its pair)."""
        if not is_super_call(expr):
            return False
        classdef = self.facts.enclosing_class(expr)
        if classdef is None or not any(isinstance(f, ast.FunctionDef | ast.AsyncFunctionDef) for f in self.facts.ancestors(expr)):
            return False
        return any(
            qualified in N.PZ_PARALLEL_BASES and qualified in N.PZ_WRAPPER_BASES
            for base in classdef.bases
            for qualified in self.facts.qualified_names(base)
        )

    def iterated(self, expr: ast.AST) -> bool:
        """``expr`` is a name some ``for agent in name.agent_iter():`` loop iterates."""
        if not isinstance(expr, ast.Name):
            return False
        bindings = self.facts.bindings_of(expr)
        return bool(bindings) and id(bindings) in self._iterated_bindings

    def _known_otherwise(self, bindings: list[ast.AST]) -> bool:
        """One binding is a Gym env or a VecEnv: ``env`` is reused for two kinds of env in this
        scope, and ``agent_iter`` only speaks for some of its values."""
        for binding in bindings:
            kind = self.receivers.binding_kind(binding)
            if kind is not None and kind not in (*PETTINGZOO_KINDS, EnvKind.UNKNOWN, EnvKind.NOT_ENV):
                return True
        return False

    def _made_by_wrapper_fn(self, expr: ast.AST, depth: int = 0) -> bool:
        """``parallel_env = parallel_wrapper_fn(env)`` at module level, then ``parallel_env()``
        (how PettingZoo's own env modules, and the custom ones copied from them, make a
        parallel env): the receiver analysis sees a call of a variable, not of a factory."""
        if depth > 3:
            return False
        if isinstance(expr, ast.Name):
            values = [parent.value for b in self.facts.bindings_of(expr)
                      if isinstance(parent := self.facts.parent(b), ast.Assign)]
            return bool(values) and all(self._made_by_wrapper_fn(v, depth + 1) for v in values)
        if not (isinstance(expr, ast.Call) and isinstance(expr.func, ast.Name)):
            return False
        for binding in self.facts.bindings_of(expr.func):
            assign = self.facts.parent(binding)
            if isinstance(assign, ast.Assign) and isinstance(assign.value, ast.Call):
                if any(q.endswith(".parallel_wrapper_fn") for q in self.facts.qualified_names(assign.value.func)):
                    return True
        return False

    def class_kind(self, classdef: ast.ClassDef) -> EnvKind | None:
        """The PettingZoo kind of a class defined here (from its bases), or None."""
        kind = self.receivers.class_kind(classdef)
        return kind if kind in PETTINGZOO_KINDS else None

    def _attribute_key(self, attr: ast.Attribute) -> tuple[int, str]:
        classdef = self.facts.enclosing_class(attr)
        return (id(classdef) if classdef is not None else 0, full_name(attr) or "")
