"""Child side of a script smoke check: ``python -m gymmigrate.smoke.bootstrap CONFIG SCRIPT [ARGS...]``.

Runs SCRIPT as ``__main__`` (as ``python SCRIPT ARGS`` would: same argv, the script's
folder first on sys.path) with the observer installed, after seeding Python's
``random`` and NumPy's global RNG with the seed. However the script ends (it returns,
calls sys.exit, raises, spends the budget, or the parent sends SIGTERM at the timeout)
the observations are written as JSON to the path named in CONFIG; the parent reads
that file, so this process always exits 0 unless it is killed.
"""

from __future__ import annotations

import json
import os
import random
import runpy
import signal
import sys
import sysconfig
import time
import traceback
from pathlib import Path

import gymmigrate
from gymmigrate.smoke.evidence import records_to_json
from gymmigrate.smoke.multi_agent_probe import MultiAgentObserver
from gymmigrate.smoke.probe import Budget, Observatory, SmokeStop, SmokeTimeout
from gymmigrate.smoke.targets import describe_exception


def main(argv: list[str]) -> int:
    config = json.loads(Path(argv[0]).read_text(encoding="utf-8"))
    script, script_args = argv[1], argv[2:]
    output = Path(config["output"])
    started = time.perf_counter()

    import numpy as np

    seed = config["seed"]
    random.seed(seed)
    np.random.seed(seed)
    observatory = Observatory(seed, Budget(config["episodes"], config["max_steps"]), inject_seed=True)
    agents = MultiAgentObserver(observatory)  # PettingZoo envs, if the script imports PettingZoo

    def on_term(signum: int, frame: object) -> None:
        raise SmokeTimeout("stopped at the timeout")

    signal.signal(signal.SIGTERM, on_term)
    sys.argv = [script, *script_args]
    sys.path[0] = str(Path(script).resolve().parent)
    stopped_by, error = "finished", None
    try:
        observatory.install()
        agents.install()
        try:
            runpy.run_path(script, run_name="__main__")
        finally:
            agents.uninstall()
            observatory.uninstall()
    except SmokeStop:
        stopped_by = "budget"
    except SmokeTimeout:
        stopped_by = "timeout"
    except SystemExit as exc:
        if exc.code not in (None, 0):
            stopped_by, error = "error", f"the script exited with sys.exit({exc.code!r})"
    except BaseException as exc:  # the script's own crash: report it, do not re-raise
        stopped_by, error = "error", _describe_crash(exc, script) + agents.crash_hint(exc)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    record = observatory.record(stopped_by, error, seconds=time.perf_counter() - started)
    temporary = output.with_suffix(".tmp")
    temporary.write_text(json.dumps(records_to_json(record)), encoding="utf-8")
    os.replace(temporary, output)
    return 0


def _describe_crash(exc: BaseException, script: str) -> str:
    text = describe_exception(exc)
    frame = _user_frame(exc)
    if frame is not None:
        filename, lineno = frame
        text += f" (at {_shown(filename, script)}:{lineno})"
    return text


def _user_frame(exc: BaseException) -> tuple[str, int] | None:
    """The deepest frame of the user's code: not the stdlib, gymnasium, numpy, PettingZoo or gymmigrate."""
    import gymnasium
    import numpy

    skipped = tuple(
        str(Path(p).resolve())
        for p in (
            Path(sysconfig.get_paths()["stdlib"]),
            Path(gymnasium.__file__).parent,
            Path(numpy.__file__).parent,
            Path(gymmigrate.__file__).parent,
            *(Path(m.__file__).parent for m in [sys.modules.get("pettingzoo")] if m is not None and m.__file__),
        )
    )
    found = None
    for summary in traceback.extract_tb(exc.__traceback__):
        resolved = str(Path(summary.filename).resolve())
        if not resolved.startswith(skipped) and summary.lineno is not None:
            found = (summary.filename, summary.lineno)
    return found


def _shown(filename: str, script: str) -> str:
    path = Path(filename).resolve()
    if path == Path(script).resolve():
        return script
    try:
        return str(path.relative_to(Path.cwd()))
    except ValueError:
        return str(path)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
