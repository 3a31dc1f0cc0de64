"""Noise patterns settled by the rewrite, executed against Gymnasium."""

from __future__ import annotations

import logging
import warnings
from pathlib import Path

from gymmigrate.engine import transform_source
from tests.fixture_cases import RULE_FIXTURES


def test_logger_info_and_debug_run_through_the_standard_library(tmp_path: Path, caplog) -> None:
    path = RULE_FIXTURES / "GM906" / "info_debug_to_logging.py"
    rewritten = transform_source(path.read_bytes(), str(path)).rewritten
    namespace: dict[str, object] = {"__name__": "migrated_logging"}
    exec(compile(rewritten, str(path), "exec"), namespace)  # noqa: S102 (our own fixture)
    target = tmp_path / "monitor"
    with caplog.at_level(logging.DEBUG, logger="migrated_logging"), warnings.catch_warnings(record=True):
        namespace["make_dirs"](str(target))
    assert target.is_dir()
    assert [r.getMessage() for r in caplog.records] == [
        f"Creating monitor directory {target}",
        f"Writing manifest to {target}",
    ]


def test_a_file_that_lowers_gyms_level_keeps_its_log_calls_reported() -> None:
    path = RULE_FIXTURES / "GM906" / "logger_levels.py"
    result = transform_source(path.read_bytes(), str(path))
    assert b"gym.logger.info(" in result.rewritten
    assert any(f.rule == "GM906" and f.needs_review and "info" in f.message for f in result.findings)


def test_a_step_limit_wrapper_truncates() -> None:
    import gymnasium

    path = RULE_FIXTURES / "GM602" / "time_limit_pattern.py"
    rewritten = transform_source(path.read_bytes(), str(path)).rewritten
    namespace: dict[str, object] = {"__name__": "migrated_time_limit"}
    exec(compile(rewritten, str(path), "exec"), namespace)  # noqa: S102 (our own fixture)
    env = namespace["StepLimit"](gymnasium.make("CartPole-v1").unwrapped, max_episode_steps=3)
    env.reset(seed=0)
    flags = [env.step(i % 2)[2:4] for i in range(3)]
    assert flags == [(False, False), (False, False), (False, True)], "the third step is cut by the limit"


def test_an_untraced_receiver_is_one_review_item_naming_every_line() -> None:
    path = RULE_FIXTURES / "GM201" / "untraced_receiver_asked_once.py"
    result = transform_source(path.read_bytes(), str(path))
    asked = [f for f in result.findings if f.needs_review]
    assert [(f.line, f.rule) for f in asked] == [(7, "GM201")]
    assert asked[0].message.endswith("(the same question at lines 10, 11)")
    pointers = [f for f in result.findings if "asked once, at line 7" in f.message]
    # the module makes no Gym env (an unused import): reported, nothing rewritten
    assert sorted(f.line for f in pointers) == [10, 11] and not any(f.is_change for f in pointers)


def test_the_legacy_autoreset_question_is_asked_once_per_file() -> None:
    path = RULE_FIXTURES / "GM706" / "loop_variable_terminal.py"
    result = transform_source(path.read_bytes(), str(path))
    asked = [f for f in result.findings if f.needs_review and f.rule == "GM706"]
    assert [f.line for f in asked] == [3] and "same step" in asked[0].message
    assert sorted(f.line for f in result.findings if f.rule == "GM706" and not f.needs_review) == [9, 10]


def test_a_sampled_discrete_action_takes_the_integer_branch_of_a_migrated_step() -> None:
    path = RULE_FIXTURES / "GM903" / "discrete_action_in_step.py"
    rewritten = transform_source(path.read_bytes(), str(path)).rewritten
    namespace: dict[str, object] = {"__name__": "migrated_maze"}
    exec(compile(rewritten, str(path), "exec"), namespace)  # noqa: S102 (our own fixture)
    env = namespace["Maze"]()
    env.reset(seed=0)
    env.action_space.seed(0)
    action = env.action_space.sample()
    assert not isinstance(action, int)  # np.int64: the legacy check alone would miss it
    *_, info = env.step(action)
    assert info["move"] in ("N", "S", "E", "W")


def test_a_removed_import_repeated_in_a_file_is_one_item_naming_every_import() -> None:
    path = RULE_FIXTURES / "GM105" / "noop_same_removed_import_in_two_methods.py"
    result = transform_source(path.read_bytes(), str(path))
    asked = [f for f in result.findings if f.needs_review]
    assert [(f.line, f.rule) for f in asked] == [(7, "GM105")]
    assert asked[0].message.endswith("(the same question at line 14)")
    assert [f.line for f in result.findings if "asked once, at line 7" in f.message] == [14]


def test_removed_imports_needing_different_moves_name_no_other_line() -> None:
    path = RULE_FIXTURES / "GM105" / "noop_different_moves_asked_apart.py"
    result = transform_source(path.read_bytes(), str(path))
    assert [f.line for f in result.findings if f.needs_review] == [2, 7]
    assert not any("the same question" in f.message or "asked once" in f.message for f in result.findings)
