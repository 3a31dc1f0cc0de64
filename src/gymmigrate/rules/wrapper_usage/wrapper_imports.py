"""What the module's imports of gym's wrappers become (GM608, GM611, GM614).

``from gym.wrappers import FrameStack, Monitor`` keeps its module here (the imports rules
move it to ``gymnasium`` in the same run) and changes its names: renamed wrappers get their
1.x names, ``VectorListInfo`` moves to ``wrappers.vector``, gym's ``Monitor`` gives way to
``RecordEpisodeStatistics`` and ``RecordVideo``, and ``gymnasium.experimental.wrappers``
becomes ``gymnasium.wrappers``. What the names bind is recorded for the rest of
``renames.WrapperRenames``, which decides their uses; the edits are recorded once every
call is decided (``finish``), since what a Monitor call uses and what GM613 leaves unused
change the import list.
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.import_guards import import_error_guard
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.wrapper_usage.import_edits import ImportEdit, import_build
from gymmigrate.rules.wrapper_usage.legacy_imports import (
    LegacyImports,
    import_move,
    migrated_path,
    removed_import,
)
from gymmigrate.rules.wrapper_usage.monitor_consumers import (
    reads_of,
    report_guarded_monitor,
)
from gymmigrate.rules.wrapper_usage.tables import (
    RENAMED,
    experimental_name,
    rename_code,
)

if TYPE_CHECKING:
    from gymmigrate.rules.wrapper_usage.stacks import StacksFamily


class WrapperImports:
    """The ``from ... import`` statements of gym's (and gymnasium's experimental) wrappers
    in one module: what each becomes, and what the names they bind stand for."""

    def __init__(self, family: StacksFamily, legacy: LegacyImports) -> None:
        self.family = family
        self.facts = family.facts
        self.legacy = legacy
        self.renamed_locals: dict[str, str] = {}  # imported name -> new name
        self.monitor_locals: set[str] = set()
        self.monitor_aliases: list[tuple[ast.alias, str]] = []  # plain Monitor imports the rewrite drops
        self.guarded_monitors: set[ast.alias] = set()  # Monitor imports under ``except ImportError``: left alone
        self.edits: dict[ast.ImportFrom, ImportEdit] = {}
        self.monitor_imports: list[ImportEdit] = []

    def decide(self, statement: ast.ImportFrom) -> None:
        if statement.level or statement.module is None or any(a.name == "*" for a in statement.names):
            return
        module = statement.module
        rest = N.strip_gym_prefix(module)
        if rest is None:
            return
        if rest.startswith(("experimental.wrappers", "experimental.vector")):
            self._experimental(statement, rest)
            return
        stays = self.legacy.stays_legacy(statement)
        if not stays:
            rest = migrated_path(rest)  # where the imports rules put it in the same run
        if rest not in ("wrappers", "wrappers.vector", "wrappers.monitor"):
            return
        names = statement.names
        if stays and module.startswith("gym.") and not (len(names) == 1 and names[0].name == "Monitor"):
            # The imports rules leave this legacy import (it names something removed): its
            # names stay as they are until a person splits it.
            return
        edit = ImportEdit(statement)
        for index, alias in enumerate(names):
            name = alias.name
            bound = alias.asname or name
            if name in RENAMED and rest == "wrappers":
                new = RENAMED[name]
                edit.renames[index] = new
                if alias.asname is None:
                    self.renamed_locals[bound] = new
                code, kind = rename_code(name)
                self.family.report(statement, code, f"`{name}` was renamed `{new}` in Gymnasium 1.0", kind=kind)
            elif name == "VectorListInfo" and rest in ("wrappers", "wrappers.vector"):
                if rest == "wrappers" and len(names) > 1:
                    self.family.report(
                        statement,
                        "GM608",
                        "`VectorListInfo` is now `gymnasium.wrappers.vector.DictInfoToList`: import it from there",
                        kind=FixKind.FLAG,
                    )
                    continue
                edit.module = "wrappers.vector"
                edit.renames[index] = "DictInfoToList"
                if alias.asname is None:
                    self.renamed_locals[bound] = "DictInfoToList"
                self.family.report(statement, "GM608", "`VectorListInfo` is now `gymnasium.wrappers.vector.DictInfoToList`")
            elif name == "Monitor" and rest in ("wrappers", "wrappers.monitor") and import_error_guard(self.facts, statement):
                self.guarded_monitors.add(alias)
                report_guarded_monitor(self.family, statement, alias, bound)
            elif name == "Monitor" and rest in ("wrappers", "wrappers.monitor"):
                self.monitor_aliases.append((alias, bound))
                present = {a.name for a in names}
                edit.added[index] = [r for r in ("RecordEpisodeStatistics", "RecordVideo") if r not in present]
                edit.dropped.add(index)
                self.monitor_locals.add(bound)
                if stays:
                    edit.absolute_module = "gymnasium.wrappers"
                elif rest != "wrappers":
                    edit.module = "wrappers"
                self.monitor_imports.append(edit)
                shadowed = not reads_of(self.facts, alias, bound) and bool(self.facts.reads_of(bound))
                self.family.report(
                    statement,
                    "GM611",
                    f"`Monitor` is gone: its import is dropped; a later binding of `{bound}` replaces it before any use"
                    if shadowed
                    else "`Monitor` is gone: it is replaced by RecordVideo and RecordEpisodeStatistics",
                    tier=Tier.NOTE,
                )
        if edit.changed:
            self.edits[statement] = edit

    def _experimental(self, statement: ast.ImportFrom, rest: str) -> None:
        new_module = "gymnasium." + rest.replace("experimental.wrappers", "wrappers", 1).replace(
            "experimental.vector", "vector", 1
        )
        edit = ImportEdit(statement, absolute_module=new_module)
        for index, alias in enumerate(statement.names):
            new = experimental_name(alias.name) if rest.startswith("experimental.wrappers") else None
            if new is None:
                continue
            edit.renames[index] = new
            if alias.asname is None:
                self.renamed_locals[alias.name] = new
        self.family.report(statement, "GM614", f"gymnasium.{rest} -> {new_module}: the experimental wrappers became the 1.0 wrappers")
        self.edits[statement] = edit

    def finish(self, names_used: set[str], unused_after: list[ast.Name]) -> None:
        """Record the edits, once every call is decided: ``names_used`` are the names the
        rewritten Monitor calls use, ``unused_after`` the wrapper names GM613 replaced by a
        vector wrapper's path."""
        # Monitor's replacements that no rewritten call uses are not imported (as the
        # LibCST pass's RemoveImportsVisitor dropped them).
        for edit in self.monitor_imports:
            edit.added = {i: [n for n in names if n in names_used] for i, names in edit.added.items()}
        # A single-env wrapper whose only uses became ``gym.wrappers.vector.X``.
        for func in unused_after:
            for binding in self.facts.bindings_of(func):
                statement = self.facts.parent(binding)
                if not (isinstance(binding, ast.alias) and isinstance(statement, ast.ImportFrom)):
                    continue
                if self.legacy.stays_legacy(statement) or _other_reads(self.facts, binding, func.id, unused_after):
                    continue
                edit = self.edits.setdefault(statement, ImportEdit(statement))
                edit.dropped.add(statement.names.index(binding))
        for statement, edit in self.edits.items():
            if not edit.changed:
                continue
            if len(edit.dropped) == len(statement.names) and not any(edit.added.values()):
                self.family.plan.remove(statement)
                move = None if self.legacy.stays_legacy(statement) else import_move(statement)
                if move is not None:
                    code, message = move
                    self.family.plan.report(statement, code, FixKind.AUTO, message)
                continue
            self.family.plan.replace(statement, import_build(edit))
            removed = removed_import(statement) if edit.absolute_module and self.legacy.stays_legacy(statement) else None
            if removed is not None:
                self.family.plan.report(statement, "GM105", FixKind.FLAG, removed)


def _other_reads(facts: ModuleFacts, alias: ast.alias, name: str, unused_after: list[ast.Name]) -> bool:
    """Does any read of ``name`` bound by ``alias`` stay in the output?"""
    removed = {id(func) for func in unused_after}
    return any(id(read) not in removed for read in facts.reads_of(name, alias))
