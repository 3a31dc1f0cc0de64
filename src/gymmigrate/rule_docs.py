"""Each rule's manual for ``gymmigrate rules``: its page (``docs/rules/<CODE>.md``) and a
before/after example taken from the fixtures the tests run (``fixtures/rules/<CODE>/``),
so the example shown cannot drift from what the rule does.

In a source checkout both are read where they are. An installed package has no
``docs/`` or ``fixtures/``: it reads ``rule_docs.json``, generated from them by
``python -m gymmigrate.rule_docs`` and shipped as package data (a test fails when it is
out of date).
"""

from __future__ import annotations

import json
import sys
from dataclasses import asdict, dataclass
from pathlib import Path

from gymmigrate.rules import all_rules
from gymmigrate.rules.base import standalone_rules

PACKAGE = Path(__file__).resolve().parent
CHECKOUT = PACKAGE.parent.parent
GENERATED = PACKAGE / "rule_docs.json"


@dataclass(frozen=True)
class RuleDoc:
    code: str
    page: str  # the Markdown page
    example: str | None  # fixtures/rules/<CODE>/<case>.py
    before: str | None
    after: str | None  # None: the example is reported, not rewritten


def from_checkout(root: Path = CHECKOUT) -> dict[str, RuleDoc] | None:
    """Every rule's doc read from a source checkout; None when this is not one."""
    pages, fixtures = root / "docs" / "rules", root / "fixtures" / "rules"
    if not (pages.is_dir() and fixtures.is_dir()):
        return None
    standalone = {rule.code for rule in standalone_rules()}
    docs = {}
    for rule in all_rules():
        page = pages / f"{rule.code}.md"
        text = page.read_text(encoding="utf-8") if page.is_file() else ""
        if rule.code in standalone:
            example = _dependency_example(root / "fixtures" / "dependencies", rule.code, root)
        else:
            example = _example(fixtures / rule.code, rule.code, root)
        docs[rule.code] = RuleDoc(rule.code, text, *example)
    return docs


def _dependency_example(folder: Path, code: str, root: Path) -> tuple[str | None, str | None, str | None]:
    """The smallest dependency-file case (``fixtures/dependencies/<case>/``) where the rule fires."""
    firing = []
    for findings in sorted(folder.glob("*/findings")):
        if not any(row.split()[1:2] == [code] for row in findings.read_text(encoding="utf-8").splitlines()):
            continue
        for source in sorted(findings.parent.iterdir()):
            if source.name == "findings" or ".expected" in source.name:
                continue
            stem, dot, suffix = source.name.partition(".")
            expected = source.with_name(f"{stem}.expected{dot}{suffix}")
            firing.append((not expected.is_file(), source.stat().st_size, source, expected))
    return _smallest(firing, root)


def _smallest(firing: list[tuple[bool, int, Path, Path]], root: Path) -> tuple[str | None, str | None, str | None]:
    """The example among ``firing`` (reported-only last, then by size): path, before, after."""
    if not firing:
        return None, None, None
    _, _, source, expected = min(firing)
    after = expected.read_text(encoding="utf-8") if expected.is_file() else None
    return source.relative_to(root).as_posix(), source.read_text(encoding="utf-8"), after


def _example(folder: Path, code: str, root: Path) -> tuple[str | None, str | None, str | None]:
    """The smallest case where the rule fires, preferring one it rewrites."""
    firing = []
    for source in sorted(folder.glob("*.py")):
        if source.name.endswith(".expected.py"):
            continue
        findings = source.with_suffix(".findings")
        rows = findings.read_text(encoding="utf-8").splitlines() if findings.is_file() else []
        if not any(row.split("#", 1)[0].split()[1:2] == [code] for row in rows):
            continue
        expected = source.with_name(source.name[: -len(".py")] + ".expected.py")
        firing.append((not expected.is_file(), source.stat().st_size, source, expected))
    return _smallest(firing, root)


def load() -> dict[str, RuleDoc]:
    docs = from_checkout()
    if docs is not None:
        return docs
    data = json.loads(GENERATED.read_text(encoding="utf-8"))
    return {code: RuleDoc(**fields) for code, fields in data.items()}


def render_json(docs: dict[str, RuleDoc]) -> str:
    return json.dumps({code: asdict(doc) for code, doc in sorted(docs.items())}, indent=1, sort_keys=True) + "\n"


def main() -> None:
    """Regenerate rule_docs.json from the checkout."""
    docs = from_checkout()
    if docs is None:
        sys.exit("run this from a source checkout (docs/rules and fixtures/rules are needed)")
    GENERATED.write_text(render_json(docs), encoding="utf-8")
    print(f"wrote {GENERATED}")


if __name__ == "__main__":
    main()
