"""A method a wrapper class of the run defines is read with get_wrapper_attr
(``fixtures/project_wrapper_reach``).

``console.show.describe(env)`` reads ``env.get_action_meanings()``; the run hands it a bare
``Machine()`` and a ``KeyMap`` (a Gym wrapper of another module with a method of that name).
Legacy forwarding found the wrapper's own first, as ``get_wrapper_attr`` does; ``.unwrapped``
would skip it. Without such a wrapper in the run the base env's method is read through
``.unwrapped``.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from typer.testing import CliRunner

from gymmigrate.cli import app

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "project_wrapper_reach"
runner = CliRunner()


def _copy(tmp_path: Path) -> Path:
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    return run


def _rewrite(run: Path) -> str:
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code in (0, 1), result.output
    return (run / "console" / "show.py").read_text()


def test_a_method_a_run_wrapper_defines_is_read_with_get_wrapper_attr(tmp_path: Path) -> None:
    text = _rewrite(_copy(tmp_path))
    assert 'return env.get_wrapper_attr("get_action_meanings")()' in text
    assert ".unwrapped" not in text


def test_a_second_run_keeps_the_decision_once_the_wrapper_records_its_arguments(tmp_path: Path) -> None:
    """The migration gives the run's wrapper a second base (``RecordConstructorArgs``, a
    mixin that defines nothing an env forwards): the second run must still see a wrapper
    defining the method, and change nothing."""
    run = _copy(tmp_path)
    keymap = run / "console" / "keymap.py"
    keymap.write_text(
        keymap.read_text().replace(
            '    """Keeps two of the machine\'s actions."""\n',
            '    """Keeps two of the machine\'s actions."""\n\n'
            "    def __init__(self, env, keep=2):\n        super().__init__(env)\n        self.keep = keep\n",
        )
    )
    first = _rewrite(run)
    assert "RecordConstructorArgs" in keymap.read_text()
    assert 'return env.get_wrapper_attr("get_action_meanings")()' in first
    again = runner.invoke(app, ["rewrite", str(run)])
    assert again.exit_code in (0, 1), again.output
    assert "rewrote 0 of" in again.output
    assert (run / "console" / "show.py").read_text() == first


def test_a_wrapper_with_a_mixin_base_still_defines_what_it_defines(tmp_path: Path) -> None:
    run = _copy(tmp_path)
    keymap = run / "console" / "keymap.py"
    keymap.write_text(keymap.read_text().replace("(gym.Wrapper)", "(gym.Wrapper, gym.utils.EzPickle)"))
    text = _rewrite(run)
    assert 'return env.get_wrapper_attr("get_action_meanings")()' in text


def test_without_such_a_wrapper_the_base_envs_method_is_read_through_unwrapped(tmp_path: Path) -> None:
    run = _copy(tmp_path)
    (run / "console" / "keymap.py").unlink()
    main = run / "console" / "main.py"
    main.write_text("".join(line for line in main.read_text().splitlines(keepends=True) if "KeyMap" not in line))
    text = _rewrite(run)
    assert "return env.unwrapped.get_action_meanings()" in text


def test_a_base_env_attribute_of_a_held_gym_env_is_read_through_unwrapped(tmp_path: Path) -> None:
    """Wrapped or not, ``unwrapped`` reaches it (a bare env's is itself): no question."""
    run = _copy(tmp_path)
    runner.invoke(app, ["rewrite", str(run)])
    assert "return self._machine.unwrapped.x_threshold" in (run / "console" / "panel.py").read_text()


def test_a_render_of_an_env_built_by_a_run_class_elsewhere_names_its_constructor(tmp_path: Path) -> None:
    """``replay(env, 10)`` in main.py passes ``Machine()``: the mode goes to that constructor
    (it takes render_mode once migrated), not to a gym.make the run never calls."""
    run = _copy(tmp_path)
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    found = [f for f in json.loads(result.stdout) if f["rule"] == "GM402"]
    assert [(Path(f["path"]).name, f["line"], f["kind"]) for f in found] == [("replay.py", 5, "flag")]
    assert "main.py:11" in found[0]["message"]
    assert "constructor of its env class" in found[0]["message"]
