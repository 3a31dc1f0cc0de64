"""The catalog entries of the reset and seeding family (GM201-GM208, GM704)."""

from __future__ import annotations

from gymmigrate.findings import FixKind
from gymmigrate.rules.base import Rule

RULES = (
    Rule(
        "GM201",
        "reset() returns (obs, info)",
        FixKind.AUTO,
        "`obs = env.reset()` becomes `obs, info = env.reset()`; `env.reset()[0]` where it is used as a value.",
    ),
    Rule(
        "GM202",
        "return_info= removed",
        FixKind.AUTO,
        "The gym 0.22-0.25 `return_info=` keyword of `reset()` is dropped and the unpack fixed.",
    ),
    Rule(
        "GM203",
        "env.seed() removed",
        FixKind.ASSIST,
        "`env.seed(s)` becomes `env.reset(seed=s)` in place, or is merged into the reset that follows it.",
    ),
    Rule(
        "GM204",
        "seed the first reset only",
        FixKind.FLAG,
        "A reset with the same seed on every loop iteration is reported; `--seed N` seeds unseeded envs once.",
    ),
    Rule(
        "GM205",
        "space seeding",
        FixKind.FLAG,
        "`space.seed(s)` is kept; subscripts of its result (an int or a dict now) are reported.",
    ),
    Rule(
        "GM206",
        "seeds must be Python ints",
        FixKind.ASSIST,
        "numpy seeds (`np.random.randint(...)`, `rng.integers(...)`, array elements) are wrapped in `int(...)`.",
    ),
    Rule(
        "GM207",
        "custom reset keywords",
        FixKind.FLAG,
        "Arguments other than seed=/options= passed to `reset()` are reported: they belong in `options={...}`. "
        "Where an env class of the run takes such keywords and the run's wrappers or callers pass them, they move "
        "into `options` at every site (the env's and wrappers' resets read them from there), or at none.",
    ),
    Rule(
        "GM208",
        "vector env seed()",
        FixKind.AUTO,
        "`envs.seed(s)` on a Gym vector env becomes `envs.reset(seed=s)`.",
    ),
    Rule(
        "GM704",
        "vector reset returns (obs, infos)",
        FixKind.AUTO,
        "`obs = envs.reset()` on a Gym vector env becomes `obs, infos = envs.reset()`.",
    ),
)
