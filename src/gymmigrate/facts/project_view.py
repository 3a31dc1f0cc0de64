"""The run's joined facts as one file sees them (``ProjectView``): what the receiver
analysis and the rules ask of the other modules of the run. Calls and parameters across
modules are asked here; renders, imported classes, class hierarchies and registrations in
the views it derives from (``project_view_renders.py``, ``project_view_classes.py``,
``project_view_hierarchy.py``, ``project_view_registry.py``).
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from gymmigrate.facts.creator_tables import Field
from gymmigrate.facts.import_roots import import_parts, is_test_path
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.project_view_classes import ClassView
from gymmigrate.facts.project_view_fixtures import FixtureView
from gymmigrate.facts.project_view_hierarchy import HierarchyView
from gymmigrate.facts.project_view_registry import RegistryView
from gymmigrate.facts.project_view_renders import RenderView

if TYPE_CHECKING:
    from gymmigrate.facts.project import ProjectFacts
    from gymmigrate.facts.reset_contract import Contract


@dataclass(frozen=True)
class ProjectView(ClassView, FixtureView, HierarchyView, RegistryView, RenderView):
    """The run's facts as one file sees them."""

    facts: ProjectFacts
    path: str

    def param_kinds(self, qualname: str, param: str) -> list[EnvKind]:
        """What other modules of the run pass for ``param`` of this file's ``qualname``."""
        return self.facts.param_kinds.get((self.path, qualname, param), [])

    def param_sources(self, qualname: str, param: str) -> tuple[str | None, ...]:
        """Per call from another module of the run, the variable it hands on for ``param``
        of this file's ``qualname`` (``ProjectFacts.param_sources``)."""
        return self.facts.param_sources.get((self.path, qualname, param), ())

    def seed_called_elsewhere(self) -> bool:
        """Another module of the run calls ``x.seed(...)`` on something it cannot trace and
        imports this module's env classes: their seed() may be what it calls."""
        return self.path in self.facts.seed_called

    def seed_used(self) -> bool:
        """Some module of the run calls ``x.seed(...)`` or ``x._seed(...)`` on other than a
        library module or a space: an env class's seed() may be what it calls."""
        return self.facts.seed_used

    def seed_used_without_a_value(self) -> bool:
        """One of the calls ``seed_used`` counts passes no seed (``x.seed()``, ``x.seed(None)``)."""
        return self.facts.seed_used_without_a_value

    def return_info_passed(self) -> bool:
        """Some module of the run calls ``x.reset(return_info=...)`` with a mode other than
        ``True`` (not a reset handing its own flag on): a caller may want the bare observation."""
        return self.facts.return_info_passed

    def configure_called(self) -> bool:
        """Some module of the run calls ``x.configure(...)`` (or ``x._configure``) on other
        than ``self``: an env's renamed gym < 0.9 ``configure`` hook may be what it calls."""
        return self.facts.configure_called

    def seed_classes(self) -> list[str]:
        """The env classes of the run that keep their own seed() (GM503), by name."""
        return sorted({name for _, name in self.facts.seed_classes})

    def seed_wrappers(self) -> list[str]:
        """The Gym wrapper classes of the run that define (or inherit from a base of the run)
        a seed() of their own, by name: gym's ``env.seed(s)`` reached the outermost one of a
        chain, Gymnasium's ``reset(seed=s)`` never calls it."""
        return sorted({name for _, name in self.facts.seed_wrappers})

    def checks_envs(self) -> bool:
        """A module of the run imports Gym's or Gymnasium's ``check_env`` (or its module)."""
        return self.facts.checks_envs

    def recreates_envs(self) -> bool:
        """A module of the run imports ``check_env`` or calls ``make(x.spec)`` /
        ``x.spec.make()``: Gymnasium rebuilds wrapped envs from their spec there."""
        return self.facts.checks_envs or self.facts.recreates_from_spec

    def call_kind(self, qualified: str) -> EnvKind | None:
        """What calling an imported name of the run gives (``from hunt import HuntEnv``:
        a PettingZoo parallel env; ``pkg.make``: a Gym env). ``EnvKind.UNKNOWN`` for a name
        a module of the run binds but cannot classify; None when the run does not define it."""
        split = self.facts._split(qualified, self.path)
        if split is None:
            return None
        path, name = split
        if "." in name:
            return None
        found = self.facts.call_kinds.get((path, name))
        return found if found is not None else EnvKind.UNKNOWN

    def table_kind(self, qualified: str, field: Field | None) -> EnvKind | None:
        """What calling through an imported table of creators of the run gives
        (``T[k](...)``, ``T[k]["make"](...)`` with ``field``; ``ProjectFacts.table_kinds``):
        unknown for a name of the run that is no closed table, None for no name of the run."""
        split = self.facts._split(qualified, self.path)
        if split is None or "." in split[1]:
            return None
        return self.facts.table_kinds.get((*split, "" if field is None else field), EnvKind.UNKNOWN)

    def table_made(self, qualified: str, field: Field | None) -> bool:
        """Every callable of an imported table of creators of the run returns a
        ``make(...)`` result, maybe wrapped (``ProjectFacts.made_tables``)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and (*split, "" if field is None else field) in self.facts.made_tables

    def table_altered(self, name: str) -> bool:
        """Another module of the run writes into this module's top-level ``name``."""
        return (self.path, name) in self.facts.altered_tables

    def returns_made(self, qualified: str) -> bool:
        """An imported def of the run that returns ``make(...)`` results (``utils.make_env``):
        a wrapper stack, whatever its caller does with it."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.made

    def gym_env_callers(self, qualname: str, param: str) -> list[str]:
        """``run.py:18`` for each call in another module that passes a Gym env to ``param``
        of this file's ``qualname`` (``ProjectFacts.gym_env_callers``)."""
        return [
            f"{os.path.relpath(path, os.path.dirname(self.path))}:{line}"
            for path, line in self.facts.gym_env_callers.get((self.path, qualname, param), ())
        ]

    def gym_env_handers(self, qualname: str, param: str) -> list[str]:
        """``agents.py:10`` for each call in another module that hands on, to ``param`` of
        this file's ``qualname``, what some call further up gives a Gym env
        (``ProjectFacts.gym_env_handers``)."""
        return [
            f"{os.path.relpath(path, os.path.dirname(self.path))}:{line}"
            for path, line in self.facts.gym_env_handers.get((self.path, qualname, param), ())
        ]

    def test_double_callers(self, qualname: str, param: str) -> list[str] | None:
        """``tests/x_test.py:16`` for each call in another module that passes an env of
        another kind than a Gym env to ``param`` (a mock with an API of its own), when every
        such call is in a test module; None when one is not."""
        callers = self.facts.other_env_callers.get((self.path, qualname, param), ())
        if not callers or not all(is_test_path(path) for path, _ in callers):
            return None
        return [f"{os.path.relpath(path, os.path.dirname(self.path))}:{line}" for path, line in callers]

    def passed_ids(self, function: str, param: str) -> tuple[str | None, ...]:
        """For a top-level def of this file, the env id each call in another module passes to
        ``param`` ("" its default, None no id literal); () when no other module calls it
        (``ProjectFacts.passed_ids``)."""
        return self.facts.passed_ids.get((self.path, function, param), ())

    def passes_id_to_make(self, line: int, key: str) -> bool:
        """The call of this file at ``line`` passes, as argument ``key`` (a position or a
        keyword), an env id literal that a def of the run hands to a Gym id call
        (``ProjectFacts.id_slots``)."""
        return (line, key) in self.facts.id_slots.get(self.path, ())

    def keeps_argument(self, qualified: str, key: str) -> bool:
        """The def (or class, its ``__init__``) of the run that ``qualified`` names uses the
        argument ``key`` (a position, ``self`` not counted, or a keyword) only where it is:
        it hands it to no call and stores it nowhere (``ModuleSummary.escaping_params``)."""
        found = self.facts._resolve(qualified, self.path)
        if found is None or found not in self.facts.escaping_params:
            return False
        params = self.facts.def_params.get(found, ())
        positional = params[1:] if "." in found[1] else params
        param = positional[int(key)] if key.isdigit() and int(key) < len(positional) else key
        return param in params and param not in self.facts.escaping_params[found]

    def handed_on(self, function: str) -> bool:
        """Another module of the run reads this file's ``function`` as a value (``partial(f)``)."""
        return (self.path, function) in self.facts.handed_on

    def imports_legacy_gym(self, qualified: str) -> bool:
        """``qualified`` (an import of this file: ``pkg.wrappers`` or ``pkg.wrappers.make_env``)
        names a module of the run that imports legacy ``gym``."""
        level, parts = import_parts(qualified)
        for module in (parts, parts[:-1]):
            path = self.facts._module_path(module, level, self.path) if module else None
            if path and path != self.path and path in self.facts.legacy_gym:
                return True
        return False

    def made_at(self, qualified: str) -> str | None:
        """Where an imported def of the run that returns ``make(...)`` results makes its env,
        as a reader of this file finds it: "the make in `make_env` of wrappers.py" (no line:
        the run may move it, adding imports above it)."""
        split = self.facts._split(qualified, self.path)
        found = self.facts.made_at.get(split) if split is not None else None
        if found is None or found[0] == self.path:
            return None
        path, name = found
        return f"the make in `{name}` of {os.path.relpath(path, os.path.dirname(self.path))}"

    def star_call_kind(self, name: str, stars: tuple[str, ...]) -> EnvKind | None:
        """What calling ``name`` gives where this file binds it only through star imports
        (``stars``: ``from utils.wrappers import *`` gives ``"utils.wrappers"``) of modules of
        the run; None when none of them binds it."""
        for path in self._star_paths(stars):
            found = self.facts.call_kinds.get((path, name))
            if found is not None:
                return found
        return None

    def star_wrapper_class(self, name: str, stars: tuple[str, ...]) -> bool:
        """``name``, bound in this file only by star imports, is a Gym wrapper class of the
        run module that defines it."""
        return any(name in self.facts.wrapper_classes.get(path, ()) for path in self._star_paths(stars))

    def wrapper_class(self, qualified: str) -> bool:
        """An imported name of the run is a Gym wrapper class of the module that defines it."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split[1] in self.facts.wrapper_classes.get(split[0], ())

    def _star_paths(self, stars: tuple[str, ...]) -> list[str]:
        found = []
        for module in stars:
            level, parts = import_parts(module)
            path = self.facts._module_path(parts, level, self.path)
            if path and path != self.path:
                found.append(path)
        return found

    def library_alias(self, qualified: str) -> str | None:
        """The library callable an imported name of the run is bound to (``pkg.make`` ->
        ``gym.make``), or None."""
        split = self.facts._split(qualified, self.path)
        return None if split is None else self.facts.aliases.get(split)

    def imports_multi_agent(self, qualified_names: Iterable[str]) -> bool:
        """One of these imported names is a PettingZoo env class or factory of the run."""
        return any(self.call_kind(q) in (EnvKind.PZ_AEC, EnvKind.PZ_PARALLEL) for q in qualified_names)

    def passed_multi_agent(self) -> bool:
        """Another module of the run passes a PettingZoo env to a def or class of this one
        (``MarkovVec(par_env)`` with ``par_env`` a parallel env): its calls on that
        parameter are PettingZoo calls, though this module imports no PettingZoo."""
        return self.path in self.facts.multi_agent_passed

    def bootstrap_masks(self, qualified: str) -> tuple[tuple[str, ...], frozenset[tuple[str, str]]] | None:
        """For a def or method of another module of the run (``agents.Agent.learn``): its
        parameters and which of them mask bootstrapping from which (``facts/bootstrap.py``);
        None when the run does not define it."""
        resolved = self.facts._resolve(qualified, self.path)
        if resolved is not None:
            return self.facts.bootstrap_masks.get(resolved, ((), frozenset()))
        split = self._split_in_module_without_gym(qualified)
        return self.facts.bootstrap_masks.get(split) if split is not None else None

    def defines(self, qualified: str) -> bool:
        """The name comes from a module of the run (its own code, not a library's)."""
        return self.facts._split(qualified, self.path) is not None

    def has_module(self, dotted: str) -> bool:
        """A module of the run may be imported as ``dotted`` (``gym_minigrid`` in the
        gym-minigrid repository itself)."""
        return dotted in self.facts.modules

    def imported_packages(self) -> frozenset[str]:
        """The top-level packages this module imports, and the run's modules it imports, that
        import it, or that a script imports along with it (``multiagent`` imported by the
        script that builds this module's agents, or by the factory that script calls)."""
        return self.facts.nearby_packages.get(self.path, frozenset())

    def is_module(self, dotted: str) -> bool:
        """``dotted`` names a module or package of the run (``multiagent`` when the project has
        its own ``multiagent/`` package)."""
        return any(path == dotted or path.startswith(dotted + ".") for path in self.facts.modules)

    def kept_step_classes(self, qualname: str, param: str) -> tuple[str | None, ...]:
        """Per call in another module of ``param`` of this file's ``qualname``, the class
        whose step and reset keep their own contract it passes an instance of (None: anything
        else); empty when no such call passes one (``ProjectFacts.kept_params``)."""
        return self.facts.kept_params.get((self.path, qualname, param), ())

    def thunk_factory_kind(self, qualified: str) -> EnvKind | None:
        """What the thunk an imported def of the run returns returns (``from envs import
        make_env``; ``ProjectFacts.thunk_factories``); None when it is no such def."""
        return self.facts.thunk_factory(qualified, self.path)

    def thunk_item_kind(self, qualified: str, index: int, size: int | None) -> EnvKind | None:
        """What the thunk at ``index`` of the tuple an imported def of the run returns
        returns (``create, _ = make_creator(...)``; ``ProjectFacts.thunk_items``); None when
        it is no such def."""
        return self.facts.thunk_item_kind(qualified, self.path, index, size)

    def thunk_made(self, qualified: str, item: tuple[int, int | None] | None) -> bool:
        """The thunk an imported def of the run returns (or holds at ``item`` of the tuple it
        returns) returns make() results (``ProjectFacts.made_thunks``)."""
        return self.facts.thunk_made(qualified, self.path, item)

    def item_kinds(self, qualname: str, param: str) -> list[EnvKind]:
        """Per call in another module of ``param`` of this file's ``qualname`` (as
        ``param_kinds``), the kind of every item of the list it passes (unknown where it
        passes anything else; ``ProjectFacts.item_kinds``)."""
        return self.facts.item_kinds.get((self.path, qualname, param), [])

    def thunk_kinds(self, qualname: str, param: str) -> list[EnvKind]:
        """Per call in another module of ``param`` of this file's ``qualname`` (as
        ``param_kinds``), what calling each item of the list of thunks it passes returns
        (unknown where it passes anything else; ``ProjectFacts.thunk_kinds``)."""
        return self.facts.thunk_kinds.get((self.path, qualname, param), [])

    def creator_kinds(self, qualname: str, param: str) -> list[EnvKind]:
        """Per call in another module of ``param`` of this file's ``qualname`` (as
        ``param_kinds``), what calling the class or other creator it passes gives (unknown
        where it passes anything else; ``ProjectFacts.creator_kinds``)."""
        return self.facts.creator_kinds.get((self.path, qualname, param), [])

    def thunk_stacks(self, qualname: str, param: str) -> list[str | None]:
        """Per call in another module of ``param`` of this file's ``qualname`` (as
        ``thunk_kinds``), the Gym-only library stack every thunk of the list it passes makes an
        env of (None where not one; ``ProjectFacts.thunk_stacks``)."""
        return self.facts.thunk_stacks.get((self.path, qualname, param), [])

    def reset_contract(self) -> Contract | None:
        """The env reset keywords the run passes down its wrapper chains (GM207)."""
        return self.facts.reset_contract
