"""The rule framework.

A *rule* is one catalog entry (``GM301``: its id, title, fix kind and summary). A
*family* (``RuleFamily``) implements a few related rules: it reads the file's facts
(``gymmigrate.facts``, built once from CPython's ``ast``), reports findings and records
edits in the file's ``Plan``. Every family decides on the same original module, in the
order of ``rules/__init__.py``'s ``PIPELINE``; the edits are applied afterwards in one LibCST traversal
(``gymmigrate.edits.apply``), so a single run reaches the fixed point.

Adding a rule family is adding a module under ``gymmigrate.rules`` that defines a
``RuleFamily`` subclass; it registers itself and is picked up by ``rules/__init__.py``.
"""

from __future__ import annotations

import ast
from functools import lru_cache
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, ClassVar

from gymmigrate.facts.profile import FileProfile
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.notes import FamilyNotes
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
    notes: FamilyNotes = field(default_factory=FamilyNotes)  # what the families tell each other


_FAMILIES: list[type[RuleFamily]] = []


class RuleFamily:
    """A family of rules that decides from facts and records edits in a ``Plan``.

    Subclasses set ``RULES`` (and ``after`` where they read another family's notes), may narrow ``may_fire`` with a cheap test on
    the facts, and implement ``decide``. They report with ``self.report(node, code,
    message)`` (``node`` is an ``ast`` node of the original source) and edit through
    ``self.plan`` (``replace``, ``insert_after``, ``ensure_import``...).
    """

    RULES: ClassVar[tuple[Rule, ...]] = ()
    # Families whose notes this one reads (``rules/notes.py``): the pipeline runs them first.
    after: ClassVar[tuple[str, ...]] = ()

    def __init_subclass__(cls, **kwargs: object) -> None:
        super().__init_subclass__(**kwargs)
        if cls.RULES:
            _FAMILIES.append(cls)

    def __init__(self, context: FileContext, facts: ModuleFacts, receivers: Receivers, plan: Plan) -> None:
        self.context = context
        self.facts = facts
        self.receivers = receivers
        self.plan = plan
        self.notes = context.notes
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
    """Every family, in the order of ``PIPELINE`` (``rules/__init__.py``)."""
    return list(_ordered_families())


def set_pipeline(names: tuple[str, ...]) -> None:
    """The order families decide in; each must come after the families it names in ``after``."""
    global _PIPELINE
    _PIPELINE = names
    _ordered_families.cache_clear()


_PIPELINE: tuple[str, ...] = ()


@lru_cache(maxsize=1)
def _ordered_families() -> tuple[type[RuleFamily], ...]:
    by_name = {cls.__name__: cls for cls in _FAMILIES}
    missing = sorted(set(by_name) - set(_PIPELINE))
    unknown = sorted(set(_PIPELINE) - set(by_name))
    if missing or unknown:
        raise RuntimeError(f"rules/__init__.py PIPELINE: families not listed {missing}, names without a family {unknown}")
    for position, name in enumerate(_PIPELINE):
        for before in by_name[name].after:
            if before not in by_name:
                raise RuntimeError(f"{name}.after names {before!r}, which is no family")
            if _PIPELINE.index(before) > position:
                raise RuntimeError(f"{name} reads the notes of {before}, which the PIPELINE runs later")
    return tuple(by_name[name] for name in _PIPELINE)


# Rules carried out outside the Python engine (``rules/dependency_files.py``).
_STANDALONE_RULES: list[Rule] = []


def register_rules(*rules: Rule) -> None:
    """Declare rules that no family of the Python engine implements."""
    _STANDALONE_RULES.extend(rules)


def standalone_rules() -> list[Rule]:
    return list(_STANDALONE_RULES)


def all_rules() -> list[Rule]:
    rules = [rule for cls in registered_families() for rule in cls.RULES] + _STANDALONE_RULES
    return sorted(rules, key=lambda rule: rule.code)
