"""Directly built envs of classes whose bases are another module's (issue #19).

``fixtures/project_bare_run_classes/``: ``rig.arm.PlanarArm`` derives ``Arm`` (``TaskEnv`` of
another module and a plain mixin), and the run registers it: its module cannot classify it,
but no class of its hierarchy is a Gym wrapper, so ``PlanarArm(...)`` is the env itself and
``put_in_hand()`` on it is left with no question (it was asked whether the env is wrapped).
The near case is no bare env: ``ClippedXY`` derives ``ClippedArm``, which derives the run's
``Clip``, a ``gym.Wrapper``, so what it builds is a wrapper (the run follows its bases through
the classes of its own module) and ``put_in_hand()`` goes through ``get_wrapper_attr``.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.fixture_cases import migrated_project


def test_a_directly_built_env_of_a_wrapper_free_hierarchy_is_the_env_itself(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_bare_run_classes")
    play = (project / "play.py").read_text()
    assert "    env = PlanarArm(hand=0.25)\n    env.reset()\n    return env.put_in_hand()\n" in play
    assert '    env = ClippedXY()\n    env.reset()\n    return env.get_wrapper_attr("put_in_hand")()\n' in play
    assert review == []
    code = "import play\nprint(play.grab(), play.grab_clipped())\n"
    run = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["0.25", "0.5"]
