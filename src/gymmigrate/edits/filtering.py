"""Rules left out of a run (``--select``/``--ignore``) and suppressed findings leave the
plan together with their edits, and with the edits of the families coupled to them.

Every family has decided by now; this only removes what the run was told to leave out.
"""

from __future__ import annotations

from gymmigrate.edits.plan import Plan
from gymmigrate.options import RewriteOptions
from gymmigrate.suppressions import Suppressions


def filter_plan(plan: Plan, text: str, options: RewriteOptions) -> None:
    """Drop the findings of deselected rules and the suppressed ones, with their edits."""
    selection = options.selection
    suppressions = Suppressions.find(text, {finding.rule for finding in plan.findings})
    if (selection is None or selection.every_rule) and suppressions is None:
        return
    dropped = set()
    for index, finding in enumerate(plan.findings):
        if selection is not None and not selection.allows(finding.rule):
            dropped.add(index)
        elif suppressions is not None:
            statement = plan.facts.statement_of(plan.finding_nodes[index])
            if suppressions.silences(finding.rule, (finding.line, statement.lineno)):
                dropped.add(index)
    plan.drop_findings(_with_coupled(plan, dropped))


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


def _with_coupled(plan: Plan, dropped: set[int]) -> set[int]:
    families = plan.finding_families
    scope_of = plan.facts.enclosing_function
    left_out: set[tuple[int, str]] = set()  # (function, family)
    for index in dropped:
        if plan.findings[index].is_change:
            scope = id(scope_of(plan.finding_nodes[index]))
            left_out.update((scope, family) for family in COUPLED_FAMILIES.get(families[index], ()))
    if not left_out:
        return dropped
    return dropped | {
        index
        for index, finding in enumerate(plan.findings)
        if finding.is_change and (id(scope_of(plan.finding_nodes[index])), families[index]) in left_out
    }
