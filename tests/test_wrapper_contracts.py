"""Own wrapper contracts: what the items on a wrapper subclass's constructor and reset advise."""

from __future__ import annotations

from gymmigrate.engine import transform_source
from tests.fixture_cases import FIXTURES


def _messages(path: str, rule: str) -> list[str]:
    source = (FIXTURES / path).read_bytes()
    return [f.message for f in transform_source(source, path).findings if f.rule == rule]


def test_gm603_advises_the_wrapper_base_by_name_where_an_env_base_comes_first() -> None:
    # ``super().__init__(env)`` would reach the env base's abstract constructor first
    (message,) = _messages("rules/GM603/env_base_ahead.py", "GM603")
    assert "call `gym.Wrapper.__init__(self, env)`" in message
    assert "`__getattr__`" in message


def test_gm603_keeps_super_advice_where_the_wrapper_base_comes_first() -> None:
    (message,) = _messages("rules/GM603/wrapper_base_first.py", "GM603")
    assert "call it instead of setting `self.env` by hand" in message
    assert "gym.Wrapper.__init__(self, env)" not in message


def test_gm601_reports_a_wrapper_reset_that_returns_nothing() -> None:
    (message,) = _messages("rules/GM601/reset_returns_nothing.py", "GM601")
    assert "returns nothing at the end of its body" in message


def test_gm601_is_quiet_on_a_pass_through_reset_and_a_raising_hook() -> None:
    assert _messages("rules/GM601/reset_returns_inner_pair_kept.py", "GM601") == []


def test_gm602_reports_a_step_that_returns_a_four_value_method() -> None:
    messages = _messages("rules/GM602/step_returns_own_four_value_method.py", "GM602")
    assert len(messages) == 2
    assert "`self.run_many(...)`" in messages[0] and "wrapped env's own `run_many`" in messages[0]
    assert "`self.scripted(...)`" in messages[1] and "gives four values" in messages[1]


def test_gm602_is_quiet_on_a_method_that_hands_on_five_values() -> None:
    assert _messages("rules/GM602/step_returns_own_five_value_method_kept.py", "GM602") == []
