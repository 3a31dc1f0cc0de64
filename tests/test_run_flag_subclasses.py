"""A subclass of a class of two APIs that sets the flag picking Gymnasium's shapes
(``fixtures/project_flag_subclasses``).

``DualBoard`` returns five values from step and ``(obs, info)`` from reset only under
``if self.modern:``: its item asks which API to keep. ``ModernBoard`` (another module) sets
``self.modern = True`` last in its ``__init__`` and its own step returns five values: its
instances are on Gymnasium's API, so it gets a note, not a second question. ``ChosenBoard``
stores whatever its caller passes: it keeps the question.
"""

from __future__ import annotations

from pathlib import Path

from tests.fixture_cases import migrated_project


def test_a_subclass_setting_the_gymnasium_flag_asks_nothing(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_flag_subclasses")
    assert [(path, line, rule) for path, line, rule in review if rule == "GM504"] == [
        ("boards/base.py", 4, "GM504"),
        ("boards/modern.py", 20, "GM504"),
    ]
    modern = (project / "boards" / "modern.py").read_text()
    assert "        obs, reward, terminated, truncated, info = super().step(action)\n" in modern
    assert "def reset" not in modern
