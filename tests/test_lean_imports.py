"""``check``, and ``rewrite`` where nothing changes, never import LibCST; rich loads only
for a terminal. Each command runs in a fresh interpreter, which then lists what it loaded."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
LEGACY = ROOT / "fixtures" / "examples" / "legacy_cartpole_dqn.py"

_PROBE = """
import sys
sys.argv = ["gymmigrate", *sys.argv[1:]]
from gymmigrate.cli import main
try:
    main()
except SystemExit:
    pass
sys.stderr.write("\\nLOADED " + " ".join(sorted(sys.modules)) + "\\n")
"""


def modules_loaded_by(*arguments: str) -> set[str]:
    done = subprocess.run([sys.executable, "-c", _PROBE, *arguments], capture_output=True, text=True, timeout=120)
    line = next(line for line in done.stderr.splitlines() if line.startswith("LOADED "))
    return set(line[len("LOADED ") :].split())


def loaded_by(*arguments: str) -> set[str]:
    return {name.split(".")[0] for name in modules_loaded_by(*arguments)}


def test_check_imports_no_libcst_no_rich_and_no_typer() -> None:
    """A pre-commit hook's ``check FILES``: cli.py reads the arguments itself."""
    loaded = loaded_by("check", str(LEGACY))
    assert "libcst" not in loaded
    assert "rich" not in loaded  # findings and summary go to pipes here, not a terminal
    assert "typer" not in loaded
    loaded = loaded_by("check", "--select", "GM1", "--output-format", "json", "-j", "1", str(LEGACY))
    assert not loaded & {"libcst", "rich", "typer"}


def test_check_of_one_file_loads_only_what_it_uses() -> None:
    """No worker pool, no git, no JSON for text findings, no dependency-file parsers, no
    other command's modules."""
    modules = modules_loaded_by("check", str(LEGACY))
    assert not {name.split(".")[0] for name in modules} & {"subprocess", "multiprocessing", "threading", "json"}
    assert not modules & {"gymmigrate.typer_app", "gymmigrate.rules_listing", "gymmigrate.rule_docs"}
    # the runner reads plugin entry points (GM111) with the standard library only; the
    # requirement parsers (packaging, the TOML and YAML readers) load with a dependency file
    light = {"gymmigrate.dependencies.plugins", "gymmigrate.dependencies.positions"}
    assert not any(name.startswith(("gymmigrate.smoke", "gymmigrate.dependencies.")) for name in modules - light)
    assert not {name.split(".")[0] for name in modules} & {"packaging", "tomlkit", "yaml"}


def test_check_help_still_comes_from_typer() -> None:
    assert "typer" in loaded_by("check", "--help")


@pytest.mark.parametrize("diff", [True, False], ids=["rewrite --diff", "rewrite"])
def test_rewrite_with_nothing_to_change_imports_no_libcst(tmp_path: Path, diff: bool) -> None:
    clean = tmp_path / "train.py"
    clean.write_text("import gymnasium as gym\n\nenv = gym.make('CartPole-v1')\nobs, info = env.reset(seed=0)\n")
    loaded = loaded_by("rewrite", *(["--diff"] if diff else []), str(tmp_path))
    assert "libcst" not in loaded
    assert clean.read_text().startswith("import gymnasium")


def test_rewrite_that_changes_a_file_does_load_libcst(tmp_path: Path) -> None:
    """The probe can see LibCST: a real edit loads it."""
    legacy = tmp_path / "train.py"
    legacy.write_bytes(LEGACY.read_bytes())
    assert "libcst" in loaded_by("rewrite", "--diff", str(legacy))
