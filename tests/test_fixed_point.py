"""The fixed point by iteration: a rewrite whose output another round still changes is
applied again and verified, up to a bound; only an oscillation is refused, naming the
rules that kept changing it. The rules here are test-only families registered for one
test each, so the mechanism is exercised whatever the real rules do."""

from __future__ import annotations

import ast
from collections.abc import Iterator
from contextlib import contextmanager

import pytest

from gymmigrate.engine import MAX_ROUNDS, transform_source
from gymmigrate.findings import FixKind
from gymmigrate.rules import PIPELINE
from gymmigrate.rules.base import _FAMILIES, FamilySpec, Rule, RuleFamily, set_pipeline
from gymmigrate.source_text import TransformError


@contextmanager
def registered(family: type[RuleFamily]) -> Iterator[None]:
    if family not in _FAMILIES:  # registered when its class was made; again for a second use
        _FAMILIES.append(family)
    set_pipeline((*PIPELINE, FamilySpec(family.__name__, __name__)))
    try:
        yield
    finally:
        _FAMILIES.remove(family)
        set_pipeline(PIPELINE)


def _counter_family(name: str, step: dict[int, int]) -> type[RuleFamily]:
    """Rewrites ``level = N`` to ``level = step[N]``; a file saying ``import gym`` so it runs."""

    def decide(self: RuleFamily) -> None:
        for node in ast.walk(self.facts.tree):
            if (
                isinstance(node, ast.Assign)
                and isinstance(node.targets[0], ast.Name)
                and node.targets[0].id == "level"
                and isinstance(node.value, ast.Constant)
                and node.value.value in step
            ):
                new = step[node.value.value]
                self.plan.replace(node.value, lambda cst_node, new=new: cst_node.with_changes(value=str(new)))
                self.report(node, "GM998", f"level {node.value.value} -> {new}")

    return type(name, (RuleFamily,), {"RULES": (Rule("GM998", "test", FixKind.AUTO, "test"),), "decide": decide})


def test_a_rewrite_that_needs_a_second_round_settles() -> None:
    family = _counter_family("TwoRounds", {1: 2, 2: 3})
    with registered(family):
        result = transform_source(b"import gymnasium as gym\nlevel = 1\n")
    assert result.rewritten == b"import gymnasium as gym\nlevel = 3\n"
    assert [f.message for f in result.findings if f.rule == "GM998"] == ["level 1 -> 2", "level 2 -> 3"]
    assert all(f.line == 2 and f.line_after == 2 for f in result.findings if f.rule == "GM998")
    with registered(family):
        assert transform_source(result.rewritten).rewritten == result.rewritten  # a fixed point


def test_an_oscillation_is_refused_naming_the_rule() -> None:
    family = _counter_family("SeeSaw", {1: 2, 2: 1})
    with registered(family), pytest.raises(TransformError, match=r"oscillates \(SeeSaw"):
        transform_source(b"import gymnasium as gym\nlevel = 1\n")


def test_a_rewrite_that_never_settles_is_refused_after_the_bound() -> None:
    family = _counter_family("Climb", {n: n + 1 for n in range(1, 20)})
    with registered(family), pytest.raises(TransformError, match=rf"does not settle after {MAX_ROUNDS} rounds \(Climb"):
        transform_source(b"import gymnasium as gym\nlevel = 1\n")
