"""Arbitrary Python programs (hypothesmith, from the language grammar) keep the engine's promises.

tests/test_properties.py composes programs from legacy Gym statements; these come from
the whole grammar instead, with or without Gym code mixed in, to reach syntax no one
thought of. Whatever happens, the engine either refuses the file (TransformError, left
alone) or its promises hold:

- a program that never mentions gym is returned byte for byte;
- a rewrite parses;
- a second run over a rewrite changes nothing.

The default run is small, to keep the suite fast. ``GYMMIGRATE_LONG_PROPERTIES=1``
runs many more examples (minutes).
"""

from __future__ import annotations

import ast
import os
import re

import hypothesmith
import pytest
from hypothesis import HealthCheck, assume, given, reject, settings
from hypothesis import strategies as st

from gymmigrate.engine import Transformed, transform_source
from gymmigrate.source_text import TransformError

# Generated code is often odd ("'str' object is not callable; perhaps you missed a comma?").
pytestmark = pytest.mark.filterwarnings("ignore::SyntaxWarning")

LONG = os.environ.get("GYMMIGRATE_LONG_PROPERTIES") == "1"
PROPERTIES = settings(
    max_examples=1000 if LONG else 30,
    deadline=None,  # one example can hit a slow path of LibCST; a deadline would only flake
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large],
)
GYM = re.compile("gym", re.IGNORECASE)
BROKEN_PROMISES = ("internal error", "not stable", "oscillates", "does not settle", "would not parse")
LEGACY_SNIPPETS = [
    "import gym\n",
    "from gym import spaces\n",
    "import gym\nenv = gym.make('CartPole-v1')\nenv.seed(0)\nobs = env.reset()\n",
    "import gym\nenv = gym.make('CartPole-v1')\nobs, reward, done, info = env.step(0)\n",
]


def _encoded(program: str) -> bytes:
    try:
        return program.encode("utf-8")
    except UnicodeEncodeError:  # lone surrogates: not a file anyone can save
        reject()


def _transform(source: bytes) -> Transformed | None:
    """The rewrite, or None when the engine refuses the input (it is then left alone).

    Refusing input (a syntax error, an encoding, bytes LibCST cannot reproduce) is
    allowed. The engine's own checks also turn a rule crash, an unstable or unparsable
    rewrite into a refusal: safe for the user, but a broken promise here.
    """
    try:
        return transform_source(source, "generated.py")
    except TransformError as exc:
        assert not any(broken in str(exc) for broken in BROKEN_PROMISES), str(exc)
        return None


def _parses(source: bytes) -> bool:
    try:
        ast.parse(source)
    except SyntaxError:
        return False
    return True


def _join(program: str, snippet: str, snippet_first: bool) -> str:
    return snippet + program if snippet_first else program + "\n" + snippet


# Built once: from_grammar() compiles the Python grammar, which takes a second or two.
PROGRAMS = hypothesmith.from_grammar()
# A generated program with legacy Gym code before or after it.
PROGRAMS_WITH_GYM_CODE = st.builds(_join, PROGRAMS, st.sampled_from(LEGACY_SNIPPETS), st.booleans())


@PROPERTIES
@given(PROGRAMS.filter(lambda program: not GYM.search(program)))
def test_programs_without_gym_code_are_never_changed(program: str) -> None:
    source = _encoded(program)
    result = _transform(source)
    assert result is None or result.rewritten == source


@PROPERTIES
@given(PROGRAMS_WITH_GYM_CODE)
def test_any_program_stays_identical_or_becomes_code_that_parses(program: str) -> None:
    source = _encoded(program)
    result = _transform(source)
    assert result is None or result.rewritten == source or _parses(result.rewritten)


@PROPERTIES
@given(PROGRAMS_WITH_GYM_CODE)
def test_a_second_run_changes_nothing(program: str) -> None:
    result = _transform(_encoded(program))
    assume(result is not None and result.changed)
    again = transform_source(result.rewritten, "generated.py")
    assert again.rewritten == result.rewritten
