"""GM303: reads of the legacy ``info["TimeLimit.truncated"]`` key.

Gymnasium's ``TimeLimit`` no longer sets the key, so ``info["TimeLimit.truncated"]``
raises and ``info.get("TimeLimit.truncated", False)`` is silently always false (``info.pop`` likewise). Where
the ``info`` comes from a step this family rewrote, the read becomes ``truncated and not
terminated``, the exact legacy meaning (legacy ``TimeLimit`` stored ``not done`` there,
and only when the limit was hit); ``"TimeLimit.truncated" in info`` becomes
``truncated``. Other reads are reported; stores of the key (a legacy time-limit
wrapper) are reported too. Stable-Baselines3 VecEnv infos still carry the key (SB104)
and are left alone.
"""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import Scope, walk
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.step_done.common import (
    TIME_LIMIT_KEY,
    StepFamilyBase,
    StepNames,
    stands_alone,
)

_UNTRACED = object()  # a read whose info dict comes from no known step


class _UnsureStep:
    """The info comes from a step left for review: its receiver may be an SB3 VecEnv."""

    def __init__(self, receiver: str) -> None:
        self.receiver = receiver


_DISCARDED = StepNames("_", "_", vector=False)  # a step whose done target was ``_``


def time_limit_reads(facts_strings: list[ast.Constant], parent_of) -> list[ast.expr]:
    """``info[KEY]``, ``info.get(KEY, ...)``, ``info.pop(KEY, ...)`` and ``KEY in info``
    nodes, in source order. A pop reads the key as a get does (removing a key Gymnasium never
    writes changes nothing), and ``info.pop(KEY)`` raises where it is now absent."""
    found: list[ast.expr] = []
    for string in facts_strings:
        if string.value != TIME_LIMIT_KEY:
            continue
        parent = parent_of(string)
        if isinstance(parent, ast.Subscript) and parent.slice is string:
            found.append(parent)
        elif (
            isinstance(parent, ast.Call)
            and parent.args
            and parent.args[0] is string
            and isinstance(parent.func, ast.Attribute)
            and parent.func.attr in ("get", "pop")
        ):
            found.append(parent)
        elif (
            isinstance(parent, ast.Compare)
            and parent.left is string
            and len(parent.ops) == 1
            and isinstance(parent.ops[0], (ast.In, ast.NotIn))
        ):
            found.append(parent)
    return found


class TimeLimitRules(StepFamilyBase):
    """GM303 (mixed into the family)."""

    def plan_time_limit_read(self, node: ast.expr) -> None:
        if isinstance(node, ast.Subscript) and not isinstance(node.ctx, ast.Load):
            # A legacy TimeLimit-style wrapper *writing* the key: a store cannot become a
            # `truncated and not terminated` expression, and the wrapper must now report
            # the limit through the truncated flag it returns.
            classdef = self.facts.enclosing_class(node)
            if classdef is not None and self._own_info_publisher(classdef):
                # A class that is no Gym env (an adapter to the project's own env API) filling
                # the key into the info it hands its own callers: that is the project's
                # contract, which the migration does not change.
                self.report(
                    node,
                    "GM303",
                    f'`{classdef.name}` is no Gym env: the "{TIME_LIMIT_KEY}" key it sets is read by its own '
                    "callers, so it is kept; Gymnasium code reads the step's `truncated` flag instead",
                    FixKind.FLAG,
                    tier=Tier.NOTE,
                )
                return
            self.report(
                node,
                "GM303",
                f'writes the legacy "{TIME_LIMIT_KEY}" info key, which Gymnasium code no longer reads: '
                "return the time limit as the step's `truncated` flag instead",
                FixKind.FLAG,
            )
            return
        if isinstance(node, ast.Call) and node.func.attr == "pop" and isinstance(self.facts.parent(node), ast.Expr):  # type: ignore[attr-defined]
            # ``info.pop(KEY, None)`` alone: it only drops a key Gymnasium never writes.
            if len(node.args) < 2 and not node.keywords:
                self.report(
                    node,
                    "GM303",
                    f'Gymnasium never sets "{TIME_LIMIT_KEY}", so this pop without a default raises KeyError: '
                    "remove it (the step's `truncated` flag tells the time limit)",
                    FixKind.FLAG,
                )
            return
        base = _time_limit_base(node)
        names = self._info_step(base) if isinstance(base, ast.Name) else _UNTRACED
        if names is None:
            return  # SB3 VecEnv infos keep the key (SB104)
        if isinstance(names, _UnsureStep):
            # The step is left for review (its receiver may be no Gym env): an SB3 VecEnv
            # still sets the key, so "always false" would be a guess. The read is told only
            # in the terms of that question.
            self.report(
                node,
                "GM303",
                f'if `{names.receiver}` is a Gym env, its TimeLimit no longer sets "{TIME_LIMIT_KEY}" and this read '
                "is always false (use `truncated and not terminated` from its step); an SB3 VecEnv still sets the key: "
                "then keep it",
                FixKind.FLAG,
            )
            return
        if isinstance(names, StepNames) and not names.vector:
            self._replace_read(node, names)
            default = _truthy_default(node)
            equivalent = (
                f"`{names.truncated}` (the key was present exactly when the time limit was hit)"
                if isinstance(node, ast.Compare)
                else f"`not {names.terminated}` when `{names.truncated}` (the key held `not done` at the time limit), "
                f"else the default `{self.facts.segment(default)}` as before"
                if default is not None
                else f"`{names.truncated} and not {names.terminated}` (the key held `not done` at the time limit)"
            )
            # The step that made this info certainly gave the flags read instead: the
            # replacement is the legacy value itself, nothing is left to decide.
            self.report(node, "GM303", f'Gymnasium no longer sets "{TIME_LIMIT_KEY}": replaced by {equivalent}', tier=Tier.NOTE)
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

    def _own_info_publisher(self, classdef: ast.ClassDef) -> bool:
        """The class derives from bases that are none of Gym's (through the module's classes)
        and is not a wrapper the run proves: its step's info goes to the project's callers."""
        if not classdef.bases or self.receivers.is_gym_wrapper_class(classdef):
            return False
        kind = self.receivers.class_kind(classdef)
        if kind is EnvKind.NOT_ENV:
            return True
        # unknown: only when every base is the run's own code (a library base may be Gym's)
        project = self.receivers.project
        return kind is EnvKind.UNKNOWN and all(
            self.receivers.local_class(base) is not None
            or any(q.startswith(".") or (project is not None and project.defines(q)) for q in self.facts.qualified_names(base))
            for base in classdef.bases
        )

    def _info_step(self, base: ast.Name) -> object:
        """The rewritten step whose ``info`` target certainly reaches ``base`` (StepNames),
        None for the infos of an SB3 VecEnv step, else ``_UNTRACED``."""
        binding = self.flow.last_binding_of(base)
        if isinstance(binding, ast.Name):
            holder = self.facts.parent(binding)
            step = self.facts.parent(holder) if holder is not None else None
            if isinstance(step, ast.Assign) and step in self.info_steps:
                target = step.targets[0]  # the tuple ``unpack.py`` split
                if (
                    isinstance(target, (ast.Tuple, ast.List))
                    and target.elts[3] is binding
                    and self.flow.dominates(step, base, binding)
                ):
                    return self.info_steps[step]
        scope, _ = self.facts.resolve(base.id, self.facts.scope_of(base))
        if scope is not None and (id(scope), base.id) in self.guarded_infos:
            return None
        if scope is not None and (id(scope), base.id) in self.unsure_infos:
            return _UnsureStep(self.unsure_infos[(id(scope), base.id)])
        infos = self._iterated_infos(base)
        if infos is not None:
            # ``for info in infos`` over a vector step's infos: the list's step decides.
            outer, _ = self.facts.resolve(infos.id, self.facts.scope_of(infos))
            if outer is not None and (id(outer), infos.id) in self.guarded_infos:
                return None
            if outer is not None and (id(outer), infos.id) in self.unsure_infos:
                return _UnsureStep(self.unsure_infos[(id(outer), infos.id)])
        if scope is not None:
            names = self._only_step_infos(scope, base)
            if names is not None:
                return names
        return _UNTRACED

    def _iterated_infos(self, base: ast.Name) -> ast.Name | None:
        """The list ``base`` iterates over, when the read sits in a ``for`` loop or a
        comprehension whose target is ``base`` itself and whose iterable is a plain name."""
        for ancestor in self.facts.ancestors(base):
            generators: list[ast.comprehension | ast.For | ast.AsyncFor] = []
            if isinstance(ancestor, (ast.ListComp, ast.SetComp, ast.GeneratorExp, ast.DictComp)):
                generators = list(ancestor.generators)
            elif isinstance(ancestor, (ast.For, ast.AsyncFor)) and any(base is n for s in ancestor.body for n in walk(s)):
                generators = [ancestor]
            for generator in generators:
                if isinstance(generator.target, ast.Name) and generator.target.id == base.id:
                    return generator.iter if isinstance(generator.iter, ast.Name) else None
            if isinstance(ancestor, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)):
                return None
        return None

    def _only_step_infos(self, scope: Scope, base: ast.Name) -> StepNames | None:
        """The flags of the steps that alone bind ``base``'s info, when the read cannot
        see an info and flags from two different steps.

        After ``while not done: obs, r, done, info = env.step(a)`` no statement dominates
        the read, but if every binding of ``info`` in the frame is the info target of a
        rewritten step, the flag names are new to the frame, and every rewritten step that
        binds those flags also binds this ``info``, then ``info`` and the flags were always
        assigned together: the read and ``truncated and not terminated`` see the same step.
        """
        if not self.flow.same_frame(base, scope):
            return None
        by_scope = self._unpacks_by_scope()
        steps = by_scope.get(id(scope), [])
        infos = {id(a.targets[0].elts[3]) for a, _ in steps}  # type: ignore[attr-defined]
        bindings = scope.bindings.get(base.id, [])
        if not bindings or any(id(b) not in infos for b in bindings):
            return None
        names = next(n for a, n in steps if any(a.targets[0].elts[3] is b for b in bindings))  # type: ignore[attr-defined]
        if names is _DISCARDED or names.vector or scope.bindings.get(names.terminated) or scope.bindings.get(names.truncated):
            return None
        for assign, other in steps:
            shares = {other.terminated, other.truncated} & {names.terminated, names.truncated}
            info = assign.targets[0].elts[3]  # type: ignore[attr-defined]
            if shares and not (isinstance(info, ast.Name) and info.id == base.id and other == names):
                return None
        return names

    def _unpacks_by_scope(self) -> dict[int, list[tuple[ast.Assign, StepNames]]]:
        """Every step unpack this family rewrites, by the scope it binds in (built once)."""
        def build() -> dict[int, list[tuple[ast.Assign, StepNames]]]:
            found: dict[int, list[tuple[ast.Assign, StepNames]]] = {}
            for assign, unpack in self.notes.step_unpacks.items():
                if unpack.discarded:  # ``_`` took both flags: no names to read
                    found.setdefault(id(self.facts.scope_of(assign)), []).append((assign, _DISCARDED))
                else:
                    found.setdefault(id(self.facts.scope_of(assign)), []).append((assign, unpack.names))
            return found

        return self.facts.memo(("time-limit-unpacks", id(self.plan)), build)

    def _replace_read(self, node: ast.expr, names: StepNames) -> None:
        if isinstance(node, ast.Compare):
            # The key was present exactly when the time limit was reached.
            negated = isinstance(node.ops[0], ast.NotIn)

            def membership(cst_node: cst.Comparison) -> cst.BaseExpression:
                expression: cst.BaseExpression = cst.Name(names.truncated)
                if negated:
                    expression = cst.UnaryOperation(operator=cst.Not(), expression=expression)
                return expression.with_changes(lpar=cst_node.lpar, rpar=cst_node.rpar)

            self.plan.replace(node, membership)
            return
        bare = stands_alone(node, self.facts.parent(node))
        default = _truthy_default(node)
        if default is not None:
            # ``info.get(KEY, True)``: the key held ``not done`` when the time limit was hit
            # and was absent otherwise, when the default was the value (a project's own time
            # limit filling the key in): both cases kept.
            text = f"(not {names.terminated}) if {names.truncated} else {self.facts.segment(default)}"

            def conditional(cst_node: cst.BaseExpression) -> cst.BaseExpression:
                expression = cst.parse_expression(text)
                if cst_node.lpar:
                    return expression.with_changes(lpar=cst_node.lpar, rpar=cst_node.rpar)
                return expression if bare else expression.with_changes(lpar=[cst.LeftParen()], rpar=[cst.RightParen()])

            self.plan.replace(node, conditional)
            return

        def lookup(cst_node: cst.BaseExpression) -> cst.BaseExpression:
            expression = cst.BooleanOperation(
                left=cst.Name(names.truncated),
                operator=cst.And(),
                right=cst.UnaryOperation(operator=cst.Not(), expression=cst.Name(names.terminated)),
            )
            if cst_node.lpar:
                return expression.with_changes(lpar=cst_node.lpar, rpar=cst_node.rpar)
            if bare:
                return expression
            return expression.with_changes(lpar=[cst.LeftParen()], rpar=[cst.RightParen()])

        self.plan.replace(node, lookup)


def _truthy_default(node: ast.expr) -> ast.expr | None:
    """The default of ``info.get(KEY, d)`` / ``info.pop(KEY, d)`` unless it is a falsy
    constant (``None``, ``False``, ``0``), for which ``truncated and not terminated`` is
    already the legacy value."""
    if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)):
        return None
    default = node.args[1] if len(node.args) > 1 else next((k.value for k in node.keywords if k.arg == "default"), None)
    if default is None or (isinstance(default, ast.Constant) and not default.value):
        return None
    return default


def _time_limit_base(node: ast.expr) -> ast.expr:
    """The dict a ``TimeLimit.truncated`` read looks in."""
    if isinstance(node, ast.Subscript):
        return node.value
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
        return node.func.value
    return node.comparators[0]  # type: ignore[attr-defined]
