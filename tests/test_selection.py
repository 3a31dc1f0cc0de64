"""Rule selection: --select/--ignore/--extend-*, by code or prefix; a deselected rule
neither reports nor fixes."""

from __future__ import annotations

import ast
import builtins
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app
from gymmigrate.engine import lint_source, transform_source
from gymmigrate.options import RewriteOptions
from gymmigrate.rules import all_rules
from gymmigrate.selection import Selection, SelectionError
from gymmigrate.source_text import TransformError
from tests.fixture_cases import collect_cases

runner = CliRunner()
CODES = ["GM101", "GM103", "GM201", "GM301", "GM302", "PZ101"]
LOOP = b"""import gym

env = gym.make("CartPole-v1")
env.seed(0)
obs = env.reset()
obs, reward, done, info = env.step(0)
"""


def allowed(**selectors: object) -> set[str]:
    selection = Selection.from_selectors(codes=CODES, **selectors)  # type: ignore[arg-type]
    return {code for code in CODES if selection.allows(code)}


def test_default_selects_every_rule() -> None:
    assert allowed() == set(CODES)
    assert Selection.from_selectors(codes=CODES).every_rule


def test_select_by_prefix_and_code() -> None:
    assert allowed(select=["GM3"]) == {"GM301", "GM302"}
    assert allowed(select=["GM101", "PZ"]) == {"GM101", "PZ101"}


def test_more_specific_selector_wins_and_ignore_wins_ties() -> None:
    assert allowed(select=["GM3"], ignore=["GM302"]) == {"GM301"}
    assert allowed(select=["GM302"], ignore=["GM3"]) == {"GM302"}
    assert allowed(select=["GM301"], ignore=["GM301"]) == set()


def test_extend_select_and_extend_ignore_add_to_the_base() -> None:
    assert allowed(select=["GM1"], extend_select=["GM301"]) == {"GM101", "GM103", "GM301"}
    assert allowed(extend_ignore=["GM1", "PZ"]) == {"GM201", "GM301", "GM302"}
    assert allowed(ignore=["GM2"], extend_ignore=["GM3"]) == {"GM101", "GM103", "PZ101"}


@pytest.mark.parametrize("selector", ["GM999", "XY", "gm"])
def test_unknown_selector_is_an_error(selector: str) -> None:
    with pytest.raises(SelectionError, match="unknown rule code or prefix"):
        Selection.from_selectors(select=[selector], codes=CODES)


def options(**selectors: object) -> RewriteOptions:
    return RewriteOptions(selection=Selection.from_selectors(codes=[r.code for r in all_rules()], **selectors))  # type: ignore[arg-type]


def test_deselected_rule_neither_reports_nor_fixes() -> None:
    full = transform_source(LOOP)
    assert {"GM101", "GM203", "GM301"} <= {f.rule for f in full.findings}
    only_imports = transform_source(LOOP, options=options(select=["GM1"]))
    assert {f.rule for f in only_imports.findings} == {"GM101"}
    assert only_imports.rewritten == LOOP.replace(b"import gym\n", b"import gymnasium as gym\n")
    without_step = transform_source(LOOP, options=options(ignore=["GM3"]))
    assert "GM301" not in {f.rule for f in without_step.findings}
    assert b"obs, reward, done, info = env.step(0)" in without_step.rewritten
    assert b"env.reset(seed=0)" in without_step.rewritten


def test_check_agrees_with_rewrite_under_selection() -> None:
    findings, would_change = lint_source(LOOP, options=options(select=["GM3"]))
    rewritten = transform_source(LOOP, options=options(select=["GM3"]))
    assert [f.rule for f in findings] == [f.rule for f in rewritten.findings] == ["GM301"]
    assert would_change and rewritten.changed


def test_family_without_selected_rule_is_not_run() -> None:
    findings, would_change = lint_source(LOOP, options=options(select=["GM9"]))
    assert findings == [] and not would_change


def _unbound_names(source: bytes) -> set[str]:
    """Names read that nothing in the module binds (a crude, scope-blind check: enough to
    catch a kept edit that reads a name only a dropped edit would have made)."""
    tree = ast.parse(source)
    bound = set(dir(builtins))
    read = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Name):
            (read if isinstance(node.ctx, ast.Load) else bound).add(node.id)
        elif isinstance(node, ast.arg):
            bound.add(node.arg)
        elif isinstance(node, ast.alias):
            bound.add((node.asname or node.name).split(".")[0])
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            bound.add(node.name)
        elif isinstance(node, ast.ExceptHandler) and node.name:
            bound.add(node.name)
    return read - bound


# Changes that another rule's edit carries out (PZ109: the spaces import moves with
# GM101-GM103), so selecting the rule alone reports them without changing the file.
CARRIED_BY_OTHERS = {"PZ109"}


@pytest.mark.parametrize("case", collect_cases(), ids=lambda case: case.id)
def test_each_rule_alone_and_each_rule_left_out(case) -> None:
    """On every fixture: selecting one rule reports only it and changes the file exactly
    when it makes a change; leaving one rule out reports none of it, and the file changes
    exactly when another rule does; no kept edit reads a name only a dropped one makes.
    This holds the attribution of edits to findings (``Plan.drop_findings``) and the
    coupled families (``edits.filtering.COUPLED_FAMILIES``) to every rule's real decisions.
    A half-migrated result the rules would change again is refused, file unchanged."""
    source = case.source.read_bytes()
    full = transform_source(source, str(case.source))
    unbound = _unbound_names(source) | _unbound_names(full.rewritten)
    for rule in sorted({f.rule for f in full.findings}):
        for selectors in ({"select": [rule]}, {"ignore": [rule]}):
            try:
                result = transform_source(source, str(case.source), options(**selectors))
            except TransformError as exc:
                assert "oscillates" in str(exc) or "does not settle" in str(exc), f"{selectors}: {exc}"
                continue
            rules = {f.rule for f in result.findings}
            assert rules <= {rule} if "select" in selectors else rule not in rules
            changes = any(f.is_change for f in result.findings)
            if rule in CARRIED_BY_OTHERS and "select" in selectors:
                assert not result.changed or changes, selectors
            else:
                assert result.changed == changes, selectors
            assert not _unbound_names(result.rewritten) - unbound, selectors


def test_every_code_and_family_prefix_is_accepted() -> None:
    for rule in all_rules():
        Selection.from_selectors(select=[rule.code, rule.code[:3]], codes=[r.code for r in all_rules()])


# -- the command line ---------------------------------------------------------------------


@pytest.fixture
def loop_file(tmp_path: Path) -> Path:
    path = tmp_path / "loop.py"
    path.write_bytes(LOOP)
    return path


def test_check_select_prefix(loop_file: Path) -> None:
    result = runner.invoke(app, ["check", "--select", "GM3", str(loop_file)])
    assert result.exit_code == 1
    assert {line.split()[1] for line in result.stdout.splitlines()} == {"GM301"}


def test_check_ignore_and_extend_comma_lists(loop_file: Path) -> None:
    result = runner.invoke(app, ["check", "--ignore", "GM3,GM2", "--extend-ignore", "GM103", str(loop_file)])
    assert {line.split()[1] for line in result.stdout.splitlines()} == {"GM101"}
    result = runner.invoke(app, ["check", "--select", "GM1", "--extend-select", "GM301", str(loop_file)])
    assert {line.split()[1] for line in result.stdout.splitlines()} == {"GM101", "GM301"}


def test_rewrite_select_changes_only_that_rule(loop_file: Path) -> None:
    result = runner.invoke(app, ["rewrite", "--select", "GM101", str(loop_file)])
    assert result.exit_code == 0, result.output
    assert loop_file.read_bytes() == LOOP.replace(b"import gym\n", b"import gymnasium as gym\n")


@pytest.mark.parametrize("command", ["check", "rewrite"])
def test_unknown_code_is_a_usage_error(loop_file: Path, command: str) -> None:
    result = runner.invoke(app, [command, "--select", "GM999", str(loop_file)])
    assert result.exit_code == 2
    assert "unknown rule code or prefix 'GM999'" in result.stderr
    assert loop_file.read_bytes() == LOOP
