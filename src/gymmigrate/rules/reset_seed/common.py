"""What the reset and seed rules share: the receiver policy, per-call edits, loop checks.

``ResetSeedBase`` carries the state of one file's decisions (the edits collected per
call, the names introduced for ``info``); the rule modules (``resets``, ``seeds``,
``cli_seed``; ``seeds`` through its mixins ``seed_methods``, ``seed_merges`` and
``next_reset``) extend it and ``ResetSeed`` in ``__init__`` puts them together.
"""

from __future__ import annotations

import ast
from collections.abc import Hashable

from gymmigrate.facts.decisions import Action, Decision, decide
from gymmigrate.facts.env_classes import env_base_call
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import is_super_call, named_class_call
from gymmigrate.facts.reset_flow import (
    InfoNames,
    NumpySeeds,
    enclosing_loops,
    guarded_to_run_once,
    is_iteration_invariant,
    made_anew_in,
)
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import RuleFamily
from gymmigrate.rules.reset_seed.call_edits import CallEdit


class ResetSeedBase(RuleFamily):
    """Shared helpers; registers nothing (no ``RULES``)."""

    def _start(self) -> None:
        self._edits: dict[ast.Call, CallEdit] = {}
        self.contract_keywords: frozenset[str] = frozenset()  # moved into options (GM207, contract.py)
        self.info_names = InfoNames(self.facts)
        self.numpy_seeds = NumpySeeds(self.facts)

    def _edit(self, call: ast.Call) -> CallEdit:
        """The edit of ``call``, planned once; the rules fill it in before it is applied."""
        edit = self._edits.get(call)
        if edit is None:
            edit = self._edits[call] = CallEdit()
            self.plan.replace(call, edit.build)
        return edit

    def own_plain_class(self, classdef: ast.ClassDef, seen: set[str]) -> bool:
        """A class whose bases are ``object`` or plain classes of this module, none a Gym env
        or wrapper class: its methods are called by the project alone."""
        if classdef.name in seen or classdef.keywords:
            return False
        seen.add(classdef.name)
        if self.receivers.class_kind(classdef) not in (EnvKind.UNKNOWN, EnvKind.NOT_ENV):
            return False
        if self.receivers.is_gym_wrapper_class(classdef):
            return False
        for base in classdef.bases:
            if isinstance(base, ast.Name) and base.id == "object":
                continue
            names = self.facts.qualified_names(base)
            if any(q in ("abc.ABC", "abc.ABCMeta") for q in names):
                continue  # an abstract interface of the project says nothing Gym would call
            project = self.receivers.project
            if project is not None and any(project.is_plain_root(q) for q in names):
                continue  # ``from ._environment import Environment``, the project's own ``class Environment(ABC)``
            local = self.receivers.local_class(base)
            if local is None or not self.own_plain_class(local, seen):
                return False
        return True

    # -- the receiver ---------------------------------------------------------------------

    def _receiver_kind(self, receiver: ast.expr) -> EnvKind:
        # ``super().reset()`` inside a Gym wrapper reaches the wrapped env's reset; so does
        # ``gym.Wrapper.reset(self)``, naming the base ``super()`` would reach.
        if is_super_call(receiver) or isinstance(receiver, (ast.Name, ast.Attribute)):
            classdef = self.facts.enclosing_class(receiver)
            if classdef is not None and self.receivers.is_gym_wrapper_class(classdef):
                if is_super_call(receiver) or self.receivers.super_kind(receiver) is EnvKind.GYM_ENV:
                    return EnvKind.GYM_ENV
        return self.receivers.kind_of(receiver)

    def _names_base(self, call: ast.Call) -> bool:
        """``Base.reset(self, ...)`` naming a base of the method's class: its first argument
        is the instance, not an argument of the reset."""
        function = self.facts.enclosing_function(call)
        classdef = self.facts.enclosing_class(call)
        if function is None or classdef is None or self.facts.parent(function) is not classdef:
            return False
        method = call.func.attr if isinstance(call.func, ast.Attribute) else ""
        return named_class_call(call, method, function, classdef.bases) is not None or env_base_call(
            self.facts, call, method, function
        )

    def _decide(self, receiver: ast.expr, legacy_shape: bool = False) -> tuple[Decision, bool]:
        """The decision for a Gym single-env or vector-env call, and whether it is a vector env."""
        kind = self._receiver_kind(receiver)
        vector = kind is EnvKind.GYM_VEC
        expected = EnvKind.GYM_VEC if vector else EnvKind.GYM_ENV
        return decide(kind, receiver, self.context.profile, legacy_shape=legacy_shape, expected=expected, origins=self.receivers), vector

    def _stepped_the_legacy_way(self, receiver: ast.expr) -> bool:
        """The same name is stepped in the same function with four unpacked values: an
        untraced ``e.reset()`` next to ``o, r, done, _ = e.step(a)`` is the same question."""
        if not isinstance(receiver, ast.Name):
            return False
        function = self.facts.enclosing_function(receiver)
        for call in self.facts.attribute_calls.get("step", ()):
            value = call.func.value if isinstance(call.func, ast.Attribute) else None
            if not (isinstance(value, ast.Name) and value.id == receiver.id):
                continue
            if self.facts.enclosing_function(call) is not function:
                continue
            assign = self.facts.parent(call)
            if (
                isinstance(assign, ast.Assign)
                and len(assign.targets) == 1
                and isinstance(assign.targets[0], (ast.Tuple, ast.List))
                and len(assign.targets[0].elts) == 4
            ):
                return True
        return False

    @staticmethod
    def _kind(decision: Decision, default: FixKind | None = None) -> FixKind | None:
        return FixKind.ASSIST if decision.action is Action.REWRITE_FOR_REVIEW else default

    @staticmethod
    def _why(decision: Decision) -> str:
        return f" ({decision.reason})" if decision.action is Action.REWRITE_FOR_REVIEW else ""

    # -- GM204 ------------------------------------------------------------------------------

    def _check_seed_in_loop(self, call: ast.Call, seed: ast.expr, shown: str) -> None:
        """GM204: a seed that is the same on every iteration of a loop resets the RNG each time."""
        if isinstance(seed, ast.Constant) and seed.value is None:
            return
        receiver = call.func.value if isinstance(call.func, ast.Attribute) else None
        for loop in enclosing_loops(self.facts, call):
            if receiver is not None and made_anew_in(self.facts, receiver, loop):
                continue  # a new env each iteration, seeded once: no reseed
            if is_iteration_invariant(self.facts, seed, loop) and not guarded_to_run_once(self.facts, call, loop):
                self.report(
                    call,
                    "GM204",
                    f"{shown} reseeds with the same value on every loop iteration, so every episode starts from "
                    "the same state: seed the first reset before the loop and reset without a seed inside it, "
                    "unless identical episodes are intended",
                )
                return


def is_space(receiver: ast.expr) -> bool:
    """``env.action_space``, ``observation_space``, ``space``, ``spaces["x"]``..."""
    if isinstance(receiver, ast.Subscript):
        return is_space(receiver.value)
    if isinstance(receiver, ast.Attribute):
        name = receiver.attr
    elif isinstance(receiver, ast.Name):
        name = receiver.id
    else:
        return False
    return name.lower().endswith(("space", "spaces"))


def is_seeding(call: ast.Call) -> bool:
    """``x.seed(...)`` or ``x.reset(seed=...)``."""
    func = call.func  # an attribute: the calls of ``x.seed`` and ``x.reset`` only
    return (isinstance(func, ast.Attribute) and func.attr == "seed") or any(kw.arg == "seed" for kw in call.keywords)


def moving_seed_question(seed_method: ast.FunctionDef | ast.AsyncFunctionDef) -> Hashable:
    """What an item that asks to move a seed() method's seeding into reset() asks: GM203 at a
    seed call inside the method, GM205 at a space seeded there and GM503 at the method itself
    ask it alike, so the file's review list asks it once."""
    return ("seed() method", seed_method.lineno)


def _seed_argument(call: ast.Call) -> ast.expr | None:
    """The one seed of ``x.seed(s)`` / ``x.seed(seed=s)``, else None."""
    if len(call.args) + len(call.keywords) != 1:
        return None
    if call.args:
        return None if isinstance(call.args[0], ast.Starred) else call.args[0]
    keyword = call.keywords[0]
    return keyword.value if keyword.arg == "seed" else None
