"""Edits of one ``from ... import`` statement: renamed, dropped and added names, a new module.

Decided in ``wrapper_imports.py``, carried out by one build per statement so renames,
Monitor's replacements and the names GM613 left unused compose.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass, field

from gymmigrate.edits.lazy import cst
from gymmigrate.edits.syntax import dotted_node


@dataclass
class ImportEdit:
    """What happens to one ``from ... import`` statement."""

    statement: ast.ImportFrom
    renames: dict[int, str] = field(default_factory=dict)  # alias index -> new name
    dropped: set[int] = field(default_factory=set)  # alias indexes removed
    added: dict[int, list[str]] = field(default_factory=dict)  # alias index -> names put in its place (Monitor's)
    module: str | None = None  # new module path under the package root ("wrappers.vector")
    absolute_module: str | None = None  # a whole new module name (the import stays legacy otherwise)

    @property
    def changed(self) -> bool:
        return bool(self.renames or self.dropped or self.added or self.module or self.absolute_module)




def import_build(edit: ImportEdit):
    def build(node: cst.ImportFrom) -> cst.ImportFrom:
        originals = list(node.names)  # type: ignore[arg-type]
        names: list[cst.ImportAlias] = []
        for index, alias in enumerate(originals):
            names.extend(cst.ImportAlias(name=cst.Name(name)) for name in edit.added.get(index, ()))
            if index in edit.dropped:
                continue
            if index in edit.renames:
                alias = alias.with_changes(name=cst.Name(edit.renames[index]))
            names.append(alias)
        module = node.module
        if edit.absolute_module is not None:
            module = dotted_node(edit.absolute_module)
        elif edit.module is not None and module is not None:
            # Keep the package the node names now (``gym`` until the imports rules ran).
            root = _cst_root(module)
            module = dotted_node(f"{root}.{edit.module}")
        return node.with_changes(module=module, names=_with_commas(names, originals))

    return build


def _cst_root(node: cst.BaseExpression) -> str:
    while isinstance(node, cst.Attribute):
        node = node.value
    return node.value if isinstance(node, cst.Name) else "gymnasium"


def _with_commas(names: list[cst.ImportAlias], originals: list[cst.ImportAlias]) -> list[cst.ImportAlias]:
    """Separators for a rebuilt import list: ``, `` between names, the original's last comma kept."""
    last = originals[-1].comma if originals else cst.MaybeSentinel.DEFAULT
    result = []
    for i, alias in enumerate(names):
        if i < len(names) - 1:
            keep = originals[i].comma if i < len(originals) - 1 and originals[i].comma is not cst.MaybeSentinel.DEFAULT else None
            result.append(alias.with_changes(comma=keep or cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))))
        else:
            result.append(alias.with_changes(comma=last))
    return result
