"""README and docs/rules/ are the user's manual: every rule, every option and the Quick start are in them."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import typer

from gymmigrate.cli import app
from gymmigrate.rules import all_rules
from gymmigrate.rules.base import standalone_rules

README = (Path(__file__).resolve().parent.parent / "README.md").read_text(encoding="utf-8")


RULE_DOCS = Path(__file__).resolve().parent.parent / "docs" / "rules"


def _section(code: str) -> str:
    page = RULE_DOCS / f"{code}.md"
    assert page.is_file(), f"{code} has no page docs/rules/{code}.md"
    text = page.read_text(encoding="utf-8")
    assert re.match(rf"# {code}\b", text), f"docs/rules/{code}.md must start with its heading"
    return text


@pytest.mark.parametrize("rule", all_rules(), ids=lambda rule: rule.code)
def test_every_rule_is_documented_with_an_example(rule) -> None:
    section = _section(rule.code)
    fence = "```" if rule in standalone_rules() else "```python"  # dependency files hold no Python
    assert section.count(fence) >= 1, f"{rule.code} needs a before/after example in docs/rules/{rule.code}.md"
    assert f"| {rule.kind.value} |" in README.split(f"| [{rule.code}]", 1)[1].split("\n", 1)[0]


def test_quick_start_has_exactly_two_shell_blocks() -> None:
    quick = README.split("## Quick start", 1)[1].split("\n## ", 1)[0]
    blocks = re.findall(r"```sh\n(.*?)```", quick, flags=re.S)
    assert len(blocks) == 2
    assert "gymmigrate rewrite --diff fixtures/examples/" in blocks[0]
    assert 'pip install -e ".[test]"' in blocks[1] and "pytest" in blocks[1]


def test_every_cli_option_is_documented() -> None:
    command = typer.main.get_command(app)
    commands = command.commands  # type: ignore[attr-defined]
    assert set(commands) >= {"rewrite", "check", "smoke"}
    for name, sub in commands.items():
        assert f"gymmigrate {name}" in README
        for param in sub.params:
            for option in param.opts:
                if option.startswith("--") and option != "--help":
                    assert option in README, f"`gymmigrate {name} {option}` is not in README"


def test_every_test_named_under_guarantees_exists() -> None:
    section = README.split("### Guarantees", 1)[1].split("\n### ", 1)[0]
    named = re.findall(r"`(tests/test_\w+\.py)::(test_\w+)`", section)
    assert len(named) >= 8, "each guarantee names the test that proves it"
    root = Path(__file__).resolve().parent.parent
    for path, test in named:
        source = (root / path).read_text(encoding="utf-8")
        assert re.search(rf"^def {test}\(", source, flags=re.M), f"README names {path}::{test}, which does not exist"
