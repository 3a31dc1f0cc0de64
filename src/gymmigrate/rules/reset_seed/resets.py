"""``reset()`` calls: the result is ``(obs, info)`` and the legacy keywords go (GM201, GM202, GM207, GM704).

Gym 0.26 (and so Gymnasium) returns ``(obs, info)`` from ``reset()``
(``Env.reset -> tuple[ObsType, dict]``), for single and vector envs alike, and the
0.22-0.25 ``return_info=`` keyword is gone. So:

* GM201/GM704 ``obs = env.reset()`` becomes ``obs, info = env.reset()`` (``infos`` for a
  vector env), with an ``info`` name that hides no other value; a reset used as a value
  (``torch.tensor(env.reset())``) gets ``[0]``; uses that cannot be rewritten are reported.
* GM202 ``return_info=`` is dropped and the unpack fixed; a value only known at run time,
  or a pair kept whole, is reported instead (the result would read like a legacy reset).
* GM207 other keywords (and positional arguments) belong in ``options={...}``.
* GM206/GM204 a ``seed=`` that is a numpy scalar is wrapped in ``int()``; one that is the
  same on every iteration of a loop is reported.

Already migrated code (a two-name unpack, ``env.reset()[0]``, a pass-through
``return self.env.reset(**kwargs)``) is left alone.
"""

from __future__ import annotations

import ast
from enum import Enum

from gymmigrate.facts.batched_steps import steps_batched
from gymmigrate.facts.class_shapes import per_agent_receivers
from gymmigrate.facts.decisions import Action, Decision, receiver_text
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.legacy_wrapper_hooks import in_dead_hook
from gymmigrate.facts.module import is_super_call
from gymmigrate.facts.reset_flow import scope_of_expression
from gymmigrate.facts.version_checks import dead_version_branch
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.reset_seed.call_edits import unpack_builder
from gymmigrate.rules.reset_seed.common import ResetSeedBase

RESET_KEYWORDS = frozenset({"seed", "options", "return_info"})


class Use(Enum):
    """How the value of a ``reset()`` call is used."""

    STATEMENT = "statement"  # env.reset()
    UNPACKED = "unpacked"  # obs, info = env.reset(): already migrated
    ASSIGN = "assign"  # obs = env.reset()
    OBS_TUPLE = "obs-tuple"  # player, dealer, ace = env.reset() (a Tuple observation)
    IN_TUPLE = "in-tuple"  # obs, done = env.reset(), False
    INDEXED = "indexed"  # env.reset()[0]: already migrated, unless legacy code indexed the obs
    PASSTHROUGH = "passthrough"  # return self.env.reset(**kwargs) in a Gym env's reset()
    FOREIGN_RESET = "foreign-reset"  # return env.reset() in reset() of a class that is no Gym env
    EXPRESSION = "expression"  # torch.tensor(env.reset()), return env.reset() in a helper
    UNSUPPORTED = "unsupported"  # await env.reset(), starred unpacks


# Uses that need no change on Gymnasium whatever the legacy call returned.
_SETTLED = (Use.STATEMENT, Use.UNPACKED, Use.INDEXED, Use.PASSTHROUGH)


class Shape(Enum):
    """What a legacy ``reset()`` call returned."""

    OBS = "obs"  # gym <= 0.25 without return_info=True
    PAIR = "pair"  # return_info=True
    EITHER = "either"  # reset(seed=...) or reset(options=...): obs in 0.22-0.25, the pair from 0.26
    AT_RUN_TIME = "at-run-time"  # return_info=<expression>


class ResetCalls(ResetSeedBase):
    def _decide_reset(self, call: ast.Call) -> None:
        func = call.func
        if not isinstance(func, ast.Attribute):  # ``x.method(...)`` calls only
            return
        receiver = func.value
        if dead_version_branch(call, self.facts) is not None or self.receivers.in_legacy_by_version_method(call):
            return  # the legacy branch of a gym version check: it never runs on Gymnasium (GM108)
        if in_dead_hook(self.receivers, call):
            return  # a gym < 0.9 wrapper hook left dead (GM616): its body stays whole
        if self.receivers.legacy_step_class(receiver) is not None:
            # A class of the run whose step keeps its own four fields (a batch, a wrapper around
            # one) keeps its reset with it (GM504/GM602 report the class): the calls on its
            # instances stay as they are.
            return
        decision, vector = self._decide(receiver, legacy_shape=self._stepped_the_legacy_way(receiver))
        if decision.action is Action.LEAVE:
            return
        if decision.action is Action.REWRITE_FOR_REVIEW and isinstance(receiver, ast.Name) and steps_batched(self.facts, receiver):
            # The step of the same name reads its done flags one per env, so GM301 leaves it
            # (a vector env maybe): its reset is the same decision, left and reported with it.
            decision = Decision(
                Action.REPORT,
                f"could not trace where `{receiver.id}` comes from, and it may be a vector env (the done flags of its "
                "step look batched); not rewritten",
            )
        classdef = self.facts.enclosing_class(call)
        if decision.action is not Action.REWRITE and isinstance(receiver, ast.Name) and classdef is not None:
            if receiver.id in per_agent_receivers(classdef):
                # The class concatenates this env's done into a list (``done_n += done``): a
                # per-agent env whose four-field step the run keeps (GM301), so its reset too.
                return
        code = "GM704" if vector else "GM201"
        name = receiver_text(receiver)
        use, assign, index = self._use_of(call)
        keywords = {kw.arg: kw for kw in call.keywords if kw.arg is not None}
        if decision.action is Action.REPORT:
            custom = set(keywords) - {"seed", "options"} - self.contract_keywords
            if use not in _SETTLED or custom:
                self.report(
                    call,
                    code,
                    f"{decision.reason}: if it is a Gym env, reset() returns (obs, info) now and the result must be unpacked",
                    FixKind.FLAG,
                    question=self.receiver_question(receiver, decision),
                )
            return
        self._check_custom_arguments(call, name, keywords)
        shape = self._legacy_shape(call, decision, name, keywords, use)
        seed = keywords.get("seed")
        if seed is not None:
            self._check_seed_in_loop(call, seed.value, f"`{name}.reset(seed=...)`")
            if self.numpy_seeds.is_numpy(seed.value):
                self._edit(call).int_seed = True
                # int() of a numpy integer is the same seed legacy gym took: nothing to decide, a note
                self.report(seed.value, "GM206", "numpy seed wrapped in int(): Gymnasium accepts only Python ints as seeds", tier=Tier.NOTE)
        if shape is Shape.EITHER:
            if self.context.profile.imports_gym and use in (Use.ASSIGN, Use.OBS_TUPLE, Use.IN_TUPLE, Use.EXPRESSION):
                # Still importing legacy gym: the code was written for a reset that returned
                # the observation (0.22-0.25); on Gymnasium a single name would hold the pair.
                legacy = Decision(
                    Action.REWRITE_FOR_REVIEW,
                    "gym 0.22-0.25 returned only the observation from reset(seed=/options=); "
                    "if this code was written for gym 0.26 and kept the pair on purpose, undo this",
                )
                self._reshape(call, use, assign, index, code, legacy, vector)
            elif use not in _SETTLED:
                self.report(
                    call,
                    code,
                    f"`{name}.reset(seed=/options=)` is used as one value: gym 0.22-0.25 returned only the "
                    "observation here, Gymnasium returns (obs, info); unpack it unless the tuple is wanted",
                    FixKind.FLAG,
                )
        elif use is Use.INDEXED:
            if self.context.profile.imports_gym and shape is Shape.OBS:
                self.report(
                    call,
                    code,
                    f"`{name}.reset()[i]` is read as the (obs, info) pair now; if this legacy code meant a "
                    f"component of the observation, write `{name}.reset()[0][i]`",
                    FixKind.FLAG,
                )
        elif shape is Shape.OBS:
            self._reshape(call, use, assign, index, code, decision, vector)

    def _check_custom_arguments(self, call: ast.Call, name: str, keywords: dict[str, ast.keyword]) -> None:
        """GM207: reset() takes only seed= and options= (and, until 0.25, return_info=)."""
        custom = [key for key in keywords if key not in RESET_KEYWORDS and key not in self.contract_keywords]
        arguments = call.args[1:] if self._names_base(call) else call.args  # the instance aside
        positional = any(not isinstance(arg, ast.Starred) for arg in arguments)
        if custom or positional:
            shown = ", ".join(f"`{key}=`" for key in custom) or "positional arguments"
            self.report(
                call,
                "GM207",
                f"`{name}.reset()` takes only seed= and options= now: pass {shown} as options={{...}} "
                "and read them from `options` in the env's reset()",
            )

    def _legacy_shape(
        self, call: ast.Call, decision: Decision, name: str, keywords: dict[str, ast.keyword], use: Use
    ) -> Shape:
        """What the legacy call returned; drops ``return_info=`` (GM202) on the way."""
        return_info = keywords.get("return_info")
        if return_info is None:
            # reset(seed=/options=) returned obs in gym 0.22-0.25 and the pair from 0.26 on.
            return Shape.EITHER if "seed" in keywords or "options" in keywords else Shape.OBS
        flag = return_info.value.value if isinstance(return_info.value, ast.Constant) else None
        if use in (Use.STATEMENT, Use.PASSTHROUGH) and self._hands_on_own_flag(call, return_info.value):
            # ``self.env.reset(seed=seed, return_info=return_info)`` in an env's ``reset``
            # whose own ``return_info`` the class rules remove (GM502, PZ105): they drop the
            # keyword with the parameter, and the pair this reset returns is what is kept.
            return Shape.PAIR
        if not isinstance(flag, bool):
            self.report(
                call,
                "GM202",
                "return_info=<expression> chose the result's shape at run time; reset() always returns "
                "(obs, info) now: drop the keyword and keep the branch that unpacks two values",
                FixKind.FLAG,
            )
            return Shape.AT_RUN_TIME
        kept_whole = use not in (Use.STATEMENT, Use.UNPACKED, Use.PASSTHROUGH)
        if flag and kept_whole and not ({"seed", "options"} & set(keywords)):
            # `pair = env.reset(return_info=True)` would become `pair = env.reset()`, which
            # reads exactly like a legacy obs-only reset: no later run could tell them apart.
            self.report(
                call,
                "GM202",
                f"reset() always returns (obs, info) now: drop return_info=True here by hand; "
                f"`{name}.reset()` kept as one value already is the pair",
                FixKind.FLAG,
            )
            return Shape.AT_RUN_TIME
        self._edit(call).drop.add("return_info")
        self.report(
            call,
            "GM202",
            f"return_info= dropped: `{name}.reset()` always returns (obs, info){self._why(decision)}",
            self._kind(decision),
            question=self.receiver_question(call.func.value, decision),  # type: ignore[attr-defined]
        )
        return Shape.PAIR if flag else Shape.OBS

    def _hands_on_own_flag(self, call: ast.Call, value: ast.AST) -> bool:
        """``return_info=return_info`` passing the enclosing method's own parameter, in the
        ``reset`` of a Gym or PettingZoo env class."""
        function = self.facts.enclosing_function(call)
        return (
            isinstance(value, ast.Name)
            and value.id == "return_info"
            and function is not None
            and function.name == "reset"
            and (classdef := self.facts.enclosing_class(function)) is not None
            and self.receivers.class_kind(classdef) in (EnvKind.GYM_ENV, EnvKind.PZ_AEC, EnvKind.PZ_PARALLEL)
            and any(a.arg == "return_info" for a in (*function.args.args, *function.args.kwonlyargs))
            and [b for b in self.facts.bindings_of(value)] == [a for a in (*function.args.args, *function.args.kwonlyargs) if a.arg == "return_info"]
        )

    def _reshape(
        self,
        call: ast.Call,
        use: Use,
        assign: ast.Assign | None,
        index: int | None,
        code: str,
        decision: Decision,
        vector: bool,
    ) -> None:
        name = receiver_text(call.func.value)  # type: ignore[attr-defined]
        kind = self._kind(decision)
        why = self._why(decision)
        question = self.receiver_question(call.func.value, decision)  # type: ignore[attr-defined]
        if use in (Use.ASSIGN, Use.OBS_TUPLE, Use.IN_TUPLE) and assign is not None:
            scope = scope_of_expression(self.facts, call)
            info = self.info_names.choose(scope, call, "infos" if vector else "info")
            self.plan.replace(assign, unpack_builder(info, index))
            self._note_wrapper_info_name(call, info)
            self.report(call, code, f"`{name}.reset()` returns (obs, {info}) now: the result is unpacked{why}", kind, question=question)
        elif use is Use.EXPRESSION:
            self._edit(call).index_result = True
            pair = "(obs, infos)" if vector else "(obs, info)"
            self.report(
                call, code, f"`{name}.reset()` returns {pair} now: the observation is `[0]` of it here{why}", kind, question=question
            )
        elif use is Use.FOREIGN_RESET:
            self.report(
                call,
                code,
                f"`{name}.reset()` now returns (obs, info) and is returned from a reset() of a class that is not "
                "a Gym env: add [0] if callers expect the observation, or keep the tuple and migrate the callers",
                FixKind.FLAG,
            )
        elif use is Use.UNSUPPORTED:
            self.report(
                call,
                code,
                f"`{name}.reset()` returns (obs, info) now and this use was not rewritten: unpack it by hand",
                FixKind.FLAG,
            )

    def _use_of(self, call: ast.Call) -> tuple[Use, ast.Assign | None, int | None]:
        parent = self.facts.parent(call)
        if isinstance(parent, ast.Expr):
            return Use.STATEMENT, None, None
        if isinstance(parent, ast.Await):
            return Use.UNSUPPORTED, None, None
        if isinstance(parent, ast.Assign) and parent.value is call:
            if len(parent.targets) != 1:
                return Use.EXPRESSION, None, None
            return _target_use(parent.targets[0]), parent, None
        if isinstance(parent, ast.Tuple):
            assign = self.facts.parent(parent)
            if isinstance(assign, ast.Assign) and assign.value is parent and len(assign.targets) == 1:
                target = assign.targets[0]
                if isinstance(target, (ast.Tuple, ast.List)) and len(target.elts) == len(parent.elts):
                    if not any(isinstance(e, ast.Starred) for e in (*target.elts, *parent.elts)):
                        index = next(i for i, e in enumerate(parent.elts) if e is call)
                        use = _target_use(target.elts[index])
                        if use is Use.ASSIGN or use is Use.OBS_TUPLE:
                            return Use.IN_TUPLE, assign, index
                        return use, None, None
        if isinstance(parent, ast.Subscript) and parent.value is call and _picks_from_pair(parent):
            return Use.INDEXED, None, None
        if isinstance(parent, ast.Return):
            return self._return_use(call), None, None
        if self._hoisted_by_wrapper_rules(call):
            return Use.PASSTHROUGH, None, None
        return Use.EXPRESSION, None, None

    def _hoisted_by_wrapper_rules(self, call: ast.Call) -> bool:
        """``return f(self.env.reset())`` in a Gym wrapper's reset: the wrapper rules (GM601)
        unpack the inner reset into ``obs, info`` and return ``f(obs), info``; indexing the
        call here as well would hand ``f`` the observation's first element."""
        if not isinstance(self.facts.statement_of(call), ast.Return):
            return False
        function = self.facts.enclosing_function(call)
        classdef = self.facts.enclosing_class(call)
        if function is None or function.name != "reset" or classdef is None:
            return False
        func = call.func
        if not isinstance(func, ast.Attribute):  # ``x.method(...)`` calls only
            return False
        receiver = func.value
        inner = (
            isinstance(receiver, ast.Attribute) and isinstance(receiver.value, ast.Name)
            and receiver.value.id == "self" and receiver.attr == "env"
        ) or is_super_call(receiver) or self._names_base(call)
        # a reset kept with a batch's own step hands on only the observation: ``[0]`` here
        return inner and self.receivers.is_gym_wrapper_class(classdef) and not self.receivers.keeps_own_reset(classdef)

    def _return_use(self, call: ast.Call) -> Use:
        function = self.facts.enclosing_function(call)
        if function is None or function.name != "reset":
            return Use.EXPRESSION  # a helper whose callers use the result as the observation
        classdef = self.facts.enclosing_class(function)
        if classdef is not None and self.receivers.keeps_own_reset(classdef):
            return Use.EXPRESSION  # a reset kept with a batch's own step returns the observation alone
        if classdef is not None:
            if self.receivers.is_gym_wrapper_class(classdef) or self.receivers.class_kind(classdef).is_gym:
                return Use.PASSTHROUGH
            if self.own_plain_class(classdef, set()):
                # the project's own class (a task around its env), whose reset() its own code
                # calls: it returned the observation, and keeps returning it
                return Use.EXPRESSION
        return Use.FOREIGN_RESET

    def _note_wrapper_info_name(self, call: ast.Call, info: str) -> None:
        """Tell the wrappers family (GM601) which name holds info in a Gym class's method."""
        function = self.facts.enclosing_function(call)
        classdef = self.facts.enclosing_class(call)
        if function is not None and classdef is not None:
            names = self.notes.reset_info_names
            names[f"{classdef.name}.{function.name}"] = info


def _target_use(target: ast.expr) -> Use:
    if isinstance(target, (ast.Tuple, ast.List)):
        if any(isinstance(element, ast.Starred) for element in target.elts):
            return Use.UNSUPPORTED
        return Use.UNPACKED if len(target.elts) == 2 else Use.OBS_TUPLE
    return Use.ASSIGN


def _picks_from_pair(subscript: ast.Subscript) -> bool:
    """``x[0]`` or ``x[1]``: reads one half of an (obs, info) pair."""
    index = subscript.slice
    return isinstance(index, ast.Constant) and type(index.value) is int and index.value in (0, 1)
