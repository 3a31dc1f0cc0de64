"""Step and ``done`` semantics at call sites (GM301-GM304, GM703).

Since gym 0.26 ``step`` returns five values, ``(obs, reward, terminated, truncated,
info)``: ``terminated`` means the MDP reached a terminal state, ``truncated`` that the
episode was cut (usually by ``TimeLimit``). The legacy ``done`` was their ``or``
(Gymnasium release notes 0.26, "Step termination / truncation"; migration guide,
"Environment step").

* GM301 ``obs, r, done, info = env.step(a)`` on a Gym env -> ``obs, r, terminated,
  truncated, info = env.step(a)``, plus ``done = terminated or truncated`` right after
  it when the old flag is still read (loop tests, ``break`` conditions, a ``while not
  done`` loop around the step).
* GM302 reads of ``done`` that feed a value (``1 - done``, masks, tensors, replay
  writes) become ``terminated``: a time-limit truncation must still bootstrap from the
  next state. Each one is a review item; reads whose purpose is unclear are reported.
* GM303 ``info["TimeLimit.truncated"]`` / ``info.get("TimeLimit.truncated", False)``:
  Gymnasium's ``TimeLimit`` no longer sets the key, so the read is silently always
  false. It becomes ``truncated and not terminated``, the exact legacy meaning (legacy
  ``TimeLimit`` stored ``not done`` there, and only when the limit was hit).
* GM304 step results that are not unpacked: constant indices move (``res[3]`` ->
  ``res[4]``, ``res[2]`` -> ``res[2] or res[3]``); other uses are reported.
* GM703 the same split for Gym vector envs, with arrays: ``dones =
  np.logical_or(terminations, truncations)`` (``or`` on arrays raises).

Stable-Baselines3 VecEnvs keep the four-value step and their ``TimeLimit.truncated``
info key (SB102-SB104); objects that are not envs (optimisers, schedulers, agents) are
left alone, unless four names are unpacked from their ``step`` in a Gym file, which
is reported.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import libcst as cst
from libcst.codemod.visitors import AddImportsVisitor
from libcst.helpers import get_full_name_for_node
from libcst.metadata import PositionProvider

from gymmigrate.analysis.decisions import Action, Decision, decide, receiver_text
from gymmigrate.analysis.done_uses import DoneUse, classify_done_read
from gymmigrate.analysis.flow import METADATA as FLOW_METADATA
from gymmigrate.analysis.flow import Flow
from gymmigrate.analysis.receivers import METADATA, EnvKind, ReceiverAnalysis
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileProfile, Rule, RulePass

RULES = (
    Rule(
        "GM301",
        "step returns terminated and truncated",
        FixKind.AUTO,
        "`obs, r, done, info = env.step(a)` unpacks five values; `done = terminated or truncated` where it is read.",
    ),
    Rule(
        "GM302",
        "bootstrapping uses terminated",
        FixKind.ASSIST,
        "Value targets, masks and replay writes of `done` use `terminated`; unclear uses are reported.",
    ),
    Rule(
        "GM303",
        "TimeLimit.truncated info key",
        FixKind.ASSIST,
        '`info["TimeLimit.truncated"]` becomes `truncated and not terminated`; the key is no longer set.',
    ),
    Rule(
        "GM304",
        "step results that are not unpacked",
        FixKind.ASSIST,
        "Constant indices of a step result move (`res[3]` -> `res[4]`, `res[2]` -> `res[2] or res[3]`).",
    ),
    Rule(
        "GM703",
        "vector step returns terminations and truncations",
        FixKind.AUTO,
        "Vector `obs, rewards, dones, infos = envs.step(a)` unpacks five arrays; "
        "`dones = np.logical_or(terminations, truncations)`.",
    ),
)

TIME_LIMIT_KEY = "TimeLimit.truncated"


@dataclass(frozen=True)
class StepNames:
    """Names of the two new flags for one step, and how to join them into ``done``."""

    terminated: str
    truncated: str
    vector: bool
    numpy: str = "np"

    @property
    def code(self) -> str:
        return "GM703" if self.vector else "GM301"

    def joined(self) -> cst.BaseExpression:
        if self.vector:
            return cst.parse_expression(f"{self.numpy}.logical_or({self.terminated}, {self.truncated})")
        return cst.parse_expression(f"{self.terminated} or {self.truncated}")


@dataclass
class _Unpack:
    """The plan for one four-target step unpack."""

    names: StepNames
    done_target: cst.BaseAssignTargetExpression
    alias: bool = False
    inline: bool = False  # the step shares its line (``a; b``) or sits in a one-line suite


class StepDonePass(RulePass):
    RULES = RULES
    ORDER = 55
    METADATA_DEPENDENCIES = (PositionProvider, *METADATA, *FLOW_METADATA)

    def __init__(self, context) -> None:  # type: ignore[no-untyped-def]
        super().__init__(context)
        self._unpacks: dict[cst.Assign, _Unpack] = {}
        self._replacements: dict[cst.CSTNode, cst.BaseExpression] = {}
        self._reported_reads: set[int] = set()

    @classmethod
    def applies_to(cls, source: str, profile: FileProfile) -> bool:
        return ".step(" in source or TIME_LIMIT_KEY in source

    # -- planning (on the input tree) ---------------------------------------------------

    def visit_Module(self, node: cst.Module) -> None:
        self.analysis = ReceiverAnalysis(node, self.metadata)
        self.flow = Flow(self.metadata)
        self._numpy_name = _numpy_name(node)
        finder = _StepAndKeyFinder()
        node.visit(finder)
        self._info_names: dict[int, StepNames | None] = {}  # info reads -> the step they come from
        # Four-target step unpacks: a read that one of them dominates belongs to it alone.
        self._legacy_unpacks = [
            call_parent
            for call_parent in (self.flow.parent(call) for call in finder.steps)
            if isinstance(call_parent, cst.Assign) and _four_targets(call_parent)
        ]
        for call in finder.steps:
            self._plan_step(call)
        for node_with_key in finder.time_limit_reads:
            self._plan_time_limit_read(node_with_key)

    def _decision(self, receiver: cst.BaseExpression, legacy_shape: bool) -> tuple[Decision, bool]:
        """What to do with ``receiver.step``, and whether it is a vector env."""
        kind = self._super_kind(receiver) or self.analysis.kind_of(receiver)
        if kind is EnvKind.GYM_VEC:
            return decide(kind, receiver, self.context.profile, legacy_shape=legacy_shape, expected=EnvKind.GYM_VEC), True
        return decide(kind, receiver, self.context.profile, legacy_shape=legacy_shape), False

    def _super_kind(self, receiver: cst.BaseExpression) -> EnvKind | None:
        """``super().step(a)`` inside a Gym wrapper or env subclass is the wrapped Gym step."""
        if not (isinstance(receiver, cst.Call) and get_full_name_for_node(receiver.func) == "super"):
            return None
        classdef = self.analysis.enclosing(receiver, cst.ClassDef)
        if not isinstance(classdef, cst.ClassDef):
            return None
        if self.analysis.is_gym_wrapper_class(classdef):
            return EnvKind.GYM_ENV
        kind = self.analysis.class_kind(classdef)
        return kind if kind.is_gym else None

    def _plan_step(self, call: cst.Call) -> None:
        receiver = call.func.value  # type: ignore[attr-defined]
        parent = self.flow.parent(call)
        if isinstance(parent, cst.Assign) and parent.value is call and len(parent.targets) == 1:
            target = parent.targets[0].target
            if isinstance(target, (cst.Tuple, cst.List)) and not _starred(target):
                if len(target.elements) == 5:
                    return  # already migrated
                if len(target.elements) == 4:
                    self._plan_unpack(parent, target, receiver)
                    return
            if isinstance(target, cst.Name):
                self._plan_result_name(parent, target, receiver)
                return
        if isinstance(parent, cst.Expr) or _returned_from_step_method(call, self.flow):
            return  # result unused, or passed through by a wrapper's step (the wrapper rules' job)
        decision, vector = self._decision(receiver, legacy_shape=False)
        if decision.action is not Action.LEAVE and self.context.profile.imports_gym:
            self.report(
                call,
                "GM304",
                f"`{receiver_text(receiver)}.step()` result is used without unpacking five values "
                "(index 2 is now terminated, 3 truncated, 4 info): update this use by hand",
                FixKind.FLAG,
            )

    # -- GM301 / GM703 -----------------------------------------------------------------

    def _plan_unpack(self, assign: cst.Assign, target: cst.Tuple | cst.List, receiver: cst.BaseExpression) -> None:
        decision, vector = self._decision(receiver, legacy_shape=True)
        done_target = target.elements[2].value
        if decision.action is Action.LEAVE:
            self._note_guarded_info(target.elements[3].value)
            return
        if not isinstance(done_target, (cst.Name, cst.Attribute, cst.Subscript)):
            target_text = cst.Module([]).code_for_node(done_target)
            self.report(
                assign,
                "GM301",
                f"step now returns terminated and truncated, and the done target `{target_text}` cannot be split: "
                "unpack five values by hand",
                FixKind.FLAG,
            )
            return
        if decision.action is Action.REWRITE_FOR_REVIEW and _looks_vectorised(receiver, done_target):
            decision = Decision(Action.REPORT, decision.reason + "; it may be a vector env")
        if decision.action is Action.REPORT:
            self.report(
                assign,
                "GM301",
                f"{decision.reason}: if it is a Gym env, unpack `obs, reward, terminated, truncated, info`",
                FixKind.FLAG,
            )
            return
        names = self._step_names(assign, vector)
        plan = _Unpack(names=names, done_target=done_target, inline=_shares_line(assign, self.flow))
        self._unpacks[assign] = plan
        if isinstance(done_target, cst.Name):
            if done_target.value != "_":
                plan.alias = self._plan_done_reads(assign, done_target, names)
                # ``global done``: readers live in other scopes and cannot all be traced.
                plan.alias = plan.alias or self._declared_outside(assign, done_target.value)
        else:
            plan.alias = True  # ``self.done``/``dones[i]``: readers cannot be traced
        if plan.alias and vector and self._numpy_name is None:
            AddImportsVisitor.add_needed_import(self.context.codemod, "numpy", asname="np")
        info_target = target.elements[3].value
        if isinstance(info_target, cst.Name):
            for read in self.flow.reads(info_target):
                if self.flow.dominates(assign, read, info_target):
                    self._info_names[id(read)] = names
        message = f"step now returns {names.terminated} and {names.truncated} instead of one done flag"
        if decision.action is Action.REWRITE_FOR_REVIEW:
            self.report(assign, names.code, f"{message}; {decision.reason}", FixKind.ASSIST)
        else:
            self.report(assign, names.code, message)

    def _declared_outside(self, node: cst.CSTNode, name: str) -> bool:
        function = self.analysis.enclosing(node, cst.FunctionDef)
        if not isinstance(function, cst.FunctionDef):
            return False
        finder = _OuterDeclarations()
        function.body.visit(finder)
        return name in finder.names

    def _note_guarded_info(self, info_target: cst.BaseExpression) -> None:
        """SB3 VecEnv infos still carry ``TimeLimit.truncated`` (SB104): stay silent on them."""
        if isinstance(info_target, cst.Name):
            for read in self.flow.reads(info_target):
                self._info_names.setdefault(id(read), None)

    def _step_names(self, assign: cst.Assign, vector: bool) -> StepNames:
        scope = self.flow.scope(assign.targets[0].target)
        scope_node = getattr(scope, "node", None) or self._module_node(assign)
        taken = self.flow.names_used_in(scope, scope_node) if scope is not None else set()
        compatible = _step_bound_names(scope_node)
        base = ("terminations", "truncations") if vector else ("terminated", "truncated")
        return StepNames(*(_fresh(name, taken, compatible) for name in base), vector=vector, numpy=self._numpy_name or "np")

    def _module_node(self, node: cst.CSTNode) -> cst.CSTNode:
        top = node
        for ancestor in self.flow.ancestors(node):
            top = ancestor
        return top

    def _plan_done_reads(self, assign: cst.Assign, done: cst.Name, names: StepNames) -> bool:
        """Plan every read of the old flag; True when ``done = ...`` must be kept."""
        needs_alias = False
        for read in self.flow.reads(done):
            if read in self._replacements or not self.flow.observes(read, assign, done):
                continue
            if any(
                other is not assign
                and _binds(other, done.value)
                and self.flow.is_after(other, assign)
                and self.flow.dominates(other, read, done)
                for other in self._legacy_unpacks
            ):
                continue  # a later step rebinds the flag before this read
            use = classify_done_read(read, self.flow.parent)
            if use is DoneUse.DATA and self.flow.dominates(assign, read, done):
                self._replacements[read] = read.with_changes(value=names.terminated)
                self._report_read(
                    read,
                    f"`{done.value}` used as a value (target, mask or stored transition) now reads "
                    f"`{names.terminated}`: a time-limit truncation must still bootstrap; review",
                    FixKind.ASSIST,
                )
                continue
            needs_alias = True
            if use is DoneUse.DATA:
                self._report_read(
                    read,
                    f"`{done.value}` used as a value may not come from the step on line {self.flow.line(assign)}; "
                    f"if it feeds bootstrapping, use `{names.terminated}` there",
                    FixKind.FLAG,
                )
            elif use is DoneUse.AMBIGUOUS:
                self._report_read(
                    read,
                    f"`{done.value}` now means `{names.terminated} or {names.truncated}`; "
                    f"if this use decides bootstrapping, use `{names.terminated}`",
                    FixKind.FLAG,
                )
        return needs_alias

    def _report_read(self, read: cst.Name, message: str, kind: FixKind) -> None:
        if id(read) not in self._reported_reads:
            self._reported_reads.add(id(read))
            self.report(read, "GM302", message, kind)

    # -- GM303 ---------------------------------------------------------------------------

    def _plan_time_limit_read(self, node: cst.BaseExpression) -> None:
        if self._is_store(node):
            # A legacy TimeLimit-style wrapper *writing* the key: a store cannot become a
            # `truncated and not terminated` expression, and the wrapper must now report
            # the limit through the truncated flag it returns.
            self.report(
                node,
                "GM303",
                f'writes the legacy "{TIME_LIMIT_KEY}" info key, which Gymnasium code no longer reads: '
                "return the time limit as the step's `truncated` flag instead",
                FixKind.FLAG,
            )
            return
        base = _time_limit_base(node)
        names = self._info_names.get(id(base), _UNTRACED) if isinstance(base, cst.Name) else _UNTRACED
        if names is None:
            return  # SB3 VecEnv infos keep the key (SB104)
        if isinstance(names, StepNames) and not names.vector:
            self._replacements[node] = _truncation_expression(node, names, self.flow.parent(node))
            equivalent = (
                f"`{names.truncated}` (the key was present exactly when the time limit was hit)"
                if isinstance(node, cst.Comparison)
                else f"`{names.truncated} and not {names.terminated}` (the key held `not done` at the time limit)"
            )
            self.report(node, "GM303", f'Gymnasium no longer sets "{TIME_LIMIT_KEY}": replaced by {equivalent}; review')
            return
        if self.context.profile.imports_sb3:
            return  # most likely SB3 VecEnv infos, which still carry the key
        self.report(
            node,
            "GM303",
            f'Gymnasium\'s TimeLimit no longer sets "{TIME_LIMIT_KEY}", so this read is always false: '
            "use `truncated and not terminated` from the step that produced this info",
            FixKind.FLAG,
        )

    def _is_store(self, node: cst.BaseExpression) -> bool:
        """Is ``node`` assigned to or deleted (``info[key] = ...``, ``del info[key]``)?"""
        child: cst.CSTNode = node
        parent = self.flow.parent(child)
        while isinstance(parent, (cst.Element, cst.Tuple, cst.List, cst.StarredElement)):
            child, parent = parent, self.flow.parent(parent)
        if isinstance(parent, cst.AssignTarget):
            return True
        if isinstance(parent, (cst.AugAssign, cst.AnnAssign)) and parent.target is child:
            return True
        return isinstance(parent, cst.Del)

    # -- GM304 ---------------------------------------------------------------------------

    def _plan_result_name(self, assign: cst.Assign, result: cst.Name, receiver: cst.BaseExpression) -> None:
        decision, vector = self._decision(receiver, legacy_shape=False)
        if decision.action is Action.LEAVE:
            return
        reads = [read for read in self.flow.reads(result) if self.flow.observes(read, assign, result)]
        if not self.context.profile.imports_gym or any(
            (_constant_index(read, self.flow.parent) or 0) in (4, -5) for read in reads
        ):
            return  # Gymnasium code, or indices that already count five values: nothing to move
        if decision.action is Action.REPORT:
            self.report(assign, "GM304", f"{decision.reason}; if it is a Gym env, its step returns five values", FixKind.FLAG)
            return
        for read in reads:
            index = _constant_index(read, self.flow.parent)
            subscript = self.flow.parent(read)
            dominated = self.flow.dominates(assign, read, result)
            if index in (0, 1, -1) and dominated:
                continue  # observation, reward and info keep their places
            if index == 3 and dominated:
                self._replacements[subscript] = _with_index(subscript, 4)  # type: ignore[arg-type]
                exact = FixKind.AUTO if decision.action is Action.REWRITE else FixKind.ASSIST
                self.report(subscript, "GM304", f"`{result.value}[3]` (info) is `{result.value}[4]` now", exact)
            elif index == 2 and dominated and not (vector or _looks_vectorised(receiver, result)):
                either = cst.BooleanOperation(
                    left=subscript.with_changes(lpar=(), rpar=()),  # type: ignore[union-attr]
                    operator=cst.Or(),
                    right=_with_index(subscript, 3).with_changes(lpar=(), rpar=()),  # type: ignore[arg-type]
                )
                self._replacements[subscript] = _parenthesize_if_needed(either, subscript, self.flow.parent)  # type: ignore[arg-type]
                self.report(
                    subscript,
                    "GM304",
                    f"`{result.value}[2]` (done) is now `{result.value}[2] or {result.value}[3]`; "
                    f"if it feeds bootstrapping, use `{result.value}[2]` (terminated) alone",
                )
            else:
                self.report(
                    read,
                    "GM304",
                    f"`{result.value}` holds a five-value step result now (2 terminated, 3 truncated, 4 info): "
                    "update this use by hand",
                    FixKind.FLAG,
                )

    # -- applying the plan (on the output tree) ------------------------------------------

    def leave_Name(self, original_node: cst.Name, updated_node: cst.Name) -> cst.BaseExpression:
        return self._replacements.get(original_node, updated_node)

    def leave_Subscript(self, original_node: cst.Subscript, updated_node: cst.Subscript) -> cst.BaseExpression:
        return self._replacements.get(original_node, updated_node)

    def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.BaseExpression:
        return self._replacements.get(original_node, updated_node)

    def leave_Comparison(self, original_node: cst.Comparison, updated_node: cst.Comparison) -> cst.BaseExpression:
        return self._replacements.get(original_node, updated_node)

    def leave_Assign(
        self, original_node: cst.Assign, updated_node: cst.Assign
    ) -> cst.Assign | cst.FlattenSentinel[cst.BaseSmallStatement]:
        plan = self._unpacks.get(original_node)
        if plan is None:
            return updated_node
        target = updated_node.targets[0]
        updated_node = updated_node.with_changes(targets=[target.with_changes(target=_split_done(target.target, plan.names))])
        if plan.alias and plan.inline:
            alias = _alias(plan).with_changes(semicolon=updated_node.semicolon)
            first = updated_node.with_changes(
                semicolon=cst.Semicolon(whitespace_before=cst.SimpleWhitespace(""), whitespace_after=cst.SimpleWhitespace(" "))
            )
            return cst.FlattenSentinel([first, alias])
        return updated_node

    def leave_SimpleStatementLine(
        self, original_node: cst.SimpleStatementLine, updated_node: cst.SimpleStatementLine
    ) -> cst.SimpleStatementLine | cst.FlattenSentinel[cst.SimpleStatementLine]:
        if len(original_node.body) != 1:
            return updated_node
        plan = self._unpacks.get(original_node.body[0])  # type: ignore[call-overload]
        if plan is None or not plan.alias or plan.inline:
            return updated_node
        return cst.FlattenSentinel([updated_node, cst.SimpleStatementLine(body=[_alias(plan)])])


# -- helpers --------------------------------------------------------------------------------

_UNTRACED = object()  # a ``TimeLimit.truncated`` read whose info dict comes from no known step
ParentOf = Callable[[cst.CSTNode], "cst.CSTNode | None"]


class _StepAndKeyFinder(cst.CSTVisitor):
    """``x.step(...)`` calls and reads of the ``TimeLimit.truncated`` info key, in order."""

    def __init__(self) -> None:
        self.steps: list[cst.Call] = []
        self.time_limit_reads: list[cst.BaseExpression] = []

    def visit_Call(self, node: cst.Call) -> None:
        if isinstance(node.func, cst.Attribute) and node.func.attr.value == "step":
            self.steps.append(node)
        elif (
            isinstance(node.func, cst.Attribute)
            and node.func.attr.value == "get"
            and node.args
            and _is_time_limit_key(node.args[0].value)
        ):
            self.time_limit_reads.append(node)

    def visit_Subscript(self, node: cst.Subscript) -> None:
        if len(node.slice) == 1 and isinstance(node.slice[0].slice, cst.Index):
            if _is_time_limit_key(node.slice[0].slice.value):
                self.time_limit_reads.append(node)

    def visit_Comparison(self, node: cst.Comparison) -> None:
        if (
            _is_time_limit_key(node.left)
            and len(node.comparisons) == 1
            and isinstance(node.comparisons[0].operator, (cst.In, cst.NotIn))
        ):
            self.time_limit_reads.append(node)


class _OuterDeclarations(cst.CSTVisitor):
    """Names a function declares ``global`` or ``nonlocal`` (not in nested functions)."""

    def __init__(self) -> None:
        self.names: set[str] = set()

    def visit_FunctionDef(self, node: cst.FunctionDef) -> bool:
        return False

    def visit_Global(self, node: cst.Global) -> None:
        self.names.update(item.name.value for item in node.names)

    def visit_Nonlocal(self, node: cst.Nonlocal) -> None:
        self.names.update(item.name.value for item in node.names)


def _numpy_name(module: cst.Module) -> str | None:
    """The name a module-level ``import numpy [as x]`` binds, if there is one."""
    for statement in module.body:
        if isinstance(statement, cst.SimpleStatementLine):
            for small in statement.body:
                if isinstance(small, cst.Import):
                    for alias in small.names:
                        if get_full_name_for_node(alias.name) == "numpy":
                            return alias.asname.name.value if alias.asname else "numpy"  # type: ignore[union-attr]
    return None


def _is_time_limit_key(node: cst.BaseExpression) -> bool:
    return isinstance(node, cst.SimpleString) and node.evaluated_value == TIME_LIMIT_KEY


def _time_limit_base(node: cst.BaseExpression) -> cst.BaseExpression:
    """The dict a ``TimeLimit.truncated`` read looks in."""
    if isinstance(node, cst.Subscript):
        return node.value
    if isinstance(node, cst.Call):
        return node.func.value  # type: ignore[attr-defined]
    return node.comparisons[0].comparator  # type: ignore[attr-defined]


def _truncation_expression(
    node: cst.BaseExpression, names: StepNames, parent: cst.CSTNode | None
) -> cst.BaseExpression:
    """The Gymnasium spelling of a legacy ``TimeLimit.truncated`` read (same parentheses)."""
    if isinstance(node, cst.Comparison):
        # The key was present exactly when the time limit was reached.
        negated = isinstance(node.comparisons[0].operator, cst.NotIn)
        expression: cst.BaseExpression = cst.Name(names.truncated)
        if negated:
            expression = cst.UnaryOperation(operator=cst.Not(), expression=expression)
        return expression.with_changes(lpar=node.lpar, rpar=node.rpar)
    expression = cst.BooleanOperation(
        left=cst.Name(names.truncated),
        operator=cst.And(),
        right=cst.UnaryOperation(operator=cst.Not(), expression=cst.Name(names.terminated)),
    )
    if node.lpar:
        return expression.with_changes(lpar=node.lpar, rpar=node.rpar)
    return _parenthesize_if_needed(expression, node, lambda n: parent if n is node else None)


def _parenthesize_if_needed(
    expression: cst.BooleanOperation, original: cst.BaseExpression, parent_of: ParentOf
) -> cst.BaseExpression:
    """Keep precedence: bare only where a whole expression stands on its own."""
    parent = parent_of(original)
    bare = (
        isinstance(parent, (cst.If, cst.While, cst.Assert)) and parent.test is original
    ) or (
        isinstance(parent, (cst.Assign, cst.Return, cst.Expr, cst.Arg, cst.AnnAssign, cst.Element))
        and parent.value is original
    )
    if bare:
        return expression
    return expression.with_changes(lpar=[cst.LeftParen()], rpar=[cst.RightParen()])


def _constant_index(read: cst.Name, parent_of: ParentOf) -> int | None:
    """``res[2]`` read (not stored) with a literal integer index -> 2; otherwise None."""
    subscript = parent_of(read)
    if not isinstance(subscript, cst.Subscript) or subscript.value is not read or len(subscript.slice) != 1:
        return None
    holder = parent_of(subscript)
    if (isinstance(holder, (cst.AssignTarget, cst.AugAssign, cst.Del)) and holder.target is subscript) or (
        isinstance(holder, cst.Element) and isinstance(parent_of(parent_of(holder)), cst.AssignTarget)
    ):
        return None  # a store into the result
    index = subscript.slice[0].slice
    if not isinstance(index, cst.Index):
        return None
    value = index.value
    sign = 1
    if isinstance(value, cst.UnaryOperation) and isinstance(value.operator, cst.Minus):
        sign, value = -1, value.expression
    if isinstance(value, cst.Integer) and not value.lpar:
        return sign * int(value.value)
    return None


def _with_index(subscript: cst.Subscript, index: int) -> cst.Subscript:
    element = subscript.slice[0]
    return subscript.with_changes(
        slice=[element.with_changes(slice=element.slice.with_changes(value=cst.Integer(str(index))))]  # type: ignore[union-attr]
    )


def _four_targets(assign: cst.Assign) -> bool:
    if len(assign.targets) != 1:
        return False
    target = assign.targets[0].target
    return isinstance(target, (cst.Tuple, cst.List)) and len(target.elements) == 4 and not _starred(target)


def _binds(assign: cst.Assign, name: str) -> bool:
    return any(name in _bound_names(target.target) for target in assign.targets)


def _starred(target: cst.Tuple | cst.List) -> bool:
    return any(isinstance(el, cst.StarredElement) for el in target.elements)


def _split_done(target: cst.BaseAssignTargetExpression, names: StepNames) -> cst.BaseAssignTargetExpression:
    """``obs, r, done, info`` -> ``obs, r, terminated, truncated, info`` (user spacing kept)."""
    elements = list(target.elements)  # type: ignore[attr-defined]
    done = elements[2]
    discard = isinstance(done.value, cst.Name) and done.value.value == "_"
    first = cst.Name("_" if discard else names.terminated)
    second = cst.Name("_" if discard else names.truncated)
    comma = done.comma if isinstance(done.comma, cst.Comma) else cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))
    elements[2:3] = [cst.Element(value=first, comma=comma), cst.Element(value=second, comma=comma)]
    return target.with_changes(elements=elements)


def _alias(plan: _Unpack) -> cst.Assign:
    return cst.Assign(targets=[cst.AssignTarget(target=plan.done_target.deep_clone())], value=plan.names.joined())


def _shares_line(assign: cst.Assign, flow: Flow) -> bool:
    line = flow.parent(assign)
    return not (isinstance(line, cst.SimpleStatementLine) and len(line.body) == 1)


def _fresh(base: str, taken: set[str], compatible: set[str]) -> str:
    if base not in taken or base in compatible:
        return base
    candidate, number = base + "_", 2
    while candidate in taken:
        candidate, number = f"{base}_{number}", number + 1
    return candidate


def _step_bound_names(scope_node: cst.CSTNode) -> set[str]:
    """Names that only ever hold step flags in ``scope_node`` (safe to bind again)."""
    collector = _FlagNameCollector()
    scope_node.visit(collector)
    return collector.flags - collector.other_bindings


class _FlagNameCollector(cst.CSTVisitor):
    def __init__(self) -> None:
        self.flags: set[str] = set()
        self.other_bindings: set[str] = set()

    def visit_Assign(self, node: cst.Assign) -> None:
        value = node.value
        is_step = isinstance(value, cst.Call) and isinstance(value.func, cst.Attribute) and value.func.attr.value == "step"
        for target in node.targets:
            t = target.target
            if is_step and isinstance(t, (cst.Tuple, cst.List)) and len(t.elements) == 5:
                self.flags.update(el.value.value for el in t.elements[2:4] if isinstance(el.value, cst.Name))
                continue
            for name in _bound_names(t):
                self.other_bindings.add(name)

    def visit_Param(self, node: cst.Param) -> None:
        self.other_bindings.add(node.name.value)

    def visit_For(self, node: cst.For) -> None:
        self.other_bindings.update(_bound_names(node.target))

    def visit_AugAssign(self, node: cst.AugAssign) -> None:
        self.other_bindings.update(_bound_names(node.target))

    def visit_AsName(self, node: cst.AsName) -> None:
        self.other_bindings.update(_bound_names(node.name))  # type: ignore[arg-type]

    def visit_NamedExpr(self, node: cst.NamedExpr) -> None:
        self.other_bindings.update(_bound_names(node.target))


def _bound_names(target: cst.CSTNode) -> set[str]:
    if isinstance(target, cst.Name):
        return {target.value}
    if isinstance(target, (cst.Tuple, cst.List)):
        return {n for el in target.elements for n in _bound_names(el.value)}
    if isinstance(target, cst.StarredElement):
        return _bound_names(target.value)
    return set()


def _looks_vectorised(receiver: cst.BaseExpression, done_target: cst.BaseExpression) -> bool:
    """An untraced ``envs.step`` or a ``dones`` target: single-env ``or`` would be wrong."""
    name = receiver_text(receiver).rsplit(".", 1)[-1].lower()
    plural = name.endswith(("envs", "environments"))
    return plural or (isinstance(done_target, cst.Name) and done_target.value.endswith("dones"))


def _returned_from_step_method(call: cst.Call, flow: Flow) -> bool:
    parent = flow.parent(call)
    if not isinstance(parent, cst.Return):
        return False
    function = next((a for a in flow.ancestors(call) if isinstance(a, (cst.FunctionDef, cst.Lambda))), None)
    return isinstance(function, cst.FunctionDef) and function.name.value == "step"
