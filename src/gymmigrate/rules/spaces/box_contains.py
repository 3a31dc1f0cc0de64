"""A float32 ``Box`` whose ``contains()`` is asked of float64 observations (GM910).

``Box`` without a dtype is float32, in gym as in Gymnasium. gym <= 0.20's
``Box.contains(x)`` compared only the shape and the bounds; since gym 0.21, and in
Gymnasium 1.x, it also asks ``np.can_cast(x.dtype, box.dtype)``, which is False for a
float64 array against a float32 Box: ``assert space.contains(obs)`` that passed on an old
gym fails, and ``if space.contains(obs)`` takes the other branch.

Reported at the ``Box`` (one decision per space) where everything the module shows points
that way: the Box has no dtype, its bounds are float64 arrays (``np.array([0.5, 1.0])``,
``np.full(6, -np.inf)``, ``np.hstack`` of one), it is an attribute of a Gym env class
(class attribute, ``self.<name> = Box(...)`` or a property returning it) whose observations
are float64 arrays too, and the run calls ``contains()`` on that name. The item names
those calls. An action space is left out: its ``contains()`` checks actions, which an
agent draws in the space's own dtype. Whether the values checked are float64 is for a
person to confirm, and whether to give the Box ``dtype=np.float64`` or cast the values.
Part of ``drift.SpaceDrift``.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.env_classes import EnvClasses
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import FUNCTIONS, call_argument, own_returns
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import RuleFamily

# Spaces whose contains() checks actions (drawn in the space's own dtype), not observations.
_ACTION_SPACES = frozenset({"action_space", "single_action_space"})
# numpy constructors that make float64 arrays when given no dtype (``np.full`` only with a
# float fill value), and those whose result has the widest dtype of their inputs.
_FLOAT64_MAKERS = frozenset({"zeros", "ones", "empty", "eye", "identity"})
_RANDOM_FLOATS = frozenset({"rand", "randn", "random", "uniform", "normal", "random_sample"})
_JOINERS = frozenset({"hstack", "vstack", "concatenate", "stack", "append", "column_stack", "r_"})
_SAME_DTYPE_METHODS = frozenset({"copy", "flatten", "ravel", "reshape", "squeeze"})
_FLOAT_CONSTANTS = frozenset({"numpy.inf", "numpy.Inf", "numpy.nan", "numpy.pi", "numpy.e"})
_OBSERVATION_METHODS = ("_get_obs", "step", "reset")
_MAX_DEPTH = 6


def decide_box_contains(family: RuleFamily, call: ast.Call) -> None:
    facts = family.facts
    if call_argument(call, 3, "dtype") is not None or any(k.arg is None for k in call.keywords):
        return
    if any(isinstance(a, ast.Starred) for a in call.args):
        return
    low, high = call_argument(call, 0, "low"), call_argument(call, 1, "high")
    if low is None or high is None:
        return
    stored = _stored_as(facts, call)
    if stored is None or stored[0] in _ACTION_SPACES:
        return
    name, classdef = stored
    receivers = family.receivers
    if not (receivers.class_kind(classdef) is EnvKind.GYM_ENV or EnvClasses.of(facts, receivers).is_custom_env(classdef)):
        return
    wide = _Float64(family)
    if not (wide.array(low, 0) and wide.array(high, 0)):
        return
    observation = wide.observation(classdef)
    if observation is None:
        return
    uses = _contains_uses(family, name)
    if not uses:
        return
    shown = ", ".join(uses[:4]) + (f" (and {len(uses) - 4} more)" if len(uses) > 4 else "")
    asker = "module" if family.receivers.project is None else "run"
    family.report(
        call,
        "GM910",
        f"`{name}` is a float32 `Box` (no dtype) with float64 bounds, and `{classdef.name}`'s observations are float64 "
        f"(`{facts.segment(observation)}`, line {observation.lineno}): Gymnasium's `contains()` is False for a float64 "
        f"value (it checks that the dtype casts to the Box's; gym <= 0.20 did not), and the {asker} asks it at {shown}; give "
        "the Box dtype=np.float64, or cast what is checked",
        FixKind.FLAG,
    )


def _stored_as(facts: ModuleFacts, call: ast.Call) -> tuple[str, ast.ClassDef] | None:
    """The name a class holds the Box under: a class attribute (``HAND = Box(...)``),
    ``self.<name> = Box(...)`` in a method, or a property returning it."""
    parent = facts.parent(call)
    if isinstance(parent, ast.Assign) and parent.value is call and len(parent.targets) == 1:
        target = parent.targets[0]
        owner = facts.parent(parent)
        if isinstance(target, ast.Name) and isinstance(owner, ast.ClassDef):
            return target.id, owner
        if isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self":
            classdef = facts.enclosing_class(call)
            return (target.attr, classdef) if classdef is not None else None
        return None
    if isinstance(parent, ast.Return) and parent.value is call:
        function = facts.enclosing_function(call)
        holder = facts.parent(function) if function is not None else None
        if isinstance(function, FUNCTIONS) and isinstance(holder, ast.ClassDef) and _is_property(function):
            return function.name, holder
    return None


def _is_property(function: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    for decorator in function.decorator_list:
        name = decorator.attr if isinstance(decorator, ast.Attribute) else decorator.id if isinstance(decorator, ast.Name) else None
        if name in ("property", "cached_property"):
            return True
    return False


def _contains_uses(family: RuleFamily, name: str) -> list[str]:
    project = family.receivers.project
    if project is not None:
        return project.contains_calls(name)
    lines = []
    for call in family.facts.attribute_calls.get("contains", ()):
        receiver = call.func.value  # type: ignore[attr-defined]
        read = receiver.attr if isinstance(receiver, ast.Attribute) else receiver.id if isinstance(receiver, ast.Name) else None
        if read == name and len(call.args) == 1 and not call.keywords:
            lines.append(f"line {call.lineno}")
    return lines


class _Float64:
    """Whether an expression is certainly a NumPy array whose dtype does not cast to float32
    (float64, or wider: anything a float64 array is joined or computed with)."""

    def __init__(self, family: RuleFamily) -> None:
        self.facts = family.facts
        self.receivers = family.receivers

    def observation(self, classdef: ast.ClassDef) -> ast.expr | None:
        """An observation the class (or a class of this module it derives from) returns that
        is float64: from ``_get_obs``, ``step`` (its first value, or its only one) or
        ``reset``, following ``self.<method>()`` into the class's own methods."""
        methods: dict[str, ast.FunctionDef | ast.AsyncFunctionDef] = {}
        for current in self.receivers.local_lineage(classdef):
            for statement in current.body:
                if isinstance(statement, FUNCTIONS):
                    methods.setdefault(statement.name, statement)
        for name in _OBSERVATION_METHODS:
            function = methods.get(name)
            if function is None:
                continue
            for ret in own_returns(function):
                value = ret.value
                if isinstance(value, ast.Tuple):
                    value = value.elts[0] if name == "step" and len(value.elts) in (4, 5) else None
                found = self._returned(value, methods, 0) if value is not None else None
                if found is not None:
                    return found
        return None

    def _returned(self, value: ast.expr, methods: dict[str, ast.FunctionDef | ast.AsyncFunctionDef], depth: int) -> ast.expr | None:
        if self.array(value, 0):
            return value
        func = value.func if isinstance(value, ast.Call) else None
        if (
            depth < 2
            and isinstance(func, ast.Attribute)
            and isinstance(func.value, ast.Name)
            and func.value.id == "self"
            and func.attr in methods
        ):
            for ret in own_returns(methods[func.attr]):
                if ret.value is not None and not isinstance(ret.value, ast.Tuple):
                    found = self._returned(ret.value, methods, depth + 1)
                    if found is not None:
                        return found
        return None

    def array(self, expr: ast.AST, depth: int) -> bool:
        if depth > _MAX_DEPTH:
            return False
        if isinstance(expr, ast.Call):
            return self._call(expr, depth)
        if isinstance(expr, ast.UnaryOp) and isinstance(expr.op, (ast.USub, ast.UAdd)):
            return self.array(expr.operand, depth + 1)
        if isinstance(expr, ast.BinOp):
            # a float64 array computed with anything numeric stays float64 (or wider)
            return self.array(expr.left, depth + 1) or self.array(expr.right, depth + 1)
        if isinstance(expr, ast.Subscript):
            return self.array(expr.value, depth + 1)
        if isinstance(expr, ast.IfExp):
            return self.array(expr.body, depth + 1) and self.array(expr.orelse, depth + 1)
        if isinstance(expr, ast.Name):
            values = self._values(expr)
            return bool(values) and all(self.array(v, depth + 1) for v in values)
        if isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and expr.value.id == "self":
            values = self.receivers.self_attribute_values(expr, expr.attr)
            return bool(values) and all(self.array(v, depth + 1) for v in values)
        return False

    def _values(self, name: ast.Name) -> list[ast.expr]:
        """What every binding of ``name`` assigns; empty where one binding is no plain assignment."""
        values = []
        for binding in self.facts.bindings_of(name):
            statement = self.facts.parent(binding)
            if not (isinstance(binding, ast.Name) and isinstance(statement, ast.Assign) and statement.targets == [binding]):
                return []
            values.append(statement.value)
        return values

    def _call(self, call: ast.Call, depth: int) -> bool:
        func = call.func
        if isinstance(func, ast.Attribute) and func.attr in _SAME_DTYPE_METHODS and not self._numpy(func):
            return self.array(func.value, depth + 1)  # ``obs.copy()``, ``x.reshape(-1)``
        name = self._numpy(func)
        if name is None or any(k.arg is None for k in call.keywords):
            return False
        if any(k.arg == "dtype" for k in call.keywords):
            return False
        if name in _FLOAT64_MAKERS:
            return len(call.args) <= 1
        if name.startswith("random."):
            return name[len("random.") :] in _RANDOM_FLOATS
        if name == "full":
            fill = call_argument(call, 1, "fill_value")
            return len(call.args) <= 2 and fill is not None and self._float(fill)
        if name in ("array", "asarray"):
            if len(call.args) != 1:
                return False
            items = call.args[0]
            if isinstance(items, (ast.List, ast.Tuple)):
                return self._float_items(items, depth)
            return self.array(items, depth + 1)
        if name in _JOINERS:
            first = call.args[0] if call.args else None
            parts = first.elts if isinstance(first, (ast.List, ast.Tuple)) else list(call.args) if name == "append" else []
            return any(self.array(part, depth + 1) for part in parts)
        return False

    def _numpy(self, func: ast.AST) -> str | None:
        """``zeros`` for ``np.zeros``, ``random.uniform`` for ``np.random.uniform``; None
        for what is not a function of NumPy."""
        for qualified in self.facts.qualified_names(func):
            if qualified.startswith("numpy."):
                return qualified[len("numpy.") :]
        return None

    def _float_items(self, items: ast.List | ast.Tuple, depth: int) -> bool:
        """A list of numbers at least one of which is a float (NumPy makes float64 of it),
        or of such lists."""
        floats = False
        for item in items.elts:
            if isinstance(item, (ast.List, ast.Tuple)):
                if not self._float_items(item, depth + 1):
                    return False
                floats = True
            elif self._float(item):
                floats = True
            elif not self._number(item):
                return False
        return floats

    def _float(self, expr: ast.AST) -> bool:
        if isinstance(expr, ast.UnaryOp) and isinstance(expr.op, (ast.USub, ast.UAdd)):
            return self._float(expr.operand)
        if isinstance(expr, ast.Constant):
            return isinstance(expr.value, float)
        return bool(self.facts.qualified_names(expr) & _FLOAT_CONSTANTS)

    def _number(self, expr: ast.AST) -> bool:
        if isinstance(expr, ast.UnaryOp) and isinstance(expr.op, (ast.USub, ast.UAdd)):
            return self._number(expr.operand)
        return isinstance(expr, ast.Constant) and isinstance(expr.value, (int, float)) and not isinstance(expr.value, bool)
