"""Custom Env subclasses and np_random (custom_env.py, rng.py), end to end.

The acceptance envs under ``fixtures/envs/`` are look-alikes of gym 0.21's classic-control
and toy-text envs (``def seed`` with ``seeding.np_random``, RandomState calls, four-value
step, ``render(self, mode="human")``, old metadata keys). After the whole pipeline each
must pass Gymnasium's ``check_env``, run under ``gymnasium.make`` through a registered id,
and be deterministic for a seed.
"""

from __future__ import annotations

import ast
import itertools
import types
import warnings

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from gymmigrate.engine import transform_source
from gymmigrate.findings import FixKind
from tests.fixture_cases import FIXTURES

ENV_FIXTURES = FIXTURES / "envs"
ACCEPTANCE = [
    ("pole_balance", "PoleBalanceEnv"),
    ("hill_climb", "HillClimbEnv"),
    ("ice_grid", "IceGridEnv"),
    ("gym09_chain", "ChainWalkEnv"),  # gym <= 0.9: _step/_reset/_seed/_render, forwarding methods
]
_ids = itertools.count()


def _migrate(name: str) -> str:
    source = ENV_FIXTURES / f"{name}.py"
    return transform_source(source.read_bytes(), str(source)).rewritten.decode()


def _load_class(code: str, name: str, class_name: str) -> type:
    module = types.ModuleType(f"migrated_{name}_{next(_ids)}")
    exec(compile(code, f"<migrated {name}>", "exec"), module.__dict__)
    return getattr(module, class_name)


def _register(env_class: type) -> str:
    env_id = f"GymmigrateTest/{env_class.__name__}{next(_ids)}-v0"
    gymnasium.register(id=env_id, entry_point=env_class, max_episode_steps=40)
    return env_id


@pytest.fixture(scope="module", params=ACCEPTANCE, ids=[name for name, _ in ACCEPTANCE])
def migrated(request: pytest.FixtureRequest) -> tuple[str, type]:
    name, class_name = request.param
    return name, _load_class(_migrate(name), name, class_name)


@pytest.mark.parametrize("name", [name for name, _ in ACCEPTANCE])
def test_acceptance_output_is_exact(name: str) -> None:
    source = ENV_FIXTURES / f"{name}.py"
    expected = (ENV_FIXTURES / f"{name}.expected.py").read_text(encoding="utf-8")
    result = transform_source(source.read_bytes(), str(source))
    assert result.rewritten.decode() == expected
    ast.parse(expected)
    assert transform_source(expected.encode(), "again.py").rewritten.decode() == expected
    rows = sorted((f.line, f.rule, f.kind.value) for f in result.findings)
    listed = sorted(
        (int(line), rule, kind)
        for line, rule, kind in (row.split() for row in (ENV_FIXTURES / f"{name}.findings").read_text().splitlines() if row.strip())
    )
    assert rows == listed


def test_migrated_env_passes_check_env(migrated: tuple[str, type]) -> None:
    _, env_class = migrated
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env_class())
    # Without a spec the checker cannot try the other render modes; nothing else may warn.
    assert [w for w in caught if "not having a spec" not in str(w.message)] == []


def test_migrated_env_runs_under_make(migrated: tuple[str, type]) -> None:
    _, env_class = migrated
    env = gymnasium.make(_register(env_class))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env.unwrapped)
    assert [str(w.message) for w in caught] == []
    obs, info = env.reset(seed=11)
    assert obs in env.observation_space and isinstance(info, dict)
    for _ in range(60):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert isinstance(terminated, bool) and isinstance(truncated, bool)
        if terminated or truncated:
            break
    assert terminated or truncated, "TimeLimit(40) or the task must end the episode"
    env.close()


def test_migrated_env_is_deterministic_for_a_seed(migrated: tuple[str, type]) -> None:
    _, env_class = migrated
    env_id = _register(env_class)
    first = gymnasium.make(env_id).reset(seed=1234)[0]
    second = gymnasium.make(env_id).reset(seed=1234)[0]
    assert np.array_equal(first, second)
    env = gymnasium.make(env_id)
    env.reset(seed=5)
    env.action_space.seed(5)
    run_a = [env.step(env.action_space.sample())[0] for _ in range(3)]
    env.reset(seed=5)
    env.action_space.seed(5)
    run_b = [env.step(env.action_space.sample())[0] for _ in range(3)]
    assert all(np.array_equal(a, b) for a, b in zip(run_a, run_b))


def test_migrated_env_renders_through_make(migrated: tuple[str, type], capsys: pytest.CaptureFixture[str]) -> None:
    _, env_class = migrated
    env_id = _register(env_class)
    for mode in env_class.metadata["render_modes"]:
        env = gymnasium.make(env_id, render_mode=mode)
        env.reset(seed=0)
        frame = env.render()
        if mode == "rgb_array":
            assert isinstance(frame, np.ndarray) and frame.ndim == 3
        elif mode == "ansi":
            assert isinstance(frame, str) and frame
        env.close()
    unrendered = gymnasium.make(env_id)
    unrendered.reset(seed=0)
    assert unrendered.render() is None


def test_gym09_script_builds_the_local_class_and_renders_as_text() -> None:
    """``ChainWalkEnv()`` then ``render(mode="ansi")``: the class is the creation site."""
    namespace: dict[str, object] = {}
    exec(compile(_migrate("gym09_chain"), "<migrated gym09_chain>", "exec"), namespace)
    frames = namespace["demo"]()  # type: ignore[operator]
    assert frames and all(isinstance(f, str) and len(f) == 6 and f.count("o") == 1 for f in frames)


@pytest.mark.filterwarnings("ignore")
def test_legacy_source_would_fail_under_gymnasium() -> None:
    """The unmigrated class (gym swapped for gymnasium by hand) breaks where the issue says."""
    code = (ENV_FIXTURES / "pole_balance.py").read_text().replace("import gym\n", "import gymnasium as gym\n")
    code = code.replace("from gym ", "from gymnasium ").replace("from gym.", "from gymnasium.")
    env_class = _load_class(code, "legacy", "PoleBalanceEnv")
    env = gymnasium.make(_register(env_class))
    with pytest.raises(TypeError, match="unexpected keyword argument 'seed'"):
        env.reset(seed=0)


# -- pieces of the rules -----------------------------------------------------------------


def _run(code: str) -> tuple[str, list[tuple[int, str, str]]]:
    result = transform_source(code.encode(), "case.py")
    return result.rewritten.decode(), sorted((f.line, f.rule, f.kind.value) for f in result.findings)


@pytest.mark.parametrize(
    ("done", "terminated", "truncated"),
    [
        ("bool(x > 1 or self.steps >= self.max_steps)", "bool(x > 1)", "bool(self.steps >= self.max_steps)"),
        ("self.t >= 200", "False", "bool(self.t >= 200)"),
        ("self.elapsed_steps > self.limit or self.crashed", "bool(self.crashed)", "bool(self.elapsed_steps > self.limit)"),
    ],
)
def test_step_limit_becomes_truncated(done: str, terminated: str, truncated: str) -> None:
    code = f"import gymnasium as gym\n\nclass E(gym.Env):\n    def step(self, a):\n        done = {done}\n        return 0, 0.0, done, {{}}\n"
    out, findings = _run(code)
    assert f"terminated = {terminated}\n" in out
    assert f"truncated = {truncated}\n" in out
    assert "return 0, 0.0, terminated, truncated, {}" in out
    assert findings == [(6, "GM504", "assist")]


def test_cartpole_steps_beyond_done_is_not_a_step_limit() -> None:
    code = (
        "import gymnasium as gym\n\nclass E(gym.Env):\n    def step(self, a):\n"
        "        done = self.x > 2 or self.steps_beyond_done == 0\n        return 0, 0.0, done, {}\n"
    )
    out, _ = _run(code)
    assert "return 0, 0.0, terminated, False, {}" in out
    assert "terminated = bool(self.x > 2 or self.steps_beyond_done == 0)" in out


def test_wrapper_classes_are_left_to_the_wrapper_rules() -> None:
    code = (
        "import gymnasium as gym\n\nclass W(gym.Wrapper):\n    metadata = {}\n"
        "    def render(self, mode='human'):\n        return self.env.render()\n"
    )
    out, findings = _run(code)
    assert "def render(self, mode='human')" in out
    assert not [f for f in findings if f[1] in ("GM405", "GM501", "GM503", "GM504")]


def test_sb3_vec_env_rng_is_never_touched() -> None:
    code = (
        "from stable_baselines3.common.vec_env import DummyVecEnv\n"
        "venv = DummyVecEnv([lambda: None])\nx = venv.np_random.randint(3)\n"
    )
    out, findings = _run(code)
    assert out == code and findings == []


@pytest.mark.parametrize(
    ("legacy", "modern"),
    [
        ("rand(2, 3)", "random((2, 3))"),
        ("randn(4)", "standard_normal(4)"),
        ("random_integers(5)", "integers(1, 5, endpoint=True)"),
        ("random_integers(2, 4, size=3)", "integers(2, 4, size=3, endpoint=True)"),
        ("randint(0, 10, size=(2,))", "integers(0, 10, size=(2,))"),
        ("random_sample((2,))", "random((2,))"),
    ],
)
def test_generator_mapping_keeps_shapes_and_ranges(legacy: str, modern: str) -> None:
    code = f"from gymnasium.utils import seeding\n\nrng, _ = seeding.np_random(0)\nvalue = rng.{legacy}\n"
    out, _ = _run(code)
    assert f"value = rng.{modern}\n" in out
    new_value = eval(f"rng.{modern}", {"rng": np.random.default_rng(0)})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)  # random_integers
        old_value = eval(f"r.{legacy}", {"r": np.random.RandomState(0)})
    assert np.shape(old_value) == np.shape(new_value)
    assert np.asarray(new_value).dtype.kind == np.asarray(old_value).dtype.kind


def test_random_integers_bounds_are_inclusive() -> None:
    rng = np.random.default_rng(0)
    draws = set(rng.integers(1, 3, size=500, endpoint=True).tolist())
    assert draws == {1, 2, 3}


def test_pcg64_note_once_per_file() -> None:
    code = (
        "import gymnasium as gym\n\nclass E(gym.Env):\n    def a(self):\n        return self.np_random.randint(2)\n"
        "    def b(self):\n        return self.np_random.rand()\n"
    )
    _, findings = _run(code)
    assert [f for f in findings if f[2] == FixKind.FLAG.value] == [(5, "GM505", "flag")]


# -- every combination of legacy features still yields a valid Gymnasium env ----------------

_SEEDS = {
    "canonical": "    def seed(self, seed=None):\n        self.np_random, seed = seeding.np_random(seed)\n        return [seed]\n",
    "space_too": (
        "    def seed(self, seed=None):\n        self.np_random, seed = seeding.np_random(seed)\n"
        "        self.action_space.seed(seed)\n        return [seed]\n"
    ),
    "none": "",
}
_RESETS = {
    "v021": "    def reset(self):\n        self.t = 0\n        self.x = self.np_random.uniform(-0.5, 0.5)\n        return self._obs()\n",
    "v022": (
        "    def reset(self, seed=None, return_info=False, options=None):\n        super().reset(seed=seed)\n"
        "        self.t = 0\n        self.x = self.np_random.uniform(-0.5, 0.5)\n"
        "        if not return_info:\n            return self._obs()\n        else:\n            return self._obs(), {}\n"
    ),
}
_DONES = {
    "with_limit": "        done = bool(abs(self.x) > 1.0 or self.t >= self.limit)\n",
    "task_only": "        done = abs(self.x) > 1.0\n",
}
_RENDERS = {
    "mode": "    def render(self, mode='human'):\n        return np.zeros((4, 4, 3), dtype=np.uint8) if mode == 'rgb_array' else None\n",
    "none": "",
}


def _legacy_env(seed: str, reset: str, done: str, render: str) -> str:
    return (
        "import gym\nimport numpy as np\nfrom gym import spaces\nfrom gym.utils import seeding\n\n\n"
        "class WalkEnv(gym.Env):\n"
        "    metadata = {'render.modes': ['human', 'rgb_array'], 'video.frames_per_second': 20}\n\n"
        "    def __init__(self, limit=30):\n        self.limit = limit\n"
        "        self.observation_space = spaces.Box(-2.0, 2.0, shape=(1,), dtype=np.float32)\n"
        "        self.action_space = spaces.Discrete(2)\n"
        + ("        self.seed()\n" if _SEEDS[seed] else "")
        + "\n    def _obs(self):\n        return np.array([self.x], dtype=np.float32)\n\n"
        + (_SEEDS[seed] + "\n" if _SEEDS[seed] else "")
        + _RESETS[reset]
        + "\n    def step(self, action):\n        self.t += 1\n"
        "        self.x += 0.1 if action == 1 else -0.1 + 0.01 * self.np_random.randn()\n"
        + _DONES[done]
        + "        return self._obs(), 1.0, done, {}\n"
        + ("\n" + _RENDERS[render] if _RENDERS[render] else "")
    )


@pytest.mark.parametrize(
    ("seed", "reset", "done", "render"),
    list(itertools.product(_SEEDS, _RESETS, _DONES, _RENDERS)),
)
def test_legacy_feature_combinations_pass_check_env(seed: str, reset: str, done: str, render: str) -> None:
    code = _legacy_env(seed, reset, done, render)
    result = transform_source(code.encode(), "walk.py")
    migrated = result.rewritten.decode()
    assert transform_source(result.rewritten, "walk.py").rewritten == result.rewritten
    env_class = _load_class(migrated, "walk", "WalkEnv")
    env = gymnasium.make(_register(env_class))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env.unwrapped, skip_render_check=not _RENDERS[render])
    assert [str(w.message) for w in caught] == []
    assert np.array_equal(env.reset(seed=9)[0], env.reset(seed=9)[0])


def test_a_gym_026_reset_that_returns_the_pair_is_not_paired_again() -> None:
    """fixtures/rules/GM501/reset_already_pair: only the signature changes; the migrated
    env resets to (obs, info) with a bare array observation and passes check_env."""
    from pathlib import Path

    from gymnasium.utils.env_checker import check_env

    expected = Path(__file__).resolve().parent.parent / "fixtures" / "rules" / "GM501" / "reset_already_pair.expected.py"
    namespace: dict[str, object] = {}
    exec(compile(expected.read_text(), str(expected), "exec"), namespace)
    env = namespace["Treasure"]()
    obs, info = env.reset(seed=0)
    assert obs.shape == (2,) and info == {}
    check_env(env, skip_render_check=True)


def test_helper_returns_split_by_node_not_by_a_reused_id() -> None:
    """The step rebuild splits ``return self._observe()`` into a four-value unpack and a
    five-value return; each split Return is replaced, which frees its id. A later bare
    ``return`` could be allocated at that address and be taken for it (an AssertionError on
    some runs of the same input, not others). Many alternating returns make the reuse likely."""
    import libcst as cst

    from gymmigrate.rules.custom_env.cst_edits import _HelperReturnUnpacker, visit_suite

    branches = "".join(
        f"    if c == {i}:\n        return self._observe()\n    if d == {i}:\n        return\n" for i in range(300)
    )
    function = cst.parse_module("def step(self, a):\n" + branches).body[0]
    assert isinstance(function, cst.FunctionDef)
    positions = {2 * i: ("obs", "reward", "done", "info") for i in range(300)}
    for _ in range(10):
        body = visit_suite(function.body, _HelperReturnUnpacker(positions))
        code = cst.Module(body=[function.with_changes(body=body)]).code
        assert code.count("return obs, reward, done, False, info") == 300
        assert code.count("        return\n") == 300
