"""Code built on gym's ``Monitor`` that no rewrite of a ``Monitor(...)`` call reaches (GM611).

``Monitor(env, dir)`` calls become ``RecordVideo``/``RecordEpisodeStatistics`` (``monitor.py``);
what else reads the class is reported here, never rewritten: nothing in Gymnasium has
Monitor's API (``get_total_steps``, ``stats_recorder``, ``_start``...).

* An import of ``Monitor`` inside ``try: ... except ImportError:`` is left as it is: under
  Gymnasium it fails and the ``except`` branch's fallback runs, as the legacy code did on an
  install without Monitor. Dropping it (the plain import's rewrite) would skip the fallback
  and leave the name unbound. The import and every class derived from the name are items.
* A plain import loses the name (its calls are rewritten): a read that is not such a call
  (a base class, an ``isinstance`` test) is an item.
* ``lookup(env, "Monitor")``: a wrapper searched by its class name finds nothing once the
  Monitor is rewritten (in this module or another of the run).
"""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.import_guards import import_error_guard, in_handler_of

MONITOR_NAME = "Monitor"


def reads_of(facts: ModuleFacts, alias: ast.alias, name: str) -> list[ast.Name]:
    """Every read of ``name`` the import ``alias`` binds (alone or among other bindings),
    but not those in the ``except ImportError`` branch around it (the fallback's own)."""
    statement = facts.parent(alias)
    guard = import_error_guard(facts, statement) if isinstance(statement, ast.stmt) else None
    reads = [read for read in facts.reads_of(name, alias) if not (guard is not None and in_handler_of(facts, read, guard))]
    return sorted(reads, key=lambda n: (n.lineno, n.col_offset))


def derived_class(facts: ModuleFacts, read: ast.Name) -> ast.ClassDef | None:
    parent = facts.parent(read)
    return parent if isinstance(parent, ast.ClassDef) and any(base is read for base in parent.bases) else None


def class_uses(facts: ModuleFacts, classdef: ast.ClassDef) -> list[int]:
    """Lines of this module that read the class's name (constructions, tests, subclasses)."""
    return sorted({read.lineno for read in facts.reads_of(classdef.name, classdef)})


def lines_text(lines: list[int]) -> str:
    if not lines:
        return ""
    return ("line " if len(lines) == 1 else "lines ") + ", ".join(str(n) for n in lines)


def name_lookups(facts: ModuleFacts) -> list[ast.Call]:
    """Calls handed the string ``"Monitor"``: a search of a wrapper stack by class name."""
    found = []
    for node in ast.walk(facts.tree):
        if isinstance(node, ast.Call):
            values = [*node.args, *(k.value for k in node.keywords)]
            if any(isinstance(v, ast.Constant) and v.value == MONITOR_NAME for v in values):
                found.append(node)
    return found
