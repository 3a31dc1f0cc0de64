"""GM511: an env class that ``gymnasium.make`` builds but that never sets a space (report only).

gym 0.21's ``Env`` gave every env ``action_space = None`` and ``observation_space = None``;
Gymnasium's only annotates them, and the env checker ``make`` puts around every env raises
``AttributeError: The environment must specify an observation space`` the moment the env is
built. Asked once at the class, where an entry point of the run makes it (the class itself or
a registered def that constructs it) and neither the class nor a base sets the space by the
end of its construction (``facts/space_setters.py``).

Source: Gymnasium 1.4 ``wrappers/common.py`` (``PassiveEnvChecker.__init__``), ``core.py``.
"""

from __future__ import annotations

from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.space_setters import SPACES, local_unset_spaces, registered_here
from gymmigrate.findings import FixKind
from gymmigrate.rules.custom_env.common import ClassDecision


def decide_unset_spaces(decision: ClassDecision) -> None:
    classdef = decision.classdef
    family = decision.family
    facts, receivers = family.facts, family.receivers
    if not family.context.profile.imports_gym:
        return  # written for Gymnasium: no legacy default was ever there
    if facts.classes.get(classdef.name) is not classdef or receivers.class_kind(classdef) is not EnvKind.GYM_ENV:
        return
    project = receivers.project
    unset = project.unset_spaces(classdef.name) if project is not None else frozenset()
    if not unset:
        # ``register(id=..., entry_point=Sim)`` in this module (a run of one file, or an entry
        # point the join does not read: the class object itself)
        made = facts.memo(("registered-here", 0), lambda: registered_here(facts, receivers, None))
        unset = (local_unset_spaces(facts, receivers, classdef) or frozenset()) if classdef.name in made else frozenset()
    if not unset:
        return
    missing = [space for space in SPACES if space in unset]
    named = " and ".join(f"`{space}`" for space in missing)
    first = missing[0].split("_")[0]
    decision.report(
        classdef,
        "GM511",
        f"`{classdef.name}` leaves {named} unset once built (gym 0.21's Env had None there; Gymnasium's has no default), and an entry "
        f"point of the run makes it: the env checker `gymnasium.make` puts around it raises AttributeError (\"The environment "
        f"must specify an {first} space\") where no wrapper in between sets one; set "
        + " and ".join(f"`self.{space}`" for space in missing)
        + " in `__init__`, or register (or make) it with `disable_env_checker=True`",
        FixKind.FLAG,
    )
