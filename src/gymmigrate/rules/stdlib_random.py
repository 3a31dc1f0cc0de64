"""GM510: env methods that draw from Python's global ``random``, in a run that checks envs.

Gymnasium's contract is that ``reset(seed=s)`` makes what follows reproducible: the env
draws from ``self.np_random``, which ``super().reset(seed=seed)`` seeds. A method of an env
class that draws from the standard library's global ``random`` module is not seeded by it.
That is no change from Gym (``env.seed(s)`` never seeded ``random`` either; the project's
own ``random.seed`` governs those draws, on Gym as on Gymnasium), so the draws are left
alone and not reported, except where the run imports ``check_env``: Gymnasium 1.x's
checker fails such an env ("Deterministic step rewards are not equivalent for the same
seed and action"), where gym 0.26's did not look.

There (a module of the run, or the file itself, imports Gym's or Gymnasium's
``check_env``):

* ``random.random()`` -> ``self.np_random.random()`` and ``random.uniform(a, b)`` ->
  ``self.np_random.uniform(a, b)`` (ASSIST: a different stream, seeded by
  ``reset(seed=...)`` and no longer by the project's ``random.seed``; a program that
  reseeds the env at every episode now replays the same draws in each).
* Other draws (``randint``, ``choice``, ``shuffle``, ``gauss``...) differ in their
  Generator spelling (``integers`` excludes the high end, ``choice`` of a list of tuples
  returns an array): reported once per class.

Moving the draws elsewhere would change the legacy program: a run that seeds ``random``
once and the env never loses its reproducibility, and one that calls ``env.seed(s)``
before every episode (GM203 makes that ``reset(seed=s)``) would repeat each episode's
draws.

Only methods of Gym env classes (not wrappers, whose draws are their own), with ``self``.

Source: Gymnasium 1.4 ``core.py`` (``Env.np_random``, ``Env.reset``) and
``utils/env_checker.py`` (``check_step_determinism``).
"""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.env_classes import EnvClasses
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts
from gymmigrate.facts.project_imports import imports_env_checker
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext, Rule, RuleFamily

RULES = (
    Rule(
        "GM510",
        "stdlib random in env methods",
        FixKind.ASSIST,
        "Where the run calls `check_env`, `random.random()` / `random.uniform()` in an env's methods draw from `self.np_random`, which `reset(seed=...)` seeds.",
    ),
)

_SAME_DRAW = frozenset({"random", "uniform"})
_OTHER_DRAWS = frozenset(
    {"randint", "randrange", "choice", "choices", "shuffle", "sample", "gauss", "normalvariate", "triangular",
     "betavariate", "expovariate", "gammavariate", "lognormvariate", "vonmisesvariate", "paretovariate", "weibullvariate"}
)


class StdlibRandom(RuleFamily):
    RULES = RULES

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        return "random" in facts.text and (context.profile.imports_gym or context.profile.imports_gymnasium)

    def decide(self) -> None:
        if not self._checks_envs():
            return  # the draws stay on the global stream, as on Gym: nothing changes
        self.env = EnvClasses.of(self.facts, self.receivers)
        flagged: set[int] = set()
        calls = [c for name in (*_SAME_DRAW, *_OTHER_DRAWS) for c in (*self.facts.attribute_calls.get(name, ()), *self.facts.calls_by_name.get(name, ()))]
        calls.sort(key=lambda c: (c.lineno, c.col_offset))
        for call in calls:
            qualified = self.facts.qualified_names(call.func)
            if len(qualified) != 1:
                continue
            module, _, draw = next(iter(qualified)).rpartition(".")
            if module != "random":
                continue
            classdef = self._env_class_with_self(call)
            if classdef is None:
                continue
            if draw in _SAME_DRAW:
                self.report(
                    call,
                    "GM510",
                    f"`random.{draw}()` draws from Python's global generator, and Gymnasium's `check_env`, which this run "
                    f"imports, fails an env whose seeded reset does not make its steps reproducible: drawn from "
                    f"`self.np_random.{draw}` instead. The draws now follow `reset(seed=...)`, not the project's "
                    "`random.seed`: a `reset(seed=s)` before every episode replays the same draws in each (seed the "
                    "first reset only)",
                    question=("GM510", id(classdef)),
                )
                self.plan.replace(call, lambda node, draw=draw: node.with_changes(func=cst.parse_expression(f"self.np_random.{draw}")))
            elif id(classdef) not in flagged:
                flagged.add(id(classdef))
                self.report(
                    call,
                    "GM510",
                    f"`{classdef.name}` draws from Python's global `random` (`random.{draw}`), which `reset(seed=...)` does "
                    "not seed, and Gymnasium's `check_env`, which this run imports, fails it: draw from `self.np_random` "
                    "(`integers`, `choice`, `shuffle`...; mind that `integers` excludes its high end), seeded by the "
                    "first `reset(seed=...)` only",
                    FixKind.FLAG,
                    question=("GM510", id(classdef)),
                )

    def _checks_envs(self) -> bool:
        """The file or a module of the run imports Gym's or Gymnasium's ``check_env``, or
        calls it through its module (``gym.utils.env_checker.check_env(env)``)."""
        project = self.receivers.project
        if project is not None and project.checks_envs():
            return True
        if any(imports_env_checker(q) for q in self.facts.imports.values()):
            return True
        calls = (*self.facts.attribute_calls.get("check_env", ()), *self.facts.calls_by_name.get("check_env", ()))
        return any(imports_env_checker(q) for call in calls for q in self.facts.qualified_names(call.func))

    def _env_class_with_self(self, call: ast.Call) -> ast.ClassDef | None:
        """The Gym env class (not a wrapper) whose method, taking ``self``, holds ``call``."""
        method = self.facts.enclosing_function(call)
        while method is not None and not isinstance(self.facts.parent(method), ast.ClassDef):
            method = self.facts.enclosing_function(method)
        if method is None or not isinstance(method, FUNCTIONS):
            return None
        classdef = self.facts.parent(method)
        assert isinstance(classdef, ast.ClassDef)
        args = method.args.args
        if not args or args[0].arg != "self" or method.decorator_list:
            return None
        if self.receivers.is_gym_wrapper_class(classdef):
            return None
        if self.receivers.class_kind(classdef) is EnvKind.GYM_ENV or self.env.is_custom_env(classdef):
            return classdef
        return None
