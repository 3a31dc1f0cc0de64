"""The rule index says where each rule lives: README's "Rules" table and docs/rules/README.md
name, for every rule, the module that decides it. Both went stale once when rule families
became packages (`rules/custom_env.py` became `rules/custom_env/`), so a reader sent there
found nothing; these tests tie the paths the docs name to the package as it is."""

from __future__ import annotations

import re
from functools import cache
from pathlib import Path

import pytest

from gymmigrate.rules import all_rules

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "src" / "gymmigrate"
INDEXES = (ROOT / "README.md", ROOT / "docs" / "rules" / "README.md")
# every page that names modules by their path in the package
PAGES = (ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md")), PACKAGE / "rules" / "README.md")

_ROW = re.compile(r"^\| \[(?P<code>[A-Z]+\d+)\]\([^)]*\) \| .+? \| \w+ \| (?P<where>.*?) \|$", re.M)
# a `rules/...` path that is not part of another one (`fixtures/rules/GM101/`, `docs/rules/`)
_RULES_PATH = re.compile(r"(?<![\w/.-])rules/[\w/.]*")


def _relative(path: Path) -> str:
    return str(path.relative_to(ROOT))


@cache
def _source(named: str) -> str:
    """The text of a module the docs name, or of every module under a folder they name."""
    path = PACKAGE / named
    if named.endswith("/"):
        return "\n".join(module.read_text(encoding="utf-8") for module in sorted(path.rglob("*.py")))
    return path.read_text(encoding="utf-8")


def _rows(index: Path) -> dict[str, list[str]]:
    return {m["code"]: re.findall(r"`([^`]+)`", m["where"]) for m in _ROW.finditer(index.read_text(encoding="utf-8"))}


def _exists(named: str) -> bool:
    path = PACKAGE / named
    return path.is_dir() if named.endswith("/") else path.is_file()


def test_every_rules_path_in_the_docs_exists() -> None:
    missing = []
    for page in PAGES:
        named = {match.rstrip(".") for match in _RULES_PATH.findall(page.read_text(encoding="utf-8"))}
        # a link to a rule page relative to docs/ (`rules/GM111.md`) is not a module path
        missing += [f"{_relative(page)}: {path}" for path in sorted(named) if not path.endswith(".md") and not _exists(path)]
    assert not missing, "modules named in the docs that are not under src/gymmigrate/:\n" + "\n".join(missing)


@pytest.mark.parametrize("index", INDEXES, ids=_relative)
def test_every_rule_has_a_row_naming_the_module_that_decides_it(index: Path) -> None:
    rows = _rows(index)
    assert sorted({rule.code for rule in all_rules()} - set(rows)) == [], f"rules without a row in {_relative(index)}"
    wrong = []
    for code, where in rows.items():
        if not where:
            wrong.append(f"{code}: names no module")
        elif missing := [named for named in where if not _exists(named)]:
            wrong.append(f"{code}: {missing} not under src/gymmigrate/")
        elif silent := [named for named in where if code not in _source(named)]:
            wrong.append(f"{code}: {silent} never mention it")
        elif not any(re.search(rf"[\"']{code}[\"']", _source(named)) for named in where):
            # a docstring that mentions the code is not where the rule is declared or reported
            wrong.append(f"{code}: none of {where} declares or reports it")
    assert not wrong, f"{_relative(index)}, column 'where':\n" + "\n".join(wrong)
