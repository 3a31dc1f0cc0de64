"""What the wrapper rules share: the catalog entries, syntax tests on the original
``ast`` (what an override delegates to, its simple statements and the names they bind) and
the LibCST tuple builders."""

from __future__ import annotations

import ast
from collections.abc import Iterator, Sequence

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.module import FUNCTIONS, is_super_call, walk
from gymmigrate.facts.receiver_classes import duck_wrapper_attribute
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import Rule

RULES = (
    Rule(
        "GM601",
        "wrapper reset returns (obs, info)",
        FixKind.ASSIST,
        "A wrapper's `reset` override returns `(obs, info)`; pass-throughs stay.",
    ),
    Rule(
        "GM602",
        "wrapper step returns five values",
        FixKind.AUTO,
        "A wrapper's `step` override returns `(obs, reward, terminated, truncated, info)`.",
    ),
    Rule(
        "GM603",
        "wrapper __init__ without super().__init__",
        FixKind.FLAG,
        "A wrapper whose `__init__` never calls `super().__init__(env)` is reported.",
    ),
    Rule(
        "GM618",
        "subclasses of rewritten Gym wrappers",
        FixKind.ASSIST,
        "A subclass of `RecordEpisodeStatistics`/`NormalizeReward`/`NormalizeObservation` reading state 1.x no longer keeps (`num_envs`, `t0`...) is reported; "
        "a `RecordEpisodeStatistics` subclass whose `step` computes the statistics itself gets gym 0.26's `__init__`/`reset` state back.",
    ),
)

# Gym 0.26 wrappers whose Gymnasium 1.x versions are single-env rewrites (the vector ones
# moved to ``gymnasium.wrappers.vector``): state a subclass may read that is gone.
GONE_WRAPPER_STATE: dict[str, frozenset[str]] = {
    "RecordEpisodeStatistics": frozenset({"num_envs", "is_vector_env", "t0"}),
    "NormalizeReward": frozenset({"num_envs", "is_vector_env", "returns"}),
    "NormalizeObservation": frozenset({"num_envs", "is_vector_env"}),
}



# What a wrapper delegates to when the class keeps no other name for it.
INNER = ("env",)


def _is_inner_env(node: ast.expr, inner: Sequence[str] = INNER) -> bool:
    """``self.env`` (or another attribute in ``inner``, ``inner_env_names``) or ``super()`` /
    ``super(Cls, self)``: what an override delegates to."""
    if isinstance(node, ast.Attribute):
        return isinstance(node.value, ast.Name) and node.value.id == "self" and node.attr in inner
    return is_super_call(node)


def _inner_call(
    node: ast.AST | None, method: str, inner: Sequence[str] = INNER, bases: Sequence[ast.expr] = ()
) -> ast.Call | None:
    """``node`` if it is ``self.env.<method>(...)`` or ``super().<method>(...)``, or
    ``Base.<method>(self, ...)`` naming one of the class's ``bases``: the wrapper's base
    class, whose method reaches the wrapped env as ``super()`` does."""
    if (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and node.func.attr == method
        and (_is_inner_env(node.func.value, inner) or is_base_call(node, bases))
    ):
        return node
    return None


def is_base_call(call: ast.Call, bases: Sequence[ast.expr]) -> bool:
    """``Base.method(self, ...)`` naming one of ``bases`` as the class statement spells it."""
    receiver = call.func.value if isinstance(call.func, ast.Attribute) else None
    if not isinstance(receiver, (ast.Name, ast.Attribute)) or not call.args:
        return False
    first = call.args[0]
    text = ast.dump(receiver)
    return isinstance(first, ast.Name) and first.id == "self" and any(ast.dump(base) == text for base in bases)


def arguments_of(call: ast.Call, bases: Sequence[ast.expr]) -> list[ast.expr]:
    """The arguments a call hands the method, the instance of ``Base.method(self, ...)`` aside."""
    return call.args[1:] if is_base_call(call, bases) else call.args


def _inner_calls(root: ast.AST, method: str, inner: Sequence[str] = INNER, bases: Sequence[ast.expr] = ()) -> list[ast.Call]:
    """Inner ``method`` calls under ``root``, not inside lambdas, in source order."""
    found: list[ast.Call] = []
    stack = [root]
    while stack:
        node = stack.pop()
        if isinstance(node, ast.Lambda):
            continue
        call = _inner_call(node, method, inner, bases)  # ``node`` itself, as a Call
        if call is not None:
            found.append(call)
        stack.extend(ast.iter_child_nodes(node))
    found.sort(key=lambda call: (call.lineno, call.col_offset))
    return found


def inner_env_names(classdef: ast.ClassDef) -> tuple[str, ...]:
    """``env`` and the attributes a wrapper keeps the same inner env in: ``self._env = env``
    in an ``__init__`` that hands that very parameter (never rebound) to
    ``super().__init__``, or ``self._env = self.env``, where no other line of the class
    stores the attribute. A reset delegating through such a name delegates to the inner env."""
    held = duck_wrapper_attribute(classdef)
    if held is not None:
        return (*INNER, held)  # a plain class holds what it wraps in an attribute of its own
    init = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "__init__"), None)
    if init is None:
        return INNER
    params = [a.arg for a in (*init.args.posonlyargs, *init.args.args)][1:]
    handed: set[str] = set()
    rebound: set[str] = set()
    for node in walk(init):
        if (
            isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "__init__"
            and is_super_call(node.func.value)
        ):
            first = node.args[0] if node.args else next((k.value for k in node.keywords if k.arg == "env"), None)
            if isinstance(first, ast.Name) and first.id in params:
                handed.add(first.id)
        elif isinstance(node, ast.Name) and isinstance(node.ctx, (ast.Store, ast.Del)):
            rebound.add(node.id)
    handed -= rebound
    in_init = {id(node) for node in walk(init)}
    stores: dict[str, list[ast.expr | None]] = {}
    for node in walk(classdef):
        targets: list[ast.expr] = []
        value: ast.expr | None = None
        if isinstance(node, ast.Assign):
            targets, value = node.targets, node.value
        elif isinstance(node, (ast.AnnAssign, ast.AugAssign)):
            targets, value = [node.target], None
        for target in targets:
            if isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self":
                # a parameter's name means that parameter only in ``__init__`` itself
                kept = value if len(targets) == 1 and (id(node) in in_init or not isinstance(value, ast.Name)) else None
                stores.setdefault(target.attr, []).append(kept)
    names = list(INNER)
    for attr, values in stores.items():
        if attr in INNER:
            continue
        if values and all(
            (isinstance(v, ast.Name) and v.id in handed) or (isinstance(v, ast.Attribute) and _is_inner_env(v))
            for v in values
        ):
            names.append(attr)
    return tuple(names)


def _statements(body: list[ast.stmt]) -> Iterator[ast.stmt]:
    """Simple statements of a function body, in order, not entering nested definitions."""
    for statement in body:
        if isinstance(statement, (*FUNCTIONS, ast.ClassDef)):
            continue
        blocks = [getattr(statement, field, None) for field in ("body", "orelse", "finalbody")]
        blocks += [handler.body for handler in getattr(statement, "handlers", ())]
        blocks += [case.body for case in getattr(statement, "cases", ())]
        suites = [block for block in blocks if isinstance(block, list)]
        if not suites:
            yield statement
        for suite in suites:
            yield from _statements(suite)


def _single_assign(statement: ast.stmt) -> ast.Assign | None:
    if isinstance(statement, ast.Assign) and len(statement.targets) == 1:
        return statement
    return None


def _target_names(target: ast.expr) -> list[str] | None:
    """``a, b, _`` -> ["a", "b", "_"]; None when an element is not a plain name."""
    if not isinstance(target, (ast.Tuple, ast.List)):
        return None
    names = [element.id for element in target.elts if isinstance(element, ast.Name)]
    return names if len(names) == len(target.elts) else None


def _assigned_names(statement: ast.stmt) -> set[str]:
    targets: list[ast.expr] = []
    if isinstance(statement, ast.Assign):
        targets = statement.targets
    elif isinstance(statement, ast.AnnAssign) and statement.value is not None:
        targets = [statement.target]
    names: set[str] = set()
    for target in targets:
        if isinstance(target, ast.Name):
            names.add(target.id)
        else:
            names.update(_target_names(target) or ())
    return names


def _names_in(function: ast.AST) -> set[str]:
    """Every name a function binds or reads (parameters included): fresh names avoid them."""
    names: set[str] = {function.name} if isinstance(function, FUNCTIONS) else set()
    for node in walk(function):
        if isinstance(node, ast.Name):
            names.add(node.id)
        elif isinstance(node, ast.arg):
            names.add(node.arg)
    return names


def _fresh(base: str, taken: set[str]) -> str:
    name = base
    while name in taken:
        name += "_"
    taken.add(name)
    return name


def _tuple(elements: Sequence[cst.BaseExpression], like: cst.Tuple | None = None) -> cst.Tuple:
    """A tuple with ``, `` separators, keeping the parentheses of ``like`` if it had any."""
    items = [
        cst.Element(value=e, comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" ")))
        for e in elements[:-1]
    ] + [cst.Element(value=elements[-1])]
    if like is not None:
        return like.with_changes(elements=items)
    return cst.Tuple(elements=items, lpar=[], rpar=[])


def _parenthesized(expr: cst.BaseExpression) -> cst.BaseExpression:
    if isinstance(expr, (cst.BooleanOperation, cst.IfExp, cst.Lambda, cst.NamedExpr, cst.Tuple)) and not expr.lpar:
        return expr.with_changes(lpar=[cst.LeftParen()], rpar=[cst.RightParen()])
    return expr
