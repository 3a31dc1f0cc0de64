"""Re-parsing only the touched top-level statements gives exactly the whole-module edit.

``edits.splice`` cuts the runs of top-level statements that hold an edit out of the
text, edits them as small modules and keeps the rest of the text as it was. It is only
an optimisation: for every input it must give the bytes that editing the whole module
gives, or decline (None) and let the engine edit the whole module.
"""

from __future__ import annotations

import ast
import textwrap

import libcst as cst
import pytest

from gymmigrate.edits.apply import ApplyError, apply_plan
from gymmigrate.edits.plan import Plan
from gymmigrate.edits.splice import splice_plan
from gymmigrate.engine import _parse_cst, plan_file
from gymmigrate.facts import ModuleFacts
from gymmigrate.options import RewriteOptions
from gymmigrate.source_text import decode
from tests.fixture_cases import collect_cases


def _plan(text: str) -> Plan:
    return plan_file(ast.parse(text), text, "<test>", RewriteOptions())


def both_ways(text: str) -> tuple[str | None, str]:
    """(spliced or None, whole-module result), each from its own plan: builds may keep state."""
    spliced = splice_plan(text, _plan(text), _parse_cst)
    whole = apply_plan(cst.parse_module(text), _plan(text)).code
    return spliced, whole


@pytest.mark.parametrize("case", collect_cases(), ids=lambda case: case.id)
def test_every_fixture_gives_the_same_text_either_way(case) -> None:
    text, _ = decode(case.source.read_bytes())
    if not _plan(text).has_edits:
        return
    spliced, whole = both_ways(text)
    assert spliced is None or spliced == whole


LEGACY_LOOP = """\
import gym
# set up
env = gym.make("CartPole-v1")
env.seed(0)
obs = env.reset()
"""


@pytest.mark.parametrize(
    "text",
    [
        LEGACY_LOOP,
        LEGACY_LOOP.replace("\n", "\r\n"),  # CRLF newlines come back as CRLF
        "import gym; import os\nenv = gym.make('CartPole-v1'); obs = env.reset()\nprint(os.sep)\n",  # shared lines
        # tabs in the first block, and a later block to edit
        "import gym\nif True:\n\tx = 1\n\ndef run():\n\tenv = gym.make('CartPole-v1')\n\tobs = env.reset()\n",
        # the first block indented by two, the edited one by four: the cut would guess four
        "import gym\nif True:\n  x = 1\n\ndef run():\n    env = gym.make('CartPole-v1')\n    if x:\n        obs = env.reset()\n",
        # a decorated class, comments between statements, no newline at the end
        "import gym\n\n@decorate\nclass Env(gym.Env):\n    def reset(self):\n        return 0\n# tail comment\nx = 1",
        # the statement before the seeded one is compound: its footer holds the comment
        "import gym\nclass A:\n    pass\n    # footer\nenv = gym.make('CartPole-v1')\nenv.seed(0)\nenv.reset()\n",
    ],
    ids=["lf", "crlf", "shared-lines", "tabs", "mixed-indent", "decorated", "after-compound"],
)
def test_edge_cases_give_the_same_text_either_way(text: str) -> None:
    spliced, whole = both_ways(text)
    assert whole != text  # the case really edits something
    assert spliced is None or spliced == whole


def test_a_file_edited_in_one_place_is_only_reparsed_there(monkeypatch: pytest.MonkeyPatch) -> None:
    untouched = "".join(f"def helper_{i}(x):\n    return x + {i}\n\n" for i in range(50))
    text = "import gym\n\n" + untouched + "env = gym.make('CartPole-v1')\nobs = env.reset()\n"
    parsed: list[str] = []

    def parse(segment: str) -> cst.Module:
        parsed.append(segment)
        return cst.parse_module(segment)

    result = splice_plan(text, _plan(text), parse)
    assert result == apply_plan(cst.parse_module(text), _plan(text)).code
    assert sum(len(segment) for segment in parsed) < len(text) / 10
    assert untouched in result


def test_an_edit_reaching_outside_the_cut_is_an_error_not_a_wrong_edit() -> None:
    # The comment above a removed statement moves to the next one, which this cut lacks.
    text = "x = 0\n# note\na = 1\nb = 2\n"
    plan = Plan(ModuleFacts(ast.parse(text), text))
    plan.remove(plan.facts.tree.body[1], keep_comments=True)
    with pytest.raises(ApplyError, match="outside"):
        apply_plan(cst.parse_module("x = 0\n# note\na = 1\n"), plan, window=(0, 2))
    assert splice_plan(text, plan, _parse_cst) == "x = 0\n# note\nb = 2\n"


def test_decline_where_the_whole_module_is_needed() -> None:
    # new imports with nothing to follow: they go before the first statement
    text = "env = make()\n"
    plan = Plan(ModuleFacts(ast.parse(text), text))
    plan.add_import("import gymnasium as gym")
    assert splice_plan(text, plan, _parse_cst) is None
    # the removal of the first statement: its comment lines are the module's header
    text = textwrap.dedent(
        """\
        # comment
        x = 1
        y = 2
        """
    )
    plan = Plan(ModuleFacts(ast.parse(text), text))
    plan.remove(plan.facts.tree.body[0])
    assert splice_plan(text, plan, _parse_cst) is None
