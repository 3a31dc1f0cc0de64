"""Env classes whose own render() takes no mode and never reads render_mode
(``fixtures/project_modeless_render``).

``sketch``'s ``Canvas`` is built by its constructor in another module and rendered bare:
its render draws as it did whatever the env is made with, so no question. ``board``'s
``Board`` has the same shape, but the package registers it: a ``make`` may reach it, and
the bare render stays asked.
"""

from __future__ import annotations

from pathlib import Path

from tests.fixture_cases import migrated_project


def test_a_bare_render_of_a_modeless_render_asks_only_where_the_class_is_registered(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_modeless_render")
    renders = [(path, line) for path, line, rule in review if rule == "GM402"]
    assert renders == [("board/show.py", 10)]
    for package in ("sketch", "board"):
        assert "render_mode" not in (project / package / "show.py").read_text()
