"""check --output-format: json, sarif (2.1.0 structure and rule metadata), github annotations."""

from __future__ import annotations

import json
from dataclasses import fields
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app
from gymmigrate.findings import Finding, FixKind
from gymmigrate.formats import (
    escape_data,
    escape_property,
    github_annotation,
    rule_help_uri,
)
from gymmigrate.rules import all_rules

runner = CliRunner()
LOOP = b'import gym\n\nenv = gym.make("CartPole-v1")\nenv.reset()\nobs, reward, done, info = env.step(0)\n'


@pytest.fixture
def loop_file(tmp_path: Path) -> Path:
    path = tmp_path / "loop.py"
    path.write_bytes(LOOP)
    return path


def check(path: Path, output_format: str) -> tuple[int, str]:
    result = runner.invoke(app, ["check", "--output-format", output_format, str(path)])
    return result.exit_code, result.stdout


def test_json_lists_every_finding_field(loop_file: Path) -> None:
    code, out = check(loop_file, "json")
    assert code == 1
    items = json.loads(out)
    assert {item["rule"] for item in items} == {"GM101", "GM301"}
    step = next(item for item in items if item["rule"] == "GM301")
    assert step["path"] == str(loop_file)
    assert (step["line"], step["column"], step["end_line"]) == (5, 0, 5)
    assert step["kind"] == "auto" and step["fix_available"] is True
    assert {f.name for f in fields(Finding) if not f.metadata.get("internal")} <= set(step), "every Finding field flows into JSON"
    assert "question" not in step  # the run's question key is internal


def test_json_of_a_clean_file_is_an_empty_list(tmp_path: Path) -> None:
    clean = tmp_path / "clean.py"
    clean.write_bytes(b"import gymnasium as gym\n")
    assert check(clean, "json") == (0, "[]\n")


def test_sarif_structure_and_rule_metadata(loop_file: Path) -> None:
    code, out = check(loop_file, "sarif")
    assert code == 1
    log = json.loads(out)
    assert log["version"] == "2.1.0" and "sarif" in log["$schema"]
    (run,) = log["runs"]
    driver = run["tool"]["driver"]
    assert driver["name"] == "gymmigrate"
    rules = driver["rules"]
    assert [rule["id"] for rule in rules] == [rule.code for rule in all_rules()]
    for rule in rules:
        assert rule["name"] and rule["shortDescription"]["text"] and rule["fullDescription"]["text"]
        assert rule["helpUri"] == rule_help_uri(rule["id"])
        assert rule["helpUri"].endswith(f"docs/rules/{rule['id']}.md")
    results = run["results"]
    assert {result["ruleId"] for result in results} == {"GM101", "GM301"}
    for result in results:
        assert rules[result["ruleIndex"]]["id"] == result["ruleId"]
        assert result["level"] in {"note", "warning", "error"}
        assert result["message"]["text"]
        location = result["locations"][0]["physicalLocation"]
        assert location["artifactLocation"]["uri"].endswith("loop.py")
        region = location["region"]
        assert region["startLine"] >= 1 and region["startColumn"] >= 1
        assert region["endLine"] >= region["startLine"]
    assert run["invocations"][0]["executionSuccessful"] is True


def test_every_rule_page_exists_for_its_help_uri() -> None:
    docs = Path(__file__).resolve().parent.parent / "docs" / "rules"
    assert all((docs / f"{rule.code}.md").is_file() for rule in all_rules())


def test_github_annotations(loop_file: Path) -> None:
    code, out = check(loop_file, "github")
    assert code == 1
    lines = out.splitlines()
    assert len(lines) == 2
    step = next(line for line in lines if "title=GM301" in line)
    path = str(loop_file).replace(":", "%3A").replace(",", "%2C")
    assert step.startswith(f"::warning file={path},line=5,col=1,endLine=5,endColumn=")
    assert ",title=GM301::GM301 " in step


def test_github_escaping() -> None:
    assert escape_data("50% done\r\nnext") == "50%25 done%0D%0Anext"
    assert escape_property("a:b,c%") == "a%3Ab%2Cc%25"
    finding = Finding(2, 4, "GM301", FixKind.AUTO, "x, y: 100%\nz", end_line=2, end_column=9)
    line = github_annotation("dir,1/a:b.py", finding)
    assert line == "::warning file=dir%2C1/a%3Ab.py,line=2,col=5,endLine=2,endColumn=10,title=GM301::GM301 x, y: 100%25%0Az"


def test_unknown_format_is_a_usage_error(loop_file: Path) -> None:
    result = runner.invoke(app, ["check", "--output-format", "xml", str(loop_file)])
    assert result.exit_code == 2 and "--output-format must be one of" in result.stderr


def test_errors_appear_in_every_format(tmp_path: Path) -> None:
    broken = tmp_path / "broken.py"
    broken.write_bytes(b"import gym\ndef (:\n")
    assert check(broken, "github")[1].startswith("::error file=")
    log = json.loads(check(broken, "sarif")[1])
    assert log["runs"][0]["invocations"][0]["executionSuccessful"] is False


def test_the_report_of_rewrite_carries_the_same_findings_list(loop_file: Path, tmp_path: Path) -> None:
    report = tmp_path / "report.json"
    expected = json.loads(check(loop_file, "json")[1])
    result = runner.invoke(app, ["rewrite", "--diff", "--report", str(report), str(loop_file)])
    assert result.exit_code == 1
    data = json.loads(report.read_text())
    assert {"files", "summary", "mode"} <= set(data), "the report keeps its shape"
    assert [(f["rule"], f["line"]) for f in data["findings"]] == [(f["rule"], f["line"]) for f in expected]


def test_notebook_findings_name_their_cell_and_no_line_of_the_json_file() -> None:
    notebook = Path(__file__).resolve().parent.parent / "fixtures" / "notebooks" / "multi_cell_loop.ipynb"
    items = json.loads(check(notebook, "json")[1])
    assert items and all(isinstance(item["cell"], int) for item in items)
    first = items[0]
    log = json.loads(check(notebook, "sarif")[1])
    result = log["runs"][0]["results"][0]
    assert "region" not in result["locations"][0]["physicalLocation"]
    assert result["message"]["text"].startswith(f"cell {first['cell'] + 1}, line {first['line']}: ")
    annotation = check(notebook, "github")[1].splitlines()[0]
    assert ",line=" not in annotation
    assert f"::{first['rule']} cell {first['cell'] + 1}, line {first['line']}: " in annotation
