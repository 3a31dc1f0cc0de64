"""PettingZoo wrapper classes: which classes derive, here or through classes of other
modules of the run, from PettingZoo's AEC ``BaseWrapper`` (or a wrapper built on it, such
as ``OrderEnforcingWrapper``) or from ``BaseParallelWrapper``.

A class's answer is ``(api, methods)``: ``"aec"`` or ``"parallel"``, and the methods the
classes of the run between it and PettingZoo's base define (its own included), so a rule
knows whether PettingZoo's ``reset``/``step`` are the ones an instance runs.

Each module's summary lists its top-level names that are such classes, or import aliases
of PettingZoo's wrapper bases, and ``ref:<qualified>`` for a class whose base is a class
of another module of the run (or an import of a name of the run): ``ProjectView.pz_wrapper``
follows the references.
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.facts import names as N
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts

if TYPE_CHECKING:
    from gymmigrate.facts.project_view import ProjectView

AEC = "aec"
PARALLEL = "parallel"
REF = "ref:"
_MAX_DEPTH = 8

AEC_WRAPPER_BASES = frozenset(q for q in N.PZ_WRAPPER_BASES if q in N.PZ_AEC_BASES)
PARALLEL_WRAPPER_BASES = frozenset(q for q in N.PZ_WRAPPER_BASES if q in N.PZ_PARALLEL_BASES)

Entry = tuple[str, tuple[str, ...]]  # (api or ``ref:<qualified>``, methods defined)


def library_api(qualified: str) -> str | None:
    if qualified in AEC_WRAPPER_BASES:
        return AEC
    if qualified in PARALLEL_WRAPPER_BASES:
        return PARALLEL
    return None


def _own_methods(classdef: ast.ClassDef) -> frozenset[str]:
    return frozenset(s.name for s in classdef.body if isinstance(s, FUNCTIONS))


def _is_run_name(qualified: str) -> bool:
    return not N.is_library(qualified)


def wrapper_api(
    facts: ModuleFacts, classdef: ast.ClassDef, project: ProjectView | None = None
) -> tuple[str, frozenset[str], frozenset[str]] | None:
    """``(api, methods, inherited)`` for a PettingZoo wrapper class defined here, else None:
    the methods the run's classes from it up to PettingZoo's base define, and those of its
    bases alone (what ``super().reset(...)`` reaches before PettingZoo's own)."""
    found = _resolve(facts, classdef, project, 0)
    if found is None or found[0].startswith(REF):
        return None
    return found[0], found[1] | _own_methods(classdef), found[1]


def _resolve(facts: ModuleFacts, classdef: ast.ClassDef, project: ProjectView | None, depth: int) -> tuple[str, frozenset[str]] | None:
    """``(api or ref:<qualified>, the methods the bases define up to PettingZoo's)``."""
    if depth > _MAX_DEPTH:
        return None
    reference = None
    for base in classdef.bases:
        qualified = facts.qualified_names(base)
        for q in qualified:
            api = library_api(q)
            if api is not None:
                return api, frozenset()
        local = facts.classes.get(base.id) if isinstance(base, ast.Name) else None
        if local is not None and local is not classdef and not qualified:
            found = _resolve(facts, local, project, depth + 1)
            if found is not None:
                return found[0], found[1] | _own_methods(local)
            continue
        for q in qualified:
            if not _is_run_name(q):
                continue
            if project is not None:
                other = project.pz_wrapper(q)
                if other is not None:
                    return other
            elif reference is None:
                reference = REF + q
    return (reference, frozenset()) if reference is not None else None


def summarize(facts: ModuleFacts) -> dict[str, Entry]:
    """The module's top-level PettingZoo wrapper classes and aliases, for the run's join."""
    found: dict[str, Entry] = {}
    for name, bindings in facts.module_scope.bindings.items():
        if len(bindings) != 1:
            continue
        binding = bindings[0]
        if isinstance(binding, ast.alias):
            qualified = facts.imports.get(binding)
            if qualified is None:
                continue
            api = library_api(qualified)
            if api is not None:
                found[name] = (api, ())
            elif _is_run_name(qualified):
                found[name] = (REF + qualified, ())
        elif isinstance(binding, ast.ClassDef) and facts.classes.get(name) is binding:
            resolved = _resolve(facts, binding, None, 0)
            if resolved is not None:
                found[name] = (resolved[0], tuple(sorted(resolved[1] | _own_methods(binding))))
    return found
