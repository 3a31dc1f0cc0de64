"""One module's summary for the facts across the run (``facts/project.py`` joins it; the
record is ``facts/module_summary.py``): its defs, its env classes, and the ``EnvKind`` of
each argument it passes into other modules.

Pure: text in, ``ModuleSummary`` out. Reading the files of a run, and mapping this over
them on the worker pool, is the runner's.

This module puts the summary together; each part is asked of its own module:
``calls`` (the calls into the run and what they pass), ``untraced`` (seed and render
calls on receivers the module cannot trace), ``exports`` (what its top-level names give),
``defs`` (its top-level defs and names) and ``classes`` (its top-level classes).
"""

from __future__ import annotations

import ast
import os
from collections.abc import Mapping
from dataclasses import replace

from gymmigrate.facts import pz_wrappers
from gymmigrate.facts.atari_signs import atari_users
from gymmigrate.facts.class_shapes import renders_nothing
from gymmigrate.facts.creator_tables import altered_imports, writes_into_import
from gymmigrate.facts.done_uses import top_level_records
from gymmigrate.facts.env_classes import EnvClasses
from gymmigrate.facts.env_specs import module_spec_lists, recreates_from_spec
from gymmigrate.facts.frame_modes import frame_classes
from gymmigrate.facts.id_params import escaping_parameters, id_parameters
from gymmigrate.facts.init_attributes import module_class_stores
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.made_holders import made_holders
from gymmigrate.facts.mode_handovers import param_renders
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts
from gymmigrate.facts.module_summary import ModuleSummary, Signature
from gymmigrate.facts.own_api import gymnasium_flag, own_api_shape
from gymmigrate.facts.own_steps import (
    five_step_trees,
    helper_candidates,
    helper_hand_ons,
    own_step_shapes,
)
from gymmigrate.facts.receiver_classes import duck_wrapper_param
from gymmigrate.facts.receivers import Receivers
from gymmigrate.facts.render_handovers import bare_render_params, handed_constructions
from gymmigrate.facts.render_modes import (
    draws_only_in_render,
    render_kept_classes,
    steps_draw_on_own_flags,
)
from gymmigrate.facts.reset_contract import sites as reset_sites
from gymmigrate.facts.rng_handovers import rng_stores
from gymmigrate.facts.space_setters import (
    checked_entries,
    def_builds,
    module_unset_spaces,
    runs_base_init,
)
from gymmigrate.facts.step_counts import step_counting
from gymmigrate.facts.step_hooks import plain_overrides, step_hooks
from gymmigrate.facts.summaries.calls import CallSummarizer
from gymmigrate.facts.summaries.classes import (
    contains_calls,
    default_mode_renders,
    done_methods,
    driven_kinds,
    fixed_mode_renders,
    held_params,
    init_held,
    instance_calls,
    mode_renders,
    modeless_renders,
    mujoco_py_uses,
    named_class_calls,
    own_renders,
    plain_classes,
    plain_roots,
    property_aliases,
    renamed_hooks,
    render_forwards,
    render_mode_heirs,
    rendering_wrappers,
    run_bases,
    self_calls,
    space_calls,
    stored_attributes,
    subclasses,
    super_calls,
    varargs_renders,
)
from gymmigrate.facts.summaries.defs import (
    bootstrap_masks,
    gym_only_makers,
    handed_on,
    loads_model_for_the_run,
    loads_saved_state,
    made_factories,
    made_thunks,
    masks_of,
    named_ids,
    opaque_registrations,
    registered_ids,
    registrations,
    signature,
)
from gymmigrate.facts.summaries.exports import Exports, declared_all, star_bases
from gymmigrate.facts.summaries.fixtures import conftest_fixtures
from gymmigrate.facts.summaries.untraced import (
    UntracedCalls,
    calls_from_outside,
    calls_seed,
    calls_seed_without_a_value,
    passes_return_info,
)
from gymmigrate.facts.wrapper_attributes import wrapper_defined
from gymmigrate.facts.wrapper_steps import module_reset_steps, self_handoffs
from gymmigrate.source_text import first_statement_line
from gymmigrate.suppressions import skips_file

__all__ = ["loads_saved_state", "plain_classes", "space_calls", "summarize", "summarize_masks"]


def summarize(path: str, text: str, star_bindings: Mapping[str, str] | None = None) -> ModuleSummary | None:
    """The summary of one module's text (already screened by its reader), or None when it
    does not parse. ``star_bindings``: the names its star imports bind (``ModuleFacts``)."""
    try:
        tree = ast.parse(text)
        facts = ModuleFacts(tree, text, star_bindings)
        summary = _summary(facts, Receivers(facts), os.path.realpath(path))
        return replace(summary, skips_file=True) if skips_file(text, first_statement_line(tree)) else summary
    except Exception:  # noqa: BLE001  (the file's own run reports why; it just adds no facts)
        return None


def summarize_masks(path: str, text: str) -> ModuleSummary | None:
    """The summary of a module with no Gym code: only the defs that mask bootstrapping
    with a flag parameter (an agent's ``learn``, a memory's ``store``), for the callers of
    the run (``facts/bootstrap.py``), its record classes (a memory's ``Transition``) and its
    plain root classes (``class Environment(ABC)``, ``plain_roots``). None when it has none
    of these or does not parse."""
    try:
        tree = ast.parse(text)
    except (SyntaxError, ValueError):
        return None
    # Only the module's defs are read: no ModuleFacts (its indexes cost more than the parse).
    functions = {s.name: s for s in tree.body if isinstance(s, FUNCTIONS)}
    classes = {s.name: s for s in tree.body if isinstance(s, ast.ClassDef)}
    masks = masks_of(functions, classes)
    records = top_level_records(tree)
    roots = plain_roots(tree)
    # A module that writes into a name it imports (``registry.add`` filling a table of
    # creators) keeps that table open, Gym code or not. Its facts cost a walk: asked only
    # where the text shows such a write (``runner._may_write_into_import``).
    altered = altered_imports(ModuleFacts(tree, text)) if writes_into_import(text.encode("utf-8", "surrogateescape")) else frozenset()
    loads = loads_model_for_the_run(tree)
    if not masks and not records and not roots and not altered and not loads:
        return None
    defs = {name: signature(_named(functions, classes, name), is_method="." in name) for name in masks}
    return ModuleSummary(
        os.path.realpath(path),
        defs,
        frozenset(),
        frozenset(),
        (),
        bootstrap_masks=masks,
        masks_only=True,
        record_classes=records,
        plain_roots=roots,
        altered=altered,
        loads_saved_state=loads,
        # what a loading module imports: the modules of the run it may load a model for
        imported=_imported_names(tree) if loads else (),
    )


def _imported_names(tree: ast.Module) -> tuple[str, ...]:
    """The qualified names the imports of ``tree`` name (``pkg.mod``, ``.tasks.Task``), as
    ``ModuleSummary.imported`` holds them, without the module's full facts."""
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = "." * node.level + (node.module or "")
            names.update(f"{base}.{alias.name}" if base and not base.endswith(".") else base + alias.name for alias in node.names if alias.name != "*")
    return tuple(sorted(names))


def _named(
    functions: Mapping[str, ast.FunctionDef | ast.AsyncFunctionDef], classes: Mapping[str, ast.ClassDef], qualname: str
) -> ast.FunctionDef | ast.AsyncFunctionDef:
    if "." not in qualname:
        return functions[qualname]
    owner, name = qualname.split(".", 1)
    return next(s for s in classes[owner].body if isinstance(s, FUNCTIONS) and s.name == name)


def unproved_duck_wrappers(facts: ModuleFacts, receivers: Receivers) -> dict[str, str]:
    """The module's plain classes shaped as duck wrappers that its own constructions do not
    prove (other modules build them), with the parameter they hold (``duck_wrappers``)."""
    found: dict[str, str] = {}
    for name, classdef in facts.classes.items():
        param = duck_wrapper_param(classdef)
        if param is not None and not receivers.is_duck_wrapper(classdef) and not receivers.derives_own_api(classdef):
            found[name] = param.arg
    return found


def _summary(facts: ModuleFacts, receivers: Receivers, path: str) -> ModuleSummary:
    defs: dict[str, Signature] = {}
    for name, function in facts.functions.items():
        defs[name] = signature(function, is_method=False)
    env = EnvClasses.of(facts, receivers)
    env_classes, render_mode, render_mode_if_env = set(), set(), set()
    for name, classdef in facts.classes.items():
        for statement in classdef.body:
            if isinstance(statement, FUNCTIONS):
                defs[f"{name}.{statement.name}"] = signature(statement, is_method=True)
        if receivers.class_kind(classdef) is EnvKind.GYM_ENV or env.is_custom_env(classdef):
            env_classes.add(name)
            if env.takes_render_mode(classdef) and id(classdef) not in render_kept_classes(facts, receivers):
                render_mode.add(name)
        elif receivers.class_kind(classdef) is EnvKind.UNKNOWN and env.would_take_render_mode(classdef):
            render_mode_if_env.add(name)
    calls = CallSummarizer(facts, receivers)
    untraced = UntracedCalls(calls)
    exports = Exports(facts, receivers)
    call_summaries = tuple(calls.calls())
    named = named_ids(facts)
    made = made_factories(facts, receivers)
    done_causes = done_methods(facts)
    return ModuleSummary(
        path,
        defs,
        frozenset(env_classes),
        frozenset(render_mode),
        call_summaries,
        bare_render_params=bare_render_params(facts),
        handed_constructions=handed_constructions(facts, call_summaries),
        untraced_seed_call=untraced.has_untraced_call("seed"),
        untraced_render_call=untraced.has_untraced_call("render"),
        calls_configure=calls_from_outside(facts, "configure"),
        calls_seed=calls_seed(facts),
        calls_seed_without_a_value=calls_seed_without_a_value(facts),
        passes_return_info=passes_return_info(facts),
        render_makers=frozenset(untraced.render_makers),  # filled by the line above
        seed_makers=frozenset(untraced.seed_makers),  # filled with untraced_seed_call
        imported=tuple(sorted(set(facts.imports.values()))),
        exports=exports.exports(env_classes),
        aliases=exports.aliases(),
        tables=exports.tables(env_classes),
        made_tables=exports.made_tables(made),
        altered=altered_imports(facts),
        star_imports=tuple(
            "." * s.level + (s.module or "") for s in facts.tree.body if isinstance(s, ast.ImportFrom) and any(a.name == "*" for a in s.names)
        ),
        star_bases=star_bases(facts),
        declared_all=declared_all(facts),
        subclasses=subclasses(facts),
        self_calls=self_calls(facts),
        super_calls=super_calls(facts),
        named_class_calls=named_class_calls(facts),
        run_bases=run_bases(facts, receivers),
        renamed_hooks=renamed_hooks(facts, receivers),
        instance_calls=instance_calls(facts),
        recreates_from_spec=recreates_from_spec(facts),
        own_api_classes=frozenset(n for n, c in facts.classes.items() if receivers.derives_own_api(c)),
        own_api_flags={n: f for n, c in facts.classes.items() if own_api_shape(c) is not None and (f := gymnasium_flag(c)) is not None},
        wrapper_classes=frozenset(name for name, classdef in facts.classes.items() if receivers.is_gym_wrapper_class(classdef)),
        duck_wrappers=unproved_duck_wrappers(facts, receivers),
        wrapper_defined=wrapper_defined(facts),
        wrapping_helpers={
            name: receivers.wrapped_parameter(function)
            for name, function in facts.functions.items()
            if receivers.wraps_argument(function)
        },
        pz_wrappers=pz_wrappers.summarize(facts),
        plain_classes=plain_classes(facts),
        space_calls=space_calls(facts, receivers),
        contains_calls=contains_calls(facts),
        mujoco_py_uses=mujoco_py_uses(facts),
        unset_spaces=module_unset_spaces(facts, receivers),
        base_built=frozenset(name for name, classdef in facts.classes.items() if runs_base_init(classdef)),
        def_builds=def_builds(facts, receivers),
        checked_entries=checked_entries(facts),
        reset_steps=module_reset_steps(facts),
        self_handoffs=self_handoffs(facts, receivers),
        spec_lists=module_spec_lists(facts),
        made_factories=made,
        gym_only_makers=gym_only_makers(facts, receivers),
        passes_init_up=calls.passes_init_up(),
        classes=frozenset(facts.classes),
        bootstrap_masks=bootstrap_masks(facts),
        record_classes=top_level_records(facts.tree),
        plain_roots=plain_roots(facts.tree),
        done_methods=done_causes[0],
        done_items=done_causes[1],
        step_hooks=step_hooks(facts),
        plain_overrides=plain_overrides(facts),
        helper_candidates=helper_candidates(facts),
        helper_hand_ons=helper_hand_ons(facts),
        own_step_shapes=own_step_shapes(facts),
        five_step_trees=five_step_trees(facts, receivers),
        rng_stores=rng_stores(facts, receivers),
        step_counting=step_counting(facts, receivers),
        render_mode_heirs=render_mode_heirs(facts, receivers),
        own_renders=own_renders(facts, receivers, calls),
        modeless_renders=modeless_renders(facts, receivers),
        varargs_renders=varargs_renders(facts),
        render_only_classes=frozenset(name for name, classdef in facts.classes.items() if draws_only_in_render(facts, receivers, classdef)),
        own_flag_steps=frozenset(name for name, classdef in facts.classes.items() if steps_draw_on_own_flags(facts, receivers, classdef)),
        registrations=registrations(facts),
        loads_saved_state=loads_model_for_the_run(facts.tree),
        registered_ids=registered_ids(facts),
        named_ids=named[0],
        opaque_make=named[1],
        render_mode_if_env=frozenset(render_mode_if_env),
        held_params=held_params(facts, receivers),
        init_held=init_held(facts, receivers),
        property_aliases=property_aliases(facts),
        made_holders=made_holders(facts, receivers),
        fixtures=conftest_fixtures(path, facts, receivers),
        param_renders=param_renders(facts, receivers),
        driven_kinds=driven_kinds(facts, receivers),
        stored_attributes=stored_attributes(facts, receivers),
        handed_on=handed_on(facts),
        silent_renders=frozenset(name for name, classdef in facts.classes.items() if renders_nothing(facts, classdef)),
        frame_classes=frame_classes(facts),
        render_forwards=render_forwards(facts, receivers),
        atari_users=atari_users(facts),
        id_params=id_parameters(facts, receivers),
        inherited_id_calls=tuple(calls.inherited_id_calls()),
        escaping_params=escaping_parameters(facts),
        thunk_factories={
            name: kind for name, function in facts.functions.items() if (kind := receivers.factory_thunk_kind(function)) is not EnvKind.UNKNOWN
        },
        thunk_items={
            name: (*item, kind)
            for name, function in facts.functions.items()
            if (item := receivers.thunk_item(function)) is not None
            and (kind := receivers.factory_thunk_kind(function, item)) is not EnvKind.UNKNOWN
        },
        made_thunks=made_thunks(facts, receivers),
        thunk_factory_refs={
            name: refs for name, function in facts.functions.items() if (refs := receivers.factory_thunk_refs(function))
        },
        mode_renders=mode_renders(facts),
        opaque_registrations=opaque_registrations(facts),
        fixed_mode_renders=fixed_mode_renders(facts),
        default_mode_renders=default_mode_renders(facts),
        rendering_wrappers=rendering_wrappers(facts, receivers),
        legacy_steps=frozenset(
            name
            for name, classdef in facts.classes.items()
            if (name in env_classes and receivers.class_keeps_legacy_step(classdef)) or receivers.own_record_wrapper(classdef)
        ),
        kept_resets=frozenset(name for name, classdef in facts.classes.items() if receivers.reset_kept(classdef)),
        legacy_if=receivers.legacy_dependencies(),
        forwarding_wrappers=frozenset(
            name
            for name, classdef in facts.classes.items()
            if receivers.is_gym_wrapper_class(classdef) and receivers.forwards_inner_contract(classdef)
        ),
        class_stores=module_class_stores(facts),
        reset_sites=reset_sites(facts, lambda classdef: receivers.class_kind(classdef) is EnvKind.GYM_ENV),
    )
