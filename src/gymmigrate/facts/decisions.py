"""One policy for every call-site rule: rewrite, rewrite for review, report, or leave.

Keeping the policy in one place means ``reset``, ``step``, ``seed`` and ``render``
rules treat an uncertain receiver the same way.
"""

from __future__ import annotations

import ast
import re
from dataclasses import dataclass
from enum import Enum
from typing import TYPE_CHECKING, Protocol

from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import full_name

if TYPE_CHECKING:
    from gymmigrate.facts.profile import FileProfile


class Origins(Protocol):
    """What ``decide`` asks the receiver analysis (``Receivers.run_defined``)."""

    def run_defined(self, expr: ast.AST) -> bool: ...
    def mixed_callers(self, expr: ast.AST) -> str | None: ...

    def library_made(self, expr: ast.AST) -> str | None: ...
    def library_record_env(self, expr: ast.AST) -> str | None: ...
    def gym_only_stack(self, expr: ast.AST) -> str | None: ...
    def own_api_holder(self, expr: ast.AST) -> str | None: ...
    def dispatched_from_gym(self, expr: ast.AST) -> str | None: ...
    def handles_gym_envs(self) -> bool: ...
    def annotated_class(self, expr: ast.AST) -> str | None: ...
    def tested_other_class(self, expr: ast.AST) -> str | None: ...

# Spellings that name an environment. Used only to decide between reporting and
# staying silent (or, in a file that uses nothing but Gym, rewriting for review):
# never to rewrite on its own.
_ENV_LIKE = re.compile(r"(^|_)(env|envs|environment|environments)(_|$|\d)", re.IGNORECASE)


class Action(str, Enum):
    REWRITE = "rewrite"  # the receiver is a Gym env: rewrite (AUTO unless the rule says ASSIST)
    REWRITE_FOR_REVIEW = "rewrite-for-review"  # probably a Gym env: rewrite as ASSIST, list it
    REPORT = "report"  # cannot tell: leave the code, list it for review (FLAG)
    LEAVE = "leave"  # not a Gym env (SB3 VecEnv, PettingZoo, optimiser...): never touch


@dataclass(frozen=True)
class Decision:
    action: Action
    reason: str


def receiver_text(receiver: ast.AST) -> str:
    return full_name(receiver) or "the receiver"


def looks_like_env(receiver: ast.AST) -> bool:
    name = full_name(receiver) or ""
    last = name.rsplit(".", 1)[-1]
    return bool(_ENV_LIKE.search(last))


def decide(
    kind: EnvKind,
    receiver: ast.AST,
    profile: FileProfile,
    *,
    legacy_shape: bool = False,
    expected: EnvKind = EnvKind.GYM_ENV,
    origins: Origins | None = None,
) -> Decision:
    """What to do with ``receiver.method(...)`` given its classified ``kind``.

    ``legacy_shape``: the call is used the legacy way (e.g. four names unpacked from
    ``step``), which makes an unknown receiver worth reporting even if its name does
    not look like an env. ``expected`` is the kind the rule rewrites (GYM_ENV or GYM_VEC).
    ``origins``: the receiver analysis; with it, an object the run itself makes (a class or
    a def of the run, a name imported from one of its modules) is never rewritten on the
    "this file uses only Gym" fallback: the run knows that code, so it reports instead. Nor
    is a receiver annotated with a class not shown to be a Gym env, nor one in a file that
    makes, wraps and subclasses no Gym env (``Origins.handles_gym_envs``): its Gym use (spaces,
    a viewer) says nothing of what its env-like names hold.
    """
    name = receiver_text(receiver)
    if kind is expected:
        return Decision(Action.REWRITE, f"`{name}` is a {kind.value}")
    if kind is not EnvKind.UNKNOWN:
        return Decision(Action.LEAVE, f"`{name}` is a {kind.value}")
    env_like = looks_like_env(receiver)
    mixed = origins.mixed_callers(receiver) if origins is not None else None
    if mixed is not None:
        return Decision(Action.REPORT, f"`{name}` may not be a Gym env: {mixed}; not rewritten")
    stack = origins.gym_only_stack(receiver) if (env_like or legacy_shape) and origins is not None else None
    if stack is not None:
        # made on a library stack still on gym (GM107), maybe through the project's own
        # wrappers and factories: it keeps gym's API until that stack is ported, and then
        # (Shimmy) it is a Gymnasium env; the stack's item decides it, asked at its import
        return Decision(
            Action.REPORT, f"`{name}` is an env built on {stack}, a library still on gym (GM107): not rewritten; it becomes a Gymnasium env when that library is ported"
        )
    foreign = origins.library_record_env(receiver) if (env_like or legacy_shape) and origins is not None else None
    if foreign is not None:
        # the class fills it from another library and reads its step as a record (a
        # TimeStep): no Gym env, whatever the file's imports say, so nothing to ask
        return Decision(Action.LEAVE, f"`{name}` is made by `{foreign}` and its step() result is read as a record, not Gym's tuple")
    if (env_like or legacy_shape) and origins is not None and origins.run_defined(receiver):
        return Decision(Action.REPORT, f"`{name}` holds an object the project makes itself, not shown to be a Gym env; not rewritten")
    holder = origins.own_api_holder(receiver) if (env_like or legacy_shape) and origins is not None else None
    if holder is not None and origins is not None:
        dispatcher = origins.dispatched_from_gym(receiver)
        if dispatcher is not None:
            # ``wrap_env`` sends Gym envs to another class first: this one wraps another API
            return Decision(Action.LEAVE, f"`{name}` is held by {holder}, which `{dispatcher}` builds only for envs that are not Gym's")
    fallback = env_like and profile.gym_only
    library = origins.library_made(receiver) if (fallback or holder is not None) and origins is not None else None
    if holder is not None and library is None:
        # a wrapper of an env API other than Gym's forwarding its own reset/step: what it
        # holds follows that API as likely as Gym's, so the file's imports settle nothing
        # (the library that made what it holds, where the code shows one, says more: below)
        return Decision(Action.REPORT, f"`{name}` is held by {holder}; not shown to be a Gym env, not rewritten")
    if library is not None:
        return Decision(Action.REPORT, f"`{name}` is made by `{library}`, a library other than Gym, not shown to be a Gym env; not rewritten")
    annotated = origins.annotated_class(receiver) if fallback and origins is not None else None
    if annotated is not None:
        # the code says what it holds, and that is no Gym class the run knows: a file's
        # imports do not outweigh it (``environment: VecEnv`` of the project's own vec env)
        return Decision(Action.REPORT, f"`{name}` is annotated {annotated}; not rewritten")
    tested = origins.tested_other_class(receiver) if fallback and origins is not None else None
    if tested is not None:
        # ``if isinstance(env, gym.Env): ... elif isinstance(env, PlainEnv): ...``: the code
        # says this name may hold that class's instance, whose API is its own
        return Decision(
            Action.REPORT,
            f"`{name}` may hold a `{tested}` (this function tests for one), which is no Gym env: not rewritten;"
            f" branch on `isinstance({name}, {tested})` as the code does elsewhere",
        )
    if fallback and origins is not None and not origins.handles_gym_envs():
        # Gym's spaces, errors, a viewer or seeding utils only: the file makes, wraps and
        # subclasses no Gym env, so its env-like names may hold any env (a project's own)
        return Decision(Action.REPORT, f"could not tell whether `{name}` is a Gym env (this file makes, wraps and subclasses none); not rewritten")
    if fallback:
        return Decision(
            Action.REWRITE_FOR_REVIEW,
            f"could not trace where `{name}` comes from; rewritten because this file uses only Gym",
        )
    if env_like or (legacy_shape and (profile.imports_gym or profile.imports_gymnasium)):
        return Decision(Action.REPORT, f"could not tell whether `{name}` is a Gym env; not rewritten")
    return Decision(Action.LEAVE, f"`{name}` is not known to be an env")
