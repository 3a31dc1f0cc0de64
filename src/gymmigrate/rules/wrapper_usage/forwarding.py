"""Attribute forwarding is gone (GM604-GM606): what legacy code read through ``Wrapper.__getattr__``.

Gymnasium 1.0 removed ``Wrapper.__getattr__``, so on an env built through ``make`` or
wrappers ``env.x_threshold`` raises ``AttributeError``:

* GM604 (ASSIST) base-env state and methods become ``env.unwrapped.foo``; anything a
  wrapper may define becomes ``env.get_wrapper_attr("foo")`` (outermost to base, exactly
  what forwarding did). Writes are reported (forwarding never applied to them). A raw env
  built by its own constructor never had the problem. ``env.env.state`` on a bare make
  result becomes ``env.unwrapped.state``: make's layers have no ``state`` to shadow it.
  What Gymnasium's class of a built-in env no longer has (CarRacing's pyglet ``viewer``,
  ``builtin_attributes.py``) is reported on that env whatever the layer, not rewritten.
* GM605 (ASSIST) ``env._max_episode_steps`` on a bare ``make`` result is the outermost
  TimeLimit's own attribute, left as it is (reads and writes work as in gym); under wrappers
  of the code's own it is read from ``env.spec.max_episode_steps`` (a make below them) or
  with ``env.get_wrapper_attr("_max_episode_steps")``. Not on an Atari make, which has no
  TimeLimit now (``atari_limits.py``): a write right after it becomes ``max_episode_steps=``
  of the make; other writes and reads (``env.spec.max_episode_steps`` too) are reported.
* GM606 (FLAG) ``gym.make(id).env`` (legacy: "drop the TimeLimit") becomes ``.unwrapped``;
  other ``env.env.env`` chains are reported: ``make`` now stacks three wrappers.
  ``isinstance(env, TimeLimit)`` answers as before (TimeLimit is still the outermost wrapper
  ``make`` returns): left alone on a make result, a note on a stack of the code's own;
  reported on an Atari make (no TimeLimit there now).

Where an env comes from (its *origin*) decides between those rewrites. The family is
this module (the decisions on ``env.x``) and its siblings: ``origins.py`` (where an env
comes from, which wrapper is outermost and what it defines), ``bare_make.py`` (which names
hold a bare make result), ``make_layers.py`` (``.env`` chains through make's layers and
``isinstance(env, TimeLimit)``), ``self_forwarding.py`` (``self.x`` in a wrapper class's
own methods), ``getattr_hasattr.py`` (a class's ``__getattr__`` handing lookups on, and
``hasattr`` guards), ``monitor_attributes.py`` (``env.videos``, ``env.monitor``),
``builtin_attributes.py`` (attributes Gymnasium's built-in envs lost) and
``forwarding_edits.py`` (the LibCST builders of the rewrites).
"""

from __future__ import annotations

import ast
from collections.abc import Hashable

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.decisions import Action, Decision
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import FUNCTIONS, dotted_name, full_name, walk
from gymmigrate.facts.narrowing import isinstance_guards
from gymmigrate.findings import RUN_QUESTION, FixKind, Tier, gym_only_question
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.wrapper_usage.atari_api import (
    ATARI_METHOD_WORDS,
    atari_method_call,
)
from gymmigrate.rules.wrapper_usage.atari_limits import (
    max_episode_steps_on_atari,
    spec_limit_on_atari,
)
from gymmigrate.rules.wrapper_usage.bare_make import bare_make_result
from gymmigrate.rules.wrapper_usage.builtin_attributes import gone_from_builtin
from gymmigrate.rules.wrapper_usage.forwarding_edits import (
    replace_with_get_wrapper_attr,
    set_wrapper_attr,
    through,
)
from gymmigrate.rules.wrapper_usage.getattr_hasattr import (
    UNWRAPPED,
    WrappedReads,
    forwarded_through_wrapper_attr,
    getattr_forwarding,
    hasattr_through_wrappers,
)
from gymmigrate.rules.wrapper_usage.held_envs import EVERY, SOME
from gymmigrate.rules.wrapper_usage.made_attributes import classes_holding
from gymmigrate.rules.wrapper_usage.make_layers import MakeLayers
from gymmigrate.rules.wrapper_usage.monitor_attributes import (
    monitor_api,
    reads_monitor_videos,
    report_monitor_videos,
)
from gymmigrate.rules.wrapper_usage.origins import (
    CYCLE,
    INNER,
    MADE,
    RAW,
    WRAPPED,
    EnvOrigins,
    Origin,
)
from gymmigrate.rules.wrapper_usage.self_forwarding import self_forwarding
from gymmigrate.rules.wrapper_usage.step_keywords import decide_step_keyword
from gymmigrate.rules.wrapper_usage.tables import BASE_ENV_ATTRIBUTES, SAFE_ATTRIBUTES

RULES = (
    Rule("GM604", "attribute forwarding removed", FixKind.ASSIST, "`env.foo` -> `env.unwrapped.foo` / `env.get_wrapper_attr(\"foo\")`."),
    Rule("GM605", "env._max_episode_steps", FixKind.ASSIST, "`env._max_episode_steps` under wrappers of your own -> `env.spec.max_episode_steps` or `get_wrapper_attr`."),
    Rule(
        "GM606",
        "wrapper-stack assumptions",
        FixKind.FLAG,
        "`gym.make(id).env` -> `.unwrapped`; other `.env` chains are reported; `isinstance(env, TimeLimit)` on a stack of "
        "your own is noted; `env.step(action_dict=a)` on a make result -> `env.step(a)`.",
    ),
)


# where an isinstance check stops holding for a read: its function, class body or module
_NARROWING_ENDS = (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef, ast.Module)


class WrapperForwarding(RuleFamily):
    """GM604-GM606. In the pipeline after the wrapper subclass rules, as the LibCST pass it replaced."""

    RULES = RULES

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.origins = EnvOrigins(self.facts, self.receivers)
        self._make_layers = MakeLayers(self)
        self._wrapped_reads = WrappedReads(self.facts)
        self._iterated: set[str] | None = None  # ``_collections``
        self._env_api_receivers: set[str] | None = None  # ``_join_receiver``

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        # gym's AtariEnv's methods on the env a class works on, in a module that never names
        # the library (a subclass of another module's wrapper): only those calls are decided
        return cls._forwarding_may_fire(facts, context) or _calls_atari_methods(facts)

    @classmethod
    def _forwarding_may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        if "gym" in facts.text:
            return True
        # ``env = utils.make_env(...)`` in a file that never names the library
        project = context.options.project
        if project is None:
            return False
        if any(name in facts.text for _, name in project.made):
            return True
        # ``create, _ = make_creator(params)`` then ``create()``: a thunk of make() results
        if any(name in facts.text for names in project.made_thunks.values() for name in names):
            return True
        # ``self.env = CREATORS[name](**cfg)``: a table of another module whose creators make envs
        if any(name in facts.text for _, name, _ in project.made_tables):
            return True
        # ``class Task(pkg.BaseWrapper)``: a wrapper class of another module of the run
        if any(name in facts.text for _, name in project.wrapper_defined):
            return True
        # ``def run_agent(env): ... env.flat_actions`` in a file that never names the library,
        # called from other modules of the run with Gym envs
        view = project.view(context.path)
        if view.receives_made_holders():
            return True  # ``env.env.env`` where every caller passes ``GymEnv(name)``, holding a make result
        if any(
            EnvKind.GYM_ENV in view.param_kinds(name, arg.arg)
            for name, function in facts.functions.items()
            for arg in (*function.args.posonlyargs, *function.args.args, *function.args.kwonlyargs)
        ):
            return True
        # ``class Planner: def __init__(self, task)``, built by other modules of the run with Gym envs
        return any(
            EnvKind.GYM_ENV in view.param_kinds(f"{name}.__init__", arg.arg) or view.gym_env_handers(f"{name}.__init__", arg.arg)
            for name, classdef in facts.classes.items()
            for init in classdef.body
            if isinstance(init, FUNCTIONS) and init.name == "__init__"
            for arg in (*init.args.posonlyargs, *init.args.args, *init.args.kwonlyargs)
        )

    def decide(self) -> None:
        if not self._forwarding_may_fire(self.facts, self.context):
            for node in self.facts.parents:
                if isinstance(node, ast.Attribute):
                    atari_method_call(self, node, self.context.profile.imports_gym)
            return
        for node in self.facts.parents:  # every node once, in source order
            if isinstance(node, ast.Attribute):
                self._attribute_access(node)
        for call in self.facts.calls_by_name.get("getattr", []):
            reported = len(self.plan.findings)
            getattr_forwarding(self, call)
            if len(self.plan.findings) == reported:
                self._join_dynamic_lookup(call)
        for call in self.facts.calls_by_name.get("hasattr", []):
            reported = len(self.plan.findings)
            hasattr_through_wrappers(self, self._wrapped_reads, call)
            if len(self.plan.findings) == reported:
                self._join_dynamic_lookup(call)
        for call in self.facts.calls_by_name.get("isinstance", []):
            self._make_layers.isinstance_time_limit(call)
        for call in self.facts.attribute_calls.get("step", []):
            decide_step_keyword(self, self.origins, call)

    def _attribute_access(self, attr: ast.Attribute) -> None:
        name = attr.attr
        receiver = attr.value
        if name == "env":
            self._make_layers.env_chain(attr)
            return
        if atari_method_call(self, attr, self.context.profile.imports_gym):
            return  # gym's AtariEnv's ``_get_image()``, ``clone_full_state()``...: ale-py's has other names
        if name == "max_episode_steps" and spec_limit_on_atari(self, attr):
            return  # ``env.spec.max_episode_steps`` of an Atari make: None now
        if name == "_max_episode_steps" and max_episode_steps_on_atari(self, attr):
            return  # no TimeLimit on an Atari make now
        if name in SAFE_ATTRIBUTES or (name.startswith("__") and name.endswith("__")):
            return
        call = self.facts.parent(attr)
        if name == "_seed" and isinstance(call, ast.Call) and call.func is attr:
            return  # gym < 0.9's ``env._seed(s)`` is ``env.seed(s)``: the seeding rules' business (GM203)
        if isinstance(receiver, ast.Name) and receiver.id in ("self", "cls"):
            if receiver.id == "self":
                self_forwarding(self, attr)
            return
        if isinstance(receiver, ast.Name) and self._narrowed_to_bare_env(receiver):
            return  # ``if isinstance(env, OwnEnv):`` there env is that class itself: no layer to read through
        if gone_from_builtin(self, attr):
            self._make_layers.no_layer_has(attr)
            return
        if self._make_layers.read_through(attr) or self._make_layers.read_through_wrapper(attr):
            return
        sub_env = self.origins.is_sub_env(receiver)
        kind = self.receivers.kind_of(receiver)
        # ``self._inner`` that a base of another module stores from what this class's
        # constructions hand it: Gym envs, made or bare, where the run builds the class (SOME:
        # at some constructions, the others untraced). The receiver kinds follow the same
        # hand-up (``SelfAttributes.handed_up``): a Gym env there is still asked which.
        handed = self.origins.handed_gym_env(receiver) if kind in (EnvKind.UNKNOWN, EnvKind.GYM_ENV) else None
        if handed == SOME and self.origins.held_init_param(receiver) is not None:
            if self.receivers.test_double_callers(receiver):
                handed = None  # only tests pass something else: asked naming their doubles (_read_past_test_double)
            else:
                self._held_question(attr)
                return
        known = sub_env or handed is not None or kind is EnvKind.GYM_ENV
        monitor_read = reads_monitor_videos(self, attr, known, kind)
        if not known and not monitor_read and not self.origins.outer_is_wrapper(receiver):
            if not self._wrapped_on_some_path(attr) and not self._read_past_test_double(attr):
                self._join_gym_env_question(attr)
            return
        if monitor_read:
            report_monitor_videos(self, attr)
            return
        if monitor_api(self, attr):
            return
        origin: Origin
        if sub_env or handed == EVERY:
            origin = INNER  # what the env_fns built, or the constructions hand on: make() results, maybe wrapped
        elif handed == SOME:
            origin = None  # a Gym env where some constructions are, untraced where the others are: asked
        else:
            # what the read sees where the bindings disagree, or the name may hold its env
            # bare or wrapped: ``env = Arena()`` just above ``env = dress(env, env.size)``
            # is the bare env the size is read from
            origin = self.origins.at_read(receiver)
            if origin in (None, CYCLE, RAW) and (not known or self.origins.outer_is_wrapper(receiver)):
                origin = WRAPPED  # whatever else the name held, where it is read it is a wrapper
        if origin == CYCLE:
            origin = None
        if origin in (None, RAW) and self.origins.gym_envs_from_elsewhere(receiver, origin):
            origin = WRAPPED  # bare or made: get_wrapper_attr reads both (a Gymnasium Env has it too)
        if origin is None and isinstance(receiver, ast.Name) and self.receivers.narrowing.is_env(receiver):
            origin = WRAPPED  # ``isinstance(env, gym.Env)`` checked it: bare or wrapped, get_wrapper_attr reads both
        if origin is None and self.origins.traced_gym_env(receiver):
            origin = WRAPPED
        if origin is None and self._gym_env_on_every_path(receiver):
            origin = WRAPPED  # bare on some paths, made or wrapped on others: get_wrapper_attr reads both
        if origin is None and forwarded_through_wrapper_attr(self, receiver):
            origin = WRAPPED  # its class's ``__getattr__`` reads it through get_wrapper_attr: so do its own reads
        if origin == RAW:
            return
        if name in self.origins.outer_attributes(receiver):
            return  # the outermost wrapper has it: no forwarding involved
        code = "GM605" if name == "_max_episode_steps" else "GM604"
        if name == "_max_episode_steps" and bare_make_result(self.facts, receiver):
            # make still returns TimeLimit outermost (as gym did): the attribute is its own, and
            # a write changes the limit as before (checked on gymnasium 1.4: CartPole-v1 with
            # ``_max_episode_steps = 5`` truncates at step 5).
            self.report(
                attr,
                code,
                "`_max_episode_steps` is the TimeLimit's own attribute, and gym.make still returns TimeLimit outermost: "
                "left as it is",
                tier=Tier.NOTE,
            )
            return
        if isinstance(attr.ctx, (ast.Store, ast.Del)):
            statement = self.facts.parent(attr)
            if (origin == WRAPPED or self.origins.outer_is_wrapper(receiver)) and isinstance(statement, ast.Assign):
                # The user's own stack: the legacy write landed on its outermost wrapper, and
                # so does this one (reads through get_wrapper_attr find it there first);
                # set_wrapper_attr would reach an inner wrapper that has the name (a
                # RecordVideo's episode_trigger) and change what the program does.
                self.report(
                    attr,
                    code,
                    f"writing `{dotted_name(attr) or name}` sets it on the outermost wrapper, as it did: left as it is",
                    tier=Tier.NOTE,
                )
                return
            if (
                origin in (MADE, INNER)
                and name != "_max_episode_steps"
                and isinstance(statement, ast.Assign)
                and len(statement.targets) == 1
                and statement.targets[0] is attr
            ):
                if origin == INNER and self._forwarding_setter(attr, name):
                    # The wrapper's own setter of ``name`` handing the write to ``self.env``:
                    # a layer of this family has the property, so set_wrapper_attr calls its
                    # setter as the legacy write did; a bare env is set directly, as before;
                    # any other layer passes it down to the one that has it, where the
                    # getter's get_wrapper_attr reads it back. Nothing is left to decide.
                    self.report(
                        attr,
                        code,
                        f"the `{name}` setter hands the write to the wrapped env: `set_wrapper_attr(\"{name}\", ...)` "
                        f"sets it on the next layer that has `{name}` (this class's own setter) or on the env, as the "
                        "legacy write did",
                        tier=Tier.NOTE,
                    )
                    self.plan.replace(statement, set_wrapper_attr(name))
                    return
                holders = classes_holding(self.facts, self.receivers, receiver, name) if origin == MADE else None
                if holders is not None:
                    # Every env the make may build has the name when it is written, and no
                    # layer make adds has it: set_wrapper_attr lands on the env, as the legacy
                    # write to the bare env did. Nothing is left to check.
                    self.report(
                        attr,
                        code,
                        f"writing `{dotted_name(attr) or name}` would set it on the outermost wrapper only (writes never "
                        f"forwarded): `set_wrapper_attr(\"{name}\", ...)` sets it on the env, as a write to the bare env "
                        f"did ({', '.join(holders)} sets `{name}` when constructed, and no layer of make has it)",
                        tier=Tier.NOTE,
                    )
                    self.plan.replace(statement, set_wrapper_attr(name))
                    return
                self.report(
                    attr,
                    code,
                    f"writing `{dotted_name(attr) or name}` would set it on the outermost wrapper only (writes never "
                    f"forwarded): `set_wrapper_attr(\"{name}\", ...)` sets it on the layer that has it, the base env "
                    "when no wrapper does, as a write to the bare env did",
                )
                self.plan.replace(statement, set_wrapper_attr(name))
                return
            if origin is not None:
                self.report(
                    attr,
                    code,
                    f"writing `{dotted_name(attr) or name}` sets it on the outermost wrapper only (it never forwarded): "
                    f"use `.unwrapped.{name} = ...` or `.set_wrapper_attr(\"{name}\", ...)` to change the env",
                    kind=FixKind.FLAG,
                )
            elif handed == SOME:
                # the same decision as the reads through it: is it a (made) Gym env?
                self.report(
                    attr,
                    code,
                    f"`{dotted_name(receiver)}` is a Gym env where some constructions of this class hand one in (the "
                    f"others could not be traced): where it is a make result, writing `.{name}` sets it on the outermost "
                    "wrapper, not on the env, and reads through it raise AttributeError (forwarding is gone); use "
                    f"`.set_wrapper_attr(\"{name}\", ...)` and `.get_wrapper_attr(...)` (a Gymnasium env, wrapped or not, has both)",
                    kind=FixKind.FLAG,
                    question=("GM604", "wrapped", id(self.facts.enclosing_class(attr)), self.origins.stored_as(receiver)),
                )
            return
        text = dotted_name(receiver) or "the env"
        if (
            origin is None
            and kind is EnvKind.GYM_ENV
            and self._base_only(name)
            and not (isinstance(receiver, ast.Attribute) and receiver.attr == "env")
        ):
            # A Gym env, wrapped or not: ``unwrapped`` of a bare env is the env itself, so
            # ``.unwrapped.ale`` reads what ``.ale`` read either way; no wrapper of the run
            # defines the name to be found first. (Through an ``.env`` chain the question is
            # which layer it meant: GM606 asks it with this read.)
            self.report(
                attr,
                code,
                f"attribute forwarding is gone in Gymnasium 1.0: `{name}` belongs to the base env, read it through "
                "`.unwrapped` (the env itself when it is not wrapped)",
                tier=Tier.NOTE,
            )
            self.plan.replace(attr, through("unwrapped", name))
            self._wrapped_reads.note(attr, name, UNWRAPPED)
            return
        if origin is None:
            # One question per object ("is `self.viewer` wrapped?"): asked at its first
            # read, which names the lines of the others (the plan's ask_once); those are
            # notes pointing there, so a person fixing the item sees every read.
            owner = self._question_owner(attr, text)
            message = (
                f"could not tell whether `{text}` is wrapped: if it is, `.{name}` raises AttributeError on Gymnasium "
                f"1.x; use `.unwrapped.{name}` or `.get_wrapper_attr(\"{name}\")`"
            )
            # ``self.inner`` and the ``self._inner`` that property returns: one object; a
            # parameter fed one variable by every call (``search(env)``, ``helper(env)``): one
            # object for every def it reaches
            fed = self.origin_question(attr.value)
            question: Hashable = (
                ("GM604", "wrapped", "fed", fed) if fed is not None else ("GM604", "wrapped", id(owner), self.origins.stored_as(attr.value) or text)
            )
            self.report(attr, code, message, kind=FixKind.FLAG, question=question)
            self._asked(attr, question, message)
            return
        if name == "_max_episode_steps":
            if origin == MADE:
                self.report(attr, code, "`_max_episode_steps` is read from the spec: `.spec.max_episode_steps`", tier=Tier.NOTE)
                self.plan.replace(attr, through("spec", "max_episode_steps"))
                return
            self.report(
                attr,
                code,
                "`_max_episode_steps` is on the TimeLimit wrapper, not forwarded any more: read it with "
                "get_wrapper_attr (env.spec may be None for an env built without make)",
                tier=Tier.NOTE,  # the same attribute forwarding reached: an explanation
            )
            replace_with_get_wrapper_attr(self.facts, self.plan, attr, name)
            self._wrapped_reads.note(attr, name)
            return
        if self._base_only(name):
            self.report(
                attr,
                code,
                f"attribute forwarding is gone in Gymnasium 1.0: `{name}` belongs to the base env, read it through "
                "`.unwrapped`",
                tier=Tier.NOTE,
            )
            self.plan.replace(attr, through("unwrapped", name))
            self._wrapped_reads.note(attr, name, UNWRAPPED)
            return
        self.report(
            attr,
            code,
            f"attribute forwarding is gone in Gymnasium 1.0: `get_wrapper_attr(\"{name}\")` searches the wrappers "
            "and the base env as forwarding did",
            tier=Tier.NOTE,
        )
        replace_with_get_wrapper_attr(self.facts, self.plan, attr, name)
        self._wrapped_reads.note(attr, name)

    def _held_question(self, attr: ast.Attribute) -> None:
        """``self.task.width`` in a plain class of the run that holds its constructor's
        ``task``, given a Gym env by some constructions and something else (or what the run
        cannot trace) by the others: where it is a make result the read raises
        AttributeError, where it is not, ``.unwrapped`` would. One question per parameter,
        naming the constructions that pass a Gym env."""
        held = self.origins.held_init_param(attr.value)
        classdef = self.facts.enclosing_class(attr)
        assert held is not None and classdef is not None  # held_init_param found both
        name = attr.attr
        text = dotted_name(attr.value) or held.id
        where = ", ".join(self.origins.held_constructions(held)) or "some constructions"
        message = (
            f"`{text}` holds what the constructions of `{classdef.name}` pass for `{held.id}`: a Gym env at {where}, "
            "something else or what the run cannot trace at the others. Where it is a make() result, "
            f"`.{name}` raises AttributeError on Gymnasium 1.x (wrappers no longer forward it): use "
            f"`.unwrapped.{name}` if every construction passes a Gym env, or `.get_wrapper_attr(\"{name}\")`"
        )
        question = ("GM604", "held", id(self.facts.bindings_of(held)[0]))
        self.report(attr, "GM604", message, kind=FixKind.FLAG, question=question)
        self._asked(attr, question, message)

    def _asked(self, attr: ast.Attribute, question: Hashable, message: str) -> None:
        """A read asked about: a ``hasattr`` of the name on the same object is named by the same question."""
        if isinstance(attr.ctx, ast.Load):
            self._wrapped_reads.ask(attr, question, message)

    def _gym_env_on_every_path(self, receiver: ast.expr) -> bool:
        """Every value the receiver may hold is a Gym env the run traces, bare on some paths
        and in wrappers on others (``make_env`` returning ``gym.make(id)`` in one branch and
        ``Sim()`` in another): its origins disagree, but none is unknown."""
        reached = self.origins.reached(receiver)
        # a make on some path: a wrapper of the code's own on some paths only keeps its
        # question (which branch a helper takes is not told here)
        return MADE in reached and reached <= _TRACED_ORIGINS

    def _wrapped_on_some_path(self, attr: ast.Attribute) -> bool:
        """A read through a receiver that is a make() result (or a Gym wrapper) on some paths
        and what the run cannot trace on the others (``make_env`` returning ``gym.make(id)``
        in one branch, an instance of a class looked up by name in another): where it is
        made, the read raises AttributeError. Reported, one question per object and scope,
        as the untraced side decides between ``.unwrapped`` and leaving it."""
        if not isinstance(attr.ctx, ast.Load) or not isinstance(attr.value, ast.Name):
            # a name a factory's call bound (``env = make_env(...)``): an item of a container
            # or an attribute is told by ``origin`` alone, and unjoining its values costs a walk
            # of every item per read
            return False
        reached = self.origins.reached(attr.value)
        if None not in reached or not reached & _WRAPPER_ORIGINS:
            return False
        name = attr.attr
        text = dotted_name(attr.value) or "the env"
        owner = self._question_owner(attr, text)
        message = (
            f"`{text}` is a make() result (Gym wrappers) on some paths, and what it holds on the others could not be traced: where "
            f"it is made, `.{name}` raises AttributeError on Gymnasium 1.x (wrappers no longer forward it); use "
            f"`.unwrapped.{name}` if every path gives a Gym env (a bare env is its own `unwrapped`), or "
            f"`.get_wrapper_attr(\"{name}\")`"
        )
        question = ("GM604", "wrapped", id(owner), self.origins.stored_as(attr.value) or text)
        self.report(attr, "GM604", message, kind=FixKind.FLAG, question=question)
        self._asked(attr, question, message)
        return True

    def _question_owner(self, attr: ast.Attribute, text: str) -> ast.AST | None:
        """What one GM604 question is asked per: the class for a ``self.`` receiver, else the def."""
        return self.facts.enclosing_class(attr) if text.startswith("self.") else self.facts.enclosing_function(attr)

    def _narrowed_to_bare_env(self, read: ast.Name) -> bool:
        """Whether ``read`` sits in ``if isinstance(<name>, Cls):`` (not rebound under it)
        where ``Cls`` is a Gym env class of the run that is no Gym wrapper: an instance of
        it is the env itself, whatever wraps it elsewhere, so its reads never forwarded."""
        for guard, tested, classes in isinstance_guards(self.facts, read, _NARROWING_ENDS):
            if tested != read.id:
                continue
            if any(guard in self.facts.ancestors(binding) for binding in self.facts.bindings_of(read)):
                return False  # rebound under the check
            members = classes.elts if isinstance(classes, ast.Tuple) else [classes]
            return bool(members) and all(self._bare_env_class(member) for member in members)
        return False

    def _bare_env_class(self, expr: ast.expr) -> bool:
        """``expr`` names a Gym env class of the run that is no Gym wrapper class."""
        if isinstance(expr, ast.Name) and expr.id in self.facts.classes:
            classdef = self.facts.classes[expr.id]
            if self.facts.bindings_of(expr) != [classdef]:
                return False  # the name holds something else too
            return self.receivers.class_kind(classdef) is EnvKind.GYM_ENV and not self.receivers.is_gym_wrapper_class(classdef)
        project = self.receivers.project
        qualified = self.facts.qualified_names(expr)
        if project is None or len(qualified) != 1:
            return False
        (name,) = qualified
        return project.call_kind(name) is EnvKind.GYM_ENV and not project.is_wrapper_class(name)

    def _forwarding_setter(self, attr: ast.Attribute, name: str) -> bool:
        """Whether ``attr`` is ``self.env.<name>`` written in the class's own ``@<name>.setter``:
        the setter of a property the class defines, forwarding to the env it wraps."""
        receiver = attr.value
        if not (isinstance(receiver, ast.Attribute) and receiver.attr == "env" and isinstance(receiver.value, ast.Name)):
            return False
        function = self.facts.enclosing_function(attr)
        if function is None or not self.facts.is_method(function) or not function.args.args:
            return False
        if receiver.value.id != function.args.args[0].arg or function.name != name:
            return False
        return any(
            isinstance(d, ast.Attribute) and d.attr == "setter" and isinstance(d.value, ast.Name) and d.value.id == name
            for d in function.decorator_list
        )

    def _base_only(self, name: str) -> bool:
        """State or a method of the base envs that no wrapper class of the run defines."""
        return name in BASE_ENV_ATTRIBUTES and name not in self.origins.local_wrapper_attributes()

    def _join_dynamic_lookup(self, call: ast.Call) -> None:
        """``getattr(env, cmd)`` / ``hasattr(env, cmd)`` that no rule decided: a name of the env's own
        looked up through a wrapper stack is not found any more, as ``env.cmd`` would not be."""
        if len(call.args) < 2 or self.facts.bindings_of(call.func):  # type: ignore[arg-type]
            return
        target, looked_up = call.args[0], call.args[1]
        if isinstance(looked_up, ast.Constant) and (
            not isinstance(looked_up.value, str) or looked_up.value in SAFE_ATTRIBUTES or looked_up.value.startswith("__")
        ):
            return  # Gym's own API, or a dunder: found on every wrapper
        if isinstance(target, (ast.Name, ast.Attribute, ast.Subscript)) and not (isinstance(target, ast.Name) and target.id in ("self", "cls")):
            self._join_receiver(target, call.lineno)

    def _join_gym_env_question(self, attr: ast.Attribute) -> None:
        """``env.setMapSize(n)`` on an env whose reset or step asks whether it is a Gym env: if
        it is, a wrapper stack no longer forwards the env's own method, so that answer decides
        this read too. It is named by that item, not asked again (``Plan.join``); where nothing
        asks about the receiver, nothing is said (a proven Gym env is decided above, a proven
        other object needs nothing)."""
        if isinstance(attr.ctx, ast.Load):
            self._join_receiver(attr.value, attr.lineno)

    def _join_receiver(self, receiver: ast.expr, line: int) -> None:
        name = full_name(receiver)
        if not isinstance(receiver, ast.Subscript) and name in self._collections():
            return  # ``self.envs.append(env)``: the list of envs, not an env (its items ask the question)
        # no reset, step, seed, render or close of that name asks whether it is a Gym env (an
        # item of a collection, ``self.envs[0]``, may be asked under a loop variable's name)
        if not isinstance(receiver, ast.Subscript) and name is not None and name not in self._api_receivers():
            return
        for action in (Action.REPORT, Action.REWRITE_FOR_REVIEW):
            question = self.receiver_question(receiver, Decision(action, ""))
            # only the "is it a Gym env" questions of a receiver, not a library's port (GM107):
            # that is decided by the library, whatever the env's own methods are
            if isinstance(question, tuple) and question[0] in ("receiver", "fed", RUN_QUESTION) and question != gym_only_question(str(question[-1])):
                self.plan.join(question, line)

    def _api_receivers(self) -> set[str]:
        """The names whose env-API calls (``reset``, ``step``, ``seed``, ``render``, ``close``)
        the module makes: the receivers a "could not tell whether ... is a Gym env" question
        is asked about. Read once: asking every attribute read for its receiver's question
        cost a tenth of a large run."""
        if self._env_api_receivers is None:
            self._env_api_receivers = {
                name
                for method in ("reset", "step", "seed", "render", "close", "_reset", "_step", "_seed", "_render")
                for call in self.facts.attribute_calls.get(method, ())
                if (name := full_name(call.func.value)) is not None  # type: ignore[attr-defined]
            }
        return self._env_api_receivers

    def _collections(self) -> set[str]:
        """The names the module iterates over or subscripts (``for env in self.envs``, ``self.envs[0]``):
        collections of envs, whose items the questions are about."""
        if self._iterated is None:
            self._iterated = set()
            for node in walk(self.facts.tree):
                value = node.iter if isinstance(node, (ast.For, ast.AsyncFor, ast.comprehension)) else node.value if isinstance(node, ast.Subscript) else None
                name = full_name(value) if value is not None else None
                if name:
                    self._iterated.add(name)
        return self._iterated

    def _read_past_test_double(self, attr: ast.Attribute) -> bool:
        """``self.environment.ale.lives()`` where this module's own calls hand ``environment`` a
        Gym env and only a test module passes a double of its own (``MockEnv`` that sets
        ``self.ale``): the double has the attribute, the made env's wrappers do not (forwarding
        is gone), so the production read raises AttributeError. ``.unwrapped.ale`` would fail
        on the double, which has no ``unwrapped``: the change is for a person, with both sides named."""
        name = attr.attr
        if name not in BASE_ENV_ATTRIBUTES or not isinstance(attr.ctx, ast.Load):
            return False
        doubles = self.receivers.test_double_callers(attr.value)
        if not doubles:
            return False
        text = dotted_name(attr.value) or "the env"
        owner = self._question_owner(attr, text)
        self.report(
            attr,
            "GM604",
            f"`{text}` is a Gym env where this module makes it, and only tests pass a double of their own "
            f"({', '.join(doubles)}): on the made env `.{name}` raises AttributeError (its wrappers no longer forward "
            f"it); read `.unwrapped.{name}`, and give the test double an `unwrapped` that returns itself",
            kind=FixKind.FLAG,
            question=("GM604", "test double", id(owner), text),
        )
        return True


# What a traced Gym env comes from, and of those, what is a wrapper stack where it is read.
_WRAPPER_ORIGINS = frozenset({MADE, WRAPPED, INNER})
_TRACED_ORIGINS = _WRAPPER_ORIGINS | {RAW}


def _calls_atari_methods(facts: ModuleFacts) -> bool:
    """The text calls one of gym's AtariEnv's methods (``seed`` only through ``.unwrapped``:
    every env had one)."""
    return any(word in facts.text for word in ATARI_METHOD_WORDS)
