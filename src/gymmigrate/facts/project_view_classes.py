"""What one file asks of the run about the classes and defs it imports (``ClassView``, a part
of ``ProjectView``): wrappers, plain and record classes, what their instances hold and keep.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from gymmigrate.facts.import_roots import import_parts, nearest_root
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module_summary import MAX_CHAIN, REF, InitHeld

if TYPE_CHECKING:
    from gymmigrate.facts.project import ProjectFacts


class ClassView:
    """The run's facts about imported classes as one file sees them (``facts`` and ``path`` are
    ``ProjectView``'s)."""

    facts: ProjectFacts
    path: str

    def held_kind(self, qualified: str, attribute: str) -> EnvKind | None:
        """``holder.gym_env`` where ``holder`` is an instance of the run's plain class
        ``qualified``: the env every construction passes (``ProjectFacts.held_kinds``)."""
        split = self.facts._split(qualified, self.path)
        return None if split is None else self.facts.held_kinds.get((*split, attribute))

    def driven_kind(self, qualified: str, attribute: str) -> EnvKind | None:
        """``self.<attribute>`` of a class deriving the run's class ``qualified`` and never
        storing it: what that class stores there and resets or steps, where its module
        settles it (``ProjectFacts.driven_kinds``); None otherwise."""
        split = self.facts._split(qualified, self.path)
        return None if split is None else self.facts.driven_kinds.get(split, {}).get(attribute)

    def held_slot(self, qualified: str, attribute: str) -> tuple[str, int] | None:
        """``holder.attribute`` where ``holder`` is an instance of the run's plain class
        ``qualified``: the constructor parameter it holds and its position in a call."""
        split = self.facts._split(qualified, self.path)
        return None if split is None else self.facts.held_slots.get((*split, attribute))

    def holds_made(self, qualified: str, attribute: str) -> bool:
        """An instance of the run's class ``qualified`` holds a bare ``gym.make`` result in
        ``attribute`` (``ProjectFacts.made_holders``)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and attribute in self.facts.made_holders.get(split, ())

    def held_made(self, qualname: str, param: str) -> frozenset[str] | None:
        """The attributes holding a bare make result in what every call of another module
        passes to ``param`` of this module's ``qualname``; None where no such call passes it
        (``ProjectFacts.held_made``)."""
        return self.facts.held_made.get((self.path, qualname, param))

    def receives_made_holders(self) -> bool:
        """Some call of another module hands a def of this module a holder of a bare make
        result in every call (``held_made``): its ``holder.env`` reads are the forwarding rules'."""
        return any(key[0] == self.path and held for key, held in self.facts.held_made.items())

    def property_alias(self, qualified: str, name: str) -> str | None:
        """The attribute of ``self`` that the property ``name`` of the run's class
        ``qualified`` (or of a base of it of the run) only returns (``ProjectFacts.property_aliases``)."""
        split = self.facts._split(qualified, self.path)
        return None if split is None else self.facts.property_aliases.get(split, {}).get(name)

    def init_held(self, qualified: str, attribute: str) -> InitHeld | None:
        """``self.<attribute>`` that the run's class ``qualified`` (a base of this file's
        class) stores only from a parameter of its ``__init__``: that parameter, its position
        in a call and whether the class is a Gym env wrapper written by hand around it,
        subclassed or not (``ProjectFacts.init_held``)."""
        split = self.facts._split(qualified, self.path)
        return None if split is None else self.facts.init_held.get((*split, attribute))

    def makes_bare_env(self, qualified: str) -> bool:
        """An imported Gym env class of the run that is no wrapper (``TakeoffAviary``): its
        instance is the env itself, whose attributes need no forwarding."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.bare_env_classes

    def _split_in_module_without_gym(self, qualified: str) -> tuple[str, str] | None:
        """``("/run/pkg/memory.py", "Transition")`` for ``pkg.memory.Transition`` where that
        module has no Gym code (only its masks and records are summarised, so ``_split`` does
        not know it); absolute imports only."""
        parts = qualified.split(".")
        for cut in range(len(parts) - 1, 0, -1):
            paths = self.facts.mask_modules.get(".".join(parts[:cut]), ())
            path = nearest_root(paths, cut, self.path) if paths else None
            if path:
                return path, ".".join(parts[cut:])
        return None

    def is_plain_root(self, qualified: str) -> bool:
        """An imported name of the run is a top-level class deriving only ``object`` or
        ``abc.ABC`` (``from ._environment import Environment``), in a module with Gym code or
        without (``ModuleSummary.plain_roots``)."""
        split = self.facts._split(qualified, self.path)
        if split is None or split[0] not in self.facts.plain_roots:
            split = self._split_in_module_without_gym(qualified) if not qualified.startswith(".") else self._split_relative(qualified)
        return split is not None and split[1] in self.facts.plain_roots.get(split[0], ())

    def _split_relative(self, qualified: str) -> tuple[str, str] | None:
        """``_split`` of a relative name (``._environment.Environment``) into a module with
        plain roots that has no Gym code (which ``_split`` does not know)."""
        level, parts = import_parts(qualified)
        for cut in range(len(parts) - 1, 0, -1):
            path = self.facts._module_path(parts[:cut], level, self.path, known=self.facts.plain_roots)
            if path:
                return path, ".".join(parts[cut:])
        return None

    def is_record_class(self, qualified: str) -> bool:
        """An imported name of the run is a record class (``from .memory import Transition``,
        a ``namedtuple`` of a module with no Gym code too)."""
        split = self.facts._split(qualified, self.path)
        if split is not None and split[1] in self.facts.record_classes.get(split[0], ()):
            return True
        # ``_split`` stops at ``pkg/__init__.py`` for a module with no Gym code
        split = self._split_in_module_without_gym(qualified)
        return split is not None and split[1] in self.facts.record_classes.get(split[0], ())

    def derives_own_api(self, qualified: str) -> bool:
        """An imported class of the run that derives a library class with an env API of its
        own (``dm_env.Environment``), in its module or through another's: its instances are
        that API's envs whatever they hold (``ProjectFacts.own_api_classes``)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.own_api_classes

    def own_api_flag(self, qualified: str) -> str | None:
        """For an imported class of the run with two APIs, the attribute that picks
        Gymnasium's shapes in its step and reset (``ProjectFacts.own_api_flags``)."""
        split = self.facts._split(qualified, self.path)
        return self.facts.own_api_flags.get(split) if split is not None else None

    def counts_no_steps(self, qualified: str) -> bool:
        """An imported class of the run that counts no steps, nor does any base of it
        (``ProjectFacts.quiet_classes``): it cannot end a subclass's episodes on a limit."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.quiet_classes

    def keeps_legacy_step(self, qualified: str) -> bool:
        """An imported name of the run makes instances whose step keeps the four-field
        contract (the run does not migrate that step): their callers keep it too."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.legacy_steps

    def keeps_reset(self, qualified: str) -> bool:
        """An imported name of the run makes instances whose reset the run keeps as it was,
        without seed/options (``ProjectFacts.kept_resets``)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.kept_resets

    def forwards_inner_contract(self, qualified: str) -> bool:
        """An imported Gym wrapper class of the run whose step and reset hand on the wrapped
        env's results unchanged (``ProjectFacts.forwarding_wrappers``)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.forwarding_wrappers

    def seed_holder(self, qualified: str) -> str | None:
        """For an imported name of the run: "own" when it is a class defining seed(), "inner"
        when its instances hold one in their wrapper chain (``ProjectFacts.seed_chains``)."""
        split = self.facts._split(qualified, self.path)
        if split is None:
            return None
        return "own" if split in self.facts.seed_owners else "inner" if split in self.facts.seed_chains else None

    def is_spec_list(self, qualified: str) -> bool:
        """An imported name of the run is bound to a list of the registry's EnvSpecs."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split[1] in self.facts.spec_lists.get(split[0], ())

    def pz_wrapper(self, qualified: str) -> tuple[str, frozenset[str]] | None:
        """For an imported name of the run that is a PettingZoo wrapper class (or an alias of
        PettingZoo's wrapper bases): ("aec" | "parallel", the methods the run's classes on the
        way define); None otherwise. References are followed a few modules deep."""
        split = self.facts._split(qualified, self.path)
        methods: set[str] = set()
        for _ in range(MAX_CHAIN):
            if split is None:
                return None
            path, name = split
            entry = self.facts.pz_wrappers.get(path, {}).get(name)
            if entry is None:
                return None
            api, defined = entry
            methods.update(defined)
            if not api.startswith(REF):
                return api, frozenset(methods)
            split = self.facts._split(api[len(REF) :], path)
        return None

    def wraps_argument(self, qualified: str) -> bool:
        """An imported def of the run returns its first argument, maybe in Gym wrappers
        (``from common.wrappers import wrap_deepmind``)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split[1] in self.facts.wrapping_helpers.get(split[0], {})

    def wrapped_parameter(self, qualified: str) -> str | None:
        """The parameter whose argument an imported def of the run returns, maybe in Gym
        wrappers (``ProjectView.wraps_argument``): a call may pass it by keyword (``env=``)."""
        split = self.facts._split(qualified, self.path)
        return None if split is None else self.facts.wrapping_helpers.get(split[0], {}).get(split[1])

    def gym_only_maker(self, qualified: str) -> str | None:
        """The Gym-only stack (``nes_py``) whose envs an imported def of the run returns
        (``from src.env import create_env``), or None."""
        split = self.facts._split(qualified, self.path)
        return None if split is None else self.facts.gym_only_makers.get(split[0], {}).get(split[1])

    def uses_atari(self, qualified: str) -> bool:
        """An imported def or class of the run uses what only an Atari env has
        (``from utils.atari_wrapper import wrap_deepmind``)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split[1] in self.facts.atari_users.get(split[0], ())

    def class_of_run(self, qualified: str) -> tuple[str, str] | None:
        """``(path, "Policy")`` for an imported name of the run that is a top-level class with
        methods (``from .base import Policy``): where its attributes are decided."""
        split = self.facts._split(qualified, self.path)
        if split is None or "." in split[1]:
            return None
        prefix = split[1] + "."
        return split if any(q.startswith(prefix) for q in self.facts.defs.get(split[0], ())) else None

    def inherited_params(self, qualified: str, method: str) -> tuple[str, ...] | None:
        """The parameters of ``method`` as an imported class of the run has it: its own, or
        that of the first of its bases of the run (depth first, in the order each class
        names them) that defines one (``class Camera(BaseSim)`` reaching ``BaseSim.reset``).
        None where no class of the run on the way defines it."""
        split = self.facts._split(qualified, self.path)
        if split is None or "." in split[1]:
            return None
        todo, seen = [split], set()
        while todo:
            current = todo.pop(0)
            if current in seen:
                continue
            seen.add(current)
            params = self.facts.def_params.get((current[0], f"{current[1]}.{method}"))
            if params is not None:
                return params
            todo[:0] = self.facts.class_bases.get(current, ())
        return None

    def class_methods(self, qualified: str) -> frozenset[str]:
        """The methods of an imported class of the run (``from pkg import TrialEnv``) with
        those of its bases of the run; empty when the run does not define the class."""
        split = self.facts._split(qualified, self.path)
        if split is None or "." in split[1]:
            return frozenset()
        return self.facts.class_methods.get(split, frozenset())

    def is_wrapper_class(self, qualified: str) -> bool:
        """An imported name of the run is a Gym wrapper class (``from pkg.wrappers import X``)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split[1] in self.facts.wrapper_classes.get(split[0], ())

    def run_wrapper_attributes(self) -> frozenset[str]:
        """What any Gym wrapper class of the run defines for ``self``: an env handed around
        the run may be one of them, and its own ``x`` shadows the base env's."""
        return frozenset().union(*self.facts.wrapper_defined.values())

    def wrapper_defined(self, qualified: str) -> frozenset[str] | None:
        """For an imported Gym wrapper class of the run (re-exports followed), what it and
        its bases define for ``self``; None when the run cannot tell."""
        split = self.facts._split(qualified, self.path)
        return None if split is None else self.facts.wrapper_defined.get(split)

    def imported_class(self, qualified: str) -> tuple[bool, bool] | None:
        """For an imported class of the run: (is an env class, takes render_mode)."""
        level, parts = import_parts(qualified)
        if len(parts) < 2:
            return None
        path = self.facts._module_path(parts[:-1], level, self.path)
        if not path:
            return None
        name = parts[-1]
        return name in self.facts.env_classes.get(path, ()), name in self.facts.render_mode_classes.get(path, ())
