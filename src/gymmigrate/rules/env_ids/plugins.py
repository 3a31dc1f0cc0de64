"""GM111, the Python side: a module named by a ``gym.envs`` plugin entry point calls its
register function on import.

gym 0.22-0.26 called the function itself, on ``import gym``; Gymnasium 1.x loads no
plugins. The run resolves each entry point of its dependency files
(``gymmigrate.dependencies.plugins``, ``runner._with_plugins``) to a module of the run
that defines the function, and ``ProjectView.plugin_calls`` hands it here: the call is
appended to the module (before a trailing ``if __name__ == "__main__":`` block), inside
``namespace(NAME)`` for a plugin that gym registered in its own namespace. A module that
already calls the function at its top level is left as it is, so a second run changes
nothing. The dependency file reports the entry point, with where the call went.
"""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import ModuleFacts
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext, RuleFamily


class EnvPlugins(RuleFamily):
    CARRIES_OUT = ("GM111",)  # a dependency-file rule (rules/dependency_files.py)

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        project = context.options.project
        return project is not None and bool(project.view(context.path).plugin_calls())

    def decide(self) -> None:
        project = self.context.options.project
        assert project is not None
        body = self.facts.tree.body
        anchor = next((statement for statement in reversed(body) if not _is_main_guard(statement)), None)
        if anchor is None:
            return
        called = _called_at_top_level(body)
        for function, namespace in project.view(self.context.path).plugin_calls():
            if function in called:
                continue
            called.add(function)
            if namespace is None:
                code = f"{function}()"
                where = ""
            else:
                context = self.plan.ensure_import("gymnasium.envs.registration", "namespace")
                code = f"with {context}({namespace!r}):\n    {function}()"
                where = f" inside `namespace({namespace!r})`, where gym registered its ids"
            # PEP 8's two blank lines after a def or class, one after other code
            blank = 2 if isinstance(anchor, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) else 1
            self.plan.insert_after(anchor, cst.parse_statement(code + "\n").with_changes(leading_lines=[cst.EmptyLine()] * blank))
            self.report(
                anchor,
                "GM111",
                f"a `gym.envs` entry point names `{function}`, which gym called on import and Gymnasium never calls: "
                f"`{function}()` is called at the end of this module{where}, so importing it registers the envs",
                kind=FixKind.ASSIST,
            )


def _is_main_guard(statement: ast.stmt) -> bool:
    test = statement.test if isinstance(statement, ast.If) else None
    return (
        isinstance(test, ast.Compare)
        and isinstance(test.left, ast.Name)
        and test.left.id == "__name__"
        and any(isinstance(c, ast.Constant) and c.value == "__main__" for c in test.comparators)
    )


def _called_at_top_level(body: list[ast.stmt]) -> set[str]:
    """Names called by the module's own top-level code (not inside a def or class)."""
    called: set[str] = set()
    stack: list[ast.AST] = [statement for statement in body if not _is_main_guard(statement)]
    while stack:
        node = stack.pop()
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.Lambda)):
            continue
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
            called.add(node.func.id)
        stack.extend(ast.iter_child_nodes(node))
    return called
