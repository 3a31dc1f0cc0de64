"""The step family: finds every ``x.step(...)`` call and ``TimeLimit.truncated`` read and
hands each to its rule (GM301-GM304, GM703).

Each call is classified once (``Receivers``); Stable-Baselines3 VecEnvs keep the
four-value step and their ``TimeLimit.truncated`` key (SB102-SB104), and objects that
are not envs (optimisers, schedulers, agents) are left alone, unless four names are
unpacked from their ``step`` in a Gym file, which is reported.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import FUNCTIONS, walk
from gymmigrate.facts.reset_contract import extra_params, own_reset
from gymmigrate.facts.reset_contract import join as join_contract
from gymmigrate.facts.reset_contract import sites as reset_sites
from gymmigrate.facts.step_calls import extra_actions, foreign_step
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext
from gymmigrate.rules.step_done.common import RULES, TIME_LIMIT_KEY, sole_step_return
from gymmigrate.rules.step_done.results import ResultRules
from gymmigrate.rules.step_done.time_limit import TimeLimitRules, time_limit_reads
from gymmigrate.rules.step_done.unpack import UnpackRules


class StepDone(UnpackRules, TimeLimitRules, ResultRules):
    RULES = RULES

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        if TIME_LIMIT_KEY in facts.text:
            return True
        # Steps already unpacked into five names are migrated: nothing to do for them.
        # ``def reset``: a step callable of the run's reset contract called in an env's reset
        # (an env module: it says ``step`` somewhere, the family's word)
        return ("def reset" in facts.text and "step" in facts.text) or any(
            not _five_targets(facts.parent(call), call) for call in facts.attribute_calls.get("step", ())
        )

    def decide(self) -> None:
        facts = self.facts
        self.flow = Flow.of(facts)
        self.numpy_name = _numpy_name(facts.tree)
        self.info_steps = {}
        self.guarded_infos = set()
        self.unsure_infos = {}
        self.done_steps = {}
        self.result_steps = {}
        self.reported_reads = set()
        self.callee_questions = {}
        self.rollout_stores = {}
        self.zero_tail_functions = set()
        steps = facts.attribute_calls.get("step", [])
        self.forwarded_unpacks = {}
        self.step_callables = set()
        for call in steps:
            parent = facts.parent(call)
            if isinstance(parent, ast.Assign) and parent.value is call and len(parent.targets) == 1:
                unpack = self._forwarded_unpack(parent, parent.targets[0])
                if unpack is not None:
                    self.forwarded_unpacks[id(parent)] = unpack
        self.legacy_unpacks = {
            parent for parent in (facts.parent(call) for call in steps) if isinstance(parent, ast.Assign) and _four_targets(parent)
        } | set(self.forwarded_unpacks.values())
        for call in steps:
            self._plan_step(call)
        self._plan_step_callables()
        self._plan_pass_through_methods()
        self.finish_done_reads()
        self.finish_results()
        if TIME_LIMIT_KEY in facts.text:
            for node in time_limit_reads(facts.strings, facts.parent):
                self.plan_time_limit_read(node)

    def _plan_step(self, call: ast.Call) -> None:
        func = call.func
        if not isinstance(func, ast.Attribute):  # ``x.method(...)`` calls only
            return
        receiver = func.value
        if not call.args and not call.keywords and not self.receivers.kind_of(receiver).is_gym:
            # Gym's step takes the action, legacy or new: ``status = sim.step()`` on an object
            # not proven a Gym env (a simulator's handle advancing a frame) is no env step,
            # so there is nothing to migrate and nothing to ask
            return
        parent = self.facts.parent(call)
        if foreign_step(call, self.receivers, self.facts):
            # never rewritten; asked about only where the receiver is otherwise a Gym env
            # (a model's ``step(obs, states, dones)`` is no env at all)
            if self.receivers.kind_of(receiver).is_gym and not (isinstance(parent, ast.Expr) or _five_targets(parent, call)):
                self.report(
                    call,
                    "GM301",
                    f"`{self.facts.segment(func)}(...)` is called with {1 + extra_actions(call, self.facts)} actions: Gym's step "
                    "takes one, so this is the env's own step API (a package of its own, such as a second player's "
                    "action), not Gym's; its result is left as it is. Through Shimmy's compatibility env step() takes "
                    "one action: port this env by hand, or keep its module on gym",
                    FixKind.FLAG,
                )
            return
        if isinstance(parent, ast.Assign) and parent.value is call and len(parent.targets) == 1:
            target = parent.targets[0]
            if isinstance(target, (ast.Tuple, ast.List)) and not _starred(target):
                if len(target.elts) == 5:
                    return  # already migrated
                if len(target.elts) == 4:
                    self.plan_unpack(parent, target, receiver)
                    return
            if isinstance(target, ast.Name):
                unpack = self.forwarded_unpacks.get(id(parent))
                if unpack is not None:
                    # ``res = env.step(a)`` then ``obs, r, done, info = res``: one unpack of
                    # this step, migrated as if written in one statement.
                    self.plan_unpack(unpack, unpack.targets[0], receiver)  # type: ignore[arg-type]
                    return
                self.plan_result_name(parent, target, receiver)
                return
        if isinstance(parent, ast.Expr) or self._returned_from_step_method(call, parent):
            return  # result unused, or passed through by a wrapper's step (the wrapper rules' job)
        if self.plan_indexed_step(call, receiver):
            return
        self.report_unpacked_use(call, receiver)

    def _plan_step_callables(self) -> None:
        """``ob, r, done, info = step_fn(a)`` in an env's reset, where the run's wrappers hand
        ``step_fn`` only their own ``self.step`` (facts/reset_contract.py): a step result."""
        project = self.receivers.project
        if project is not None:
            contract = project.reset_contract()
        else:
            contract = join_contract([("", reset_sites(self.facts, lambda c: self.receivers.class_kind(c) is EnvKind.GYM_ENV))])
        if contract is None or not contract.step_callables:
            return
        for classdef in [n for n in walk(self.facts.tree) if isinstance(n, ast.ClassDef)]:
            reset = own_reset(classdef)
            if reset is None or self.receivers.is_gym_wrapper_class(classdef):
                continue
            params = {a.arg for a in extra_params(reset)} & contract.step_callables
            for node in walk(reset):
                if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in params:
                    parent = self.facts.parent(node)
                    if isinstance(parent, ast.Assign) and parent.value is node and _four_targets(parent):
                        self.step_callables.add(id(node.func))
                        self.plan_unpack(parent, parent.targets[0], node.func)  # type: ignore[arg-type]

    def _plan_pass_through_methods(self) -> None:
        """``obs, r, done, info = self.advance(a)`` where ``advance`` is a method of the class
        whose body only returns ``self.x.step(...)``: the call gives exactly that step's result,
        so its unpack is decided on ``self.x`` (rewritten where the run proves a Gym env, asked
        where it cannot tell, left where it proves something else). ``step`` itself is
        ``_self_step``'s; a method a subclass of this module replaces may give anything."""
        classes = [n for n in walk(self.facts.tree) if isinstance(n, ast.ClassDef)]
        for classdef in classes:
            inner = {
                s.name: step
                for s in classdef.body
                if isinstance(s, FUNCTIONS) and s.name != "step" and (step := _passed_through_step(s)) is not None
            }
            replaced = {
                s.name for c in classes if c is not classdef and classdef in self.receivers.local_lineage(c) for s in c.body if isinstance(s, FUNCTIONS)
            }
            for name in set(inner) - replaced:
                for call in self.facts.attribute_calls.get(name, ()):
                    func = call.func
                    assert isinstance(func, ast.Attribute)
                    parent = self.facts.parent(call)
                    if not (isinstance(func.value, ast.Name) and self.receivers.is_self(func.value)):
                        continue
                    if classdef not in self.receivers.local_lineage(self.facts.enclosing_class(call) or classdef):
                        continue  # ``self`` of an unrelated class, with a method of the same name
                    if isinstance(parent, ast.Assign) and parent.value is call and _four_targets(parent) and not _starred(parent.targets[0]):  # type: ignore[arg-type]
                        self.plan_unpack(parent, parent.targets[0], inner[name].func.value)  # type: ignore[arg-type, attr-defined]

    def _forwarded_unpack(self, assign: ast.Assign, target: ast.expr) -> ast.Assign | None:
        """``obs, r, done, info = res`` where ``res = x.step(a)`` (``assign``) is the only
        binding of ``res`` and that unpack its only read, dominated by the step."""
        if not isinstance(target, ast.Name):
            return None
        scope = self.flow.binding_scope(target)
        if scope is None or len(scope.bindings.get(target.id, [])) != 1:
            return None
        reads = self.flow.reads(target)
        if len(reads) != 1:
            return None
        unpack = self.facts.parent(reads[0])
        if not (isinstance(unpack, ast.Assign) and unpack.value is reads[0] and _four_targets(unpack)):
            return None
        if not self.flow.same_frame(reads[0], scope) or not self.flow.dominates(assign, reads[0], target):
            return None
        return unpack

    def _returned_from_step_method(self, call: ast.Call, parent: ast.AST | None) -> bool:
        if not isinstance(parent, ast.Return):
            return False
        function = self.facts.enclosing(call, (*FUNCTIONS, ast.Lambda))
        return isinstance(function, FUNCTIONS) and function.name == "step"


def _passed_through_step(function: ast.FunctionDef | ast.AsyncFunctionDef) -> ast.Call | None:
    """``self.x.step(...)`` where the method's body (docstring aside) is only ``return`` of it."""
    value = sole_step_return(function)
    if value is None:
        return None
    assert isinstance(value.func, ast.Attribute)
    inner = value.func.value
    if isinstance(inner, ast.Attribute) and isinstance(inner.value, ast.Name) and inner.value.id == "self":
        return value
    return None


def _numpy_name(module: ast.Module) -> str | None:
    """The name a module-level ``import numpy [as x]`` binds, if there is one."""
    for statement in module.body:
        if isinstance(statement, ast.Import):
            for alias in statement.names:
                if alias.name == "numpy":
                    return alias.asname or "numpy"
    return None


def _starred(target: ast.Tuple | ast.List) -> bool:
    return any(isinstance(el, ast.Starred) for el in target.elts)


def _four_targets(assign: ast.Assign) -> bool:
    if len(assign.targets) != 1:
        return False
    target = assign.targets[0]
    return isinstance(target, (ast.Tuple, ast.List)) and len(target.elts) == 4 and not _starred(target)


def _five_targets(parent: ast.AST | None, call: ast.Call) -> bool:
    if not (isinstance(parent, ast.Assign) and parent.value is call and len(parent.targets) == 1):
        return False
    target = parent.targets[0]
    return isinstance(target, (ast.Tuple, ast.List)) and len(target.elts) == 5 and not _starred(target)
