"""Space drift (rules/spaces/drift.py): the migrated fixtures run on Gymnasium 1.4.

The GM903 / GM905 fixtures' expected outputs are imported and run against real
Gymnasium spaces: the checks that were False on NumPy ints and plain dicts hold again,
and the JSON writes succeed. The behaviours the rules rest on are asserted here too, so
an upgrade of Gymnasium that changes them fails this file first.
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path
from types import ModuleType, SimpleNamespace

import gymnasium
import numpy as np
import pytest
from gymnasium import spaces

from tests.fixture_cases import RULE_FIXTURES


def _load(path: Path) -> ModuleType:
    spec = importlib.util.spec_from_file_location(path.stem.replace(".", "_"), path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_behaviours_the_rules_rest_on() -> None:
    discrete = spaces.Discrete(3)
    assert type(discrete.n) is np.int64 and type(discrete.sample()) is np.int64  # GM903
    with pytest.raises(TypeError):
        json.dumps(discrete.n)
    assert type(spaces.Dict({"a": discrete}).sample()) is dict  # GM905
    assert type(spaces.Tuple([discrete]).sample()) is tuple
    for build in (lambda: spaces.MultiBinary(0), lambda: spaces.Discrete(0)):  # GM909
        with pytest.raises(ValueError):
            build()
    with pytest.raises(TypeError):
        spaces.Discrete(4.0)  # type: ignore[arg-type]
    assert spaces.MultiDiscrete([]).shape == (0,)  # still builds: no rule
    assert spaces.Box(0, 1, (2,), np.float32) != spaces.Box(0, 1, (2,), np.float64)  # GM910


def test_migrated_int_checks_and_json_run() -> None:
    module = _load(RULE_FIXTURES / "GM903" / "space_ints.expected.py")
    env = gymnasium.make("CartPole-v1")
    assert module.check(env) is True
    assert json.loads(module.GridEnv().describe()) == {"actions": 4}


def test_migrated_dict_checks_run() -> None:
    module = _load(RULE_FIXTURES / "GM905" / "dict_sample.expected.py")
    env = SimpleNamespace(observation_space=spaces.Dict({"x": spaces.Discrete(2)}))
    assert set(module.check(env)) == {"position", "goal"}


def test_box_bounds_reported_are_exactly_those_gymnasium_rejects() -> None:
    """GM909 on Box: every literal Box of the fixture runs; the lines reported raise and
    the others build."""
    from gymmigrate.engine import transform_source

    path = RULE_FIXTURES / "GM909" / "box_bounds_outside_dtype.py"
    source = path.read_bytes()
    reported = {f.line for f in transform_source(source, str(path)).findings if f.rule == "GM909"}
    namespace: dict = {"gym": gymnasium, "np": np, "spaces": spaces}
    for number, line in enumerate(source.decode().splitlines(), 1):
        if "Box(" not in line:
            continue
        statement = line.split("#")[0].strip()
        if number in reported:
            with pytest.raises(ValueError, match="out of bounds of the dtype range"):
                exec(statement, namespace)
        else:
            exec(statement, namespace)
    assert len(reported) == 3


def test_box_bound_items_say_what_gym_built() -> None:
    """GM909 names the bound gym 0.26 built (the literal cast into the dtype, as NumPy wraps
    it) and, where the cast bounds cross, says that no Gymnasium space reproduces them:
    Gymnasium 1.x rejects low > high too."""
    from gymmigrate.engine import transform_source

    path = RULE_FIXTURES / "GM909" / "box_bounds_outside_dtype.py"
    messages = {f.line: f.message for f in transform_source(path.read_bytes(), str(path)).findings if f.rule == "GM909"}
    def cast(value: int, dtype: type) -> int:
        return int(np.array(value).astype(dtype))  # NumPy's wrap, what gym's np.full gave

    assert f"had low 0 above high {cast(200, np.int8)}" in messages[7]  # 0..255 itself becomes uint8 (pixel_range_int8)
    assert f"had low {cast(-1, np.uint8)} above high 10" in messages[8]
    assert "no Gymnasium space reproduces" in messages[7]
    assert f"the legacy space's high was {cast(70000, np.int16)}" in messages[9]  # 0..4464: they do not cross
    with pytest.raises(ValueError, match="low values must be less than or equal to high"):
        spaces.Box(np.zeros(2, np.int8), np.full(2, -1, np.int8), dtype=np.int8)
