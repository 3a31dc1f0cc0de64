"""Rules left out of a run (``--select``/``--ignore``) and suppressed findings leave the
plan together with their edits, and with the changes that only make sense beside them.

Every family has decided by now; this only removes what the run was told to leave out,
and what would be broken without it. Three couplings say what goes with what:

* ``COUPLED_FAMILIES``: a change left out takes the changes of the families coupled with
  its own in the same function (a step unpack and the done reads of its names);
* ``Need`` (``edits.plan``): a change that reads a name another family's edit makes (a
  parameter it adds to a signature) is kept only while that edit is;
* ``together`` (``Plan.report``): changes made at every place or at none (GM207's reset
  contract) are kept or left out as one.

A change of a rule the run keeps that goes this way is not lost silently: it stays as an
item "not rewritten" that says what it goes with.
"""

from __future__ import annotations

import ast
from collections import defaultdict
from collections.abc import Hashable, Iterable

from gymmigrate.edits.plan import Plan
from gymmigrate.options import RewriteOptions
from gymmigrate.suppressions import Suppressions

_LEFT_OUT = "which this run leaves out (--select/--ignore or a suppression comment); select both or neither"
_LEFT_TOO = "which is left as it is too"
_NOT_MADE = "which this run does not make here"


def filter_plan(plan: Plan, text: str, options: RewriteOptions) -> None:
    """Drop the findings of deselected rules and the suppressed ones, with their edits, and
    the changes that go with them."""
    selection = options.selection
    suppressions = Suppressions.find(text, {finding.rule for finding in plan.findings})
    if (selection is None or selection.every_rule) and suppressions is None and not any(plan.finding_needs):
        return
    left_out = set()
    for index, finding in enumerate(plan.findings):
        if selection is not None and not selection.allows(finding.rule):
            left_out.add(index)
        elif suppressions is not None:
            statement = plan.facts.statement_of(plan.finding_nodes[index])
            if suppressions.silences(finding.rule, (finding.line, statement.lineno)):
                left_out.add(index)
    why: dict[int, str] = {}  # a change left out because of others: why
    dropped = set(left_out)
    while True:  # a change left out may be one another goes with in turn
        grown = _with_coupled(plan, dropped, left_out, why)
        grown = _with_unmet_needs(plan, grown, why)
        grown = _with_groups(plan, grown, left_out, why)
        if grown == dropped:
            break
        dropped = grown
    flagged = {index: f"left as it is: {reason}. The change: {plan.findings[index].message}" for index, reason in why.items() if index not in left_out}
    plan.drop_findings(dropped, flagged)


def _goes_with(plan: Plan, partners: Iterable[int], left_out: set[int], how: str) -> str:
    """Why a change goes: the changes it goes with (``left_out``: those the run left out)."""
    partners = set(partners)
    lines: dict[str, set[int]] = defaultdict(set)
    for index in partners:
        lines[plan.findings[index].rule].add(plan.findings[index].line)
    shown = ", ".join(
        f"{rule}'s change at line {min(at)}" if len(at) == 1 else f"{rule}'s changes at lines {', '.join(map(str, sorted(at)))}"
        for rule, at in sorted(lines.items())
    )
    return f"it goes with {shown} ({how}), {_LEFT_OUT if partners & left_out else _LEFT_TOO}"


# Families whose fixes build on one another's names: the step unpack introduces
# ``terminated`` that the done reads use, the reset unpack introduces ``info`` that a
# wrapper's return uses, a wrapper's step override and the step inside it agree on five
# values, a vector loop needs the import its info edit adds. Leaving out a change of one
# of them leaves out the changes of the families it is coupled with in the same function
# (or at module level), so no kept edit reads a name a dropped one would have made.
COUPLED_FAMILIES = {
    "StepDone": frozenset({"StepDone", "WrapperClasses"}),
    "ResetSeed": frozenset({"ResetSeed", "WrapperClasses"}),
    "WrapperClasses": frozenset({"WrapperClasses", "StepDone", "ResetSeed"}),
    "VectorEnvs": frozenset({"VectorEnvs"}),
    # PettingZoo: last()'s termination/truncation names and the dead-agent step that reads
    # them; the parallel step/reset unpacks and the env classes that return them.
    "AecLoop": frozenset({"AecLoop"}),
    "ParallelCalls": frozenset({"ParallelCalls", "EnvClasses"}),
    "EnvClasses": frozenset({"EnvClasses", "ParallelCalls"}),
}


def _scope(plan: Plan, node: ast.AST) -> ast.AST | None:
    """The function a finding is about (None: the module level): a finding on a ``def``
    (its signature, its returns) is about that function, not the one around it."""
    if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
        return node
    return plan.facts.enclosing_function(node)


def _with_coupled(plan: Plan, dropped: set[int], left_out: set[int], why: dict[int, str]) -> set[int]:
    families = plan.finding_families
    taken: dict[tuple[int, str], list[int]] = defaultdict(list)  # (id of the function, family) -> the changes that take it
    for index in dropped:
        if plan.findings[index].is_change:
            for family in COUPLED_FAMILIES.get(families[index], ()):
                taken[id(_scope(plan, plan.finding_nodes[index])), family].append(index)
    if not taken:
        return dropped
    coupled = set(dropped)
    for index, finding in enumerate(plan.findings):
        if index in dropped or not finding.is_change:
            continue
        scope = _scope(plan, plan.finding_nodes[index])
        partners = taken.get((id(scope), families[index]))
        if partners:
            coupled.add(index)
            where = "at module level" if scope is None else "in the same function"
            why.setdefault(index, _goes_with(plan, partners, left_out, where))
    return coupled


def _with_groups(plan: Plan, dropped: set[int], left_out: set[int], why: dict[int, str]) -> set[int]:
    groups: dict[Hashable, list[int]] = defaultdict(list)
    for index, group in enumerate(plan.finding_groups):
        if group is not None and plan.findings[index].is_change:
            groups[group].append(index)
    grown = set(dropped)
    for members in groups.values():
        partners = [index for index in members if index in dropped]
        if not partners:
            continue
        for index in members:
            if index not in dropped:
                grown.add(index)
                why.setdefault(index, _goes_with(plan, partners, left_out, "made at every place or at none"))
    return grown


def _with_unmet_needs(plan: Plan, dropped: set[int], why: dict[int, str]) -> set[int]:
    """``dropped`` and the changes whose ``Need`` no edit kept meets."""
    needing = [(index, need) for index, need in enumerate(plan.finding_needs) if need is not None and index not in dropped]
    if not needing:
        return dropped
    kept = plan.kept_edits(dropped)
    made = plan.kept_edits(set())  # every edit the families planned
    unmet = set(dropped)
    for index, need in needing:
        # the edit on the node itself, or on a class or function around it (a class rebuilt whole)
        edits = {(need.family, id(node)) for node in (need.node, *plan.facts.ancestors(need.node))}
        if edits & kept:
            continue
        unmet.add(index)
        left_out = need.family in plan.left_out_families or bool(edits & made)
        why.setdefault(index, f"it reads {need.what}, {_LEFT_OUT if left_out else _NOT_MADE}")
    return unmet
