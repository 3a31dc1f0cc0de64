"""Computes, from the installed Gymnasium, the table in ``gymmigrate/rules/gymnasium_api.py``.

``python -m tests.gymnasium_api_table`` prints the table (to paste after an upgrade);
``tests/test_import_targets.py`` checks the shipped table against it.
"""

from __future__ import annotations

import ast
import os
from pathlib import Path


def installed_modules() -> dict[str, Path]:
    import gymnasium

    root = Path(gymnasium.__file__).parent
    modules: dict[str, Path] = {}
    for folder, subfolders, files in os.walk(root):
        subfolders[:] = sorted(s for s in subfolders if s != "__pycache__")
        package = ".".join(Path(folder).relative_to(root.parent).parts)
        for file in files:
            if file.endswith(".py"):
                modules[package if file == "__init__.py" else f"{package}.{file[:-3]}"] = Path(folder) / file
    return modules


def public_names(path: Path) -> set[str]:
    """Names a module binds at its top level (defs, classes, assignments, imports, ``__all__``)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    names: set[str] = set()

    def visit(statements: list[ast.stmt]) -> None:
        for node in statements:
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                names.add(node.name)
            elif isinstance(node, (ast.Assign, ast.AnnAssign)):
                targets = node.targets if isinstance(node, ast.Assign) else [node.target]
                for target in targets:
                    names.update(n.id for n in ast.walk(target) if isinstance(n, ast.Name))
                    if isinstance(target, ast.Name) and target.id == "__all__" and isinstance(node.value, (ast.List, ast.Tuple)):
                        names.update(e.value for e in node.value.elts if isinstance(e, ast.Constant))
            elif isinstance(node, (ast.Import, ast.ImportFrom)):
                for alias in node.names:
                    if alias.name != "*":
                        names.add(alias.asname or alias.name.split(".")[0])
            elif isinstance(node, (ast.If, ast.Try)):
                visit(node.body)
                for handler in getattr(node, "handlers", ()):
                    visit(handler.body)
                visit(node.orelse)
                visit(getattr(node, "finalbody", []))

    visit(tree.body)
    return {name for name in names if not name.startswith("_")}


def table() -> dict[str, frozenset[str]]:
    modules = installed_modules()
    result: dict[str, set[str]] = {}
    for module, path in modules.items():
        names = public_names(path)
        prefix = module + "."
        names.update(m[len(prefix) :] for m in modules if m.startswith(prefix) and "." not in m[len(prefix) :])
        result[module] = names
    # ``from x import *`` re-exports: follow them once (gymnasium.envs re-exports registration)
    for module, path in modules.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in tree.body:
            if isinstance(node, ast.ImportFrom) and any(a.name == "*" for a in node.names) and node.module in result:
                result[module] |= result[node.module]
    return {module: frozenset(names) for module, names in sorted(result.items())}


def render() -> str:
    lines = [f"    {module!r}: {' '.join(sorted(names))!r}," for module, names in table().items()]
    return "GYMNASIUM_API = {\n" + "\n".join(lines) + "\n}\n"


if __name__ == "__main__":
    print(render(), end="")
