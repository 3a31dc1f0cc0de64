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
