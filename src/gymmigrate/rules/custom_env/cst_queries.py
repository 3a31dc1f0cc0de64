"""What a class rebuild asks about a method's LibCST body, answered from one traversal.

The builds in ``rebuild.py`` receive methods as other edits left them and ask, for
example, whether ``done`` is assigned once, read outside the returns, or declared
global. A LibCST traversal costs about what parsing the same code costs, so each body
is indexed once (``_BodyIndex``) and every question reads the index.
"""

from __future__ import annotations

import libcst as cst


class OwnBodyOnly:
    """Mixed into a LibCST visitor or transformer (before its LibCST base) that reads or
    rewrites one function's own body: a nested def, class or lambda returns to its own
    caller and binds its own names, so none of it is entered."""

    def visit_FunctionDef(self, node: cst.FunctionDef) -> bool:
        return False

    def visit_ClassDef(self, node: cst.ClassDef) -> bool:
        return False

    def visit_Lambda(self, node: cst.Lambda) -> bool:
        return False


class _OwnReturns(OwnBodyOnly, cst.CSTVisitor):
    def __init__(self) -> None:
        self.returns: list[cst.Return] = []

    def visit_Return(self, node: cst.Return) -> None:
        self.returns.append(node)


def own_returns(function: cst.FunctionDef | cst.BaseSuite) -> list[cst.Return]:
    """The ``return`` statements of one function (or body), in order, not of nested ones."""
    collector = _OwnReturns()
    body = function.body if isinstance(function, cst.FunctionDef) else function
    body.visit(collector)
    return collector.returns


class _BodyIndex(cst.CSTVisitor):
    """One traversal of a method body answers every question the builds ask about it.

    A LibCST traversal costs about what parsing the same code costs, so asking eight
    questions with eight ``findall`` calls made a class rebuild the slowest step of the
    engine. Lists keep pre-order, the order ``findall`` returned.
    """

    def __init__(self) -> None:
        self.names: dict[str, int] = {}  # every Name node's value -> count
        self.assign_targets: dict[str, int] = {}  # ``name = ...`` (any Assign) -> count
        self.tuple_targets: set[str] = set()  # ``a, name = ...``
        self.single_assigns: dict[str, list[cst.Assign]] = {}  # ``name = value`` with one target
        self.aug_targets: set[str] = set()
        self.ann_targets: set[str] = set()
        self.for_targets: set[str] = set()
        self.globals: set[str] = set()
        self.has_nonlocal = False
        self.calls: list[cst.Call] = []
        self.comparisons: list[cst.Comparison] = []
        self.self_attributes: set[str] = set()  # ``self.<attr>`` read or written

    def visit_Name(self, node: cst.Name) -> None:
        self.names[node.value] = self.names.get(node.value, 0) + 1

    def visit_Assign(self, node: cst.Assign) -> None:
        for target in node.targets:
            value = target.target
            if isinstance(value, cst.Name):
                self.assign_targets[value.value] = self.assign_targets.get(value.value, 0) + 1
            elif isinstance(value, cst.Tuple):
                self.tuple_targets.update(
                    e.value.value for e in value.elements if isinstance(e, cst.Element) and isinstance(e.value, cst.Name)
                )
        if len(node.targets) == 1 and isinstance(node.targets[0].target, cst.Name):
            self.single_assigns.setdefault(node.targets[0].target.value, []).append(node)

    def visit_AugAssign(self, node: cst.AugAssign) -> None:
        if isinstance(node.target, cst.Name):
            self.aug_targets.add(node.target.value)

    def visit_AnnAssign(self, node: cst.AnnAssign) -> None:
        if isinstance(node.target, cst.Name):
            self.ann_targets.add(node.target.value)

    def visit_For(self, node: cst.For) -> None:
        if isinstance(node.target, cst.Name):
            self.for_targets.add(node.target.value)

    def visit_Global(self, node: cst.Global) -> None:
        self.globals.update(item.name.value for item in node.names)

    def visit_Nonlocal(self, node: cst.Nonlocal) -> None:
        self.has_nonlocal = True

    def visit_Call(self, node: cst.Call) -> None:
        self.calls.append(node)

    def visit_Comparison(self, node: cst.Comparison) -> None:
        self.comparisons.append(node)

    def visit_Attribute(self, node: cst.Attribute) -> None:
        if isinstance(node.value, cst.Name) and node.value.value == "self":
            self.self_attributes.add(node.attr.value)


# Builds ask several questions of the same (immutable) node: index it once. Keyed by
# id() with the node kept alive in the entry, so an id is never reused while cached.
_INDEXES: dict[int, tuple[cst.CSTNode, _BodyIndex]] = {}


def _index(node: cst.CSTNode) -> _BodyIndex:
    """The index of a body (a FunctionDef is indexed by its body: names outside it are
    parameters, decorators and annotations, which only ``_uses_name`` counts)."""
    body = node.body if isinstance(node, cst.FunctionDef) else node
    entry = _INDEXES.get(id(body))
    if entry is not None and entry[0] is body:
        return entry[1]
    index = _BodyIndex()
    body.visit(index)
    if len(_INDEXES) > 256:
        _INDEXES.clear()
    _INDEXES[id(body)] = (body, index)
    return index


def _uses_self_attribute(node: cst.CSTNode, attr: str) -> bool:
    """``self.<attr>`` anywhere in the body."""
    return attr in _index(node).self_attributes


def _checks_is_none(node: cst.CSTNode, attr: str) -> bool:
    """``self.<attr> is None`` somewhere in the body."""
    for comparison in _index(node).comparisons:
        left = comparison.left
        if (
            len(comparison.comparisons) == 1
            and isinstance(left, cst.Attribute)
            and isinstance(left.value, cst.Name)
            and left.value.value == "self"
            and left.attr.value == attr
            and isinstance(comparison.comparisons[0].operator, cst.Is)
            and isinstance(comparison.comparisons[0].comparator, cst.Name)
            and comparison.comparisons[0].comparator.value == "None"
        ):
            return True
    return False


def _assigns_name(fn: cst.CSTNode, name: str) -> bool:
    index = _index(fn)
    return name in index.assign_targets or name in index.tuple_targets


def _single_assignment(fn: cst.FunctionDef, name: str) -> cst.BaseExpression | None:
    index = _index(fn)
    assigns = index.single_assigns.get(name, [])
    others = name in index.aug_targets or name in index.ann_targets or name in index.for_targets
    if len(assigns) != 1 or others or _assigns_in_tuple(fn, name):
        return None
    return assigns[0].value


def _assigns_in_tuple(fn: cst.FunctionDef, name: str) -> bool:
    return name in _index(fn).tuple_targets


def _uses_name(fn: cst.CSTNode, name: str) -> bool:
    if name in _index(fn).names:
        return True
    if not isinstance(fn, cst.FunctionDef):
        return False
    # Outside the body: the function's name, parameters, decorators, return annotation.
    outside: list[cst.CSTNode] = [fn.name, fn.params, *fn.decorators]
    if fn.returns is not None:
        outside.append(fn.returns)
    return any(name in _index(part).names for part in outside)


def _declares_global(fn: cst.FunctionDef, name: str) -> bool:
    index = _index(fn)
    return name in index.globals or index.has_nonlocal


def _rebinds_name(fn: cst.FunctionDef, name: str) -> bool:
    index = _index(fn)
    return _assigns_name(fn, name) or name in index.aug_targets or name in index.for_targets


def _reads_name_outside_returns(fn: cst.FunctionDef, name: str) -> bool:
    index = _index(fn)
    total = index.names.get(name, 0)
    in_returns = sum(_index(r).names.get(name, 0) for r in own_returns(fn))
    stores = index.assign_targets.get(name, 0)
    return total - in_returns - stores > 0
