"""Whether a file is in reach of the PettingZoo rules: it imports PettingZoo or SuperSuit,
iterates ``x.agent_iter()``, imports a PettingZoo env class or factory another module of the
run defines, or is passed a PettingZoo env by another module of the run.

It lives outside ``rules/pettingzoo`` so that another family (GM203, which leaves a
PettingZoo env's ``seed()`` to PZ106) can ask it without loading the PettingZoo rules for
every plain Gym file.
"""

from __future__ import annotations

from gymmigrate.facts import ModuleFacts
from gymmigrate.rules.base import FileContext


def pettingzoo_in_reach(facts: ModuleFacts, context: FileContext) -> bool:
    if context.profile.imports_pettingzoo or "agent_iter" in facts.attribute_calls:
        return True
    project = context.options.project
    if project is None:
        return False
    view = project.view(context.path)
    return view.imports_multi_agent(facts.imports.values()) or view.passed_multi_agent()
