"""PZ101-PZ103: the AEC loop (``for agent in env.agent_iter(): ... env.last() ...``).

Since PettingZoo 1.21 ``last()`` returns ``observation, reward, termination, truncation,
info``; a four-name unpack raises ``ValueError: too many values to unpack``. The old
``done`` is kept as ``done = termination or truncation`` where something still reads it
for loop control; ``None if done else ...`` (the canonical "a dead agent steps with
None") reads both flags directly, and value reads (``1 - done``, buffer writes) use
``termination`` and are listed for review: a truncated agent's return still bootstraps.
``env.dones`` reads on an env object become both dicts (``all(env.dones.values())``
becomes ``not env.agents``, the loop test PettingZoo documents).
"""

from __future__ import annotations

import ast

from gymmigrate.facts.done_uses import DoneUse, classify_done_read
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.findings import FixKind
from gymmigrate.rules.pettingzoo.common import (
    PZ101,
    PZ102,
    PZ103,
    PettingZooFamily,
    either,
    tuple_target,
    values_call,
)

TERMINATION, TRUNCATION = "termination", "truncation"


class AecLoop(PettingZooFamily):
    RULES = (PZ101, PZ102, PZ103)

    def decide(self) -> None:
        self.flow = Flow.of(self.facts)
        for call in self.facts.attribute_calls.get("last", ()):
            self._plan_last(call)
        for attr in self.facts.attributes.get("dones", ()):
            self._plan_env_dones(attr)

    # -- last() -------------------------------------------------------------------------

    def _plan_last(self, call: ast.Call) -> None:
        func = call.func
        if not isinstance(func, ast.Attribute):  # ``x.method(...)`` calls only
            return
        receiver = func.value
        assign = self.facts.parent(call)
        if self.multi_agent.kind(receiver) is not EnvKind.PZ_AEC:
            if self.multi_agent.iterated(receiver) and isinstance(assign, ast.Assign) and tuple_target(assign, 4) is not None:
                self.report(assign, "PZ101", f"`{self.facts.segment(receiver)}` is iterated with `agent_iter()` but "
                            "also holds another kind of env here: if this is the PettingZoo env, unpack "
                            "`observation, reward, termination, truncation, info`", FixKind.FLAG)
            return
        target = tuple_target(assign, 4)
        if target is None or not isinstance(assign, ast.Assign):  # a target is only found on an Assign
            if isinstance(assign, ast.Assign) and tuple_target(assign, 5) is None and assign.value is call:
                self.report(assign, "PZ101", "`last()` returns five values since PettingZoo 1.21: unpack "
                            "`observation, reward, termination, truncation, info`", FixKind.FLAG)
            return
        done = target.elts[2]
        if isinstance(done, ast.Name) and done.id == "_":
            self.split_target(target, 2, "_", "_")
        else:
            self.split_target(target, 2, TERMINATION, TRUNCATION)
            if isinstance(done, ast.Name):
                self._plan_done_reads(assign, done)
            else:
                self.plan.insert_after(assign, f"{self.facts.segment(done)} = {TERMINATION} or {TRUNCATION}")
        self.report(assign, "PZ101", "`last()` returns termination and truncation instead of one done flag")

    def _plan_done_reads(self, assign: ast.Assign, done: ast.Name) -> None:
        keep = False
        for read in self.flow.reads(done):
            if not self.flow.dominates(assign, read, done):
                keep = keep or self.flow.observes(read, assign, done)
                continue
            parent = self.facts.parent(read)
            if isinstance(parent, ast.IfExp) and parent.test is read and _is_none(parent.body):
                self.replace_text(read, f"{TERMINATION} or {TRUNCATION}")
                self.report(read, "PZ102", "a dead agent (terminated or truncated) must step with `None`")
            elif classify_done_read(read, self.facts) is DoneUse.DATA:
                self.replace_text(read, TERMINATION)
                self.report(read, "PZ101", "a value read of `done` now uses `termination`: a truncated agent "
                            "still bootstraps from its next observation; review", FixKind.ASSIST)
            else:
                keep = True
        if keep:
            self.plan.insert_after(assign, f"{done.id} = {TERMINATION} or {TRUNCATION}")

    # -- env.dones on an env object -----------------------------------------------------

    def _plan_env_dones(self, attr: ast.Attribute) -> None:
        owner = attr.value
        if isinstance(owner, ast.Name) and self.receivers.is_self(owner):
            return  # inside the env class: env_classes.py
        kind = self.multi_agent.kind(owner)
        if kind is None:
            return
        env = self.facts.segment(owner)
        parent = self.facts.parent(attr)
        if isinstance(attr.ctx, ast.Load) and isinstance(parent, ast.Subscript) and parent.value is attr:
            if isinstance(parent.ctx, ast.Load):
                index = self.facts.segment(parent.slice)
                if _value_use(parent, self.facts):
                    self.replace_text(parent, f"{env}.terminations[{index}]")
                    self.report(parent, "PZ103", "a value read of `dones` now uses `terminations`: a truncated agent "
                                "still bootstraps from its next observation; review", FixKind.ASSIST)
                    return
                self.replace_text(parent, either(parent, f"{env}.terminations[{index}] or {env}.truncations[{index}]", self.facts))
                self.report(parent, "PZ103", "`dones` is split into `terminations` and `truncations` since PettingZoo 1.21")
                return
        aggregate = values_call(attr, self.facts)
        if aggregate is not None and aggregate[1] == "all":
            outer = aggregate[0]
            negation = self.facts.parent(outer)
            if isinstance(negation, ast.UnaryOp) and isinstance(negation.op, ast.Not):
                self.replace_text(negation, f"{env}.agents")
            else:
                self.replace_text(outer, either(outer, f"not {env}.agents", self.facts))
            self.report(outer, "PZ103", "every agent is done exactly when `agents` is empty (PettingZoo 1.21 removed `dones`)")
            return
        self.report(attr, "PZ103", f"`{env}.dones` was removed in PettingZoo 1.21: read `terminations` "
                    "and/or `truncations` by what this use means", FixKind.FLAG)


def _is_none(node: ast.AST) -> bool:
    return isinstance(node, ast.Constant) and node.value is None


def _value_use(read: ast.expr, facts) -> bool:
    """``1 - env.dones[a]``, a buffer write: the flag feeds a value (see facts.done_uses).
    A plain assignment (``over = env.dones[a]``) is not judged: it keeps both flags."""
    if isinstance(facts.parent(read), ast.Assign):
        return False
    return classify_done_read(read, facts) is DoneUse.DATA  # type: ignore[arg-type]
