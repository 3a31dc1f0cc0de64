"""Rule selection: --select/--ignore/--extend-*, by code or prefix; a deselected rule
neither reports nor fixes."""

from __future__ import annotations

import ast
import builtins
import io
import symtable
import tokenize
from functools import cache
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app
from gymmigrate.engine import Transformed, lint_source, transform_source
from gymmigrate.findings import FixKind
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


# Names a module has without binding them.
_MODULE_NAMES = frozenset(dir(builtins)) | {"__file__", "__name__", "__doc__", "__spec__", "__loader__", "__package__", "__builtins__", "__path__"}


def _unbound_names(source: bytes) -> set[tuple[str, str]]:
    """``(scope, name)`` of each name a scope reads that nothing it can see binds: not the
    scope itself, an enclosing function, the module or the builtins (by ``symtable``, as
    Python resolves them; a method does not see its class body). A kept edit that reads a
    name only a left-out edit makes (``options``, a parameter another rule adds to the
    signature) shows here, whatever other scope binds the name. A star import binds
    anything: such a module is not checked."""
    tree = ast.parse(source)
    if any(isinstance(node, ast.ImportFrom) and node.names[0].name == "*" for node in ast.walk(tree)):
        return set()
    encoding, _ = tokenize.detect_encoding(io.BytesIO(source).readline)
    module = symtable.symtable(source.decode(encoding), "<fixture>", "exec")
    tables = [module]
    for table in tables:
        tables.extend(table.get_children())
    bound = set(_MODULE_NAMES)
    for table in tables:
        for symbol in table.get_symbols():
            if table is module and (symbol.is_assigned() or symbol.is_imported() or symbol.is_namespace()):
                bound.add(symbol.get_name())
            elif symbol.is_declared_global() and symbol.is_assigned():
                bound.add(symbol.get_name())
    unbound = set()

    def visit(table: symtable.SymbolTable, scope: str) -> None:
        for symbol in table.get_symbols():
            if symbol.is_referenced() and (table is module or symbol.is_global()) and symbol.get_name() not in bound:
                unbound.add((scope, symbol.get_name()))
        for child in table.get_children():
            visit(child, f"{scope}.{child.get_name()}" if scope else child.get_name())

    visit(module, "")
    return unbound


# Changes that another rule's edit carries out (PZ109: the spaces import moves with
# GM101-GM103), so selecting the rule alone reports them without changing the file.
CARRIED_BY_OTHERS = {"PZ109"}


@cache
def _migrated(path: Path) -> tuple[bytes, Transformed, frozenset[tuple[str, str]]]:
    """A fixture's input, its whole migration, and the names either leaves unbound (a name
    the whole migration leaves unbound, reported, is not the selection's doing)."""
    source = path.read_bytes()
    full = transform_source(source, str(path))
    return source, full, frozenset(_unbound_names(source) | _unbound_names(full.rewritten))


def _alone(case, selectors: dict[str, list[str]]) -> Transformed | None:
    """The fixture migrated under ``selectors``; None where the half-migrated result would
    change again and is refused, file unchanged."""
    try:
        return transform_source(case.source.read_bytes(), str(case.source), options(**selectors))
    except TransformError as exc:
        assert "oscillates" in str(exc) or "does not settle" in str(exc), f"{selectors}: {exc}"
        return None


@pytest.mark.parametrize("case", collect_cases(), ids=lambda case: case.id)
def test_each_rule_alone_leaves_no_name_unbound(case) -> None:
    """On every fixture, each rule selected alone (``--select CODE``): the output parses,
    reports only that rule, changes the file exactly when the rule makes a change, and
    reads no name unbound in its scope that the input (and the whole migration) did not.
    A change that only makes sense beside a change of a rule left out (a body reading the
    ``options`` another rule adds to the signature) is left out with it and reported as
    not rewritten (``edits.filtering``): never half made."""
    _, full, unbound = _migrated(case.source)
    for rule in sorted({f.rule for f in full.findings}):
        result = _alone(case, {"select": [rule]})
        if result is None:
            continue
        ast.parse(result.rewritten)
        assert {f.rule for f in result.findings} <= {rule}
        changes = any(f.is_change for f in result.findings)
        if rule in CARRIED_BY_OTHERS:
            assert not result.changed or changes, rule
        else:
            assert result.changed == changes, rule
        assert not _unbound_names(result.rewritten) - unbound, rule


@pytest.mark.parametrize("case", collect_cases(), ids=lambda case: case.id)
def test_each_rule_left_out(case) -> None:
    """On every fixture, each rule left out (``--ignore CODE``): none of it is reported, the
    file changes exactly when another rule changes it, and no kept edit reads a name only a
    dropped one makes. With the test above, this holds the attribution of edits to findings
    (``Plan.drop_findings``) and the couplings (``edits.filtering``) to every rule's real
    decisions."""
    _, full, unbound = _migrated(case.source)
    for rule in sorted({f.rule for f in full.findings}):
        result = _alone(case, {"ignore": [rule]})
        if result is None:
            continue
        assert rule not in {f.rule for f in result.findings}
        assert result.changed == any(f.is_change for f in result.findings), rule
        assert not _unbound_names(result.rewritten) - unbound, rule


def test_a_reset_reading_options_goes_with_the_signature_that_gives_them() -> None:
    """``--select GM207`` on an env whose reset gets ``seed``/``options`` from GM501: the
    reads from ``options`` would be a NameError without GM501's signature, so the reset and,
    with it, every move of the file's contract are left as they are and reported; selected
    together, both are made."""
    path = Path(__file__).resolve().parent.parent / "fixtures/rules/GM207/env_reset_gets_options.py"
    source = path.read_bytes()
    alone = transform_source(source, str(path), options(select=["GM207"]))
    assert alone.rewritten == source
    assert {(f.line, f.kind) for f in alone.findings} == {(line, FixKind.FLAG) for line in (6, 13, 20, 21)}
    reset = next(f for f in alone.findings if f.line == 6)
    assert reset.message.startswith(
        "left as it is: it reads the `seed` and `options` parameters GM501 gives this env's reset, which this run leaves out"
    )
    assert "GM207's changes at lines 6, 20, 21" in next(f for f in alone.findings if f.line == 13).message
    both = transform_source(source, str(path), options(select=["GM207", "GM501"]))
    assert b'def reset(self, level=0, *, seed=None, options=None):\n        super().reset(seed=seed)\n        level = (options or {}).get("level", level)' in both.rewritten
    assert {f.kind for f in both.findings} == {FixKind.AUTO}


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
