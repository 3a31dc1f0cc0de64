"""Which rules a run applies: ``--select`` / ``--ignore`` (and their ``extend-`` forms),
by code or prefix, the way ruff reads them.

A selector is a rule code (``GM301``), a prefix of codes (``GM3``, ``PZ``) or ``ALL``.
For each rule the most specific selector that matches it decides (ignore wins a tie);
a rule no selector matches is on when nothing was selected (every rule runs by default).
A deselected rule neither reports nor fixes: ``filter_plan`` drops its findings together
with their edits, and does the same for findings silenced by a suppression comment.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from gymmigrate.edits.plan import Plan
    from gymmigrate.rules.base import RewriteOptions


class SelectionError(ValueError):
    """A selector names no implemented rule; the message says which."""


@dataclass(frozen=True)
class Selection:
    """The rules a run applies, resolved once from the selectors."""

    allowed: frozenset[str]
    every_rule: bool = field(default=False)

    def allows(self, code: str) -> bool:
        return self.every_rule or code in self.allowed

    @classmethod
    def from_selectors(
        cls,
        select: Sequence[str] | None = None,
        ignore: Sequence[str] = (),
        extend_select: Sequence[str] = (),
        extend_ignore: Sequence[str] = (),
        *,
        codes: Iterable[str] | None = None,
    ) -> Selection:
        codes = sorted(codes if codes is not None else _implemented_codes())
        chosen = list(select) if select is not None else ["ALL"]
        chosen += list(extend_select)
        ignored = list(ignore) + list(extend_ignore)
        for selector in chosen + ignored:
            check_selector(selector, codes)
        allowed = {code for code in codes if _decides(code, chosen, ignored)}
        return cls(frozenset(allowed), every_rule=allowed == set(codes))


def check_selector(selector: str, codes: Sequence[str]) -> None:
    if selector == "ALL" or any(code.startswith(selector) for code in codes):
        return
    raise SelectionError(f"unknown rule code or prefix {selector!r} (see `gymmigrate rules`)")


def parse_selectors(values: Sequence[str] | None) -> list[str] | None:
    """Command-line values, each possibly a comma-separated list, as selectors."""
    if values is None:
        return None
    return [part.strip().upper() for value in values for part in value.split(",") if part.strip()]


def _decides(code: str, chosen: Sequence[str], ignored: Sequence[str]) -> bool:
    def specificity(selectors: Sequence[str]) -> int:
        lengths = [0 if s == "ALL" else len(s) for s in selectors if s == "ALL" or code.startswith(s)]
        return max(lengths, default=-1)

    selected, deselected = specificity(chosen), specificity(ignored)
    return selected >= 0 and selected > deselected


def _implemented_codes() -> list[str]:
    from gymmigrate.dependencies import CODES as DEPENDENCY_CODES
    from gymmigrate.rules import all_rules

    return [rule.code for rule in all_rules()] + list(DEPENDENCY_CODES)


def family_selected(family: type, selection: Selection | None) -> bool:
    """Whether any rule of ``family`` is on: a family with none is not even run."""
    return selection is None or any(selection.allows(rule.code) for rule in family.RULES)  # type: ignore[attr-defined]


def filter_plan(plan: Plan, text: str, options: RewriteOptions) -> None:
    """Drop the findings of deselected rules and the suppressed ones, with their edits."""
    from gymmigrate.suppressions import Suppressions

    selection = getattr(options, "selection", None)
    suppressions = Suppressions.find(text)
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
    left_out = set()  # (function, family)
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
