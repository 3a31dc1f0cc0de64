"""The wrapper class family: finds the Gym wrapper subclasses and hands their
``__init__`` (GM603), ``step`` (GM602) and ``reset`` (GM601) to their rules."""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.class_shapes import touches_self_env
from gymmigrate.facts.module import FUNCTIONS, is_super_call, walk
from gymmigrate.facts.receiver_classes import duck_wrapper_attribute
from gymmigrate.findings import FixKind, Tier, gym_only_question
from gymmigrate.rules.base import FileContext
from gymmigrate.rules.reset_seed.common import is_space, moving_seed_question
from gymmigrate.rules.wrapper_usage.tables import wrapper_rest
from gymmigrate.rules.wrappers import episode_state
from gymmigrate.rules.wrappers.common import (
    GONE_WRAPPER_STATE,
    INNER,
    RULES,
    _is_inner_env,
)
from gymmigrate.rules.wrappers.reset import ResetOverrides
from gymmigrate.rules.wrappers.step import StepOverrides


class WrapperClasses(StepOverrides, ResetOverrides):
    RULES = RULES
    after = ("ResetSeed", "StepDone")

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        if "Wrapper" in facts.text or "wrappers" in facts.text or "self.env" in facts.text:
            return True
        # a plain class holding its env under a name of its own (``self.game``)
        return "def step" in facts.text and any(duck_wrapper_attribute(c) is not None for c in facts.all_classes)

    def decide(self) -> None:
        for classdef in self.facts.all_classes:
            if not self.receivers.is_gym_wrapper_class(classdef):
                if self.context.profile.imports_gym and self.receivers.unproved_duck_wrapper(classdef):
                    if self.receivers.built_nowhere(classdef):
                        # no code of the run builds it: no env reaches it, nothing to decide now
                        self.report(
                            classdef,
                            "GM602",
                            f"`{classdef.name}` holds an env in `self.{duck_wrapper_attribute(classdef)}` and forwards to it like "
                            "a Gym wrapper, but no code of this run builds it: left as it is (four-field step, bare reset); "
                            "code outside the run that puts a Gym env in it must migrate it",
                            FixKind.FLAG,
                            tier=Tier.NOTE,
                        )
                        continue
                    self.report(
                        classdef,
                        "GM602",
                        f"`{classdef.name}` holds an env in `self.{duck_wrapper_attribute(classdef)}` and forwards to it like a Gym wrapper, but "
                        "the run does not show that every construction of it passes a Gym env: it and its callers "
                        "are left as they are (four-field step, bare reset); migrate them together, or check the "
                        "whole project in one run",
                        FixKind.FLAG,
                    )
                continue
            library = self.receivers.wraps_gym_only(classdef)
            if library is not None:
                self.report(
                    classdef,
                    "GM602",
                    f"`{classdef.name}` wraps what `{library}` makes, a library still on gym (GM107): its step and "
                    "reset keep gym's API (a four-field step, per-agent arrays when it is batched), so this wrapper and "
                    "the code that steps it are left as they are (gymnasium.Wrapper also refuses an env that is no "
                    "gymnasium.Env); port them together with that env (Shimmy, or the library's Gymnasium successor)",
                    FixKind.FLAG,
                    # ported with the library's envs: the decision its import asks (GM107)
                    question=gym_only_question(N.gym_only_stack(library.split(".", 1)[0])),
                )
                continue
            if self.receivers.wraps_pz_parallel(classdef):
                self.report(
                    classdef,
                    "GM602",
                    f"`{classdef.name}` is a Gym wrapper around a PettingZoo parallel env: gymnasium.Wrapper refuses "
                    "an env that is no gymnasium.Env (TypeError), so derive it from `object` (store `self.env = env` "
                    "and read the env's attributes there) or from PettingZoo's `BaseParallelWrapper`; its reset and "
                    "step keep their own API, with PettingZoo's per-agent terminations and truncations",
                    FixKind.FLAG,
                )
                continue
            if self.receivers.wraps_vec_env(classdef):
                self.report(
                    classdef,
                    "GM602",
                    f"`{classdef.name}` is a Gym wrapper that this run puts only around VecEnvs: gymnasium.Wrapper "
                    "refuses an env that is no gymnasium.Env (TypeError), so derive it from a VecEnv wrapper base "
                    "(Stable-Baselines3's `VecEnvWrapper`) or from `object` (store `self.env = venv`); its step and "
                    "reset, and the calls on its instances, keep the VecEnv's API (four fields, reset with no seed) "
                    "and are left as they are",
                    FixKind.FLAG,
                )
                continue
            if self.receivers.wraps_vec_env_sometimes(classdef):
                self.report(
                    classdef,
                    "GM602",
                    f"`{classdef.name}` is put around a Gym env at some constructions of this run and around a "
                    "VecEnv at others: migrated as a Gymnasium wrapper, it refuses the VecEnv (gymnasium.Wrapper "
                    "takes only a gymnasium.Env, TypeError) and its step and reset no longer match the VecEnv's; "
                    "give the VecEnv constructions a class of their own (a VecEnv wrapper base)",
                    FixKind.FLAG,
                )
            self._check_gone_state(classdef)
            for statement in classdef.body:
                if not isinstance(statement, FUNCTIONS):
                    continue
                if statement.name == "__init__" and self.receivers.has_gym_wrapper_base(classdef):
                    self._check_init(classdef, statement)
                elif statement.name == "step":
                    if self._reports_wrapped_batch(classdef, statement):
                        continue
                    if self.receivers.legacy_by_version(classdef):
                        self.report(
                            statement,
                            "GM602",
                            "left as it is: this wrapper presents the legacy API (four values from step, the "
                            "observation from reset) whatever gym is installed, and the branch of its gym version "
                            "check that runs on Gymnasium already reads the inner env's new API; its callers stay too",
                            FixKind.FLAG,
                            tier=Tier.NOTE,
                        )
                        continue
                    self._fix_step(statement)
                elif statement.name == "reset":
                    if self.receivers.keeps_own_reset(classdef):
                        # A batch (or a wrapper around one) keeps its reset's return with its step;
                        # a batch wrapper still takes the seed/options outer wrappers pass and hands
                        # them to the Gym env it wraps.
                        if self.receivers.wraps_legacy_step(classdef) is None:
                            self._fix_reset_signature(statement)
                        continue
                    self._fix_reset(classdef, statement)
                elif statement.name == "seed":
                    self._check_seed(classdef, statement)
                elif statement.name == "render":
                    self._check_render(classdef, statement)

    def _reports_wrapped_batch(self, classdef: ast.ClassDef, function: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
        """``Stats(Batch(...))`` where Batch's step keeps its four stacked fields: the wrapper's
        step unpacks those four, so it keeps them as well (its reset follows the batch's)."""
        batch = self.receivers.wraps_legacy_step(classdef)
        if batch is None:
            return False
        if self._names_legacy_wrapper(batch):
            # a wrapper of the run kept on the legacy API on purpose (``CompatWrapper``-like):
            # the chain above it keeps that API, no batch to port
            self.report(
                function,
                "GM602",
                f"left as it is: `{classdef.name}` is put around `{batch}` here, a wrapper of this project that keeps "
                "the legacy API (four values from step, the observation from reset): this step and reset keep it "
                "too, and so do the calls of it this run can trace",
                FixKind.FLAG,
                tier=Tier.NOTE,
            )
            return True
        self.report(
            function,
            "GM602",
            f"`{classdef.name}` is put around `{batch}` here, a batch of envs whose step keeps its four stacked fields "
            "(GM504 reports it): this step keeps them too, and so do the calls of it this run can trace; if the "
            "wrapper also wraps single Gymnasium envs elsewhere, port it together with the batch",
            FixKind.FLAG,
        )
        return True

    def _names_legacy_wrapper(self, name: str) -> bool:
        """``name`` (what ``wraps_legacy_step`` gives) is a Gym wrapper of the run kept on the
        legacy API (behind a version check, or of the project's own record, or put around
        one), not a batch of envs: such a class or a def of this module, or a name this module
        imports that the run knows as a wrapper class."""
        for _ in range(16):
            local = self.facts.classes.get(name)
            if local is None:
                break
            if self.receivers.legacy_by_version(local) or self.receivers.own_record_wrapper(local):
                return True
            inner = self.receivers.wraps_legacy_step(local)  # a batch of this module is none
            if inner is None or not self.receivers.is_gym_wrapper_class(local):
                return False
            name = inner
        if name in self.facts.functions:
            return True
        project = self.receivers.project
        return project is not None and any(
            project.is_wrapper_class(q) for q in self.facts.imports.values() if q.rsplit(".", 1)[-1] == name
        )

    # -- seed() and render(mode, ...) overrides: Gymnasium calls neither that way ----------------

    def _check_seed(self, classdef: ast.ClassDef, function: ast.FunctionDef | ast.AsyncFunctionDef) -> None:
        """``def seed(self, seed): self.action_space.seed(seed)``: Gymnasium never calls a
        wrapper's seed(), so its spaces go unseeded; the seeding belongs in ``reset(seed=...)``."""
        if not self.context.profile.imports_gym:
            return
        spaces = [
            node.func.value
            for node in walk(function)
            if isinstance(node, ast.Call)
            and isinstance(node.func, ast.Attribute)
            and node.func.attr == "seed"
            and is_space(node.func.value)
        ]
        if not spaces:
            return
        shown = ", ".join(f"`{self.facts.segment(space)}`" for space in spaces[:3]) + (", ..." if len(spaces) > 3 else "")
        self.report(
            function,
            "GM205",
            f"`{classdef.name}.seed()` seeds {shown}; Gymnasium never calls a wrapper's seed(), so those spaces are no "
            "longer seeded: seed them in reset (`if seed is not None: self.action_space.seed(seed)`) and hand the seed "
            "on with `self.env.reset(seed=seed, options=options)`",
            FixKind.FLAG,
            question=moving_seed_question(function),
        )

    def _check_render(self, classdef: ast.ClassDef, function: ast.FunctionDef | ast.AsyncFunctionDef) -> None:
        """``def render(self, mode="rgb_array", height=None, width=None)`` forwarding them to
        ``self.env.render(mode=mode, ...)``: Gymnasium's wrappers call render() bare and the
        inner env's render() takes no arguments (TypeError), so the mode and the image size
        must be given where the inner env is made."""
        if not self.context.profile.imports_gym:
            return
        args = function.args
        named = [a.arg for a in (*args.posonlyargs, *args.args, *args.kwonlyargs)][1:]  # ``self`` first
        if not named:
            return  # ``render(self)`` or ``render(self, *args, **kwargs)``: Gymnasium's call works
        held = duck_wrapper_attribute(classdef) or "env"  # a plain class's ``self.environment``
        forwarded = [
            node
            for node in walk(function)
            if isinstance(node, ast.Call)
            and isinstance(node.func, ast.Attribute)
            and node.func.attr == "render"
            and (node.args or node.keywords)
            and _is_inner_env(node.func.value, (*INNER, held))
        ]
        where = (
            f": `{self.facts.segment(forwarded[0])}` on line {forwarded[0].lineno} raises TypeError (the inner render() "
            "takes none)"
            if forwarded
            else ""
        )
        self.report(
            function,
            "GM405",
            f"`{classdef.name}.render({', '.join(named)})` takes arguments Gymnasium never passes (its wrappers call "
            f"render() bare){where}; pass the mode as render_mode= and the image size (width=, height= for MuJoCo envs) "
            f"to gym.make where the inner env is made, then forward `self.{held}.render()`",
            FixKind.FLAG,
        )

    # -- GM618 ------------------------------------------------------------------------------

    def _check_gone_state(self, classdef: ast.ClassDef) -> None:
        """A subclass of gym's RecordEpisodeStatistics (or the normalize wrappers) that reads
        what the 0.26 base set (``self.num_envs``, ``self.t0``) and 1.x's does not."""
        bases = {rest for base in classdef.bases for q in self.facts.qualified_names(base) if (rest := wrapper_rest(q)) is not None}
        gone: set[str] = set()
        for base in bases:
            gone |= GONE_WRAPPER_STATE.get(base, frozenset())
        if not gone:
            return
        stored = self.receivers.self_stores(classdef)
        read = sorted(
            {
                node.attr
                for node in walk(classdef)
                if isinstance(node, ast.Attribute)
                and isinstance(node.ctx, ast.Load)
                and node.attr in gone
                and node.attr not in stored
                and isinstance(node.value, ast.Name)
                and node.value.id == "self"
            }
        )
        if not read:
            return
        base = sorted(bases & set(GONE_WRAPPER_STATE))[0]
        reading = f"`{classdef.name}` reads `{'`, `'.join('self.' + name for name in read)}`, which gym's `{base}` set and Gymnasium 1.x's does not"
        why = ""
        if base == episode_state.BASE:
            restoration, why = episode_state.plan_restoration(classdef, set(read))
            if restoration is not None:
                self._restore_episode_state(classdef, restoration, reading)
                return
        self.report(
            classdef,
            "GM618",
            f"{reading}: the 1.x `{base}` is single-env (the vector one is "
            f"`gymnasium.wrappers.vector.{base}`) and keeps its episode state differently"
            + (f"; {why}" if why else "")
            + "; port this subclass by hand",
            FixKind.FLAG,
        )

    def _restore_episode_state(self, classdef: ast.ClassDef, restoration: episode_state.Restoration, reading: str) -> None:
        """gym 0.26's ``__init__``/``reset`` state, back in a subclass that computes its own statistics."""
        time_name = self.plan.ensure_import("time") if "t0" in restoration.init_names else ""
        if restoration.init_names:
            self.plan.insert_after(restoration.init_anchor, *episode_state.init_lines(restoration.init_names, time_name))
        restored = [f"`self.{name}`" for name in (*restoration.init_names, *restoration.reset_names)]
        if restoration.reset_names:
            np_name = self.plan.ensure_import("numpy")
            if restoration.reset_anchor is not None:
                self.plan.insert_after(restoration.reset_anchor, *episode_state.reset_lines(restoration.reset_names, np_name))
            else:
                code = episode_state.reset_method(restoration.reset_names, np_name)
                self.plan.insert_after(restoration.last, lambda: _after_a_blank_line(code))
        self.report(
            classdef,
            "GM618",
            f"{reading}; its `step` computes the statistics itself, so {', '.join(restored)} are set as gym 0.26's "
            "`__init__`/`reset` set them (one env: Gymnasium 1.x's `RecordEpisodeStatistics` raises on a vector env, "
            "whose wrapper is `gymnasium.wrappers.vector.RecordEpisodeStatistics`)",
            FixKind.ASSIST,
        )

    # -- GM603 ------------------------------------------------------------------------------

    def _check_init(self, classdef: ast.ClassDef, init: ast.FunctionDef | ast.AsyncFunctionDef) -> None:
        if any(_is_super_init(node) for node in walk(init)) or not _uses_self_env(classdef):
            return
        ahead = self._bases_ahead_of_wrapper(classdef)
        if ahead is None:
            self.report(
                init,
                "GM603",
                f"`{classdef.name}.__init__` never calls `super().__init__(env)`: gymnasium.Wrapper "
                "needs it to set `env` and the action/observation space and metadata properties; call it "
                "instead of setting `self.env` by hand",
            )
            return
        first, wrapper = ahead
        # The method resolution order reaches the bases listed first before the wrapper base:
        # ``super().__init__(env)`` would run ``first``'s constructor with the env as its argument.
        self.report(
            init,
            "GM603",
            f"`{classdef.name}.__init__` never calls the wrapper base's constructor: gymnasium.Wrapper needs it "
            "to set its private fields (`wrapper.metadata` and the space properties read them); "
            f"`super().__init__(env)` would run the constructor of `{ast.unparse(first)}`, listed before "
            f"`{ast.unparse(wrapper)}`, with the env as its argument wherever that base has one, so call "
            f"`{ast.unparse(wrapper)}.__init__(self, env)`. "
            "Gymnasium 1.x's Wrapper no longer forwards the attributes it does not define to the env "
            "(gym's `__getattr__` is gone): what this class and its callers read through it and it does not "
            "define itself (the env's own extensions) needs a forwarding `__getattr__` to `self.env` or "
            "`get_wrapper_attr`",
        )

    def _bases_ahead_of_wrapper(self, classdef: ast.ClassDef) -> tuple[ast.expr, ast.expr] | None:
        """The first base listed before ``classdef``'s first Gym wrapper base, and that wrapper
        base; None where the wrapper base comes first (``super()`` reaches it)."""
        for index, base in enumerate(classdef.bases):
            if self.receivers.is_gym_wrapper_base(classdef, base):
                return (classdef.bases[0], base) if index else None
        return None


def _uses_self_env(classdef: ast.ClassDef) -> bool:
    """Some method of the class reads or sets ``self.env``, or the class leaves ``step`` to
    the base (whose step reads ``self.env``). A class on a Wrapper base that defines its own
    step and never touches ``self.env`` (it holds a ``venv``, worker pipes, ``num_envs``: a
    batch of its own) is no wrapper layer: the base's ``__init__(env)`` has no env to take
    there, so GM603 has nothing to ask of it."""
    if not any(isinstance(s, FUNCTIONS) and s.name == "step" for s in classdef.body):
        return True
    return touches_self_env(classdef)


def _is_super_init(node: ast.AST) -> bool:
    """``super().__init__(...)``, ``super(Cls, self).__init__(...)`` or ``Base.__init__(self, ...)``."""
    if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "__init__"):
        return False
    owner = node.func.value
    if is_super_call(owner):
        return True
    if isinstance(owner, (ast.Name, ast.Attribute)) and node.args:
        first = node.args[0]
        return isinstance(first, ast.Name) and first.id == "self"
    return False


def _after_a_blank_line(code: str) -> cst.BaseStatement:
    return cst.parse_statement(code).with_changes(leading_lines=[cst.EmptyLine(indent=False)])
