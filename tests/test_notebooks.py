"""Notebooks: code cells migrated as one program; magics, outputs, metadata and layout kept.

Fixtures: ``fixtures/notebooks/<case>.ipynb`` and, when it changes, ``<case>.expected.ipynb``.
"""

from __future__ import annotations

import ast
import json
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app
from gymmigrate.files import discover
from gymmigrate.options import RewriteOptions
from gymmigrate.process import Status, process_file
from gymmigrate.source_text import TransformError
from gymmigrate.sources import adapter_for
from gymmigrate.sources.json_text import Span, cell_source_spans, new_source_text
from gymmigrate.sources.magics import Magics
from gymmigrate.sources.programs import lint_document, transform_document

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures" / "notebooks"
NOTEBOOK = adapter_for(Path("x.ipynb"))
runner = CliRunner()


def _rewrite(source: bytes) -> bytes:
    assert NOTEBOOK is not None
    return transform_document(NOTEBOOK, source, "nb.ipynb", RewriteOptions()).rewritten


def _notebook(*cells: tuple[str, object], indent: int = 1) -> bytes:
    data = {
        "cells": [
            {"cell_type": kind, "execution_count": None, "metadata": {}, "outputs": [], "source": source}
            if kind == "code"
            else {"cell_type": kind, "metadata": {}, "source": source}
            for kind, source in cells
        ],
        "metadata": {"kernelspec": {"display_name": "Python 3", "language": "python", "name": "python3"}},
        "nbformat": 4,
        "nbformat_minor": 5,
    }
    return (json.dumps(data, sort_keys=True, indent=indent, ensure_ascii=False) + "\n").encode("utf-8")


def test_a_notebook_with_magics_shell_escapes_and_outputs_is_byte_identical() -> None:
    source = (FIXTURES / "clean_with_magics.ipynb").read_bytes()
    assert _rewrite(source) == source


def test_a_loop_spread_over_cells_is_migrated_as_one_program() -> None:
    source = (FIXTURES / "multi_cell_loop.ipynb").read_bytes()
    expected = (FIXTURES / "multi_cell_loop.expected.ipynb").read_bytes()
    rewritten = _rewrite(source)
    assert rewritten == expected
    assert _rewrite(rewritten) == rewritten, "a second run changes nothing"


def test_outputs_metadata_and_markdown_cells_are_kept() -> None:
    before = json.loads((FIXTURES / "multi_cell_loop.ipynb").read_bytes())
    after = json.loads(_rewrite((FIXTURES / "multi_cell_loop.ipynb").read_bytes()))
    assert after["metadata"] == before["metadata"]
    assert len(after["cells"]) == len(before["cells"])
    for old, new in zip(before["cells"], after["cells"]):
        assert {k: v for k, v in old.items() if k != "source"} == {k: v for k, v in new.items() if k != "source"}
        if old["cell_type"] != "code":
            assert new["source"] == old["source"]
    magic_cells = [c for c in after["cells"] if c["source"] and c["source"][0].startswith(("!", "%%"))]
    assert [c["source"] for c in magic_cells] == [
        ['!pip install "gymnasium>=1.0"\n', "%matplotlib inline"],  # its requirement moved (GM109)
        ["%%time\n", "for _ in range(3):\n", "    env.reset()"],
    ]


def test_migrated_cells_run_in_order_and_complete_a_seeded_episode() -> None:
    """Run the code cells as Jupyter would (magics skipped) against gymnasium."""
    cells = json.loads((FIXTURES / "multi_cell_loop.expected.ipynb").read_bytes())["cells"]
    magics = Magics()
    namespace: dict[str, object] = {}
    for cell in cells:
        if cell["cell_type"] == "code":
            exec(compile(magics.hide("".join(cell["source"]) + "\n"), "<cell>", "exec"), namespace)
    assert namespace["done"] is True
    assert namespace["total"] >= 1.0
    first_observation = namespace["obs"]
    # Seeded: the same notebook gives the same episode again.
    namespace_again: dict[str, object] = {}
    for cell in cells:
        if cell["cell_type"] == "code":
            exec(compile(Magics().hide("".join(cell["source"]) + "\n"), "<cell>", "exec"), namespace_again)
    assert namespace_again["total"] == namespace["total"]
    assert (namespace_again["obs"] == first_observation).all()


def test_cell_source_as_a_string_stays_a_string_and_final_newlines_are_kept() -> None:
    source = _notebook(("code", "import gym\nenv = gym.make('CartPole-v1')"), ("code", ["obs = env.reset()\n", "print(obs)"]))
    cells = json.loads(_rewrite(source))["cells"]
    assert cells[0]["source"] == "import gymnasium as gym\nenv = gym.make('CartPole-v1')"
    assert cells[1]["source"] == ["obs, info = env.reset()\n", "print(obs)"]


def test_the_detected_indent_is_kept() -> None:
    source = _notebook(("code", "import gym\n"), indent=2)
    rewritten = _rewrite(source)
    assert rewritten == _notebook(("code", "import gymnasium as gym\n"), indent=2)


def test_a_layout_json_dumps_cannot_reproduce_is_edited_in_place_not_refused() -> None:
    """``1e-5`` reads back as ``1e-05``: the file is not serialized again, only the source edited."""
    source = _notebook(("code", "import gym\n")).replace(b'"nbformat": 4', b'"nbformat": 4, "x": 1e-5')
    rewritten = _rewrite(source)
    assert rewritten == source.replace(b'"import gym\\n"', b'"import gymnasium as gym\\n"')
    assert NOTEBOOK is not None
    findings, would_change = lint_document(NOTEBOOK, source, "nb.ipynb", RewriteOptions())  # check agrees with rewrite
    assert would_change and [f.rule for f in findings] == ["GM101"]


def test_magic_lines_are_hidden_only_where_a_statement_starts() -> None:
    code = (
        "files = !ls\n"
        "for name in files:\n"
        "    !echo {name}\n"
        "    %time f(name)\n"
        'text = """\n'
        "!not a shell line, inside a string\n"
        '"""\n'
        "call(a,\n"
        "     b)?\n"
        "env.step?\n"
        "x = 1  # what?\n"
    )
    magics = Magics()
    hidden = magics.hide(code)
    assert hidden.splitlines() == [
        "pass  # gymmigrate-magic 0",
        "for name in files:",
        "    pass  # gymmigrate-magic 1",
        "    pass  # gymmigrate-magic 2",
        'text = """',
        "!not a shell line, inside a string",
        '"""',
        "call(a,",
        "     b)?",
        "pass  # gymmigrate-magic 3",
        "x = 1  # what?",
    ]
    assert magics.restore(hidden) == code


def test_a_cell_magic_hides_the_whole_cell_unless_its_body_is_python() -> None:
    magics = Magics()
    assert magics.hide("%%bash\nobs = env.reset()\n") == "pass  # gymmigrate-magic 0\n"
    timed = "%%time\nobs = env.reset()\n!ls\n"
    assert magics.hide(timed) == "pass  # gymmigrate-magic 1\nobs = env.reset()\npass  # gymmigrate-magic 2\n"
    assert magics.restore(magics.hide(timed)) == timed


def test_a_timed_training_cell_is_migrated() -> None:
    source = _notebook(("code", "import gym\nenv = gym.make('CartPole-v1')"), ("code", ["%%time\n", "obs = env.reset()"]))
    cells = json.loads(_rewrite(source))["cells"]
    assert cells[1]["source"] == ["%%time\n", "obs, info = env.reset()"]


def test_a_cell_that_does_not_parse_is_reported_with_its_number(tmp_path: Path) -> None:
    path = tmp_path / "broken.ipynb"
    source = _notebook(
        ("markdown", "# Title"), ("code", "import gym\n"), ("code", "def f(:\n    env.reset()\n"), ("code", "model = \n")
    )
    path.write_bytes(source)
    result = runner.invoke(app, ["rewrite", str(tmp_path)])
    assert result.exit_code == 0, result.stderr
    assert f"{path}:cell 3:line 1: GM001 (not rewritten) this code cell does not parse (line 1: invalid syntax)" in result.stderr
    assert "cell 4" not in result.stderr  # an exercise cell that mentions no env: a note, not a review item
    cells = json.loads(path.read_bytes())["cells"]
    assert cells[1]["source"] == "import gymnasium as gym\n"  # the other cells are migrated
    assert cells[2]["source"] == "def f(:\n    env.reset()\n"  # the broken ones are left as they were
    assert cells[3]["source"] == "model = \n"
    check = runner.invoke(app, ["check", "--output-format", "json", str(path)])
    tiers = {f["cell"]: f["tier"] for f in json.loads(check.stdout) if f["rule"] == "GM001"}
    assert tiers == {2: "review", 3: "note"}  # JSON cells count from 0, like nb["cells"]


def test_an_exercise_placeholder_cell_is_left_and_the_rest_migrated() -> None:
    source = (FIXTURES / "exercise_placeholder.ipynb").read_bytes()
    expected = (FIXTURES / "exercise_placeholder.expected.ipynb").read_bytes()
    assert NOTEBOOK is not None
    transformed = transform_document(NOTEBOOK, source, "nb.ipynb", RewriteOptions())
    assert transformed.rewritten == expected
    assert _rewrite(expected) == expected, "a second run changes nothing"
    before, after = json.loads(source)["cells"], json.loads(expected)["cells"]
    assert after[4]["source"] == before[4]["source"]  # `return <YOUR CODE>`, byte for byte
    flagged = [(f.rule, f.cell, f.line, f.kind.value) for f in transformed.findings if f.rule == "GM001"]
    assert flagged == [("GM001", 4, 3, "flag")]
    findings, would_change = lint_document(NOTEBOOK, source, "nb.ipynb", RewriteOptions())
    assert would_change
    strip = lambda fs: [(f.rule, f.cell, f.line) for f in fs]  # noqa: E731
    assert strip(findings) == strip(transformed.findings)


def test_the_cells_around_an_exercise_placeholder_run_on_gymnasium() -> None:
    """Every code cell of the migrated exercise but the placeholder, run in order against
    Gymnasium, as a student who skipped the exercise would."""
    cells = json.loads((FIXTURES / "exercise_placeholder.expected.ipynb").read_bytes())["cells"]
    namespace: dict[str, object] = {}
    skipped = 0
    for cell in cells:
        if cell["cell_type"] != "code":
            continue
        code = "".join(cell["source"]) + "\n"
        try:
            compiled = compile(code, "<cell>", "exec")
        except SyntaxError:
            skipped += 1
            continue
        exec(compiled, namespace)
    assert skipped == 1
    assert namespace["done"] is True
    assert 1 <= namespace["steps"] <= 500  # type: ignore[operator]
    assert type(namespace["env"]).__module__.startswith("gymnasium")


def test_check_locates_findings_by_cell_and_line(tmp_path: Path) -> None:
    shutil.copy(FIXTURES / "multi_cell_loop.ipynb", tmp_path / "loop.ipynb")
    report = tmp_path / "report.json"
    result = runner.invoke(app, ["check", str(tmp_path), "--report", str(report)])
    assert result.exit_code == 1
    assert f"{tmp_path / 'loop.ipynb'}:cell 3:line 1:1: GM101 [auto]" in result.stdout
    assert f"{tmp_path / 'loop.ipynb'}:cell 6:line 5:5: GM301 [auto]" in result.stdout
    file = json.loads(report.read_text())["files"][0]
    findings = [*file["review"], *file["notes"]]
    assert {(c["rule"], c["cell"], c["line"]) for c in findings} >= {("GM101", 2, 1), ("GM301", 5, 5)}


def test_check_agrees_with_rewrite() -> None:
    assert NOTEBOOK is not None
    source = (FIXTURES / "multi_cell_loop.ipynb").read_bytes()
    findings, would_change = lint_document(NOTEBOOK, source, "nb.ipynb", RewriteOptions())
    transformed = transform_document(NOTEBOOK, source, "nb.ipynb", RewriteOptions())
    assert would_change and transformed.changed
    strip = lambda fs: [(f.rule, f.cell, f.line, f.column) for f in fs]  # noqa: E731
    assert strip(findings) == strip(transformed.findings)


def test_rewrite_diff_shows_code_cells_not_json(tmp_path: Path) -> None:
    path = tmp_path / "loop.ipynb"
    shutil.copy(FIXTURES / "multi_cell_loop.ipynb", path)
    result = runner.invoke(app, ["rewrite", "--diff", str(tmp_path)])
    assert result.exit_code == 1
    assert f"--- {path} (code cells)" in result.stdout
    assert "# cell 6\n-obs = env.reset()\n+obs, info = env.reset(seed=42)\n" in result.stdout
    assert '"source"' not in result.stdout and '"outputs"' not in result.stdout
    assert path.read_bytes() == (FIXTURES / "multi_cell_loop.ipynb").read_bytes()


def test_rewrite_writes_the_notebook_then_a_second_run_changes_nothing(tmp_path: Path) -> None:
    for name in ("multi_cell_loop.ipynb", "clean_with_magics.ipynb"):
        shutil.copy(FIXTURES / name, tmp_path / name)
    (tmp_path / ".ipynb_checkpoints").mkdir()
    shutil.copy(FIXTURES / "multi_cell_loop.ipynb", tmp_path / ".ipynb_checkpoints" / "multi_cell_loop-checkpoint.ipynb")
    result = runner.invoke(app, ["rewrite", str(tmp_path)])
    assert result.exit_code == 0, result.stderr
    assert "rewrote 1 of 2 files" in result.stderr
    assert (tmp_path / "multi_cell_loop.ipynb").read_bytes() == (FIXTURES / "multi_cell_loop.expected.ipynb").read_bytes()
    assert (tmp_path / "clean_with_magics.ipynb").read_bytes() == (FIXTURES / "clean_with_magics.ipynb").read_bytes()
    again = runner.invoke(app, ["rewrite", "--diff", str(tmp_path)])
    assert again.exit_code == 0 and again.stdout == ""


def test_notebooks_of_other_languages_and_without_gym_are_left_alone(tmp_path: Path) -> None:
    r_notebook = json.loads(_notebook(("code", "env <- gym_make('CartPole-v1')\n")))
    r_notebook["metadata"]["kernelspec"]["language"] = "R"
    path = tmp_path / "r.ipynb"
    path.write_text(json.dumps(r_notebook, indent=1) + "\n")
    assert process_file(path, RewriteOptions(), write=True, want_diff=False).status is Status.UNCHANGED
    plain = tmp_path / "plain.ipynb"
    plain.write_bytes(_notebook(("code", "print('hello')\n")))
    assert process_file(plain, RewriteOptions(), write=True, want_diff=False).status is Status.SKIPPED


def test_walking_a_folder_takes_notebooks() -> None:
    found = {path.name for path in discover([str(FIXTURES)]).files}
    assert found == {
        "clean_with_magics.ipynb",
        "multi_cell_loop.ipynb",
        "multi_cell_loop.expected.ipynb",
        "exercise_placeholder.ipynb",
        "exercise_placeholder.expected.ipynb",
        "hand_indented_source.ipynb",
        "hand_indented_source.expected.ipynb",
        "duplicate_top_level_keys.ipynb",
        "duplicate_top_level_keys.expected.ipynb",
    }


def test_rewrite_smoke_does_not_run_notebooks(tmp_path: Path) -> None:
    shutil.copy(FIXTURES / "multi_cell_loop.ipynb", tmp_path / "loop.ipynb")
    result = runner.invoke(app, ["rewrite", "--smoke", str(tmp_path)])
    assert result.exit_code == 0, result.stderr
    assert "no rewritten file creates an env" in result.stderr


def test_a_broken_cell_in_a_notebook_without_gym_code_is_not_an_error(tmp_path: Path) -> None:
    path = tmp_path / "notes.ipynb"
    path.write_bytes(_notebook(("markdown", "About gym environments"), ("code", "print 'python 2'\n")))
    assert process_file(path, RewriteOptions(), write=True, want_diff=False).status is Status.UNCHANGED


def _cells_of(text: str) -> list[str]:
    """``text`` cut into cells of two top-level statements each, as a notebook would hold it."""
    tree = ast.parse(text)
    lines = text.splitlines(keepends=True)
    starts = [min([node.lineno, *(d.lineno for d in getattr(node, "decorator_list", ()))]) for node in tree.body]
    bounds = [0, *(start - 1 for start in sorted(set(starts[1::2]))), len(lines)]
    return ["".join(lines[a:b]) for a, b in zip(bounds, bounds[1:]) if a < b]


RULE_CASES = sorted(
    path
    for path in (Path(__file__).resolve().parent.parent / "fixtures" / "rules").glob("*/*.py")
    if not path.name.endswith(".expected.py")
)


@pytest.mark.parametrize("case", RULE_CASES, ids=lambda path: f"{path.parent.name}/{path.stem}")
def test_every_rule_case_cut_into_cells_migrates_as_the_script_does(case: Path) -> None:
    """Cells are one program: the cells' code after migration is the script's migration."""
    text = case.read_text(encoding="utf-8")
    expected = case.with_name(f"{case.stem}.expected.py")
    after = expected.read_text(encoding="utf-8") if expected.exists() else text
    source = _notebook(*(("code", cell.splitlines(keepends=True)) for cell in _cells_of(text)))
    cells = json.loads(_rewrite(source))["cells"]
    assert "".join("".join(cell["source"]) for cell in cells) == after


def test_a_def_redefined_in_a_later_cell_gets_the_calls_of_the_def_that_calls_it() -> None:
    # A function defined in a cell and again in a later one: the call inside ``episode()``
    # runs whenever that is called, so both definitions are traced to the make it passes.
    source = _notebook(
        ("code", "import gym\n"),
        ("code", 'def episode():\n    sim = gym.make("CartPole-v1")\n    sim.reset()\n    return angle(sim)\n'),
        ("code", "def angle(sim):\n    return sim.env.state[2]\n"),
        ("code", "episode()\n"),
        ("code", "def angle(sim, index=2):\n    return sim.env.state[index]\n"),
        ("code", "episode()\n"),
    )
    rewritten = _rewrite(source).decode()
    assert "sim.env.state" not in rewritten
    assert rewritten.count("sim.unwrapped.state") == 2
    findings, would_change = lint_document(NOTEBOOK, source, "nb.ipynb", RewriteOptions())
    assert would_change
    assert [f.kind.value for f in findings if f.rule == "GM604"] == ["auto", "auto"]


def test_a_cell_whose_first_statement_is_removed_keeps_its_place() -> None:
    source = _notebook(
        ("code", "import gym\n"),
        ("code", "from gym.wrappers import NormalizeReward\nenvs = gym.vector.SyncVectorEnv([lambda: gym.make('CartPole-v1')])\n"),
        ("code", "envs = NormalizeReward(envs, gamma=0.99)\n"),
    )
    cells = json.loads(_rewrite(source))["cells"]
    assert [cell["source"] for cell in cells] == [
        "import gymnasium as gym\n",
        "envs = gym.vector.SyncVectorEnv([lambda: gym.make('CartPole-v1')])\n",
        "envs = gym.wrappers.vector.NormalizeReward(envs, gamma=0.99)\n",
    ]


def test_a_colab_layout_is_kept_key_order_and_escapes_included() -> None:
    """Colab writes indent 2, its own key order, and may escape non-ASCII."""
    data = {
        "nbformat": 4,
        "nbformat_minor": 0,
        "metadata": {"colab": {"provenance": []}, "kernelspec": {"name": "python3", "display_name": "Python 3"}},
        "cells": [
            {"cell_type": "code", "source": ["import gym  # épisode\n", "env = gym.make('CartPole-v1')"], "metadata": {"id": "x1"},
             "execution_count": None, "outputs": []},
        ],
    }
    source = (json.dumps(data, indent=2, ensure_ascii=True) + "\n").encode()
    data["cells"][0]["source"][0] = "import gymnasium as gym  # épisode\n"
    assert _rewrite(source) == (json.dumps(data, indent=2, ensure_ascii=True) + "\n").encode()


@pytest.mark.parametrize(
    ("content", "reason"),
    [
        ('{"cells": [ gym', "not a readable notebook (invalid JSON"),
        ('[1, 2, "gym"]', "not a notebook in nbformat 4"),
        ('{"cells": [{"cell_type": "code", "source": ["import gym\\n", 3]}]}', "neither text nor a list of lines"),
        ('{"cells": [{"cell_type": "code", "source": "import gym\\nx = \\"\\ud800\\""}]}', "not valid Unicode"),
    ],
    ids=["invalid-json", "not-a-notebook", "odd-source", "lone-surrogate"],
)
def test_files_that_are_not_notebooks_are_reported_and_left_alone(tmp_path: Path, content: str, reason: str) -> None:
    path = tmp_path / "odd.ipynb"
    path.write_text(content)
    result = process_file(path, RewriteOptions(), write=True, want_diff=True)
    assert result.status is Status.ERROR and reason in (result.error or "")
    assert path.read_text() == content


def test_a_notebook_with_crlf_line_ends_is_migrated_and_keeps_them() -> None:
    """Saved on Windows or checked out with core.autocrlf: the JSON's line ends are CRLF."""
    lf = _notebook(("markdown", "# Title"), ("code", ["import gym\n", "env = gym.make('CartPole-v1')\n", "obs = env.reset()"]))
    crlf = lf.replace(b"\n", b"\r\n")
    rewritten = _rewrite(crlf)
    assert rewritten == _rewrite(lf).replace(b"\n", b"\r\n")
    assert b"obs, info = env.reset()" in rewritten and b"\n" not in rewritten.replace(b"\r\n", b"")
    assert _rewrite(rewritten) == rewritten


# Notebooks edited by hand, whose layout `json.dumps` cannot write again (audit 6,
# Stable-Baselines Colab notebooks): the changed sources are edited in the JSON text.
HAND_EDITED = {
    "hand_indented_source": {  # one line of a cell's JSON indented by hand
        "cell 2:line 2:14: GM109",  # its `!pip install gym[box2d]`, given the new requirement
        "cell 3:line 1:1: GM101",
        "cell 4:line 3:7: GM201",
        "cell 4:line 7:5: GM301",
        "cell 4:line 9:15: GM201",
    },
    "duplicate_top_level_keys": {  # two headers merged: metadata, nbformat(_minor) twice, mixed indents
        "cell 3:line 1:1: GM101",
        "cell 4:line 1:7: GM201",
        "cell 4:line 6:5: GM301",
        "cell 4:line 11:15: GM201",
    },
}


def _outside_sources(text: str, cells: set[int]) -> list[str]:
    """The JSON text cut at the ``source`` values of ``cells``: what must stay as it was."""
    spans = cell_source_spans(text)
    pieces, done = [], 0
    for index in sorted(cells):
        pieces.append(text[done : spans[index].start])
        done = spans[index].end
    return [*pieces, text[done:]]


@pytest.mark.parametrize("case", sorted(HAND_EDITED))
def test_a_hand_edited_notebook_is_migrated_in_place(case: str) -> None:
    source = (FIXTURES / f"{case}.ipynb").read_bytes()
    expected = (FIXTURES / f"{case}.expected.ipynb").read_bytes()
    rewritten = _rewrite(source)
    assert rewritten == expected
    assert _rewrite(rewritten) == rewritten, "a second run changes nothing"
    before, after = json.loads(source), json.loads(rewritten)
    changed = {i for i, (old, new) in enumerate(zip(before["cells"], after["cells"])) if old["source"] != new["source"]}
    # hand_indented_source's install cell gets the new requirement of its `!pip install` line
    assert changed == ({1, 2, 3} if case == "hand_indented_source" else {2, 3})
    # Every byte outside the changed cells' sources is the file's own.
    assert _outside_sources(rewritten.decode(), changed) == _outside_sources(source.decode(), changed)
    # What Jupyter reads: the new sources, everything else as it was.
    assert "".join(after["cells"][2]["source"]).startswith("import gymnasium as gym\n")
    assert "    obs, reward, terminated, truncated, info = env.step(action)\n" in after["cells"][3]["source"]
    for old, new in zip(before["cells"], after["cells"]):
        assert {k: v for k, v in old.items() if k != "source"} == {k: v for k, v in new.items() if k != "source"}
    assert {k: v for k, v in before.items() if k != "cells"} == {k: v for k, v in after.items() if k != "cells"}


def test_the_hand_indented_lines_keep_their_bytes() -> None:
    rewritten = _rewrite((FIXTURES / "hand_indented_source.ipynb").read_bytes()).decode()
    assert '\n    "!apt-get update && apt-get install swig cmake\\n",\n' in rewritten  # a kept line of the install cell
    assert '\n      "for i in range(100):  # ré-indenté à la main\\n",\n' in rewritten  # a kept line of a changed cell
    assert '\n    "obs, info = env.reset()\\n",\n' in rewritten  # a changed line, indented as the line it replaces


def test_duplicate_top_level_keys_stay_and_the_last_ones_count() -> None:
    rewritten = _rewrite((FIXTURES / "duplicate_top_level_keys.ipynb").read_bytes()).decode()
    assert rewritten.count('"nbformat_minor"') == 2
    assert '\n  "metadata": {\n    "colab": {' in rewritten and '\n "metadata": {\n  "accelerator"' in rewritten
    assert json.loads(rewritten)["nbformat_minor"] == 1


@pytest.mark.parametrize("case", sorted(HAND_EDITED))
def test_check_and_rewrite_agree_on_a_hand_edited_notebook(tmp_path: Path, case: str) -> None:
    path = tmp_path / f"{case}.ipynb"
    shutil.copy(FIXTURES / f"{case}.ipynb", path)
    checked = runner.invoke(app, ["check", str(path)])
    assert checked.exit_code == 1, checked.stderr
    listed = {line.removeprefix(f"{path}:").split(" [")[0] for line in checked.stdout.splitlines()}
    assert listed == HAND_EDITED[case]
    assert path.read_bytes() == (FIXTURES / f"{case}.ipynb").read_bytes()
    diff = runner.invoke(app, ["rewrite", "--diff", str(path)])
    assert diff.exit_code == 1 and "error" not in diff.stderr
    assert "+import gymnasium as gym" in diff.stdout
    written = runner.invoke(app, ["rewrite", str(path)])
    assert written.exit_code == 0, written.stderr
    assert path.read_bytes() == (FIXTURES / f"{case}.expected.ipynb").read_bytes()
    again = runner.invoke(app, ["rewrite", "--diff", str(path)])
    assert again.exit_code == 0 and again.stdout == ""


@pytest.mark.parametrize("case", sorted(HAND_EDITED))
def test_a_hand_edited_notebook_with_crlf_line_ends_keeps_them(case: str) -> None:
    source = (FIXTURES / f"{case}.ipynb").read_bytes().replace(b"\n", b"\r\n")
    expected = (FIXTURES / f"{case}.expected.ipynb").read_bytes().replace(b"\n", b"\r\n")
    assert _rewrite(source) == expected


def test_of_two_cells_lists_the_last_is_migrated_and_the_first_kept() -> None:
    """``json.loads`` (so Jupyter) keeps the last of a repeated key: that list is the notebook."""
    first = '"cells": [{"cell_type": "code", "metadata": {}, "outputs": [], "source": ["obs = env.reset()"]}]'
    last = '"cells": [{"cell_type": "code", "metadata": {}, "outputs": [], "source": ["import gym\\n", "env = gym.make(\\"CartPole-v1\\")\\n", "obs = env.reset()"]}]'
    source = f'{{\n {first},\n {last},\n "metadata": {{}}, "nbformat": 4, "nbformat_minor": 5\n}}\n'
    rewritten = _rewrite(source.encode()).decode()
    assert rewritten == source.replace(last, last.replace("import gym", "import gymnasium as gym").replace("obs = env", "obs, info = env"))
    assert json.loads(rewritten)["cells"][0]["source"] == ["import gymnasium as gym\n", 'env = gym.make("CartPole-v1")\n', "obs, info = env.reset()"]


def test_of_two_sources_of_a_cell_the_last_is_migrated() -> None:
    cell = '{"cell_type": "code", "source": "import os\\n", "metadata": {}, "outputs": [], "source": "import gym\\n"}'
    source = f'{{"cells": [{cell}], "metadata": {{}}, "nbformat": 4, "nbformat_minor": 5}}'
    rewritten = _rewrite(source.encode()).decode()
    assert rewritten == source.replace('"import gym\\n"', '"import gymnasium as gym\\n"')


@pytest.mark.parametrize(
    ("text", "new", "expected"),
    [
        pytest.param('{\n "cells": [\n  {\n   "source": []\n  }\n ]\n}', ["a\n", "b"],
                     '[\n    "a\\n",\n    "b"\n   ]', id="empty-list-gets-the-file-indent"),
        pytest.param('{"cells": [{"source": []}]}', ["a"], '["a"]', id="empty-list-one-line-file"),
        pytest.param('{"cells": [{"source": [ "a\\n" , "b" ]}]}', ["a\n", "c\n", "b"],
                     '[ "a\\n" , "c\\n", "b" ]', id="spacing-of-kept-lines-kept"),
        pytest.param('{"cells": [{"source": ["a\\n", "b"]}]}', [], "[]", id="all-lines-removed"),
        pytest.param('{"cells": [{"source": "a"}]}', "é", '"é"', id="string-non-ascii-as-is"),
    ],
)
def test_a_new_source_is_written_in_the_style_of_the_old(text: str, new: str | list[str], expected: str) -> None:
    span = cell_source_spans(text)[0]
    assert isinstance(span, Span)
    assert new_source_text(text, span, new, ensure_ascii=False) == expected


def test_an_edit_that_would_not_read_back_is_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    """The edited text is read again before it is written: a wrong edit is never written."""
    monkeypatch.setattr("gymmigrate.sources.notebook.new_source_text", lambda *args, **kwargs: '["import os\\n"]')
    with pytest.raises(TransformError, match="could not be edited in place; left unchanged"):
        _rewrite((FIXTURES / "hand_indented_source.ipynb").read_bytes())


def test_an_install_line_in_a_notebook_gets_the_new_requirements(tmp_path: Path) -> None:
    """``!pip install gym==0.24`` is IPython syntax, never parsed as Python: its requirements
    move as a requirements file's do (GM109, SB110 for the companions), the rest of the line
    and of the cell stays byte for byte, and a second run finds nothing."""
    path = tmp_path / "train.ipynb"
    source = _notebook(
        ("code", "!pip install gym==0.24 pyglet\n%pip install -q stable-baselines3==1.6\n%matplotlib inline\n"),
        ("code", "import gym\nenv = gym.make('CartPole-v1')\nobs = env.reset()\n"),
    )
    path.write_bytes(source)
    check = runner.invoke(app, ["check", "--output-format", "json", str(path)])
    installs = [(f["cell"], f["line"], f["rule"]) for f in json.loads(check.stdout) if f["rule"] in ("GM109", "SB110")]
    assert installs == [(0, 1, "GM109"), (0, 2, "SB110")]
    result = runner.invoke(app, ["rewrite", str(path)])
    assert result.exit_code == 0, result.stderr
    cells = json.loads(path.read_bytes())["cells"]
    assert "".join(cells[0]["source"]) == (
        '!pip install "gymnasium>=1.0" pyglet\n%pip install -q "stable-baselines3>=2.9"\n%matplotlib inline\n'
    )
    assert "obs, info = env.reset()" in "".join(cells[1]["source"])
    again = runner.invoke(app, ["check", str(path)])
    assert again.exit_code == 0 and again.stdout == ""


def test_a_shell_line_continued_with_a_backslash_is_hidden_with_its_continuation(tmp_path: Path) -> None:
    """``!apt-get install -y \\`` and its indented next line (IPython joins them) inside an
    ``if``: both are IPython's, so the cell parses and its ``!pip install gym`` is migrated."""
    path = tmp_path / "setup.ipynb"
    path.write_bytes(
        _notebook(
            ("code", "backend = 'gym'\nif backend == 'mujoco':\n    !apt-get install -y \\\n        libglew-dev patchelf\nelse:\n    !pip install gym\n"),
            ("code", "import gym\nenv = gym.make('Acrobot-v1')\n"),
        )
    )
    check = runner.invoke(app, ["check", "--output-format", "json", str(path)])
    assert [(f["cell"], f["line"], f["rule"]) for f in json.loads(check.stdout) if f["rule"] in ("GM001", "GM109")] == [(0, 6, "GM109")]
    result = runner.invoke(app, ["rewrite", str(path)])
    assert result.exit_code == 0, result.stderr
    cells = json.loads(path.read_bytes())["cells"]
    assert "".join(cells[0]["source"]) == (
        "backend = 'gym'\nif backend == 'mujoco':\n    !apt-get install -y \\\n        libglew-dev patchelf\nelse:\n    !pip install \"gymnasium>=1.0\"\n"
    )


def test_an_install_line_in_a_cell_that_does_not_parse_is_left_and_said_so(tmp_path: Path) -> None:
    """The cell is left byte for byte, so no GM109 note may say its install line was migrated:
    GM001 says the line is left and asks for it by hand."""
    path = tmp_path / "exercise.ipynb"
    source = _notebook(("code", "!pip install gym\nanswer = <YOUR CODE>\n"), ("code", "import gym\n"))
    path.write_bytes(source)
    check = runner.invoke(app, ["check", "--output-format", "json", str(path)])
    found = [f for f in json.loads(check.stdout) if f["cell"] == 0]
    assert [(f["rule"], f["tier"]) for f in found] == [("GM001", "review")]
    assert "install line" in found[0]["message"]
    result = runner.invoke(app, ["rewrite", str(path)])
    assert result.exit_code == 0, result.stderr
    assert json.loads(path.read_bytes())["cells"][0]["source"] == json.loads(source)["cells"][0]["source"]


def test_install_lines_that_only_describe_the_pin_rewrite_are_notes(tmp_path: Path) -> None:
    """``%pip install -U gym~=0.21.0`` and the next line's ``gym[atari,accept-rom-license]``:
    the notebook's own code is migrated in the same run, so nothing is left to decide (audit F);
    a pin with a real question (the mujoco-py extra) stays on the review list."""
    path = tmp_path / "colab.ipynb"
    path.write_bytes(
        _notebook(
            ("code", "%pip install -U gym~=0.21.0\n%pip install -U gym[atari,accept-rom-license]~=0.21.0\n"),
            ("code", "import gym\nenv = gym.make('CartPole-v1')\nobs = env.reset()\n"),
        )
    )
    check = runner.invoke(app, ["check", "--output-format", "json", str(path)])
    installs = [(f["line"], f["tier"]) for f in json.loads(check.stdout) if f["rule"] == "GM109"]
    assert installs == [(1, "note"), (2, "note")]
    path.write_bytes(_notebook(("code", "!pip install gym[mujoco]==0.21\n"), ("code", "import gym\n")))
    check = runner.invoke(app, ["check", "--output-format", "json", str(path)])
    assert [f["tier"] for f in json.loads(check.stdout) if f["rule"] == "GM109"] == ["review"]


def test_an_unparsed_cell_is_a_review_item_for_its_gym_code_not_for_its_words(tmp_path: Path) -> None:
    """GM001's tier follows the code of the cell (a token scan), not "environment" in a
    docstring or a comment; a done flag that masks a value asks GM302's question."""
    path = tmp_path / "exercise.ipynb"
    path.write_bytes(
        _notebook(
            ("code", "import gym\nenv = gym.make('CartPole-v1')\n"),
            ("code", 'class Actor:\n    def act(self, obs):\n        """Acts in the environment."""\n        return <YOUR CODE>\n'),
            ("code", "# train on the env\nloss.backward()\noptimizer.step()\nmodel = <YOUR CODE>\n"),
            ("code", "is_not_done = 1 - is_done\ntarget = reward + gamma * next_q * is_not_done\nloss = <YOUR CODE>\n"),
            ("code", "s = env.reset()\na = <YOUR CODE>\n"),
        )
    )
    check = runner.invoke(app, ["check", "--output-format", "json", str(path)])
    found = {f["cell"]: f for f in json.loads(check.stdout) if f["rule"] == "GM001"}
    assert {cell: f["tier"] for cell, f in found.items()} == {1: "note", 2: "note", 3: "review", 4: "review"}
    assert "`terminated`" in found[3]["message"] and "GM302" in found[3]["message"]
    assert [found[cell]["cell_number"] for cell in sorted(found)] == [2, 3, 4, 5]  # as the messages count
