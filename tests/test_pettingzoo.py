"""PZ101-PZ110 at run time: PettingZoo 1.20-style code, rewritten, runs on PettingZoo 1.27.

The fixtures under ``fixtures/rules/PZ1xx/`` are written against the pre-1.21 API
(``done`` from ``last()``, four dicts from a parallel ``step``, ``seed()``,
``self.dones``, ``_was_done_step``). Each test rewrites one with the engine and runs the
result against the installed PettingZoo: the loops play real classic envs (seeded), and
the custom envs pass PettingZoo's own conformance tests.
"""

from __future__ import annotations

import contextlib
import importlib
import subprocess
import sys
import types
import warnings
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app
from gymmigrate.engine import transform_source
from gymmigrate.rules.pettingzoo.renamed_names import RENAMED

pettingzoo = pytest.importorskip("pettingzoo")
from pettingzoo.test import api_test, parallel_api_test  # noqa: E402

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures" / "rules"


def load(source: bytes, name: str) -> types.ModuleType:
    module = types.ModuleType(name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)  # module-level creation warns on 1.27 (PZ110)
        exec(compile(source, name, "exec"), module.__dict__)
    return module


def rewritten(fixture: str) -> types.ModuleType:
    path = FIXTURES / fixture
    result = transform_source(path.read_bytes(), str(path))
    assert result.changed
    return load(result.rewritten, fixture)


@pytest.fixture(autouse=True)
def quiet_deprecations():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        yield


def test_legacy_aec_loop_fails_on_current_pettingzoo() -> None:
    legacy = load((FIXTURES / "PZ101/rps_aec_loop.py").read_bytes(), "legacy")
    with pytest.raises((ValueError, AttributeError)):
        legacy.play(seed=1)


def test_rewritten_aec_loop_plays_rock_paper_scissors_seeded() -> None:
    module = rewritten("PZ101/rps_aec_loop.py")
    first, again = module.play(seed=3), module.play(seed=3)
    assert first == again
    assert set(first) == {"player_0", "player_1"}
    assert first["player_0"] == -first["player_1"]  # zero-sum: every round was scored


def test_rewritten_tictactoe_loop_keeps_done_for_control() -> None:
    module = rewritten("PZ101/tictactoe_done_kept.py")
    moves, finished = module.play(seed=0)
    assert finished
    assert 5 <= moves <= 9  # first legal square every time: a real game to its end


def test_rewritten_connect_four_script_runs() -> None:
    module = rewritten("PZ102/dead_agent_action.py")
    assert not module.env.agents  # the loop ran until every agent was done


def test_rewritten_parallel_loop_runs_until_agents_leave() -> None:
    module = rewritten("PZ104/parallel_loop.py")
    totals, steps = module.play(seed=5, cycles=7)
    assert steps == 7  # ``while penv.agents`` stops at truncation, as ``all(dones)`` did
    assert totals == module.play(seed=5, cycles=7)[0]
    assert set(totals) == {"player_0", "player_1"}


def test_legacy_custom_aec_env_fails_the_current_api_test() -> None:
    legacy = load((FIXTURES / "PZ108/custom_aec_env.py").read_bytes().replace(b"from gym.", b"from gymnasium."), "legacy_env")
    with pytest.raises(Exception):  # noqa: B017  (any failure of the 1.27 API test: it names no one error type)
        api_test(legacy.env(), num_cycles=20)


def test_rewritten_custom_aec_env_passes_api_test() -> None:
    module = rewritten("PZ108/custom_aec_env.py")
    api_test(module.env(), num_cycles=100)
    env = module.env()
    env.reset(seed=0)
    for _agent in env.agent_iter():
        observation, reward, termination, truncation, info = env.last()
        env.step(None if termination or truncation else 0)
    assert not env.agents


def test_rewritten_custom_parallel_env_passes_parallel_api_test() -> None:
    module = rewritten("PZ108/custom_parallel_env.py")
    parallel_api_test(module.parallel_env(), num_cycles=100)
    env = module.parallel_env()
    observations, infos = env.reset(seed=4)
    first = env.np_random.integers(1 << 30)
    env.reset(seed=4)
    assert env.np_random.integers(1 << 30) == first  # ``reset(seed=)`` reaches the env's own ``seed()``


def test_cli_rewrites_a_mixed_file_in_place(tmp_path: Path) -> None:
    script = tmp_path / "mixed.py"
    script.write_bytes((FIXTURES / "PZ101/mixed_gym_and_aec.py").read_bytes())
    result = CliRunner().invoke(app, ["rewrite", str(script)])
    assert result.exit_code == 0, result.output
    assert script.read_bytes() == (FIXTURES / "PZ101/mixed_gym_and_aec.expected.py").read_bytes()
    load(script.read_bytes(), "mixed")  # the Gym loop and the AEC loop both run


def test_rewrite_and_check_never_import_pettingzoo() -> None:
    code = (
        "import sys\n"
        "from pathlib import Path\n"
        "from gymmigrate.engine import lint_source, transform_source\n"
        f"for path in sorted(Path({str(FIXTURES)!r}).glob('PZ1*/*.py')):\n"
        "    transform_source(path.read_bytes(), str(path))\n"
        "    lint_source(path.read_bytes(), str(path))\n"
        "assert 'pettingzoo' not in sys.modules and 'supersuit' not in sys.modules\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def test_the_old_spelling_of_the_parallel_wrapper_base_imports_on_pettingzoo_1_27() -> None:
    """fixtures/rules/PZ108/wrapper_old_spelling: SuperSuit's ``BaseParallelWraper``
    import is an ImportError on current PettingZoo; the migrated module imports."""
    import runpy

    expected = FIXTURES / "PZ108" / "wrapper_old_spelling.expected.py"
    namespace = runpy.run_path(str(expected))
    from pettingzoo.utils.wrappers import BaseParallelWrapper

    assert issubclass(namespace["Skip"], BaseParallelWrapper)


def test_the_old_spelling_through_pettingzoo_utils_imports_on_pettingzoo_1_27() -> None:
    """fixtures/rules/PZ108/wrapper_old_spelling_utils: the same class imported from the
    ``pettingzoo.utils`` package, which re-exports the wrappers."""
    import runpy

    legacy = FIXTURES / "PZ108" / "wrapper_old_spelling_utils.py"
    with pytest.raises(ImportError):
        runpy.run_path(str(legacy))
    namespace = runpy.run_path(str(legacy.with_suffix(".expected.py")))
    from pettingzoo.utils import BaseParallelWrapper

    assert issubclass(namespace["Repeat"], BaseParallelWrapper)


def test_every_rename_target_imports_from_pettingzoo_1_27() -> None:
    """Each name the PZ108 rename table gives is in its module on the installed
    PettingZoo, and the legacy name is gone there or only an alias that warns."""
    for module_name, names in RENAMED.items():
        module = importlib.import_module(module_name)
        for old, (new, _release) in names.items():
            exec(f"from {module_name} import {new}", {})
            legacy = getattr(module, old, None)
            if legacy is not None:  # the deprecated alias warns, naming the new name, before it converts
                with pytest.warns(UserWarning, match=new), contextlib.suppress(AttributeError):
                    legacy(None)


def test_conversions_under_their_old_names_import_on_pettingzoo_1_27() -> None:
    """fixtures/rules/PZ108/conversions_old_names: the pre-1.15 names are an ImportError on
    current PettingZoo; the migrated module binds the same names to the current objects."""
    import runpy

    from pettingzoo.utils import conversions

    legacy = FIXTURES / "PZ108" / "conversions_old_names.py"
    with pytest.raises(ImportError):
        runpy.run_path(str(legacy))
    namespace = runpy.run_path(str(legacy.with_suffix(".expected.py")))
    assert namespace["from_parallel_wrapper"] is conversions.parallel_to_aec_wrapper
    assert namespace["as_parallel"] is conversions.aec_to_parallel_wrapper
    assert namespace["from_parallel"] is conversions.parallel_to_aec


@pytest.mark.parametrize("fixture", ["PZ108/inner_game_dones.py", "PZ104/inner_game_local_dones.py"])
def test_dones_of_a_held_game_are_terminations_beside_the_cycle_limit(fixture: str) -> None:
    """fixtures/rules/PZ108/inner_game_dones, PZ104/inner_game_local_dones: the dones a
    parallel env unpacks from a track of its module that counts nothing are terminations;
    the env's own ``max_cycles`` truncates the others. The migrated env passes PettingZoo's
    parallel API test, and on the limit step a runner that crossed the line stays terminated."""
    module = rewritten(fixture)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        parallel_api_test(module.RaceEnv(), num_cycles=4)
    env = module.RaceEnv(max_cycles=3)
    env.reset(seed=0)
    for _ in range(3):
        _, _, terminations, truncations, _ = env.step({"hare": 2, "tortoise": 1})
    assert terminations == {"hare": True, "tortoise": False}
    assert truncations == {"hare": False, "tortoise": True}
    assert env.agents == []


def test_mpe_imports_moved_to_mpe2_run_on_pettingzoo_1_27() -> None:
    """fixtures/rules/PZ111/mpe_family_import: ``pettingzoo.mpe`` raises ImportError on
    PettingZoo 1.27; the migrated module imports the same envs from mpe2 and runs them."""
    import runpy

    pytest.importorskip("mpe2")
    legacy = FIXTURES / "PZ111" / "mpe_family_import.py"
    with pytest.raises(ImportError, match="MPE2"):
        runpy.run_path(str(legacy))
    namespace = runpy.run_path(str(legacy.with_suffix(".expected.py")))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        assert namespace["spread_rollout"](seed=1) == 5  # max_cycles ends it: the same as v2
        assert namespace["push_agents"]() == ["adversary_0", "agent_0"]


def test_bumped_env_raises_on_its_old_version_and_runs_on_the_new_one() -> None:
    """fixtures/rules/PZ111/bumped_with_removed_keyword: knights_archers_zombies_v10 imports
    on PettingZoo 1.27 but raises DeprecatedEnv when made; v11 runs, with the old keywords
    turned into their v11 equivalents where the value is a literal."""
    import runpy

    pytest.importorskip("pygame")
    from pettingzoo.utils.deprecated_module import DeprecatedEnv

    legacy = runpy.run_path(str(FIXTURES / "PZ111" / "bumped_with_removed_keyword.py"))
    with pytest.raises(DeprecatedEnv):
        legacy["make_default"]()
    migrated = runpy.run_path(str(FIXTURES / "PZ111" / "bumped_with_removed_keyword.expected.py"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        env = migrated["make_default"]()
        env.reset(seed=0)
        assert env.agents == ["archer_0", "archer_1", "knight_0", "knight_1"]
        with pytest.raises(TypeError, match="vector_state"):
            migrated["make"](image=False)  # reported: a computed value has no certain equivalent
        images = migrated["make_images"]()
        observations, _ = images.reset(seed=0)
        assert observations["archer_0"].shape == (512, 512, 3)  # what v10 gave for vector_state=False
        assert migrated["make_slow"](5).reset(seed=0)


def test_parallel_wrapper_reset_through_super_returns_the_pair() -> None:
    """fixtures/rules/PZ105/wrapper_super_reset: a ``BaseParallelWrapper`` subclass whose
    ``reset`` reads ``super().reset(...)`` as the observations; on PettingZoo 1.23+ that is
    the ``(observations, infos)`` pair, so the legacy wrapper fails and the migrated one runs."""
    import runpy

    from pettingzoo.classic import rps_v2

    legacy = runpy.run_path(str(FIXTURES / "PZ105" / "wrapper_super_reset.py"))
    migrated = runpy.run_path(str(FIXTURES / "PZ105" / "wrapper_super_reset.expected.py"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        with pytest.raises(AttributeError, match="items"):
            legacy["ScaleObservations"](rps_v2.parallel_env(), 2).reset(seed=0)
        env = migrated["ScaleObservations"](rps_v2.parallel_env(), 2)
        observations, infos = env.reset(seed=0)
        assert set(observations) == set(infos) == {"player_0", "player_1"}
        assert observations["player_0"] == 2 * 3  # rps starts every agent on observation 3
        parallel_api_test(migrated["ScaleObservations"](rps_v2.parallel_env(), 1), num_cycles=5)


def test_parallel_wrapper_reads_the_raw_envs_generator() -> None:
    """fixtures/rules/PZ108/parallel_wrapper_rng: ``self.np_random`` in a parallel wrapper
    reached the raw env through PettingZoo 1.21's attribute forwarding; the AEC-to-parallel
    conversion no longer forwards, so only the migrated ``self.unwrapped.np_random`` runs."""
    import runpy

    pytest.importorskip("pygame")
    from pettingzoo.butterfly import knights_archers_zombies_v11

    legacy = runpy.run_path(str(FIXTURES / "PZ108" / "parallel_wrapper_rng.py"))
    migrated = runpy.run_path(str(FIXTURES / "PZ108" / "parallel_wrapper_rng.expected.py"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        env = legacy["RandomRepeat"](knights_archers_zombies_v11.parallel_env())
        env.reset(seed=0)
        with pytest.raises(AttributeError, match="np_random"):
            env.step({agent: 0 for agent in env.agents})
        env = migrated["RandomRepeat"](knights_archers_zombies_v11.parallel_env())
        env.reset(seed=0)
        observations, *_ = env.step({agent: 0 for agent in env.agents})
        assert set(observations) == {"archer_0", "archer_1", "knight_0", "knight_1"}
