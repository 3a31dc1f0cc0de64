"""Method contracts follow their class: a hook migrated in a base class, migrated in its overrides.

``def step(self, a): ...; return self.post_step(a)`` makes ``post_step`` part of the step
contract: the rewrite gives its returns the five fields (``step.py``). A subclass that
overrides ``post_step`` still returns four, and its ``step()`` (the base's) then hands
four values to a Gymnasium caller that unpacks five. So a hook is followed only when
every override in the run follows with it:

* overrides in subclasses of the same module whose returns the rewrite can carry out
  (four-value literals, or ``return super().post_step(...)``) are migrated with the base;
* overrides in other modules of the run (their summaries list them, re-exports of the
  base followed: ``ProjectView.overridden_elsewhere``) are migrated with the base when the
  join found every one of them plain (facts/step_hooks.py): each module migrates its own;
* an override the rewrite cannot carry out, here or elsewhere, keeps every one of them on
  the old contract: the base's ``step`` is reported instead.

``reset`` hooks (``return self._restart()``) are never followed when overridden: the base's
``reset`` returns ``(self._restart(), {})``, right whichever override runs.
"""

from __future__ import annotations

import ast

from gymmigrate.facts.step_hooks import plain_override
from gymmigrate.rules.custom_env.common import ClassDecision, Method, local_subclasses


def overrides(decision: ClassDecision, name: str) -> tuple[list[tuple[ast.ClassDef, Method]], list[str]]:
    """The overrides of method ``name``: in this module (class, method), and where in other
    modules of the run (``path:Class``)."""
    local = []
    for sub in local_subclasses(decision):
        method = decision.env.index(sub).methods.get(name)
        if method is not None:
            local.append((sub, method))
    project = decision.family.receivers.project
    elsewhere: list[str] = []
    if project is not None:
        for classdef in (decision.classdef, *local_subclasses(decision)):
            if decision.family.facts.parent(classdef) is decision.family.facts.tree:
                elsewhere.extend(project.overridden_elsewhere(classdef.name, name))
    return local, elsewhere


def step_override_migratable(method: Method) -> bool:
    """Every return of the override is a four-value literal, five already, or the base's own
    (``return super().post_step(a)``), and it reads the base's result nowhere else (the
    same test the run's summaries make of overrides elsewhere)."""
    return plain_override(method)


def where(decision: ClassDecision, local: list[tuple[ast.ClassDef, Method]], elsewhere: list[str]) -> str:
    names = [f"{c.name} (line {m.lineno})" for c, m in local]
    names += [w.rsplit("/", 1)[-1] for w in elsewhere]
    return ", ".join(names)
