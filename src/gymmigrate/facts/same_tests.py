"""Bindings a read cannot see because the code tests the same thing twice.

``if MODE == "arm": env = Arm() elif MODE == "cart": env = gym.make(...)`` and later, with
``MODE`` never rebound, ``if MODE == "arm": env.reset(True) elif MODE == "cart":
env.reset()``: both bindings reach both reads by position, yet the read under ``MODE ==
"cart"`` (and not ``MODE == "arm"``) can only see the value bound where the same tests came
out the same way. ``excluded`` names the bindings whose branch contradicts the read's.

A test counts only when its value cannot change between the two places: made of names,
attributes of names, constants, comparisons, ``and``/``or``/``not``; every name bound once in
the scope it resolves to (a parameter or one assignment; ``global`` rebinding lands there
too), no attribute it reads stored anywhere in the module, ``in`` only against literals.
Tests are compared by their syntax tree (``MODE ==  "arm"`` is ``MODE == "arm"``).
"""

from __future__ import annotations

import ast

from gymmigrate.facts.module import FUNCTIONS, ModuleFacts, walk

Guard = tuple[str, bool]  # (the test's tree, the branch taken)


def excluded(facts: ModuleFacts, read: ast.AST, bindings: list[ast.AST]) -> set[int]:
    """ids of the ``bindings`` that sit in a branch of a test the read is in the other branch
    of (the test unchanged in between): the read never sees their value."""
    mine = guards(facts, read)
    if not mine:
        return set()
    out: set[int] = set()
    for binding in bindings:
        theirs = guards(facts, binding)
        if any((test, not taken) in mine for test, taken in theirs):
            out.add(id(binding))
    return out


def guards(facts: ModuleFacts, node: ast.AST) -> frozenset[Guard]:
    """The stable tests of the ``if`` statements around ``node`` in its own function (or
    module), each with the branch ``node`` sits in."""
    found: set[Guard] = set()
    child = node
    for ancestor in facts.ancestors(node):
        if isinstance(ancestor, (*FUNCTIONS, ast.Lambda, ast.ClassDef)):
            break
        if isinstance(ancestor, ast.If) and child is not ancestor.test:
            key = test_key(facts, ancestor.test)
            if key is not None:
                found.add((key, child in ancestor.body))
        child = ancestor
    return frozenset(found)


def test_key(facts: ModuleFacts, test: ast.expr) -> str | None:
    """What identifies ``test`` among the module's tests, when its value cannot change
    between two places it is evaluated; None otherwise."""
    return facts.memo(("stable-test", id(test)), lambda: ast.dump(test) if _stable(facts, test) else None, while_computing=None)


def _stable(facts: ModuleFacts, expr: ast.expr) -> bool:
    if isinstance(expr, ast.Constant):
        return True
    if isinstance(expr, ast.Name):
        _, bindings = facts.resolve(expr.id, facts.scope_of(expr))
        return len(bindings) == 1
    if isinstance(expr, ast.Attribute):
        return expr.attr not in _stored_attributes(facts) and _stable(facts, expr.value) and not isinstance(expr.value, ast.Constant)
    if isinstance(expr, ast.BoolOp):
        return all(_stable(facts, value) for value in expr.values)
    if isinstance(expr, ast.UnaryOp) and isinstance(expr.op, ast.Not):
        return _stable(facts, expr.operand)
    if isinstance(expr, ast.Compare):
        for op, right in zip(expr.ops, expr.comparators):
            if isinstance(op, (ast.In, ast.NotIn)) and not _literal(right):
                return False  # ``x in seen``: a list the code may grow
        operands = [expr.left, *expr.comparators]
        return all(_literal(o) or (not isinstance(o, (ast.Tuple, ast.List, ast.Set)) and _stable(facts, o)) for o in operands)
    return False


def _literal(expr: ast.expr) -> bool:
    if isinstance(expr, ast.Constant):
        return True
    return isinstance(expr, (ast.Tuple, ast.List, ast.Set)) and all(isinstance(e, ast.Constant) for e in expr.elts)


def _stored_attributes(facts: ModuleFacts) -> frozenset[str]:
    """Attribute names the module assigns anywhere (``args.env = ...``, ``setattr`` aside)."""

    def compute() -> frozenset[str]:
        return frozenset(
            node.attr for node in walk(facts.tree) if isinstance(node, ast.Attribute) and isinstance(node.ctx, (ast.Store, ast.Del))
        )

    return facts.memo(("stored-attributes", id(facts.tree)), compute)
