"""Sizes and bounds Gymnasium 1.x rejects (GM909).

``MultiBinary(0)`` and ``Discrete(0)`` raise ValueError in Gymnasium 1.x (gym 0.21 built
them), ``Discrete(<float>)`` TypeError: reported, since what an empty space should become
is the env's choice; but a ``MultiBinary(n)`` whose int size can be 0 gets an empty
``Box(0, 1, (0,), "int8")`` for 0, the empty space with gym's shape, dtype, sample and
flattening. ``Box(0, 255, dtype=np.int8)`` (a literal bound outside an integer dtype's
range) raises ValueError too (gym cast the bound): reported. Part of ``drift.SpaceDrift``.
"""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import ModuleFacts
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.base import RuleFamily
from gymmigrate.rules.spaces.values import SpaceValues, space_class_of

_INT_RANGES = {
    "int8": (-(2**7), 2**7 - 1),
    "uint8": (0, 2**8 - 1),
    "int16": (-(2**15), 2**15 - 1),
    "uint16": (0, 2**16 - 1),
    "int32": (-(2**31), 2**31 - 1),
    "uint32": (0, 2**32 - 1),
    "int64": (-(2**63), 2**63 - 1),
    "uint64": (0, 2**64 - 1),
}


def _argument(call: ast.Call, position: int, name: str) -> ast.expr | None:
    for kw in call.keywords:
        if kw.arg == name:
            return kw.value
    if any(isinstance(a, ast.Starred) for a in call.args[: position + 1]):
        return None
    return call.args[position] if position < len(call.args) else None


def _number(expr: ast.AST | None) -> float | None:
    """A literal int or float (``255``, ``-1``, ``255.0``), else None."""
    sign = 1
    if isinstance(expr, ast.UnaryOp) and isinstance(expr.op, (ast.USub, ast.UAdd)):
        sign = -1 if isinstance(expr.op, ast.USub) else 1
        expr = expr.operand
    if isinstance(expr, ast.Constant) and isinstance(expr.value, (int, float)) and not isinstance(expr.value, bool):
        return sign * expr.value
    return None


def _wrapped(value: int, limits: tuple[int, int]) -> int:
    """``value`` cast into an integer dtype of range ``limits``, as NumPy wraps it."""
    low, high = limits
    return (value - low) % (high - low + 1) + low


def _legacy_cast(call: ast.Call, name: str, bound: float, limits: tuple[int, int]) -> str:
    """What gym 0.26's Box made of the bound: an integer bound wrapped into the dtype; where
    the other bound is known too and the wrapped bounds cross, a space no value is in. Said
    so that the item shows why no Gymnasium space reproduces it (1.x also rejects low > high)."""
    if not float(bound).is_integer():
        return f"gym cast it into the dtype, so the legacy space's {name} was not {bound:g}"
    wrapped = _wrapped(int(bound), limits)
    text = f"gym cast it into the dtype: the legacy space's {name} was {wrapped}"
    other_name = "high" if name == "low" else "low"
    other = _number(_argument(call, 1 if other_name == "high" else 0, other_name))
    if other is not None and float(other).is_integer():
        low, high = (wrapped, _wrapped(int(other), limits)) if name == "low" else (_wrapped(int(other), limits), wrapped)
        if low > high:
            return (
                f"gym cast it into the dtype: the legacy space had low {low} above high {high}, so contains() was False "
                "for every value, which no Gymnasium space reproduces"
            )
    return text


def decide_size(family: RuleFamily, spaces: SpaceValues, call: ast.Call, name: str) -> None:
    """``MultiBinary(n)`` / ``Discrete(n)`` with a size Gymnasium 1.x rejects."""
    size = call.args[0] if call.args and not isinstance(call.args[0], ast.Starred) else next((k.value for k in call.keywords if k.arg == "n"), None)
    if size is None:
        return
    parent = family.facts.parent(call)
    if isinstance(parent, ast.IfExp) and parent.body is call and ast.dump(parent.test) == ast.dump(size):
        return  # ``MultiBinary(n) if n else ...``: the size is tested already
    box = _box_beside(family.facts, call) if name == "MultiBinary" else None
    # A size from a parameter counts only in a module still on legacy gym, whose callers
    # may pass the 0 gym accepted; code already written for Gymnasium chose its sizes.
    from_legacy_parameter = family.context.profile.imports_gym and _from_parameter(family, size)
    if box is not None and _pure(size) and _int_size(family, size) and (_may_be_zero(spaces, size) or from_legacy_parameter):
        # gym built an empty MultiBinary for n=0; an empty int8 Box is the space Gymnasium
        # builds with its shape, dtype, sample and flattening: it stands in for n=0 only.
        text = family.facts.segment(size)
        family.report(
            call,
            "GM909",
            f"`MultiBinary(0)` raises ValueError in Gymnasium 1.x (gym built an empty space), and `{text}` can be 0: "
            f'an empty `Box(0, 1, (0,), "int8")` stands in for it then (its `contains()` takes integer arrays only)',
            FixKind.ASSIST,
            tier=Tier.NOTE,
        )
        family.plan.replace(call, _empty_box_when_zero(box))
        return
    if _may_be_zero(spaces, size):
        text = family.facts.segment(size)
        where = "" if isinstance(size, ast.Constant) else f": `{text}` can be 0 here"
        family.report(
            call,
            "GM909",
            f"`{name}` with n=0 raises ValueError in Gymnasium 1.x (gym built an empty space){where}; leave the space "
            "out (or use a Box of shape (0,)) when the feature is off",
            FixKind.FLAG,
        )
    elif name == "Discrete" and _is_float(size):
        family.report(call, "GM909", f"`Discrete(n)` needs an integer in Gymnasium 1.x (a float raises TypeError): `{family.facts.segment(size)}` is a float; use `//` or int()", FixKind.FLAG)


def decide_box_bounds(family: RuleFamily, call: ast.Call) -> bool:
    """``Box(0, 255, dtype=np.int8)``: gym cast the bound into the dtype (255 wrapped to -1);
    Gymnasium 1.x raises ValueError for a bound outside an integer dtype's range. True when
    reported."""
    dtype = _argument(call, 3, "dtype")
    dtype_name = _dtype_name(family.facts, dtype) if dtype is not None else None
    limits = _INT_RANGES.get(dtype_name) if dtype_name is not None else None
    if limits is None:
        return False
    if dtype_name == "int8" and isinstance(dtype, (ast.Attribute, ast.Constant)) and _pixel_bounds(call):
        # 0..255 is exactly uint8's range and no other dtype's: the pixels it was written for.
        # gym's space held no value (255 wrapped to -1), so no Gymnasium space keeps that;
        # the samples change from all zeros to 0..255, which the item says.
        family.report(
            call,
            "GM909",
            "`Box(0, 255)` with int8 raises ValueError in Gymnasium 1.x (int8 holds -128..127; gym wrapped 255 to -1, "
            "a space no value was in, whose `sample()` gave zeros): dtype -> uint8, the dtype 0..255 was written for; "
            "its samples now span 0..255",
            FixKind.ASSIST,
        )
        family.plan.replace(dtype, _to_uint8)
        return True
    for position, name in ((0, "low"), (1, "high")):
        bound = _number(_argument(call, position, name))
        if bound is None or limits[0] <= bound <= limits[1]:
            continue
        family.report(
            call,
            "GM909",
            f"`Box` {name}={bound:g} is outside the range of {dtype_name} ({limits[0]}..{limits[1]}): Gymnasium 1.x "
            f"raises ValueError ({_legacy_cast(call, name, bound, limits)}); use the "
            "dtype the bounds were meant for (`np.uint8` for 0..255 pixels) or bounds the dtype holds",
            FixKind.FLAG,
        )
        return True
    return False


def _pixel_bounds(call: ast.Call) -> bool:
    """Literal bounds 0 and 255: the pixel range."""
    return _number(_argument(call, 0, "low")) == 0 and _number(_argument(call, 1, "high")) == 255


def _to_uint8(node: cst.BaseExpression) -> cst.BaseExpression:
    """``np.int8`` -> ``np.uint8``, ``"int8"`` -> ``"uint8"``, spelled as written."""
    if isinstance(node, cst.Attribute):
        return node.with_changes(attr=cst.Name("uint8"))
    if isinstance(node, cst.SimpleString):
        return node.with_changes(value=node.value.replace("int8", "uint8", 1))
    return node


def _dtype_name(facts: ModuleFacts, dtype: ast.AST) -> str | None:
    if isinstance(dtype, ast.Constant) and isinstance(dtype.value, str):
        return dtype.value
    for q in facts.qualified_names(dtype):
        if q.startswith("numpy."):
            return q.rsplit(".", 1)[-1]
    return None


def _box_beside(facts: ModuleFacts, call: ast.Call) -> str | None:
    """How ``Box`` is spelled beside this ``MultiBinary``: ``spaces.Box`` for
    ``spaces.MultiBinary``, ``Box`` where the module imports it from the spaces; else None."""
    if isinstance(call.func, ast.Attribute):
        return f"{facts.segment(call.func.value)}.Box" if "\n" not in facts.segment(call.func.value) else None
    for binding in facts.module_scope.bindings.get("Box", ()):
        if isinstance(binding, ast.alias) and space_class_of({facts.imports.get(binding, "")}) == "Box":
            return "Box"
    return None


def _int_size(family: RuleFamily, expr: ast.AST, depth: int = 0) -> bool:
    """``expr`` is an int wherever it comes from: an int literal, a conditional of ints, a
    parameter annotated ``int`` or defaulting to an int, a name or ``self`` attribute every
    assignment of which is one of these."""
    if depth > 3:
        return False
    if isinstance(expr, ast.Constant):
        return isinstance(expr.value, int) and not isinstance(expr.value, bool)
    if isinstance(expr, ast.IfExp):
        return _int_size(family, expr.body, depth + 1) and _int_size(family, expr.orelse, depth + 1)
    if isinstance(expr, ast.Call) and isinstance(expr.func, ast.Name) and expr.func.id in ("int", "len"):
        return not family.facts.bindings_of(expr.func)
    values: list[ast.AST] = []
    if isinstance(expr, ast.Name):
        bindings = family.facts.bindings_of(expr)
        if not bindings:
            return False
        for binding in bindings:
            if isinstance(binding, ast.arg):
                if not _int_parameter(binding, family.facts):
                    return False
                continue
            statement = family.facts.parent(binding)
            if not (isinstance(binding, ast.Name) and isinstance(statement, ast.Assign) and binding in statement.targets):
                return False
            values.append(statement.value)
    elif isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and family.receivers.is_self(expr.value):
        values = list(family.receivers.self_attribute_values(expr, expr.attr))
        if not values:
            return False
    else:
        return False
    return all(_int_size(family, v, depth + 1) for v in values)


def _from_parameter(family: RuleFamily, expr: ast.AST) -> bool:
    """``n`` or ``self.n`` bound from a parameter: the caller chooses the size, 0 too."""
    if isinstance(expr, ast.Name):
        return any(isinstance(b, ast.arg) for b in family.facts.bindings_of(expr))
    if isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and family.receivers.is_self(expr.value):
        return any(
            isinstance(v, ast.Name) and any(isinstance(b, ast.arg) for b in family.facts.bindings_of(v))
            for v in family.receivers.self_attribute_values(expr, expr.attr)
        )
    return False


def _may_be_zero(spaces: SpaceValues, expr: ast.AST, depth: int = 0) -> bool:
    if isinstance(expr, ast.Constant):
        return expr.value == 0 and not isinstance(expr.value, bool) and isinstance(expr.value, int)
    if isinstance(expr, (ast.List, ast.Tuple)):
        return any(_may_be_zero(spaces, e, depth) for e in expr.elts)
    if isinstance(expr, ast.IfExp):
        return _may_be_zero(spaces, expr.body, depth) or _may_be_zero(spaces, expr.orelse, depth)
    if isinstance(expr, ast.Name) and depth == 0:
        return any(_may_be_zero(spaces, v, depth + 1) for v in spaces.values(expr))
    return False


def _is_float(expr: ast.AST) -> bool:
    return (isinstance(expr, ast.BinOp) and isinstance(expr.op, ast.Div)) or (isinstance(expr, ast.Constant) and isinstance(expr.value, float))


def _pure(expr: ast.AST) -> bool:
    """A name or an attribute chain of one (``n``, ``self.n``): read twice, the same value."""
    while isinstance(expr, ast.Attribute):
        expr = expr.value
    return isinstance(expr, ast.Name)


def _int_parameter(arg: ast.arg, facts: ModuleFacts) -> bool:
    """A parameter annotated ``int`` or whose default is an int literal."""
    if isinstance(arg.annotation, ast.Name) and arg.annotation.id == "int":
        return True
    function = facts.parent(arg)
    while function is not None and not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
        function = facts.parent(function)
    if function is None:
        return False
    args = function.args
    positional = [*args.posonlyargs, *args.args]
    defaults: dict[int, ast.expr | None] = {id(a): d for a, d in zip(positional[len(positional) - len(args.defaults) :], args.defaults)}
    defaults.update({id(a): d for a, d in zip(args.kwonlyargs, args.kw_defaults)})
    default = defaults.get(id(arg))
    return isinstance(default, ast.Constant) and isinstance(default.value, int) and not isinstance(default.value, bool)


def _empty_box_when_zero(box: str):
    """``spaces.MultiBinary(n)`` -> ``(spaces.MultiBinary(n) if n else spaces.Box(0, 1, (0,), "int8"))``."""

    def build(node: cst.BaseExpression) -> cst.BaseExpression:
        assert isinstance(node, cst.Call)
        size = next((a.value for a in node.args if a.keyword is None or a.keyword.value == "n"), None)
        assert size is not None
        empty = cst.parse_expression('Box(0, 1, (0,), "int8")')
        assert isinstance(empty, cst.Call)
        if isinstance(node.func, cst.Attribute):
            empty = empty.with_changes(func=node.func.with_changes(attr=cst.Name("Box")))  # the same module as changed
        else:
            empty = empty.with_changes(func=cst.Name(box))
        return cst.IfExp(
            test=size.deep_clone(),
            body=node,
            orelse=empty,
            lpar=[cst.LeftParen()],
            rpar=[cst.RightParen()],
        )

    return build
