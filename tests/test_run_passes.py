"""How often a run migrates each file: once, whether it writes or shows a diff, on one
process or on workers; only a refused env module (whose importers must then be migrated
against the facts without its classes) costs a second pass."""

from __future__ import annotations

import shutil
from collections import Counter
from pathlib import Path

import pytest

from gymmigrate import process, runner
from gymmigrate.options import RewriteOptions
from gymmigrate.process import FileResult, Status
from gymmigrate.runner import run_files
from gymmigrate.source_text import TransformError

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures"
LEGACY = b'import gym\nenv = gym.make("CartPole-v1")\nobs = env.reset()\n'


def _pair(root: Path, scripts: int = 0) -> list[Path]:
    """envs.py (an env class play.py imports: a provider), play.py, and legacy scripts."""
    folder = root / "pair"
    shutil.copytree(FIXTURES / "project_blocked", folder)
    envs = folder / "envs.py"
    envs.write_text(envs.read_text().replace("# gymmigrate: skip-file\n", "import gym  # legacy\n"))
    extra = []
    for index in range(scripts):
        script = folder / f"script_{index:02}.py"
        script.write_bytes(LEGACY)
        extra.append(script)
    return [folder / "play.py", *extra, envs]


def _counting(monkeypatch: pytest.MonkeyPatch, refuse: str | None = None) -> Counter[str]:
    """Count the migrations of each file (in this process), refusing ``refuse``."""
    counts: Counter[str] = Counter()
    real = process.transform_source

    def counted(source: bytes, path: str = "<string>", options: RewriteOptions | None = None):  # type: ignore[no-untyped-def]
        counts[Path(path).name] += 1
        if refuse is not None and path.endswith(refuse):
            raise TransformError("the rewrite is not stable (a second run would change it again); file left unchanged")
        return real(source, path, options)

    monkeypatch.setattr(process, "transform_source", counted)
    return counts


@pytest.mark.parametrize("write", [True, False], ids=["written", "diff"])
def test_each_file_is_migrated_once(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, write: bool) -> None:
    paths = _pair(tmp_path, scripts=2)
    counts = _counting(monkeypatch)
    results = list(run_files(paths, RewriteOptions(), write=write, want_diff=not write, jobs=1))
    assert [r.path for r in results] == [str(p) for p in paths]
    assert all(r.status is Status.CHANGED for r in results)
    assert set(counts.values()) == {1}, counts
    assert all(r.written is write for r in results)
    if write:
        assert b"import gymnasium" in paths[-1].read_bytes() and b"import gymnasium" in paths[1].read_bytes()
        assert "reset(seed=3)" in paths[0].read_text(), "play.py migrated against the migrated PairEnv"


def test_a_written_provider_edited_meanwhile_is_left_as_it_is(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The provider is migrated before the others and written in its turn: an edit saved
    in between wins, as it does during any one file's rewrite."""
    paths = _pair(tmp_path)
    envs = paths[-1]
    results = run_files(paths, RewriteOptions(), write=True, want_diff=False, jobs=1)
    assert next(results).path == str(paths[0])  # envs.py is migrated (in memory) by now
    envs.write_text(envs.read_text() + "# saved by an editor\n")
    edited = envs.read_bytes()
    last = next(results)
    assert last.status is Status.ERROR and last.error is not None and last.error.startswith("not rewritten:")
    assert envs.read_bytes() == edited


@pytest.mark.parametrize("write", [True, False], ids=["written", "diff"])
def test_a_refused_provider_on_workers_answers_as_on_one_process(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, write: bool
) -> None:
    """On workers, --diff migrates the other files while the provider is checked; once it
    is refused, those results are dropped and every file runs again without its classes."""
    answers: dict[int, list[FileResult]] = {}
    for jobs in (1, 2):
        paths = _pair(tmp_path / f"jobs{jobs}", scripts=runner.PARALLEL_THRESHOLD)
        _counting(monkeypatch, refuse="envs.py")  # workers are forked: they refuse it too
        results = list(run_files(paths, RewriteOptions(), write=write, want_diff=not write, jobs=jobs))
        answers[jobs] = [FileResult(Path(r.path).name, r.status, r.findings, r.error, r.diff and "diff", r.written) for r in results]
    assert answers[1] == answers[2]
    by_name = {r.path: r for r in answers[2]}
    assert by_name["envs.py"].status is Status.ERROR
    assert by_name["play.py"].status is Status.UNCHANGED
    assert [f.rule for f in by_name["play.py"].findings if f.rule == "GM002"] == ["GM002"]
    assert by_name["script_00.py"].status is Status.CHANGED
