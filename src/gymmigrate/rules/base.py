"""The rule framework.

A *rule* is one catalog entry (``GM301``: its id, title, fix kind and summary). A
*family* (``RuleFamily``) implements a few related rules: it reads the file's facts
(``gymmigrate.facts``, built once from CPython's ``ast``), reports findings and records
edits in the file's ``Plan``. Every family decides on the same original module, in
``ORDER``; the edits are applied afterwards in one LibCST traversal
(``gymmigrate.edits.apply``), so a single run reaches the fixed point.

Adding a rule family is adding a module under ``gymmigrate.rules`` that defines a
``RuleFamily`` subclass; it registers itself and is picked up by ``rules/__init__.py``.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

from gymmigrate.facts.profile import FileProfile
from gymmigrate.findings import FixKind, Tier
from gymmigrate.options import RewriteOptions

if TYPE_CHECKING:
    from gymmigrate.edits.plan import Plan
    from gymmigrate.facts import ModuleFacts
    from gymmigrate.facts.receivers import Receivers


@dataclass(frozen=True)
class Rule:
    """One catalog entry: what the README documents and what ``--select`` will name."""

    code: str
    title: str
    kind: FixKind
    summary: str


@dataclass
class FileContext:
    """What every family of one file knows besides the facts: its path, the run's options
    and the cheap import profile."""

    path: str
    options: RewriteOptions
    profile: FileProfile


_FAMILIES: list[type[RuleFamily]] = []


class RuleFamily:
    """A family of rules that decides from facts and records edits in a ``Plan``.

    Subclasses set ``RULES`` and ``ORDER``, may narrow ``may_fire`` with a cheap test on
    the facts, and implement ``decide``. They report with ``self.report(node, code,
    message)`` (``node`` is an ``ast`` node of the original source) and edit through
    ``self.plan`` (``replace``, ``insert_after``, ``ensure_import``...).
    """

    RULES: ClassVar[tuple[Rule, ...]] = ()
    ORDER: ClassVar[int] = 100

    def __init_subclass__(cls, **kwargs: object) -> None:
        super().__init_subclass__(**kwargs)
        if cls.RULES:
            _FAMILIES.append(cls)

    def __init__(self, context: FileContext, facts: ModuleFacts, receivers: Receivers, plan: Plan) -> None:
        self.context = context
        self.facts = facts
        self.receivers = receivers
        self.plan = plan
        self._rules = {rule.code: rule for rule in self.RULES}

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        """Cheap test on the facts: can this family fire at all in this file?"""
        return True

    def decide(self) -> None:
        raise NotImplementedError

    def report(
        self, node: ast.AST, code: str, message: str, kind: FixKind | None = None, tier: Tier | None = None
    ) -> None:
        """``tier`` only where it differs from what the kind implies (see findings.Tier)."""
        self.plan.report(node, code, kind or self._rules[code].kind, message, tier)


def registered_families() -> list[type[RuleFamily]]:
    return sorted(_FAMILIES, key=lambda cls: (cls.ORDER, cls.__module__))


def all_rules() -> list[Rule]:
    rules = [rule for cls in registered_families() for rule in cls.RULES]
    return sorted(rules, key=lambda rule: rule.code)
