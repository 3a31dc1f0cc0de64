"""Code built on gym's ``Monitor`` that no rewrite of a ``Monitor(...)`` call reaches (GM611).

``Monitor(env, dir)`` calls become ``RecordVideo``/``RecordEpisodeStatistics`` (``monitor.py``);
what else reads the class is reported here, never rewritten: nothing in Gymnasium has
Monitor's API (``get_total_steps``, ``stats_recorder``, ``_start``...).

* An import of ``Monitor`` inside ``try: ... except ImportError:`` is left as it is: under
  Gymnasium it fails and the ``except`` branch's fallback runs, as the legacy code did on an
  install without Monitor. Dropping it (the plain import's rewrite) would skip the fallback
  and leave the name unbound. The import and every class derived from the name are items.
* A plain import loses the name (its calls are rewritten): a read that is not such a call
  (a base class, an ``isinstance`` test) is an item, and so is a read of
  ``gym.wrappers.Monitor`` by its path, and a call where the name may be bound to gym's
  Monitor or to something else.
* ``lookup(env, "Monitor")``: a wrapper searched by its class name finds nothing once the
  Monitor is rewritten (in this module or another of the run).
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.import_guards import import_error_guard, in_handler_of
from gymmigrate.facts.module import walk
from gymmigrate.findings import FixKind
from gymmigrate.rules.repeats import Repeats

if TYPE_CHECKING:
    from gymmigrate.rules.wrapper_usage.legacy_imports import LegacyImports
    from gymmigrate.rules.wrapper_usage.stacks import StacksFamily

MONITOR_NAME = "Monitor"
# gym's Monitor by its attribute path (``gym.wrappers.Monitor``), before and after GM101
_GYM_MONITORS = frozenset(
    f"{package}.wrappers{sub}.Monitor" for package in ("gym", "gymnasium") for sub in ("", ".monitor")
)


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
    for node in walk(facts.tree):
        if isinstance(node, ast.Call):
            values = [*node.args, *(k.value for k in node.keywords)]
            if any(isinstance(v, ast.Constant) and v.value == MONITOR_NAME for v in values):
                found.append(node)
    return found


def report_guarded_monitor(family: StacksFamily, statement: ast.ImportFrom, alias: ast.alias, bound: str) -> None:
    """``try: from gym.wrappers import Monitor as M / except ImportError: <fallback>``: left as
    it is; the import and each class derived from ``M`` are items."""
    reads = reads_of(family.facts, alias, bound)
    derived = [c for c in (derived_class(family.facts, r) for r in reads) if c is not None]
    others = sorted({r.lineno for r in reads if derived_class(family.facts, r) is None})
    used = [f"`{c.name}` (line {c.lineno}) derives from it" for c in derived]
    if others:
        used.append(f"it is read at {lines_text(others)}")
    family.report(
        statement,
        "GM611",
        f"`Monitor` is gone: under Gymnasium this import fails and the `except ImportError` branch runs, as on "
        f"an install without Monitor; left as it is. Rebuild what uses `{bound}` on RecordVideo and "
        f"RecordEpisodeStatistics" + (f" ({'; '.join(used)})" if used else ""),
        kind=FixKind.FLAG,
    )
    for classdef in derived:
        uses = lines_text(class_uses(family.facts, classdef))
        family.report(
            classdef,
            "GM611",
            f"`{classdef.name}` derives from gym's removed `Monitor` (`{bound}`); under Gymnasium it derives from "
            f"the `except ImportError` fallback instead: rebuild it on RecordVideo and RecordEpisodeStatistics"
            + (f" (used at {uses} here, and wherever other modules make it)" if uses else " (and wherever other modules make it)"),
            kind=FixKind.FLAG,
        )


def report_monitor_consumers(
    family: StacksFamily, aliases: list[tuple[ast.alias, str]], covered: set[int], legacy: LegacyImports, imports_sb3: bool
) -> None:
    """Reads of a dropped Monitor name (``aliases``: the plain imports, with the names they
    bind) that no rewritten call covers (``covered``: ids of those calls' funcs), reads of
    ``gym.wrappers.Monitor``, and lookups by name."""
    for alias, bound in aliases:
        for read in reads_of(family.facts, alias, bound):
            if id(read) in covered:
                continue
            classdef = derived_class(family.facts, read)
            what = f"`{classdef.name}` derives from it" if classdef is not None else "this use is left as it is"
            spelled = "gym's `Monitor`" + (f" (`{bound}`)" if bound != MONITOR_NAME else "")
            family.report(
                read,
                "GM611",
                f"{spelled} is gone and its import is replaced: {what}; rebuild it on RecordVideo "
                "and RecordEpisodeStatistics",
                kind=FixKind.FLAG,
            )
    _report_monitor_attributes(family, legacy)
    if imports_sb3:
        return  # Stable-Baselines' own Monitor is still there
    repeats = Repeats("GM611")
    for call in name_lookups(family.facts):
        family.report(
            call,
            "GM611",
            f"`{family.facts.segment(call)}` looks for a wrapper named `{MONITOR_NAME}`: gym's Monitor is gone (it "
            "becomes RecordEpisodeStatistics/RecordVideo), so the search finds nothing on Gymnasium; "
            f"RecordEpisodeStatistics keeps `episode_count`, `return_queue`, `length_queue`",
            kind=FixKind.FLAG,
            question=repeats.question(MONITOR_NAME),
        )


def _report_monitor_attributes(family: StacksFamily, legacy: LegacyImports) -> None:
    """``gym.wrappers.Monitor`` read other than as the call it constructs (an
    ``isinstance`` test, a base, a stored class): the attribute is gone from Gymnasium's
    wrappers, so the read raises AttributeError; what replaces the test is a person's call."""
    for attribute in family.facts.attributes.get("Monitor", ()):
        parent = family.facts.parent(attribute)
        if isinstance(parent, ast.Call) and parent.func is attribute:
            continue  # a construction: planned (or asked about) by the Monitor rewrite
        if not family.facts.qualified_names(attribute) & _GYM_MONITORS or legacy.binds_legacy(attribute):
            continue
        family.report(
            attribute,
            "GM611",
            f"`{family.facts.segment(attribute)}` is gone (AttributeError on Gymnasium): videos and statistics come "
            "from RecordVideo and RecordEpisodeStatistics now (it keeps `episode_count`, `return_queue`, "
            "`length_queue`); test for those or drop this use",
            kind=FixKind.FLAG,
        )


def report_unsure_monitor(family: StacksFamily, call: ast.Call, others: list[ast.AST]) -> None:
    """A ``Monitor`` name bound both to gym's Monitor and to something else, where which
    binding holds at the call is not known (one is under ``if``, in a loop...)."""
    assert isinstance(call.func, ast.Name)
    lines = lines_text(sorted({getattr(other, "lineno", None) or family.facts.statement_of(other).lineno for other in others}))
    family.report(
        call,
        "GM611",
        f"not rewritten: `{call.func.id}` here is gym's removed `Monitor` or what {lines} bind{'s' if len(others) == 1 else ''} it to, and which "
        "one holds at this call is not known; if it is gym's, rebuild it on RecordVideo and RecordEpisodeStatistics",
        kind=FixKind.FLAG,
    )
