"""Families load lazily: a family's module is imported only for a file that spells one of
its words (``rules/__init__.py``'s ``PIPELINE``). The words must be a necessary condition
of the family's own ``may_fire``, or a file would silently miss its rewrites: every
fixture, notebook program and benchmark example holds the pipeline to that."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.profile import FileProfile
from gymmigrate.options import RewriteOptions
from gymmigrate.rules import PIPELINE
from gymmigrate.rules.base import FileContext
from gymmigrate.rules.wrapper_usage.atari_api import ATARI_METHOD_WORDS

ROOT = Path(__file__).resolve().parent.parent
SOURCES = sorted(p for p in (ROOT / "fixtures").rglob("*.py"))


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(ROOT / "fixtures")))
def test_a_family_that_may_fire_is_always_loaded(path: Path) -> None:
    text = path.read_text(encoding="utf-8")
    try:
        tree = ast.parse(text)
    except SyntaxError:
        pytest.skip("not Python 3")
    facts = ModuleFacts(tree, text)
    context = FileContext(path=str(path), options=RewriteOptions(), profile=FileProfile.from_source(text))
    for spec in PIPELINE:
        if spec.load().may_fire(facts, context):
            assert spec.may_fire_in(text), f"{spec.name} may fire on {path.name} but none of {spec.words} is in it"


def test_check_loads_only_the_families_that_may_fire(tmp_path: Path) -> None:
    script = tmp_path / "train.py"
    script.write_text("import gym\nenv = gym.make('CartPole-v1')\nobs = env.reset()\n")
    probe = (
        "import sys\n"
        f"sys.argv = ['gymmigrate', 'check', {str(script)!r}]\n"
        "from gymmigrate.cli import main\n"
        "try:\n    main()\nexcept SystemExit:\n    pass\n"
        "print(sorted(m for m in sys.modules if m.startswith('gymmigrate.rules.pettingzoo')), file=sys.stderr)\n"
    )
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=120)
    assert done.stderr.strip().splitlines()[-1] == "[]", done.stderr


def test_forwarding_words_name_the_atari_methods() -> None:
    """The forwarding family decides gym's AtariEnv's calls in modules that never name gym:
    its words must hold every spelling it fires on."""
    (spec,) = [s for s in PIPELINE if s.name == "WrapperForwarding"]
    assert set(ATARI_METHOD_WORDS) <= set(spec.words or ())
