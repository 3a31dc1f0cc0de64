"""An entry point into a gym module that names an env class the project defines itself
(``fixtures/project_own_entry_class``).

``arena/__init__.py`` registers ``"gym.envs:GuardedArena"``: Gymnasium has no such class,
but ``arena/envs/guarded.py`` defines one, which ``arena.envs`` (named by the module's other
entry point) exports: the item names that class and that spelling. The string stays (which
class the legacy string reached depended on the gym installed). ``"gym.envs:FogArena"``,
a name no class of the project has, keeps the plain item; ``"gym.envs:TwinArena"``, a name
two classes of the project have, names both and picks neither.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app
from tests.fixture_cases import FIXTURES


def test_an_entry_point_into_gym_names_the_projects_own_class(tmp_path: Path) -> None:
    project = tmp_path / "project"
    shutil.copytree(FIXTURES / "project_own_entry_class", project)
    report = tmp_path / "report.json"
    result = CliRunner().invoke(app, ["rewrite", "--report", str(report), str(project)])
    assert result.exit_code == 0, result.output
    items = {
        f["line"]: f["message"]
        for file in json.loads(report.read_text())["files"]
        if file["path"].endswith("arena/__init__.py")
        for f in file["review"]
        if f["rule"] == "GM105"
    }
    assert sorted(items) == [5, 7, 9]
    assert '`entry_point="arena.envs:GuardedArena"`' in items[5]
    assert "envs/guarded.py" in items[5]
    assert "FogArena" in items[7] and "this project defines" not in items[7]
    assert "envs/twin_a.py, envs/twin_b.py" in items[9] and "entry_point=" not in items[9].split(";", 1)[1]
    text = (project / "arena" / "__init__.py").read_text()
    assert '"gym.envs:GuardedArena"' in text and '"gym.envs:FogArena"' in text
