"""gymmigrate rules: the table of every rule, each rule's page with its fixture example,
and the generated data an installed package reads."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate import rule_docs
from gymmigrate.cli import app
from gymmigrate.rules import all_rules

runner = CliRunner()
ROOT = Path(__file__).resolve().parent.parent
DOCS = rule_docs.from_checkout(ROOT)


def test_rules_lists_every_rule() -> None:
    result = runner.invoke(app, ["rules"], env={"COLUMNS": "200"})
    assert result.exit_code == 0
    for rule in all_rules():
        row = next((line for line in result.stdout.splitlines() if f" {rule.code} " in line), None)
        assert row is not None, f"{rule.code} is missing from `gymmigrate rules`"
        assert f" {rule.kind.value} " in row


@pytest.mark.parametrize("rule", all_rules(), ids=lambda rule: rule.code)
def test_rules_code_shows_page_and_fixture_example(rule) -> None:
    result = runner.invoke(app, ["rules", rule.code.lower()], env={"COLUMNS": "200"})
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith(f"{rule.code}: {rule.title} ({rule.kind.value})")
    doc = DOCS[rule.code]
    assert doc.page.startswith(f"# {rule.code}"), "its page is shown"
    assert doc.before is not None, f"no fixture under fixtures/rules/{rule.code}/ where {rule.code} fires"
    assert f"Example ({doc.example})" in result.stdout
    shown = [line.strip() for line in result.stdout.splitlines()]
    for line in (doc.before + (doc.after or "")).splitlines():
        if line.strip():
            assert line.strip() in shown, f"example line {line!r} not shown"


def test_unknown_rule_is_a_usage_error() -> None:
    result = runner.invoke(app, ["rules", "GM999"])
    assert result.exit_code == 2 and "unknown rule 'GM999'" in result.stderr


def test_packaged_rule_docs_are_up_to_date() -> None:
    assert DOCS is not None
    assert rule_docs.GENERATED.read_text(encoding="utf-8") == rule_docs.render_json(DOCS), (
        "src/gymmigrate/rule_docs.json is stale: run `python -m gymmigrate.rule_docs`"
    )


def test_installed_package_reads_the_generated_docs(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.setattr(rule_docs, "CHECKOUT", tmp_path)  # no docs/ or fixtures/ there
    monkeypatch.setattr(rule_docs.from_checkout, "__defaults__", (tmp_path,))
    assert rule_docs.load() == DOCS


def test_rules_reference_index_lists_every_rule_with_title_and_kind() -> None:
    index = (ROOT / "docs" / "rules" / "README.md").read_text(encoding="utf-8")
    rows = {m["code"]: (m["title"], m["kind"]) for m in re.finditer(
        r"^\| \[(?P<code>[A-Z]+\d+)\]\((?P=code)\.md\) \| (?P<title>[^|]+?) \| (?P<kind>\w+) \|", index, re.M
    )}
    expected = {rule.code: (rule.title, rule.kind.value) for rule in all_rules()}
    assert {code: rows.get(code) for code in expected} == expected
