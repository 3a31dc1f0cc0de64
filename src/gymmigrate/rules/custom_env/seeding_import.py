"""``from gym.utils import seeding`` goes when the removed ``seed()`` bodies were its only use.

Gymnasium still has ``gymnasium.utils.seeding``, so the import is only dropped when
nothing that survives the rewrite reads it, decided on the scopes' reads: the import
statement loses that name, or goes when it had no other.
"""

from __future__ import annotations

import ast
from collections import defaultdict

from gymmigrate.edits.lazy import cst
from gymmigrate.edits.plan import Plan
from gymmigrate.facts.module import ModuleFacts

SEEDING = frozenset({"gym.utils.seeding", "gymnasium.utils.seeding"})


def drop_unused_seeding_import(facts: ModuleFacts, plan: Plan, deleted: list[ast.stmt]) -> None:
    deleted_set = set(deleted)
    dropped: dict[ast.ImportFrom, set[str]] = defaultdict(set)
    for alias, qualified in facts.imports.items():
        if qualified not in SEEDING:
            continue
        statement = facts.parent(alias)
        if not isinstance(statement, ast.ImportFrom):
            continue
        bound = alias.asname or alias.name
        reads = facts.reads_of(bound, alias)
        if any(not any(a in deleted_set for a in facts.ancestors(read)) for read in reads):
            continue
        dropped[statement].add(bound)
    for statement, names in dropped.items():
        if len(names) == len(statement.names):
            plan.remove(statement)
        else:
            plan.replace(statement, _without(names))


def _without(names: set[str]):
    def build(node: cst.ImportFrom) -> cst.ImportFrom:
        assert isinstance(node.names, (list, tuple))
        kept = [a for a in node.names if (a.evaluated_alias or a.evaluated_name) not in names]
        kept[-1] = kept[-1].with_changes(comma=cst.MaybeSentinel.DEFAULT)
        return node.with_changes(names=kept)

    return build

