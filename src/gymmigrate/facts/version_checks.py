"""Which branch of a ``gym.__version__`` check runs once ``gym`` is Gymnasium 1.x.

After the import rewrite ``gym.__version__`` is Gymnasium's ("1.4.0"), so a comparison with
a 0.x literal gives the same answer on every Gymnasium 1.x release: ``gym.__version__ >=
"0.26.0"`` (as strings, "1..." sorts after "0..."), ``version.parse(gym.__version__) <
version.parse("0.24")``, or a helper of this module that compares the parsed version with
its parameter (``def ge(v): return parse(gym.__version__) >= parse(v)``) called with a 0.x
literal. The other branch never runs: code there is neither rewritten nor reported (GM108
reports the check). A 1.x literal may answer differently on another release: unsettled.
"""

from __future__ import annotations

import ast

from gymmigrate.facts.module import FUNCTIONS, ModuleFacts, walk
from gymmigrate.facts.self_attributes import self_stores

GYMNASIUM_RELEASE = (1, 4, 0)  # the release the migration targets (rules.gymnasium_api.GYMNASIUM_VERSION)

# Names a version parse may call: each keeps the order of releases.
_PARSERS = frozenset({"parse", "Version", "LooseVersion", "StrictVersion", "parse_version", "int", "tuple", "list", "map", "str"})
_COMPARE = {
    ast.Lt: lambda a, b: a < b,
    ast.LtE: lambda a, b: a <= b,
    ast.Gt: lambda a, b: a > b,
    ast.GtE: lambda a, b: a >= b,
    ast.Eq: lambda a, b: a == b,
    ast.NotEq: lambda a, b: a != b,
}
_MIRRORED: dict[type, type] = {ast.Lt: ast.Gt, ast.LtE: ast.GtE, ast.Gt: ast.Lt, ast.GtE: ast.LtE, ast.Eq: ast.Eq, ast.NotEq: ast.NotEq}


def gym_module_names(facts: ModuleFacts) -> frozenset[str]:
    """Names this module binds to the gym (or gymnasium) package itself. A name bound to
    both (``try: import gymnasium as gym / except ImportError: import gym``) is left out:
    the fallback stays, so the name may still be legacy gym at run time."""

    def compute() -> frozenset[str]:
        bound: dict[str, set[str]] = {}
        for alias, qualified in facts.imports.items():
            bound.setdefault(alias.asname or alias.name.split(".", 1)[0], set()).add(qualified)
        return frozenset(name for name, packages in bound.items() if len(packages) == 1 and packages <= {"gym", "gymnasium"})

    return facts.memo(("gym-module-names", 0), compute)


def settled_test(test: ast.AST, facts: ModuleFacts) -> bool | None:
    """The value of the ``if`` test ``test`` on every Gymnasium 1.x run, or None."""
    names = gym_module_names(facts)
    if not names or "__version__" not in facts.text:
        return None
    return _value(test, facts, names)


def dead_version_branch(node: ast.AST, facts: ModuleFacts) -> ast.If | ast.IfExp | None:
    """The settled version check (``settled_test``) whose branch that never runs holds ``node``."""
    if "__version__" not in facts.text:
        return None
    child = node
    for ancestor in facts.ancestors(node):
        if isinstance(ancestor, (ast.If, ast.IfExp)) and child is not ancestor.test:
            value = settled_test(ancestor.test, facts)
            if value is not None:
                body = ancestor.body if isinstance(ancestor, ast.If) else [ancestor.body]
                in_body = any(child is statement for statement in body)
                if in_body is not value:
                    return ancestor
        child = ancestor
    return None


def _value(test: ast.AST, facts: ModuleFacts, names: frozenset[str]) -> bool | None:
    if isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not):
        inner = _value(test.operand, facts, names)
        return None if inner is None else not inner
    if isinstance(test, ast.BoolOp):
        values = [_value(v, facts, names) for v in test.values]
        decisive = isinstance(test.op, ast.Or)  # ``or``: one True settles it; ``and``: one False
        if decisive in values:
            return decisive
        return None if None in values else not decisive
    if isinstance(test, ast.Compare) and len(test.ops) == 1:
        return _compare(test.left, test.ops[0], test.comparators[0], names, None)
    stored = _stored_flag(test, facts)
    if stored:
        answers = {_value(value, facts, names) for value in stored}
        return answers.pop() if len(answers) == 1 else None
    if isinstance(test, ast.Call) and isinstance(test.func, ast.Name) and len(test.args) == 1 and not test.keywords:
        literal = _constant_of(test.args[0], facts)
        helper = _helper(test.func.id, facts)
        if helper is not None and isinstance(literal, ast.Constant) and isinstance(literal.value, str):
            function, compare, parameter = helper
            release = _release(literal.value)
            if release is None:
                return None
            return _compare(compare.left, compare.ops[0], compare.comparators[0], names, (parameter, release))
    return None


def _stored_flag(test: ast.AST, facts: ModuleFacts) -> list[ast.expr]:
    """``if self._legacy_api:`` where every store of ``self._legacy_api`` in this module is a
    plain assignment in the class of the read (``self._legacy_api = parse(gym.__version__) <
    parse("0.25")`` in ``__init__``): the values stored, else []. A stored value that is
    itself a flag is not followed (no chains, no loops)."""
    if not (isinstance(test, ast.Attribute) and isinstance(test.ctx, ast.Load) and isinstance(test.value, ast.Name) and test.value.id == "self"):
        return []
    classdef = facts.enclosing_class(test)
    if classdef is None:
        return []
    for attr in facts.attributes.get(test.attr, ()):
        if isinstance(attr.ctx, (ast.Store, ast.Del)) and facts.enclosing_class(attr) is not classdef:
            return []  # another class of the module stores it too
    stored = self_stores(facts, classdef, test.attr)
    if not stored or any(isinstance(value, (ast.Attribute, ast.Name)) for value in stored):
        return []
    return stored


def _helper(name: str, facts: ModuleFacts) -> tuple[ast.AST, ast.Compare, str] | None:
    """A module-level ``def name(p): return <compare of the parsed version with parsed p>``."""
    for statement in facts.tree.body:
        if isinstance(statement, FUNCTIONS) and statement.name == name:
            arguments = statement.args
            if len(arguments.args) != 1 or arguments.vararg or arguments.kwarg or arguments.kwonlyargs:
                return None
            body = [s for s in statement.body if not (isinstance(s, ast.Expr) and isinstance(s.value, ast.Constant))]
            if len(body) == 1 and isinstance(body[0], ast.Return) and isinstance(body[0].value, ast.Compare):
                compare = body[0].value
                if len(compare.ops) == 1:
                    return statement, compare, arguments.args[0].arg
            staged = _staged_compare(body, facts)
            return None if staged is None else (statement, staged, arguments.args[0].arg)
    return None


# ``operator.ge(a, b)`` and its kin, as the comparison they make.
_OPERATOR_COMPARES: dict[str, type[ast.cmpop]] = {"lt": ast.Lt, "le": ast.LtE, "gt": ast.Gt, "ge": ast.GtE, "eq": ast.Eq, "ne": ast.NotEq}


def _staged_compare(body: list[ast.stmt], facts: ModuleFacts) -> ast.Compare | None:
    """A helper that parses in steps: ``mine = gym.__version__.split(".")``, ``theirs =
    other.split(".")``, loops that only turn items into numbers (``mine[i] = int(mine[i])``,
    in a try), then ``return mine >= theirs`` or ``return operator.ge(mine, theirs)``. Both
    sides go through the same steps, so the comparison is the one of their assigned values
    (a Compare built from them, for ``_compare``); None for any other shape."""
    if len(body) < 3 or not isinstance(body[-1], ast.Return):
        return None
    returned = body[-1].value
    if isinstance(returned, ast.Compare) and len(returned.ops) == 1:
        left, op, right = returned.left, returned.ops[0], returned.comparators[0]
    elif (
        isinstance(returned, ast.Call)
        and isinstance(returned.func, ast.Attribute)
        and isinstance(returned.func.value, ast.Name)
        and returned.func.value.id == "operator"
        and "operator" in facts.imports.values()
        and returned.func.attr in _OPERATOR_COMPARES
        and len(returned.args) == 2
        and not returned.keywords
    ):
        left, right = returned.args
        op = _OPERATOR_COMPARES[returned.func.attr]()
    else:
        return None
    if not (isinstance(left, ast.Name) and isinstance(right, ast.Name)) or left.id == right.id:
        return None
    values: dict[str, ast.expr] = {}
    for statement in body[:-1]:
        if (
            isinstance(statement, ast.Assign)
            and len(statement.targets) == 1
            and isinstance(statement.targets[0], ast.Name)
            and statement.targets[0].id in (left.id, right.id)
            and statement.targets[0].id not in values
        ):
            values[statement.targets[0].id] = statement.value
        elif not (isinstance(statement, ast.For) and _converts_items(statement, (left.id, right.id))):
            return None
    if set(values) != {left.id, right.id}:
        return None
    return ast.Compare(left=values[left.id], ops=[op], comparators=[values[right.id]])


def _converts_items(loop: ast.For, names: tuple[str, str]) -> bool:
    """``for i in range(...):`` whose only stores are ``x[i] = int(x[i])`` on ``names`` (in a
    try whose handlers only pass): each item becomes a number or stays, the same way on both
    sides."""
    if not isinstance(loop.target, ast.Name) or loop.orelse:
        return False
    statements: list[ast.stmt] = []
    for statement in loop.body:
        if isinstance(statement, ast.Try) and not statement.orelse and not statement.finalbody:
            if not all(all(isinstance(s, ast.Pass) for s in handler.body) for handler in statement.handlers):
                return False
            statements.extend(statement.body)
        else:
            statements.append(statement)
    for statement in statements:
        if not (isinstance(statement, ast.Assign) and len(statement.targets) == 1):
            return False
        target, value = statement.targets[0], statement.value
        if not (
            isinstance(target, ast.Subscript)
            and isinstance(target.value, ast.Name)
            and target.value.id in names
            and isinstance(value, ast.Call)
            and isinstance(value.func, ast.Name)
            and value.func.id in _PARSERS
            and len(value.args) == 1
            and ast.dump(value.args[0]) == ast.dump(ast.Subscript(value=ast.Name(id=target.value.id, ctx=ast.Load()), slice=target.slice, ctx=ast.Load()))
        ):
            return False
    return True


def _compare(
    left: ast.AST, op: ast.cmpop, right: ast.AST, names: frozenset[str], parameter: tuple[str, tuple[int, ...]] | None
) -> bool | None:
    """``left op right``, one side the gym version and the other a 0.x release, both read the
    same way (both raw strings, or both parsed)."""
    left_side, right_side = _side(left, names, parameter), _side(right, names, parameter)
    if left_side is None or right_side is None:
        return None
    (left_kind, left_parsed), (right_kind, right_parsed) = left_side, right_side
    kind = type(op)
    if right_kind == "version":
        left_kind, right_kind, left_parsed, right_parsed = right_kind, left_kind, right_parsed, left_parsed
        kind = _MIRRORED.get(kind, kind)
    if left_kind != "version" or not isinstance(right_kind, tuple) or left_parsed != right_parsed or kind not in _COMPARE:
        return None
    other = right_kind
    if not other or other >= (1,):
        return None  # a 1.x release may answer differently on another Gymnasium release
    if kind in (ast.Eq, ast.NotEq):
        return kind is ast.NotEq
    width = max(len(GYMNASIUM_RELEASE), len(other))
    target = (GYMNASIUM_RELEASE + (0,) * width)[:width]
    return bool(_COMPARE[kind](target, (other + (0,) * width)[:width]))


def _side(node: ast.AST, names: frozenset[str], parameter: tuple[str, tuple[int, ...]] | None):
    """("version", parsed) for the gym version, (release, parsed) for a 0.x literal (or the
    helper's parameter, standing for the literal its call passes); None for anything else.
    ``parsed``: whether a parse (``version.parse``, ``[int(x) for x in v.split(".")]``) reads it."""
    if _is_version(node, names):
        return "version", False
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        release = _release(node.value)
        return (release, False) if release is not None else None
    if parameter is not None and isinstance(node, ast.Name) and node.id == parameter[0]:
        return parameter[1], False
    leaves = [n for n in walk(node) if _is_version(n, names)]
    # a parse strips surrounding blanks (``version.parse(" 0.25.0")`` is 0.25.0)
    literals = [n for n in walk(node) if isinstance(n, ast.Constant) and isinstance(n.value, str) and _release(n.value.strip())]
    params = [n for n in walk(node) if parameter is not None and isinstance(n, ast.Name) and n.id == parameter[0]]
    if len(leaves) + len(literals) + len(params) != 1 or not _order_keeping(node, names, parameter):
        return None
    if leaves:
        return "version", True
    if literals:
        release = _release(str(literals[0].value).strip())
        return (release, True) if release is not None else None
    return parameter[1], True  # type: ignore[index]


def _order_keeping(node: ast.AST, names: frozenset[str], parameter) -> bool:
    """Only calls of parsers, ``.split(".")``, comprehensions and ``[:n]`` slices: a parse
    that orders releases as versions are ordered."""
    local = {n.id for n in walk(node) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Store)}
    for n in walk(node):
        if isinstance(n, ast.Subscript):
            if not (isinstance(n.slice, ast.Slice) and n.slice.lower is None and n.slice.step is None):
                return False
        elif isinstance(n, ast.Call):
            func = n.func
            name = func.attr if isinstance(func, ast.Attribute) else func.id if isinstance(func, ast.Name) else None
            if name == "split":
                if not (len(n.args) == 1 and isinstance(n.args[0], ast.Constant) and n.args[0].value == "."):
                    return False
            elif name not in _PARSERS:
                return False
        elif isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load):
            if n.id not in local and n.id not in names and n.id not in _PARSERS and (parameter is None or n.id != parameter[0]):
                if n.id not in ("version", "packaging", "distutils"):
                    return False
    return True


def _is_version(node: ast.AST, names: frozenset[str]) -> bool:
    return isinstance(node, ast.Attribute) and node.attr == "__version__" and isinstance(node.value, ast.Name) and node.value.id in names


def _release(text: str) -> tuple[int, ...] | None:
    """``"0.26.0"`` -> (0, 26, 0); None for anything but dotted numbers."""
    parts = text.split(".")
    if not parts or not all(part.isdigit() for part in parts):
        return None
    return tuple(int(part) for part in parts)


def _constant_of(node: ast.expr, facts: ModuleFacts) -> ast.expr:
    """A module-level name assigned once, a string (``V_NEW_API = "0.26.0"``): that string."""
    if not isinstance(node, ast.Name):
        return node
    values = [
        s.value
        for s in facts.tree.body
        if isinstance(s, ast.Assign) and any(isinstance(t, ast.Name) and t.id == node.id for t in s.targets)
    ]
    stores = [n for n in walk(facts.tree) if isinstance(n, ast.Name) and n.id == node.id and not isinstance(n.ctx, ast.Load)]
    if len(values) == 1 and len(stores) == 1 and isinstance(values[0], ast.Constant) and isinstance(values[0].value, str):
        return values[0]
    return node


def reads_version(test: ast.AST, facts: ModuleFacts, *, any_module: bool = False) -> bool:
    """``test`` reads the gym version: directly, or by calling a def of this module that
    reads it (``if gym_at_least("0.26"):``), settled or not.

    ``any_module=True`` accepts any ``x.__version__`` (and a def of the module's scope that
    reads one, found by the name called): the render rules (``rendering/planning.py``)
    only need to know that ``if <version test> and flag:`` switches between two render
    APIs, whichever module's version it reads; the receiver rules
    (``receiver_origins.py``) keep the default, for which only gym's own version says that
    the branch it guards serves legacy gym's step API.
    """
    if "__version__" not in facts.text:
        return False
    if any_module:

        def is_version(node: ast.AST) -> bool:
            return isinstance(node, ast.Attribute) and node.attr == "__version__"

        def is_helper(name: str) -> bool:
            local = facts.functions.get(name)
            return local is not None and any(is_version(n) for n in walk(local))

    else:
        names = gym_module_names(facts)
        if not names:
            return False

        def is_version(node: ast.AST) -> bool:
            return _is_version(node, names)

        helpers = {s.name for s in facts.tree.body if isinstance(s, FUNCTIONS) and any(is_version(n) for n in walk(s))}

        def is_helper(name: str) -> bool:
            return name in helpers

    return any(
        is_version(n) or (isinstance(n, ast.Call) and isinstance(n.func, ast.Name) and is_helper(n.func.id))
        for n in walk(test)
    )
