"""PettingZoo 1.21 split ``dones`` by meaning: after migration, a catch is a termination and a
match called off at ``max_cycles`` a truncation.

The fixtures (``fixtures/rules/PZ104/tag_*.py``, ``PZ108/tag_*.py``) are games of tag written
against the 1.20 API (``dones``, ``env.seed``, four dicts from a parallel ``step``, a
four-value ``last()``), each ending its episodes both ways in a different legacy pattern.
Each is migrated by the engine and played on PettingZoo 1.27 over seeded episodes; the
test decides what each episode meant from what the players saw (the last gap between
chaser and runner, 0 for a catch, and the number of cycles), never from the flags, and
checks the flags against it. A catch on the last cycle is a termination: an agent that
terminated on a step is not also truncated.
"""

from __future__ import annotations

import json
import random
import types
import warnings
from collections import Counter
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gymmigrate.cli import app
from gymmigrate.engine import transform_source

pytest.importorskip("pettingzoo")
from pettingzoo.test import api_test, parallel_api_test  # noqa: E402

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures" / "rules"
AEC = ["PZ108/tag_separate_stores.py", "PZ108/tag_limit_in_helper.py", "PZ108/tag_if_limit_sets_all.py"]
PARALLEL = ["PZ104/tag_or_limit.py", "PZ104/tag_item_stores.py"]
SEEDS = range(60)
MAX_CYCLES = 8  # the fixtures' default


def migrated_source(fixture: str) -> bytes:
    path = FIXTURES / fixture
    result = transform_source(path.read_bytes(), str(path))
    assert result.changed
    return result.rewritten


def migrated(fixture: str) -> types.ModuleType:
    module = types.ModuleType(fixture.replace("/", "_")[:-3])
    exec(compile(migrated_source(fixture), fixture, "exec"), module.__dict__)
    return module


@pytest.fixture(autouse=True)
def quiet_deprecations():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        yield


def meant(cycles: int, gap: int) -> str:
    """What the legacy program meant by an episode's end, from what its players saw."""
    if gap == 0:
        return "terminated"  # the chaser caught the runner (on the last cycle too)
    assert cycles == MAX_CYCLES, "an episode without a catch only ends at max_cycles"
    return "truncated"


def play_aec(module: types.ModuleType, seed: int) -> tuple[int, int, dict[str, str]]:
    """The fixture's own seeded policy, on the 1.27 API: cycles, last gap, each agent's ending."""
    env = module.TagEnv()
    env.reset(seed=seed)
    rng = random.Random(seed)
    cycles, ended = 0, {}
    for agent in env.agent_iter():
        observation, reward, termination, truncation, info = env.last()
        assert not (termination and truncation)
        if termination or truncation:
            ended[agent] = "terminated" if termination else "truncated"
            action = None
        else:
            action = rng.randrange(3)
            cycles += agent == "runner"
        env.step(action)
    return cycles, int(observation), ended


def play_parallel(module: types.ModuleType, seed: int) -> tuple[int, int, dict[str, str]]:
    env = module.TagEnv()
    observations, infos = env.reset(seed=seed)
    rng = random.Random(seed)
    cycles, ended = 0, {}
    while env.agents:
        actions = {agent: rng.randrange(3) for agent in env.agents}
        observations, rewards, terminations, truncations, infos = env.step(actions)
        cycles += 1
        for agent in terminations:
            assert not (terminations[agent] and truncations[agent])
            if terminations[agent] or truncations[agent]:
                ended[agent] = "terminated" if terminations[agent] else "truncated"
    return cycles, int(observations["runner"]), ended


@pytest.mark.parametrize("fixture", AEC + PARALLEL)
def test_endings_after_migration_mean_what_the_legacy_game_meant(fixture: str) -> None:
    module = migrated(fixture)
    play = play_aec if fixture in AEC else play_parallel
    expected: Counter[str] = Counter()
    counted: Counter[str] = Counter()
    for seed in SEEDS:
        cycles, gap, ended = play(module, seed)
        assert (cycles, gap) == module.play(seed)  # the fixture's own driver, migrated, saw the same game
        assert set(ended) == {"chaser", "runner"}
        expected[meant(cycles, gap)] += 1
        for agent, how in ended.items():
            assert how == meant(cycles, gap), (seed, agent)
        counted[ended["runner"]] += 1
    assert counted == expected
    # The seeds end both ways, and some catches fall on the last cycle (precedence matters).
    assert expected["terminated"] > 0 and expected["truncated"] > 0


def test_the_seeded_episodes_cover_both_endings_and_late_catches() -> None:
    module = migrated("PZ104/tag_or_limit.py")
    games = [module.play(seed) for seed in SEEDS]
    hit_limit = sum(cycles == MAX_CYCLES for cycles, _ in games)
    caught_at_limit = sum(cycles == MAX_CYCLES and gap == 0 for cycles, gap in games)
    truncated = sum(play_parallel(module, seed)[2]["runner"] == "truncated" for seed in SEEDS)
    assert truncated == hit_limit - caught_at_limit
    assert caught_at_limit > 0 and truncated > 0


@pytest.mark.parametrize("fixture", AEC)
def test_migrated_aec_tag_passes_the_api_test(fixture: str) -> None:
    api_test(migrated(fixture).TagEnv(), num_cycles=40)


@pytest.mark.parametrize("fixture", PARALLEL)
def test_migrated_parallel_tag_passes_the_parallel_api_test(fixture: str) -> None:
    parallel_api_test(migrated(fixture).TagEnv(), num_cycles=40)


@pytest.mark.parametrize("fixture", ["PZ108/tag_if_limit_sets_all.py", "PZ104/tag_or_limit.py"])
def test_smoke_counts_called_off_matches_as_truncations(tmp_path: Path, fixture: str) -> None:
    """``gymmigrate smoke`` on the migrated env: per agent, terminations and truncations
    apart; an episode is a truncation exactly when nobody was caught (return 0: only the
    chaser scores, and only for a catch) and then it ran to ``max_cycles``."""
    target = tmp_path / "tag_env.py"
    target.write_bytes(migrated_source(fixture))
    evidence = tmp_path / "evidence.json"
    result = CliRunner().invoke(app, ["smoke", f"{target}:TagEnv", "--seed", "1", "--episodes", "12",
                                      "--evidence", str(evidence)])
    assert result.exit_code == 0, result.stderr
    env = json.loads(evidence.read_text(encoding="utf-8"))["envs"][0]
    episodes = env["episodes"]
    assert len(episodes) == 12
    called_off = [e for e in episodes if e["return"] == 0]
    assert {e["ending"] for e in called_off} <= {"truncated"}
    assert {e["ending"] for e in episodes if e["return"] != 0} <= {"terminated"}
    assert 0 < len(called_off) < len(episodes)  # these seeds end both ways
    # every called-off match ran the full length, the longest any episode ran
    assert {e["length"] for e in called_off} == {max(e["length"] for e in episodes)}
    for agent in ("chaser", "runner"):
        assert env["agent_counts"][agent] == {"terminated": len(episodes) - len(called_off), "truncated": len(called_off)}
