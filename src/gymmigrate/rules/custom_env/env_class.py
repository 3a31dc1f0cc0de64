"""Custom ``Env`` subclasses: the methods Gymnasium calls with a new contract.

One family decides, per custom env class, what each rule does with its methods
(``seed.py``, ``reset.py``, ``step.py``, ``render.py``, ``observations.py``), and
records a single replacement of the class whose build (``rebuild.py``) rewrites the
methods in dependency order: ``seed()``'s seeding folds into ``reset``, ``render``'s
mode reaches ``__init__``. Very old ``_step`` / ``_reset`` / ``_seed`` / ``_render``
(gym < 0.9) are renamed first and then migrated like the modern names. Wrapper
subclasses are left to the wrapper rules.

Sources: Gymnasium ``core.py`` (``Env.reset`` seeds ``_np_random``), gym 0.26 release
notes, ``envs/registration.py::make``.
"""

from __future__ import annotations

import ast
from collections.abc import Callable

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.env_classes import EnvClasses
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import ModuleFacts, own_returns
from gymmigrate.facts.own_api import gymnasium_flag, is_info_pair, own_api_shape
from gymmigrate.facts.summaries.untraced import calls_from_outside
from gymmigrate.findings import FixKind, Tier, configure_hook_question
from gymmigrate.rules.base import FileContext, RuleFamily
from gymmigrate.rules.custom_env.common import (
    CLASS_RULES,
    UNDERSCORE_RULE,
    ClassDecision,
    method_of,
)
from gymmigrate.rules.custom_env.hook_calls import rename_hook_calls_first
from gymmigrate.rules.custom_env.observations import (
    decide_float64_observations,
    decide_mujoco,
)
from gymmigrate.rules.custom_env.plans import ClassPlan
from gymmigrate.rules.custom_env.render import (
    decide_render,
    decide_subclass_render_mode,
    report_kept_render_options,
)
from gymmigrate.rules.custom_env.reset import (
    decide_internal_calls,
    decide_published,
    decide_reset,
)
from gymmigrate.rules.custom_env.reset_none import decide_reset_without_observation
from gymmigrate.rules.custom_env.seed import decide_seed
from gymmigrate.rules.custom_env.seeding_import import drop_unused_seeding_import
from gymmigrate.rules.custom_env.spaces import (
    decide_list_spaces,
    decide_observation_stores,
    decide_unset_spaces,
)
from gymmigrate.rules.custom_env.step import decide_step


class EnvClassFamily(RuleFamily):
    RULES = CLASS_RULES
    after = ("Rendering",)

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        if not facts.all_classes:
            return False
        if "gym" in facts.text:
            return True
        # ``class Hallway(MiniWorldEnv)`` in a module that never names Gym: its base is an
        # env class of another module of the run, whose migration its overrides follow.
        project = context.options.project
        if project is None:
            return False
        view = project.view(context.path)
        return any(
            view.call_kind(qualified) in (EnvKind.GYM_ENV, EnvKind.OWN_API)
            for classdef in facts.all_classes
            for base in classdef.bases
            for qualified in facts.qualified_names(base)
        )

    def _configure_called(self) -> bool:
        """A ``x.configure(...)`` / ``x._configure(...)`` call on other than ``self`` in this
        module or (in a run of several files) in any module of the run."""
        project = self.receivers.project
        return calls_from_outside(self.facts, "configure") or (project is not None and project.configure_called())

    def decide(self) -> None:
        env = EnvClasses.of(self.facts, self.receivers)
        if rename_hook_calls_first(self, env):
            return  # the next round decides on the renamed code
        deleted: list[ast.stmt] = []
        removed_seed = False
        inherited: dict[int, list[str]] = {}  # subclass -> step hooks its bases migrated (hooks.py)
        for classdef in self.facts.all_classes:
            if not env.is_custom_env(classdef):
                continue
            decision = ClassDecision(self, env, classdef)
            decide_mujoco(decision)
            decide_unset_spaces(decision)
            decide_list_spaces(decision)
            decide_observation_stores(decision)
            if self.receivers.class_kind(classdef) is EnvKind.OWN_API:
                # Its reset/step are on a contract of their own, and the calls on its instances
                # stay on it (the receiver rules leave them): nothing that contract reaches
                # (seed, reset, step, render) is migrated; one item says so.
                _report_own_api(decision)
                decide_float64_observations(decision)
                continue
            if decision.plan.published and decide_published(decision):
                decide_float64_observations(decision)
                continue  # reported once, left whole
            for new, old in decision.renamed.items():
                why = ""
                if new == "configure":
                    why = (
                        "; Gymnasium never calls it: call `env.unwrapped.configure(...)`"
                        if self._configure_called()
                        # only the class's own ``self._configure()`` calls, renamed with it
                        else "; nothing in the run calls it but the class's own methods (renamed with it)"
                    )
                # an explanation of the rename; the migrated method's own findings follow;
                # one question for every class of the file: how the run's callers reach it
                asks = why.startswith("; Gymnasium")
                decision.report(
                    decision.methods[old],
                    UNDERSCORE_RULE[new],
                    f"gym < 0.9 method `{old}` renamed `{new}`{why}",
                    tier=None if asks else Tier.NOTE,
                    question=configure_hook_question() if asks else None,
                )
                for call in decision.index.self_calls.get(old, ()):
                    method = method_of(decision, call)
                    if method is not None:
                        decision.plan.rename_callers.add(method.name)
            # A class whose step the run keeps on its own four fields (a batch, per-agent lists,
            # a step returning a name) keeps its reset with it: a Gymnasium reset beside a legacy
            # step matches neither API, and users of the class break. Its seed() stays too (its
            # own API may call it); the step's item names the reset.
            kept = self.receivers.keeps_own_reset(classdef)
            decision.plan.reset_kept = kept
            if not kept:
                decide_seed(decision)
                decide_reset(decision)
                decide_reset_without_observation(decision)
            decide_step(decision, inherited)
            if not kept:
                # render(mode) belongs to that same own API: its callers (``Runner.run``
                # calling ``self.env.render()``, the 'human' default) keep it, and no
                # gymnasium.make ever passes the class a render_mode.
                decide_render(decision)
            else:
                report_kept_render_options(decision)
            decide_subclass_render_mode(decision)
            if not kept:
                decide_internal_calls(decision)
            decide_float64_observations(decision)
            if self._changes(decision):
                self.plan.replace(classdef, _rewrite_class(decision.plan))
            deleted.extend(decision.deleted_statements)
            removed_seed = removed_seed or bool(decision.removed)
        if removed_seed:
            drop_unused_seeding_import(self.facts, self.plan, deleted)

    @staticmethod
    def _changes(decision: ClassDecision) -> bool:
        plan = decision.plan
        return bool(
            plan.renamed
            or plan.seed
            or plan.render
            or plan.render_init_only
            or plan.pass_render_mode
            or plan.unpack_self_reset
            or plan.reset
            or plan.reset_alias
            or plan.step
        )


def _report_own_api(decision: ClassDecision) -> None:
    """One review item for a class on an API of its own: its own shape, or (a subclass that
    defines reset or step) the base it takes the contract from."""
    classdef = decision.classdef
    shape = decision.family.receivers.own_api(classdef)
    if shape is None:
        if not {"reset", "step"} & set(decision.methods):
            return  # nothing of its own on that contract: its base's item covers it
        taken = _gymnasium_through_flag(decision)
        if taken is not None:
            base, flag = taken
            decision.report(
                classdef,
                "GM504",
                f"`{classdef.name}` takes Gymnasium's shapes from `{base}`, which has two APIs: its __init__ sets "
                f"`self.{flag} = True`, which picks `{base}`'s five-value step and (obs, info) reset, and its own "
                f"overrides return those shapes: left as it is, on Gymnasium's API (`{base}`'s item asks about the other)",
                FixKind.FLAG,
                tier=Tier.NOTE,
            )
            return
        shape = "it derives from an env class of the run that follows one"
    decision.report(
        classdef,
        "GM504",
        f"`{classdef.name}` follows an API of its own, neither Gym's nor Gymnasium's: {shape}; its reset() and "
        "step() are left as they are, and so are the calls on its instances this run traces; migrate the class and "
        "its callers together by hand",
        FixKind.FLAG,
    )


def _gymnasium_through_flag(decision: ClassDecision) -> tuple[str, str] | None:
    """(base, flag) for a subclass of a class of two APIs (``own_api.gymnasium_flag``: its
    step and reset take Gymnasium's shapes only under ``if self.<flag>:``) whose __init__
    sets that flag to True last, which nothing else in the class writes, and whose own step
    and reset return only Gymnasium's shapes: its instances are on Gymnasium's API. None
    otherwise (a flag the subclass leaves to its callers, or sets to something else)."""
    classdef = decision.classdef
    receivers = decision.family.receivers
    found: set[tuple[str, str]] = set()
    for base_expr in classdef.bases:
        local = receivers.local_class(base_expr)
        if local is not None:
            flag = gymnasium_flag(local) if own_api_shape(local) is not None else None
        elif receivers.project is not None:
            flags = {receivers.project.own_api_flag(q) for q in receivers.facts.qualified_names(base_expr)}
            flag = flags.pop() if len(flags) == 1 else None
        else:
            flag = None
        if flag is not None:
            found.add((ast.unparse(base_expr), flag))
    if len(found) != 1:
        return None
    base, flag = found.pop()
    init = decision.methods.get("__init__")
    if not isinstance(init, (ast.FunctionDef, ast.AsyncFunctionDef)):
        return None
    sets = [i for i, s in enumerate(init.body) if _sets_flag_true(s, flag)]
    if not sets or any(_calls_init(s) for s in init.body[sets[-1] + 1 :]):
        return None  # a base __init__ called after it may set the flag again
    writes = [
        n
        for n in ast.walk(classdef)
        if isinstance(n, ast.Attribute) and n.attr == flag and isinstance(n.ctx, ast.Store)
    ]
    if len(writes) != 1:
        return None
    step, reset = decision.methods.get("step"), decision.methods.get("reset")
    if step is not None and not all(r.value is not None and _five(r.value) for r in own_returns(step)):
        return None
    if reset is not None and not all(r.value is not None and is_info_pair(r.value) for r in own_returns(reset)):
        return None
    return base, flag


def _five(value: ast.expr) -> bool:
    return isinstance(value, ast.Tuple) and len(value.elts) == 5


def _sets_flag_true(statement: ast.stmt, flag: str) -> bool:
    """``self.<flag> = True``."""
    if not (isinstance(statement, ast.Assign) and len(statement.targets) == 1):
        return False
    target = statement.targets[0]
    return (
        isinstance(target, ast.Attribute)
        and target.attr == flag
        and isinstance(target.value, ast.Name)
        and target.value.id == "self"
        and isinstance(statement.value, ast.Constant)
        and statement.value.value is True
    )


def _calls_init(statement: ast.stmt) -> bool:
    return any(isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute) and n.func.attr == "__init__" for n in ast.walk(statement))


def _rewrite_class(plan: ClassPlan) -> Callable[[cst.ClassDef], cst.ClassDef]:
    """The class's build: ``rebuild.rewrite_class``, loaded when it first runs."""

    def build(node: cst.ClassDef) -> cst.ClassDef:
        from gymmigrate.rules.custom_env.rebuild import (
            rewrite_class,  # the apply layer: LibCST
        )

        return rewrite_class(plan)(node)

    return build
