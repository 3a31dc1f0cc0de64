"""Read the before/after fixture pairs under ``fixtures/rules/<RULE>/``; migrate a copy of a
fixture project (``migrated_project``).

Each case is ``<name>.py`` (the input), an optional ``<name>.expected.py`` (the expected
output; when absent the case is a no-op and the output must equal the input byte for
byte) and a mandatory ``<name>.findings``: one ``LINE RULE KIND [TIER]`` per expected
finding (line in the input, kind auto/assist/flag), ``#`` comments allowed, empty for
none. TIER (note/review) is written only where it differs from what the kind implies
(an assist rewrite shown as a note).
"""

from __future__ import annotations

import json
import shutil
from dataclasses import dataclass
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures"
RULE_FIXTURES = FIXTURES / "rules"


@dataclass(frozen=True)
class Case:
    rule_dir: str
    name: str
    source: Path
    expected: Path | None
    findings: Path

    @property
    def id(self) -> str:
        return f"{self.rule_dir}/{self.name}"

    @property
    def is_noop(self) -> bool:
        return self.expected is None

    def expected_findings(self) -> list[tuple]:
        rows: list[tuple] = []
        for raw in self.findings.read_text(encoding="utf-8").splitlines():
            line = raw.split("#", 1)[0].strip()
            if not line:
                continue
            number, rule, kind, *tier = line.split()
            rows.append((int(number), rule, kind, *tier))
        return sorted(rows)


def finding_row(finding) -> tuple:
    """A finding as a ``.findings`` row: the tier only where the kind does not imply it."""
    from gymmigrate.findings import Tier

    row: tuple = (finding.line, finding.rule, finding.kind.value)
    return row if finding.tier is Tier.of(finding.kind) else (*row, finding.tier.value)


def collect_cases() -> list[Case]:
    cases = []
    for source in sorted(RULE_FIXTURES.glob("*/*.py")):
        if source.name.endswith(".expected.py"):
            continue
        stem = source.name[: -len(".py")]
        expected = source.with_name(stem + ".expected.py")
        cases.append(
            Case(
                rule_dir=source.parent.name,
                name=stem,
                source=source,
                expected=expected if expected.exists() else None,
                findings=source.with_name(stem + ".findings"),
            )
        )
    return cases


def migrated_project(tmp_path: Path, name: str) -> tuple[Path, list[tuple[str, int, str]]]:
    """A copy of ``fixtures/<name>`` (``tmp_path/project``) after one ``rewrite --report`` in
    this process, with its review items as ``(path in the project, line, rule)``, sorted:
    the fixture itself stays the legacy input of every test."""
    project = tmp_path / "project"
    shutil.copytree(FIXTURES / name, project)
    report = tmp_path / "report.json"
    result = CliRunner().invoke(app, ["rewrite", "--report", str(report), str(project)])
    assert result.exit_code == 0, result.output
    review = [
        (Path(file["path"]).relative_to(project).as_posix(), f["line"], f["rule"])
        for file in json.loads(report.read_text())["files"]
        for f in file["review"]
    ]
    return project, sorted(review)
