"""The run's joined facts as one file sees them (``ProjectView``): what the receiver
analysis and the rules ask of the other modules of the run.
"""

from __future__ import annotations

import ast
import os
from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from gymmigrate.facts.done_causes import Cause, DoneCause, Limit
from gymmigrate.facts.import_roots import import_parts, is_test_path, nearest_root
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module_summary import MAX_CHAIN, REF

if TYPE_CHECKING:
    from gymmigrate.facts.project import ProjectFacts
    from gymmigrate.facts.reset_contract import Contract


@dataclass(frozen=True)
class ProjectView:
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

    def seed_classes(self) -> list[str]:
        """The env classes of the run that keep their own seed() (GM503), by name."""
        return sorted({name for _, name in self.facts.seed_classes})

    def seed_wrappers(self) -> list[str]:
        """The Gym wrapper classes of the run that define (or inherit from a base of the run)
        a seed() of their own, by name: gym's ``env.seed(s)`` reached the outermost one of a
        chain, Gymnasium's ``reset(seed=s)`` never calls it."""
        return sorted({name for _, name in self.facts.seed_wrappers})

    def seed_class_of_id(self, env_id: str) -> str | None:
        """The class of the run that keeps seed() which the run registers ``env_id`` for."""
        return self.facts.seed_ids.get(env_id)

    def render_called_elsewhere(self) -> bool:
        """The same for ``x.render(mode)``: this module's env classes keep render(mode)."""
        return self.path in self.facts.render_called

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

    def settled_render(self, qualname: str, param: str) -> list[str]:
        """``cli.py:5`` for each constructor in another module that gets ``render_mode="human"``
        for the bare renders of ``param`` of this file's ``qualname``, when every call of the
        def passes an env it builds (``ProjectFacts.settled_renders``); empty otherwise."""
        return [
            f"{os.path.relpath(path, os.path.dirname(self.path))}:{line}"
            for path, line, _ in self.facts.settled_renders.get((self.path, qualname, param), ())
        ]

    def gives_render_modes(self) -> bool:
        """This file has a constructor that ``gets_render_mode``."""
        return any(path == self.path for path, _, _ in self.facts.render_mode_constructions)

    def gets_render_mode(self, call: ast.Call) -> bool:
        """``call`` of this file is a constructor that gets ``render_mode="human"`` for the bare
        renders of a def of another module it is passed to (``settled_render``)."""
        return (self.path, call.lineno, call.col_offset) in self.facts.render_mode_constructions

    def handed_render_mode(self, call: ast.Call) -> str | None:
        """The frame mode ``call``, a ``gym.make`` of this file, gets for the renders of the
        calls of other modules it is handed to (``ProjectFacts.handed_render_modes``)."""
        return self.facts.handed_render_modes.get((self.path, call.lineno, call.col_offset))

    def gives_handed_modes(self) -> bool:
        """This file has a make that gets a ``handed_render_mode``."""
        return any(path == self.path for path, _, _ in self.facts.handed_render_modes)

    def settled_mode_render(self, qualname: str, param: str) -> tuple[str, list[str]] | None:
        """(mode, ``main.py:32`` for each make) where every call of the run passes ``param`` of
        this file's ``qualname`` an env made in another module that gets the one frame mode
        its renders ask (``ProjectFacts.settled_mode_renders``); None otherwise."""
        found = self.facts.settled_mode_renders.get((self.path, qualname, param))
        if found is None:
            return None
        mode, makes = found
        return mode, sorted({f"{os.path.relpath(path, os.path.dirname(self.path))}:{line}" for path, line, _ in makes})

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

    def makes_bare_env(self, qualified: str) -> bool:
        """An imported Gym env class of the run that is no wrapper (``TakeoffAviary``): its
        instance is the env itself, whose attributes need no forwarding."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.bare_env_classes
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
        return any(
            path == self.path and any(k in (EnvKind.PZ_AEC, EnvKind.PZ_PARALLEL) for k in kinds)
            for (path, _, _), kinds in self.facts.param_kinds.items()
        )

    def bootstrap_masks(self, qualified: str) -> tuple[tuple[str, ...], frozenset[tuple[str, str]]] | None:
        """For a def or method of another module of the run (``agents.Agent.learn``): its
        parameters and which of them mask bootstrapping from which (``facts/bootstrap.py``);
        None when the run does not define it."""
        resolved = self.facts._resolve(qualified, self.path)
        if resolved is not None:
            return self.facts.bootstrap_masks.get(resolved, ((), frozenset()))
        split = self._split_in_module_without_gym(qualified)
        return self.facts.bootstrap_masks.get(split) if split is not None else None

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

    def defines(self, qualified: str) -> bool:
        """The name comes from a module of the run (its own code, not a library's)."""
        return self.facts._split(qualified, self.path) is not None
    def has_module(self, dotted: str) -> bool:
        """A module of the run may be imported as ``dotted`` (``gym_minigrid`` in the
        gym-minigrid repository itself)."""
        return dotted in self.facts.modules

    def plugin_calls(self) -> tuple[tuple[str, str | None], ...]:
        """The register functions of ``gym.envs`` entry points this module must call on
        import, each with the namespace gym registered its ids in (None: the root)."""
        return self.facts.plugin_calls.get(self.path, ())

    def imported_packages(self) -> frozenset[str]:
        """The top-level packages this module imports, and the run's modules it imports, that
        import it, or that a script imports along with it (``multiagent`` imported by the
        script that builds this module's agents, or by the factory that script calls)."""
        return self.facts.nearby_packages.get(self.path, frozenset())

    def is_module(self, dotted: str) -> bool:
        """``dotted`` names a module or package of the run (``multiagent`` when the project has
        its own ``multiagent/`` package)."""
        return any(path == dotted or path.startswith(dotted + ".") for path in self.facts.modules)

    def built_elsewhere(self, classname: str) -> bool:
        """Another module of the run calls this file's class ``classname``."""
        return any(
            path == self.path and qualname in (classname, f"{classname}.__init__") for path, qualname, _ in self.facts.param_kinds
        )

    def subclassed_elsewhere(self, classname: str) -> bool:
        """Another module of the run derives a class from this file's ``classname``."""
        return (self.path, classname) in self.facts.overrides

    def built_through_super_elsewhere(self, classname: str) -> bool:
        """Every subclass of this file's ``classname`` in another module runs its
        ``__init__`` only through its own ``super().__init__(...)``, which the join follows,
        and is subclassed nowhere else itself: what they pass reaches ``param_kinds``."""
        subs = self.facts.subclasses_of.get((self.path, classname), [])
        return bool(subs) and all(sub in self.facts.init_passers and sub not in self.facts.subclasses_of for sub in subs)

    def overridden_elsewhere(self, classname: str, method: str) -> list[str]:
        """Subclasses in other modules of the run that override ``classname.method``."""
        return self.facts.overrides.get((self.path, classname), {}).get(method, [])

    def called_in_hierarchy_elsewhere(self, classname: str, method: str) -> list[str]:
        """Classes of other modules of the run above or below ``classname`` (bases it
        imports, subclasses, at any depth) whose methods call ``self.<method>(...)``: the
        base's ``step`` reading a helper its subclass defines, as ("pkg/base.py:Base")."""
        start = (self.path, classname)
        below: dict[tuple[str, str], list[tuple[str, str]]] = self.facts.subclasses_of
        above: dict[tuple[str, str], list[tuple[str, str]]] = {}
        for base, subs in below.items():
            for sub in subs:
                above.setdefault(sub, []).append(base)
        found: list[str] = []
        for links in (above, below):
            seen = {start}
            todo = list(links.get(start, ()))
            while todo:
                other = todo.pop(0)
                if other in seen:
                    continue
                seen.add(other)
                if other[0] != self.path and method in self.facts.self_calls.get(other, ()):
                    found.append(f"{other[0]}:{other[1]}")
                todo += links.get(other, ())
        return found

    def hook_followed_elsewhere(self, classname: str, method: str) -> bool:
        """Every override of ``classname``'s step hook ``method`` in other modules of the run
        can return five values with it (facts/step_hooks.py): they follow the base."""
        return method in self.facts.followed_hooks.get((self.path, classname), ())

    def inherited_hooks(self, classname: str) -> frozenset[str]:
        """The step hooks that bases of ``classname`` in other modules migrate, which its
        overrides follow."""
        return self.facts.inherited_hooks.get((self.path, classname), frozenset())

    def mode_renders_below(self, classname: str) -> list[tuple[str, str]]:
        """The ``self.render(mode)`` calls of subclasses in other modules of the run that
        reach ``classname``'s render(), as ("pull.py:5", call)."""
        return self.facts.mode_renders_below.get((self.path, classname), [])

    def done_overrides(self, classname: str, method: str) -> list[DoneCause]:
        """Why what ``method`` returns is True in each override of it by subclasses in
        other modules of the run, at any depth (``Base`` <- ``Single`` <- ``Hover``); each
        limit names the module it is in."""
        found: list[DoneCause] = []
        seen: set[tuple[str, str]] = set()
        todo = list(self.facts.subclasses_of.get((self.path, classname), ()))
        while todo:
            sub = todo.pop(0)
            if sub in seen:
                continue
            seen.add(sub)
            cause = self.facts.done_methods.get(sub, {}).get(method)
            if cause is None and method in self.facts.subclass_methods.get(sub, ()):
                cause = DoneCause(Cause.UNKNOWN)  # an override that takes arguments, or returns nothing
            if cause is not None:
                where = os.path.basename(sub[0])
                found.append(DoneCause(cause.cause, tuple(Limit(limit.line, limit.text, where, limit.by_counter) for limit in cause.limits)))
            todo += self.facts.subclasses_of.get(sub, ())
        return found
    def kept_render_behind_registry(self) -> str | None:
        """A class of the run that keeps its legacy render(mode) and takes no render_mode,
        where this module imports one that registers envs from data (``opaque_kept_renders``)."""
        return self.facts.opaque_kept_renders.get(self.path)

    def registered_without_render_mode(self, env_id: str | None) -> str | None:
        """The class of the run that ``gymnasium.make(env_id)`` builds (any registered one
        when ``env_id`` is None: not a literal) if its constructor takes no ``render_mode``."""
        ids = self.facts.no_render_mode_ids
        if env_id is not None:
            return ids.get(env_id)
        return next(iter(sorted(ids.values())), None)

    def takes_render_mode(self, qualified: str) -> bool:
        """An imported class of the run whose constructor takes ``render_mode`` once migrated
        (its own, or threaded down from a base: ``thread_render_mode``)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split[1] in self.facts.render_mode_classes.get(split[0], ())

    def derives_own_api(self, qualified: str) -> bool:
        """An imported class of the run that derives a library class with an env API of its
        own (``dm_env.Environment``), in its module or through another's: its instances are
        that API's envs whatever they hold (``ProjectFacts.own_api_classes``)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.own_api_classes

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

    def kept_step_classes(self, qualname: str, param: str) -> tuple[str | None, ...]:
        """Per call in another module of ``param`` of this file's ``qualname``, the class
        whose step and reset keep their own contract it passes an instance of (None: anything
        else); empty when no such call passes one (``ProjectFacts.kept_params``)."""
        return self.facts.kept_params.get((self.path, qualname, param), ())

    def thunk_factory_kind(self, qualified: str) -> EnvKind | None:
        """What the thunk an imported def of the run returns returns (``from envs import
        make_env``; ``ProjectFacts.thunk_factories``); None when it is no such def."""
        return self.facts.thunk_factory(qualified, self.path)

    def thunk_kinds(self, qualname: str, param: str) -> list[EnvKind]:
        """Per call in another module of ``param`` of this file's ``qualname`` (as
        ``param_kinds``), what calling each item of the list of thunks it passes returns
        (unknown where it passes anything else; ``ProjectFacts.thunk_kinds``)."""
        return self.facts.thunk_kinds.get((self.path, qualname, param), [])

    def renders_nothing(self, qualified: str) -> bool:
        """An imported class of the run whose render() is a stub (it renders no env)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.silent_renders

    def render_forward(self, qualified: str) -> str | None:
        """For an imported class of the run whose render() forwards bare to the env it holds
        (``ModuleSummary.render_forwards``), the module of that forward as a reader of this
        file finds it (no line: the run may move it, adding imports above it)."""
        split = self.facts._split(qualified, self.path)
        found = self.facts.render_forwards.get(split) if split is not None else None
        if found is None or found[0] == self.path:
            return None
        return os.path.relpath(found[0], os.path.dirname(self.path))

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
        return split is not None and split[1] in self.facts.wrapping_helpers.get(split[0], ())

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

    def class_methods(self, qualified: str) -> frozenset[str]:
        """The methods of an imported class of the run (``from pkg import TrialEnv``) with
        those of its bases of the run; empty when the run does not define the class."""
        split = self.facts._split(qualified, self.path)
        if split is None or "." in split[1]:
            return frozenset()
        return self.facts.class_methods.get(split, frozenset())

    def renders_wrapped_env(self, qualified: str) -> bool:
        """An imported name of the run is a Gym wrapper class whose reset/step render the env
        it wraps."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.rendering_wrappers

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

    def own_render_here(self, name: str) -> bool:
        """A class of this module whose render(mode) stays the project's own
        (``ProjectFacts.own_renders``): it takes no render_mode."""
        return (self.path, name) in self.facts.own_renders

    def own_render(self, qualified: str) -> bool:
        """``own_render_here`` for a name this module imports (re-exports followed)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.own_renders

    def modeless_render_here(self, name: str) -> bool:
        """A class of this module whose render() no render mode changes
        (``ProjectFacts.modeless_renders``)."""
        return (self.path, name) in self.facts.modeless_renders

    def modeless_render(self, qualified: str) -> bool:
        """``modeless_render_here`` for a name this module imports (re-exports followed)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.modeless_renders
    def unset_spaces(self, name: str) -> frozenset[str]:
        """The spaces a class of this module leaves unset with its bases, where an entry point
        of the run makes it (the class itself, or a registered def that constructs it)."""
        return self.facts.unset_spaces.get((self.path, name), frozenset())

    def may_register(self, env_id: str) -> bool:
        """The run may register ``env_id`` with the Gym registry: it registers that literal,
        or ids it does not spell as literals."""
        ids = self.facts.registered_ids
        return env_id in ids or None in ids

    def registered_here(self, name: str) -> bool:
        """A class of this module that the run registers as an ``entry_point``."""
        return (self.path, name) in self.facts.registered_classes

    def reached_from_outside(self, name: str) -> bool:
        """Code of the run beyond this module may get hold of its env class ``name``:
        another module imports this one, or registers ``name`` (or any class, from
        entry points that are no literal) for ``make`` to build."""
        return bool(self.facts.importers.get(self.path)) or self.registered_here(name) or self.facts.registers_from_data

    def non_space_env(self, module: str, name: str) -> tuple[str, str, str] | None:
        """For ``module:name`` as an ``entry_point`` spells it, a class of the run whose
        spaces are not Spaces: (attribute, space class, what that class derives from)."""
        path = self.facts.modules.get(module)
        return self.facts.non_space_envs.get((path, name)) if path else None

    def reset_contract(self) -> Contract | None:
        """The env reset keywords the run passes down its wrapper chains (GM207)."""
        return self.facts.reset_contract

    def wrapper_stepper(self, module: str, name: str) -> str | None:
        """For ``module:name`` as an ``entry_point`` spells it, the class of the run whose
        reset steps the wrapper around it (that class, or a base of it)."""
        path = self.facts.modules.get(module)
        return self.facts.wrapper_steppers.get((path, name)) if path else None

    def wrapper_stepper_here(self, name: str) -> str | None:
        """``wrapper_stepper`` for a class of this module."""
        return self.facts.wrapper_steppers.get((self.path, name))

    def wrapper_stepper_of(self, qualified: str) -> str | None:
        """``wrapper_stepper`` for a name this module imports (``from .tasks import Task``)."""
        split = self.facts._split(qualified, self.path)
        return None if split is None else self.facts.wrapper_steppers.get(split)

    def any_wrapper_stepper(self) -> str | None:
        """A class of the run whose reset steps the wrapper around it, if any: what an
        ``entry_point`` the run cannot resolve may name."""
        return min(self.facts.wrapper_steppers.values(), default=None)

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

