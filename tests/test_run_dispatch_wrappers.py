"""A library's generic wrappers chosen by an ``isinstance(env, gym.Env)`` dispatch
(``fixtures/project_dispatch_wrappers``).

``lib/adapters.py`` sends Gym envs to ``GymAdapter`` and every other env to ``SimAdapter``,
whose step follows a simulator's own four-value API; ``train.py`` makes a vector env and
hands it to the dispatcher. Legacy vector envs were ``gym.Env``, Gymnasium's are not: the
check is the item (GM708), not ``SimAdapter``'s step, which no Gym env reached. The
adapter built for Gym envs tests for vector envs and hands on each step (GM706: next-step
autoreset), and forwards ``render(*args)`` to them (GM401: no render_mode anywhere).
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_dispatch_wrappers"
runner = CliRunner()


def _findings(run: Path) -> list[dict]:
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code == 1
    return [f for f in json.loads(result.stdout) if Path(f["path"]).name == "adapters.py"]


def test_dispatch_check_is_the_item_not_the_other_api_step(tmp_path: Path) -> None:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    found = _findings(run)
    review = sorted((f["line"], f["rule"]) for f in found if f["tier"] == "review")
    assert review == [(28, "GM706"), (32, "GM401"), (43, "GM708")]
    assert not [f for f in found if f["line"] == 37]  # SimAdapter's own four-value step
    assert "`adapt` builds this class for Gym envs" in next(f["message"] for f in found if f["rule"] == "GM401")


def test_vector_env_passed_among_others_still_reaches_the_check(tmp_path: Path) -> None:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    (run / "single.py").write_text(
        'import gym\n\nfrom lib.adapters import adapt\n\nenv = adapt(gym.make("Pendulum-v1"))\nenv.reset()\n'
    )
    found = _findings(run)
    check = [f for f in found if f["rule"] == "GM708"]
    assert [(f["line"], f["tier"]) for f in check] == [(43, "review")]
    assert not [f for f in found if f["line"] == 37]
