"""``env.videos`` and ``env.monitor`` (GM604): what gym's ``Monitor`` and gym < 0.9's monitor
API gave, which no Gymnasium wrapper has for forwarding to find.

gym's Monitor kept the list of the videos it wrote (``videos``); RecordVideo, which the run
puts in its place (GM611), keeps none. gym < 0.9's ``env.monitor.start(dir)`` /
``.close()`` recorded through an attribute of the env itself. Part of
``forwarding.WrapperForwarding``.
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import dotted_name
from gymmigrate.findings import FixKind

if TYPE_CHECKING:
    from gymmigrate.rules.wrapper_usage.self_forwarding import ForwardingFamily

# Attributes of gym's Monitor itself that no Gymnasium wrapper has: ``videos`` (the
# (video, metadata) paths it wrote).
_MONITOR_ONLY_ATTRIBUTES = frozenset({"videos"})


def reads_monitor_videos(family: ForwardingFamily, attr: ast.Attribute, known: bool, kind: EnvKind) -> bool:
    """``env.videos`` in a module that records with Monitor, on an env the run shows is a
    Gym env (``known``), cannot trace (made by a factory handed around), or holds in a
    wrapper: no other object there is shown to have videos."""
    return (
        attr.attr in _MONITOR_ONLY_ATTRIBUTES
        and isinstance(attr.ctx, ast.Load)
        and (known or kind is EnvKind.UNKNOWN or family.origins.outer_is_wrapper(attr.value))
        and _records_with_gym_monitor(family.facts)
    )


def report_monitor_videos(family: ForwardingFamily, attr: ast.Attribute) -> None:
    # gym's Monitor kept the list of the videos it wrote; RecordVideo, which the run
    # puts in its place (GM611), keeps none, so no forwarding can reach one.
    family.report(
        attr,
        "GM604",
        f"`{dotted_name(attr) or attr.attr}` was gym Monitor's list of (video, metadata) file pairs; RecordVideo, "
        "which replaces the Monitor here, keeps no such list (AttributeError on Gymnasium, through "
        "`get_wrapper_attr` too): list the .mp4 files it writes in its video_folder instead (it writes no "
        "metadata json)",
        kind=FixKind.FLAG,
    )


def monitor_api(family: ForwardingFamily, attr: ast.Attribute) -> bool:
    """``env.monitor`` read (gym < 0.9's monitor API): decided here, True; anything else False."""
    if attr.attr != "monitor" or not isinstance(attr.ctx, ast.Load):
        return False
    receiver = attr.value
    if _closes_monitor_of_env(family, attr):
        # ``env.monitor.close()`` on an env the run made, read no more afterwards: the
        # wrapper that recorded is gone, ``env.close()`` is what the item would say.
        family.plan.replace(attr, lambda node: node.value)
        family.report(
            attr,
            "GM604",
            f"`{dotted_name(attr)}.close()` (gym < 0.9's monitor API) -> `{dotted_name(receiver)}.close()`: the env is not "
            "used after it; record with `RecordVideo`/`RecordEpisodeStatistics` around the env",
            kind=FixKind.AUTO,
        )
        return True
    # gym < 0.9's ``env.monitor.start(dir)`` / ``.close()``: no wrapper has it to forward.
    family.report(
        attr,
        "GM604",
        f"`{dotted_name(attr) or attr.attr}` (gym < 0.9's monitor API) is gone, and no wrapper has it: record with "
        "`RecordVideo`/`RecordEpisodeStatistics` around the env; `.monitor.close()` becomes `.close()` "
        "(which also closes the env)",
        kind=FixKind.FLAG,
        question=("GM604", "monitor", dotted_name(receiver)),
    )
    return True


def _records_with_gym_monitor(facts: ModuleFacts) -> bool:
    """This module wraps an env in gym's ``Monitor`` or in the ``RecordVideo`` that replaces
    it (a later pass of the run, or a second run, sees that one)."""

    def scan() -> bool:
        for node in facts.parents:
            if isinstance(node, ast.Call) and isinstance(node.func, (ast.Name, ast.Attribute)):
                last = node.func.id if isinstance(node.func, ast.Name) else node.func.attr
                if last in ("Monitor", "RecordVideo") and any(
                    (N.strip_gym_prefix(q) or "").startswith("wrappers.") for q in facts.qualified_names(node.func)
                ):
                    return True
        return False

    return bool(facts.memo(("records-with-gym-monitor", id(facts.tree)), scan))


def _closes_monitor_of_env(family: ForwardingFamily, attr: ast.Attribute) -> bool:
    """``env.monitor.close()`` as a statement, ``env`` a name the run shows is a Gym env
    and that nothing in its scope reads after this line (``close`` closes the env too)."""
    receiver, close = attr.value, family.facts.parent(attr)
    call = family.facts.parent(close) if close is not None else None
    if not (
        isinstance(receiver, ast.Name)
        and isinstance(close, ast.Attribute)
        and close.attr == "close"
        and isinstance(call, ast.Call)
        and call.func is close
        and not call.args
        and not call.keywords
        and isinstance(family.facts.parent(call), ast.Expr)
    ):
        return False
    if family.receivers.kind_of(receiver) is not EnvKind.GYM_ENV:
        return False
    scope = family.facts.scope_of(receiver)
    return not any(read.lineno > call.lineno for read in scope.reads.get(receiver.id, []))
