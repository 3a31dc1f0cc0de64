"""Every line a person reads in one review item names the same version of the file.

After a rewrite the review list places an item in the file as written (``line_after``);
the lines its message names, "(the same question at lines 16, 17)" of its own file and
"(the same decision at 2 other places: b.py:8, ...)" of the others, are placed there too,
each other file by its own rewrite (``Finding.message_after``, ``report.decide_once``).
``check`` writes nothing: there every line is the source's.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app
from gymmigrate.findings import renumber_lines

runner = CliRunner()

# A loop that gains `done = terminated or truncated` above a function whose env cannot be
# traced: its first reset asks the question, and the step and the last reset join it.
UNTRACED = """\
import gym

env = gym.make("CartPole-v1")
obs = env.reset()
done = False
while not done:
    obs, reward, done, info = env.step(env.action_space.sample())


def run(env_fn, episodes):
    env = env_fn()
    for _ in range(episodes):
        obs = env.reset()
        done = False
        while not done:
            obs, reward, done, info = env.step(env.action_space.sample())
    obs = env.reset()
    return obs
"""

_ITEM = re.compile(r"^  (?P<path>\S+?):(?P<line>\d+): (?P<rule>GM\d+) \((?:not )?rewritten\) (?P<message>.*)$", re.M)
_SAME_QUESTION = re.compile(r"\(the same question at lines? ([\d, ]+)\)$")
_OTHER_PLACE = re.compile(r"(\S+?\.py):(\d+)")


def _review(stderr: str) -> list[re.Match[str]]:
    return list(_ITEM.finditer(stderr.partition("Review (")[2]))


def _line(path: Path, number: int) -> str:
    return path.read_text(encoding="utf-8").splitlines()[number - 1]


def test_a_rewritten_items_question_names_lines_of_the_written_file(tmp_path: Path) -> None:
    script = tmp_path / "play.py"
    script.write_text(UNTRACED, encoding="utf-8")
    result = runner.invoke(app, ["rewrite", str(script)])
    assert result.exit_code == 0, result.output
    [item] = _review(result.stderr)
    asked = _SAME_QUESTION.search(item["message"])
    assert asked is not None, item["message"]
    step, reset = (int(number) for number in asked[1].split(", "))
    # the function's statements moved down by the line added in the loop above it
    assert (int(item["line"]), step, reset) == (14, 17, 19)
    assert _line(script, int(item["line"])).strip() == "obs, info = env.reset()"
    assert "= env.step(" in _line(script, step)
    assert _line(script, reset).strip() == "obs, info = env.reset()"


def test_check_names_lines_of_the_source(tmp_path: Path) -> None:
    script = tmp_path / "play.py"
    script.write_text(UNTRACED, encoding="utf-8")
    result = runner.invoke(app, ["check", str(script)])
    assert result.exit_code == 1
    [item] = _review(result.stderr)
    assert int(item["line"]) == 13 and item["message"].endswith("(the same question at lines 16, 17)")
    asked = [line for line in result.stdout.splitlines() if "(the same question at" in line]
    assert len(asked) == 1 and asked[0].startswith(f"{script}:13:") and asked[0].endswith("(the same question at lines 16, 17)")
    assert script.read_text(encoding="utf-8") == UNTRACED


# A removed env id is one decision of the run; the files that use it are rewritten by
# different numbers of lines above it (or not at all).
LOOP = """\
probe = gym.make("CartPole-v1")
probe.reset()
done = False
while not done:
    obs, reward, done, info = probe.step(0)
"""


def _run_wide_decision(tmp_path: Path, *, home_changes: bool) -> Path:
    run = tmp_path / "run"
    run.mkdir()
    home = f"import gym\n\n{LOOP}" if home_changes else "import gymnasium as gym\n\n"
    (run / "a.py").write_text(f'{home}env = gym.make("Striker-v2")\n', encoding="utf-8")
    (run / "b.py").write_text(f'import gym\n\n{LOOP}env = gym.make("Striker-v2")\n', encoding="utf-8")
    (run / "c.py").write_text(f'import gym\n\n{LOOP}{LOOP.replace("probe", "other")}env = gym.make("Striker-v2")\n', encoding="utf-8")
    return run


@pytest.mark.parametrize("home_changes", [False, True], ids=["home file left as it was", "home file rewritten"])
def test_a_run_wide_decision_names_each_other_file_as_written(tmp_path: Path, home_changes: bool) -> None:
    run = _run_wide_decision(tmp_path, home_changes=home_changes)
    result = runner.invoke(app, ["rewrite", str(run)])
    assert result.exit_code == 0, result.output
    [item] = _review(result.stderr)
    assert item["rule"] == "GM805" and Path(item["path"]).name == "a.py"
    places = [(Path(path), int(line)) for path, line in _OTHER_PLACE.findall(item["message"].partition("(the same decision at")[2])]
    assert [(path.name, line) for path, line in places] == [("b.py", 9), ("c.py", 15)]
    for path, line in [(Path(item["path"]), int(item["line"])), *places]:
        assert "Striker-v2" in _line(path, line), (path.name, line)


def test_check_names_each_other_file_by_its_source(tmp_path: Path) -> None:
    run = _run_wide_decision(tmp_path, home_changes=True)
    result = runner.invoke(app, ["check", "--output-format", "json", str(run)])
    assert result.exit_code == 1
    [item] = [f for f in json.loads(result.stdout) if f["tier"] == "review"]
    assert (Path(item["path"]).name, item["line"]) == ("a.py", 8)
    assert item["message"].endswith(f"(the same decision at 2 other places: {run / 'b.py'}:8, {run / 'c.py'}:13)")


def test_the_json_report_of_a_rewrite_reads_the_source_like_its_line(tmp_path: Path) -> None:
    """The report gives ``line`` and ``line_after``; its message names lines as ``line`` does."""
    run = _run_wide_decision(tmp_path, home_changes=True)
    report = tmp_path / "report.json"
    result = runner.invoke(app, ["rewrite", "--report", str(report), str(run)])
    assert result.exit_code == 0, result.output
    [item] = [f for f in json.loads(report.read_text(encoding="utf-8"))["findings"] if f["tier"] == "review"]
    assert (item["line"], item["line_after"]) == (8, 9)
    assert item["message"].endswith(f"(the same decision at 2 other places: {run / 'b.py'}:8, {run / 'c.py'}:13)")
    assert "message_after" not in item


def test_a_notebooks_question_names_cells_lines_as_written(tmp_path: Path) -> None:
    cells = [
        "import gym\n\nprobe = gym.make('CartPole-v1')\ndone = False\nwhile not done:\n    obs, reward, done, info = probe.step(0)\n",
        UNTRACED.partition("\n\n\n")[2],
    ]
    notebook = tmp_path / "play.ipynb"
    data = {
        "cells": [{"cell_type": "code", "execution_count": None, "metadata": {}, "outputs": [], "source": code} for code in cells],
        "metadata": {},
        "nbformat": 4,
        "nbformat_minor": 5,
    }
    notebook.write_text(json.dumps(data, indent=1) + "\n", encoding="utf-8")
    checked = runner.invoke(app, ["check", str(notebook)])
    assert "cell 2:line 4: GM201" in checked.stderr and "(the same question at cell 2 line 7, cell 2 line 8)" in checked.stderr
    result = runner.invoke(app, ["rewrite", str(notebook)])
    assert result.exit_code == 0, result.output
    assert "cell 2:line 4: GM201" in result.stderr and "(the same question at cell 2 line 7, cell 2 line 9)" in result.stderr
    written = "".join(json.loads(notebook.read_text(encoding="utf-8"))["cells"][1]["source"]).splitlines()
    assert written[3].strip() == written[8].strip() == "obs, info = env.reset()" and "= env.step(" in written[6]


def test_lines_a_rewrite_joins_are_named_once() -> None:
    where = {5: 7, 6: 7, 9: 12, 40: 44}
    message = "the step on line 40 (the same question at lines 5, 6; and at line 9, where ...)"
    assert renumber_lines(message, where.__getitem__) == "the step on line 44 (the same question at line 7; and at line 12, where ...)"
    assert renumber_lines("see file.py:40 and the 3 lines above", where.__getitem__) == "see file.py:40 and the 3 lines above"


# An env whose reset and step ask whether it is a Gym env: its own methods and attributes,
# which a Gymnasium wrapper no longer forwards, depend on the same answer and are named by
# that one item. Receivers nothing asks about, a proven Gym env and a proven other object
# get nothing new.
_FIXTURES = Path(__file__).parent.parent / "fixtures" / "rules" / "GM604"


def test_an_untraced_envs_own_uses_are_named_by_its_question() -> None:
    result = runner.invoke(app, ["check", str(_FIXTURES / "untraced_env_own_methods_join_question.py")])
    item, looked_up, growing = _review(result.stderr)
    own = (
        "the env's own methods and attributes, which a Gymnasium wrapper no longer forwards: if it is a Gym env, "
        "read them through `.unwrapped` or `get_wrapper_attr`)"
    )
    assert int(item["line"]) == 11 and item["rule"] == "GM301"
    assert item["message"].endswith(f"(the same question at lines 17, 20, {own}")
    # a name looked up by getattr/hasattr is the env's own too; Gym's `observation_space` is not
    assert int(looked_up["line"]) == 27 and looked_up["message"].endswith(f"(the same question at lines 30, 31, {own}")
    # `self.envs.append(env)` is a call on the list of envs, not on an env
    assert int(growing["line"]) == 42 and "(the same question" not in growing["message"]
    # the lines are placed through a rewrite like the others the question names
    assert renumber_lines(item["message"], lambda n: n + 1).endswith("(the same question at lines 18, 21, the env's own methods and attributes, which a Gymnasium wrapper no longer forwards: if it is a Gym env, read them through `.unwrapped` or `get_wrapper_attr`)")


@pytest.mark.parametrize("case", ["noop_own_methods_of_unasked_or_proven_env", "own_methods_of_proven_envs_unchanged"])
def test_own_uses_of_receivers_not_asked_about_stay_silent(case: str) -> None:
    result = runner.invoke(app, ["check", str(_FIXTURES / f"{case}.py")])
    assert not _review(result.stderr) and "own methods and attributes" not in result.stdout + result.stderr
