"""Changed signatures of the wrappers Gymnasium kept (GM609) and AtariPreprocessing's frame skip (GM615).

One function per 1.x wrapper name, registered with ``@handles("<Name>")``: it decides from the
``ast`` call (reporting through the family) and returns the build that rewrites the
LibCST call, or None when nothing changes. Builds find arguments by keyword and by
position among the positional ones, never by identity, so an edit another family made
to the same call first (``new_step_api=`` dropped by GM305) does not disturb them.

Sources: gymnasium 1.0 release notes; ``FrameStackObservation(env, stack_size, *,
padding_type)``, ``AddRenderObservation(env, render_only, render_key, obs_key)``,
``TransformObservation(env, func, observation_space)``, ``ResizeObservation(env, shape)``,
``RecordEpisodeStatistics(env, buffer_length, stats_key)``, ``TimeLimit(env,
max_episode_steps)``, ``FilterObservation(env, filter_keys)``,
``AtariPreprocessing(env, noop_max, frame_skip, ...)``.
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from typing import TYPE_CHECKING

from gymmigrate.edits.arguments import append_keyword
from gymmigrate.edits.lazy import cst
from gymmigrate.facts.module import keyword, string_value
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.wrapper_usage.atari_limits import atari_make, reaching_make

if TYPE_CHECKING:
    from gymmigrate.rules.wrapper_usage.stacks import StacksFamily

CallBuild = Callable[["cst.Call"], "cst.Call"]
Handler = Callable[["StacksFamily", ast.Call], "CallBuild | None"]

# The 1.x wrapper name -> the function that decides its call's arguments.
HANDLERS: dict[str, Handler] = {}


def handles(wrapper: str) -> Callable[[Handler], Handler]:
    """Register the decorated function as the argument rule for calls of ``wrapper``."""

    def register(function: Handler) -> Handler:
        if wrapper in HANDLERS:
            raise ValueError(f"two argument handlers for {wrapper}")
        HANDLERS[wrapper] = function
        return function

    return register


# -- reading the ast call ----------------------------------------------------------------------


def positional(call: ast.Call) -> list[ast.expr]:
    return [a for a in call.args if not isinstance(a, ast.Starred)]


def has_star(call: ast.Call) -> bool:
    return any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords)


def parameter(call: ast.Call, name: str, position: int) -> ast.expr | None:
    """The value bound to a wrapper parameter, passed by keyword or at ``position``."""
    found = keyword(call, name)
    if found is not None:
        return found.value
    args = positional(call)
    return args[position] if len(args) > position else None


def _is_constant(node: ast.AST | None, value: object) -> bool:
    return isinstance(node, ast.Constant) and type(node.value) is type(value) and node.value == value


def _is_int(node: ast.AST | None) -> bool:
    return isinstance(node, ast.Constant) and type(node.value) is int


def missing_or_none(call: ast.Call, name: str, position: int) -> bool:
    """A required parameter left out (and not possibly in *args/**kwargs) or passed None."""
    found = parameter(call, name, position)
    if found is None:
        return not has_star(call)
    return _is_constant(found, None)


# -- editing the LibCST call -------------------------------------------------------------------


def _cst_keyword(call: cst.Call, name: str) -> cst.Arg | None:
    return next((a for a in call.args if a.keyword is not None and a.keyword.value == name), None)


def _cst_parameter(call: cst.Call, name: str, position: int) -> cst.Arg | None:
    found = _cst_keyword(call, name)
    if found is None:
        args = [a for a in call.args if a.keyword is None and not a.star]
        found = args[position] if len(args) > position else None
    return found


def _renamed(arg: cst.Arg, new: str) -> cst.Arg:
    assert arg.keyword is not None
    return arg.with_changes(keyword=arg.keyword.with_changes(value=new))


def _rename_keyword(call: cst.Call, old: str, new: str) -> cst.Call:
    arg = _cst_keyword(call, old)
    if arg is None:
        return call
    return call.with_changes(args=[_renamed(a, new) if a is arg else a for a in call.args])


def _without(call: cst.Call, drop: cst.Arg) -> cst.Call:
    """The call without ``drop``; the new last argument keeps the old last one's comma."""
    args = [a for a in call.args if a is not drop]
    if args and call.args and args[-1] is not call.args[-1]:
        args[-1] = args[-1].with_changes(comma=call.args[-1].comma)
    return call.with_changes(args=args)


# -- one function per wrapper --------------------------------------------------------------------


@handles("FrameStackObservation")
def args_FrameStackObservation(family: StacksFamily, call: ast.Call) -> CallBuild | None:
    notes = []
    kind: FixKind | None = None
    renames_stack = keyword(call, "num_stack") is not None
    if renames_stack:
        notes.append("`num_stack=` is `stack_size=`")
    lz4 = parameter(call, "lz4_compress", 2)
    if lz4 is not None:
        notes.append("`lz4_compress` is gone (frames are a plain ndarray now)")
        if not _is_constant(lz4, False):
            kind = FixKind.ASSIST
    if not notes:
        return None
    family.report(call, "GM609", "FrameStackObservation: " + "; ".join(notes), kind=kind)
    drops_lz4 = lz4 is not None

    def build(node: cst.Call) -> cst.Call:
        dropped = _cst_parameter(node, "lz4_compress", 2) if drops_lz4 else None
        if renames_stack:
            node = _rename_keyword(node, "num_stack", "stack_size")
        if dropped is not None:
            node = _without(node, next(a for a in node.args if a.value is dropped.value))
        return node

    return build


@handles("AddRenderObservation")
def args_AddRenderObservation(family: StacksFamily, call: ast.Call) -> CallBuild | None:
    if len(positional(call)) > 2 or keyword(call, "render_kwargs") is not None:
        family.report(
            call,
            "GM609",
            "AddRenderObservation has no render_kwargs: create the env with render_mode=\"rgb_array\" (and "
            "its render options) instead, then pass render_only/render_key",
            kind=FixKind.FLAG,
        )
        return None
    keys = keyword(call, "pixel_keys")
    if keys is not None:
        value = keys.value
        if not (isinstance(value, (ast.Tuple, ast.List)) and len(value.elts) == 1):
            family.report(call, "GM609", "AddRenderObservation takes one `render_key`, not a list of pixel keys", kind=FixKind.FLAG)
            return None
    if keys is None and keyword(call, "pixels_only") is None:
        return None

    def build(node: cst.Call) -> cst.Call:
        node = _rename_keyword(node, "pixels_only", "render_only")
        arg = _cst_keyword(node, "pixel_keys")
        if arg is not None and isinstance(arg.value, (cst.Tuple, cst.List)):
            single = arg.value.elements[0].value
            new = arg.with_changes(keyword=cst.Name("render_key"), value=single)
            node = node.with_changes(args=[new if a is arg else a for a in node.args])
        return node

    return build


@handles("TransformObservation")
def args_TransformObservation(family: StacksFamily, call: ast.Call) -> CallBuild | None:
    f = keyword(call, "f")
    args = positional(call)
    has_space = keyword(call, "observation_space") is not None or len(args) >= 3
    func = f.value if f is not None else args[1] if len(args) >= 2 else None
    if has_space:
        if f is None:
            return None
        family.report(call, "GM609", "TransformObservation's `f=` is `func=`")
        return lambda node: _rename_keyword(node, "f", "func")
    if func is None or has_star(call):
        return None
    if _keeps_shape(func):
        family.report(call, "GM609", "TransformObservation needs an observation_space: None keeps the env's, as before")
    else:
        family.report(
            call,
            "GM609",
            "TransformObservation needs an observation_space: None keeps the env's space, as legacy did; pass "
            "the new space if `func` changes the observation's shape or dtype",
            kind=FixKind.ASSIST,
            tier=Tier.NOTE,  # exactly what the legacy wrapper did (it never changed the space)
        )
    by_keyword = f is not None

    def build(node: cst.Call) -> cst.Call:
        node = _rename_keyword(node, "f", "func")
        items = list(node.args)
        last = items[-1]
        comma = cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))
        space = cst.Arg(value=cst.Name("None"))
        if last.keyword is not None or by_keyword:
            space = cst.Arg(
                keyword=cst.Name("observation_space"),
                value=cst.Name("None"),
                equal=cst.AssignEqual(cst.SimpleWhitespace(""), cst.SimpleWhitespace("")),
            )
        return node.with_changes(args=[*items[:-1], last.with_changes(comma=comma), space.with_changes(comma=last.comma)])

    return build


@handles("TransformReward")
def args_TransformReward(family: StacksFamily, call: ast.Call) -> CallBuild | None:
    if keyword(call, "f") is None:
        return None
    family.report(call, "GM609", "TransformReward's `f=` is `func=`")
    return lambda node: _rename_keyword(node, "f", "func")


@handles("ResizeObservation")
def args_ResizeObservation(family: StacksFamily, call: ast.Call) -> CallBuild | None:
    shape = parameter(call, "shape", 1)
    if shape is None or not _is_int(shape):
        return None
    text = family.facts.segment(shape)
    family.report(call, "GM609", f"ResizeObservation takes a (height, width) pair: {text} -> ({text}, {text})")

    def build(node: cst.Call) -> cst.Call:
        arg = _cst_parameter(node, "shape", 1)
        if arg is None:
            return node
        size = arg.value
        pair = cst.Tuple(
            elements=[
                cst.Element(value=size, comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))),
                cst.Element(value=size.deep_clone()),
            ]
        )
        return node.with_changes(args=[arg.with_changes(value=pair) if a is arg else a for a in node.args])

    return build


@handles("RecordEpisodeStatistics")
def args_RecordEpisodeStatistics(family: StacksFamily, call: ast.Call) -> CallBuild | None:
    if keyword(call, "deque_size") is None:
        return None
    family.report(call, "GM609", "RecordEpisodeStatistics' `deque_size=` is `buffer_length=`")
    return lambda node: _rename_keyword(node, "deque_size", "buffer_length")


# RecordVideo's ``new_step_api=`` is GM305's (make_kwargs), which deletes it from every
# wrapper constructor: the LibCST pass this replaces never saw it either.


@handles("TimeLimit")
def args_TimeLimit(family: StacksFamily, call: ast.Call) -> CallBuild | None:
    return time_limit_without_limit(family, call, "TimeLimit")


def time_limit_without_limit(family: StacksFamily, call: ast.Call, name: str) -> CallBuild | None:
    """``TimeLimit(env)``, or a subclass of it that keeps its ``__init__``, built without
    ``max_episode_steps``: legacy TimeLimit read the limit from the spec of the env it
    wrapped (the one ``gym.make`` registered); Gymnasium's requires it (TypeError). Where
    that env is a make result or its ``.env`` (the make certainly reaching the call, no
    ``max_episode_steps`` given to it, no Atari id), the make's ``spec.max_episode_steps``
    is that same limit and is passed; anything else is reported. (The inner layers' own
    spec has no limit on Gymnasium: ``make("Pendulum-v1").env.spec.max_episode_steps`` is
    None, checked on 1.4.)"""
    if not missing_or_none(call, "max_episode_steps", 1):
        return None
    given = parameter(call, "max_episode_steps", 1)
    source = None if given is not None else _made_limit(family, parameter(call, "env", 0))
    if isinstance(source, str):
        family.report(
            call,
            "GM609",
            f"{name} needs max_episode_steps in Gymnasium 1.x (legacy read it from the wrapped env's spec, the "
            f"limit make registered): passed `{source}`, that limit",
            kind=FixKind.AUTO,
        )
        return lambda node: append_keyword(node, "max_episode_steps", cst.parse_expression(source))
    why = f"; {source[1]}" if isinstance(source, tuple) else ""
    family.report(
        call,
        "GM609",
        f"{name} needs max_episode_steps in Gymnasium 1.x (legacy read it from the spec): pass the "
        f"limit, e.g. env.spec.max_episode_steps of the make result{why}",
        kind=FixKind.FLAG,
    )
    return None


def _made_limit(family: StacksFamily, env: ast.expr | None) -> str | tuple[None, str] | None:
    """``X.spec.max_episode_steps`` for an argument ``X`` or ``X.env`` with ``X`` a name a
    make call without ``max_episode_steps`` certainly reaches; (None, why) for an Atari
    make (no limit registered now); None when the argument is anything else."""
    holder = env.value if isinstance(env, ast.Attribute) and env.attr == "env" else env
    if not isinstance(holder, ast.Name):
        return None
    make = reaching_make(family.facts, holder)
    if make is None or any(k.arg in ("max_episode_steps", None) for k in make.keywords) or len(make.args) > 1:
        return None
    atari = atari_make(family.facts, family.receivers, make)
    if atari is not None:
        return None, f"the make's id is an Atari one (`{atari[1]}`), which ale-py registers with no step limit (gym registered one)"
    return f"{holder.id}.spec.max_episode_steps"


@handles("FilterObservation")
def args_FilterObservation(family: StacksFamily, call: ast.Call) -> CallBuild | None:
    if missing_or_none(call, "filter_keys", 1):
        family.report(
            call,
            "GM609",
            "FilterObservation needs filter_keys in Gymnasium 1.x (None no longer means every key): list the keys",
            kind=FixKind.FLAG,
        )
    return None


@handles("ClipAction")
def args_ClipAction(family: StacksFamily, call: ast.Call) -> CallBuild | None:
    # Where the module never reads a space's bounds nor samples one (agents that size their
    # output from ``.shape`` and tell spaces by class), the new space changes nothing here.
    facts = family.facts
    reads_bounds = any(facts.attributes.get(name) for name in ("low", "high", "bounded_below", "bounded_above", "is_bounded"))
    samples = bool(facts.attribute_calls.get("sample"))
    handed = _action_spaces_handed_on(family)
    if handed:
        lines = ", ".join(str(line) for line in handed)
        why = f"; the action space itself leaves this code on line(s) {lines} (stored, returned or passed on), where its bounds may be read"
    else:
        why = "" if reads_bounds or samples else "; nothing in this module reads a space's bounds or samples one"
    family.report(
        call,
        "GM609",
        "ClipAction now exposes action_space Box(-inf, inf): code or agents that read the bounds or sample "
        "from this env's action_space must use the inner env's space" + why,
        kind=FixKind.FLAG,
        tier=None if reads_bounds or samples or handed else Tier.NOTE,
    )
    return None


def _action_spaces_handed_on(family: StacksFamily) -> list[int]:
    """Lines where ``x.action_space`` itself is a value (``self._space = env.action_space``,
    ``return env.action_space``, ``Agent(env.action_space)``) rather than read here for its
    shape or class: whoever receives it (an adapter's ``action_space`` property, a policy)
    may read the bounds ClipAction widened, beyond what this module shows."""
    facts = family.facts
    lines: set[int] = set()
    for node in facts.attributes.get("action_space", []):
        if not isinstance(node.ctx, ast.Load):
            continue
        parent = facts.parent(node)
        if isinstance(parent, ast.Attribute) and parent.value is node:
            continue  # ``.shape``, ``.n``, ``.__class__``: read here
        if isinstance(parent, ast.Subscript) and parent.value is node:
            continue  # one agent's space of a list, read here
        if isinstance(parent, ast.Call) and isinstance(parent.func, ast.Name) and parent.func.id in ("isinstance", "type", "len", "print"):
            continue
        if isinstance(parent, ast.Compare):
            continue
        lines.add(node.lineno)
    return sorted(lines)


@handles("AtariPreprocessing")
def args_AtariPreprocessing(family: StacksFamily, call: ast.Call) -> CallBuild | None:
    """GM615: the base env must not skip frames itself (AtariPreprocessing raises)."""
    if _is_constant(parameter(call, "frame_skip", 2), 1):
        return None
    args = positional(call)
    if not args:
        return None
    make = family.stacks.make_call(args[0])
    if make is None or frameskip_is_one(make):
        return None
    family.report(
        call,
        "GM615",
        "AtariPreprocessing skips frames itself and raises if the base env skips too: make the env with "
        "frameskip=1 (e.g. gym.make(\"ALE/Pong-v5\", frameskip=1))",
    )
    return None




def frameskip_is_one(make: ast.Call) -> bool:
    """Does this make() call build an env that does not skip frames (or can it not be told)?"""
    frameskip = keyword(make, "frameskip")
    if frameskip is not None:
        return _is_constant(frameskip.value, 1)
    args = positional(make)
    env_id = string_value(args[0]) if args else None
    if env_id is None:
        return True  # cannot tell: stay quiet rather than guess
    # ``ALE/X-v5`` skips 4 frames, ``X-v4`` 2-4, ``XDeterministic-v4`` 4; only NoFrameskip ids do not.
    return "NoFrameskip" in env_id


def _keeps_shape(func: ast.expr) -> bool:
    """``lambda obs: obs / 255.0``-like functions: arithmetic with numbers keeps shape (not dtype, see ASSIST)."""
    if not isinstance(func, ast.Lambda):
        return False
    arguments = func.args
    if len(arguments.args) != 1 or arguments.posonlyargs:
        return False
    param = arguments.args[0].arg

    def simple(node: ast.expr) -> bool:
        if isinstance(node, ast.Name):
            return node.id == param
        if isinstance(node, ast.Constant):
            return type(node.value) in (int, float)
        if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub, ast.Mult)):
            return simple(node.left) and simple(node.right)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
            return simple(node.operand)
        return False

    return simple(func.body)
