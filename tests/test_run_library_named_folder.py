"""A folder of the run named after a Gym-only library (``examples/tensorforce/``) is not that
library: a script in it importing the library's gym adapter (``tensorforce.contrib.openai_gym``)
is still told the adapter makes legacy gym envs (GM107). Only a module of the run that really
is the adapter (``tensorforce/contrib/openai_gym.py`` inside the run) silences the report."""

from __future__ import annotations

import json
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

runner = CliRunner()
SCRIPT = 'import gym\nfrom tensorforce.contrib.openai_gym import OpenAIGym\n\nenv = OpenAIGym("CartPole-v0")\n'


def _gm107(run: Path) -> list[tuple[str, int]]:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    findings = json.loads(result.stdout)
    return [(str(Path(f["path"]).relative_to(run)), f["line"]) for f in findings if f["rule"] == "GM107"]


def _examples(run: Path) -> None:
    (run / "examples" / "tensorforce").mkdir(parents=True)
    (run / "examples" / "tensorforce" / "run_gym.py").write_text(SCRIPT)
    (run / "examples" / "tensorforce" / "helpers.py").write_text("STEPS = 10\n")


def test_an_examples_folder_named_after_the_library_still_reports_its_adapter(tmp_path: Path) -> None:
    _examples(tmp_path)
    assert _gm107(tmp_path) == [("examples/tensorforce/run_gym.py", 2)]


def test_the_runs_own_copy_of_the_adapter_module_is_not_reported(tmp_path: Path) -> None:
    _examples(tmp_path)
    own = tmp_path / "tensorforce" / "contrib"
    own.mkdir(parents=True)
    (tmp_path / "tensorforce" / "__init__.py").write_text("")
    (own / "__init__.py").write_text("")
    (own / "openai_gym.py").write_text("import gym\n\n\nclass OpenAIGym:\n    pass\n")
    assert _gm107(tmp_path) == []
