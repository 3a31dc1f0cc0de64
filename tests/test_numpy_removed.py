"""GM914 (rules/numpy_removed.py): the migrated fixture runs on the NumPy 2 Gymnasium 1.4
installs with, and the legacy one does not.

The rule's tables are checked against the installed NumPy too: every name it replaces is
gone (``AttributeError``) and every replacement exists, so a NumPy that brought a name
back (as 2.0 did with ``np.bool`` and ``np.long``) fails this file first.
"""

from __future__ import annotations

import builtins
import importlib.util
import math
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

from gymmigrate.engine import transform_source
from gymmigrate.rules import numpy_removed
from tests.fixture_cases import RULE_FIXTURES

CASE = RULE_FIXTURES / "GM914" / "removed_names"


def _load(path: Path) -> ModuleType:
    spec = importlib.util.spec_from_file_location(path.stem.replace(".", "_"), path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_numpy_is_2() -> None:
    assert int(np.__version__.split(".")[0]) >= 2


# NumPy 2 warns that np.object / np.str may come back as its own scalar types one day
@pytest.mark.filterwarnings("ignore:In the future:FutureWarning")
@pytest.mark.parametrize("name", sorted(numpy_removed._ALL))
def test_replaced_names_are_gone(name: str) -> None:
    with pytest.raises(AttributeError):
        getattr(np, name)


@pytest.mark.parametrize("old, new", sorted(numpy_removed._RENAMED.items()))
def test_numpy_replacements_exist(old: str, new: str) -> None:
    assert hasattr(np, new)


@pytest.mark.parametrize("old, new", sorted(numpy_removed._BUILTINS.items()))
def test_builtin_replacements_are_builtin_types(old: str, new: str) -> None:
    # NumPy 1.x had ``np.float is float``: the builtin is the very object the alias named
    assert old == new and isinstance(getattr(builtins, new), type)
    np.dtype(getattr(builtins, new))  # and NumPy 2 still takes it as a dtype


def test_names_numpy_2_defines_again_are_left_alone() -> None:
    # np.bool is np.bool_ and np.long a C long on NumPy 2: no longer the builtins, and no longer failing
    for name in ("bool", "long", "ulong"):
        assert hasattr(np, name)
        assert name not in numpy_removed._ALL


def test_legacy_fixture_fails_on_numpy_2() -> None:
    module = _load(CASE.with_suffix(".py"))
    with pytest.raises(AttributeError):
        module.GridEnv(3)


def test_migrated_fixture_runs_on_numpy_2(tmp_path: Path) -> None:
    migrated = transform_source(CASE.with_suffix(".py").read_bytes(), str(CASE.with_suffix(".py")))
    path = tmp_path / "migrated.py"
    path.write_bytes(migrated.rewritten)
    env = _load(path).GridEnv(3)
    assert env.observation_space.dtype == np.float64
    assert env.grid.dtype == np.dtype(int)
    assert env.visited.dtype == np.bool_
    assert env.phase.dtype == np.complex128
    (rounded, wave, text, raw, missing, bounds, lowest, worst, squared, cells, running, done) = env.stats([1.0, 2.0])
    assert rounded.dtype == np.float64 and wave.dtype == np.complex128
    assert text.dtype.kind == "U" and raw.dtype.kind == "S"
    assert all(math.isnan(value) for value in missing)
    assert bounds == [math.inf] * 4
    assert lowest == -math.inf and worst == 2.0
    assert squared == math.inf  # (-inf) ** 2: the parentheses keep the legacy value
    assert cells == 9 and list(running) == [1.0, 2.0] and not done
