"""What an expression is to the space drift rules: a space of which class, or a space's
``n``/``start``/``sample()``/``spaces`` (GM903, GM905, GM909, GM910).

Read from the module alone: a constructor call, ``self.action_space`` where every store
of it is one, a name every binding of which is one, or a name an enclosing ``if
isinstance(name, spaces.X):`` narrows. ``UNKNOWN`` is a space of a class not known here
(``env.action_space``).
"""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.narrowing import isinstance_guards
from gymmigrate.facts.receivers import Receivers

SPACE_ATTRIBUTES = frozenset({"action_space", "observation_space", "single_action_space", "single_observation_space"})
SPACE_INT_ATTRIBUTES = frozenset({"n", "start"})
UNKNOWN = "?"  # a space of a class not known here
# What a list has and a tuple has not: each changes a list in place and raises on a tuple
# (a Tuple space's members, or a list of spaces that should become a Tuple space).
LIST_MUTATORS = frozenset({"append", "extend", "insert", "remove", "pop", "sort", "reverse", "clear"})
# A narrowing check holds up to the def or class around the name.
_NARROWING_ENDS = (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.Module)


def space_class_of(qualified: set[str]) -> str | None:
    """The class of gym's (or Gymnasium's) spaces among qualified names: ``Box`` for
    ``gym.spaces.Box``, else None."""
    for q in qualified:
        rest = N.strip_gym_prefix(q)
        if rest is not None and rest.startswith("spaces.") and rest.rsplit(".", 1)[-1][:1].isupper():
            return rest.rsplit(".", 1)[-1]
    return None


class SpaceValues:
    """The space classes of one module's expressions."""

    def __init__(self, facts: ModuleFacts, receivers: Receivers) -> None:
        self.facts = facts
        self.receivers = receivers

    def space_class(self, expr: ast.AST, depth: int = 0) -> str | None:
        """The space class of ``expr`` (``"Box"``), ``UNKNOWN`` for a space of a class not
        known here (``env.action_space``), None for what is not known to be a space."""
        if isinstance(expr, ast.Call):
            return space_class_of(self.facts.qualified_names(expr.func))
        if isinstance(expr, ast.Attribute) and expr.attr in SPACE_ATTRIBUTES:
            if isinstance(expr.value, ast.Name) and self.receivers.is_self(expr.value):
                values = self.receivers.self_attribute_values(expr, expr.attr)
                found = {self.space_class(v, depth + 1) if isinstance(v, ast.Call) else None for v in values}
                if len(found) == 1 and None not in found:
                    return found.pop()
            return UNKNOWN
        if isinstance(expr, ast.Name) and depth == 0:
            narrowed = self._narrowed(expr)
            if narrowed is not None:
                return narrowed
            values = self.values(expr)
            found = {self.space_class(v, depth + 1) for v in values} if values else {None}
            return found.pop() if len(found) == 1 else (UNKNOWN if None not in found else None)
        return None

    def narrowed(self, expr: ast.AST) -> str | None:
        """The space class an enclosing isinstance check proves for a name, else None."""
        return self._narrowed(expr) if isinstance(expr, ast.Name) else None

    def _narrowed(self, name: ast.Name) -> str | None:
        """The space class an enclosing ``if isinstance(name, spaces.X):`` proves (a helper
        that walks a space of any class: ``def f(space): if isinstance(space, Dict): ...``)."""
        for guard, tested, classes in isinstance_guards(self.facts, name, _NARROWING_ENDS):
            if tested == name.id and not isinstance(classes, ast.Tuple):
                if any(self._inside(binding, guard) for binding in self.facts.bindings_of(name)):
                    return None  # rebound under the check
                return space_class_of(self.facts.qualified_names(classes))
        return None

    def _inside(self, node: ast.AST, ancestor: ast.AST) -> bool:
        current: ast.AST | None = node
        while current is not None:
            if current is ancestor:
                return True
            current = self.facts.parent(current)
        return False

    def values(self, name: ast.Name) -> list[ast.expr]:
        """What every binding of ``name`` assigns (empty when one is not a plain assignment)."""
        return self.facts.assigned_values(name) or []

    def space_value(self, expr: ast.AST, what: frozenset[str], depth: int = 0) -> str | None:
        """For ``<space>.n`` / ``<space>.sample()`` (the members in ``what``: "n", "start",
        "sample", "spaces"), or a name every binding of which is one: the space's class."""
        if isinstance(expr, ast.Attribute) and expr.attr in what and expr.attr != "sample":
            return self.space_class(expr.value)
        if (
            isinstance(expr, ast.Call)
            and "sample" in what
            and isinstance(expr.func, ast.Attribute)
            and expr.func.attr == "sample"
        ):
            return self.space_class(expr.func.value)
        if isinstance(expr, ast.Name) and depth == 0:
            values = self.values(expr)
            found = {self.space_value(v, what, depth + 1) for v in values} if values else {None}
            if None in found:
                return None
            return found.pop() if len(found) == 1 else UNKNOWN
        return None
