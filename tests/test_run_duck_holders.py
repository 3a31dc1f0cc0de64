"""A plain class of one module that stands for the Gym env another module hands it (issue #19).

``fixtures/project_duck_holders/``: ``shrink.Shrink`` keeps the env it is given in
``self.game``, offers its spaces, skips frames and builds its own observations and four-field step;
``runner.Runner.start`` makes an env and, below it in the same method, hands the inner layer of
that make to ``Shrink``, rebinding the attribute. The run proves ``Shrink`` holds a Gym env:
it is migrated with ``Runner``'s calls, and the ``.env`` read, which sees the make, is asked
about (Gymnasium's inner layer no longer forwards the base env's attributes).
``shrink.Tape`` has the same shape but is built on what another library makes: it and its
caller stay as they are, and the caller is reported.

``store_seen`` is the part that says what such a read sees: the store above it in the same
method, unless something between may store the attribute again.
"""

from __future__ import annotations

import ast
from pathlib import Path

import gymnasium as gym
import numpy as np

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.self_attributes import store_seen
from tests.fixture_cases import migrated_project


def _migrated(tmp_path: Path) -> tuple[Path, list[tuple[str, int, str]]]:
    return migrated_project(tmp_path, "project_duck_holders")


def test_the_holder_of_another_module_is_migrated_with_its_callers(tmp_path: Path) -> None:
    project, review = _migrated(tmp_path)
    shrink = (project / "shrink.py").read_text()
    assert "def reset(self, *, seed=None, options=None):" in shrink
    assert "return self._small(), total, terminated, truncated, info" in shrink
    runner = (project / "runner.py").read_text()
    assert "obs, info = self._game.reset()" in runner
    assert ("runner.py", 16, "GM606") in review  # ``self._game.env`` sees the make above it
    namespace: dict = {}
    exec(compile(shrink, "shrink.py", "exec"), namespace)
    env = namespace["Shrink"](gym.make("CartPole-v1").unwrapped)
    obs, info = env.reset(seed=0)
    assert obs.dtype == np.uint8 and info == {}
    result = env.step(0)
    assert len(result) == 5


def test_the_same_shape_built_on_another_librarys_object_is_left(tmp_path: Path) -> None:
    project, review = _migrated(tmp_path)
    shrink = (project / "shrink.py").read_text()
    assert "obs = self.game.reset()\n        self.frames = [obs]" in shrink
    assert "obs, reward, ended, info = self.game.step(action)" in shrink
    runner = (project / "runner.py").read_text()
    assert "obs = tape.reset()" in runner
    assert ("runner.py", 29, "GM201") in review


def _read(source: str) -> tuple[ModuleFacts, ast.Attribute]:
    facts = ModuleFacts(ast.parse(source), source)
    reads = [
        node for node in ast.walk(facts.tree)
        if isinstance(node, ast.Attribute) and node.attr == "inner" and isinstance(node.ctx, ast.Load)
    ]
    return facts, max(reads, key=lambda node: node.lineno)


def test_a_read_sees_the_store_above_it_in_the_method() -> None:
    facts, read = _read(
        "class Holder:\n"
        "    def start(self):\n"
        "        self.inner = make()\n"
        "        if wanted():\n"
        "            self.inner = Wrap(self.inner)\n"
    )
    seen = store_seen(facts, read, "inner")
    assert isinstance(seen, ast.Call) and ast.unparse(seen) == "make()"


def test_a_method_call_between_may_store_it_again() -> None:
    facts, read = _read(
        "class Holder:\n"
        "    def start(self):\n"
        "        self.inner = make()\n"
        "        self.configure()\n"
        "        self.inner = Wrap(self.inner)\n"
    )
    assert store_seen(facts, read, "inner") is None


def test_a_loop_around_the_read_sees_its_own_store_on_the_next_turn() -> None:
    facts, read = _read(
        "class Holder:\n"
        "    def start(self):\n"
        "        self.inner = make()\n"
        "        for _ in range(3):\n"
        "            self.inner = Wrap(self.inner)\n"
    )
    assert store_seen(facts, read, "inner") is None
