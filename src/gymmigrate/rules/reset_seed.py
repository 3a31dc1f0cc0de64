"""Reset and seeding at call sites (GM201-GM208, GM704).

Gym 0.26 (and so Gymnasium) changed three things about starting an episode:

* ``reset()`` returns ``(obs, info)`` (``Env.reset -> tuple[ObsType, dict]``), for single
  and vector envs alike, and the 0.22-0.25 ``return_info=`` keyword is gone
  (GM201, GM202, GM704).
* ``env.seed(s)`` is gone (``AttributeError: 'TimeLimit' object has no attribute 'seed'``):
  a seed is passed to ``reset(seed=s)``, "right after initialization and then never
  again" (``Env.reset`` docstring). A seed moved onto every reset of an episode loop makes
  every episode identical, the most common hand-migration bug (GM203, GM204, GM208).
* Seeds must be Python ints (``Seed must be a python integer``, GM206); ``Space.seed()``
  returns an int or a dict, not ``[seed]`` (GM205); custom reset keywords go into
  ``options={...}`` (GM207).

Every call site asks ``analysis.decisions.decide`` about its receiver first, so
Stable-Baselines3 VecEnvs (obs-only ``reset()``, ``vec_env.seed(s)``: their current API,
SB102/SB103), PettingZoo envs and unrelated objects are never touched. Already migrated
code (a two-name reset unpack, ``reset(seed=...)``) is left alone.

The pass plans every edit on the input tree first (it needs look-ahead: a seed merged into
the next reset, a seed inserted before a loop) and applies the plan while leaving nodes.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from enum import Enum

import libcst as cst
from libcst.metadata import PositionProvider, Scope, ScopeProvider

from gymmigrate.analysis.decisions import Action, Decision, decide, receiver_text
from gymmigrate.analysis.receivers import METADATA, EnvKind, ReceiverAnalysis
from gymmigrate.analysis.reset_flow import (
    InfoNames,
    NumpySeeds,
    enclosing_loops,
    guarded_to_run_once,
    is_iteration_invariant,
)
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileProfile, Rule, RulePass

RULES = (
    Rule(
        "GM201",
        "reset() returns (obs, info)",
        FixKind.AUTO,
        "`obs = env.reset()` becomes `obs, info = env.reset()`; `env.reset()[0]` where it is used as a value.",
    ),
    Rule(
        "GM202",
        "return_info= removed",
        FixKind.AUTO,
        "The gym 0.22-0.25 `return_info=` keyword of `reset()` is dropped and the unpack fixed.",
    ),
    Rule(
        "GM203",
        "env.seed() removed",
        FixKind.ASSIST,
        "`env.seed(s)` becomes `env.reset(seed=s)` in place, or is merged into the reset that follows it.",
    ),
    Rule(
        "GM204",
        "seed the first reset only",
        FixKind.FLAG,
        "A reset with the same seed on every loop iteration is reported; `--seed N` seeds unseeded envs once.",
    ),
    Rule(
        "GM205",
        "space seeding",
        FixKind.FLAG,
        "`space.seed(s)` is kept; subscripts of its result (an int or a dict now) are reported.",
    ),
    Rule(
        "GM206",
        "seeds must be Python ints",
        FixKind.ASSIST,
        "numpy seeds (`np.random.randint(...)`, `rng.integers(...)`, array elements) are wrapped in `int(...)`.",
    ),
    Rule(
        "GM207",
        "custom reset keywords",
        FixKind.FLAG,
        "Arguments other than seed=/options= passed to `reset()` are reported: they belong in `options={...}`.",
    ),
    Rule(
        "GM208",
        "vector env seed()",
        FixKind.AUTO,
        "`envs.seed(s)` on a Gym vector env becomes `envs.reset(seed=s)`.",
    ),
    Rule(
        "GM704",
        "vector reset returns (obs, infos)",
        FixKind.AUTO,
        "`obs = envs.reset()` on a Gym vector env becomes `obs, infos = envs.reset()`.",
    ),
)

RESET_KEYWORDS = frozenset({"seed", "options", "return_info"})
_MAY_FIRE = re.compile(r"\.\s*(?:reset|seed)\s*\(")
_NO_SPACE = cst.SimpleWhitespace("")


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


class Shape(Enum):
    """What a legacy ``reset()`` call returned."""

    OBS = "obs"  # gym <= 0.25 without return_info=True
    PAIR = "pair"  # return_info=True
    EITHER = "either"  # reset(seed=...) or reset(options=...): obs in 0.22-0.25, the pair from 0.26
    AT_RUN_TIME = "at-run-time"  # return_info=<expression>


@dataclass
class CallEdit:
    """Changes to one ``reset``/``seed`` call, applied in ``leave_Call``."""

    to_reset: bool = False  # env.seed(s) -> env.reset(seed=s)
    drop: set[str] = field(default_factory=set)
    add_seed: cst.BaseExpression | None = None
    int_seed: bool = False


@dataclass(frozen=True)
class Unpack:
    """``obs = env.reset()`` -> ``obs, info = env.reset()`` (``element``: position in a tuple value)."""

    info_name: str
    element: int | None = None


class ResetSeedPass(RulePass):
    RULES = RULES
    ORDER = 50
    METADATA_DEPENDENCIES = (PositionProvider, *METADATA)

    def __init__(self, context) -> None:  # type: ignore[no-untyped-def]
        super().__init__(context)
        self._edits: dict[int, CallEdit] = {}
        self._unpacks: dict[int, Unpack] = {}
        self._indexed: set[int] = set()
        self._removed: set[int] = set()
        self._inserted: dict[int, list[cst.SimpleStatementLine]] = {}

    @classmethod
    def applies_to(cls, source: str, profile: FileProfile) -> bool:
        return bool(_MAY_FIRE.search(source))

    # -- planning ---------------------------------------------------------------------

    def visit_Module(self, node: cst.Module) -> None:
        self.module = node
        self.analysis = ReceiverAnalysis(node, self.metadata)
        self.info_names = InfoNames(self.analysis, self._position)
        self.numpy_seeds = NumpySeeds(self.analysis, self._scope)
        sites = _CallSites()
        node.visit(sites)
        for call in sites.seeds:
            self._plan_seed(call)
        for call in sites.resets:
            self._plan_reset(call)
        if self.context.options.seed is not None:
            self._plan_cli_seed(self.context.options.seed, sites)

    def _position(self, node: cst.CSTNode) -> tuple[int, int]:
        start = self.get_metadata(PositionProvider, node).start
        return (start.line, start.column)

    def _scope(self, node: cst.CSTNode) -> Scope | None:
        return self.get_metadata(ScopeProvider, node, None)

    def _edit(self, call: cst.Call) -> CallEdit:
        return self._edits.setdefault(id(call), CallEdit())

    def _receiver_kind(self, receiver: cst.BaseExpression) -> EnvKind:
        # ``super().reset()`` inside a Gym wrapper reaches the wrapped env's reset.
        if isinstance(receiver, cst.Call) and isinstance(receiver.func, cst.Name) and receiver.func.value == "super":
            classdef = self.analysis.enclosing(receiver, cst.ClassDef)
            if isinstance(classdef, cst.ClassDef) and self.analysis.is_gym_wrapper_class(classdef):
                return EnvKind.GYM_ENV
        return self.analysis.kind_of(receiver)

    def _decide(self, receiver: cst.BaseExpression) -> tuple[Decision, bool]:
        """The decision for a Gym single-env or vector-env call, and whether it is a vector env."""
        kind = self._receiver_kind(receiver)
        vector = kind is EnvKind.GYM_VEC
        expected = EnvKind.GYM_VEC if vector else EnvKind.GYM_ENV
        return decide(kind, receiver, self.context.profile, expected=expected), vector

    def _kind(self, decision: Decision, default: FixKind | None = None) -> FixKind | None:
        return FixKind.ASSIST if decision.action is Action.REWRITE_FOR_REVIEW else default

    @staticmethod
    def _why(decision: Decision) -> str:
        return f" ({decision.reason})" if decision.action is Action.REWRITE_FOR_REVIEW else ""

    # -- reset() -----------------------------------------------------------------------

    def _plan_reset(self, call: cst.Call) -> None:
        receiver = call.func.value  # type: ignore[attr-defined]
        decision, vector = self._decide(receiver)
        if decision.action is Action.LEAVE:
            return
        code = "GM704" if vector else "GM201"
        name = receiver_text(receiver)
        use, assign, index = self._use_of(call)
        keywords = {arg.keyword.value: arg for arg in call.args if arg.keyword is not None}
        if decision.action is Action.REPORT:
            custom = set(keywords) - {"seed", "options"}
            if use not in (Use.STATEMENT, Use.UNPACKED, Use.INDEXED, Use.PASSTHROUGH) or custom:
                self.report(
                    call,
                    code,
                    f"{decision.reason}: if it is a Gym env, reset() returns (obs, info) now and the result must be unpacked",
                    FixKind.FLAG,
                )
            return
        self._check_custom_arguments(call, name, keywords)
        shape = self._legacy_shape(call, decision, name, keywords, use)
        seed = keywords.get("seed")
        if seed is not None:
            self._check_seed_in_loop(call, seed.value, f"`{name}.reset(seed=...)`")
            if self.numpy_seeds.is_numpy(seed.value):
                self._edit(call).int_seed = True
                self.report(seed.value, "GM206", "numpy seed wrapped in int(): Gymnasium accepts only Python ints as seeds")
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
            elif use not in (Use.STATEMENT, Use.UNPACKED, Use.INDEXED, Use.PASSTHROUGH):
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

    def _check_custom_arguments(self, call: cst.Call, name: str, keywords: dict[str, cst.Arg]) -> None:
        """GM207: reset() takes only seed= and options= (and, until 0.25, return_info=)."""
        custom = [key for key in keywords if key not in RESET_KEYWORDS]
        positional = any(arg.keyword is None and not arg.star for arg in call.args)
        if custom or positional:
            shown = ", ".join(f"`{key}=`" for key in custom) or "positional arguments"
            self.report(
                call,
                "GM207",
                f"`{name}.reset()` takes only seed= and options= now: pass {shown} as options={{...}} "
                "and read them from `options` in the env's reset()",
            )

    def _legacy_shape(
        self, call: cst.Call, decision: Decision, name: str, keywords: dict[str, cst.Arg], use: Use
    ) -> Shape:
        """What the legacy call returned; drops ``return_info=`` (GM202) on the way."""
        return_info = keywords.get("return_info")
        if return_info is None:
            # reset(seed=/options=) returned obs in gym 0.22-0.25 and the pair from 0.26 on.
            return Shape.EITHER if "seed" in keywords or "options" in keywords else Shape.OBS
        flag = _bool_constant(return_info.value)
        if flag is None:
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
        )
        return Shape.PAIR if flag else Shape.OBS

    def _reshape(
        self,
        call: cst.Call,
        use: Use,
        assign: cst.Assign | None,
        index: int | None,
        code: str,
        decision: Decision,
        vector: bool,
    ) -> None:
        name = receiver_text(call.func.value)  # type: ignore[attr-defined]
        kind = self._kind(decision)
        why = self._why(decision)
        if use in (Use.ASSIGN, Use.OBS_TUPLE, Use.IN_TUPLE) and assign is not None:
            info = self.info_names.choose(self._scope(call), call, "infos" if vector else "info")
            self._unpacks[id(assign)] = Unpack(info, index)
            self._note_wrapper_info_name(call, info)
            self.report(call, code, f"`{name}.reset()` returns (obs, {info}) now: the result is unpacked{why}", kind)
        elif use is Use.EXPRESSION:
            self._indexed.add(id(call))
            pair = "(obs, infos)" if vector else "(obs, info)"
            self.report(call, code, f"`{name}.reset()` returns {pair} now: the observation is `[0]` of it here{why}", kind)
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

    def _use_of(self, call: cst.Call) -> tuple[Use, cst.Assign | None, int | None]:
        parent = self.analysis.parent(call)
        if isinstance(parent, cst.Expr):
            return Use.STATEMENT, None, None
        if isinstance(parent, cst.Await):
            return Use.UNSUPPORTED, None, None
        if isinstance(parent, cst.Assign) and parent.value is call:
            if len(parent.targets) != 1:
                return Use.EXPRESSION, None, None
            return _target_use(parent.targets[0].target), parent, None
        if isinstance(parent, cst.Element):
            holder = self.analysis.parent(parent)
            assign = self.analysis.parent(holder) if isinstance(holder, cst.Tuple) else None
            if isinstance(assign, cst.Assign) and assign.value is holder and len(assign.targets) == 1:
                target = assign.targets[0].target
                if isinstance(target, (cst.Tuple, cst.List)) and len(target.elements) == len(holder.elements):
                    if not any(isinstance(e, cst.StarredElement) for e in (*target.elements, *holder.elements)):
                        index = next(i for i, e in enumerate(holder.elements) if e is parent)
                        use = _target_use(target.elements[index].value)
                        if use is Use.ASSIGN or use is Use.OBS_TUPLE:
                            return Use.IN_TUPLE, assign, index
                        return use, None, None
        if isinstance(parent, cst.Subscript) and parent.value is call and _picks_from_pair(parent):
            return Use.INDEXED, None, None
        if isinstance(parent, cst.Return):
            return self._return_use(call), None, None
        return Use.EXPRESSION, None, None

    def _return_use(self, call: cst.Call) -> Use:
        function = self.analysis.enclosing(call, cst.FunctionDef)
        if not isinstance(function, cst.FunctionDef) or function.name.value != "reset":
            return Use.EXPRESSION  # a helper whose callers use the result as the observation
        classdef = self.analysis.enclosing(function, cst.ClassDef)
        if isinstance(classdef, cst.ClassDef):
            if self.analysis.is_gym_wrapper_class(classdef) or self.analysis.class_kind(classdef).is_gym:
                return Use.PASSTHROUGH
        return Use.FOREIGN_RESET

    def _note_wrapper_info_name(self, call: cst.Call, info: str) -> None:
        """Tell the wrappers pass (GM601) which name holds info in a Gym class's method."""
        function = self.analysis.enclosing(call, cst.FunctionDef)
        classdef = self.analysis.enclosing(call, cst.ClassDef)
        if isinstance(function, cst.FunctionDef) and isinstance(classdef, cst.ClassDef):
            names = self.context.notes.setdefault("reset_info_names", {})
            names[f"{classdef.name.value}.{function.name.value}"] = info  # type: ignore[index]

    # -- seed() ------------------------------------------------------------------------

    def _plan_seed(self, call: cst.Call) -> None:
        receiver = call.func.value  # type: ignore[attr-defined]
        if _is_space(receiver):
            self._check_space_seed(call)
            return
        decision, vector = self._decide(receiver)
        if decision.action is Action.LEAVE:
            return
        code = "GM208" if vector else "GM203"
        name = receiver_text(receiver)
        if decision.action is Action.REPORT:
            self.report(call, code, f"{decision.reason}: if it is a Gym env, replace seed(s) with reset(seed=s)", FixKind.FLAG)
            return
        function = self.analysis.enclosing(call, cst.FunctionDef)
        if isinstance(function, cst.FunctionDef) and function.name.value == "seed":
            self.report(
                call,
                code,
                "inside a seed() method, which Gymnasium never calls: move the seeding into reset(seed=...)",
                FixKind.FLAG,
            )
            return
        parent = self.analysis.parent(call)
        if not isinstance(parent, cst.Expr):
            self.report(
                call,
                code,
                f"`{name}.seed()` is gone and its result (legacy: [seed]) is used here: call "
                f"`{name}.reset(seed=s)` and keep the seed value yourself",
                FixKind.FLAG,
            )
            return
        seed = _seed_argument(call)
        if seed is None:
            self.report(
                call,
                code,
                f"`{name}.seed()` without exactly one seed is gone: pass the seed to the first "
                f"`{name}.reset(seed=s)` (with no seed Gymnasium draws one from entropy); then delete this call",
                FixKind.FLAG,
            )
            return
        numpy = self.numpy_seeds.is_numpy(seed)
        if numpy:
            self.report(seed, "GM206", "numpy seed wrapped in int(): Gymnasium accepts only Python ints as seeds")
        self._check_seed_in_loop(call, seed, f"`{name}.seed(...)`")
        line = self.analysis.parent(parent)
        merged = self._next_reset(line, receiver) if isinstance(line, cst.SimpleStatementLine) else None
        why = self._why(decision)
        if merged is not None:
            self._removed.add(id(line))  # type: ignore[arg-type]
            self._edit(merged).add_seed = _int_call(seed) if numpy else seed
            self.report(
                call,
                code,
                f"`{name}.seed(s)` merged into the reset that follows it: `{name}.reset(seed=s)`{why}",
                self._kind(decision, FixKind.AUTO),
            )
            return
        edit = self._edit(call)
        edit.to_reset = True
        edit.int_seed = numpy
        self.report(
            call,
            code,
            f"`{name}.seed(s)` -> `{name}.reset(seed=s)` at the same place: it seeds once here and starts an extra "
            f"episode; later resets continue the seeded stream{why}",
            self._kind(decision),
        )

    def _check_space_seed(self, call: cst.Call) -> None:
        parent = self.analysis.parent(call)
        if isinstance(parent, cst.Subscript) and parent.value is call:
            self.report(
                parent,
                "GM205",
                "Space.seed() returns an int (a dict for Dict spaces) since Gymnasium 1.0, not [seed]: drop the subscript",
            )

    def _next_reset(self, line: cst.SimpleStatementLine, receiver: cst.BaseExpression) -> cst.Call | None:
        """The reset of the same env that the seeded statement ``line`` leads to, if merging is safe.

        Only statements of the same block are looked at, so a seed is never moved into a
        loop; statements in between must not touch the env (space seeding and other
        seeding calls are fine).
        """
        block = self.analysis.parent(line)
        if len(line.body) != 1 or not isinstance(block, (cst.IndentedBlock, cst.Module)):
            return None
        body = list(block.body)
        position = next(i for i, statement in enumerate(body) if statement is line)
        wanted = self.module.code_for_node(receiver)
        root = _root_name(receiver)
        for statement in body[position + 1 :]:
            reset = self._reset_statement(statement, wanted)
            if reset is not None:
                return reset
            if not _independent_of(statement, root):
                return None
        return None

    def _reset_statement(self, statement: cst.BaseStatement, receiver_code: str) -> cst.Call | None:
        if not isinstance(statement, cst.SimpleStatementLine) or len(statement.body) != 1:
            return None
        small = statement.body[0]
        value = small.value if isinstance(small, (cst.Expr, cst.Assign)) else None
        if not (isinstance(value, cst.Call) and isinstance(value.func, cst.Attribute) and value.func.attr.value == "reset"):
            return None
        if self.module.code_for_node(value.func.value) != receiver_code:
            return None
        if any(arg.star or arg.keyword is None or arg.keyword.value == "seed" for arg in value.args):
            return None
        return value

    def _check_seed_in_loop(self, call: cst.Call, seed: cst.BaseExpression, shown: str) -> None:
        """GM204: a seed that is the same on every iteration of a loop resets the RNG each time."""
        if isinstance(seed, cst.Name) and seed.value == "None":
            return
        for loop in enclosing_loops(self.analysis, call):
            if is_iteration_invariant(seed, loop) and not guarded_to_run_once(self.analysis, call, loop):
                self.report(
                    call,
                    "GM204",
                    f"{shown} reseeds with the same value on every loop iteration, so every episode starts from "
                    "the same state: seed the first reset before the loop and reset without a seed inside it, "
                    "unless identical episodes are intended",
                )
                return

    # -- --seed N ------------------------------------------------------------------------

    def _plan_cli_seed(self, seed: int, sites: _CallSites) -> None:
        """Seed the first reset of every env created here that the code never seeds (GM204)."""
        envs: dict[tuple[int, str], tuple[Scope, list[cst.Assign]]] = {}
        for assign in sites.assigns:
            target = assign.targets[0].target
            if not isinstance(target, cst.Name):
                continue
            if self.analysis.kind_of(assign.value) not in (EnvKind.GYM_ENV, EnvKind.GYM_VEC):
                continue
            scope = self._scope(target)
            if scope is not None:
                envs.setdefault((id(scope), target.value), (scope, []))[1].append(assign)
        seeded_somewhere = any(self._seeds_a_gym_env(call) for call in (*sites.seeds, *sites.resets))
        for (_, name), (scope, creations) in envs.items():
            calls = [
                call
                for call in (*sites.seeds, *sites.resets)
                if isinstance(call.func.value, cst.Name)  # type: ignore[attr-defined]
                and call.func.value.value == name  # type: ignore[attr-defined]
                and self._scope(call.func.value) is scope  # type: ignore[attr-defined]
            ]
            if any(_is_seeding(call) for call in calls):
                continue
            created_at = min(self._position(assign) for assign in creations)
            resets = sorted(
                (call for call in calls if self._position(call) > created_at),
                key=self._position,
            )
            if not resets:
                continue
            first = resets[0]
            kind = self.analysis.kind_of(first.func.value)  # type: ignore[attr-defined]
            if not kind.is_gym or (kind is EnvKind.GYM_VEC and seeded_somewhere):
                continue  # a vector env whose sub-envs are seeded already
            self._seed_first_reset(first, creations[0], name, seed)

    def _seed_first_reset(self, first: cst.Call, creation: cst.Assign, name: str, seed: int) -> None:
        creation_loops = {id(loop) for loop in enclosing_loops(self.analysis, creation)}
        loops = [loop for loop in enclosing_loops(self.analysis, first) if id(loop) not in creation_loops]
        value = cst.parse_expression(str(seed))
        if not loops:
            self._edit(first).add_seed = value
            self.report(first, "GM204", f"--seed {seed}: `{name}` had no seed; its first reset is seeded", FixKind.ASSIST)
            return
        statement = self._statement_of(loops[-1])
        reset = cst.SimpleStatementLine(
            body=[
                cst.Expr(
                    cst.Call(
                        func=cst.Attribute(value=cst.Name(name), attr=cst.Name("reset")),
                        args=[_seed_keyword(value)],
                    )
                )
            ]
        )
        self._inserted.setdefault(id(statement), []).append(reset)
        self.report(
            first,
            "GM204",
            f"--seed {seed}: `{name}` had no seed and is first reset inside a loop; "
            f"`{name}.reset(seed={seed})` inserted before the loop",
            FixKind.ASSIST,
        )

    def _statement_of(self, node: cst.CSTNode) -> cst.CSTNode:
        current = node
        parent = self.analysis.parent(current)
        while parent is not None and not isinstance(parent, (cst.IndentedBlock, cst.Module)):
            current, parent = parent, self.analysis.parent(parent)
        return current

    def _seeds_a_gym_env(self, call: cst.Call) -> bool:
        receiver = call.func.value  # type: ignore[attr-defined]
        return _is_seeding(call) and not _is_space(receiver) and self._receiver_kind(receiver).is_gym

    # -- applying the plan ----------------------------------------------------------------

    def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.BaseExpression:
        edit = self._edits.get(id(original_node))
        result: cst.BaseExpression = _apply(updated_node, edit) if edit else updated_node
        if id(original_node) in self._indexed:
            return cst.Subscript(value=result, slice=[cst.SubscriptElement(cst.Index(cst.Integer("0")))])
        return result

    def leave_Assign(self, original_node: cst.Assign, updated_node: cst.Assign) -> cst.Assign:
        unpack = self._unpacks.get(id(original_node))
        if unpack is None:
            return updated_node
        target = updated_node.targets[0]
        info = cst.Element(cst.Name(unpack.info_name))
        if unpack.element is None:
            pair = cst.Tuple(elements=[cst.Element(_grouped(target.target), comma=_comma()), info], lpar=[], rpar=[])
            return updated_node.with_changes(targets=[target.with_changes(target=pair)])
        outer = target.target
        assert isinstance(outer, (cst.Tuple, cst.List))
        elements = list(outer.elements)
        element = elements[unpack.element]
        pair = cst.Tuple(elements=[cst.Element(_grouped(element.value), comma=_comma()), info])
        elements[unpack.element] = element.with_changes(value=pair)
        return updated_node.with_changes(targets=[target.with_changes(target=outer.with_changes(elements=elements))])

    def leave_IndentedBlock(self, original_node: cst.IndentedBlock, updated_node: cst.IndentedBlock) -> cst.IndentedBlock:
        body = self._restructure(original_node.body, updated_node.body)
        return updated_node if body is None else updated_node.with_changes(body=body)

    def leave_Module(self, original_node: cst.Module, updated_node: cst.Module) -> cst.Module:
        body = self._restructure(original_node.body, updated_node.body)
        return updated_node if body is None else updated_node.with_changes(body=body)

    def _restructure(
        self,
        originals: tuple[cst.BaseStatement, ...] | list[cst.BaseStatement],
        updated: tuple[cst.BaseStatement, ...] | list[cst.BaseStatement],
    ) -> list[cst.BaseStatement] | None:
        """Drop merged seed statements (keeping their comments) and insert seeding resets."""
        if not any(id(s) in self._removed or id(s) in self._inserted for s in originals):
            return None
        body: list[cst.BaseStatement] = []
        carried: list[cst.EmptyLine] = []
        for original, new in zip(originals, updated):
            if id(original) in self._removed:
                carried.extend(new.leading_lines)
                continue
            statements: list[cst.BaseStatement] = [*self._inserted.get(id(original), []), new]
            if carried:
                first = statements[0]
                statements[0] = first.with_changes(leading_lines=[*carried, *first.leading_lines])
                carried = []
            body.extend(statements)
        return body


# -- helpers ---------------------------------------------------------------------------------


class _CallSites(cst.CSTVisitor):
    """``x.reset(...)`` and ``x.seed(...)`` calls and single-target assignments, in source order."""

    def __init__(self) -> None:
        self.resets: list[cst.Call] = []
        self.seeds: list[cst.Call] = []
        self.assigns: list[cst.Assign] = []

    def visit_Call(self, node: cst.Call) -> None:
        if isinstance(node.func, cst.Attribute):
            if node.func.attr.value == "reset":
                self.resets.append(node)
            elif node.func.attr.value == "seed":
                self.seeds.append(node)

    def visit_Assign(self, node: cst.Assign) -> None:
        if len(node.targets) == 1:
            self.assigns.append(node)


def _target_use(target: cst.BaseExpression) -> Use:
    if isinstance(target, (cst.Tuple, cst.List)):
        if any(isinstance(element, cst.StarredElement) for element in target.elements):
            return Use.UNSUPPORTED
        return Use.UNPACKED if len(target.elements) == 2 else Use.OBS_TUPLE
    return Use.ASSIGN


def _picks_from_pair(subscript: cst.Subscript) -> bool:
    """``x[0]`` or ``x[1]``: reads one half of an (obs, info) pair."""
    if len(subscript.slice) != 1:
        return False
    index = subscript.slice[0].slice
    return isinstance(index, cst.Index) and isinstance(index.value, cst.Integer) and index.value.value in ("0", "1")


def _bool_constant(node: cst.BaseExpression) -> bool | None:
    if isinstance(node, cst.Name) and node.value in ("True", "False"):
        return node.value == "True"
    return None


def _is_space(receiver: cst.BaseExpression) -> bool:
    """``env.action_space``, ``observation_space``, ``space``, ``spaces["x"]``..."""
    if isinstance(receiver, cst.Subscript):
        return _is_space(receiver.value)
    if isinstance(receiver, cst.Attribute):
        name = receiver.attr.value
    elif isinstance(receiver, cst.Name):
        name = receiver.value
    else:
        return False
    return name.lower().endswith(("space", "spaces"))


def _is_seeding(call: cst.Call) -> bool:
    attr = call.func.attr.value  # type: ignore[attr-defined]
    return attr == "seed" or any(arg.keyword is not None and arg.keyword.value == "seed" for arg in call.args)


def _seed_argument(call: cst.Call) -> cst.BaseExpression | None:
    if len(call.args) != 1 or call.args[0].star:
        return None
    arg = call.args[0]
    if arg.keyword is not None and arg.keyword.value != "seed":
        return None
    return arg.value


def _root_name(node: cst.BaseExpression) -> str | None:
    while isinstance(node, (cst.Attribute, cst.Subscript, cst.Call)):
        node = node.value if not isinstance(node, cst.Call) else node.func
    return node.value if isinstance(node, cst.Name) else None


def _independent_of(statement: cst.BaseStatement, root: str | None) -> bool:
    """Can a seed move past ``statement``? Only simple lines that leave the env alone qualify."""
    if not isinstance(statement, cst.SimpleStatementLine) or root is None:
        return False
    scan = _StatementScan()
    statement.visit(scan)
    # Reading the env's attributes is fine; rebinding the name or calling anything but a
    # seeding function (env.action_space.seed, np.random.seed...) is not.
    return root not in scan.bound and scan.only_seeding_calls


class _StatementScan(cst.CSTVisitor):
    def __init__(self) -> None:
        self.bound: set[str] = set()
        self.only_seeding_calls = True

    def _bind(self, target: cst.BaseExpression) -> None:
        if isinstance(target, (cst.Tuple, cst.List)):
            for element in target.elements:
                self._bind(element.value)
        else:
            root = _root_name(target)
            if root is not None:
                self.bound.add(root)

    def visit_AssignTarget(self, node: cst.AssignTarget) -> None:
        self._bind(node.target)

    def visit_AugAssign(self, node: cst.AugAssign) -> None:
        self._bind(node.target)

    def visit_AnnAssign(self, node: cst.AnnAssign) -> None:
        self._bind(node.target)

    def visit_NamedExpr(self, node: cst.NamedExpr) -> None:
        self._bind(node.target)

    def visit_Call(self, node: cst.Call) -> None:
        func = node.func
        called = func.attr.value if isinstance(func, cst.Attribute) else func.value if isinstance(func, cst.Name) else ""
        if "seed" not in called:
            self.only_seeding_calls = False


def _comma() -> cst.Comma:
    return cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))


def _grouped(target: cst.BaseExpression) -> cst.BaseExpression:
    """A tuple target nested in another tuple needs its own parentheses."""
    if isinstance(target, cst.Tuple) and not target.lpar:
        return target.with_changes(lpar=[cst.LeftParen()], rpar=[cst.RightParen()])
    return target


def _int_call(value: cst.BaseExpression) -> cst.Call:
    return cst.Call(func=cst.Name("int"), args=[cst.Arg(value=value)])


def _seed_keyword(value: cst.BaseExpression) -> cst.Arg:
    return cst.Arg(
        value=value,
        keyword=cst.Name("seed"),
        equal=cst.AssignEqual(whitespace_before=_NO_SPACE, whitespace_after=_NO_SPACE),
    )


def _apply(call: cst.Call, edit: CallEdit) -> cst.Call:
    args = list(call.args)
    func = call.func
    if edit.drop:
        kept = [arg for arg in args if not (arg.keyword is not None and arg.keyword.value in edit.drop)]
        if kept and kept[-1] is not args[-1]:
            kept[-1] = kept[-1].with_changes(comma=args[-1].comma)
        args = kept
    if edit.to_reset:
        func = func.with_changes(attr=cst.Name("reset"))  # type: ignore[union-attr]
        first = args[0]
        if first.keyword is None:
            args = [_seed_keyword(first.value).with_changes(comma=first.comma)]
    if edit.add_seed is not None:
        args = _appended(args, _seed_keyword(edit.add_seed), call)
    if edit.int_seed:
        args = [
            arg.with_changes(value=_int_call(arg.value)) if arg.keyword is not None and arg.keyword.value == "seed" else arg
            for arg in args
        ]
    return call.with_changes(func=func, args=args)


def _appended(args: list[cst.Arg], new: cst.Arg, call: cst.Call) -> list[cst.Arg]:
    if not args:
        return [new]
    last = args[-1]
    if isinstance(last.comma, cst.Comma):
        # A trailing comma (often a multi-line call): the new argument takes over the
        # trailing comma and the previous one gets the separator used between arguments.
        if len(args) >= 2 and isinstance(args[-2].comma, cst.Comma):
            separator = args[-2].comma
        elif isinstance(call.whitespace_before_args, cst.ParenthesizedWhitespace):
            separator = cst.Comma(whitespace_after=call.whitespace_before_args)
        else:
            separator = _comma()
        return [*args[:-1], last.with_changes(comma=separator), new.with_changes(comma=last.comma)]
    return [*args[:-1], last.with_changes(comma=_comma()), new]
