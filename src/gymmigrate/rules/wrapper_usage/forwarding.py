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

Where an env comes from (its *origin*) decides between those rewrites. Origins are
memoized per name binding site, and a name whose origin is being computed counts as
"no evidence" when reached again, so the classic ``env = Wrapper(env)`` preprocessing
stack costs one visit per assignment instead of one per path through them.
"""

from __future__ import annotations

import ast
import bisect

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.limits import self_stores
from gymmigrate.facts.module import FUNCTIONS, call_argument, dotted_name, own_returns
from gymmigrate.facts.pytest_params import fixture_values, param_fixtures
from gymmigrate.facts.wrapper_attributes import (
    self_defined,
    self_defined_in,
    takes_lookup_in_hand,
)
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.wrapper_usage.atari_limits import (
    isinstance_time_limit_on_atari,
    max_episode_steps_on_atari,
    spec_limit_on_atari,
)
from gymmigrate.rules.wrapper_usage.tables import (
    BASE_ENV_ATTRIBUTES,
    OWN_ATTRIBUTES,
    SAFE_ATTRIBUTES,
    current_name,
    wrapper_rest,
)

RULES = (
    Rule("GM604", "attribute forwarding removed", FixKind.ASSIST, "`env.foo` -> `env.unwrapped.foo` / `env.get_wrapper_attr(\"foo\")`."),
    Rule("GM605", "env._max_episode_steps", FixKind.ASSIST, "`env._max_episode_steps` under wrappers of your own -> `env.spec.max_episode_steps` or `get_wrapper_attr`."),
    Rule("GM606", "wrapper-stack assumptions", FixKind.FLAG, "`gym.make(id).env` -> `.unwrapped`; other `.env` chains are reported; `isinstance(env, TimeLimit)` on a stack of your own is noted."),
)

# Where an env came from.
MADE = "made"  # gym.make (+ wrappers): a wrapper stack with a spec
WRAPPED = "wrapped"  # wrapper constructors around something else: a stack, maybe no spec
INNER = "inner"  # a wrapper's ``self.env`` / ``env`` argument: almost always a make() result
RAW = "raw"  # an env class's constructor or ``.unwrapped``: no wrapper in between
# Reached a name whose origin is being computed (``env = Wrapper(env)``): no evidence
# either way; the other bindings decide.
CYCLE = "cycle"
# Deeper than any real chain of distinct names; beyond it the origin is unknown (reported).
MAX_DEPTH = 20

Origin = str | None
_SYNC_VECTOR_ENVS = frozenset({"vector.SyncVectorEnv", "vector.sync_vector_env.SyncVectorEnv"})


def join_origins(origins: list[Origin]) -> Origin:
    found = set(origins)
    found.discard(CYCLE)
    if not found:
        return CYCLE if origins else None
    if None in found:
        return None
    if len(found) == 1:
        return found.pop()
    if RAW in found:
        return None
    return WRAPPED if WRAPPED in found or INNER in found else MADE


class WrapperForwarding(RuleFamily):
    """GM604-GM606. In the pipeline after the wrapper subclass rules, as the LibCST pass it replaced."""

    RULES = RULES

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self._name_origins: dict[tuple[int, str], Origin] = {}
        self._in_progress: set[tuple[int, str]] = set()
        self._param_origins: dict[ast.arg, Origin] = {}
        self._depth = 0
        self._local_attrs: set[str] | None = None
        self._through_make: set[int] = set()  # ``env.env.state`` rewritten to ``env.unwrapped.state``
        self._class_attrs: dict[ast.ClassDef, set[str]] = {}
        # (scope, name) -> (lines, values) of its assignments, sorted by line; None if one is not ``x = ...``
        self._assign_lines: dict[tuple[int, str], tuple[list[int], list[ast.expr]] | None] = {}

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

    # -- GM604 / GM605 / GM606: attribute access on envs ------------------------------------------

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
                self._self_forwarding(attr)
            return
        if self._through_make_layers(attr):
            return
        sub_env = self._is_sub_env(receiver)
        known = sub_env or self.receivers.kind_of(receiver) is EnvKind.GYM_ENV
        if not known and not self._outer_is_wrapper(receiver):
            self._read_past_test_double(attr)
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
            origin = self._origin(receiver)
            if origin is None and isinstance(receiver, ast.Name):
                origin = self._dominating_origin(receiver)
            if origin in (None, CYCLE, RAW) and (not known or self._outer_is_wrapper(receiver)):
                origin = WRAPPED  # whatever else the name held, where it is read it is a wrapper
        if origin == CYCLE:
            origin = None
        if origin in (None, RAW) and self._gym_envs_from_elsewhere(receiver, origin):
            origin = WRAPPED  # bare or made: get_wrapper_attr reads both (a Gymnasium Env has it too)
        if origin is None and isinstance(receiver, ast.Name) and self.receivers.narrowing.is_env(receiver):
            origin = WRAPPED  # ``isinstance(env, gym.Env)`` checked it: bare or wrapped, get_wrapper_attr reads both
        if origin is None and self._traced_gym_env(receiver):
            origin = WRAPPED
        if origin == RAW:
            return
        if name in self._outer_attributes(receiver):
            return  # the outermost wrapper has it: no forwarding involved
        code = "GM605" if name == "_max_episode_steps" else "GM604"
        if name == "_max_episode_steps" and self._bare_make_result(receiver):
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
            if (origin == WRAPPED or self._outer_is_wrapper(receiver)) and isinstance(statement, ast.Assign):
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
                self.plan.replace(statement, _set_wrapper_attr(name))
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
                self.plan.replace(attr, _through("spec", "max_episode_steps"))
                return
            self.report(
                attr,
                code,
                "`_max_episode_steps` is on the TimeLimit wrapper, not forwarded any more: read it with "
                "get_wrapper_attr (env.spec may be None for an env built without make)",
                tier=Tier.NOTE,  # the same attribute forwarding reached: an explanation
            )
            self._replace_with_get_wrapper_attr(attr, name)
            return
        if name in BASE_ENV_ATTRIBUTES and name not in self._local_wrapper_attributes():
            self.report(
                attr,
                code,
                f"attribute forwarding is gone in Gymnasium 1.0: `{name}` belongs to the base env, read it through "
                "`.unwrapped`",
                tier=Tier.NOTE,
            )
            self.plan.replace(attr, _through("unwrapped", name))
            return
        self.report(
            attr,
            code,
            f"attribute forwarding is gone in Gymnasium 1.0: `get_wrapper_attr(\"{name}\")` searches the wrappers "
            "and the base env as forwarding did",
            tier=Tier.NOTE,
        )
        self._replace_with_get_wrapper_attr(attr, name)

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
            if self._bare_make(chain, frozenset()):
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
        self.plan.replace(attr, _unwrapped_below(depth))
        self._through_make.add(id(attr))
        return True

    def _bare_make(self, expr: ast.expr, seen: frozenset[int]) -> bool:
        """``expr`` is, on every path, what ``gym.make(...)`` returned with no wrapper of any
        kind around it: the call itself, a name or ``self.x`` every binding of which is one
        (``x = y`` followed), a parameter of a module function every call here passes one."""
        if self._is_make_call(expr):
            return True
        if id(expr) in seen:
            return False
        seen |= {id(expr)}
        if isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and expr.value.id == "self":
            classdef = self.facts.enclosing_class(expr)
            if classdef is None or self.receivers.is_gym_wrapper_class(classdef):
                return False  # a wrapper's ``self.env`` is whatever it wraps
            values = self_stores(self.facts, classdef, expr.attr)
            if not values:
                return False
            return all(self._bare_make(value, seen) for value in values)
        if not isinstance(expr, ast.Name):
            return False
        bindings = self.facts.bindings_of(expr)
        if not bindings:
            return False
        for binding in bindings:
            if id(binding) in seen:
                return False
            if isinstance(binding, ast.arg):
                if not self._param_bare_make(binding, seen | {id(binding)}):
                    return False
                continue
            statement = self.facts.parent(binding)
            if not (isinstance(statement, ast.Assign) and statement.targets == [binding]):
                return False
            if not self._bare_make(statement.value, seen | {id(binding)}):
                return False
        return True

    def _param_bare_make(self, param: ast.arg, seen: frozenset[int]) -> bool:
        arguments = self.facts.parent(param)
        function = self.facts.parent(arguments) if arguments is not None else None
        if not isinstance(function, FUNCTIONS) or self.facts.enclosing_class(function) is not None:
            return False
        params = [*function.args.posonlyargs, *function.args.args]
        position = next((i for i, p in enumerate(params) if p is param), None)
        calls = self.receivers.call_sites(function, None)
        if not calls:
            return False
        for call in calls:
            argument = call_argument(call, position, param.arg)
            if argument is None or not self._bare_make(argument, seen):
                return False
        return True

    def _gym_envs_from_elsewhere(self, receiver: ast.expr, origin: Origin) -> bool:
        """``env``, a parameter of a module function that every call from other modules of
        the run passes a Gym env, a bare one or a wrapper stack (``run_agent(gym.make(...))``
        in one test, ``run_agent(MyEnv())`` in another), and that this module's own calls
        (its ``__main__`` block) pass the bare env (``origin`` RAW), or never make."""
        project = self.receivers.project
        if project is None or not isinstance(receiver, ast.Name):
            return False
        bindings = self.facts.bindings_of(receiver)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.arg):
            return False
        arguments = self.facts.parent(bindings[0])
        function = self.facts.parent(arguments) if arguments is not None else None
        if not isinstance(function, FUNCTIONS) or self.facts.functions.get(function.name) is not function:
            return False
        if origin is None and self.receivers.call_sites(function, None):
            return False  # this module's own calls pass something untraced
        kinds = project.param_kinds(function.name, bindings[0].arg)
        return bool(kinds) and all(kind is EnvKind.GYM_ENV for kind in kinds)

    def _traced_gym_env(self, receiver: ast.expr) -> bool:
        """``holder.env`` where ``holder`` is only ever an object of a class of this module
        that is no env (``player = Agent(model, env)``), or of a plain class of another module
        of the run that every construction hands a Gym env there (``ProjectView.held_kind``),
        and the receiver analysis traced the attribute to a Gym env: bare or wrapped,
        ``get_wrapper_attr`` reads the attribute as forwarding did. The origin walk here
        follows ``self.x`` only inside the class."""
        if not (isinstance(receiver, ast.Attribute) and isinstance(receiver.value, ast.Name)):
            return False
        bindings = self.facts.bindings_of(receiver.value)
        if not bindings:
            return False
        project = self.receivers.project
        for binding in bindings:
            statement = self.facts.parent(binding)
            if not (isinstance(statement, ast.Assign) and statement.targets == [binding] and isinstance(statement.value, ast.Call)):
                return False
            func = statement.value.func
            holder = self.receivers.local_class(func)
            if holder is not None:
                if self.receivers.class_kind(holder) not in (EnvKind.UNKNOWN, EnvKind.NOT_ENV):
                    return False
            elif project is None or not any(project.held_kind(q, receiver.attr) is EnvKind.GYM_ENV for q in self.facts.qualified_names(func)):
                return False  # not a plain class of the run whose every construction passes a Gym env there
        return self.receivers.kind_of(receiver) is EnvKind.GYM_ENV

    def _dominating_origin(self, name: ast.Name) -> Origin:
        """Where the name's values disagree (``env = gym.make(...)`` in one branch, ``env =
        TakeoffAviary(...)`` later): the origin of the one assignment every path to this
        read passes last, if there is one (and it does not rebind the name from itself)."""
        flow = Flow.of(self.facts)
        last = flow.last_binding_of(name)
        statement = self.facts.statement_of(last) if isinstance(last, ast.Name) else None
        if not (isinstance(statement, ast.Assign) and statement.targets == [last]):
            return None
        if not flow.dominates(statement, name, name):
            return None
        if isinstance(statement.value, ast.Attribute) and statement.value.attr == "unwrapped":
            return RAW  # ``env = env.unwrapped``: the base env, whatever the name held before
        if any(isinstance(n, ast.Name) and n.id == name.id for n in ast.walk(statement.value)):
            return None  # ``env = Wrapper(env)``: its origin rests on the earlier values too
        origin = self._origin(statement.value)
        return None if origin == CYCLE else origin

    def _origin_above(self, name: ast.Name) -> Origin:
        """The origin of what ``name`` holds where the other bindings disagree: in ``env =
        env.env`` the assignment just above in the same block (``env = gym.make(id)``),
        elsewhere the one assignment every path to the read passes last."""
        statement = self.facts.statement_of(name)
        if isinstance(statement, ast.Assign) and any(isinstance(t, ast.Name) and t.id == name.id for t in statement.targets):
            above = Flow.of(self.facts).binding_above(name, statement)
            holder = self.facts.statement_of(above) if isinstance(above, ast.Name) else None
            if not (isinstance(holder, ast.Assign) and holder.targets == [above]):
                return None
            if any(isinstance(n, ast.Name) and n.id == name.id for n in ast.walk(holder.value)):
                return None
            origin = self._origin(holder.value)
            return None if origin == CYCLE else origin
        return self._dominating_origin(name)

    def _self_forwarding(self, attr: ast.Attribute) -> None:
        """``self.get_frame()`` in a method of a Gym wrapper class that defines no
        ``get_frame``: legacy ``Wrapper.__getattr__`` found it on the wrapped env (never a
        private name: gym refused those); ``self.get_wrapper_attr("get_frame")`` searches
        this wrapper, then the ones below it and the base env, as forwarding did."""
        name = attr.attr
        parent = self.facts.parent(attr)
        augmented = isinstance(parent, ast.AugAssign) and parent.target is attr  # ``self.x += 1`` reads it too
        if not (isinstance(attr.ctx, ast.Load) or augmented) or name.startswith("_") or name in _WRAPPER_OWN:
            return
        function = self.facts.enclosing_function(attr)
        classdef = self.facts.enclosing_class(attr)
        if function is None or classdef is None or self.facts.parent(function) is not classdef:
            return
        args = function.args.posonlyargs + function.args.args
        static = any(isinstance(d, ast.Name) and d.id in ("staticmethod", "classmethod") for d in function.decorator_list)
        if not args or args[0].arg != "self" or static:
            return
        imported: set[str] = set()
        chain = self._wrapper_chain(classdef, frozenset(), imported)
        if chain is None or name in imported:
            return
        if any(name in self_defined(local) for local in chain):
            self._read_before_own_write(attr, chain)
            return
        if augmented:
            return  # never stored but through ``+=``: reported where it is (_read_before_own_write's case)
        if self.receivers.wraps_pz_parallel(classdef):
            # no Gymnasium wrapper (GM602 at the class): the attribute is the parallel env's, on `self.env`
            # whatever base the class takes instead
            self.report(attr, "GM604", f"attribute forwarding is gone: `{name}` is the wrapped parallel env's, "
                        f"read as `self.env.{name}`", tier=Tier.NOTE)
            self.plan.replace(attr, lambda node: node.with_changes(value=_self_env()))
            return
        self.report(
            attr,
            "GM604",
            f"attribute forwarding is gone in Gymnasium 1.0: this wrapper class defines no `{name}`, which gym found on "
            f"the wrapped env; `self.get_wrapper_attr(\"{name}\")` searches the wrappers and the base env as forwarding did",
            tier=Tier.NOTE,
        )
        self._replace_with_get_wrapper_attr(attr, name)

    def _read_before_own_write(self, attr: ast.Attribute, chain: list[ast.ClassDef]) -> None:
        """``self.ob = f(self.ob)`` in a wrapper method, ``ob`` stored by no ``__init__`` of
        the chain and defined by no method or class-level name: until the statement first
        runs, gym found the read on the wrapped env. ``self.get_wrapper_attr("ob")`` looks
        at the wrapper first, then below it, as forwarding did, whichever call it is.
        ``self.ob += x`` (in place on the env's value, then stored here) is reported. Only
        where every store of ``ob`` reads it too: a store elsewhere may run first."""
        name = attr.attr
        for local in chain:
            for item in local.body:
                if isinstance(item, (*FUNCTIONS, ast.ClassDef)) and item.name == name:
                    return
                if isinstance(item, (ast.Assign, ast.AnnAssign)) and any(
                    isinstance(n, ast.Name) and n.id == name
                    for t in (item.targets if isinstance(item, ast.Assign) else [item.target])
                    for n in ast.walk(t)
                ):
                    return
                if isinstance(item, FUNCTIONS) and item.name == "__init__" and name in self_defined_in(item):
                    return
            # every store of it must read it too (``self.n = self.n + 1``, ``self.n += 1``):
            # one elsewhere (``reset`` setting ``self.n = 0``) may well run first
            for node in ast.walk(local):
                if not (isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store) and node.attr == name):
                    continue
                if not (isinstance(node.value, ast.Name) and node.value.id == "self"):
                    continue
                store = next((a for a in self.facts.ancestors(node) if isinstance(a, ast.stmt)), None)
                if isinstance(store, ast.AugAssign):
                    continue
                if not (isinstance(store, ast.Assign) and _reads_self_attribute(store.value, name)):
                    return
        statement = next((a for a in self.facts.ancestors(attr) if isinstance(a, ast.stmt)), None)
        if isinstance(statement, ast.AugAssign):
            if attr is statement.target:
                self.report(
                    attr,
                    "GM604",
                    f"attribute forwarding is gone in Gymnasium 1.0: until this line first runs, `self.{name}` is not "
                    f"this wrapper's, and gym read (and changed in place) the wrapped env's; read it with "
                    f'`self.get_wrapper_attr("{name}")` and assign the result, or set `self.{name}` in __init__',
                    FixKind.FLAG,
                )
            return
        if not isinstance(statement, ast.Assign) or not any(
            isinstance(t, ast.Attribute) and t.attr == name and isinstance(t.value, ast.Name) and t.value.id == "self"
            for target in statement.targets
            for t in ast.walk(target)
        ):
            return
        self.report(
            attr,
            "GM604",
            f"attribute forwarding is gone in Gymnasium 1.0: until this line first runs, the wrapper has no `{name}` "
            f'of its own and gym read the wrapped env\'s; `self.get_wrapper_attr("{name}")` reads its own once set, '
            "else the env's, as forwarding did",
            tier=Tier.NOTE,
        )
        self._replace_with_get_wrapper_attr(attr, name)

    def _replace_with_get_wrapper_attr(self, attr: ast.Attribute, name: str) -> None:
        """``x.get_wrapper_attr("name")``, quoted so that it can stand inside the f-strings
        around it (before Python 3.12 an f-string cannot hold its own quote)."""
        used = set()
        for ancestor in self.facts.ancestors(attr):
            if isinstance(ancestor, ast.JoinedStr):
                text = self.facts.segment(ancestor).lstrip("rRbBfFuU")
                used.add(text[:1])
        quote = next((q for q in ('"', "'") if q not in used), None)
        if quote is None:
            return  # both quotes taken by nested f-strings: the finding stands alone
        self.plan.replace(attr, _get_wrapper_attr(name, quote))

    def _wrapper_chain(self, classdef: ast.ClassDef, seen: frozenset[int], imported: set[str]) -> list[ast.ClassDef] | None:
        """``classdef`` and the classes of this module it derives from, when every base is
        one of those, a Gym wrapper base class (``Wrapper``, ``ObservationWrapper``...) or a
        wrapper class of another module of the run whose definitions the run knows (added to
        ``imported``: ``class Task(TrialWrapper)``), at least one is, and none takes
        attribute lookup in hand; else None."""
        if id(classdef) in seen or not classdef.bases or classdef.keywords:
            return None
        chain = [classdef]
        gym_base = False
        view = self.receivers.project
        for base in classdef.bases:
            qualified = self.facts.qualified_names(base)
            names = {N.strip_gym_prefix(q) for q in qualified}
            if names & N.GYM_WRAPPER_BASE_CLASSES:
                gym_base = True
                continue
            known = [view.wrapper_defined(q) for q in qualified] if view is not None else []
            if len(known) == 1 and known[0] is not None:
                imported |= known[0]
                gym_base = True
                continue
            local = self.receivers.local_class(base)
            inner = None if local is None else self._wrapper_chain(local, seen | {id(classdef)}, imported)
            if inner is None:
                return None
            chain += inner
            gym_base = True
        if not gym_base or any(takes_lookup_in_hand(local) for local in chain):
            return None
        return chain

    def _is_sub_env(self, receiver: ast.expr) -> bool:
        """``self.envs[i]`` in a subclass of Gym's ``SyncVectorEnv``, which never rebinds
        ``envs``: one of the envs its ``env_fns`` made."""
        if not (
            isinstance(receiver, ast.Subscript)
            and isinstance(receiver.value, ast.Attribute)
            and receiver.value.attr == "envs"
            and isinstance(receiver.value.value, ast.Name)
            and receiver.value.value.id == "self"
        ):
            return False
        classdef = self.facts.enclosing_class(receiver)
        if classdef is None or "envs" in self.receivers.self_stores(classdef):
            return False
        return any(
            N.strip_gym_prefix(q) in _SYNC_VECTOR_ENVS for base in classdef.bases for q in self.facts.qualified_names(base)
        )

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
        origin = self._origin(receiver)
        if origin is None and isinstance(receiver, ast.Name):
            origin = self._origin_above(receiver)
        if depth == 1 and self._is_make_call(receiver):
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

    def _is_make_call(self, expr: ast.AST) -> bool:
        return isinstance(expr, ast.Call) and any(N.strip_gym_prefix(q) in ("make", "envs.make", "envs.registration.make") for q in self.facts.qualified_names(expr.func))

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
        return not self._bare_make_result(call.args[0])

    def _bare_make_result(self, expr: ast.AST) -> bool:
        if self._is_make_call(expr):
            return True
        if not isinstance(expr, ast.Name):
            return False
        values = []
        for binding in self.facts.bindings_of(expr):
            statement = self.facts.parent(binding)
            if not (isinstance(statement, ast.Assign) and binding in statement.targets):
                return False
            values.append(statement.value)
        return bool(values) and all(self._is_make_call(value) for value in values)

    # -- what the wrappers define ----------------------------------------------------------------

    def _local_wrapper_attributes(self) -> set[str]:
        """Attributes and methods defined by wrapper classes of this module (they shadow the base env's)."""
        if self._local_attrs is None:
            attrs: set[str] = set()
            for classdef in self.facts.classes.values():
                if self.receivers.is_gym_wrapper_class(classdef):
                    attrs |= self._defined_attributes(classdef)
            self._local_attrs = attrs
        return self._local_attrs

    def _defined_attributes(self, classdef: ast.ClassDef) -> set[str]:
        names = self._class_attrs.get(classdef)
        if names is None:
            names = self._class_attrs[classdef] = _defined_attributes(classdef)
        return names

    def _outer_wrapper(self, expr: ast.expr) -> str | None:
        """The wrapper class that is the outermost layer of ``expr`` where it is read.

        For a name, the binding is the nearest assignment above the read in the same scope
        (``env = RecordEpisodeStatistics(env)`` then ``env.return_queue``): straight-line
        script code, which is where such reads live.
        """
        value: ast.expr | None = expr
        if isinstance(expr, ast.Name):
            value = self._nearest_assignment(expr)
            annotation = self._annotated_wrapper(expr) if value is None else None
            if annotation is not None:  # ``env: gym.wrappers.TimeLimit``
                named = {rest for q in self.facts.qualified_names(annotation) if (rest := wrapper_rest(q)) is not None}
                return current_name(named.pop()) if len(named) == 1 else None
        if not isinstance(value, ast.Call):
            return None
        names = {rest for q in self.facts.qualified_names(value.func) if (rest := wrapper_rest(q)) is not None}
        if len(names) == 1:
            # Its 1.x name: ``FrameStack`` is becoming FrameStackObservation in the same run.
            return current_name(names.pop())
        local = self.receivers.local_class(value.func)
        if local is not None and self.receivers.is_gym_wrapper_class(local):
            return local.name
        return None

    def _annotated_wrapper(self, name: ast.Name) -> ast.expr | None:
        """The annotation of the parameter ``name`` is, when it is its only binding."""
        bindings = self.facts.bindings_of(name)
        if len(bindings) == 1 and isinstance(bindings[0], ast.arg) and bindings[0].annotation is not None:
            return bindings[0].annotation
        return None

    def _is_run_wrapper_class(self, func: ast.expr) -> bool:
        """A Gym wrapper class another module of the run defines."""
        view = self.receivers.project
        return view is not None and any(view.is_wrapper_class(q) for q in self.facts.qualified_names(func))

    def _outer_is_wrapper(self, expr: ast.expr) -> bool:
        """``expr`` is, where it is read, a Gym wrapper made by a constructor call: Gymnasium's
        wrappers, this module's wrapper classes, or another module's of the run."""
        if self._outer_wrapper(expr) is not None:
            return True
        value = self._nearest_assignment(expr) if isinstance(expr, ast.Name) else expr
        return isinstance(value, ast.Call) and self._is_run_wrapper_class(value.func)

    def _outer_attributes(self, expr: ast.expr) -> set[str]:
        """Attributes the outermost wrapper of ``expr`` defines itself (gymnasium's or this module's)."""
        owner = self._outer_wrapper(expr)
        if owner is None:
            return set()
        if owner in OWN_ATTRIBUTES:
            return OWN_ATTRIBUTES[owner]
        local = self.facts.classes.get(owner)
        return self._defined_attributes(local) if local is not None else set()

    def _nearest_assignment(self, name: ast.Name) -> ast.expr | None:
        scope, bindings = self.facts.resolve(name.id, self.facts.scope_of(name))
        if scope is None:
            return None
        key = (id(scope), name.id)
        if key not in self._assign_lines:
            found: list[tuple[int, ast.expr]] = []
            for binding in bindings:
                parent = self.facts.parent(binding)
                if not (isinstance(parent, ast.Assign) and binding in parent.targets):
                    self._assign_lines[key] = None
                    break
                found.append((parent.lineno, parent.value))
            else:
                found.sort(key=lambda item: item[0])  # stable: the first of a line stays first
                self._assign_lines[key] = ([line for line, _ in found], [value for _, value in found])
        table = self._assign_lines[key]
        if not table:
            return None
        lines, values = table
        before = bisect.bisect_left(lines, name.lineno)  # assignments on lines above the read
        if before == 0:
            return None
        return values[bisect.bisect_left(lines, lines[before - 1])]  # the first one on the nearest line

    # -- origins -------------------------------------------------------------------------------

    def _origin(self, expr: ast.AST | None) -> Origin:
        """MADE / WRAPPED / INNER / RAW, CYCLE, or None when it cannot be told."""
        if expr is None or self._depth > MAX_DEPTH:
            return None
        self._depth += 1
        try:
            if isinstance(expr, ast.Call):
                return self._call_origin(expr)
            if isinstance(expr, ast.Attribute):
                return self._attribute_origin(expr)
            if isinstance(expr, ast.Name):
                origin = self._name_origin(expr)
                if origin in (None, CYCLE) and self.receivers.narrowing.is_env(expr):
                    return WRAPPED  # ``isinstance(env, gym.Env)`` checked it: bare or wrapped
                return origin
            if isinstance(expr, ast.Subscript):
                return self._items_origin(expr.value)
            return None
        finally:
            self._depth -= 1

    def _items_origin(self, container: ast.expr) -> Origin:
        """``self.envs[i]`` with ``self.envs = [gym.make(...) for _ in ...]`` stored in the class:
        what its items are."""
        values: list[ast.expr] = [container]
        if isinstance(container, ast.Attribute) and isinstance(container.value, ast.Name) and container.value.id == "self":
            classdef = self.facts.enclosing_class(container)
            values = self.receivers.self_stores(classdef).get(container.attr, []) if classdef is not None else []
        origins: list[Origin] = []
        for value in values:
            if isinstance(value, (ast.ListComp, ast.GeneratorExp)):
                origins.append(self._origin(value.elt))
            elif isinstance(value, (ast.List, ast.Tuple)) and value.elts:
                origins.extend(self._origin(item) for item in value.elts)
            else:
                return None
        return join_origins(origins) if origins else None

    def _attribute_origin(self, expr: ast.Attribute) -> Origin:
        if expr.attr == "unwrapped":
            return RAW
        if isinstance(expr.value, ast.Name) and expr.value.id == "self":
            classdef = self.facts.enclosing_class(expr)
            if classdef is None:
                return None
            if expr.attr == "env" and self.receivers.is_gym_wrapper_class(classdef):
                return INNER
            return join_origins([self._origin(v) for v in self.receivers.self_stores(classdef).get(expr.attr, [])])
        return None

    def _call_origin(self, call: ast.Call) -> Origin:
        if len(call.args) == 1 and self.facts.qualified_names(call.func) & {"copy.deepcopy", "copy.copy"}:
            return self._origin(call.args[0])  # a copy of the env, as made or wrapped as it is
        for q in self.facts.qualified_names(call.func):
            rest = N.strip_gym_prefix(q)
            if rest is None:
                continue
            if rest in N.GYM_ENV_FACTORIES:
                return MADE
            if rest.startswith("wrappers.") and not rest.startswith("wrappers.vector."):
                return self._wrapped(call)
            if rest.startswith("envs."):
                return RAW
        if self._is_run_wrapper_class(call.func):
            return self._wrapped(call)
        local = self.receivers.local_class(call.func)
        if local is not None:
            if self.receivers.is_gym_wrapper_class(local):
                return self._wrapped(call)
            if self.receivers.class_kind(local) is EnvKind.GYM_ENV:
                return RAW
        function = self.receivers.local_function(call.func)
        if function is not None:
            key = (id(function), "<returns>")
            if key in self._in_progress:
                return CYCLE
            if key not in self._name_origins:
                self._in_progress.add(key)
                try:
                    values = [r.value for r in own_returns(function) if r.value is not None]
                    origin = join_origins([self._origin(v) for v in values])
                finally:
                    self._in_progress.discard(key)
                if origin == CYCLE:
                    return CYCLE
                self._name_origins[key] = origin
            return self._name_origins[key]
        view = self.receivers.project
        if view is not None:
            qualified = self.facts.qualified_names(call.func)
            if any(view.returns_made(q) for q in qualified):
                return MADE  # a def of another module of the run that returns make() results
            if any(view.makes_bare_env(q) for q in qualified):
                return RAW  # an env class of another module of the run: the env itself
        return None

    def _wrapped(self, call: ast.Call) -> Origin:
        """A wrapper around its first argument: as made as what it wraps, or merely wrapped."""
        first = call.args[0] if call.args else (call.keywords[0].value if call.keywords else None)
        inner = self._origin(first) if first is not None else None
        if inner == CYCLE:
            return CYCLE
        return MADE if inner == MADE else WRAPPED

    def _name_origin(self, name: ast.Name) -> Origin:
        scope, bindings = self.facts.resolve(name.id, self.facts.scope_of(name))
        if scope is None:
            return None
        key = (id(scope), name.id)
        if key in self._name_origins:
            return self._name_origins[key]
        if key in self._in_progress:
            return CYCLE  # ``env = Wrapper(env)``: the other bindings decide
        self._in_progress.add(key)
        try:
            origin = self._bindings_origin(bindings)
        finally:
            self._in_progress.discard(key)
        if origin != CYCLE:  # a cycle is an answer only from inside it
            self._name_origins[key] = origin
        return origin

    def _bindings_origin(self, bindings: list[ast.AST]) -> Origin:
        origins: list[Origin] = []
        for binding in bindings:
            if isinstance(binding, ast.arg):
                origins.append(self._param_origin(binding))
                continue
            parent = self.facts.parent(binding)
            if isinstance(binding, ast.Name) and isinstance(parent, ast.Assign) and binding in parent.targets:
                origins.append(self._origin(parent.value))
                continue
            if isinstance(binding, ast.Name) and isinstance(parent, ast.AnnAssign) and parent.value is not None:
                origins.append(self._origin(parent.value))
                continue
            return None
        return join_origins(origins)

    def _param_origin(self, param: ast.arg) -> Origin:
        if param in self._param_origins:
            return self._param_origins[param]
        arguments = self.facts.parent(param)
        function = self.facts.parent(arguments) if arguments is not None else None  # arg -> arguments -> def
        if not isinstance(function, FUNCTIONS):
            return None
        classdef = self.facts.enclosing_class(function)
        if classdef is not None:
            if function.name == "__init__" and param.arg == "env" and self.receivers.is_gym_wrapper_class(classdef):
                return INNER
            return None
        if param.annotation is not None and any(
            wrapper_rest(q) == "TimeLimit" for q in self.facts.qualified_names(param.annotation)
        ):
            return MADE  # ``env: gym.wrappers.TimeLimit``: what make returns, its outermost layer
        # A module function: the env is whatever its callers in this module pass.
        params = [*function.args.posonlyargs, *function.args.args]
        position = next((i for i, p in enumerate(params) if p is param), None)
        calls = self.receivers.call_sites(function, None)
        if not calls:
            fixtures = param_fixtures(self.facts, function, param.arg)
            if not fixtures:
                return None
            # A test's parameter named after a pytest fixture of the module (or parametrized
            # over fixtures with ``fixture_ref``) gets what the fixtures yield or return.
            self._param_origins[param] = None
            result = join_origins([self._origin(value) for fixture in fixtures for value in fixture_values(self.facts, fixture)])
            self._param_origins[param] = result
            return result
        self._param_origins[param] = None  # a recursive call adds no evidence
        origins: list[Origin] = []
        for call in calls:
            argument = call_argument(call, position, param.arg)
            origin = self._origin(argument) if argument is not None else None
            origins.append(None if origin == CYCLE else origin)
        result = join_origins(origins)
        self._param_origins[param] = result
        return result


# gym.make's layers, legacy (TimeLimit, OrderEnforcing, PassiveEnvChecker in gym 0.24-0.26) and
# Gymnasium 1.4 (the same three).
_MAKE_LAYERS = 3
# Public attributes those layers define themselves (``vars()`` of each layer on gymnasium 1.4,
# and gym 0.26's): a read of one through ``.env`` may mean the wrapper's.
_MAKE_LAYER_ATTRIBUTES = frozenset(
    {"has_reset", "checked_reset", "checked_step", "checked_render", "checked_data_reuse", "close_called"}
)


def _unwrapped_below(depth: int):
    """``env.env.env.state`` (``depth`` ``.env``) -> ``env.unwrapped.state``."""

    def build(node: cst.Attribute) -> cst.BaseExpression:
        value: cst.BaseExpression = node.value
        for _ in range(depth):
            assert isinstance(value, cst.Attribute)
            value = value.value
        return node.with_changes(value=cst.Attribute(value=value, attr=cst.Name("unwrapped")))

    return build


def _set_wrapper_attr(name: str):
    """``env.foo = value`` -> ``env.set_wrapper_attr("foo", value)``."""

    def build(node: cst.Assign) -> cst.BaseSmallStatement:
        target = node.targets[0].target
        assert isinstance(target, cst.Attribute)
        call = cst.Call(
            func=cst.Attribute(value=target.value, attr=cst.Name("set_wrapper_attr")),
            args=[
                cst.Arg(value=cst.SimpleString(f'"{name}"'), comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))),
                cst.Arg(value=node.value),
            ],
        )
        return cst.Expr(call, semicolon=node.semicolon)

    return build


def _through(*attrs: str):
    """``env.foo`` -> ``env.<attrs...>`` (``env.unwrapped.foo``, ``env.spec.max_episode_steps``)."""

    def build(node: cst.Attribute) -> cst.BaseExpression:
        value: cst.BaseExpression = node.value
        for name in attrs[:-1]:
            value = cst.Attribute(value=value, attr=cst.Name(name))
        return node.with_changes(value=value, attr=cst.Name(attrs[-1]))

    return build


def _get_wrapper_attr(name: str, quote: str = '"'):
    def build(node: cst.Attribute) -> cst.BaseExpression:
        return cst.Call(
            func=cst.Attribute(value=node.value, attr=cst.Name("get_wrapper_attr")),
            args=[cst.Arg(value=cst.SimpleString(f"{quote}{name}{quote}"))],
            lpar=node.lpar,
            rpar=node.rpar,
        )

    return build


# Methods of Gymnasium's wrapper base classes besides SAFE_ATTRIBUTES (a subclass overrides them).
_WRAPPER_OWN = SAFE_ATTRIBUTES | {"observation", "action", "reward", "reverse_action", "env_is_wrapped"}


def _defined_attributes(classdef: ast.ClassDef) -> set[str]:
    """Methods (at any depth) and ``self.x = ...`` targets of a class."""
    names: set[str] = set()
    for node in ast.walk(classdef):
        if isinstance(node, FUNCTIONS):
            names.add(node.name)
        elif isinstance(node, ast.Assign):
            for target in node.targets:
                if isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self":
                    names.add(target.attr)
    return names


def _reads_self_attribute(node: ast.AST, name: str) -> bool:
    return any(
        isinstance(n, ast.Attribute) and n.attr == name and isinstance(n.ctx, ast.Load) and isinstance(n.value, ast.Name) and n.value.id == "self"
        for n in ast.walk(node)
    )


def _self_env() -> cst.Attribute:
    return cst.Attribute(value=cst.Name("self"), attr=cst.Name("env"))
