"""``env.videos``, ``env._flush()`` and ``env.monitor`` (GM604): what gym's ``Monitor`` and
gym < 0.9's monitor API gave, which no Gymnasium wrapper has for forwarding to find.

gym's Monitor kept the list of the videos it wrote (``videos``); RecordVideo, which the run
puts in its place (GM611), keeps none; nor does any layer have the Monitor's own methods
(``_flush``, ``get_total_steps``...). gym < 0.9's ``env.monitor.start(dir)`` /
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
# (video, metadata) paths it wrote), and its own methods and recorders. Legacy code read
# them on the Monitor, outermost; through ``get_wrapper_attr`` the read would fail on every
# layer of the stack that replaces it (or find a namesake of the env's). Its generic names
# (``directory``, ``enabled``) are left out: an env of the module may have them itself.
_MONITOR_ONLY_ATTRIBUTES = frozenset(
    {
        "videos",
        "stats_recorder",
        "video_recorder",
        "video_callable",
        "write_upon_reset",
        "file_prefix",
        "file_infix",
        "env_semantics_autoreset",
        "_monitor_id",
        "_start",
        "_flush",
        "_close",
        "set_monitor_mode",
        "_set_mode",
        "_before_step",
        "_after_step",
        "_before_reset",
        "_after_reset",
        "reset_video_recorder",
        "_close_video_recorder",
        "_video_enabled",
        "get_total_steps",
        "get_episode_rewards",
        "get_episode_lengths",
    }
)

# What the run puts in a Monitor's place (GM611).
_REPLACEMENTS = ("Monitor", "RecordVideo", "RecordEpisodeStatistics")


def reads_monitor_videos(family: ForwardingFamily, attr: ast.Attribute, known: bool, kind: EnvKind) -> bool:
    """``env.videos`` in a module that records with Monitor, on an env the run shows is a
    Gym env (``known``), cannot trace (made by a factory handed around), or holds in a
    wrapper: no other object there is shown to have videos."""
    return (
        attr.attr in _MONITOR_ONLY_ATTRIBUTES
        and isinstance(attr.ctx, ast.Load)
        # the Monitor's methods on a receiver the run shows is the env or its wrapper stack
        # only: an untraced one (a layer looked up by name, GM611) is another item's
        and (known or (kind is EnvKind.UNKNOWN and attr.attr == "videos") or family.origins.outer_is_wrapper(attr.value))
        # the Monitor's methods: also where it is RecordEpisodeStatistics already (an env
        # that gives no frames, a later round of the run, a second run), so the read stays reported
        and _records_with_gym_monitor(family.facts, ("Monitor", "RecordVideo") if attr.attr == "videos" else _REPLACEMENTS)
    )


def report_monitor_videos(family: ForwardingFamily, attr: ast.Attribute) -> None:
    if attr.attr != "videos":
        # the Monitor's own methods and recorders: nothing in the stack that replaces it
        # has them, and none has a certain equivalent (RecordEpisodeStatistics keeps the
        # last episodes only), so the use is a person's to rebuild
        family.report(
            attr,
            "GM604",
            f"`{dotted_name(attr) or attr.attr}` was gym Monitor's own: neither RecordEpisodeStatistics nor RecordVideo, "
            "which replace the Monitor here, has it (AttributeError on Gymnasium, through `get_wrapper_attr` too); left "
            "as it is: rebuild it on RecordEpisodeStatistics's `episode_count`, `return_queue`, `length_queue` (the last "
            "100 episodes), or drop it",
            kind=FixKind.FLAG,
        )
        return
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


def _records_with_gym_monitor(facts: ModuleFacts, wrappers: tuple[str, ...]) -> bool:
    """This module wraps an env in gym's ``Monitor`` or in one of the ``wrappers`` that
    replace it (a later pass of the run, or a second run, sees those)."""

    def scan() -> bool:
        for node in facts.parents:
            if isinstance(node, ast.Call) and isinstance(node.func, (ast.Name, ast.Attribute)):
                last = node.func.id if isinstance(node.func, ast.Name) else node.func.attr
                if last in wrappers and any(
                    (N.strip_gym_prefix(q) or "").startswith("wrappers.") for q in facts.qualified_names(node.func)
                ):
                    return True
        return False

    return bool(facts.memo(("records-with-gym-monitor:" + ",".join(wrappers), id(facts.tree)), scan))


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
