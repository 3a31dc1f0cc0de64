"""The package's layers import only downwards, and nothing hides an import in a function.

Each module belongs to one layer (``LAYERS``, bottom first). A module may import its own
layer and the layers below it, never one above; the imports that run (not those under
``if TYPE_CHECKING:``) form no cycle, so one file's text passes through each layer once.
An import of gymmigrate inside a function body is allowed only in ``cli.py`` and
``commands.py``, where lazy imports keep ``gymmigrate --version``, ``--help`` and ``check``
fast (each command loads only what it uses), and of the *apply layer*: the
modules that need LibCST when imported (they derive classes from LibCST's, or import a
module that does), which a build loads when it first runs so that deciding, ``check``
and a run with nothing to change never load LibCST. Third-party modules may be imported
late anywhere (rich only for a terminal). A new
module must be placed in a layer here: the test names any module it cannot place.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "src" / "gymmigrate"

# Bottom first. A module belongs to the first entry whose prefix names it (longest prefix wins).
LAYERS: list[tuple[str, tuple[str, ...]]] = [
    ("base", ("gymmigrate", "gymmigrate.findings", "gymmigrate.source_text", "gymmigrate.selection",
              "gymmigrate.suppressions", "gymmigrate.safety", "gymmigrate.writes")),
    ("facts", ("gymmigrate.facts",)),
    ("options", ("gymmigrate.options",)),
    ("edits", ("gymmigrate.edits",)),
    ("rules", ("gymmigrate.rules",)),
    ("engine", ("gymmigrate.engine", "gymmigrate.rule_docs", "gymmigrate.config")),
    ("sources", ("gymmigrate.sources", "gymmigrate.dependencies")),
    ("process", ("gymmigrate.process",)),
    ("runner", ("gymmigrate.runner", "gymmigrate.files")),
    ("report", ("gymmigrate.formats", "gymmigrate.report", "gymmigrate.rules_listing")),
    ("workflow", ("gymmigrate.workflow",)),
    ("smoke", ("gymmigrate.smoke",)),
    ("commands", ("gymmigrate.commands",)),
    ("cli", ("gymmigrate.cli", "gymmigrate.typer_app", "gymmigrate.__main__")),
]
LAZY_IMPORTS_ALLOWED = {"gymmigrate.cli", "gymmigrate.commands"}


def _loads_libcst(path: Path) -> bool:
    """Does importing this module itself import LibCST (``import libcst`` at module level, or
    a top-level class derived from one of its classes)?"""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in tree.body:
        if isinstance(node, ast.Import) and any(alias.name.split(".")[0] == "libcst" for alias in node.names):
            return True
        if isinstance(node, ast.ImportFrom) and (node.module or "").split(".")[0] == "libcst":
            return True
        if isinstance(node, ast.ClassDef):
            for base in node.bases:
                if isinstance(base, ast.Attribute) and isinstance(base.value, ast.Name) and base.value.id in ("cst", "libcst"):
                    return True
    return False


@dataclass(frozen=True)
class Import:
    source: str
    target: str
    line: int
    type_only: bool
    in_function: bool


def module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def all_modules() -> dict[str, Path]:
    return {module_name(path): path for path in sorted(PACKAGE.rglob("*.py"))}


def layer_of(module: str) -> int | None:
    best: tuple[int, int] | None = None  # (prefix length, rank)
    for rank, (_, prefixes) in enumerate(LAYERS):
        for prefix in prefixes:
            if module == prefix or (prefix != "gymmigrate" and module.startswith(prefix + ".")):
                if best is None or len(prefix) > best[0]:
                    best = (len(prefix), rank)
    return None if best is None else best[1]


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def imports_of(module: str, path: Path, modules: dict[str, Path]) -> list[Import]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    is_package = path.name == "__init__.py"
    found: list[Import] = []

    def resolve(base: str, names: list[str]) -> list[str]:
        # ``from pkg import sub`` imports the module pkg.sub; ``from pkg import name`` imports pkg.
        targets = {f"{base}.{n}" if f"{base}.{n}" in modules else base for n in names}
        return sorted(t for t in targets if t in modules)

    def visit(node: ast.AST, type_only: bool, in_function: bool) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.If) and _is_type_checking(child.test):
                for statement in child.body:
                    visit_statement(statement, True, in_function)
                for statement in child.orelse:
                    visit_statement(statement, type_only, in_function)
                continue
            visit_statement(child, type_only, in_function)

    def visit_statement(node: ast.AST, type_only: bool, in_function: bool) -> None:
        targets: list[str] = []
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names if alias.name.split(".")[0] == "gymmigrate"]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                parts = module.split(".") if is_package else module.split(".")[:-1]
                parts = parts[: len(parts) - (node.level - 1)]
                base = ".".join(parts + ([node.module] if node.module else []))
            else:
                base = node.module or ""
            if base.split(".")[0] == "gymmigrate":
                targets = resolve(base, [alias.name for alias in node.names])
        for target in targets:
            found.append(Import(module, target, node.lineno, type_only, in_function))  # type: ignore[attr-defined]
        inner = in_function or isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))
        visit(node, type_only, inner)

    visit(tree, False, False)
    return found


@lru_cache(maxsize=1)
def every_import() -> tuple[Import, ...]:
    modules = all_modules()
    return tuple(imp for module, path in modules.items() for imp in imports_of(module, path, modules))


def test_every_module_has_a_layer() -> None:
    assert [m for m in all_modules() if layer_of(m) is None] == []


def test_imports_run_only_downwards() -> None:
    upwards = [
        f"{imp.source} (line {imp.line}) imports {imp.target}: {LAYERS[layer_of(imp.source)][0]} < {LAYERS[layer_of(imp.target)][0]}"  # type: ignore[index]
        for imp in every_import()
        if imp.target != imp.source and (layer_of(imp.target) or 0) > (layer_of(imp.source) or 0)
    ]
    assert upwards == []


@lru_cache(maxsize=1)
def apply_layer() -> frozenset[str]:
    """Modules that load LibCST on import, directly or through a module-level import."""
    modules = all_modules()
    found = {module for module, path in modules.items() if _loads_libcst(path)}
    while True:
        more = {imp.source for imp in every_import() if not imp.type_only and not imp.in_function and imp.target in found}
        if more <= found:
            return frozenset(found)
        found |= more


def test_no_gymmigrate_import_inside_a_function_outside_the_cli() -> None:
    hidden = [
        f"{imp.source} (line {imp.line}) imports {imp.target} in a function"
        for imp in every_import()
        if imp.in_function and imp.source not in LAZY_IMPORTS_ALLOWED and imp.target not in apply_layer()
    ]
    assert hidden == []


def test_only_the_apply_layer_loads_libcst() -> None:
    """What deciding imports never loads LibCST: the engine, every rule family, the process."""
    expected = {
        "gymmigrate.edits.apply",
        "gymmigrate.edits.locate",
        "gymmigrate.edits.splice",
        "gymmigrate.rules.custom_env.cst_edits",
        "gymmigrate.rules.custom_env.cst_queries",
        "gymmigrate.rules.custom_env.rebuild",
        "gymmigrate.rules.wrappers.cst_builds",
    }
    assert set(apply_layer()) == expected


def test_the_imports_that_run_form_no_cycle() -> None:
    graph: dict[str, set[str]] = {}
    for imp in every_import():
        if not imp.type_only and imp.target != imp.source:
            graph.setdefault(imp.source, set()).add(imp.target)
    cycles = _cycles(graph)
    assert cycles == [], "\n".join(" -> ".join(cycle) for cycle in cycles)


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Each strongly connected component of more than one module (Tarjan), as a sorted list."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []
    counter = 0

    def connect(node: str) -> None:
        nonlocal counter
        index[node] = low[node] = counter
        counter += 1
        stack.append(node)
        on_stack.add(node)
        for successor in sorted(graph.get(node, ())):
            if successor not in index:
                connect(successor)
                low[node] = min(low[node], low[successor])
            elif successor in on_stack:
                low[node] = min(low[node], index[successor])
        if low[node] == index[node]:
            component = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.append(member)
                if member == node:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for node in sorted(graph):
        if node not in index:
            connect(node)
    return found


def test_the_checker_sees_an_upward_import(tmp_path: Path) -> None:
    """The walk itself: an import under TYPE_CHECKING, in a function, and a relative one."""
    source = (
        "from typing import TYPE_CHECKING\n"
        "from . import engine\n"
        "if TYPE_CHECKING:\n"
        "    from gymmigrate.cli import app\n"
        "def f():\n"
        "    from gymmigrate.process import Status\n"
    )
    path = PACKAGE / "facts" / "module.py"
    fake = tmp_path / "m.py"
    fake.write_text(source)
    modules = all_modules()
    found = imports_of("gymmigrate.facts.module", fake, modules)
    assert {(i.target, i.type_only, i.in_function) for i in found} == {
        ("gymmigrate.facts", False, False),  # ``from . import engine``: no facts.engine, so the package
        ("gymmigrate.cli", True, False),
        ("gymmigrate.process", False, True),
    }
    assert path.exists()


def test_the_pipeline_runs_every_family_after_those_whose_notes_it_reads() -> None:
    from gymmigrate.rules import PIPELINE, registered_families

    order = [family.__name__ for family in registered_families()]
    assert order == [spec.name for spec in PIPELINE]
    for family in registered_families():
        for writer in family.after:
            assert order.index(writer) < order.index(family.__name__), (family.__name__, writer)


def test_a_pipeline_that_runs_a_reader_first_is_refused() -> None:
    import pytest

    from gymmigrate.rules import PIPELINE
    from gymmigrate.rules.base import registered_families, set_pipeline

    swapped = list(PIPELINE)
    names = [spec.name for spec in swapped]
    reader, writer = names.index("WrapperClasses"), names.index("StepDone")
    swapped[reader], swapped[writer] = swapped[writer], swapped[reader]
    try:
        set_pipeline(tuple(swapped))
        with pytest.raises(RuntimeError, match="WrapperClasses reads the notes of StepDone"):
            registered_families()
        set_pipeline(tuple(spec for spec in PIPELINE if spec.name != "Imports"))
        with pytest.raises(RuntimeError, match="families not listed"):
            registered_families()
    finally:
        set_pipeline(PIPELINE)
