"""Every rule, from its before/after fixtures: output, parse, idempotence, findings."""

from __future__ import annotations

import ast

import pytest

from gymmigrate.engine import transform_source
from gymmigrate.findings import FixKind
from gymmigrate.rules import all_rules
from gymmigrate.rules.base import standalone_rules
from tests.fixture_cases import RULE_FIXTURES, collect_cases, finding_row

CASES = collect_cases()


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_fixture(case) -> None:
    source = case.source.read_bytes()
    result = transform_source(source, str(case.source))
    if case.is_noop:
        assert result.rewritten == source, "a no-op case must stay byte-identical"
    else:
        expected = case.expected.read_bytes()
        assert result.rewritten.decode() == expected.decode()
        assert result.rewritten == expected
        ast.parse(expected)
        again = transform_source(expected, str(case.expected))
        assert again.rewritten == expected, "a second run must change nothing"
    assert case.findings.exists(), f"{case.findings.name} is missing: every case states its findings"
    found = sorted(finding_row(f) for f in result.findings)
    assert found == case.expected_findings()


def test_every_rule_has_rewrite_and_noop_fixtures() -> None:
    by_dir: dict[str, list] = {}
    for case in CASES:
        by_dir.setdefault(case.rule_dir, []).append(case)
    missing = []
    standalone = standalone_rules()  # dependency-file rules: tests/test_dependencies.py
    for rule in all_rules():
        if rule in standalone:
            continue
        cases = by_dir.get(rule.code, [])
        fires = [c for c in cases if any(row[1] == rule.code for row in c.expected_findings())]
        if rule.kind is not FixKind.FLAG:
            fires = [c for c in fires if not c.is_noop]
        quiet = [c for c in cases if c.is_noop and not any(row[1] == rule.code for row in c.expected_findings())]
        if not fires:
            missing.append(f"{rule.code}: no case in fixtures/rules/{rule.code}/ where it fires")
        if not quiet:
            missing.append(f"{rule.code}: no no-op case in fixtures/rules/{rule.code}/")
    assert not missing, "\n".join(missing)


def test_fixture_directories_name_known_rules() -> None:
    known = {rule.code for rule in all_rules()}
    unknown = {path.name for path in RULE_FIXTURES.iterdir() if path.is_dir()} - known
    assert not unknown


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_check_decides_like_rewrite(case) -> None:
    # ``gymmigrate check`` only plans (no LibCST tree, no verification run); it must list
    # exactly what rewrite reports and agree on whether the file would change.
    from gymmigrate.engine import lint_source

    source = case.source.read_bytes()
    rewritten = transform_source(source, str(case.source))
    findings, would_change = lint_source(source, str(case.source))
    assert would_change == rewritten.changed
    strip = lambda items: sorted((f.line, f.column, f.rule, f.kind, f.tier, f.message) for f in items)  # noqa: E731
    assert strip(findings) == strip(rewritten.findings)



def test_no_receiver_half_migrated() -> None:
    # One receiver gets one decision: its reset is never rewritten while a four-value unpack
    # of its step is left, even with an item (or the reverse): half-migrated, the pair breaks
    # at run time whatever the item says. Read from the stated findings (test_fixture checks
    # they are the run's), so no fixture is rewritten twice.
    half = [found for case in CASES if (found := _half_migrated(case)) is not None]
    assert not half, "\n".join(half)


def _narrowed_by(facts, call: ast.AST, name: str) -> tuple:
    """The ``if isinstance(name, ...)`` tests (and the branch) a call sits under: a receiver
    narrowed to a class is another decision than the same name outside the test (a worker
    branching on its env's class migrates the Gym branch and asks about the rest)."""
    found = []
    node, parent = call, facts.parent(call)
    while parent is not None:
        if isinstance(parent, ast.If) and any(
            isinstance(test, ast.Call)
            and isinstance(test.func, ast.Name)
            and test.func.id == "isinstance"
            and test.args
            and isinstance(test.args[0], ast.Name)
            and test.args[0].id == name
            for test in ast.walk(parent.test)
        ):
            found.append((id(parent), node in parent.body))
        node, parent = parent, facts.parent(parent)
    return tuple(found)


def _half_migrated(case) -> str | None:
    """The first receiver of ``case`` with its reset rewritten and a legacy step left, or the
    reverse. A receiver is a name as the same bindings reach it (not those under the other
    branch of a test repeated around the read: ``same_tests``) or ``self.x`` in one class."""
    from gymmigrate.facts import same_tests
    from gymmigrate.facts.flow import Flow
    from gymmigrate.facts.module import ModuleFacts

    text = case.source.read_text(encoding="utf-8")
    try:
        tree = ast.parse(text)
    except SyntaxError:
        return None  # a file the tool refuses (Python 2): its own case says so
    facts = ModuleFacts(tree, text)
    rewritten: dict[int, set[str]] = {}
    for row in case.expected_findings():
        if row[2] in ("auto", "assist"):
            rewritten.setdefault(row[0], set()).add(row[1])
    groups: dict[tuple, dict[str, list[ast.Call]]] = {}
    for method in ("reset", "step"):
        for call in facts.attribute_calls.get(method, ()):
            receiver = call.func.value  # type: ignore[attr-defined]
            if isinstance(receiver, ast.Name):
                reaching = Flow.of(facts).reaching(receiver) or facts.bindings_of(receiver)
                cut = same_tests.excluded(facts, receiver, reaching)
                key: tuple = (
                    id(facts.scope_of(receiver)),
                    receiver.id,
                    frozenset(id(b) for b in reaching if id(b) not in cut),
                    _narrowed_by(facts, call, receiver.id),
                )
            elif isinstance(receiver, ast.Attribute) and isinstance(receiver.value, ast.Name) and receiver.value.id == "self":
                key = (id(facts.enclosing_class(receiver)), receiver.attr)
            else:
                continue
            groups.setdefault(key, {"reset": [], "step": []})[method].append(call)

    def left_legacy(call: ast.Call, code: str) -> bool:
        # ``obs = x.reset()`` / ``o, r, d, i = x.step(a)`` with no rewrite of its own
        parent = facts.parent(call)
        if not (isinstance(parent, ast.Assign) and len(parent.targets) == 1) or code in rewritten.get(call.lineno, ()):
            return False
        target = parent.targets[0]
        if code == "GM301":
            return isinstance(target, (ast.Tuple, ast.List)) and len(target.elts) == 4
        return isinstance(target, ast.Name) and not call.args and not call.keywords

    for calls in groups.values():
        resets, steps = calls["reset"], calls["step"]
        reset_done = any("GM201" in rewritten.get(c.lineno, ()) for c in resets)
        step_done = any("GM301" in rewritten.get(c.lineno, ()) for c in steps)
        if (reset_done and any(left_legacy(c, "GM301") for c in steps)) or (step_done and any(left_legacy(c, "GM201") for c in resets)):
            return f"{case.id}: {ast.unparse((resets or steps)[0])}"
    return None
