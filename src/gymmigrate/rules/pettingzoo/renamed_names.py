"""PZ108: names of ``pettingzoo.utils`` that current PettingZoo spells differently.

Every entry was checked against each release's source (1.8 to 1.26) and the installed
1.27: the new name is what the old one became, in the same module, and the old one is
gone (an ``ImportError``) or only a deprecated alias that warns and calls the new one.

* ``pettingzoo.utils.conversions``: ``from_parallel_wrapper`` and ``to_parallel_wrapper``
  became ``parallel_to_aec_wrapper`` and ``aec_to_parallel_wrapper`` in 1.15.0; the
  functions ``from_parallel`` / ``to_parallel`` became ``parallel_to_aec`` /
  ``aec_to_parallel`` (kept in ``conversions`` as aliases that warn, gone from
  ``pettingzoo.utils`` itself);
* ``pettingzoo.utils.deprecated_module.depricated_handler`` is ``deprecated_handler``
  since 1.18.0;
* ``BaseParallelWraper`` is ``BaseParallelWrapper`` since 1.22.4.

An import keeps the name it bound (``from pettingzoo.utils.conversions import
parallel_to_aec_wrapper as from_parallel_wrapper``), so no use in this module nor in a
module that imports it from here changes; an attribute read (``conversions.to_parallel``)
takes the new name. What has no same-module successor (``conversions.ActionDict``, a
``Dict[str, Optional[int]]`` alias of 1.18-1.23 whose 1.27 namesake in
``pettingzoo.utils.env`` is generic) is not renamed.
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.edits.lazy import cst

if TYPE_CHECKING:
    from gymmigrate.rules.pettingzoo.common import PettingZooFamily

# module -> {legacy name: (current name, the PettingZoo release that renamed it)}
RENAMED: dict[str, dict[str, tuple[str, str]]] = {
    "pettingzoo.utils.conversions": {
        "from_parallel_wrapper": ("parallel_to_aec_wrapper", "1.15.0"),
        "to_parallel_wrapper": ("aec_to_parallel_wrapper", "1.15.0"),
        "from_parallel": ("parallel_to_aec", "1.15.0"),
        "to_parallel": ("aec_to_parallel", "1.15.0"),
    },
    "pettingzoo.utils": {
        "from_parallel": ("parallel_to_aec", "1.15.0"),
        "to_parallel": ("aec_to_parallel", "1.15.0"),
        "BaseParallelWraper": ("BaseParallelWrapper", "1.22.4"),
    },
    "pettingzoo.utils.wrappers": {"BaseParallelWraper": ("BaseParallelWrapper", "1.22.4")},
    "pettingzoo.utils.wrappers.base_parallel": {"BaseParallelWraper": ("BaseParallelWrapper", "1.22.4")},
    "pettingzoo.utils.deprecated_module": {"depricated_handler": ("deprecated_handler", "1.18.0")},
}
# The same, by qualified legacy name.
RENAMED_QUALIFIED: dict[str, tuple[str, str]] = {
    f"{module}.{old}": new for module, names in RENAMED.items() for old, new in names.items()
}


def plan_renamed_names(family: PettingZooFamily) -> None:
    """Every import and attribute read of a renamed name in the module gets the new name."""
    facts = family.facts
    for statement in facts.import_statements:
        if isinstance(statement, ast.ImportFrom) and statement.level == 0 and statement.module in RENAMED:
            _plan_import(family, statement, RENAMED[statement.module])
    attributes = {old for names in RENAMED.values() for old in names}
    for old in sorted(attributes):
        for attr in facts.attributes.get(old, ()):
            if not isinstance(attr.ctx, ast.Load):
                continue
            found = next((RENAMED_QUALIFIED[q] for q in sorted(facts.qualified_names(attr)) if q in RENAMED_QUALIFIED), None)
            if found is None:
                continue
            new, release = found
            family.rename_attribute(attr, new)
            family.report(attr, "PZ108", f"`{old}` is `{new}` since PettingZoo {release}")


def _plan_import(family: PettingZooFamily, statement: ast.ImportFrom, renamed: dict[str, tuple[str, str]]) -> None:
    """``from M import old`` -> ``from M import new as old`` (an alias keeps its own name)."""
    found = [(alias.name, *renamed[alias.name]) for alias in statement.names if alias.name in renamed]
    if not found:
        return
    family.changed()

    def build(node: cst.ImportFrom) -> cst.ImportFrom:
        assert not isinstance(node.names, cst.ImportStar)  # it names a renamed name
        names = [
            alias.with_changes(
                name=cst.Name(renamed[alias.name.value][0]),
                asname=alias.asname or cst.AsName(name=cst.Name(alias.name.value)),
            )
            if isinstance(alias.name, cst.Name) and alias.name.value in renamed
            else alias
            for alias in node.names
        ]
        return node.with_changes(names=names)

    family.plan.replace(statement, build)
    what = "; ".join(f"`{old}` is `{new}` since PettingZoo {release}" for old, new, release in found)
    family.report(statement, "PZ108", f"{what}: imported under the old name, so no use changes")
