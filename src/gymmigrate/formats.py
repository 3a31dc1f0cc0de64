"""Findings for machines: ``check --output-format json|sarif|github`` (text is
``report.print_findings``).

- ``json``: a list, one object per finding: every ``Finding`` field (``to_json``) plus
  ``path``, ``cell_number`` (a notebook's cell counted from 1, as messages count it; ``cell``
  is the 0-based index) and ``fix_available``.
- ``sarif``: SARIF 2.1.0, one run, with each rule's metadata (``tool.driver.rules``) so
  GitHub code scanning shows its title, description and a link to its page.
- ``github``: one workflow command per finding
  (``::warning file=...,line=...,col=...,endLine=...,endColumn=...,title=GM301::message``),
  which GitHub Actions turns into annotations on the pull request.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, TextIO

from gymmigrate import __version__
from gymmigrate.rules import all_rules

if TYPE_CHECKING:
    from gymmigrate.findings import Finding
    from gymmigrate.process import FileResult

FORMATS = ("text", "json", "sarif", "github")
# The one place the project's address is written: rule pages link from here.
REPOSITORY_URL = "https://github.com/gymmigrate/gymmigrate"
DOCS_URL = f"{REPOSITORY_URL}/blob/main/docs/rules"
SARIF_SCHEMA = "https://json.schemastore.org/sarif-2.1.0.json"


def rule_help_uri(code: str) -> str:
    return f"{DOCS_URL}/{code}.md"


def finding_json(path: str, finding: Finding) -> dict[str, object]:
    # ``cell`` is the 0-based index in ``nb["cells"]`` (kept as it was for its readers);
    # ``cell_number`` counts from 1, as the messages and the text output do ("cell 15").
    cell_number = finding.cell + 1 if finding.cell is not None else None
    return {"path": path, **finding.to_json(), "cell_number": cell_number, "fix_available": finding.is_change}


def findings_json(results: Sequence[FileResult]) -> list[dict[str, object]]:
    return [finding_json(result.path, finding) for result in results for finding in result.findings]


def write_json(results: Sequence[FileResult], stream: TextIO) -> None:
    import json  # text findings (a pre-commit hook's) need no json

    stream.write(json.dumps(findings_json(results), indent=2) + "\n")


# -- SARIF ---------------------------------------------------------------------------------

_LEVELS = {"auto": "warning", "assist": "warning", "flag": "warning"}


def sarif(results: Sequence[FileResult]) -> dict[str, object]:
    rules = all_rules()
    index = {rule.code: position for position, rule in enumerate(rules)}
    return {
        "$schema": SARIF_SCHEMA,
        "version": "2.1.0",
        "runs": [
            {
                "tool": {
                    "driver": {
                        "name": "gymmigrate",
                        "version": __version__,
                        "informationUri": REPOSITORY_URL,
                        "rules": [
                            {
                                "id": rule.code,
                                "name": rule.title,
                                "shortDescription": {"text": rule.title},
                                "fullDescription": {"text": rule.summary},
                                "helpUri": rule_help_uri(rule.code),
                                "properties": {"fix": rule.kind.value},
                            }
                            for rule in rules
                        ],
                    }
                },
                "results": [
                    _sarif_result(result.path, finding, index)
                    for result in results
                    for finding in result.findings
                ],
                "invocations": [
                    {
                        "executionSuccessful": not any(r.error for r in results),
                        "toolExecutionNotifications": [
                            {"level": "error", "message": {"text": f"{r.path}: {r.error}"}} for r in results if r.error
                        ],
                    }
                ],
            }
        ],
    }


def _in_cell(finding: Finding) -> str:
    """A notebook finding's line counts within its cell, not within the .ipynb file: the
    place goes into the message and the location is the file alone."""
    return f"cell {finding.cell + 1}, line {finding.line}: " if finding.cell is not None else ""


def _sarif_result(path: str, finding: Finding, index: dict[str, int]) -> dict[str, object]:
    location: dict[str, object] = {"artifactLocation": {"uri": _uri(path)}}
    if finding.cell is None:
        region: dict[str, object] = {"startLine": finding.line, "startColumn": finding.column + 1}
        if finding.end_line is not None and finding.end_column is not None:
            region["endLine"] = finding.end_line
            region["endColumn"] = finding.end_column + 1
        location["region"] = region
    result: dict[str, object] = {
        "ruleId": finding.rule,
        "level": _LEVELS[finding.kind.value],
        "message": {"text": _in_cell(finding) + finding.message},
        "locations": [{"physicalLocation": location}],
        "properties": {"kind": finding.kind.value, "fixAvailable": finding.is_change},
    }
    if finding.rule in index:
        result["ruleIndex"] = index[finding.rule]
    if finding.cell is not None:
        result["properties"]["cell"] = finding.cell  # type: ignore[index]
    return result


def _uri(path: str) -> str:
    from urllib.parse import quote

    return quote(path.replace("\\", "/").removeprefix("./"), safe="/:")


def write_sarif(results: Sequence[FileResult], stream: TextIO) -> None:
    import json

    stream.write(json.dumps(sarif(results), indent=2) + "\n")


# -- GitHub workflow commands --------------------------------------------------------------


def escape_data(text: str) -> str:
    """A workflow command's message: %, CR and LF are escaped."""
    return text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def escape_property(text: str) -> str:
    """A workflow command's property value: also ':' and ','."""
    return escape_data(text).replace(":", "%3A").replace(",", "%2C")


def github_annotation(path: str, finding: Finding) -> str:
    properties = [("file", path)]
    if finding.cell is None:
        properties += [("line", str(finding.line)), ("col", str(finding.column + 1))]
        if finding.end_line is not None and finding.end_column is not None:
            properties += [("endLine", str(finding.end_line)), ("endColumn", str(finding.end_column + 1))]
    properties.append(("title", finding.rule))
    joined = ",".join(f"{name}={escape_property(value)}" for name, value in properties)
    return f"::warning {joined}::{escape_data(f'{finding.rule} {_in_cell(finding)}{finding.message}')}"


def write_github(results: Sequence[FileResult], stream: TextIO) -> None:
    for result in results:
        for finding in result.findings:
            stream.write(github_annotation(result.path, finding) + "\n")
        if result.error:
            stream.write(f"::error file={escape_property(result.path)}::{escape_data(result.error)}\n")
