"""``Monitor`` is gone (GM611): ``RecordVideo(RecordEpisodeStatistics(env), video_folder=dir, ...)``.

gym 0.23 removed ``gym.wrappers.Monitor``. Its statistics are ``RecordEpisodeStatistics``
and its videos ``RecordVideo``, which needs frames: the env must be made with
``render_mode="rgb_array"``. Stable-Baselines3's ``Monitor`` is another class and is
never touched (SB108); ``Monitor(..., video_callable=False)`` recorded no video and
becomes ``RecordEpisodeStatistics`` alone, and so does a Monitor over an env whose class
declares no frame mode (``facts/frame_modes.py``): legacy Monitor switched its video
recorder off for such an env, and the rendering family gives its make no mode either.

The render mode is part of the same decision, taken on the original source like every
other. Where the env's ``make`` call is found (every path from the env argument ends in
one, none passes ``render_mode`` or ``**kwargs``) and nothing else in the file may want
a mode (no ``render()`` call, no other frame consumer), this family adds
``render_mode="rgb_array"`` there itself and reports it as GM407, the rendering rule's
code, as the rendering rules would have.
The makes it gives a mode are recorded in ``notes.render_modes_added``, which the
rendering family reads, so that no make gets a second one.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
from typing import TYPE_CHECKING

from gymmigrate.edits.arguments import append_keyword
from gymmigrate.edits.lazy import cst
from gymmigrate.edits.syntax import dotted_node
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.frame_modes import frameless_env
from gymmigrate.facts.module import dotted_name, keyword
from gymmigrate.findings import FixKind, Tier, recorder_mode_question
from gymmigrate.rules.wrapper_usage.arguments import positional

if TYPE_CHECKING:
    from gymmigrate.rules.wrapper_usage.stacks import StacksFamily

RGB_ARRAY = "rgb_array"
_MONITOR_PARAMETERS = ("env", "directory", "video_callable", "force", "resume", "write_upon_reset", "uid", "mode")
_OTHER_FRAME_CONSUMERS = ("RecordVideo", "VecVideoRecorder", "play(")
_DROPPED = ("force", "resume", "write_upon_reset", "uid", "mode")


@dataclass(frozen=True)
class MonitorRewrite:
    """What ``Monitor(...)`` becomes: the names it uses (for the imports) and whether it records video."""

    uses: tuple[str, ...]


def plan_monitor(family: StacksFamily, call: ast.Call) -> MonitorRewrite | None:
    """Decide one ``Monitor(...)`` call; None when it is only reported."""
    func = call.func
    prefix = ""
    if isinstance(func, ast.Attribute):
        prefix = (dotted_name(func.value) or "") + "."
        if prefix.endswith(".monitor."):
            prefix = prefix[: -len("monitor.")]
    args = positional(call)
    values: dict[str, ast.expr] = dict(zip(_MONITOR_PARAMETERS, args))
    for kw in call.keywords:
        if kw.arg is not None:
            values[kw.arg] = kw.value
    starred = any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords)
    if not args or starred or values.get("env") is None or values.get("directory") is None:
        family.report(call, "GM611", "Monitor is gone: wrap with RecordEpisodeStatistics and RecordVideo", kind=FixKind.FLAG)
        return None
    env = values["env"]
    trigger = values.get("video_callable")
    # ``force`` cleared the folder's old monitor files; RecordVideo writes over what is there
    # (with a warning), so dropping it keeps the behaviour: no question, only the note.
    # ``mode`` ("training"/"evaluation") only labelled the episodes in the Monitor's own
    # statistics files, which nothing in Gymnasium writes: dropping it changes nothing the
    # program can see, so it is explained, not asked (as ``force``).
    dropped = sorted(k for k in values if k in _DROPPED and k not in ("force", "mode"))
    note = ""
    if dropped:
        listed = ", ".join(f"`{k}`" for k in dropped)
        note = f"; {listed} {'has' if len(dropped) == 1 else 'have'} no equivalent and {'was' if len(dropped) == 1 else 'were'} dropped"
    explained = "; `force` was dropped (RecordVideo writes over the folder's files)" if "force" in values else ""
    if "mode" in values:
        explained += "; `mode` was dropped (it only labelled the Monitor's statistics files, which Gymnasium does not write)"
    # Where each value sits in the call, to find its LibCST counterpart in the build.
    where = {name: _argument_slot(call, value) for name, value in values.items()}

    with_trigger = trigger is not None and not (isinstance(trigger, ast.Constant) and trigger.value is None)
    # ``env = Monitor(env, d)`` next to ``env = RecordEpisodeStatistics(env)``: the code keeps
    # its own statistics wrapper, so the Monitor's would count every episode twice.
    counted = _statistics_beside(family, call)
    # An env whose class declares render modes without a frame mode: legacy Monitor switched
    # its video recorder off for it and wrote statistics only. RecordVideo has no such switch
    # (it needs render_mode="rgb_array", which the env cannot honour), so the statistics are
    # the faithful rewrite.
    frameless = frameless_env(family.facts, family.receivers, env)
    if frameless is not None or (isinstance(trigger, ast.Constant) and trigger.value is False):
        if frameless is not None:
            if "force" in values:  # nothing records into the folder now
                explained = explained.replace("RecordVideo writes over the folder's files", "it cleared the folder's Monitor files, which nothing writes now")
            # the folder read elsewhere (a plotter of the Monitor's statistics files, a copy
            # of them): nothing writes those files now, which a person must know
            elsewhere = _read_elsewhere(family, values["directory"], call)
            if elsewhere:
                note += (
                    f"; `{family.facts.segment(values['directory'])}` is read at {elsewhere}: the Monitor's statistics "
                    "files are not written there any more"
                )
            family.report(
                call,
                "GM611",
                f"Monitor over {frameless}, whose metadata declares no \"rgb_array\" render mode, recorded no video, only "
                f"statistics (legacy Monitor switched its video recorder off): "
                + ("the RecordEpisodeStatistics beside it keeps them, so it is its env" if counted else "it is RecordEpisodeStatistics")
                + f"{note}{explained}",
                tier=None if note else Tier.NOTE,
            )
        else:
            family.report(call, "GM611", f"Monitor without videos is RecordEpisodeStatistics{note}{explained}", tier=None if note else Tier.NOTE)

        def stats_only(node: cst.Call) -> cst.BaseExpression:
            if counted and frameless is not None:
                # the RecordEpisodeStatistics beside it counts already; a second would add
                # the episode statistics to info twice (Gymnasium refuses that)
                return _slot_value(node, where["env"])
            return cst.Call(
                func=dotted_node(prefix + "RecordEpisodeStatistics"),
                args=[cst.Arg(value=_slot_value(node, where["env"]))],
                lpar=node.lpar,
                rpar=node.rpar,
            )

        family.plan.replace(call, stats_only)
        return MonitorRewrite(uses=("RecordEpisodeStatistics",) if not (prefix or (counted and frameless is not None)) else ())

    def record_video(node: cst.Call) -> cst.BaseExpression:
        eq = cst.AssignEqual(cst.SimpleWhitespace(""), cst.SimpleWhitespace(""))
        comma = cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))
        inner = _slot_value(node, where["env"])
        stats = inner if counted else cst.Call(func=dotted_node(prefix + "RecordEpisodeStatistics"), args=[cst.Arg(value=inner)])
        new_args = [
            cst.Arg(value=stats, comma=comma),
            cst.Arg(keyword=cst.Name("video_folder"), value=_slot_value(node, where["directory"]), equal=eq),
        ]
        if with_trigger:
            new_args[-1] = new_args[-1].with_changes(comma=comma)
            new_args.append(cst.Arg(keyword=cst.Name("episode_trigger"), value=_slot_value(node, where["video_callable"]), equal=eq))
        return cst.Call(func=dotted_node(prefix + "RecordVideo"), args=new_args, lpar=node.lpar, rpar=node.rpar)

    unclosed = _stepped_never_closed(family, call)
    if unclosed is not None:
        # Legacy Monitor finished its open video at interpreter exit (gym's atexit closer);
        # RecordVideo writes it only in close(), so the last recorded episode is lost.
        note += (
            f"; `{unclosed}` is stepped here and never closed: RecordVideo saves the video it is recording "
            f"only on close() (legacy Monitor saved it at exit), so call {unclosed}.close() when the run ends"
        )
    what = (
        "RecordVideo(env) (the RecordEpisodeStatistics beside it keeps the statistics)"
        if counted
        else "RecordVideo(RecordEpisodeStatistics(env))"
    )
    family.report(
        call,
        "GM611",
        f"Monitor is {what}: the env must be made with render_mode=\"rgb_array\" for videos{note}{explained}",
        tier=None if note else Tier.NOTE,  # dropped arguments are a question; the rest explains the rewrite
        question=recorder_mode_question(call.lineno, call.col_offset) if note else None,
    )
    family.plan.replace(call, record_video)
    _plan_render_mode(family, call, env)
    if prefix:
        return MonitorRewrite(uses=())
    return MonitorRewrite(uses=("RecordVideo",) if counted else ("RecordEpisodeStatistics", "RecordVideo"))


def _stepped_never_closed(family: StacksFamily, call: ast.Call) -> str | None:
    """``env = Monitor(...)`` bound to a plain name that this module steps (``env.step``) and
    never closes: no ``.close()`` on it, no ``with`` over it, and it never leaves the module's
    sight (passed to a call, returned, stored, rebound from), where another place might close
    it. The name, else None."""
    facts = family.facts
    assign = facts.parent(call)
    if not (isinstance(assign, ast.Assign) and assign.value is call and len(assign.targets) == 1):
        return None
    target = assign.targets[0]
    if not isinstance(target, ast.Name):
        return None
    stepped = False
    for read in facts.reads_of(target.id, target):
        if any(a is assign for a in facts.ancestors(read)):
            continue  # ``env = Monitor(env, d)``: the wrapped env, read before this binding exists
        parent = facts.parent(read)
        if isinstance(parent, ast.Attribute) and parent.value is read:
            caller = facts.parent(parent)
            if parent.attr == "close":
                return None
            if parent.attr == "step" and isinstance(caller, ast.Call) and caller.func is parent:
                stepped = True
            continue
        if isinstance(parent, ast.withitem):
            return None
        if not isinstance(parent, (ast.Compare, ast.BoolOp, ast.UnaryOp, ast.JoinedStr, ast.FormattedValue, ast.Expr)):
            return None  # passed on, returned, stored or rebound from: closed elsewhere, maybe
    return target.id if stepped else None


def _read_elsewhere(family: StacksFamily, directory: ast.expr, call: ast.Call) -> str:
    """``line 12, 40`` for the other reads of the folder name ``directory`` in its scope."""
    if not isinstance(directory, ast.Name):
        return ""
    reads = family.facts.scope_of(directory).reads.get(directory.id, [])
    lines = sorted({read.lineno for read in reads if read is not directory and read.lineno != call.lineno})
    return ("line " if len(lines) == 1 else "lines ") + ", ".join(map(str, lines)) if lines else ""


def _statistics_beside(family: StacksFamily, call: ast.Call) -> bool:
    """``name = Monitor(name, ...)`` whose statement is next to ``name =
    RecordEpisodeStatistics(name)`` (just before or just after it) in the same block."""
    facts = family.facts
    statement = facts.parent(call)
    if not (
        isinstance(statement, ast.Assign)
        and statement.value is call
        and len(statement.targets) == 1
        and isinstance(statement.targets[0], ast.Name)
    ):
        return False
    name = statement.targets[0].id
    place = Flow.of(facts).block_of(statement)
    if place is None:
        return False
    body, index = place
    for neighbour in body[max(index - 1, 0) : index + 2]:
        if neighbour is statement or not isinstance(neighbour, ast.Assign) or not isinstance(neighbour.value, ast.Call):
            continue
        wrapped = neighbour.value
        if (
            len(neighbour.targets) == 1
            and isinstance(neighbour.targets[0], ast.Name)
            and neighbour.targets[0].id == name
            and any(q.split(".")[-1] == "RecordEpisodeStatistics" for q in facts.qualified_names(wrapped.func))
            and wrapped.args
            and isinstance(wrapped.args[0], ast.Name)
            and wrapped.args[0].id == name
        ):
            return True
    return False


# -- the render mode at the env's creation --------------------------------------------------------



def _plan_render_mode(family: StacksFamily, consumer: ast.Call, env: ast.expr) -> None:
    makes = family.stacks.creation_makes(env)
    facts = family.facts
    if (
        makes
        # Another render() or frame consumer may want its own mode on the same make: the
        # rendering rules weigh them all, so the mode is theirs to place.
        and not facts.attribute_calls.get("render")
        and not any(word in facts.text for word in _OTHER_FRAME_CONSUMERS)
        and all(keyword(m, "render_mode") is None and not any(k.arg is None for k in m.keywords) for m in makes)
    ):
        # The rendering family's record of makes given a mode in this run (one protocol
        # for every family that adds one), so it does not add a second.
        given = family.notes.render_modes_added
        for make in makes:
            given[id(make)] = RGB_ARRAY
            family.plan.replace(make, _add_render_mode(_quote_of(facts.segment(make))))
            summary = _call_summary(facts, make)
            # reported at the consumer's env argument, not at the consumer call that GM611
            # rebuilds: leaving out one of the two rules leaves out its own edit only
            family.plan.report(
                env,
                "GM407",
                FixKind.ASSIST,
                f'added render_mode="{RGB_ARRAY}" to {summary} so RecordVideo gets frames',
                Tier.NOTE,
            )


def _add_render_mode(quote: str):
    def build(node: cst.Call) -> cst.Call:
        if any(a.keyword is not None and a.keyword.value == "render_mode" for a in node.args):
            return node  # a later family placed one already
        return append_keyword(node, "render_mode", cst.SimpleString(f"{quote}{RGB_ARRAY}{quote}"))

    return build


def _quote_of(text: str) -> str:
    """Write the mode the way the make call already quotes its strings."""
    for char in text:
        if char in "\"'":
            return char
    return '"'


def _call_summary(facts, call: ast.Call) -> str:
    """``gym.make("CartPole-v1", ...)``, as the rendering rules name a make call in a message."""
    first = facts.segment(call.args[0]) if call.args else ""
    more = ", ..." if len(call.args) + len(call.keywords) > 1 else ""
    return f"{facts.segment(call.func)}({first}{more})"


# -- finding arguments again in the LibCST call ---------------------------------------------------


def _argument_slot(call: ast.Call, value: ast.expr) -> tuple[str, int | str]:
    for index, arg in enumerate(a for a in call.args if not isinstance(a, ast.Starred)):
        if arg is value:
            return ("position", index)
    for kw in call.keywords:
        if kw.value is value:
            return ("keyword", kw.arg or "")
    raise ValueError("argument not in call")


def _slot_value(node: cst.Call, slot: tuple[str, int | str]) -> cst.BaseExpression:
    how, key = slot
    if how == "position":
        return [a for a in node.args if a.keyword is None and not a.star][key].value  # type: ignore[index]
    return next(a.value for a in node.args if a.keyword is not None and a.keyword.value == key)
