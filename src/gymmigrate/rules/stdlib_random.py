"""GM510: env methods that draw from Python's global ``random``.

Gymnasium's contract is that ``reset(seed=s)`` makes what follows reproducible: the env
draws from ``self.np_random``, which ``super().reset(seed=seed)`` seeds. A method of an
env class that draws from the standard library's global ``random`` module is not seeded
by it, and Gymnasium 1.x's ``check_env`` fails it ("Deterministic step rewards are not
equivalent for the same seed and action"), where gym 0.26's checker did not look.

* ``random.random()`` -> ``self.np_random.random()`` and ``random.uniform(a, b)`` ->
  ``self.np_random.uniform(a, b)`` (ASSIST: the same distribution from the env's own,
  seeded generator; the numbers drawn differ from the global stream's).
* Other draws (``randint``, ``choice``, ``shuffle``, ``gauss``...) differ in their
  Generator spelling (``integers`` excludes the high end, ``choice`` of a list of tuples
  returns an array): reported once per class.

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
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext, Rule, RuleFamily

RULES = (
    Rule(
        "GM510",
        "stdlib random in env methods",
        FixKind.ASSIST,
        "`random.random()` / `random.uniform()` in an env's methods draw from `self.np_random`, which `reset(seed=...)` seeds.",
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
                    f"`random.{draw}()` draws from Python's global generator, which `reset(seed=...)` does not seed: "
                    f"drawn from `self.np_random.{draw}` instead (same distribution, the env's own seeded stream)",
                )
                self.plan.replace(call, lambda node, draw=draw: node.with_changes(func=cst.parse_expression(f"self.np_random.{draw}")))
            elif id(classdef) not in flagged:
                flagged.add(id(classdef))
                self.report(
                    call,
                    "GM510",
                    f"`{classdef.name}` draws from Python's global `random` (`random.{draw}`), which `reset(seed=...)` does "
                    "not seed (Gymnasium's check_env fails it): draw from `self.np_random` (`integers`, `choice`, "
                    "`shuffle`...; mind that `integers` excludes its high end)",
                    FixKind.FLAG,
                )

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
