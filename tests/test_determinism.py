"""Findings and rewrites do not depend on the interpreter's hash seed.

A message once named the first of a set of conditions, so the same file gave a different
GM402 text from one run to the next; runs in one process family share a hash seed and
never showed it. Two seeds over every rule fixture and the notebooks catch that class."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures"


def _outputs(tmp_path: Path, *args: str) -> list[tuple[str, str]]:
    """What ``gymmigrate ARGS --report`` prints and reports under hash seeds 1 and 2, the two
    runs side by side (one core each: the whole fixture tree is the suite's longest run)."""
    runs = [
        (
            subprocess.Popen(
                [sys.executable, "-m", "gymmigrate", *args, "--report", str(tmp_path / f"seed{seed}.json")],
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                text=True,
                env={**os.environ, "PYTHONHASHSEED": seed},
            ),
            tmp_path / f"seed{seed}.json",
        )
        for seed in ("1", "2")
    ]
    outputs = []
    for run, report in runs:
        stdout, stderr = run.communicate()
        assert run.returncode in (0, 1), stderr
        outputs.append((stdout, report.read_text(encoding="utf-8")))
    return outputs


def test_findings_and_diff_are_the_same_under_two_hash_seeds(tmp_path: Path) -> None:
    """One ``rewrite --diff --report`` per seed: the report holds every finding with its
    message (what ``check`` prints, decided by the same plan), the diff every edit."""
    paths = [str(FIXTURES / "rules"), str(FIXTURES / "notebooks")]
    first, second = _outputs(tmp_path, "rewrite", "--diff", *paths)
    assert first[1] == second[1], "the findings differ between hash seeds"
    assert first[0] == second[0], "the diff differs between hash seeds"
