"""Custom attributes of the env a proxy of the project's own holds, read and written by its
subclasses in another module (issue #19).

``fixtures/project_proxy_attributes/``: ``pkg.proxy.Proxy`` stores what its constructor is
given in ``self._inner`` (and returns it from a property ``inner``); ``pkg.camera`` derives
``Camera``, ``Recorder`` and ``Notes`` from it, each handing its own parameter up. Every
construction of ``Camera`` passes a ``gym.make`` result: its reads go through
``get_wrapper_attr`` and its write through ``set_wrapper_attr`` (reviewed), and the migrated
code reaches the env on Gymnasium. ``Recorder`` is given a made env once and an object of
another library once: one question for its reads and its write. ``Notes`` is given the
project's own log: left as it is.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.fixture_cases import migrated_project


def test_reads_and_writes_through_the_proxy_follow_its_constructions(tmp_path: Path) -> None:
    project, review = migrated_project(tmp_path, "project_proxy_attributes")
    camera = (project / "pkg" / "camera.py").read_text()
    assert 'self.inner.set_wrapper_attr("markers_hidden", True)' in camera
    assert 'self._inner.get_wrapper_attr("aim_camera")(size)' in camera
    assert 'return self._inner.get_wrapper_attr("snapshot")(self.size)' in camera
    assert "self.inner.markers_hidden = True\n" in camera  # Recorder: asked, not rewritten
    assert "return self._inner.snapshot(4)" in camera
    assert "return self._inner.snapshot(1)" in camera  # Notes: the project's own log
    assert review == [("pkg/camera.py", 11, "GM604"), ("pkg/camera.py", 24, "GM604")]


def test_the_migrated_camera_reaches_the_env_on_gymnasium(tmp_path: Path) -> None:
    project, _ = migrated_project(tmp_path, "project_proxy_attributes")
    code = (
        "import sys, types\n"
        "sys.modules['recorders'] = types.SimpleNamespace(build_tape=lambda: None)\n"
        "from pkg import studio, factories\n"
        "camera = factories.camera_env()\n"
        "assert camera.inner.unwrapped.markers_hidden is True\n"
        "assert camera.inner.unwrapped.size == 4\n"
        "assert len(camera.picture()) == 4\n"
    )
    done = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=project, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
