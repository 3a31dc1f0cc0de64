"""What every step rule shares: the catalog entries, the names of the new flags, the
receiver decision and the per-file state the rules hand to one another.

The rules of this family read each other's conclusions within one run: a ``done`` read
that one step unpack rewrites is not claimed by a later one, and the ``info`` names an
unpack binds tell GM303 which ``TimeLimit.truncated`` reads it can rewrite.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass

from gymmigrate.facts.decisions import Action, Decision, decide, receiver_text
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.legacy_wrapper_hooks import in_dead_hook
from gymmigrate.facts.module import is_super_call
from gymmigrate.facts.own_steps import (
    is_base_step_call,
    reaches_helper_step,
    self_step_gives_five,
)
from gymmigrate.facts.version_checks import dead_version_branch
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import Rule, RuleFamily

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
    # The code reads ``done`` as one flag or as per-env flags (``isinstance(done, bool)``,
    # ``done[i]``): ``|`` is ``or`` on two bools and elementwise on arrays, where ``or`` raises.
    elementwise: bool = False
    # The code reads ``done`` as a list of per-agent flags (``all(done)``, ``zip(obs, done)``,
    # facts/per_agent_flags.py): ``or`` would return the terminated list and ``|`` raises on
    # lists, so the flags are joined agent by agent with ``np.logical_or(...).tolist()``, which
    # also takes one bool ``truncated`` (a per-agent env migrated by this run returns ``False``
    # there) or two bools (Gymnasium releases of such envs), and gives a list or a bool back.
    # ``guard`` is the code's own type test when it handles one flag too (``isinstance(done,
    # Iterable)``), used where the flags are cut agent by agent (rules/wrappers/step.py).
    per_agent: bool = False
    guard: str | None = None
    by_name: bool = False  # a dict of agents' flags (``done["__all__"]``)

    @property
    def code(self) -> str:
        return "GM703" if self.vector else "GM301"

    def joined(self) -> str:
        if self.vector:
            return f"{self.numpy}.logical_or({self.terminated}, {self.truncated})"
        if self.per_agent and self.by_name:
            return f"{{agent: {self.terminated}[agent] or {self.truncated}[agent] for agent in {self.terminated}}}"
        if self.per_agent:
            return f"{self.numpy}.logical_or({self.terminated}, {self.truncated}).tolist()"
        if self.elementwise:
            return f"{self.terminated} | {self.truncated}"
        return f"{self.terminated} or {self.truncated}"


@dataclass
class StepUnpack:
    """What the step family did to one ``obs, r, done, info = x.step(a)``."""

    names: StepNames
    discarded: bool  # the done target was ``_``: both flags became ``_``
    done_line: str | None = None  # the ``done = ...`` code inserted after it (the very object)
    claimed_reads: int = 0  # reads of ``done`` it turned into ``terminated``


class StepFamilyBase(RuleFamily):
    """State and helpers shared by the step rules (no ``RULES``: not registered itself)."""

    flow: Flow
    # Rewritten steps whose ``info`` target is a name, and the ``info`` variables of
    # SB3 VecEnv steps (scope id, name): GM303 reads resolve against them.
    info_steps: dict[ast.Assign, StepNames]
    guarded_infos: set[tuple[int, str]]
    # The ``info`` variables of steps left for review because the receiver may not be a Gym
    # env (scope id, name) -> the receiver's text: an SB3 VecEnv's infos still carry the key.
    unsure_infos: dict[tuple[int, str], str]
    # Rewritten steps by ``done`` variable (scope id, name); their reads are planned together.
    done_steps: dict[tuple[int, str], list]
    reported_reads: set[int]  # ``done`` reads already reported (by node id)
    # (callee text, argument) -> the question of the first step whose done it was handed:
    # other steps handing their done to the same argument join that question.
    callee_questions: dict[tuple[str, object], tuple[object, ...]]
    # Steps whose flag a read stores per step as a rollout's episode boundary (the note that
    # it stays ``terminated or truncated``) -> that read: the run's decision for the rollout.
    rollout_stores: dict[ast.Assign, ast.Name]
    # Functions (by id) already asked how a trajectory cut by a time limit ends: one item each.
    zero_tail_functions: set[int]
    result_steps: dict[tuple[int, str], list]  # ``res = x.step(a)`` by variable
    # Four-target step unpacks: a read that one of them dominates belongs to it alone.
    legacy_unpacks: set[ast.Assign]
    step_callables: set[int]  # ids of reset-contract step callables called in an env's reset
    forwarded_unpacks: dict[int, ast.Assign]  # id of ``res = x.step(a)`` -> ``obs, r, done, info = res``
    numpy_name: str | None

    def decision(self, receiver: ast.expr, legacy_shape: bool) -> tuple[Decision, bool]:
        """What to do with ``receiver.step``, and whether it is a vector env."""
        if id(receiver) in self.step_callables:
            # a reset-contract step callable: the run hands it only wrappers' own steps
            return Decision(Action.REWRITE, "the run's wrappers pass their own step here"), False
        kind = self.receivers.super_kind(receiver) or self.receivers.kind_of(receiver)
        profile = self.context.profile
        if in_dead_hook(self.receivers, receiver):
            # a gym < 0.9 wrapper hook GM616 leaves dead: its body stays whole for a person to port
            return Decision(Action.LEAVE, "in a gym < 0.9 hook Gymnasium never calls, left as it is"), False
        if dead_version_branch(receiver, self.facts) is not None or self.receivers.in_legacy_by_version_method(receiver):
            # the legacy branch of a gym version check: it never runs on Gymnasium (GM108)
            return Decision(Action.LEAVE, "under a gym version check that picks the API of the gym installed"), False
        if self._reaches_helper_step(receiver):
            # ``ob = super().step(a)`` over a base step that returns one value (the observation,
            # a flag), which every override builds its own step on: no step result, nothing to move
            return Decision(Action.LEAVE, "the base's step is a helper that returns one value, no step result"), False
        kept = self.receivers.legacy_step_class(receiver)
        if kept is not None:
            # The run leaves that class's step as it was (GM504 reports it there): its
            # callers keep the same four fields, or they would no longer match.
            return Decision(Action.LEAVE, f"`{receiver_text(receiver)}` is a {kept}, whose step keeps four fields"), False
        if kind is EnvKind.GYM_VEC:
            return decide(kind, receiver, profile, legacy_shape=legacy_shape, expected=EnvKind.GYM_VEC, origins=self.receivers), True
        own = self._self_step(receiver)
        if own is not None:
            return own, False
        return decide(kind, receiver, profile, legacy_shape=legacy_shape, origins=self.receivers), False

    def _reaches_helper_step(self, receiver: ast.expr) -> bool:
        """``super().step(...)`` (or ``Base.step(self, ...)`` naming the first base) in a
        class whose base's step is a helper of the run (facts/own_steps.py)."""
        call = self.facts.parent(self.facts.parent(receiver))
        classdef = self.facts.enclosing_class(receiver)
        function = self.facts.enclosing_function(receiver)
        if classdef is None or function is None or self.facts.parent(function) is not classdef:
            return False
        return is_base_step_call(call, classdef, function) and reaches_helper_step(self.facts, self.receivers, classdef)

    def _self_step(self, receiver: ast.expr) -> Decision | None:
        """``self.step(a)`` inside a Gym wrapper class of this module runs the wrapper's own
        step. With no ``step`` of its own, or one that only returns the inner step (``return
        self.env.step(action)``), that is the inner Gym env's five values: rewritten. Any
        other ``step`` of its own is migrated (or not) by the wrappers family, decided
        there: reported, not left silently on four fields. In any other class, it runs the
        class's own step or an override below it: where every one of them gives five values
        once the run has migrated it (facts/own_steps.py), so does the call: rewritten; else
        the env-class family asks about it. None: not such a call."""
        if not (isinstance(receiver, ast.Name) and receiver.id == "self"):
            return None
        function = self.facts.enclosing_function(receiver)
        classdef = self.facts.parent(function) if function is not None else None
        if not isinstance(classdef, ast.ClassDef):
            return None
        params = [*function.args.posonlyargs, *function.args.args]  # type: ignore[union-attr]
        if not params or params[0].arg != "self":
            return None
        kind = self.receivers.class_kind(classdef)
        if kind is not EnvKind.GYM_ENV or not self.receivers.is_gym_wrapper_class(classdef):
            selection = self.context.options.selection
            if kind is EnvKind.GYM_ENV and selection is not None and not selection.allows("GM504"):
                return None  # the env classes' steps stay on four values: so does this call
            if self_step_gives_five(self.facts, self.receivers, classdef, function.name):  # type: ignore[union-attr]
                return Decision(Action.REWRITE, "`self.step()` runs the class's own step or an override below it, each of which gives five values once migrated")
            return None
        step = next((s for s in classdef.body if isinstance(s, (ast.FunctionDef, ast.AsyncFunctionDef)) and s.name == "step"), None)
        if step is None or _only_returns_inner_step(step):
            return Decision(Action.REWRITE, "`self` is this Gym wrapper, whose step hands on the inner step's five values")
        return Decision(
            Action.REPORT,
            "`self.step()` runs this wrapper's own step, which returns five values once migrated (GM602); not rewritten",
        )


def sole_step_return(function: ast.FunctionDef | ast.AsyncFunctionDef) -> ast.Call | None:
    """The ``x.step(...)`` call of a body that is only ``return x.step(...)``, docstring aside."""
    body = [s for s in function.body if not (isinstance(s, ast.Expr) and isinstance(s.value, ast.Constant))]
    if len(body) != 1 or not isinstance(body[0], ast.Return):
        return None
    value = body[0].value
    if not (isinstance(value, ast.Call) and isinstance(value.func, ast.Attribute) and value.func.attr == "step"):
        return None
    return value


def _only_returns_inner_step(step: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    """The body is ``return self.env.step(...)`` (or ``super().step(...)``), docstring aside."""
    value = sole_step_return(step)
    if value is None:
        return False
    assert isinstance(value.func, ast.Attribute)
    inner = value.func.value
    if is_super_call(inner):
        return True
    return isinstance(inner, ast.Attribute) and inner.attr == "env" and isinstance(inner.value, ast.Name) and inner.value.id == "self"


def looks_vectorised(receiver: ast.expr, done_target: ast.expr) -> bool:
    """An untraced ``envs.step`` or a ``dones`` target: single-env ``or`` would be wrong.
    ``envs[0].step`` is one item of a list of envs, not a plural receiver."""
    name = receiver_text(receiver).rsplit(".", 1)[-1].lower()
    plural = not isinstance(receiver, ast.Subscript) and name.endswith(("envs", "environments"))
    return plural or (isinstance(done_target, ast.Name) and done_target.id.endswith("dones"))


def stands_alone(node: ast.expr, parent: ast.AST | None) -> bool:
    """``node`` is a whole expression on its own (a test, an assigned or returned value, an
    argument, a container element): a replacement needs no parentheses there."""
    if isinstance(parent, (ast.If, ast.While, ast.Assert)):
        return parent.test is node
    if isinstance(parent, (ast.Assign, ast.Return, ast.Expr, ast.AnnAssign, ast.keyword)):
        return parent.value is node
    if isinstance(parent, ast.Call):
        return any(arg is node for arg in parent.args)
    if isinstance(parent, (ast.Tuple, ast.List, ast.Set)):
        return any(element is node for element in parent.elts)
    return False
