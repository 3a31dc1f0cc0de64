"""No rewrite reads ``terminated`` or ``truncated`` where a path leaves them unbound.

Every migrated fixture (``*.expected.py``) is read with CPython's ``ast``: in each function
that binds one of the flags itself, a ``return`` that reads it must come after a binding
of it on every path that reaches the return (``facts.flow.bound_on_every_path``), or the
migrated step raises UnboundLocalError on that path. A flag the legacy case already read
unbound somewhere is the legacy code's own; none of the fixtures does.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from gymmigrate.facts.flow import bound_on_every_path

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures"
FLAGS = frozenset({"terminated", "truncated"})


def _unbound_returns(source: str) -> list[str]:
    tree = ast.parse(source)
    problems = []
    for function in ast.walk(tree):
        if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        arguments = function.args
        parameters = {a.arg for a in [*arguments.posonlyargs, *arguments.args, *arguments.kwonlyargs]}
        parameters |= {a.arg for a in (arguments.vararg, arguments.kwarg) if a is not None}
        table = {n.id for n in ast.walk(function) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Store)}
        locals_ = (FLAGS & table) - parameters
        if not locals_:
            continue
        for node in ast.walk(function):
            if not isinstance(node, ast.Return) or node.value is None:
                continue
            read = {n.id for n in ast.walk(node.value) if isinstance(n, ast.Name) and n.id in locals_}
            if not read:
                continue
            bound = bound_on_every_path(function, node, frozenset(read), lambda statement: frozenset())
            if bound is not None and not read <= bound:
                problems.append(f"line {node.lineno}: {sorted(read - bound)} unbound on some path")
    return problems


CASES = sorted(FIXTURES.rglob("*.expected.py"))


@pytest.mark.parametrize("path", CASES, ids=[str(p.relative_to(FIXTURES)) for p in CASES])
def test_returned_flags_are_bound(path: Path) -> None:
    assert _unbound_returns(path.read_text(encoding="utf-8")) == []


def test_the_check_sees_a_branch_without_the_flags() -> None:
    source = (
        "def step(self, a):\n"
        "    if a:\n"
        "        obs, r, terminated, truncated, info = self.env.step(a)\n"
        "    else:\n"
        "        obs, r, done, info = self.replay()\n"
        "    return obs, r, terminated, truncated, info\n"
    )
    assert _unbound_returns(source) == ["line 6: ['terminated', 'truncated'] unbound on some path"]
