"""Every rewritten import keeps binding the names its scope reads.

``import gym.wrappers`` inside a function binds that function's local ``gym``; rewritten
to ``import gymnasium.wrappers`` alone it binds ``gymnasium`` only, and the function's
``gym.wrappers...`` raises NameError. Checked over every before/after fixture pair, scope
by scope (the module, each class and function, matched by their nesting of names).
"""

from __future__ import annotations

import ast

import pytest

from tests.fixture_cases import Case, collect_cases

_SCOPES = (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)


def _own_nodes(scope: ast.AST):
    """The nodes of ``scope`` outside the defs and classes nested in it."""
    stack = list(ast.iter_child_nodes(scope))
    while stack:
        node = stack.pop()
        yield node
        if not isinstance(node, (*_SCOPES, ast.Lambda)):
            stack.extend(ast.iter_child_nodes(node))


def _scopes(tree: ast.Module) -> dict[str, tuple[set[str], set[str]]]:
    """Scope path -> (names its own imports bind, names it reads)."""
    found: dict[str, tuple[set[str], set[str]]] = {}

    def visit(scope: ast.AST, path: str) -> None:
        bound: set[str] = set()
        read: set[str] = set()
        nested: dict[str, int] = {}
        for node in _own_nodes(scope):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                for alias in node.names:
                    if alias.name != "*":
                        bound.add(alias.asname or alias.name.split(".")[0])
            elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load):
                read.add(node.id)
            elif isinstance(node, _SCOPES):
                count = nested[node.name] = nested.get(node.name, 0) + 1
                visit(node, f"{path}.{node.name}#{count}")
        found[path] = (bound, read)

    visit(tree, "")
    return found


def _cases() -> list[Case]:
    return [case for case in collect_cases() if case.expected is not None and case.source.suffix == ".py"]


@pytest.mark.parametrize("case", _cases(), ids=lambda case: case.id)
def test_rewritten_imports_bind_what_their_scope_reads(case: Case) -> None:
    assert case.expected is not None
    before = _scopes(ast.parse(case.source.read_text(encoding="utf-8")))
    after = _scopes(ast.parse(case.expected.read_text(encoding="utf-8")))
    module_after = after.get("", (set(), set()))[0]
    for path, (bound, read) in before.items():
        if path not in after:
            continue  # a def the rewrite removed or renamed: nothing to match it with
        bound_after, read_after = after[path]
        lost = {
            name
            for name in bound & read & read_after
            if name not in bound_after and (path == "" or name not in module_after)
        }
        assert not lost, f"{case.id}: scope {path or '<module>'} reads {sorted(lost)}, which its imports no longer bind"
