"""What legacy code assumed about the layers ``gym.make`` stacks (GM604, GM606).

gym 0.21's make returned ``TimeLimit(env)``; gym 0.24-0.26 and Gymnasium 1.4 stack
TimeLimit, OrderEnforcing and PassiveEnvChecker. Code that reached through those layers
by ``.env`` meant an env they no longer give: ``gym.make(id).env`` (the env without its
time limit) becomes ``.unwrapped``, ``env.env.state`` on a bare make result (the base
env's state, which forwarding reached) becomes ``env.unwrapped.state``, other ``.env``
chains are reported, except under a read of what no layer has (an attribute Gymnasium's
built-in env lost, ``builtin_attributes.py``). ``isinstance(env, TimeLimit)`` still answers
as before on a make result. Part of ``forwarding.WrapperForwarding``.
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import dotted_name
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.wrapper_usage.atari_limits import (
    is_make_call,
    isinstance_time_limit_on_atari,
)
from gymmigrate.rules.wrapper_usage.bare_make import bare_make, bare_make_result
from gymmigrate.rules.wrapper_usage.forwarding_edits import (
    replace_with_get_wrapper_attr,
    unwrapped_below,
)
from gymmigrate.rules.wrapper_usage.origins import INNER, MADE, WRAPPED, Origin
from gymmigrate.rules.wrapper_usage.tables import (
    BASE_ENV_ATTRIBUTES,
    OWN_ATTRIBUTES,
    wrapper_rest,
)

if TYPE_CHECKING:
    from gymmigrate.rules.wrapper_usage.self_forwarding import ForwardingFamily

# gym.make's layers, legacy (TimeLimit, OrderEnforcing, PassiveEnvChecker in gym 0.24-0.26) and
# Gymnasium 1.4 (the same three).
_LAYERS = 3
# Public attributes those layers define themselves (``vars()`` of each layer on gymnasium 1.4,
# and gym 0.26's): a read of one through ``.env`` may mean the wrapper's.
_LAYER_ATTRIBUTES = frozenset(
    {"has_reset", "checked_reset", "checked_step", "checked_render", "checked_data_reuse", "close_called"}
)
# What any Gymnasium wrapper defines itself: read past one by ``.env``, it may have meant that one's.
_ANY_WRAPPER_ATTRIBUTES = frozenset().union(*OWN_ATTRIBUTES.values())


class MakeLayers:
    """The ``.env`` chains and ``TimeLimit`` tests of one module, for one forwarding family."""

    def __init__(self, family: ForwardingFamily) -> None:
        self.family = family
        self.facts = family.facts
        self._read_through: set[int] = set()  # ``env.env.state`` rewritten to ``env.unwrapped.state``
        self._gone: set[int] = set()  # reads of what Gymnasium's built-in env no longer has

    def isinstance_time_limit(self, call: ast.Call) -> None:
        """``isinstance(env, TimeLimit)``."""
        if self._tests_time_limit(call) and isinstance_time_limit_on_atari(self.family, call):
            return  # an Atari make has no TimeLimit now
        if self._is_isinstance_timelimit(call):
            # Gymnasium's make still puts TimeLimit outermost, as gym's did: the test
            # answers as before (and failed as before under wrappers of the code's own).
            self.family.report(
                call,
                "GM606",
                "gym.make still returns TimeLimit outermost (around OrderEnforcing and PassiveEnvChecker), so this "
                "test answers as it did; `env.spec.max_episode_steps` also works under wrappers of your own",
                tier=Tier.NOTE,
            )

    def read_through(self, attr: ast.Attribute) -> bool:
        """``env.env.state`` (read or written) with ``env`` a bare ``gym.make`` result: gym's
        make stacked at most TimeLimit, OrderEnforcing and PassiveEnvChecker, none with a
        public ``state``, so whichever layer ``.env`` named, the read reached the base env
        (gym <= 0.20: ``.env`` was the env itself; later: forwarded). Gymnasium's make stacks
        the same layers and forwards nothing: ``env.unwrapped.state`` is the base env's.
        Checked on gymnasium 1.4: CartPole-v1's ``.env.state`` raises, ``.env.state = s``
        sets it on OrderEnforcing, ``.unwrapped.state = s`` is the state the next step uses."""
        name = attr.attr
        if name.startswith("_") or name in _LAYER_ATTRIBUTES:
            return False  # gym never forwarded private names; the layers' own stay theirs
        chain: ast.expr = attr.value
        depth = 0
        while True:
            if depth == _LAYERS or not (isinstance(chain, ast.Attribute) and chain.attr == "env"):
                return False  # deeper than make's layers is past the base env
            chain, depth = chain.value, depth + 1
            if bare_make(self.facts, self.family.receivers, chain, frozenset()):
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
        self.family.report(attr, "GM604", message, kind=FixKind.AUTO, tier=Tier.NOTE)
        self.family.plan.replace(attr, unwrapped_below(depth))
        self._read_through.add(id(attr))
        return True

    def read_through_wrapper(self, attr: ast.Attribute) -> bool:
        """``env.env.robot`` (a read) with ``env`` a Gym env the run proves wrapped: a
        Gymnasium wrapper or one of the run's around a make result, a make result that is
        not a bare one on every path, a sub-env of a vector env. Legacy ``.env`` was a gym
        wrapper or the base env, and either forwarded ``robot`` from the layers below it;
        Gymnasium's layers forward nothing (``OrderEnforcing`` now sits under make's
        TimeLimit). No wrapper that could be above the link has ``robot`` (not one of the
        run's, not one of Gymnasium's), so ``env.get_wrapper_attr("robot")`` finds what the
        legacy read found; base-env state is read through ``.unwrapped``. Writes, private
        names and the wrappers' own attributes stay with GM606's question: which layer the
        chain meant."""
        name = attr.attr
        if not isinstance(attr.ctx, ast.Load) or name.startswith("_") or name in _LAYER_ATTRIBUTES | _ANY_WRAPPER_ATTRIBUTES:
            return False
        chain: ast.expr = attr.value
        depth = 0
        while isinstance(chain, ast.Attribute) and chain.attr == "env":
            chain, depth = chain.value, depth + 1
        if depth == 0 or (isinstance(chain, ast.Name) and chain.id in ("self", "cls")):
            return False  # a wrapper class's own ``self.env`` is self-forwarding's business
        origins = self.family.origins
        origin: Origin
        if origins.is_sub_env(chain):
            origin = INNER
        elif self.family.receivers.kind_of(chain) is EnvKind.GYM_ENV:
            origin = origins.at_read(chain)
            if origin is None and (origins.outer_is_wrapper(chain) or origins.traced_gym_env(chain)):
                origin = WRAPPED  # a wrapper where it is read, whatever else the name held
        else:
            return False  # unknown, or the project's own object holding something as ``.env``
        if origin not in (MADE, WRAPPED, INNER) or (origin == MADE and depth > _LAYERS):
            return False  # a bare env's ``.env`` is its own attribute; past make's layers is past the env
        receiver = dotted_name(chain) or self.facts.segment(chain)
        text = dotted_name(attr) or f"{receiver}{'.env' * depth}.{name}"
        if name in origins.local_wrapper_attributes():
            return False  # a wrapper of the run has it: the chain may have meant that layer
        if name in BASE_ENV_ATTRIBUTES:
            self.family.report(
                attr,
                "GM604",
                f"`{text}` -> `{receiver}.unwrapped.{name}`: `{name}` is the base env's, which legacy wrappers forwarded "
                "from below; Gymnasium's wrappers forward nothing",
                kind=FixKind.AUTO,
                tier=Tier.NOTE,
            )
            self.family.plan.replace(attr, unwrapped_below(depth))
        else:
            self.family.report(
                attr,
                "GM604",
                f"`{text}` -> `{receiver}.get_wrapper_attr(\"{name}\")`: legacy wrappers forwarded `{name}` from the "
                "layers below; Gymnasium's forward nothing, and no wrapper above the link defines it",
                kind=FixKind.AUTO,
                tier=Tier.NOTE,
            )
            replace_with_get_wrapper_attr(self.facts, self.family.plan, attr, name, below=depth)
        self._read_through.add(id(attr))
        return True

    def no_layer_has(self, attr: ast.Attribute) -> None:
        """GM604 reported ``attr`` as an attribute Gymnasium's built-in env lost
        (``builtin_attributes.py``): the ``.env`` chain it is read through asks nothing."""
        self._gone.add(id(attr))

    def env_chain(self, attr: ast.Attribute) -> None:
        parent = self.facts.parent(attr)
        if isinstance(parent, ast.Attribute) and parent.value is attr and parent.attr == "env":
            return  # report the outermost ``.env`` of a chain once
        if isinstance(parent, ast.Attribute) and parent.value is attr and id(parent) in self._read_through:
            return  # GM604 rewrote the read through it to ``.unwrapped``: the chain is gone
        if isinstance(parent, ast.Attribute) and parent.value is attr and id(parent) in self._gone:
            return  # no layer has what is read through it (GM604's item): which one it names does not matter
        receiver = attr.value
        depth = 1
        # down the chain to the env it is read on: the first link that holds a bare make result
        # on every path (a name or ``self.x`` bound only to one, or ``holder.env`` of a class of
        # the run that keeps one there: ``holder.env.env`` is one layer below that make)
        while not (bare := bare_make(self.facts, self.family.receivers, receiver, frozenset())):
            if not (isinstance(receiver, ast.Attribute) and receiver.attr == "env"):
                break
            receiver = receiver.value
            depth += 1
        if isinstance(receiver, ast.Name) and receiver.id == "self":
            return
        bare = bare and not is_make_call(self.facts, receiver)
        if not bare and self.family.receivers.kind_of(receiver) is not EnvKind.GYM_ENV:
            return
        origin = MADE if bare else self.family.origins.at_read(receiver)
        read = parent.attr if isinstance(parent, ast.Attribute) and parent.value is attr else None
        layer_read = read is not None and (read.startswith("_") or read in _LAYER_ATTRIBUTES)
        if depth == 1 and bare and not layer_read:
            # The env under make's TimeLimit: gym's make put TimeLimit outermost, as
            # Gymnasium's still does, so ``.env`` dropped the time limit whichever layers
            # were below it, and forwarded the base env's attributes, which Gymnasium's inner
            # layer no longer does. ``.unwrapped`` is that env. (A read of a layer's own or
            # private name through it, ``env.env.checked_step``, meant a layer: GM604 asks.)
            self.family.plan.replace(attr, lambda node: node.with_changes(attr=cst.Name("unwrapped")))
            self.family.report(
                attr,
                "GM606",
                f"`{dotted_name(attr) or self.facts.segment(attr)}` -> `.unwrapped`: `{dotted_name(receiver) or 'the receiver'}` "
                "holds a gym.make result on every path, whose `.env` was the env under its TimeLimit, forwarding that env's "
                "attributes; Gymnasium's make stacks wrappers there that forward nothing",
                FixKind.AUTO,
            )
            return
        if depth == 1 and is_make_call(self.facts, receiver):
            # gym 0.21's make returned TimeLimit(env): ``gym.make(id).env`` was the env
            # itself, without its time limit. Gymnasium's make adds layers under the
            # TimeLimit; ``.unwrapped`` is that env again.
            self.family.plan.replace(attr, lambda node: node.with_changes(attr=cst.Name("unwrapped")))
            self.family.report(
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
                self.family.report(attr, "GM606", f"{message} (decided with GM604's item on `.{outer.attr}` here)", tier=Tier.NOTE)
                return
            self.family.report(
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
            for finding, node in zip(self.family.plan.findings, self.family.plan.finding_nodes)
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
