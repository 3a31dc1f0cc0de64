"""How a ``reset``/``seed`` call and its assignment are rewritten in LibCST.

The family decides on ``ast`` and collects, per call, one ``CallEdit`` (drop
``return_info=``, ``seed(s)`` -> ``reset(seed=s)``, add a seed, wrap a numpy seed in
``int()``, take ``[0]`` of the result); the builders here carry it out on the LibCST node
the applier hands over, keeping the user's commas and line breaks.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from gymmigrate.edits.lazy import cst


@dataclass
class CallEdit:
    """Changes to one ``reset``/``seed`` call."""

    to_reset: bool = False  # env.seed(s) -> env.reset(seed=s)
    drop: set[str] = field(default_factory=set)
    # The seed to add, made when the edit is applied (it may come from another statement).
    add_seed: Callable[[], cst.BaseExpression | None] | None = None
    int_seed: bool = False
    index_result: bool = False  # env.reset() -> env.reset()[0]
    # Keywords of the run's reset contract that move into ``options`` (GM207), merged into
    # the call's own ``options=`` or, when it has none, into ``options_base`` (the options
    # of the enclosing reset); ``seed_name`` hands that reset's seed on too.
    to_options: tuple[str, ...] = ()
    options_base: str | None = None
    seed_name: str | None = None

    def build(self, call: cst.Call) -> cst.BaseExpression:
        result: cst.BaseExpression = _apply(call, self)
        if self.index_result:
            return cst.Subscript(value=result, slice=[cst.SubscriptElement(cst.Index(cst.Integer("0")))])
        return result


class SeedValue:
    """The argument of a ``seed(s)`` call that is merged into a later reset.

    The seed statement is removed; its argument (as the user wrote it, with any edit made
    inside it) is taken when the applier passes that call, which comes before the reset
    in the same block, and given to the reset's ``seed=``.
    """

    def __init__(self) -> None:
        self.value: cst.BaseExpression | None = None

    def take(self, call: cst.Call) -> cst.Call:
        self.value = call.args[0].value
        return call

    def get(self, as_int: bool, moved: Callable[[], bool] = lambda: True) -> Callable[[], cst.BaseExpression | None]:
        """``moved()``: whether the seed statement is still removed when the plan is applied
        (rule selection or a suppression comment can keep it, and then its seed stays there)."""

        def value() -> cst.BaseExpression | None:
            if not moved():
                return None
            assert self.value is not None, "the seed statement precedes the reset it is merged into"
            return int_call(self.value) if as_int else self.value

        return value


def unpack_builder(info_name: str, element: int | None) -> Callable[[cst.Assign], cst.Assign]:
    """``obs = env.reset()`` -> ``obs, info = env.reset()`` (``element``: position in a tuple value)."""

    def build(node: cst.Assign) -> cst.Assign:
        target = node.targets[0]
        info = cst.Element(cst.Name(info_name))
        if element is None:
            pair = cst.Tuple(elements=[cst.Element(_grouped(target.target), comma=_comma()), info], lpar=[], rpar=[])
            return node.with_changes(targets=[target.with_changes(target=pair)])
        outer = target.target
        assert isinstance(outer, (cst.Tuple, cst.List))
        elements = list(outer.elements)
        old = elements[element]
        pair = cst.Tuple(elements=[cst.Element(_grouped(old.value), comma=_comma()), info])
        elements[element] = old.with_changes(value=pair)
        return node.with_changes(targets=[target.with_changes(target=outer.with_changes(elements=elements))])

    return build


def seed_literal(seed: int) -> Callable[[], cst.BaseExpression]:
    """The ``--seed`` value as code, for ``CallEdit.add_seed``."""
    return lambda: cst.parse_expression(str(seed))


def seeding_reset(name: str, seed: int) -> cst.SimpleStatementLine:
    """``name.reset(seed=N)`` as a line of its own (the module's newline is used)."""
    call = cst.Call(
        func=cst.Attribute(value=cst.Name(name), attr=cst.Name("reset")),
        args=[seed_keyword(seed_literal(seed)())],
    )
    return cst.SimpleStatementLine(body=[cst.Expr(call)])


def int_call(value: cst.BaseExpression) -> cst.Call:
    return cst.Call(func=cst.Name("int"), args=[cst.Arg(value=value)])


def seed_keyword(value: cst.BaseExpression) -> cst.Arg:
    return cst.Arg(
        value=value,
        keyword=cst.Name("seed"),
        equal=cst.AssignEqual(whitespace_before=cst.SimpleWhitespace(""), whitespace_after=cst.SimpleWhitespace("")),
    )


def _comma() -> cst.Comma:
    return cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))


def _grouped(target: cst.BaseExpression) -> cst.BaseExpression:
    """A tuple target nested in another tuple needs its own parentheses."""
    if isinstance(target, cst.Tuple) and not target.lpar:
        return target.with_changes(lpar=[cst.LeftParen()], rpar=[cst.RightParen()])
    return target


def _apply(call: cst.Call, edit: CallEdit) -> cst.Call:
    args = list(call.args)
    func = call.func
    if edit.drop:
        kept = [arg for arg in args if not (arg.keyword is not None and arg.keyword.value in edit.drop)]
        if kept and kept[-1] is not args[-1]:
            kept[-1] = kept[-1].with_changes(comma=args[-1].comma)
        args = kept
    if edit.to_reset:
        func = func.with_changes(attr=cst.Name("reset"))
        first = args[0]
        if first.keyword is None:
            args = [seed_keyword(first.value).with_changes(comma=first.comma)]
    seed = edit.add_seed() if edit.add_seed is not None else None
    if seed is not None:
        args = _appended(args, seed_keyword(seed), call)
    if edit.int_seed:
        args = [
            arg.with_changes(value=int_call(arg.value)) if arg.keyword is not None and arg.keyword.value == "seed" else arg
            for arg in args
        ]
    if edit.to_options:
        args = _into_options(args, edit)
    return call.with_changes(func=func, args=args)


def _into_options(args: list[cst.Arg], edit: CallEdit) -> list[cst.Arg]:
    """``reset(step_fn=f)`` -> ``reset(options={"step_fn": f})``, merged into options there are."""
    moved = [a for a in args if a.keyword is not None and a.keyword.value in edit.to_options]
    if not moved:
        return args
    entries: list[cst.BaseDictElement] = [
        cst.DictElement(cst.SimpleString(f'"{a.keyword.value}"'), a.value, comma=_comma())  # type: ignore[union-attr]
        for a in moved
    ]
    entries[-1] = entries[-1].with_changes(comma=cst.MaybeSentinel.DEFAULT)
    own = next((a for a in args if a.keyword is not None and a.keyword.value == "options"), None)
    base = own.value if own is not None else (cst.Name(edit.options_base) if edit.options_base else None)
    if base is not None:
        merged = cst.BooleanOperation(base, cst.Or(), cst.Dict([]), lpar=[cst.LeftParen()], rpar=[cst.RightParen()])
        entries.insert(0, cst.StarredDictElement(merged, comma=_comma()))
    value = cst.Dict(entries)
    equal = cst.AssignEqual(whitespace_before=cst.SimpleWhitespace(""), whitespace_after=cst.SimpleWhitespace(""))
    last_comma = args[-1].comma
    result: list[cst.Arg] = []
    for arg in args:
        if arg is own:
            result.append(arg.with_changes(value=value))
        elif arg is moved[0]:
            if edit.seed_name is not None:
                result.append(cst.Arg(cst.Name(edit.seed_name), keyword=cst.Name("seed"), equal=equal, comma=_comma()))
            if own is None:
                result.append(cst.Arg(value, keyword=cst.Name("options"), equal=equal, comma=_comma()))
        elif arg not in moved:
            result.append(arg)
    result = [a if isinstance(a.comma, cst.Comma) else a.with_changes(comma=_comma()) for a in result]
    result[-1] = result[-1].with_changes(comma=last_comma)
    return result


def _appended(args: list[cst.Arg], new: cst.Arg, call: cst.Call) -> list[cst.Arg]:
    if not args:
        return [new]
    last = args[-1]
    if isinstance(last.comma, cst.Comma):
        # A trailing comma (often a multi-line call): the new argument takes over the
        # trailing comma and the previous one gets the separator used between arguments.
        if len(args) >= 2 and isinstance(args[-2].comma, cst.Comma):
            separator = args[-2].comma
        elif isinstance(call.whitespace_before_args, cst.ParenthesizedWhitespace):
            separator = cst.Comma(whitespace_after=call.whitespace_before_args)
        else:
            separator = _comma()
        return [*args[:-1], last.with_changes(comma=separator), new.with_changes(comma=last.comma)]
    return [*args[:-1], last.with_changes(comma=_comma()), new]
