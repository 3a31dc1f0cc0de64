"""Editing a call's arguments in the call's own layout, for ``build`` callbacks.

Rules that add or drop a keyword (``render_mode=``, ``autoreset_mode=``) must keep the
user's commas, spacing and one-argument-per-line layout, or the diff grows noisy.
"""

from __future__ import annotations

from collections.abc import Callable

from gymmigrate.edits.lazy import cst


def append_keyword(call: cst.Call, name: str, value: cst.BaseExpression) -> cst.Call:
    """Add ``name=value`` as the last argument, in the call's own layout.

    In a one-line call it follows ``, ``; in a call with one argument per line it gets
    its own line with the same indentation and the trailing comma is kept.
    """
    new_arg = cst.Arg(
        keyword=cst.Name(name),
        value=value,
        equal=cst.AssignEqual(whitespace_before=cst.SimpleWhitespace(""), whitespace_after=cst.SimpleWhitespace("")),
    )
    args = list(call.args)
    if not args:
        return call.with_changes(args=[new_arg])
    last = args[-1]
    if isinstance(last.comma, cst.Comma):
        # Trailing comma: the separator before ``last`` carries the per-line indentation.
        if len(args) >= 2 and isinstance(args[-2].comma, cst.Comma):
            separator = args[-2].comma
        else:
            separator = cst.Comma(whitespace_after=call.whitespace_before_args)
        args[-1] = last.with_changes(comma=separator)
        args.append(new_arg.with_changes(comma=last.comma))
    else:
        # One argument per line without a trailing comma: the new one gets a line of its own.
        previous = args[-2].comma if len(args) >= 2 else None
        if isinstance(previous, cst.Comma) and isinstance(previous.whitespace_after, cst.ParenthesizedWhitespace):
            separator = previous
        else:
            separator = cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))
        args[-1] = last.with_changes(comma=separator)
        args.append(new_arg.with_changes(whitespace_after_arg=last.whitespace_after_arg))
        args[-2] = args[-2].with_changes(whitespace_after_arg=cst.SimpleWhitespace(""))
    return call.with_changes(args=args)


def remove_args(call: cst.Call, drop: Callable[[cst.Arg], bool]) -> cst.Call:
    """Drop some arguments, keeping the separators of those that stay."""
    args = list(call.args)
    kept = [arg for arg in args if not drop(arg)]
    if len(kept) == len(args):
        return call
    if not kept:
        return call.with_changes(args=[], whitespace_before_args=cst.SimpleWhitespace(""))
    if args[-1] is not kept[-1]:
        # The old last argument went away: the new last one takes its comma (or none).
        kept[-1] = kept[-1].with_changes(comma=args[-1].comma, whitespace_after_arg=args[-1].whitespace_after_arg)
    return call.with_changes(args=kept)
