"""Dependency declarations (``gymmigrate.dependencies``).

Fixture cases live in ``fixtures/dependencies/<case>/``: one or more input files named as
in a repository (``requirements.txt``, ``pyproject.toml``, ``requirements/base.txt``...),
for each an optional ``<stem>.expected<suffix>`` (absent: the file must come out byte for
byte the same) and one ``findings`` file (``LINE RULE KIND`` per finding, over all inputs).
"""

from __future__ import annotations

import json
import re
import shutil
import sys
from pathlib import Path

import pytest
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name
from packaging.version import Version
from typer.testing import CliRunner

from gymmigrate.cli import app
from gymmigrate.dependencies import (
    DependencyError,
    is_dependency_file,
    kind_of,
    migrate_dependency_file,
    migrate_page_commands,
)
from gymmigrate.dependencies.pyproject import poetry_to_pep440
from gymmigrate.files import discover
from gymmigrate.rules import all_rules

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

CASES_DIR = Path(__file__).resolve().parent.parent / "fixtures" / "dependencies"
runner = CliRunner()


def _expected_path(path: Path) -> Path:
    return path.with_name(f"{path.stem}.expected{path.suffix}") if path.suffix else path.with_name(f"{path.name}.expected")


def _inputs(case: Path) -> list[Path]:
    return sorted(p for p in case.rglob("*") if p.is_file() and ".expected" not in p.name and p.name != "findings")


def _migrate(relative: Path, source: bytes):
    if relative.suffix in (".md", ".rst"):
        return migrate_page_commands(relative, source)
    return migrate_dependency_file(relative, source)


CASES = sorted(p for p in CASES_DIR.iterdir() if p.is_dir())


@pytest.mark.parametrize("case", CASES, ids=lambda p: p.name)
def test_fixture_case(case: Path) -> None:
    rows = []
    for path in _inputs(case):
        relative = path.relative_to(case)
        source = path.read_bytes()
        rewritten, findings = _migrate(relative, source)
        expected = _expected_path(path)
        if expected.exists():
            assert rewritten == expected.read_bytes(), f"{relative}: output differs from {expected.name}"
            assert rewritten != source
        else:
            assert rewritten == source, f"{relative}: a no-op case must come out byte for byte the same"
        # A second run over the output changes nothing.
        again, _ = _migrate(relative, rewritten)
        assert again == rewritten, f"{relative}: not idempotent"
        rows += [(f.line, f.rule, f.kind.value) for f in findings]
    wanted = []
    for raw in (case / "findings").read_text(encoding="utf-8").splitlines():
        number, rule, kind = raw.split()
        wanted.append((int(number), rule, kind))
    assert sorted(rows) == sorted(wanted)


def test_every_format_has_a_rewrite_and_a_noop_case() -> None:
    rewrites = {p.name for case in CASES for p in _inputs(case) if _expected_path(p).exists()}
    noops = {p.name for case in CASES for p in _inputs(case) if not _expected_path(p).exists()}
    assert {"requirements.txt", "pyproject.toml", "setup.py", "setup.cfg", "environment.yml", "Dockerfile"} <= rewrites
    assert {"requirements.txt", "pyproject.toml", "setup.py"} <= noops


def test_crlf_and_comments_are_kept() -> None:
    case = CASES_DIR / "requirements_crlf_hashes"
    rewritten = (case / "requirements.expected.txt").read_bytes()
    source = (case / "requirements.txt").read_bytes()
    assert rewritten.count(b"\r\n") == source.count(b"\r\n") and b"\n" not in rewritten.replace(b"\r\n", b"")
    assert b"--hash=sha256:e0d882f4" in rewritten and b"# mixed case" in rewritten
    # Only the changed requirement strings differ; every other line is byte-identical.
    changed = [(a, b) for a, b in zip(source.split(b"\r\n"), rewritten.split(b"\r\n")) if a != b]
    assert changed == [(b"gym==0.26.2 \\", b"gymnasium>=1.0 \\"), (b"Gym[Box2D]>=0.21\t# mixed case", b"gymnasium[box2d]>=1.0\t# mixed case")]


def _written_requirements() -> list[Requirement]:
    """Every gymnasium requirement the rewrites wrote (in the expected outputs, not in the inputs)."""
    found: list[Requirement] = []
    for case in CASES:
        for path in _inputs(case):
            expected = _expected_path(path)
            if not expected.exists():
                continue
            text = expected.read_text(encoding="utf-8")
            before = path.read_text(encoding="utf-8")
            candidates: list[str] = []
            if path.name == "pyproject.toml":
                data = tomllib.loads(text)
                candidates += data.get("project", {}).get("dependencies", [])
                for values in data.get("project", {}).get("optional-dependencies", {}).values():
                    candidates += values
                for name, value in data.get("tool", {}).get("poetry", {}).get("dependencies", {}).items():
                    if name == "gymnasium":
                        candidates.append("gymnasium" + (value["version"] if isinstance(value, dict) else value))
            else:
                candidates += re.findall(r"gymnasium(?:\[[\w,-]*\])?(?:[<>=!~]=?[\w.*]+(?:,[<>=!~]=?[\w.*]+)*)?", text)
            for candidate in candidates:
                # Only what the rewrite wrote: a line the input already had is the project's own.
                if isinstance(candidate, str) and candidate.startswith("gymnasium") and candidate not in before:
                    found.append(Requirement(candidate))
    return found


def test_every_written_gymnasium_requirement_accepts_gymnasium_1_4() -> None:
    """The migrated declarations resolve to Gymnasium 1.4.0 (checked with packaging, no
    network): every written spec admits 1.4.0 and every extra exists in 1.4.0."""
    from importlib.metadata import metadata

    installed = metadata("gymnasium")
    assert Version(installed["Version"]) >= Version("1.4")
    extras = {canonicalize_name(e) for e in installed.get_all("Provides-Extra") or []}
    requirements = _written_requirements()
    assert len(requirements) >= 15
    for requirement in requirements:
        assert requirement.specifier.contains(Version("1.4.0")), str(requirement)
        assert {canonicalize_name(e) for e in requirement.extras} <= extras, str(requirement)


def test_moved_library_pins_admit_the_checked_releases() -> None:
    from gymmigrate.dependencies.mapping import MOVED_WITH_GYM

    for name, (minimum, current, _) in MOVED_WITH_GYM.items():
        assert Requirement(f"{name}{minimum}").specifier.contains(Version(current)), name


@pytest.mark.parametrize(
    ("constraint", "admits", "excludes"),
    [("^0.21", "0.21.5", "0.22.0"), ("^1.6", "1.8.0", "2.0.0"), ("~1.6", "1.6.3", "1.7.0"), ("0.21.0", "0.21.0", "0.21.1"), ("*", "1.4.0", None), (">=1.0,<2", "1.4.0", "2.0")],
)
def test_poetry_constraints(constraint: str, admits: str, excludes: str | None) -> None:
    spec = poetry_to_pep440(constraint)
    assert spec is not None and spec.contains(admits)
    if excludes:
        assert not spec.contains(excludes)


def test_untouched_dependency_files_stay_byte_identical() -> None:
    for name, source in [
        ("requirements.txt", b"numpy==1.26\r\n# gym is mentioned only in a comment\r\n"),
        ("pyproject.toml", b'[project]\nname = "gym-tools"\ndependencies = ["numpy"]\n'),
        ("setup.py", b"from setuptools import setup\nsetup(name='x', install_requires=['numpy'])  # gym\n"),
        ("environment.yml", b"dependencies:\n  - numpy\n"),
    ]:
        rewritten, findings = migrate_dependency_file(name, source)
        assert rewritten == source and findings == [], name


def test_a_file_that_cannot_be_read_is_an_error_not_a_guess() -> None:
    with pytest.raises(DependencyError):
        migrate_dependency_file("pyproject.toml", b"[project\ndependencies = ['gym']\n")
    with pytest.raises(DependencyError):
        migrate_dependency_file("setup.py", b"setup(install_requires=['gym'\n")


def test_registry_names() -> None:
    for name in ["requirements.txt", "requirements-dev.txt", "requirements/base.txt", "constraints.txt", "setup.py", "setup.cfg", "pyproject.toml", "environment.yml", "Dockerfile", "Dockerfile.gpu", "train.dockerfile"]:
        assert is_dependency_file(name), name
    for name in ["train.py", "notes.txt", "README.md", "Pipfile", "poetry.lock"]:
        assert kind_of(name) is None, name


def test_discovery_finds_dependency_files(tmp_path: Path) -> None:
    (tmp_path / "requirements").mkdir()
    for name in ["requirements.txt", "requirements/base.txt", "pyproject.toml", "setup.cfg", "Dockerfile", "notes.txt", "train.py"]:
        (tmp_path / name).write_text("gym\n")
    found = {p.relative_to(tmp_path).as_posix() for p in discover([str(tmp_path)]).files}
    assert found == {"requirements.txt", "requirements/base.txt", "pyproject.toml", "setup.cfg", "Dockerfile", "train.py"}
    assert discover([str(tmp_path / "Dockerfile")]).files == [tmp_path / "Dockerfile"]


# -- end to end -----------------------------------------------------------------------------

REQUIREMENTS = b"gym[atari]==0.21.0  # envs\r\nautorom[accept-rom-license]\r\nnumpy\r\n"
PYPROJECT = b'[project]\nname = "agents"\ndependencies = [\n    "gym==0.21.0",\n    "stable-baselines3[extra]==1.8.0",\n]\n'
SETUP_PY = b'from setuptools import setup\n\nsetup(name="agents", install_requires=["gym[box2d]>=0.21", "numpy"])\n'


@pytest.fixture
def repo(tmp_path: Path) -> Path:
    (tmp_path / "requirements.txt").write_bytes(REQUIREMENTS)
    (tmp_path / "pyproject.toml").write_bytes(PYPROJECT)
    (tmp_path / "setup.py").write_bytes(SETUP_PY)
    (tmp_path / "clean.txt").write_bytes(b"gym\n")  # not a dependency file: never read
    return tmp_path


def test_cli_diff_check_rewrite(repo: Path) -> None:
    diff = runner.invoke(app, ["rewrite", "--diff", str(repo)])
    assert diff.exit_code == 1, diff.output
    assert f"--- {repo / 'requirements.txt'}" in diff.stdout
    # (the test runner reads stdout with universal newlines; the CRLF file is checked below)
    assert "-gym[atari]==0.21.0  # envs\n-autorom[accept-rom-license]\n+gymnasium[atari]>=1.0  # envs\n numpy\n" in diff.stdout
    assert '-    "gym==0.21.0",\n-    "stable-baselines3[extra]==1.8.0",\n+    "gymnasium>=1.0",\n+    "stable-baselines3[extra]>=2.9",\n' in diff.stdout
    assert '+setup(name="agents", install_requires=["gymnasium[box2d]>=1.0", "numpy"])\n' in diff.stdout
    assert (repo / "requirements.txt").read_bytes() == REQUIREMENTS, "--diff writes nothing"

    check = runner.invoke(app, ["check", str(repo)])
    assert check.exit_code == 1
    assert "requirements.txt:1:1: GM109" in check.stdout and "pyproject.toml:5:6: SB110" in check.stdout

    rewrite = runner.invoke(app, ["rewrite", str(repo)])
    assert rewrite.exit_code == 0, rewrite.output
    assert "rewrote 3 of 3 files" in rewrite.stderr
    assert (repo / "requirements.txt").read_bytes() == b"gymnasium[atari]>=1.0  # envs\r\nnumpy\r\n"
    assert (repo / "clean.txt").read_bytes() == b"gym\n"

    again = runner.invoke(app, ["rewrite", "--diff", str(repo)])
    assert again.exit_code == 0 and again.stdout == ""
    assert runner.invoke(app, ["check", str(repo)]).exit_code == 0


def test_cli_page_pip_lines_with_docs(tmp_path: Path) -> None:
    page = tmp_path / "README.md"
    page.write_bytes(b"# Setup\n\n```sh\npip install gym==0.21.0\n```\n\n```python\nimport gym\n```\n")
    result = runner.invoke(app, ["rewrite", "--docs", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert page.read_bytes() == b'# Setup\n\n```sh\npip install "gymnasium>=1.0"\n```\n\n```python\nimport gymnasium as gym\n```\n'
    assert runner.invoke(app, ["check", "--docs", str(tmp_path)]).exit_code == 0


def test_select_and_ignore_apply_to_dependency_rules(repo: Path) -> None:
    """A rule left out neither reports nor fixes, in dependency files as in Python."""
    only_python = runner.invoke(app, ["check", "--select", "GM3", str(repo)])
    assert only_python.exit_code == 0 and only_python.stdout == ""
    rewrite = runner.invoke(app, ["rewrite", "--ignore", "SB110", str(repo)])
    assert rewrite.exit_code == 0, rewrite.output
    pyproject = (repo / "pyproject.toml").read_text()
    assert '"gymnasium>=1.0"' in pyproject and '"stable-baselines3[extra]==1.8.0"' in pyproject
    assert runner.invoke(app, ["check", "--select", "SB110", str(repo)]).exit_code == 1
    assert runner.invoke(app, ["rewrite", "--select", "SB110", str(repo)]).exit_code == 0
    assert '"stable-baselines3[extra]>=2.9"' in (repo / "pyproject.toml").read_text()
    assert runner.invoke(app, ["check", str(repo)]).exit_code == 0


def test_hash_warning_goes_with_its_rewrite() -> None:
    source = b"gym==0.21.0 \\\n    --hash=sha256:00\n"
    _, findings = migrate_dependency_file("requirements.txt", source)
    assert sorted(f.rule for f in findings) == ["GM109", "GM110"]
    from gymmigrate.selection import Selection

    rewritten, findings = migrate_dependency_file("requirements.txt", source, selection=Selection.from_selectors(["GM110"], codes=[r.code for r in all_rules()]))
    assert rewritten == source and findings == []


def test_every_dependency_rule_fires_in_a_fixture_and_is_listed() -> None:
    """GM109, GM110 and SB110 are rules like the others: each fires in some case, and
    ``gymmigrate rules`` and ``--select`` know them."""
    from gymmigrate.rules.dependency_files import DEPENDENCY_RULES

    fired = {row.split()[1] for case in CASES for row in (case / "findings").read_text().splitlines() if row.strip()}
    assert {rule.code for rule in DEPENDENCY_RULES} <= fired
    assert set(DEPENDENCY_RULES) <= set(all_rules())


# -- packages the migrated code imports that left a declared library (mpe2 out of pettingzoo)

MPE2 = frozenset({"mpe2"})


@pytest.mark.parametrize(
    ("name", "before", "after"),
    [
        ("requirements.txt", "gym==0.26.2\npettingzoo==1.21.0  # envs\nnumpy\n",
         "gymnasium>=1.0\npettingzoo>=1.25  # envs\nmpe2>=1.0\nnumpy\n"),
        ("setup.py", 'from setuptools import setup\n\nsetup(\n    install_requires=[\n        "pettingzoo>=1.21.0",\n'
         '        "numpy",\n    ],\n    extras_require={"dev": ["pettingzoo[butterfly]"]},\n)\n',
         'from setuptools import setup\n\nsetup(\n    install_requires=[\n        "pettingzoo>=1.21.0",\n'
         '        "mpe2>=1.0",\n        "numpy",\n    ],\n    extras_require={"dev": ["pettingzoo[butterfly]"]},\n)\n'),
        ("pyproject.toml", '[project]\nname = "x"\ndependencies = [\n    "numpy",\n    \'pettingzoo>=1.24\',\n]\n',
         '[project]\nname = "x"\ndependencies = [\n    "numpy",\n    \'pettingzoo>=1.24\',\n    \'mpe2>=1.0\',\n]\n'),
    ],
)
def test_mpe2_is_declared_next_to_pettingzoo_when_the_code_imports_it(name: str, before: str, after: str) -> None:
    result = migrate_dependency_file(name, before.encode(), requires=MPE2)
    assert result.rewritten.decode() == after
    again = migrate_dependency_file(name, result.rewritten, requires=MPE2)
    assert again.rewritten == result.rewritten
    assert any(f.rule == "SB110" and "mpe2" in f.message for f in result.findings)
    if name == "setup.py":
        Requirement("mpe2>=1.0")  # what is written parses as a requirement
        compile(result.rewritten, name, "exec")


@pytest.mark.parametrize(
    ("name", "text", "requires"),
    [
        ("requirements.txt", "pettingzoo>=1.25\nmpe2\n", MPE2),  # declared already
        ("requirements.txt", "gymnasium>=1.0\n", MPE2),  # no pettingzoo here: another file's business
        ("requirements.txt", "pettingzoo>=1.25\n", frozenset()),  # the code does not import mpe2
    ],
)
def test_mpe2_is_not_added_where_it_is_not_needed(name: str, text: str, requires: frozenset[str]) -> None:
    result = migrate_dependency_file(name, text.encode(), requires=requires)
    assert result.rewritten == text.encode()
    assert not any("mpe2" in f.message for f in result.findings)


def test_mpe2_is_reported_where_no_line_can_hold_it() -> None:
    text = "pettingzoo>=1.25 --hash=sha256:abc\n"  # a hashed line: a new one needs its own hashes
    result = migrate_dependency_file("requirements.txt", text.encode(), requires=MPE2)
    assert result.rewritten == text.encode()
    assert [f.kind.value for f in result.findings if "mpe2" in f.message] == ["flag"]


def test_mpe2_joins_a_one_line_list() -> None:
    text = 'from setuptools import setup\nsetup(install_requires=["pettingzoo>=1.25"])\n'
    result = migrate_dependency_file("setup.py", text.encode(), requires=MPE2)
    assert result.rewritten.decode() == 'from setuptools import setup\nsetup(install_requires=["pettingzoo>=1.25", "mpe2>=1.0"])\n'
    assert [f.kind.value for f in result.findings if "mpe2" in f.message] == ["auto"]


def test_a_run_that_moves_mpe_imports_declares_mpe2(tmp_path: Path) -> None:
    (tmp_path / "requirements.txt").write_text("pettingzoo==1.21.0\n")
    (tmp_path / "train.py").write_text("from pettingzoo.mpe import simple_v2\n\nenv = simple_v2.env()\n")
    (tmp_path / "other.txt").write_text("pettingzoo\n")
    result = CliRunner().invoke(app, ["rewrite", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert (tmp_path / "requirements.txt").read_text() == "pettingzoo>=1.25\nmpe2>=1.0\n"
    assert (tmp_path / "train.py").read_text() == "from mpe2 import simple_v3\n\nenv = simple_v3.env()\n"
    again = CliRunner().invoke(app, ["rewrite", str(tmp_path)])
    assert again.exit_code == 0 and (tmp_path / "requirements.txt").read_text() == "pettingzoo>=1.25\nmpe2>=1.0\n"


# -- imageio next to mujoco, where the run's code imports Gymnasium's MuJoCo envs

IMAGEIO = frozenset({"imageio"})


@pytest.mark.parametrize(
    ("name", "before", "after"),
    [
        ("requirements.txt", "mujoco>=2.3  # physics\nnumpy\n", "mujoco>=2.3  # physics\nimageio>=2.14.1\nnumpy\n"),
        # the last element of a one-line list: a new element after it, in its quotes
        ("pyproject.toml", '[project]\nname = "x"\n[project.optional-dependencies]\nsim = ["mujoco >=2.3.0"]\n',
         '[project]\nname = "x"\n[project.optional-dependencies]\nsim = ["mujoco >=2.3.0", "imageio>=2.14.1"]\n'),
        ("setup.py", "from setuptools import setup\nsetup(extras_require={'sim': ['mujoco>=2.3' ]})\n",
         "from setuptools import setup\nsetup(extras_require={'sim': ['mujoco>=2.3', 'imageio>=2.14.1' ]})\n"),
    ],
)
def test_imageio_is_declared_next_to_mujoco_when_the_code_imports_mujoco_envs(name: str, before: str, after: str) -> None:
    result = migrate_dependency_file(name, before.encode(), requires=IMAGEIO)
    assert result.rewritten.decode() == after
    assert migrate_dependency_file(name, result.rewritten, requires=IMAGEIO).rewritten == result.rewritten
    # the GM110 note asking for imageio by hand is answered on that line
    assert not any(f.rule == "GM110" for f in result.findings)
    assert [f.rule for f in result.findings if "imageio" in f.message] == ["SB110"]
    if name == "setup.py":
        compile(result.rewritten, name, "exec")


@pytest.mark.parametrize(
    ("name", "text"),
    [
        ("requirements.txt", "mujoco>=2.3\n"),  # the code imports no MuJoCo env: GM110 reports it only
        ("setup.py", "from setuptools import setup\nsetup(install_requires='mujoco')\n"),  # a string, not a list
    ],
)
def test_imageio_is_not_added_without_the_import_or_a_list(name: str, text: str) -> None:
    requires = IMAGEIO if name == "setup.py" else frozenset()
    result = migrate_dependency_file(name, text.encode(), requires=requires)
    assert result.rewritten == text.encode()


def test_a_run_that_imports_mujoco_envs_declares_imageio(tmp_path: Path) -> None:
    (tmp_path / "pyproject.toml").write_text(
        '[project]\nname = "x"\ndependencies = ["gym>=0.26"]\n[project.optional-dependencies]\nmujoco = ["mujoco>=2.3"]\n'
    )
    (tmp_path / "cheetah.py").write_text(
        "from gym.envs.mujoco.half_cheetah_v4 import HalfCheetahEnv\n\n\nclass Cheetah(HalfCheetahEnv):\n    pass\n"
    )
    result = CliRunner().invoke(app, ["rewrite", str(tmp_path)])
    assert result.exit_code == 0, result.output
    expected = '[project]\nname = "x"\ndependencies = ["gymnasium>=1.0"]\n[project.optional-dependencies]\nmujoco = ["mujoco>=2.3", "imageio>=2.14.1"]\n'
    assert (tmp_path / "pyproject.toml").read_text() == expected
    assert "from gymnasium.envs.mujoco.half_cheetah_v4 import HalfCheetahEnv" in (tmp_path / "cheetah.py").read_text()
    again = CliRunner().invoke(app, ["rewrite", str(tmp_path)])
    assert again.exit_code == 0 and (tmp_path / "pyproject.toml").read_text() == expected


# -- gym's own pin where the run migrates the code beside it

PIN_WITH_CODE = Path(__file__).resolve().parent.parent / "fixtures" / "project_pin_with_code"


def _gym_pin(arguments: list[str]) -> dict:
    check = CliRunner().invoke(app, ["check", "--output-format", "json", *arguments])
    return next(f for f in json.loads(check.stdout) if f["rule"] == "GM109")


def test_the_pin_of_a_package_the_run_migrates_is_a_note() -> None:
    """``fixtures/project_pin_with_code``: the package's modules are in the run, so "the code
    must be migrated with it" is what the run does: a note that says so."""
    pin = _gym_pin([str(PIN_WITH_CODE)])
    assert pin["tier"] == "note"
    assert pin["message"] == "`gym` -> `gymnasium>=1.0`: the code beside it is migrated with it in the same run (imports, reset/step API)"


def test_the_pin_stays_a_question_where_the_code_is_not_migrated_with_it(tmp_path: Path) -> None:
    """Alone, with a module of the package left as it is, or with a rule that moves the code
    left out, the code must still be migrated with the pin: a review item."""
    assert _gym_pin([str(PIN_WITH_CODE / "setup.py")])["tier"] == "review"
    assert _gym_pin(["--ignore", "GM301", str(PIN_WITH_CODE)])["tier"] == "review"
    run = tmp_path / "run"
    shutil.copytree(PIN_WITH_CODE, run)
    pad = run / "hoverpad" / "pad.py"
    pad.write_text("# gymmigrate: skip-file\n" + pad.read_text())
    pin = _gym_pin([str(run)])
    assert pin["tier"] == "review" and "the code must be migrated with it" in pin["message"]
