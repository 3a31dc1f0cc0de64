"""Attribute forwarding is gone (GM604-GM606): what legacy code read through ``Wrapper.__getattr__``.

Gymnasium 1.0 removed ``Wrapper.__getattr__``, so on an env built through ``make`` or
wrappers ``env.x_threshold`` raises ``AttributeError``:

* GM604 (ASSIST) base-env state and methods become ``env.unwrapped.foo``; anything a
  wrapper may define becomes ``env.get_wrapper_attr("foo")`` (outermost to base, exactly
  what forwarding did). Writes are reported (forwarding never applied to them). A raw env
  built by its own constructor never had the problem. ``env.env.state`` on a bare make
  result becomes ``env.unwrapped.state``: make's layers have no ``state`` to shadow it.
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
this module (the decisions on ``env.x`` and ``.env`` chains) and three siblings:
``origins.py`` (where an env comes from, which wrapper is outermost and what it defines),
``bare_make.py`` (which names hold a bare make result), ``self_forwarding.py`` (``self.x``
in a wrapper class's own methods) and
``forwarding_edits.py`` (the LibCST builders of the rewrites).
"""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import dotted_name
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.wrapper_usage.atari_limits import (
    is_make_call,
    isinstance_time_limit_on_atari,
    max_episode_steps_on_atari,
    spec_limit_on_atari,
)
from gymmigrate.rules.wrapper_usage.bare_make import bare_make, bare_make_result
from gymmigrate.rules.wrapper_usage.forwarding_edits import (
    replace_with_get_wrapper_attr,
    set_wrapper_attr,
    through,
    unwrapped_below,
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
from gymmigrate.rules.wrapper_usage.tables import (
    BASE_ENV_ATTRIBUTES,
    SAFE_ATTRIBUTES,
    wrapper_rest,
)

RULES = (
    Rule("GM604", "attribute forwarding removed", FixKind.ASSIST, "`env.foo` -> `env.unwrapped.foo` / `env.get_wrapper_attr(\"foo\")`."),
    Rule("GM605", "env._max_episode_steps", FixKind.ASSIST, "`env._max_episode_steps` under wrappers of your own -> `env.spec.max_episode_steps` or `get_wrapper_attr`."),
    Rule("GM606", "wrapper-stack assumptions", FixKind.FLAG, "`gym.make(id).env` -> `.unwrapped`; other `.env` chains are reported; `isinstance(env, TimeLimit)` on a stack of your own is noted."),
)

# gym.make's layers, legacy (TimeLimit, OrderEnforcing, PassiveEnvChecker in gym 0.24-0.26) and
# Gymnasium 1.4 (the same three).
_MAKE_LAYERS = 3
# Public attributes those layers define themselves (``vars()`` of each layer on gymnasium 1.4,
# and gym 0.26's): a read of one through ``.env`` may mean the wrapper's.
_MAKE_LAYER_ATTRIBUTES = frozenset(
    {"has_reset", "checked_reset", "checked_step", "checked_render", "checked_data_reuse", "close_called"}
)



# Attributes of gym's Monitor itself that no Gymnasium wrapper has: ``videos`` (the
# (video, metadata) paths it wrote).
_MONITOR_ONLY_ATTRIBUTES = frozenset({"videos"})

def _get_wrapper_attr_of():
    """``getattr(target, name)`` -> ``target.get_wrapper_attr(name)``."""

    def build(node: cst.Call) -> cst.BaseExpression:
        return cst.Call(
            func=cst.Attribute(value=node.args[0].value, attr=cst.Name("get_wrapper_attr")),
            args=[cst.Arg(value=node.args[1].value)],
            lpar=node.lpar,
            rpar=node.rpar,
        )

    return build


def _has_wrapper_attr():
    """``hasattr(x, "name")`` -> ``x.has_wrapper_attr("name")``."""

    def build(node: cst.Call) -> cst.BaseExpression:
        receiver, key = node.args
        return cst.Call(
            func=cst.Attribute(value=receiver.value, attr=cst.Name("has_wrapper_attr")),
            args=[key.with_changes(comma=cst.MaybeSentinel.DEFAULT)],
            lpar=node.lpar,
            rpar=node.rpar,
        )

    return build


class WrapperForwarding(RuleFamily):
    """GM604-GM606. In the pipeline after the wrapper subclass rules, as the LibCST pass it replaced."""

    RULES = RULES

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.origins = EnvOrigins(self.facts, self.receivers)
        self._through_make: set[int] = set()  # ``env.env.state`` rewritten to ``env.unwrapped.state``
        # (owner id, receiver text, name) of reads rewritten to get_wrapper_attr: a
        # ``hasattr`` of the same name on the same receiver rests on the same proof.
        self._wrapped_reads: set[tuple[int, str, str]] = set()

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        if "gym" in facts.text:
            return True
        # ``env = utils.make_env(...)`` in a file that never names the library
        project = context.options.project
        if project is None:
            return False
        if any(name in facts.text for _, name in project.made):
            return True
        # ``class Task(pkg.BaseWrapper)``: a wrapper class of another module of the run
        if any(name in facts.text for _, name in project.wrapper_defined):
            return True
        # ``def run_agent(env): ... env.flat_actions`` in a file that never names the library,
        # called from other modules of the run with Gym envs
        view = project.view(context.path)
        return any(
            EnvKind.GYM_ENV in view.param_kinds(name, arg.arg)
            for name, function in facts.functions.items()
            for arg in (*function.args.posonlyargs, *function.args.args, *function.args.kwonlyargs)
        )

    def decide(self) -> None:
        for node in self.facts.parents:  # every node once, in source order
            if isinstance(node, ast.Attribute):
                self._attribute_access(node)
        for call in self.facts.calls_by_name.get("getattr", []):
            self._getattr_forwarding(call)
        for call in self.facts.calls_by_name.get("hasattr", []):
            self._hasattr_through_wrappers(call)
        for call in self.facts.calls_by_name.get("isinstance", []):
            if self._tests_time_limit(call) and isinstance_time_limit_on_atari(self, call):
                continue  # an Atari make has no TimeLimit now
            if self._is_isinstance_timelimit(call):
                # Gymnasium's make still puts TimeLimit outermost, as gym's did: the test
                # answers as before (and failed as before under wrappers of the code's own).
                self.report(
                    call,
                    "GM606",
                    "gym.make still returns TimeLimit outermost (around OrderEnforcing and PassiveEnvChecker), so this "
                    "test answers as it did; `env.spec.max_episode_steps` also works under wrappers of your own",
                    tier=Tier.NOTE,
                )

    def _read_owner(self, node: ast.AST, text: str) -> ast.AST | None:
        """What one receiver text names the same object in: the class for ``self.x``, else
        the function (or module) the read sits in."""
        if text.startswith("self."):
            return self.facts.enclosing_class(node)
        return self.facts.enclosing_function(node) or self.facts.tree

    def _note_wrapped_read(self, attr: ast.Attribute, name: str) -> None:
        text = dotted_name(attr.value)
        owner = self._read_owner(attr, text) if text else None
        if text and owner is not None:
            self._wrapped_reads.add((id(owner), text, name))

    def _hasattr_through_wrappers(self, call: ast.Call) -> None:
        """``hasattr(env, "x")`` guarding a read ``env.x`` the run rewrote to
        ``get_wrapper_attr``: the same proof says ``env`` is wrapped, and without
        forwarding the test is False for what only an inner layer has, so the guarded
        branch would be dead. ``has_wrapper_attr`` looks through every layer (gymnasium
        1.4: a Wrapper asks itself, then its env; an Env itself), as legacy forwarding
        answered for public names (gym refused to forward ``_private`` ones: left alone)."""
        if self.facts.bindings_of(call.func) or len(call.args) != 2 or call.keywords:  # type: ignore[arg-type]
            return
        receiver, key = call.args
        if not (isinstance(key, ast.Constant) and isinstance(key.value, str)) or key.value.startswith("_"):
            return
        text = dotted_name(receiver)
        owner = self._read_owner(call, text) if text else None
        if not text or owner is None or (id(owner), text, key.value) not in self._wrapped_reads:
            return
        self.report(
            call,
            "GM604",
            f"attribute forwarding is gone in Gymnasium 1.0, so `hasattr` is False for what only the env below the "
            f"wrappers has: `{text}.has_wrapper_attr(\"{key.value}\")` looks through every layer, as the "
            f"`get_wrapper_attr(\"{key.value}\")` read it guards does",
            tier=Tier.NOTE,
        )
        self.plan.replace(call, _has_wrapper_attr())

    def _getattr_forwarding(self, call: ast.Call) -> None:
        """``def __getattr__(self, name): return getattr(self._env, name)`` with ``self._env``
        a make result or a wrapper stack: legacy gym's wrappers forwarded the lookup on to the
        base env, Gymnasium's do not, so what only the base env (or an inner wrapper) has now
        raises AttributeError through this class. One question at the lookup: the fix
        (``get_wrapper_attr``, ``.unwrapped``) depends on what callers read through it."""
        if self.facts.bindings_of(call.func) or len(call.args) != 2 or call.keywords:  # type: ignore[arg-type]
            return
        function = self.facts.enclosing_function(call)
        classdef = self.facts.enclosing_class(call)
        if function is None or classdef is None or self.facts.parent(function) is not classdef:
            return
        params = [*function.args.posonlyargs, *function.args.args]
        if function.name not in ("__getattr__", "__getattribute__") or len(params) != 2:
            return
        target, looked_up = call.args
        if not (isinstance(looked_up, ast.Name) and looked_up.id == params[1].arg and self.facts.bindings_of(looked_up) == [params[1]]):
            return
        held = dotted_name(target)
        stored = self._looked_up_attribute(target)
        values: list[ast.expr] = [target]
        if stored is not None:
            held = f"self.{stored}"
            values = self.receivers.self_stores(classdef).get(stored, [])
        if not values or held is None:
            return
        # a make result or wrappers; or a Gym env by type (an isinstance test, an annotation),
        # which callers make with make: a raw env has its attributes itself, an unknown
        # target is not asked about
        origins = [self.origins.origin(v) for v in values]
        if not (any(o in (MADE, WRAPPED) for o in origins) or any(self.receivers.kind_of(v) is EnvKind.GYM_ENV for v in values)):
            return
        if any(o == RAW for o in origins):
            return
        if all(o in (MADE, WRAPPED) or self.receivers.kind_of(v) is EnvKind.GYM_ENV for o, v in zip(origins, values)):
            # Every object it can hold is a Gym env: ``get_wrapper_attr`` looks the name up
            # on each layer down to the base env, as gym's forwarding did, and raises
            # AttributeError for a name none has (checked on gymnasium 1.4), so ``hasattr``
            # and ``getattr(x, name, default)`` on this class answer as they did.
            self.report(
                call,
                "GM604",
                f"`{classdef.name}.{function.name}` forwards unknown attributes to `{held}`, a Gym env: Gymnasium's "
                f"wrappers no longer forward them to the env below, `{held}.get_wrapper_attr({looked_up.id})` looks "
                "through every layer as gym's forwarding did",
                tier=Tier.NOTE,
            )
            self.plan.replace(call, _get_wrapper_attr_of())
            return
        self.report(
            call,
            "GM604",
            f"`{classdef.name}.{function.name}` forwards unknown attributes to `{held}`, which holds a Gym env made "
            "with make or wrappers (and, at other stores, objects not shown to be Gym envs): Gymnasium's wrappers "
            "no longer forward attribute reads to the env below them, so what only the base env or an inner "
            "wrapper defines now raises AttributeError here; forward with "
            f"`{held}.get_wrapper_attr({looked_up.id})` (every layer, as gym's forwarding did) or read `{held}.unwrapped`",
            kind=FixKind.FLAG,
        )

    def _looked_up_attribute(self, target: ast.expr) -> str | None:
        """``x`` for a name bound once to ``super().__getattribute__("x")`` or
        ``object.__getattribute__(self, "x")`` (how a ``__getattr__`` reads its own slot
        without recursing), else None."""
        if not isinstance(target, ast.Name):
            return None
        bindings = self.facts.bindings_of(target)
        statement = self.facts.parent(bindings[0]) if len(bindings) == 1 else None
        if not (isinstance(statement, ast.Assign) and statement.targets == bindings and isinstance(statement.value, ast.Call)):
            return None
        call = statement.value
        if not (isinstance(call.func, ast.Attribute) and call.func.attr == "__getattribute__") or call.keywords or not call.args:
            return None
        name = call.args[-1]
        return name.value if isinstance(name, ast.Constant) and isinstance(name.value, str) and len(call.args) <= 2 else None

    def _records_with_gym_monitor(self) -> bool:
        """This module wraps an env in gym's ``Monitor`` or in the ``RecordVideo`` that replaces
        it (a later pass of the run, or a second run, sees that one)."""

        def scan() -> bool:
            for node in self.facts.parents:
                if isinstance(node, ast.Call) and isinstance(node.func, (ast.Name, ast.Attribute)):
                    last = node.func.id if isinstance(node.func, ast.Name) else node.func.attr
                    if last in ("Monitor", "RecordVideo") and any(
                        (N.strip_gym_prefix(q) or "").startswith("wrappers.") for q in self.facts.qualified_names(node.func)
                    ):
                        return True
            return False

        return bool(self.facts.memo(("records-with-gym-monitor", id(self.facts.tree)), scan))

    def _closes_monitor_of_env(self, attr: ast.Attribute) -> bool:
        """``env.monitor.close()`` as a statement, ``env`` a name the run shows is a Gym env
        and that nothing in its scope reads after this line (``close`` closes the env too)."""
        receiver, close = attr.value, self.facts.parent(attr)
        call = self.facts.parent(close) if close is not None else None
        if not (
            isinstance(receiver, ast.Name)
            and isinstance(close, ast.Attribute)
            and close.attr == "close"
            and isinstance(call, ast.Call)
            and call.func is close
            and not call.args
            and not call.keywords
            and isinstance(self.facts.parent(call), ast.Expr)
        ):
            return False
        if self.receivers.kind_of(receiver) is not EnvKind.GYM_ENV:
            return False
        scope = self.facts.scope_of(receiver)
        return not any(read.lineno > call.lineno for read in scope.reads.get(receiver.id, []))

    def _attribute_access(self, attr: ast.Attribute) -> None:
        name = attr.attr
        receiver = attr.value
        if name == "env":
            self._check_env_chain(attr)
            return
        if name == "max_episode_steps" and spec_limit_on_atari(self, attr):
            return  # ``env.spec.max_episode_steps`` of an Atari make: None now
        if name == "_max_episode_steps" and max_episode_steps_on_atari(self, attr):
            return  # no TimeLimit on an Atari make now
        if name in SAFE_ATTRIBUTES or (name.startswith("__") and name.endswith("__")):
            return
        if isinstance(receiver, ast.Name) and receiver.id in ("self", "cls"):
            if receiver.id == "self":
                self_forwarding(self, attr)
            return
        if self._through_make_layers(attr):
            return
        sub_env = self.origins.is_sub_env(receiver)
        kind = self.receivers.kind_of(receiver)
        known = sub_env or kind is EnvKind.GYM_ENV
        # ``env.videos`` in a module that records with Monitor, on an env the run cannot trace
        # (made by a factory handed around): no other object there is shown to have videos
        monitor_read = (
            name in _MONITOR_ONLY_ATTRIBUTES
            and isinstance(attr.ctx, ast.Load)
            and (known or kind is EnvKind.UNKNOWN or self.origins.outer_is_wrapper(receiver))
            and self._records_with_gym_monitor()
        )
        if not known and not monitor_read and not self.origins.outer_is_wrapper(receiver):
            self._read_past_test_double(attr)
            return
        if monitor_read:
            # gym's Monitor kept the list of the videos it wrote; RecordVideo, which the run
            # puts in its place (GM611), keeps none, so no forwarding can reach one.
            self.report(
                attr,
                "GM604",
                f"`{dotted_name(attr) or name}` was gym Monitor's list of (video, metadata) file pairs; RecordVideo, "
                "which replaces the Monitor here, keeps no such list (AttributeError on Gymnasium, through "
                "`get_wrapper_attr` too): list the .mp4 files it writes in its video_folder instead (it writes no "
                "metadata json)",
                kind=FixKind.FLAG,
            )
            return
        if name == "monitor" and isinstance(attr.ctx, ast.Load) and self._closes_monitor_of_env(attr):
            # ``env.monitor.close()`` on an env the run made, read no more afterwards: the
            # wrapper that recorded is gone, ``env.close()`` is what the item would say.
            self.plan.replace(attr, lambda node: node.value)
            self.report(
                attr,
                "GM604",
                f"`{dotted_name(attr)}.close()` (gym < 0.9's monitor API) -> `{dotted_name(receiver)}.close()`: the env is not "
                "used after it; record with `RecordVideo`/`RecordEpisodeStatistics` around the env",
                kind=FixKind.AUTO,
            )
            return
        if name == "monitor" and isinstance(attr.ctx, ast.Load):
            # gym < 0.9's ``env.monitor.start(dir)`` / ``.close()``: no wrapper has it to forward.
            self.report(
                attr,
                "GM604",
                f"`{dotted_name(attr) or name}` (gym < 0.9's monitor API) is gone, and no wrapper has it: record with "
                "`RecordVideo`/`RecordEpisodeStatistics` around the env; `.monitor.close()` becomes `.close()` "
                "(which also closes the env)",
                kind=FixKind.FLAG,
                question=("GM604", "monitor", dotted_name(receiver)),
            )
            return
        origin: Origin
        if sub_env:
            origin = INNER  # what the env_fns built: make() results, maybe wrapped
        else:
            origin = self.origins.origin(receiver)
            if origin is None and isinstance(receiver, ast.Name):
                # what the read sees where the bindings disagree: ``env = Arena()`` just above
                # ``env = dress(env, env.size)`` is the bare env the size is read from
                origin = self.origins.above(receiver)
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
            return
        if origin is None:
            # One question per object ("is `self.viewer` wrapped?"): asked at its first
            # read, which names the lines of the others (the plan's ask_once); those are
            # notes pointing there, so a person fixing the item sees every read.
            owner = self.facts.enclosing_class(attr) if text.startswith("self.") else self.facts.enclosing_function(attr)
            self.report(
                attr,
                code,
                f"could not tell whether `{text}` is wrapped: if it is, `.{name}` raises AttributeError on Gymnasium "
                f"1.x; use `.unwrapped.{name}` or `.get_wrapper_attr(\"{name}\")`",
                kind=FixKind.FLAG,
                question=("GM604", "wrapped", id(owner), text),
            )
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
            self._note_wrapped_read(attr, name)
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
            return
        self.report(
            attr,
            code,
            f"attribute forwarding is gone in Gymnasium 1.0: `get_wrapper_attr(\"{name}\")` searches the wrappers "
            "and the base env as forwarding did",
            tier=Tier.NOTE,
        )
        replace_with_get_wrapper_attr(self.facts, self.plan, attr, name)
        self._note_wrapped_read(attr, name)

    def _base_only(self, name: str) -> bool:
        """State or a method of the base envs that no wrapper class of the run defines."""
        return name in BASE_ENV_ATTRIBUTES and name not in self.origins.local_wrapper_attributes()

    def _read_past_test_double(self, attr: ast.Attribute) -> None:
        """``self.environment.ale.lives()`` where this module's own calls hand ``environment`` a
        Gym env and only a test module passes a double of its own (``MockEnv`` that sets
        ``self.ale``): the double has the attribute, the made env's wrappers do not (forwarding
        is gone), so the production read raises AttributeError. ``.unwrapped.ale`` would fail
        on the double, which has no ``unwrapped``: the change is for a person, with both sides named."""
        name = attr.attr
        if name not in BASE_ENV_ATTRIBUTES or not isinstance(attr.ctx, ast.Load):
            return
        doubles = self.receivers.test_double_callers(attr.value)
        if not doubles:
            return
        text = dotted_name(attr.value) or "the env"
        owner = self.facts.enclosing_class(attr) if text.startswith("self.") else self.facts.enclosing_function(attr)
        self.report(
            attr,
            "GM604",
            f"`{text}` is a Gym env where this module makes it, and only tests pass a double of their own "
            f"({', '.join(doubles)}): on the made env `.{name}` raises AttributeError (its wrappers no longer forward "
            f"it); read `.unwrapped.{name}`, and give the test double an `unwrapped` that returns itself",
            kind=FixKind.FLAG,
            question=("GM604", "test double", id(owner), text),
        )

    def _through_make_layers(self, attr: ast.Attribute) -> bool:
        """``env.env.state`` (read or written) with ``env`` a bare ``gym.make`` result: gym's
        make stacked at most TimeLimit, OrderEnforcing and PassiveEnvChecker, none with a
        public ``state``, so whichever layer ``.env`` named, the read reached the base env
        (gym <= 0.20: ``.env`` was the env itself; later: forwarded). Gymnasium's make stacks
        the same layers and forwards nothing: ``env.unwrapped.state`` is the base env's.
        Checked on gymnasium 1.4: CartPole-v1's ``.env.state`` raises, ``.env.state = s``
        sets it on OrderEnforcing, ``.unwrapped.state = s`` is the state the next step uses."""
        name = attr.attr
        if name.startswith("_") or name in _MAKE_LAYER_ATTRIBUTES:
            return False  # gym never forwarded private names; the layers' own stay theirs
        chain: ast.expr = attr.value
        depth = 0
        while True:
            if depth == _MAKE_LAYERS or not (isinstance(chain, ast.Attribute) and chain.attr == "env"):
                return False  # deeper than make's layers is past the base env
            chain, depth = chain.value, depth + 1
            if bare_make(self.facts, self.receivers, chain, frozenset()):
                break
        receiver = dotted_name(chain) or self.facts.segment(chain)
        text = dotted_name(attr) or f"{receiver}{'.env' * depth}.{name}"
        if isinstance(attr.ctx, ast.Load):
            message = (
                f"`{text}` -> `{receiver}.unwrapped.{name}`: gym.make's wrappers have no `{name}`, so the read reached "
                "the base env; Gymnasium's make stacks the same wrappers and forwards nothing"
            )
        else:
            message = (
                f"`{text}` -> `{receiver}.unwrapped.{name}`: the write meant the base env under gym.make's wrappers; "
                "on Gymnasium it would set the attribute on a wrapper (OrderEnforcing) and the env would not see it"
            )
        self.report(attr, "GM604", message, kind=FixKind.AUTO, tier=Tier.NOTE)
        self.plan.replace(attr, unwrapped_below(depth))
        self._through_make.add(id(attr))
        return True

    def _check_env_chain(self, attr: ast.Attribute) -> None:
        parent = self.facts.parent(attr)
        if isinstance(parent, ast.Attribute) and parent.value is attr and parent.attr == "env":
            return  # report the outermost ``.env`` of a chain once
        if isinstance(parent, ast.Attribute) and parent.value is attr and id(parent) in self._through_make:
            return  # GM604 rewrote the read through it to ``.unwrapped``: the chain is gone
        receiver = attr.value
        depth = 1
        while isinstance(receiver, ast.Attribute) and receiver.attr == "env":
            receiver = receiver.value
            depth += 1
        if isinstance(receiver, ast.Name) and receiver.id == "self":
            return
        if self.receivers.kind_of(receiver) is not EnvKind.GYM_ENV:
            return
        origin = self.origins.origin(receiver)
        if origin is None and isinstance(receiver, ast.Name):
            origin = self.origins.above(receiver)
        if depth == 1 and is_make_call(self.facts, receiver):
            # gym 0.21's make returned TimeLimit(env): ``gym.make(id).env`` was the env
            # itself, without its time limit. Gymnasium's make adds layers under the
            # TimeLimit; ``.unwrapped`` is that env again.
            self.plan.replace(attr, lambda node: node.with_changes(attr=cst.Name("unwrapped")))
            self.report(
                attr,
                "GM606",
                "`gym.make(id).env` -> `.unwrapped`: it meant the env without its TimeLimit (gym 0.21's make "
                "returned TimeLimit(env)); Gymnasium's make puts more wrappers under the TimeLimit",
                FixKind.AUTO,
            )
            return
        if origin == MADE or (depth >= 2 and origin in (WRAPPED, INNER)):
            message = (
                "gym.make now returns TimeLimit(OrderEnforcing(PassiveEnvChecker(env))), so `.env` chains reach "
                "a different layer: use gym.make(id, max_episode_steps=-1) to drop the time limit, or `.unwrapped`"
            )
            outer = self.facts.parent(attr)
            if isinstance(outer, ast.Attribute) and outer.value is attr and self._forwarding_reported(outer):
                # ``env.env.state``: GM604 asks about `.state` read through this very chain, and
                # its answer (`.unwrapped.state`) settles which layer `.env` meant: one decision.
                self.report(attr, "GM606", f"{message} (decided with GM604's item on `.{outer.attr}` here)", tier=Tier.NOTE)
                return
            self.report(
                attr,
                "GM606",
                message,
                # The chains of one env in one function ask one question: which layer they mean.
                question=("GM606", id(self.facts.enclosing_function(attr) or self.facts.tree), self.facts.segment(receiver)),
            )

    def _forwarding_reported(self, outer: ast.Attribute) -> bool:
        """GM604 already took up this read (attributes are decided in source order, the
        outer ``env.env.state`` before its ``env.env``)."""
        return any(
            node is outer and finding.rule == "GM604"
            for finding, node in zip(self.plan.findings, self.plan.finding_nodes)
        )

    def _tests_time_limit(self, call: ast.Call) -> bool:
        if len(call.args) != 2 or call.keywords:
            return False
        classes = call.args[1]
        candidates = list(classes.elts) if isinstance(classes, ast.Tuple) else [classes]
        return any(wrapper_rest(q) == "TimeLimit" for candidate in candidates for q in self.facts.qualified_names(candidate))

    def _is_isinstance_timelimit(self, call: ast.Call) -> bool:
        if not self._tests_time_limit(call):
            return False
        # A make() result itself: TimeLimit is its outermost wrapper in gym and in Gymnasium.
        return not bare_make_result(self.facts, call.args[0])
