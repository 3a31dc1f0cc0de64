"""PZ104, PZ105: parallel env call sites (and ``reset`` on AEC envs).

Since PettingZoo 1.21 a parallel ``step`` returns ``observations, rewards, terminations,
truncations, infos``; since 1.23 ``reset`` returns ``(observations, infos)`` and takes no
``return_info``. The dict of dones is kept where something still reads it whole
(``dones = {a: terminations[a] or truncations[a] for a in terminations}``); per-agent
reads read both dicts, and the documented loop test ``while not all(dones.values())``
becomes ``while penv.agents:`` (agents leave ``agents`` once they are done).
"""

from __future__ import annotations

import ast

from gymmigrate.edits.arguments import remove_args
from gymmigrate.edits.lazy import cst
from gymmigrate.facts.done_uses import DoneUse, classify_done_read
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import keyword
from gymmigrate.findings import FixKind
from gymmigrate.rules.pettingzoo.common import (
    AGENT,
    PZ104,
    PZ105,
    PettingZooFamily,
    either,
    tuple_target,
    values_call,
)

TERMINATIONS, TRUNCATIONS, INFOS = "terminations", "truncations", "infos"


class ParallelCalls(PettingZooFamily):
    RULES = (PZ104, PZ105)

    def decide(self) -> None:
        self.flow = Flow.of(self.facts)
        for call in self.facts.attribute_calls.get("step", ()):
            func = call.func
            if not isinstance(func, ast.Attribute):  # ``x.method(...)`` calls only
                continue
            receiver = func.value
            if self.multi_agent.kind(receiver) is EnvKind.PZ_PARALLEL:
                self._plan_step(call, receiver)
        for call in self.facts.attribute_calls.get("reset", ()):
            func = call.func
            if not isinstance(func, ast.Attribute):  # ``x.method(...)`` calls only
                continue
            receiver = func.value
            kind = self.multi_agent.kind(receiver)
            if kind is not None and not (isinstance(receiver, ast.Name) and self.receivers.is_self(receiver)):
                self._plan_reset(call, kind)

    # -- step ---------------------------------------------------------------------------

    def _plan_step(self, call: ast.Call, receiver: ast.expr) -> None:
        assign = self.facts.parent(call)
        target = tuple_target(assign, 4)
        if target is None or not isinstance(assign, ast.Assign):  # a target is only found on an Assign
            function = self.facts.enclosing_function(call)
            if function is not None and function.name == "step" and self.facts.enclosing_class(call) is not None:
                return  # ``res = self.env.step(a)`` in a wrapper's step: handed on whole, five dicts now
            if isinstance(assign, ast.Assign) and assign.value is call and tuple_target(assign, 5) is None:
                self.report(assign, "PZ104", "a parallel `step` returns five dicts since PettingZoo 1.21: unpack "
                            "`observations, rewards, terminations, truncations, infos`", FixKind.FLAG)
            return
        dones = target.elts[2]
        self.split_target(target, 2, TERMINATIONS, TRUNCATIONS)
        self.report(assign, "PZ104", "a parallel `step` returns terminations and truncations instead of dones")
        joined = f"{{{AGENT}: {TERMINATIONS}[{AGENT}] or {TRUNCATIONS}[{AGENT}] for {AGENT} in {TERMINATIONS}}}"
        if not isinstance(dones, ast.Name):
            self.plan.insert_after(assign, f"{self.facts.segment(dones)} = {joined}")
            return
        if dones.id == "_":
            return
        keep = False
        env = self.facts.segment(receiver)
        for read in self.flow.reads(dones):
            aggregate = values_call(read, self.facts)
            if aggregate is not None and aggregate[1] == "all":
                self._plan_all_done(aggregate[0], env)
                continue
            if not self.flow.dominates(assign, read, dones):
                keep = keep or self.flow.observes(read, assign, dones)
                continue
            parent = self.facts.parent(read)
            if _passed_on(read, parent, self.facts):
                # ``return obs, rewards, dones, infos`` in a wrapper's step: pass both dicts on.
                self.split_target(parent, 2, TERMINATIONS, TRUNCATIONS)  # type: ignore[arg-type]
                continue
            if isinstance(parent, ast.Subscript) and parent.value is read and isinstance(parent.ctx, ast.Load):
                index = self.facts.segment(parent.slice)
                if classify_done_read(read, self.facts) is DoneUse.DATA:
                    self.replace_text(parent, f"{TERMINATIONS}[{index}]")
                    self.report(parent, "PZ104", "a value read of `dones` now uses `terminations`: a truncated agent "
                                "still bootstraps from its next observation; review", FixKind.ASSIST)
                else:
                    self.replace_text(parent, either(parent, f"{TERMINATIONS}[{index}] or {TRUNCATIONS}[{index}]", self.facts))
                continue
            keep = True
        if keep:
            self.plan.insert_after(assign, f"{dones.id} = {joined}")

    def _passes_own_parameter(self, call: ast.Call, value: ast.AST) -> bool:
        function = self.facts.enclosing_function(call)
        return (
            isinstance(value, ast.Name)
            and value.id == "return_info"
            and function is not None
            and function.name == "reset"
            and any(a.arg == "return_info" for a in function.args.args)
        )

    def _plan_all_done(self, outer: ast.Call, env: str) -> None:
        negation = self.facts.parent(outer)
        if isinstance(negation, ast.UnaryOp) and isinstance(negation.op, ast.Not):
            self.replace_text(negation, f"{env}.agents")
        else:
            self.replace_text(outer, either(outer, f"not {env}.agents", self.facts))
        self.report(outer, "PZ104", f"loop on `{env}.agents`: agents leave it once terminated or truncated")

    # -- reset --------------------------------------------------------------------------

    def _plan_reset(self, call: ast.Call, kind: EnvKind) -> None:
        return_info = keyword(call, "return_info")
        parent = self.facts.parent(call)
        if return_info is not None and self._passes_own_parameter(call, return_info.value):
            # A wrapper's ``reset`` handing its ``return_info`` on: its own reset now always
            # returns the pair (class_reset.py), and so does the wrapped env's.
            self.changed()
            self.plan.replace(call, lambda node: remove_args(node, lambda arg: arg.keyword is not None and arg.keyword.value == "return_info"))
            self.report(call, "PZ105", "`return_info` was removed in PettingZoo 1.23")
            return
        if return_info is not None and _true(return_info.value) and not tuple_target(parent, 2) and not isinstance(parent, ast.Expr):
            # ``pair = penv.reset(return_info=True)`` is already the 1.23 pair, but the plain
            # ``pair = penv.reset()`` left behind would read as legacy code on a second run.
            self.report(call, "PZ105", "`return_info` was removed in PettingZoo 1.23 and `reset()` returns the pair: "
                        "drop the keyword by hand", FixKind.FLAG)
            return
        if return_info is not None:
            self.changed()
            self.plan.replace(call, lambda node: remove_args(node, lambda arg: arg.keyword is not None and arg.keyword.value == "return_info"))
            self.report(call, "PZ105", "`return_info` was removed in PettingZoo 1.23")
        if isinstance(parent, ast.Expr):
            return
        if kind is EnvKind.PZ_AEC:
            self.report(call, "PZ105", "an AEC `reset()` returns None: read observations with `last()` or `observe(agent)`",
                        FixKind.FLAG)
            return
        function = self.facts.enclosing_function(call)
        if isinstance(parent, ast.Return) and function is not None and function.name == "reset":
            return  # a wrapper's reset hands the pair on
        if tuple_target(parent, 2) is not None or isinstance(parent, ast.Subscript):
            return  # already ``observations, infos = penv.reset()`` or ``penv.reset()[0]``
        returned_info = return_info is not None and not (
            isinstance(return_info.value, ast.Constant) and not return_info.value.value
        )
        if returned_info:
            return  # ``reset(return_info=True)`` already gave the pair
        if return_info is not None and not isinstance(parent, ast.Assign):
            return  # the keyword is dropped; where the pair goes is reported below only for plain uses
        if isinstance(parent, ast.Assign) and len(parent.targets) == 1 and isinstance(parent.targets[0], ast.Name):
            name = parent.targets[0].id
            self.replace_text(parent.targets[0], f"{name}, {INFOS}")
            self.report(parent, "PZ105", "a parallel `reset` returns `(observations, infos)` since PettingZoo 1.23")
            return
        self.changed()
        self.plan.replace(call, _first_of_pair)
        self.report(call, "PZ105", "a parallel `reset` returns `(observations, infos)`: the observations are `[0]`")


def _first_of_pair(node: cst.BaseExpression) -> cst.Subscript:
    return cst.Subscript(value=node, slice=[cst.SubscriptElement(slice=cst.Index(value=cst.Integer("0")))])


def _true(value: ast.AST) -> bool:
    return not (isinstance(value, ast.Constant) and not value.value)


def _passed_on(read: ast.Name, parent: ast.AST | None, facts) -> bool:
    """``read`` is the dones of a four-value ``return`` (a step that hands its env's result on)."""
    return (
        isinstance(parent, ast.Tuple)
        and len(parent.elts) == 4
        and parent.elts[2] is read
        and isinstance(facts.parent(parent), ast.Return)
    )
