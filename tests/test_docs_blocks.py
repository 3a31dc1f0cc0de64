"""Python code blocks in Markdown and reStructuredText pages.

Fixtures: ``fixtures/docs/<page>.md|.rst`` and ``<page>.expected.md|.rst``.
"""

from __future__ import annotations

import ast
import difflib
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app
from gymmigrate.findings import FixKind
from gymmigrate.options import RewriteOptions
from gymmigrate.sources import adapter_for
from gymmigrate.sources.pages import _with_prompts
from gymmigrate.sources.programs import lint_document, transform_document

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures" / "docs"
PAGES = sorted(path for path in FIXTURES.iterdir() if ".expected." not in path.name)
runner = CliRunner()


def _expected(page: Path) -> Path:
    return page.with_name(f"{page.stem}.expected{page.suffix}")


def _transform(path: Path, source: bytes):
    adapter = adapter_for(path)
    assert adapter is not None
    return transform_document(adapter, source, str(path), RewriteOptions())


@pytest.mark.parametrize("page", PAGES, ids=lambda page: page.name)
def test_page_is_migrated_and_stable(page: Path) -> None:
    rewritten = _transform(page, page.read_bytes()).rewritten
    assert rewritten == _expected(page).read_bytes()
    assert _transform(page, rewritten).rewritten == rewritten, "a second run changes nothing"


@pytest.mark.parametrize("page", PAGES, ids=lambda page: page.name)
def test_only_lines_inside_python_blocks_change(page: Path) -> None:
    """Prose, shell, YAML and text blocks are byte-identical; every changed line is code."""
    adapter = adapter_for(page)
    assert adapter is not None
    document = adapter.read(page.read_bytes(), str(page))
    code_lines = document.code_line_indexes()
    before = page.read_text(encoding="utf-8").splitlines(keepends=True)
    after = _expected(page).read_text(encoding="utf-8").splitlines(keepends=True)
    matcher = difflib.SequenceMatcher(None, before, after, autojunk=False)
    changed = [i for tag, i1, i2, _, _ in matcher.get_opcodes() if tag != "equal" for i in range(i1, max(i2, i1 + 1))]
    assert changed, "the fixture migrates something"
    assert set(changed) <= code_lines


def test_shell_and_other_languages_are_untouched() -> None:
    quickstart = (FIXTURES / "quickstart.expected.md").read_text(encoding="utf-8")
    assert "```sh\npip install gym==0.21.0\npython -c \"import gym; env = gym.make('CartPole-v1'); obs = env.reset()\"\n```" in quickstart
    assert "~~~yaml\nenv: CartPole-v1\nreset: env.reset()\n~~~" in quickstart
    api = (FIXTURES / "api.expected.rst").read_text(encoding="utf-8")
    assert '.. code-block:: bash\n\n   pip install gym\n   python -c "obs = env.reset()"\n' in api
    assert ".. code-block:: text\n\n   >>> obs = env.reset()   # a text block" in api


def test_sessions_keep_prompts_and_output_and_grown_statements_get_continuation_prompts() -> None:
    quickstart = (FIXTURES / "quickstart.expected.md").read_text(encoding="utf-8")
    assert (
        ">>> while not done:\n"
        "...     obs, reward, terminated, truncated, info = env.step(0)\n"
        "...     done = terminated or truncated\n"
        "...\n"
        '>>> print("episode over")\n'
        "episode over\n"
    ) in quickstart
    assert ">>> obs.shape\n(4,)\n" in quickstart


def test_a_removed_example_takes_its_printed_output_with_it() -> None:
    api = (FIXTURES / "api.expected.rst").read_text(encoding="utf-8")
    assert "[42]" not in api and "env.seed" not in api
    assert "   >>> obs, info = env.reset(seed=42)\n" in api


def test_new_statements_in_a_session_get_their_own_prompt() -> None:
    code = "obs, reward, terminated, truncated, info = env.step(0)\ndone = terminated or truncated\n"
    assert _with_prompts(code) == [
        ">>> obs, reward, terminated, truncated, info = env.step(0)\n",
        ">>> done = terminated or truncated\n",
    ]


def test_a_page_whose_blocks_share_names_is_one_program() -> None:
    tutorial = (FIXTURES / "tutorial.expected.md").read_text(encoding="utf-8")
    # env is made in the first block: the second block's seed and reset are known Gym calls.
    assert "```python\nobservation, info = env.reset(seed=123)\n```" in tutorial
    assert "         done = terminated or truncated\n     ```" in tutorial


def test_independent_blocks_are_separate_programs(tmp_path: Path) -> None:
    page = tmp_path / "two.md"
    page.write_text("```python\nimport gym\nenv = gym.make('CartPole-v1')\n```\n\n```python\nenv.seed(1)\nobs = env.reset()\n```\n")
    rewritten = _transform(page, page.read_bytes()).rewritten.decode()
    # The second block uses `env`, which only the first binds: one program, env is known.
    assert "obs, info = env.reset(seed=1)" in rewritten
    # Here no block uses a name bound by an earlier one: each is its own program, and the
    # second block's `env` is unknown, so it is left alone.
    page.write_text("```python\nimport gym\n```\n\n```python\nenv.seed(1)\nobs = env.reset()\n```\n")
    assert "env.seed(1)\nobs = env.reset()" in _transform(page, page.read_bytes()).rewritten.decode()


def test_a_block_that_does_not_parse_is_flagged_and_left_alone() -> None:
    page = FIXTURES / "quickstart.md"
    transformed = _transform(page, page.read_bytes())
    notes = [f for f in transformed.findings if f.rule == "GM001"]
    assert len(notes) == 1 and notes[0].kind is FixKind.FLAG
    line = page.read_text(encoding="utf-8").splitlines()[notes[0].line - 1]
    assert line == "obs = env.reset(<your seed>)"
    assert "```python\nobs = env.reset(<your seed>)\n```\n" in transformed.rewritten.decode()


def test_check_agrees_with_rewrite() -> None:
    for page in PAGES:
        adapter = adapter_for(page)
        assert adapter is not None
        findings, would_change = lint_document(adapter, page.read_bytes(), str(page), RewriteOptions())
        transformed = _transform(page, page.read_bytes())
        assert would_change == transformed.changed
        assert [(f.rule, f.line) for f in findings] == [(f.rule, f.line) for f in transformed.findings]


@pytest.fixture
def project(tmp_path: Path) -> Path:
    for page in PAGES:
        shutil.copy(page, tmp_path / page.name)
    (tmp_path / "train.py").write_text("import gym\n")
    return tmp_path


def test_pages_are_walked_only_with_docs(project: Path) -> None:
    without = runner.invoke(app, ["rewrite", "--diff", str(project)])
    assert without.exit_code == 1
    assert "quickstart.md" not in without.stdout and "train.py" in without.stdout
    with_docs = runner.invoke(app, ["rewrite", "--diff", "--docs", str(project)])
    assert with_docs.exit_code == 1
    assert f"--- {project / 'quickstart.md'}" in with_docs.stdout
    assert "-env.seed(0)\n-obs = env.reset()\n+obs, info = env.reset(seed=0)\n" in with_docs.stdout
    assert f"--- {project / 'api.rst'}" in with_docs.stdout
    assert (project / "quickstart.md").read_bytes() == (FIXTURES / "quickstart.md").read_bytes()


def test_a_page_named_explicitly_is_always_processed(project: Path) -> None:
    result = runner.invoke(app, ["check", str(project / "api.rst")])
    assert result.exit_code == 1
    assert f"{project / 'api.rst'}:16:1: GM101 [auto]" in result.stdout


def test_rewrite_with_docs_writes_pages_then_changes_nothing(project: Path) -> None:
    result = runner.invoke(app, ["rewrite", "--docs", str(project)])
    assert result.exit_code == 0, result.stderr
    assert "GM001 (not rewritten)" in result.stderr
    from gymmigrate.dependencies import migrate_page_commands

    for page in PAGES:
        # The run also migrates the `pip install` lines of shell blocks (gymmigrate.dependencies).
        expected = migrate_page_commands(page, _expected(page).read_bytes()).rewritten
        assert (project / page.name).read_bytes() == expected
    assert b'pip install "gymnasium>=1.0"\n' in (project / "quickstart.md").read_bytes()
    check = runner.invoke(app, ["check", "--docs", str(project)])
    assert check.exit_code == 1  # only the block that does not parse is left
    assert [line.split(": ", 1)[1].split(" ")[0] for line in check.stdout.splitlines()] == ["GM001"]


def test_an_indented_excerpt_is_read_from_its_own_margin(tmp_path: Path) -> None:
    page = tmp_path / "excerpt.md"
    page.write_text("```python\n    import gym\n    env = gym.make('CartPole-v1')\n    obs = env.reset()\n```\n")
    rewritten = _transform(page, page.read_bytes()).rewritten.decode()
    assert rewritten == "```python\n    import gymnasium as gym\n    env = gym.make('CartPole-v1')\n    obs, info = env.reset()\n```\n"


def test_only_newlines_end_lines_so_odd_characters_in_prose_and_code_survive(tmp_path: Path) -> None:
    page = tmp_path / "odd.md"
    text = "Prose with a form feed \f and a line separator \u2028 inside.\n\n```python\nimport gym\nname = 'a\u2028b'\n```\n"
    page.write_text(text, encoding="utf-8")
    transformed = _transform(page, page.read_bytes())
    assert transformed.rewritten.decode("utf-8") == text.replace("import gym", "import gymnasium as gym")
    assert [(f.rule, f.line) for f in transformed.findings] == [("GM101", 4)]


def test_a_session_that_gains_statements_gets_a_prompt_per_statement(tmp_path: Path) -> None:
    page = tmp_path / "atari.md"
    page.write_text('```pycon\n>>> import gym\n>>> env = gym.make("BreakoutNoFrameskip-v4")\n>>> obs = env.reset()\n```\n')
    rewritten = _transform(page, page.read_bytes()).rewritten.decode()
    assert rewritten == (
        "```pycon\n"
        ">>> import gymnasium as gym\n"
        ">>> import ale_py\n"
        ">>> gym.register_envs(ale_py)\n"
        '>>> env = gym.make("BreakoutNoFrameskip-v4")\n'
        ">>> obs, info = env.reset()\n"
        "```\n"
    )
    assert _transform(page, rewritten.encode()).rewritten.decode() == rewritten, "a second run changes nothing"


def _as_session(text: str) -> str:
    """A script typed into the interpreter: ``>>>`` per top-level statement, ``...`` after."""
    tree = ast.parse(text)
    lines = text.splitlines(keepends=True)
    starts = {min([node.lineno, *(d.lineno for d in getattr(node, "decorator_list", ()))]) for node in tree.body}
    out: list[str] = []
    for number, line in enumerate(lines, start=1):
        if not line.strip():
            if number + 1 not in starts and number != len(lines):
                out.append("...\n")
            continue
        out.append((">>> " if number in starts or not out else "... ") + line)
    return "".join(out)


RULE_CASES = sorted(
    path
    for path in (Path(__file__).resolve().parent.parent / "fixtures" / "rules").glob("*/*.py")
    if not path.name.endswith(".expected.py")
)


@pytest.mark.parametrize("case", RULE_CASES, ids=lambda path: f"{path.parent.name}/{path.stem}")
def test_every_rule_case_typed_as_a_session_migrates_as_the_script_does(case: Path) -> None:
    text = case.read_text(encoding="utf-8")
    expected = case.with_name(f"{case.stem}.expected.py")
    after = expected.read_text(encoding="utf-8") if expected.exists() else text
    page = f"Prose.\n\n```pycon\n{_as_session(text if text.endswith(chr(10)) else text + chr(10))}```\n\nMore prose.\n"
    adapter = adapter_for(Path("page.md"))
    assert adapter is not None
    rewritten = transform_document(adapter, page.encode(), "page.md", RewriteOptions()).rewritten.decode()
    assert rewritten.startswith("Prose.\n\n```pycon\n") and rewritten.endswith("```\n\nMore prose.\n")
    session = rewritten.splitlines(keepends=True)[3:-3]
    assert all(line.startswith((">>> ", "... ", "...\n")) for line in session)
    code = [line[4:] if line[3:4] == " " else line[3:] for line in session]
    assert [line.rstrip() for line in code if line.strip()] == [line.rstrip() for line in after.splitlines() if line.strip()]


def test_rst_literal_blocks_are_python_only_if_they_parse_and_no_highlight_says_otherwise(tmp_path: Path) -> None:
    api = (FIXTURES / "api.expected.rst").read_text(encoding="utf-8")
    assert "Sphinx::\n\n    import gymnasium as gym\n" in api
    assert "    Episode 1: return 21.0 (env.reset() took 0.1 ms)\n" in api
    page = tmp_path / "console.rst"
    text = ".. highlight:: console\n\nRun::\n\n    import gym\n    obs = gym.make('CartPole-v1').reset()\n"
    page.write_text(text)
    transformed = _transform(page, page.read_bytes())
    assert transformed.rewritten.decode() == text and transformed.findings == []


def test_findings_give_their_line_in_the_rewritten_page_too(tmp_path: Path) -> None:
    page = tmp_path / "two.md"
    page.write_text(
        "```python\nimport gym\nenv = gym.make('CartPole-v1')\nobs, r, done, info = env.step(0)\nprint(done)\n```\n\n"
        "```python\nfrom gymnasium import spaces\nspace = spaces.Box(0, 1, (2,), dtype=None)\n```\n"
    )
    transformed = _transform(page, page.read_bytes())
    box = next(f for f in transformed.findings if f.rule == "GM904")
    before = page.read_text().splitlines()
    after = transformed.rewritten.decode().splitlines()
    assert "dtype=None" in before[box.line - 1]
    assert "dtype=None" in after[box.line_after - 1]
    assert box.line_after == box.line + 1, "the first block grew by one line (done = terminated or truncated)"
