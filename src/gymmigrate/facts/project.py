"""Facts across the files of one run: which parameters receive Gym envs from other modules.

A library method that steps an env (``def fit(self, env)``) is usually called from a
training script in another module that passes ``gym.make(...)``. One file on its own
cannot tell what ``env`` is; the run can. The run is processed in two cheap steps:

1. ``summarize`` reads each module once, on the same ``ast`` facts the rules use, into a
   small picklable ``ModuleSummary``: its top-level functions and the methods of its
   top-level classes with their parameters, its env classes, and for every call of one
   of its own defs or of an imported function, class or method (``agent.fit(env)`` where
   ``agent = Agent()`` and ``Agent`` is imported) the ``EnvKind`` of each argument.
2. ``ProjectFacts.join`` resolves those calls to the modules of the run (absolute and
   relative imports) once, and keeps, per parameter, the kinds the other modules pass.
   An argument that is a parameter of the calling def, or a new instance of a class
   imported from the run, is resolved here, once per parameter (``ParamJoin``, ``facts/project_params.py``).

Each file is then migrated with ``ProjectFacts.view(path)`` in its context: the receiver
analysis joins those kinds with the file's own call sites (``Receivers._param_kind``), and
imported env classes of the run count as env classes. A file checked alone has no view
and keeps its own, more cautious, answer. A call whose owner cannot be resolved but which
passes a VecEnv, vector env or PettingZoo env to a method of the same name still counts
against every method of that name: a guard kind wins.

This module holds ``ProjectFacts`` (the joined data, the join's order, and how a dotted
name resolves to a module of the run). The rest, by family: ``module_summary.py`` (what a
module tells the run), ``import_roots.py`` (which file a dotted name names),
``project_exports.py`` (what calling a name of the run gives, re-exports followed),
``project_params.py`` (the kinds passed to each parameter, and to what a holder
holds), ``project_contracts.py`` (non-Space spaces, ``render_mode`` down subclasses,
legacy steps), ``project_classes.py`` (class hierarchies across modules: overrides,
hooks, quiet and own-API classes, re-exports of them), ``project_imports.py`` (which
modules reach which, and the packages the run needs) and ``project_view.py``
(``ProjectView``: the facts as one file sees them; its renders, imported classes, class
hierarchies and registrations in ``project_view_*.py``).
"""

from __future__ import annotations

import os
from collections import defaultdict
from collections.abc import Container
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

from gymmigrate.facts.creator_tables import Field
from gymmigrate.facts.done_causes import DoneCause
from gymmigrate.facts.import_roots import import_parts, module_names, nearest_root
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.mode_handovers import join as join_mode_handovers
from gymmigrate.facts.module_summary import (
    NEW,
    OWN,
    REF,
    TABLE,
    UNRESOLVED,
    CallSummary,
    InitHeld,
    ModuleSummary,
    is_ref,
)
from gymmigrate.facts.project_classes import (
    inherit_driven_kinds,
    join_duck_wrappers,
    join_init_attributes,
    join_mode_renders,
    join_overrides,
    join_registered_classes,
    join_step_shapes,
    join_unmade_classes,
    join_unset_spaces,
    own_api_classes,
    quiet_classes,
    reexported,
)
from gymmigrate.facts.project_contracts import (
    NonSpaces,
    class_definer,
    class_methods,
    forwarding_wrappers,
    kept_resets,
    legacy_seeds,
    legacy_steps,
    modeless_renders,
    own_renders,
    render_definers,
    render_only_ids,
    seed_keepers,
    seeds_untraced,
    thread_render_mode,
    varargs_renders,
    wrapper_steppers,
)
from gymmigrate.facts.project_exports import (
    Exports,
    join_tables,
    join_thunk_factory_refs,
    reexport_wrappers,
    star_bindings,
)
from gymmigrate.facts.project_holders import join_made_holders, join_property_aliases
from gymmigrate.facts.project_hooks import join_hook_calls
from gymmigrate.facts.project_ids import id_slots
from gymmigrate.facts.project_imports import (
    env_modules_through_packages,
    imported_env_modules,
    imports_env_checker,
    join_import_components,
    join_nearby_packages,
    join_opaque_registrations,
    kept_mode_render,
    made_by_def,
    required_packages,
)
from gymmigrate.facts.project_params import ParamJoin, join_held
from gymmigrate.facts.project_view import ProjectView
from gymmigrate.facts.render_handovers import join as join_render_handovers
from gymmigrate.facts.reset_contract import Contract
from gymmigrate.facts.reset_contract import join as join_reset_sites

# How many package re-exports one name is followed through (``_resolve_reexported``).
_MAX_REEXPORT_HOPS = 8


def _read_for_its_load(summary: ModuleSummary) -> bool:
    return summary.masks_only and not (summary.bootstrap_masks or summary.record_classes or summary.plain_roots or summary.altered)


@dataclass
class ProjectFacts:
    """The run's joined facts; picklable, sent once to each worker with the options."""

    # (path, "Agent.fit", "env") -> the kinds other modules pass there
    param_kinds: dict[tuple[str, str, str], list[EnvKind]] = field(default_factory=dict)
    # ...and per call, the variable it hands on there ("caller path|Flow.source_of"), None for
    # anything else (an expression, the default): defs fed the same variables hold the same values
    param_sources: dict[tuple[str, str, str], tuple[str | None, ...]] = field(default_factory=dict)
    defs: dict[str, frozenset[str]] = field(default_factory=dict)  # path -> qualnames defined
    env_classes: dict[str, frozenset[str]] = field(default_factory=dict)  # path -> env classes
    wrapper_classes: dict[str, frozenset[str]] = field(default_factory=dict)  # path -> Gym wrapper classes
    wrapping_helpers: dict[str, dict[str, str]] = field(default_factory=dict)  # path -> def that wraps its argument -> that parameter
    gym_only_makers: dict[str, dict[str, str]] = field(default_factory=dict)  # path -> defs making a Gym-only stack's envs
    # path -> its PettingZoo wrapper classes (``ModuleSummary.pz_wrappers``)
    pz_wrappers: dict[str, dict[str, tuple[str, tuple[str, ...]]]] = field(default_factory=dict)
    spec_lists: dict[str, frozenset[str]] = field(default_factory=dict)  # path -> names bound to lists of EnvSpecs
    render_mode_classes: dict[str, frozenset[str]] = field(default_factory=dict)
    modules: dict[str, str] = field(default_factory=dict)  # dotted suffix -> path ("" if ambiguous)
    # dotted suffix -> every path it may name, where more than one does (see ``_module_path``)
    ambiguous: dict[str, tuple[str, ...]] = field(default_factory=dict)
    # Modules whose env classes an untraced ``x.seed(...)`` elsewhere in the run may reach.
    seed_called: set[str] = field(default_factory=set)
    # a module of the run calls ``x.configure(...)`` / ``x._configure(...)`` on other than self
    configure_called: bool = False
    # Some module of the run calls ``x.seed(...)`` / ``x._seed(...)`` on other than a library
    # module or a space (``ModuleSummary.calls_seed``): an env class's seed() may run.
    seed_used: bool = False
    # ...and one of those calls passes no seed (``ModuleSummary.calls_seed_without_a_value``)
    seed_used_without_a_value: bool = False
    # Some module of the run passes a reset a ``return_info`` mode (``ModuleSummary.passes_return_info``).
    return_info_passed: bool = False
    render_called: set[str] = field(default_factory=set)  # ...and an untraced ``x.render(mode)``
    # Modules with such a call -> (path, class) of the one env class of the run they reach
    # (``render_called``) whose own render() takes ``mode``, and the imported names that
    # build it there: that def keeps ``mode`` for them (GM405), so their calls ask its
    # question, not one of their own.
    kept_mode_renders: dict[str, tuple[str, str, frozenset[str]]] = field(default_factory=dict)
    # Some module imports Gym's (or Gymnasium's) ``check_env``, which tests in Gymnasium 1.x
    # that a seeded reset makes the steps reproducible (GM510).
    checks_envs: bool = False
    # Some module calls ``make(x.spec)`` or ``x.spec.make()`` (``ModuleSummary.recreates_from_spec``).
    recreates_from_spec: bool = False
    # Modules with env classes, and the modules of the run that import them.
    importers: dict[str, set[str]] = field(default_factory=dict)
    # (path, name) of the names of a module other modules call that resolve to no def there
    # (a class with no ``__init__`` of its own): ``ProjectView.built_elsewhere``
    called_elsewhere: set[tuple[str, str]] = field(default_factory=set)
    # the defs and classes of the run (path, qualname) another module calls, with or without arguments
    called_from_outside: set[tuple[str, str]] = field(default_factory=set)
    # ...of them, those another module calls other than as ``super().m(...)`` of a subclass
    # (which runs the base's method on the subclass's instance, and builds no base).
    built_from_outside: set[tuple[str, str]] = field(default_factory=set)
    # Modules the run leaves as they are (refused, skip-file), with the reason: their
    # classes count as unknown, so no other module is rewritten as if they had migrated.
    blocked: dict[str, str] = field(default_factory=dict)
    # (path, top-level name) -> what calling that name gives, re-exports and subclasses
    # across modules followed: ``pkg.make`` re-exported from ``utils.make = gym.make`` is a
    # Gym env factory, ``from hunt import HuntEnv`` a PettingZoo parallel env class.
    call_kinds: dict[tuple[str, str], EnvKind] = field(default_factory=dict)
    # (path, top-level name) of the Gym env factories among them whose every return is a
    # ``make(...)`` result (``ModuleSummary.made_factories``, re-exports followed).
    made: set[tuple[str, str]] = field(default_factory=set)
    # ...each with the def that makes it (path, name): where a render_mode its callers need goes.
    made_at: dict[tuple[str, str], tuple[str, str]] = field(default_factory=dict)
    # (path, top-level name) of the run's Gym env classes (re-exports and subclasses across
    # modules followed) that are no wrapper: an instance is the env itself, no stack.
    bare_env_classes: set[tuple[str, str]] = field(default_factory=set)
    # (path, top-level name) -> the library callable it stands for, re-exports followed.
    aliases: dict[tuple[str, str], str] = field(default_factory=dict)
    # (path, class) -> the methods subclasses in other modules of the run override, with
    # where ("pkg/far.py:FarEnv"): a hook a base class migrates must migrate there too.
    overrides: dict[tuple[str, str], dict[str, list[str]]] = field(default_factory=dict)
    # (path, class) -> its direct subclasses in other modules of the run, and (path, class)
    # -> the done causes of their methods, and of each value of the tuples they return
    # (``ModuleSummary.done_methods``, ``done_items``).
    subclasses_of: dict[tuple[str, str], list[tuple[str, str]]] = field(default_factory=dict)
    done_methods: dict[tuple[str, str], dict[str, DoneCause]] = field(default_factory=dict)
    done_items: dict[tuple[str, str], dict[str, tuple[DoneCause, ...]]] = field(default_factory=dict)
    subclass_methods: dict[tuple[str, str], frozenset[str]] = field(default_factory=dict)
    # (path, class) -> the methods its own methods call on a base (``ModuleSummary.super_calls``):
    # one it defines but never calls up replaces the base's for every instance below it.
    base_calls: dict[tuple[str, str], frozenset[str]] = field(default_factory=dict)
    # (path, class) -> the methods it calls as ``Cls.m(self, ...)`` (``ModuleSummary.named_class_calls``).
    named_calls: dict[tuple[str, str], frozenset[str]] = field(default_factory=dict)
    # (path, class) -> the ``self.<name>(...)`` its methods call (``ModuleSummary.self_calls``).
    self_calls: dict[tuple[str, str], frozenset[str]] = field(default_factory=dict)
    # (path, class) -> its bases of the run, resolved, in the order it names them; the gym
    # <= 0.9 hooks an env class of the run renames (``_reset``); and, per method the run may
    # remove or rename, the classes of other modules whose ``self.m(...)`` or
    # ``super().m(...)`` reaches it there, as "path:Class" (``facts/project_hooks.py``).
    class_bases: dict[tuple[str, str], tuple[tuple[str, str], ...]] = field(default_factory=dict)
    # path -> the names its classes derive that only its star imports of modules of the run
    # bind, each with the qualified name it stands for (``project_exports.star_bindings``):
    # the module is summarized and migrated with them bound (``ModuleFacts.star_bindings``).
    star_bindings: dict[str, dict[str, str]] = field(default_factory=dict)
    hook_renames: dict[tuple[str, str], frozenset[str]] = field(default_factory=dict)
    called_below: dict[tuple[str, str], dict[str, list[str]]] = field(default_factory=dict)
    # (path, top-level name) of a class of the run (or a re-export of one) -> the hooks a
    # lookup from it up finds first in a class that renames them
    renamed_above: dict[tuple[str, str], frozenset[str]] = field(default_factory=dict)
    # method name -> the modules of the run that call it on a receiver other than ``self``
    # (``ModuleSummary.instance_calls``).
    instance_calls: dict[str, list[str]] = field(default_factory=dict)
    # receiver name -> where the run calls ``<name>.contains(value)`` / ``x.<name>.contains(value)``
    # (path, line; ``ModuleSummary.contains_calls``)
    contains_calls: dict[str, list[tuple[str, int]]] = field(default_factory=dict)
    # where the run reads the mujoco-py MujocoEnv's API outside such a class (path, line;
    # ``ModuleSummary.mujoco_py_uses``)
    mujoco_py_uses: list[tuple[str, int]] = field(default_factory=list)
    # (path, class) of the classes whose ``__init__`` hands up to a base of another module
    # with ``super().__init__`` (``ModuleSummary.passes_init_up``): the base sees that call.
    init_passers: set[tuple[str, str]] = field(default_factory=set)
    # (path, class) -> the step hooks of the class (``return self.post_step(...)`` in its
    # step) that every override in another module can follow (facts/step_hooks.py).
    followed_hooks: dict[tuple[str, str], frozenset[str]] = field(default_factory=dict)
    # (path, class) whose own step is a helper returning the observation alone, on which
    # every override in the run builds its step; with the names that reach one (re-exports,
    # subclasses elsewhere that define no step); (path, class) whose step and those of the
    # classes of its module below it give five values once migrated (facts/own_steps.py).
    helper_steps: frozenset[tuple[str, str]] = frozenset()
    helper_step_names: frozenset[tuple[str, str]] = frozenset()
    five_step_trees: frozenset[tuple[str, str]] = frozenset()
    # every store of ``np_random`` in the run: (path, line, handed to another object, a Generator, class built just before)
    rng_stores: list[tuple[str, int, bool, bool, str]] = field(default_factory=list)
    # (path, class) of the run (and names re-exporting one) that counts no steps, nor does
    # any base of it, all of which the run defines (facts/step_counts.py; GM504).
    quiet_classes: frozenset[tuple[str, str]] = frozenset()
    # (path, class) of the run (and names re-exporting one) deriving a library class with
    # an env API of its own, in any module (``class Stacker(adapters.Adapter)``).
    own_api_classes: frozenset[tuple[str, str]] = frozenset()
    # (path, class) -> the flag that picks Gymnasium's shapes in that class of two APIs
    # (``ModuleSummary.own_api_flags``)
    own_api_flags: dict[tuple[str, str], str] = field(default_factory=dict)
    # constructors of a run class (path, line, column) that get render_mode="human" for the
    # bare renders of a def of another module every call of which passes their env, and
    # (path, def, parameter) of those renders -> the constructors (facts/render_handovers.py)
    render_mode_constructions: set[tuple[str, int, int]] = field(default_factory=set)
    settled_renders: dict[tuple[str, str, str], tuple[tuple[str, int, int], ...]] = field(default_factory=dict)
    # (path, line, column) of each ``gym.make`` handed only to calls whose renders ask one frame
    # mode in other modules -> that mode; (path, def, parameter) of those renders -> the mode
    # and the makes every call of the def passes (facts/mode_handovers.py)
    handed_render_modes: dict[tuple[str, int, int], str] = field(default_factory=dict)
    settled_mode_renders: dict[tuple[str, str, str], tuple[str, tuple[tuple[str, int, int], ...]]] = field(default_factory=dict)
    # (path, class) in another module -> the hooks of its bases it follows.
    inherited_hooks: dict[tuple[str, str], frozenset[str]] = field(default_factory=dict)
    # (path, name) of a Gym wrapper class of the run, or of a re-export of one -> what it
    # and its bases define for ``self`` (facts/wrapper_attributes.py).
    wrapper_defined: dict[tuple[str, str], frozenset[str]] = field(default_factory=dict)
    # (path, class) -> the ``self.render(mode)`` calls of its subclasses in other modules of
    # the run, at any depth, as ("pull.py:5", call): its render() keeps ``mode`` for them.
    mode_renders_below: dict[tuple[str, str], list[tuple[str, str]]] = field(default_factory=dict)
    # (path, top-level name) of the run's Gym wrapper classes (or re-exports of one) whose
    # reset/step render the env they wrap (``ModuleSummary.rendering_wrappers``).
    rendering_wrappers: frozenset[tuple[str, str]] = frozenset()
    # Modules that import a module of the run registering envs from data (entry points no
    # literal) -> a class of the run that keeps its legacy render(mode) and takes no
    # render_mode: a make there may build it, and render_mode= would be a TypeError.
    opaque_kept_renders: dict[str, str] = field(default_factory=dict)
    # (path, top-level name) of a class of the run (or a re-export of one) -> its methods
    # with those of its bases of the run (``project_contracts.class_methods``).
    class_methods: dict[tuple[str, str], frozenset[str]] = field(default_factory=dict)
    # Packages the migrated code imports that its dependency files must declare: ``mpe2``
    # where a module imports ``pettingzoo.mpe`` (PZ111 moves the import there).
    requires: frozenset[str] = frozenset()
    # ``gym.envs`` plugin entry points of the run's dependency files (GM111): the module
    # path -> the (function, namespace or None) calls to append to it, and the dependency
    # file's path -> entry target -> (the module that calls it, as shown, or None; why not).
    plugin_calls: dict[str, tuple[tuple[str, str | None], ...]] = field(default_factory=dict)
    plugin_routes: dict[str, dict[str, tuple[str | None, str]]] = field(default_factory=dict)
    # The Python programs of the run (modules and notebooks, realpaths), Gym code or not: a
    # dependency file's ``gym`` pin moves with the code beside it when the run holds it (GM109).
    programs: frozenset[str] = frozenset()
    # (path, top-level name) -> (space attribute, space class, what it derives from) for a
    # class (or a re-export of one) that sets a space to an instance of a class of the run
    # that is not a ``gymnasium.spaces.Space``: Gymnasium 1.x's env checker rejects it.
    non_space_envs: dict[tuple[str, str], tuple[str, str, str]] = field(default_factory=dict)
    # Those of them whose every base, at any depth, is a class of the run that ends in a
    # plain class of the run (``class Env(object)`` of a copy of another gym): no
    # gymnasium.Env at all, which ``gymnasium.make`` rejects before any checker runs ->
    # (that root class, its path).
    rootless_envs: dict[tuple[str, str], tuple[str, str]] = field(default_factory=dict)
    # (path, top-level name) of a class of the run (or a subclass at any depth, or a
    # re-export of one) -> the class whose reset steps the wrapper its instance was handed
    # (``project_contracts.wrapper_steppers``): Gymnasium 1.x's env checker raises on it.
    wrapper_steppers: dict[tuple[str, str], str] = field(default_factory=dict)
    # The env reset keywords the run's wrappers and callers pass down a chain: they move
    # into ``options`` at every site (``reset_contract.join``, GM207).
    reset_contract: Contract | None = None
    # (path, top-level name) of a class (or a re-export of one) whose step keeps the legacy
    # four-field contract after the run.
    legacy_steps: frozenset[tuple[str, str]] = frozenset()
    # (path, top-level name) of a class (or a re-export of one) whose reset, its own or a
    # base's of its module, the run keeps as it was, without seed/options: a subclass's
    # ``super().reset()`` passes it none.
    kept_resets: frozenset[tuple[str, str]] = frozenset()
    # (path, name) of an env class (or a re-export of one) whose render(mode) hands its mode
    # to an object of the project's own and that no render call of the run passes a mode to
    # nor a registration makes ``make`` reach (``project_contracts.own_renders``): it keeps
    # that render and takes no render_mode.
    own_renders: frozenset[tuple[str, str]] = frozenset()
    # (path, name) of an env class (or a re-export of one, or a subclass that defines no
    # render()) whose render() no render mode changes and that the run does not register
    # (``project_contracts.modeless_renders``): a bare render() of one asks for none.
    modeless_renders: frozenset[tuple[str, str]] = frozenset()
    # (path, name) of a class (or a re-export of one, or a subclass that defines no render())
    # whose render(self, *args) names no mode and stays (``project_contracts.varargs_renders``):
    # ``x.render("human")`` on an instance still works as it did.
    varargs_renders: frozenset[tuple[str, str]] = frozenset()
    # (path, name) of a Gym wrapper class (or a re-export of one) whose step and reset hand on
    # the wrapped env's results: around an instance of ``legacy_steps`` it keeps that contract.
    forwarding_wrappers: frozenset[tuple[str, str]] = frozenset()
    # (path, name) of a class of the run defining seed() (or a re-export or subclass of one),
    # and of what builds an instance holding one in its wrapper chain (``legacy_seeds``)
    seed_owners: frozenset[tuple[str, str]] = frozenset()
    seed_chains: frozenset[tuple[str, str]] = frozenset()
    silent_renders: frozenset[tuple[str, str]] = frozenset()  # (path, class) whose render() is a stub
    own_flag_steps: frozenset[tuple[str, str]] = frozenset()  # (path, class) whose step() draws on its own flags only
    # (path, class) -> the render modes its metadata declares, or None: it inherits those of
    # its one base (``ModuleSummary.frame_classes``)
    frame_classes: dict[tuple[str, str], tuple[str, ...] | None] = field(default_factory=dict)
    # (path, class) whose render() forwards bare to the env it holds, under each name re-exporting
    # it -> (path, line) of that forward
    render_forwards: dict[tuple[str, str], tuple[str, int]] = field(default_factory=dict)
    # Ids the run registers for an env class of the run whose constructor will not take
    # ``render_mode`` (its ``__init__`` cannot hand it on): id (None: not a literal) -> class.
    # ``gymnasium.make(id, render_mode=...)`` of one would raise TypeError.
    no_render_mode_ids: dict[str | None, str] = field(default_factory=dict)
    # ...each id's class as (path, class), and the literal ids among them whose class (or the
    # base of the run it inherits render() from) keeps a render(mode=<default>): a bare
    # render() of the made env, which Gymnasium's wrappers pass on with no arguments, still
    # draws in that default mode.
    no_render_mode_classes: dict[str | None, tuple[str, str]] = field(default_factory=dict)
    # ...and the paths of the modules whose register() calls name each of them: the id exists
    # in a process only once one of those modules has been imported there.
    no_render_mode_registrars: dict[str | None, set[str]] = field(default_factory=dict)
    default_mode_ids: frozenset[str] = frozenset()
    # (path, class) of the render() each of those literal ids reaches: a class the run leaves
    # whole keeps it, and gymnasium.make's wrappers expose render(self) only in front of it.
    registered_renders: frozenset[tuple[str, str]] = frozenset()
    # Env classes of the run that keep their own seed() (GM503: a module of the run calls
    # ``x.seed(...)`` on what it cannot trace), as (path, class), and the literal ids the run
    # registers for one of them: id -> class.
    seed_classes: frozenset[tuple[str, str]] = frozenset()
    seed_ids: dict[str, str] = field(default_factory=dict)
    # Literal ids the run registers for an env class whose drawing is its render() alone
    # (``ModuleSummary.render_only_classes``): id -> class.
    render_only_ids: dict[str, str] = field(default_factory=dict)
    # Gym wrapper classes of the run with a seed() of their own or of a base of the run, as
    # (path, class) where each is defined: Gymnasium's reset(seed=...) never calls it.
    seed_wrappers: frozenset[tuple[str, str]] = frozenset()
    # path -> the top-level packages the module imports, with those of the run's modules it
    # imports and of those that import it (one step each way): a project's neighbourhood,
    # not every project of a run over several.
    nearby_packages: dict[str, frozenset[str]] = field(default_factory=dict)
    # path -> one path that stands for the modules its imports connect it to, either way and
    # through any number of steps (``join_import_components``): one project of a run over several.
    import_components: dict[str, str] = field(default_factory=dict)
    # path -> the modules of the run its imports run (each package on an imported path
    # included), one step: what importing it imports (``ProjectView.imports_reach``).
    module_imports: dict[str, frozenset[str]] = field(default_factory=dict)
    # (path, "Agent.train_model") -> ``ModuleSummary.bootstrap_masks`` of that def, with
    # its parameters in order (a call passes them by position).
    bootstrap_masks: dict[tuple[str, str], tuple[tuple[str, ...], frozenset[tuple[str, str]]]] = field(default_factory=dict)
    # dotted suffix -> paths of the modules with no Gym code that have bootstrap masks (the
    # nearest to the importer counts when several); no module of the run for anything else.
    mask_modules: dict[str, tuple[str, ...]] = field(default_factory=dict)
    # path -> its top-level record classes (``ModuleSummary.record_classes``)
    record_classes: dict[str, frozenset[str]] = field(default_factory=dict)
    # path -> its top-level classes deriving only object or abc.ABC (``ModuleSummary.plain_roots``)
    plain_roots: dict[str, frozenset[str]] = field(default_factory=dict)
    # path -> its defs and classes that use what only an Atari env has (``ModuleSummary.atari_users``)
    atari_users: dict[str, frozenset[str]] = field(default_factory=dict)
    # (path, plain class, attribute) -> the kind every construction of the run passes to the
    # ``__init__`` parameter the attribute holds (``ModuleSummary.held_params``), where all
    # agree on a Gym env: ``holder.gym_env`` of an instance made anywhere is that env.
    held_kinds: dict[tuple[str, str, str], EnvKind] = field(default_factory=dict)
    # (path, name of a class of the run, re-exports followed) -> the kinds of the attributes
    # the class resets or steps and settles itself (``ModuleSummary.driven_kinds``)
    driven_kinds: dict[tuple[str, str], dict[str, EnvKind]] = field(default_factory=dict)
    # (path, plain class, attribute) -> (the ``__init__`` parameter it holds, its position in a
    # call): where a caller's construction passes what ``holder.attribute`` is (creation sites).
    held_slots: dict[tuple[str, str, str], tuple[str, int]] = field(default_factory=dict)
    # (path, name of a class of the run, re-exports followed) -> the attributes its instances
    # hold a bare make result in (``ModuleSummary.made_holders``)
    made_holders: dict[tuple[str, str], frozenset[str]] = field(default_factory=dict)
    # conftest.py path -> its fixtures (``ModuleSummary.fixtures``): what the tests below it
    # take by parameter name (``ProjectView.fixture_kind``, ``fixture_origin``)
    fixtures: dict[str, dict[str, tuple[str, tuple[str, ...]]]] = field(default_factory=dict)
    # (path, qualname, parameter) -> the attributes holding a bare make result in what every
    # call of another module passes there (``CallSummary.holders``; empty where a call passes
    # anything else); only parameters such calls reach (``project_holders.py``).
    held_made: dict[tuple[str, str, str], frozenset[str]] = field(default_factory=dict)
    # (path, name of a class of the run, re-exports followed) -> {property: attribute of self it
    # only returns}, its own and its bases' of the run (``ModuleSummary.property_aliases``)
    property_aliases: dict[tuple[str, str], dict[str, str]] = field(default_factory=dict)
    # Modules of the run that import legacy ``gym``: the envs they make are legacy Gym envs,
    # wherever they are rendered (a driver that never names gym).
    legacy_gym: frozenset[str] = frozenset()
    # (path, top-level def, parameter) -> per call of it in another module, the env id
    # passed there ("" for its default, None for no id literal), for the defs another
    # module calls (``CallSummary.ids``). GM106 settles an Atari helper from them.
    passed_ids: dict[tuple[str, str, str], tuple[str | None, ...]] = field(default_factory=dict)
    # (path, qualname, parameter) -> per call of it in another module, the class of the run
    # whose step and reset keep their own contract (``legacy_steps``) it passes an instance
    # of, None for anything else; only parameters some call passes one to.
    kept_params: dict[tuple[str, str, str], tuple[str | None, ...]] = field(default_factory=dict)
    # (path, qualname, parameter) -> per call of it in another module (as ``param_kinds``),
    # what calling each item of the list of thunks passed there returns (``CallSummary.thunks``;
    # unknown for any other argument).
    thunk_kinds: dict[tuple[str, str, str], list[EnvKind]] = field(default_factory=dict)
    # (path, qualname, parameter) -> per call of it in another module (as ``thunk_kinds``),
    # the Gym-only library stack every thunk passed there makes an env of, None where not
    # one (``CallSummary.thunk_stacks``).
    thunk_stacks: dict[tuple[str, str, str], list[str | None]] = field(default_factory=dict)
    # (path, qualname, parameter) -> per call of it in another module (as ``param_kinds``),
    # the kind of every item of the list passed there (``CallSummary.items``; unknown for
    # any other argument).
    item_kinds: dict[tuple[str, str, str], list[EnvKind]] = field(default_factory=dict)
    # (path, qualname, parameter) -> per call of it in another module (as ``param_kinds``),
    # what calling the class or other creator passed there gives (``CallSummary.creators``;
    # unknown for any other argument).
    creator_kinds: dict[tuple[str, str, str], list[EnvKind]] = field(default_factory=dict)
    # (path, class, attribute) -> the ``__init__`` parameter the attribute holds, its
    # position in a call and whether the class is a Gym env wrapper written by hand around it
    # (``ModuleSummary.init_held``), for every class, subclassed or not: a subclass elsewhere
    # that hands its own parameter up there holds that in the attribute (read as such, or
    # through a property returning it: ``property_aliases``).
    init_held: dict[tuple[str, str, str], InitHeld] = field(default_factory=dict)
    # path -> its top-level defs returning a thunk -> what that thunk returns (modules left
    # as they are give none: their thunks keep the old API)
    thunk_factories: dict[str, dict[str, EnvKind]] = field(default_factory=dict)
    # path -> its top-level defs returning a thunk as an item of a tuple -> (index, size,
    # what that thunk returns), and those whose thunk returns make() results -> which item
    # (None: the whole return); modules left as they are give none (``ModuleSummary.thunk_items``)
    thunk_items: dict[str, dict[str, tuple[int, int, EnvKind]]] = field(default_factory=dict)
    made_thunks: dict[str, dict[str, tuple[int, int] | None]] = field(default_factory=dict)
    # (path, table, field) -> what calling through that closed table of creators gives
    # (``join_tables``; field "" for its values themselves)
    table_kinds: dict[tuple[str, str, Field], EnvKind] = field(default_factory=dict)
    # ...and those whose every callable there returns a ``make(...)`` result: a wrapper stack
    made_tables: set[tuple[str, str, Field]] = field(default_factory=set)
    # (path, top-level name) another module writes into (``T[k] = v``): no closed table
    altered_tables: frozenset[tuple[str, str]] = frozenset()
    # (path, qualname, parameter) -> (caller path, line) of each call in another module that
    # passes a Gym env there: where that env is made, for a message (a render whose make
    # is in the run script).
    gym_env_callers: dict[tuple[str, str, str], tuple[tuple[str, int], ...]] = field(default_factory=dict)
    # ...and of each that hands on a parameter of its own def (or what its class holds from
    # one) that some call further up gives a Gym env, the others what the run cannot tell:
    # where the reads of a held env must be asked about, not left in silence.
    gym_env_handers: dict[tuple[str, str, str], tuple[tuple[str, int], ...]] = field(default_factory=dict)
    # the same for the calls that pass an env of another kind (a VecEnv, a test double with
    # an API of its own): whether those are only tests decides what a made env's reads need.
    other_env_callers: dict[tuple[str, str, str], tuple[tuple[str, int], ...]] = field(default_factory=dict)
    # caller path -> (line, argument position or keyword) of its calls that pass an env id
    # literal to a def of the run that makes it (``facts/project_ids.py``)
    id_slots: dict[str, frozenset[tuple[int, str]]] = field(default_factory=dict)
    # (path, qualname) -> the parameters whose value goes on (``ModuleSummary.escaping_params``),
    # and every def's parameters (``Signature.params``), to place a call's arguments
    escaping_params: dict[tuple[str, str], frozenset[str]] = field(default_factory=dict)
    def_params: dict[tuple[str, str], tuple[str, ...]] = field(default_factory=dict)
    # (path, top-level name) another module reads as a value, not called (``handed_on``)
    handed_on: set[tuple[str, str]] = field(default_factory=set)
    # (path, class) the run registers as an ``entry_point`` with the Gym registry: a Gym env
    # class, however it is constructed
    registered_classes: set[tuple[str, str]] = field(default_factory=set)
    # (path, class) an entry point makes (the class, or one a registered def constructs)
    # -> the spaces it leaves unset with its bases: ``gymnasium.make``'s env checker raises
    unset_spaces: dict[tuple[str, str], frozenset[str]] = field(default_factory=dict)
    # those of them whose every registration has a literal id that no module of the run
    # names, where every make() of the run passes a literal id: nothing of the run makes them
    unmade_classes: set[tuple[str, str]] = field(default_factory=set)
    # GM511 asked once per hierarchy: a made class -> the highest base of the run it inherits
    # the unset spaces from (``join_unset_spaces``), and that base -> those made classes.
    unset_owner: dict[tuple[str, str], tuple[str, str]] = field(default_factory=dict)
    unset_heirs: dict[tuple[str, str], list[tuple[str, str]]] = field(default_factory=dict)
    # the ids the run registers with the Gym registry (None: one it registers is no literal)
    registered_ids: set[str | None] = field(default_factory=set)
    # literal id -> the class of the run its entry point names (path, class), where every
    # registration of that id names the same one
    id_classes: dict[str, tuple[str, str]] = field(default_factory=dict)
    # Some module registers envs whose entry points are no literal (``opaque_registrations``):
    # an id made anywhere may then build any env class of the run.
    registers_from_data: bool = False
    # Some module loads an earlier run's policy, weights or normaliser: an env id the run
    # bumps may be made for that model (an evaluation script reaching another module's task).
    loads_saved_state: bool = False
    # ...and the modules a loading module reaches through its imports (itself included): an
    # env id of a module outside them is made by no program that loads a model for it
    load_reach: frozenset[str] = frozenset()
    # Every env-id-shaped string of the run's modules (``ModuleSummary.named_ids``)
    named_ids: frozenset[str] = frozenset()
    # (path, name of a class of the run, re-exports followed) -> the attributes its instances
    # certainly hold once constructed (``facts/init_attributes.py``; none: not listed)
    init_attributes: dict[tuple[str, str], frozenset[str]] = field(default_factory=dict)

    @classmethod
    def join(cls, summaries: list[ModuleSummary], blocked: dict[str, str] | None = None) -> ProjectFacts:
        facts = cls()
        # Gym code or not: an evaluation script loads the model into another module's task.
        # A Gym-free module read for that alone tells the run nothing else.
        facts.loads_saved_state = any(summary.loads_saved_state for summary in summaries)
        loaders = [summary for summary in summaries if summary.loads_saved_state]
        everything = {summary.path: summary for summary in summaries}
        summaries = [s for s in summaries if not _read_for_its_load(s)]
        facts.blocked = dict(blocked or {})
        facts.blocked.update(
            (s.path, "it says `# gymmigrate: skip-file`") for s in summaries if s.skips_file and s.path not in facts.blocked
        )
        for summary in summaries:
            for qualname, masks in summary.bootstrap_masks.items():
                facts.bootstrap_masks[(summary.path, qualname)] = (summary.defs[qualname].params, masks)
            if summary.record_classes:
                facts.record_classes[summary.path] = summary.record_classes
            for name, flag in summary.own_api_flags.items():
                facts.own_api_flags[(summary.path, name)] = flag
            if summary.plain_roots:
                facts.plain_roots[summary.path] = summary.plain_roots
            if summary.masks_only:
                for name in module_names(summary.path):
                    facts.mask_modules[name] = (*facts.mask_modules.get(name, ()), summary.path)
        # every module that writes into a name it imports, Gym code or not (``join_tables``)
        altered = [(s.path, q) for s in summaries for q in s.altered]
        summaries = [s for s in summaries if not s.masks_only]
        by_path = {s.path: s for s in summaries}
        facts.named_ids = frozenset().union(*(s.named_ids for s in summaries))
        for summary in summaries:
            facts.defs[summary.path] = frozenset(summary.defs)
            left = summary.path in facts.blocked
            facts.env_classes[summary.path] = frozenset() if left else summary.env_classes
            facts.wrapper_classes[summary.path] = frozenset() if left else summary.wrapper_classes
            facts.wrapping_helpers[summary.path] = {} if left else summary.wrapping_helpers
            if summary.gym_only_makers:
                facts.gym_only_makers[summary.path] = summary.gym_only_makers
            if summary.thunk_factories and not left:
                facts.thunk_factories[summary.path] = summary.thunk_factories
            if summary.thunk_items and not left:
                facts.thunk_items[summary.path] = summary.thunk_items
            if summary.made_thunks and not left:
                facts.made_thunks[summary.path] = summary.made_thunks
            if summary.atari_users:
                facts.atari_users[summary.path] = summary.atari_users
            facts.pz_wrappers[summary.path] = summary.pz_wrappers
            facts.spec_lists[summary.path] = summary.spec_lists
            facts.render_mode_classes[summary.path] = frozenset() if left else summary.render_mode_classes
            if summary.fixtures and not left:
                facts.fixtures[summary.path] = summary.fixtures
            if summary.path.endswith(".ipynb"):
                continue  # a notebook calls the run's modules; nothing imports it
            for name in module_names(summary.path):
                if name in facts.modules and facts.modules[name] != summary.path:
                    previous = facts.ambiguous.get(name) or (facts.modules[name],)
                    facts.ambiguous[name] = (*previous, summary.path)
                    facts.modules[name] = ""
                else:
                    facts.modules[name] = summary.path
        facts.load_reach = facts._reached_by(loaders, everything)
        methods_named: dict[str, list[tuple[str, str]]] = defaultdict(list)
        for summary in summaries:
            for qualname, signature in summary.defs.items():
                if signature.is_method:
                    methods_named[qualname.rsplit(".", 1)[1]].append((summary.path, qualname))
        calls_to: dict[tuple[str, str], list[tuple[str, CallSummary]]] = defaultdict(list)
        for summary in summaries:
            for call in summary.calls:
                if call.target.startswith(UNRESOLVED):
                    # A VecEnv passed to some ``x.fit``: every ``fit`` of the run may get it.
                    for path, qualname in methods_named.get(call.target[len(UNRESOLVED) :], ()):
                        calls_to[(path, qualname)].append((summary.path, call))
                    continue
                if call.target.startswith(TABLE):
                    # ``AGENTS[kind](...)``: a call of each class or def the table holds
                    for target in facts._table_targets(call.target[len(TABLE) :], summary.path, by_path):
                        calls_to[target].append((summary.path, call))
                    continue
                if call.target.startswith(OWN):
                    qualname = call.target[len(OWN) :]
                    if qualname in summary.defs:
                        calls_to[(summary.path, qualname)].append((summary.path, call))
                    continue
                resolved = facts._resolve(call.target, summary.path) or facts._resolve_reexported(call.target, summary.path, by_path)
                if resolved is not None:
                    calls_to[resolved].append((summary.path, call))
                else:
                    # a class of another module that defines no ``__init__`` of its own
                    # (``wrappers.Clip(env)``): built there with what this call passes
                    split = facts._split(call.target, summary.path)
                    if split is not None and split[0] != summary.path:
                        facts.called_elsewhere.add(split)
        facts.called_from_outside = {key for key, calls in calls_to.items() if any(caller != key[0] for caller, _ in calls)}
        facts.built_from_outside = {
            key for key, calls in calls_to.items() if any(caller != key[0] and not call.up for caller, call in calls)
        }
        imported = {q for summary in summaries for q in summary.imported}
        facts.checks_envs = any(imports_env_checker(q) for q in imported)
        facts.recreates_from_spec = any(s.recreates_from_spec for s in summaries)
        facts.legacy_gym = frozenset(s.path for s in summaries if any(q == "gym" or q.startswith("gym.") for q in s.imported))
        join_nearby_packages(facts, summaries)
        join_import_components(facts, summaries)
        facts.requires = required_packages(imported)
        join_registered_classes(facts, by_path)
        join_unset_spaces(facts, by_path)
        join_unmade_classes(facts, by_path)
        facts.registers_from_data = any(summary.opaque_registrations for summary in summaries)
        Exports(facts, by_path).run()
        facts.star_bindings = star_bindings(facts, by_path)
        join_tables(facts, by_path, altered)
        facts.own_renders = own_renders(facts, by_path)
        facts.modeless_renders = modeless_renders(facts, by_path)
        facts.varargs_renders = varargs_renders(facts, by_path)
        for path, name in facts.own_renders:  # they keep render(mode): no render_mode to pass
            facts.render_mode_classes[path] = facts.render_mode_classes.get(path, frozenset()) - {name}
        # before the parameters: an argument made by such a class keeps the def's calls on its contract
        facts.forwarding_wrappers = forwarding_wrappers(facts, by_path)
        facts.legacy_steps = legacy_steps(facts, by_path)
        facts.kept_resets = kept_resets(facts, by_path)
        join_thunk_factory_refs(facts, by_path)  # after legacy_steps: a class kept on the old step is no Gym env to them
        facts.seed_owners, facts.seed_chains = legacy_seeds(facts, by_path)
        params = ParamJoin(facts, by_path, calls_to)
        params.run()
        join_made_holders(facts, by_path, calls_to)
        join_property_aliases(facts, by_path)
        join_duck_wrappers(facts, by_path)
        join_render_handovers(facts, by_path, calls_to)
        id_calls_to = {key: list(calls) for key, calls in calls_to.items()}
        for summary in summaries:
            for call in summary.inherited_id_calls:
                resolved = facts._resolve(call.target, summary.path) or facts._resolve_reexported(call.target, summary.path, by_path)
                if resolved is not None:
                    id_calls_to.setdefault(resolved, []).append((summary.path, call))
        facts.id_slots = id_slots(by_path, id_calls_to)
        facts.escaping_params = {(path, q): names for path, summary in by_path.items() for q, names in summary.escaping_params.items()}
        facts.def_params = {(path, q): signature.params for path, summary in by_path.items() for q, signature in summary.defs.items()}
        render_callers: list[ModuleSummary] = []
        for summary in summaries:
            facts.rng_stores.extend((summary.path, *store) for store in summary.rng_stores)
            if seeds_untraced(facts, summary):
                facts.seed_called.update(imported_env_modules(facts, summary))
            facts.configure_called = facts.configure_called or summary.calls_configure
            facts.seed_used = facts.seed_used or summary.calls_seed
            facts.seed_used_without_a_value = facts.seed_used_without_a_value or summary.calls_seed_without_a_value
            facts.return_info_passed = facts.return_info_passed or summary.passes_return_info
            if summary.untraced_render_call or any(made_by_def(facts, maker, summary.path, by_path) for maker in summary.render_makers):
                # ``import pkg`` reaches the env classes ``pkg/__init__.py`` imports too
                # (``env = pkg.make_benchmark(...)``; ``env.render(mode="readable")``)
                facts.render_called.update(env_modules_through_packages(facts, summary, by_path))
                render_callers.append(summary)
            for provider in imported_env_modules(facts, summary, declared=by_path):
                facts.importers.setdefault(provider, set()).add(summary.path)
        for summary in render_callers:
            kept = kept_mode_render(facts, summary, by_path)
            if kept is not None:
                facts.kept_mode_renders[summary.path] = kept
        for path in facts.render_called:
            # Their classes keep render(mode): one whose ``mode`` can become optional takes
            # render_mode beside it (custom_env/render.py), one whose cannot takes none.
            facts.render_mode_classes[path] = facts.render_mode_classes.get(path, frozenset()) - by_path[path].fixed_mode_renders
        join_overrides(facts, summaries, by_path)
        join_mode_renders(facts, by_path)
        thread_render_mode(facts, by_path)
        join_held(facts, by_path, params)
        for summary in summaries:
            for qualified in summary.handed_on:
                resolved = facts._resolve(qualified, summary.path)
                if resolved is not None:
                    facts.handed_on.add(resolved)
        facts.class_methods = class_methods(facts, by_path)
        join_hook_calls(facts, by_path)  # after the class methods: a base elsewhere may define the public name
        definers = render_definers(facts, by_path)
        facts.default_mode_ids = frozenset(i for i, (path, name) in definers.items() if name in by_path[path].default_mode_renders)
        facts.registered_renders = frozenset(definers.values())
        join_init_attributes(facts, by_path)
        driven = inherit_driven_kinds(facts, by_path)
        for path, summary in by_path.items():
            for name in summary.exports:
                where = class_definer(facts, by_path, path, name)
                if where is not None and where[1] in by_path[where[0]].wrapper_defined:
                    facts.wrapper_defined[(path, name)] = by_path[where[0]].wrapper_defined[where[1]]
                if where is not None and where in driven:
                    facts.driven_kinds[(path, name)] = driven[where]
        facts.seed_classes, facts.seed_ids = seed_keepers(facts, by_path)
        facts.render_only_ids = render_only_ids(facts, by_path)
        NonSpaces(facts, by_path).run()
        facts.wrapper_steppers = wrapper_steppers(facts, by_path)
        facts.reset_contract = join_reset_sites(
            [(path, s.reset_sites) for path, s in by_path.items() if path not in facts.blocked],
            lambda path, name: facts.call_kinds.get((path, name)) is EnvKind.GYM_ENV,
        )
        reexport_wrappers(facts, by_path)
        # where each is defined (re-exports and factories of one are not the class)
        facts.seed_wrappers = frozenset(
            (path, name)
            for path, names in facts.wrapper_classes.items()
            if path not in facts.blocked and path in by_path
            for name in names
            if name in by_path[path].classes and "seed" in facts.class_methods.get((path, name), ())
        )
        join_opaque_registrations(facts, by_path)
        facts.rendering_wrappers = reexported(facts, by_path, {(p, n) for p, summary in by_path.items() for n in summary.rendering_wrappers})
        facts.silent_renders = frozenset((path, name) for path, summary in by_path.items() for name in summary.silent_renders)
        facts.own_flag_steps = frozenset((path, name) for path, summary in by_path.items() for name in summary.own_flag_steps)
        facts.frame_classes = {(path, name): modes for path, summary in by_path.items() for name, modes in summary.frame_classes.items()}
        # each forward under every name of the run that re-exports its class (few classes have one)
        facts.render_forwards = {
            alias: (path, line)
            for path, summary in by_path.items()
            for name, line in summary.render_forwards.items()
            for alias in reexported(facts, by_path, {(path, name)})
        }
        facts.quiet_classes = reexported(facts, by_path, quiet_classes(facts, by_path))
        facts.own_api_classes = reexported(facts, by_path, own_api_classes(facts, by_path))
        join_step_shapes(facts, by_path)  # after the overrides, call kinds, kept steps and own APIs
        # after the registrations: a make that may build a class taking no render_mode gets none
        join_mode_handovers(facts, by_path, calls_to, set(facts.subclasses_of))
        return facts

    def _table_targets(self, qualified: str, importer: str, by_path: dict[str, ModuleSummary]) -> list[tuple[str, str]]:
        """The defs (a class: its ``__init__``) of the run that a call through the closed table
        ``qualified`` (as ``importer`` imports it) may reach: its values that name one."""
        split = self._split(qualified, importer)
        summary = by_path.get(split[0]) if split is not None else None
        if split is None or summary is None:
            return []
        found = []
        for value in summary.tables.get((split[1], ""), ()):
            if is_ref(value):
                target = self._resolve(value[len(REF) :], split[0]) or self._resolve_reexported(value[len(REF) :], split[0], by_path)
                if target is not None and target not in found:
                    found.append(target)
        return found

    def _class_kind(self, kind: str, importer: str) -> EnvKind:
        """``new:envs.GridEnv`` is a Gym env when ``GridEnv`` is an env class of the run (or
        derives from one, or is re-exported); a PettingZoo env class of the run likewise."""
        name = kind[len(NEW) :]
        if name.startswith(OWN):
            # ``@create_env``: a def of the importer itself, whose returns other modules decide
            own = self.call_kinds.get((importer, name[len(OWN) :]))
            if own is None:
                return EnvKind.UNKNOWN
            return EnvKind.OWN_API if own is EnvKind.NOT_ENV else own  # (as for a plain class, below)
        found = self.view(importer).call_kind(name)
        if found is not None and found is not EnvKind.NOT_ENV:
            return found
        imported = self.view(importer).imported_class(kind[len(NEW) :])
        if imported is not None and imported[0]:
            return EnvKind.GYM_ENV
        # A plain class of the run (a helper ``Environment`` around a Gym env, with reset/step
        # of its own): no call on its instances is rewritten. Not NOT_ENV, which a join lets
        # a Gym env of another caller outweigh: a def given both is asked about.
        return EnvKind.OWN_API if found is EnvKind.NOT_ENV else EnvKind.UNKNOWN

    def thunk_factory(self, qualified: str, importer: str) -> EnvKind | None:
        """What the thunk returned by the def of the run ``qualified`` names (as ``importer``
        imports it) returns; None when it is no such def."""
        split = self._split(qualified, importer)
        return None if split is None else self.thunk_factories.get(split[0], {}).get(split[1])

    def thunk_item_kind(self, qualified: str, importer: str, index: int, size: int | None) -> EnvKind | None:
        """What the thunk at ``index`` of the tuple the def of the run ``qualified`` returns
        gives when called (``size``: the number of names it is unpacked to, None for any);
        None when it is no such def or the item is another."""
        split = self._split(qualified, importer)
        found = None if split is None else self.thunk_items.get(split[0], {}).get(split[1])
        if found is None or found[0] != index or (size is not None and found[1] != size):
            return None
        return found[2]

    def thunk_made(self, qualified: str, importer: str, item: tuple[int, int | None] | None) -> bool:
        """The thunk the def of the run ``qualified`` returns (``item`` None), or holds at
        ``item`` (index, size: None for any) of the tuple it returns, returns make() results."""
        split = self._split(qualified, importer)
        if split is None or split[1] not in self.made_thunks.get(split[0], {}):
            return False
        found = self.made_thunks[split[0]][split[1]]
        if item is None or found is None:
            return item is None and found is None
        return found[0] == item[0] and (item[1] is None or found[1] == item[1])

    def _split(self, qualified: str, importer: str) -> tuple[str, str] | None:
        """``("/run/pkg/utils.py", "make")`` for ``pkg.utils.make`` (or ``.utils.make``)."""
        level, parts = import_parts(qualified)
        if level and not parts:
            # A bare package name (``.``) has always split into the package's ``__init__.py``
            # and an empty name, which ``defines`` and ``call_kind`` tell from None. No caller
            # passes one today (star imports go to ``_module_path``), but the answer is kept.
            path = self._module_path([], level, importer)
            return (path, "") if path else None
        for cut in range(len(parts) - 1, -1, -1):
            if cut == 0 and level == 0:
                break
            path = self._module_path(parts[:cut], level, importer)
            if path and cut < len(parts):
                return path, ".".join(parts[cut:])
        return None

    def _resolve_reexported(self, target: str, importer: str, by_path: dict[str, ModuleSummary]) -> tuple[str, str] | None:
        """``_resolve`` of a target whose first name a package re-exports (``sacd.agent.Agent``
        with ``from .agent import Agent`` in ``sacd/agent/__init__.py``): the def or
        ``__init__`` it stands for, each re-export followed once."""
        split = self._split(target, importer)
        seen: set[tuple[str, str]] = set()
        # A re-export may name itself with a longer tail each hop (``pkg.x`` -> ``pkg.x.x``),
        # which ``seen`` alone never stops: a chain of re-exports is short in real packages.
        while split is not None and split not in seen and split[0] in by_path and len(seen) < _MAX_REEXPORT_HOPS:
            seen.add(split)
            path, rest = split
            name, dot, tail = rest.partition(".")
            export = by_path[path].exports.get(name)
            if not is_ref(export):
                return None
            qualified = export[len(REF) :] + dot + tail  # type: ignore[index]
            found = self._resolve(qualified, path)
            if found is not None:
                return found
            split = self._split(qualified, path)
        return None

    def _resolve(self, target: str, importer: str) -> tuple[str, str] | None:
        """``("/run/agent.py", "Agent.fit")`` for ``agent.Agent.fit``; a class called is its ``__init__``."""
        level, parts = import_parts(target)
        for cut in range(len(parts) - 1, 0, -1):
            module, rest = parts[:cut], parts[cut:]
            path = self._module_path(module, level, importer)
            if not path:
                continue
            defined = self.defs.get(path, frozenset())
            qualname = ".".join(rest)
            if qualname in defined:
                return path, qualname
            if f"{qualname}.__init__" in defined:
                return path, f"{qualname}.__init__"
            return None
        return None

    def _reached_by(self, starts: list[ModuleSummary], everything: dict[str, ModuleSummary]) -> frozenset[str]:
        """The paths of ``starts`` and of every module of the run they import, followed on
        through the imports of those."""
        reached = {summary.path for summary in starts}
        pending = list(starts)
        while pending:
            summary = pending.pop()
            for qualified in summary.imported:
                level, parts = import_parts(qualified)
                for module in (parts, parts[:-1]):  # `import envs` / `from envs import make_env`
                    path = self._module_path(module, level, summary.path, everything) if module or level else None
                    if path is not None and path not in reached and path in everything:
                        reached.add(path)
                        pending.append(everything[path])
        return frozenset(reached)

    def _module_path(self, module: list[str], level: int, importer: str, known: Container[str] | None = None) -> str | None:
        """The path of the module an import of ``importer`` names; a relative one is looked
        up among ``known`` paths (default: the modules with Gym code, ``defs``)."""
        known = self.defs if known is None else known
        if level == 0:
            dotted = ".".join(module)
            found = self.modules.get(dotted)
            if found == "":
                return nearest_root(self.ambiguous.get(dotted, ()), len(module), importer)
            return found or None
        base = Path(importer).parent
        for _ in range(level - 1):
            base = base.parent
        candidate = base.joinpath(*module)
        if not module:  # ``from . import x``: the package itself
            path = str(base / "__init__.py")
            return path if path in known else None
        for path in (f"{candidate}.py", str(candidate / "__init__.py")):
            if path in known:
                return path
        return None

    def view(self, path: str) -> ProjectView:
        return ProjectView(self, os.path.realpath(path))

    @cached_property
    def multi_agent_passed(self) -> frozenset[str]:
        """The modules that another module of the run passes a PettingZoo env
        (``ProjectView.passed_multi_agent``): asked by every file, listed once."""
        multi_agent = (EnvKind.PZ_AEC, EnvKind.PZ_PARALLEL)
        return frozenset(path for (path, _, _), kinds in self.param_kinds.items() if any(k in multi_agent for k in kinds))
