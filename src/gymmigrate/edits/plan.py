"""What the rules decided for one file: findings, and the edits that carry them out.

Rules decide from ``ModuleFacts`` (CPython ``ast``) and record here *what* to change,
addressed by ``ast`` nodes. Nothing is changed while rules decide: every rule sees the
same original module, so one run reaches the fixed point, and a file whose plan holds
no edit never pays for a LibCST tree. ``gymmigrate.edits.apply`` then carries out all
edits in one traversal.
"""

from __future__ import annotations

import ast
from collections import defaultdict
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from gymmigrate.findings import Finding, FixKind, Tier

if TYPE_CHECKING:  # LibCST is imported only by files that change
    import libcst as cst

    from gymmigrate.facts import ModuleFacts

# Receives the node as already changed by edits inside it; returns its replacement
# (a node, or a LibCST FlattenSentinel / RemovalSentinel where the parent allows it).
Build = Callable[["cst.CSTNode"], Any]


@dataclass
class Plan:
    """Findings and edits for one file, in the order the rules produced them."""

    facts: ModuleFacts
    findings: list[Finding] = field(default_factory=list)
    replacements: dict[ast.AST, list[Build]] = field(default_factory=lambda: defaultdict(list))
    before: dict[ast.stmt, list[Any]] = field(default_factory=lambda: defaultdict(list))
    after: dict[ast.stmt, list[Any]] = field(default_factory=lambda: defaultdict(list))
    removed: set[ast.stmt] = field(default_factory=set)
    # Removed statements whose comment lines (above them) move to the next statement.
    keep_comments: set[ast.stmt] = field(default_factory=set)
    imports: list[str] = field(default_factory=list)  # new top-level import lines
    # What one rule family decided that another must follow in the same run (e.g. the
    # render mode a creation site needs because a wrapper was replaced).
    notes: dict[str, Any] = field(default_factory=dict)
    _seen: set[tuple[int, str, str]] = field(default_factory=set)

    @property
    def has_edits(self) -> bool:
        return bool(self.replacements or self.before or self.after or self.removed or self.imports)

    # -- findings -------------------------------------------------------------------------

    def report(self, node: ast.AST, code: str, kind: FixKind, message: str, tier: Tier | None = None) -> None:
        line = node.lineno  # type: ignore[attr-defined]
        column = self.facts.column(node)
        # Two routes to the same conclusion, or the same item at two columns of one line
        # (`env.render(); env.render()`): one item.
        key = (line, code, message)
        if key in self._seen:
            return
        self._seen.add(key)
        end_line, end_column = self.facts.end(node)
        self.findings.append(
            Finding(
                line=line,
                column=column,
                rule=code,
                kind=kind,
                message=message,
                end_line=end_line,
                end_column=end_column,
                tier=tier,
            )
        )

    # -- edits ----------------------------------------------------------------------------

    def replace(self, node: ast.AST, build: Build) -> None:
        """Replace the LibCST counterpart of ``node`` with ``build(node_as_changed)``."""
        self.replacements[node].append(build)

    def insert_before(self, statement: ast.stmt, *code: Any) -> None:
        self.before[statement].extend(code)

    def insert_after(self, statement: ast.stmt, *code: Any) -> None:
        self.after[statement].extend(code)

    def withdraw(self, statement: ast.stmt, code: Any) -> None:
        """Take back one piece of ``code`` inserted around ``statement`` (the very object
        given to ``insert_before``/``insert_after``): a later family that removes the last
        reader of an inserted line (e.g. ``done = terminated or truncated``) drops it."""
        for inserted in (self.before, self.after):
            items = inserted.get(statement)
            if items is None:
                continue
            for index, item in enumerate(items):
                if item is code:
                    del items[index]
                    if not items:
                        del inserted[statement]
                    return

    def remove(self, statement: ast.stmt, keep_comments: bool = False) -> None:
        """Delete ``statement``; with ``keep_comments``, the comment lines above it stay,
        above the statement that follows it in its block."""
        self.removed.add(statement)
        if keep_comments:
            self.keep_comments.add(statement)

    def add_import(self, line: str) -> None:
        """A top-level import statement, added once after the module's last import."""
        if line not in self.imports:
            self.imports.append(line)

    def ensure_import(self, module: str, name: str | None = None, asname: str | None = None) -> str:
        """Make ``module`` (or ``module.name``) available; return the name to use in code."""
        qualified = f"{module}.{name}" if name else module
        bound = self.facts.imported_as(qualified)
        if bound is not None:
            return bound
        if name:
            self.add_import(f"from {module} import {name}" + (f" as {asname}" if asname else ""))
            return asname or name
        self.add_import(f"import {module}" + (f" as {asname}" if asname else ""))
        return asname or module
