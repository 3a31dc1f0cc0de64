"""PZ104 / PZ108: one store of a custom env's ``dones`` split by meaning.

A store (``self.dones = ...``, ``dones[agent] = ...``, or a parallel step's local
``dones``) goes to the dict its causes say (``endings.py`` traces them): a step or cycle
limit to ``truncations``, any other cause to ``terminations``, ``a or <limit>`` to both;
the other dict is kept beside it, and what cannot be traced goes to ``terminations`` for
review. ``env_classes.py`` finds the stores and owns the plan; this module words each.
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from typing import TYPE_CHECKING

from gymmigrate.facts.module import ModuleFacts
from gymmigrate.findings import FixKind
from gymmigrate.rules.pettingzoo.common import AGENT
from gymmigrate.rules.pettingzoo.endings import Cause, Traced, is_true, joined

if TYPE_CHECKING:
    from gymmigrate.rules.pettingzoo.env_classes import EnvClasses


def is_empty_dict(value: ast.AST) -> bool:
    if isinstance(value, ast.Dict):
        return not value.keys
    return isinstance(value, ast.Call) and isinstance(value.func, ast.Name) and value.func.id == "dict" and not value.args and not value.keywords


class _Elements:
    """The per-agent values a whole store of ``dones`` holds, and the comprehension's
    variable (None for ``dict.fromkeys`` and literals)."""

    def __init__(self, values: list[ast.expr], key: str | None, per_agent: bool) -> None:
        self.values = values
        self.key = key
        self.per_agent = per_agent  # one value for every agent: a comprehension or ``dict.fromkeys``


def _elements(value: ast.AST) -> _Elements | None:
    if isinstance(value, ast.DictComp):
        if len(value.generators) != 1:
            return None
        target = value.generators[0].target
        key = target.id if isinstance(target, ast.Name) and isinstance(value.key, ast.Name) and value.key.id == target.id else None
        return _Elements([value.value], key, key is not None)
    if (
        isinstance(value, ast.Call) and isinstance(value.func, ast.Attribute) and value.func.attr == "fromkeys"
        and isinstance(value.func.value, ast.Name) and value.func.value.id == "dict" and not value.keywords
        and 1 <= len(value.args) <= 2 and not any(isinstance(a, ast.Starred) for a in value.args)
    ):
        return _Elements(value.args[1:], None, len(value.args) == 2)
    if isinstance(value, ast.Dict) and all(k is not None for k in value.keys):
        return _Elements(list(value.values), None, False)
    return None


class DonesSplit:
    """One store of ``dones`` (``dones = ...`` or ``dones[k] = ...``) sent to the dict its
    causes say (see endings.py), with the other dict kept beside it."""

    def __init__(self, family: EnvClasses, classdef: ast.ClassDef, terminations: str, truncations: str,
                 rename: Callable[[str], None], empty: bool = False) -> None:
        self.family = family
        self.facts = family.facts
        self.endings = family.endings(classdef)
        self.term, self.trunc = terminations, truncations
        self.rename = rename  # the stored dict becomes ``terminations`` or ``truncations``
        self.empty = empty  # a local dict that starts empty: item stores keep both dicts' keys
        self.limited = False  # a step limit feeds this store
        self.code = "PZ108" if terminations.startswith("self.") else "PZ104"
        self.old = "self.dones" if terminations.startswith("self.") else "dones"

    # -- whole stores ---------------------------------------------------------------------

    def whole(self, statement: ast.Assign, owned: bool) -> None:
        value = statement.value
        elements = _elements(value)
        branch = self.endings.branch(statement)
        if branch is Cause.UNKNOWN:
            self._untraced(statement, "the `if` above it mixes a step limit with other causes")
            return
        if branch is Cause.TRUNCATION:
            self.limited = True
            if owned and elements is not None and elements.key is not None and all(is_true(v) for v in elements.values):
                # ``if <limit>: self.dones = {a: True for a in self.agents}``: keep an agent
                # that terminated on this step terminated.
                self.rename("truncations")
                self.family.replace_element(value, f"not {self.term}[{elements.key}]")
                self._report(statement, f"goes to `{self.trunc}` (the `if` above calls the match off on a step limit, "
                             "except for agents terminated on the same step)")
                return
            self._store(statement, "truncations", "the `if` above calls the match off on a step limit")
            return
        if elements is None:
            limit = self.endings.is_limit(value)
            if not limit and self.endings.mentions_limit(value):
                self._untraced(statement, "a step limit is tested inside it")
                return
            self._store(statement, "truncations" if limit else "terminations",
                        "a step limit" if limit else "no step limit among its causes: the game ended")
            return
        traced = [self.endings.value(v) for v in elements.values]
        causes = {t.cause for t in traced}
        if Cause.UNKNOWN in causes:
            self._untraced(statement, "a step limit is tested inside its value")
        elif causes <= {Cause.TERMINATION}:
            start = all(isinstance(v, ast.Constant) and v.value is False for v in elements.values)
            self._store(statement, "terminations", "all False: nothing has ended" if start else
                        "no step limit among its causes: the game ended")
        elif causes == {Cause.TRUNCATION}:
            self._store(statement, "truncations", "a step limit calls the match off")
        elif len(traced) == 1 and elements.per_agent and causes == {Cause.SPLIT}:
            self._split_whole(statement, elements, traced[0])
        else:
            self._untraced(statement, "its values end the game for some agents and call it off for others")

    def _store(self, statement: ast.Assign, stored: str, why: str) -> None:
        if stored == "truncations":
            self.limited = True
        other = self.trunc if stored == "terminations" else self.term
        mine = self.term if stored == "terminations" else self.trunc
        if not self.family.own_line(statement):
            self._untraced(statement, "it shares its line with other code")
            return
        self.rename(stored)
        elements = _elements(statement.value)
        key = elements.key if elements is not None and elements.key is not None else AGENT
        partner = f"{other} = {{}}" if self.empty and is_empty_dict(statement.value) else \
            f"{other} = {{{key}: False for {key} in {mine}}}"
        self.family.plan.insert_after(statement, partner)
        if partner.endswith("{}"):
            why = "both dicts start empty"
        self._report(statement, f"goes to `{mine}` ({why})")

    def _split_whole(self, statement: ast.Assign, elements: _Elements, traced: Traced) -> None:
        if not self.family.own_line(statement):
            self._untraced(statement, "it shares its line with other code")
            return
        key = elements.key or AGENT
        element = elements.values[0]
        if traced.name is not None:
            if not self.family.split_assignment(traced, element):
                self._untraced(statement, f"`{traced.name.id}` cannot be split where it is assigned")
                return
            self.family.replace_element(statement.value, "termination")
            partner = f"{self.trunc} = {{{key}: truncation for {key} in {self.term}}}"
        else:
            self.family.replace_element(statement.value, joined(traced.task, self.facts))
            partner = f"{self.trunc} = {{{key}: not {self.term}[{key}] and {_limit_text(traced, self.facts)} for {key} in {self.term}}}"
        self.limited = True
        self.rename("terminations")
        self.family.plan.insert_after(statement, partner)
        self._report(statement, f"splits: {_split_reason(traced, self.facts)}")

    # -- item stores ----------------------------------------------------------------------

    def item(self, statement: ast.Assign, subscript: ast.Subscript) -> None:
        index = self.facts.segment(subscript.slice)
        value = statement.value
        branch = self.endings.branch(statement)
        if branch is Cause.UNKNOWN:
            self._untraced(statement, "the `if` above it mixes a step limit with other causes")
            return
        if branch is Cause.TRUNCATION:
            self.limited = True
            if is_true(value):
                self.family.replace_text(value, f"not {self.term}[{index}]")
            self._item(statement, "truncations", index, "the `if` above calls the match off on a step limit"
                       + (", except for an agent terminated on the same step" if is_true(value) else ""))
            return
        traced = self.endings.value(value)
        if traced.cause is Cause.UNKNOWN:
            self._untraced(statement, "a step limit is tested inside its value")
        elif traced.cause is Cause.TERMINATION:
            self._item(statement, "terminations", index, "no step limit among its causes: the game ended")
        elif traced.cause is Cause.TRUNCATION:
            self._item(statement, "truncations", index, "a step limit calls the match off")
        else:
            self._split_item(statement, index, traced)

    def _item(self, statement: ast.Assign, stored: str, index: str, why: str) -> None:
        if stored == "truncations":
            self.limited = True
        mine, other = (self.term, self.trunc) if stored == "terminations" else (self.trunc, self.term)
        if self.empty:
            if not self.family.own_line(statement):
                self._untraced(statement, "it shares its line with other code")
                return
            self.family.plan.insert_after(statement, f"{other}.setdefault({index}, False)")
        self.rename(stored)
        self._report(statement, f"goes to `{mine}` ({why})")

    def _split_item(self, statement: ast.Assign, index: str, traced: Traced) -> None:
        if not self.family.own_line(statement):
            self._untraced(statement, "it shares its line with other code")
            return
        if traced.name is not None:
            if not self.family.split_assignment(traced, statement.value):
                self._untraced(statement, f"`{traced.name.id}` cannot be split where it is assigned")
                return
            self.family.replace_value(statement, "termination")
            partner = f"{self.trunc}[{index}] = truncation"
        else:
            self.family.replace_value(statement, joined(traced.task, self.facts))
            partner = f"{self.trunc}[{index}] = not {self.term}[{index}] and {_limit_text(traced, self.facts)}"
        self.limited = True
        self.rename("terminations")
        self.family.plan.insert_after(statement, partner)
        self._report(statement, f"splits: {_split_reason(traced, self.facts)}")

    # -- reports --------------------------------------------------------------------------

    def _report(self, statement: ast.stmt, what: str) -> None:
        self.family.report(statement, self.code, f"`{self.old}` split by meaning (PettingZoo 1.21): this store {what}",
                           FixKind.AUTO)

    def _untraced(self, statement: ast.Assign, why: str) -> None:
        """Kept as terminations (what ``dones`` meant before truncations existed), for review."""
        self.rename("terminations")
        if self.empty or isinstance(statement.targets[0], (ast.Name, ast.Attribute)):
            mine = self.term
            if self.family.own_line(statement):
                partner = f"{self.trunc} = {{}}" if self.empty and is_empty_dict(statement.value) else (
                    f"{self.trunc}.setdefault({self.facts.segment(statement.targets[0].slice)}, False)"
                    if isinstance(statement.targets[0], ast.Subscript)
                    else f"{self.trunc} = {{{AGENT}: False for {AGENT} in {mine}}}"
                )
                self.family.plan.insert_after(statement, partner)
        self.family.report(statement, self.code, f"`{self.old}` split: this store could not be traced ({why}), so it "
                           f"went to `{self.term}`; review: a game over is a termination, a step limit a truncation; split it "
                           "by hand", FixKind.ASSIST)


def _limit_text(traced: Traced, facts: ModuleFacts) -> str:
    text = joined(traced.limit, facts)
    return f"({text})" if len(traced.limit) > 1 else text


def _split_reason(traced: Traced, facts: ModuleFacts) -> str:
    task, limit = joined(traced.task, facts), joined(traced.limit, facts)
    return (f"`{task}` ends the game (a termination), `{limit}` calls it off (a truncation, not for an agent "
            "terminated on the same step)")
