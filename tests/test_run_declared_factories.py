"""A factory of the run that builds its env by calling a class parameter whose default and
the def's return annotation name the same class (``def build(size, env_class=GridEnv) ->
GridEnv``) gives its callers in other modules what calling that class gives
(``fixtures/project_declared_factories``).

``build`` declares a ``GridEnv``, a Gym env the run migrates: ``env.seed(s)`` on its result
is merged into the reset that follows, as on ``GridEnv(...)`` itself. ``build_dual``
declares ``DualEnv``, whose step and reset keep an API of their own and whose seed() stays:
the caller's seed and reset are left, with no question (the class's item asks it once).
``build_any`` has the same default but no annotation: a caller may hand it any class, so its
result stays a question.
"""

from __future__ import annotations

from pathlib import Path

from tests.fixture_cases import migrated_project


def test_a_declared_factory_gives_its_class(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_declared_factories")
    assert [(path, line, rule) for path, line, rule in review if path.startswith("scripts/")] == [("scripts/play.py", 20, "GM203")]
    play = (project / "scripts" / "play.py").read_text()
    assert "    env = grids.build(4)\n    first, info = env.reset(seed=seed)\n" in play
    assert "    env = grids.build_dual(4)\n    env.seed(seed)\n    start = env.reset()\n" in play
    assert "    env = grids.build_any(4)\n    env.seed(seed)\n    begin = env.reset()\n" in play
