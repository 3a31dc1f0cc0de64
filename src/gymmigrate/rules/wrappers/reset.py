"""GM601: a wrapper's ``reset`` override returns ``(obs, info)``.

``return self._process(obs)`` -> ``return self._process(obs), info`` with the info the
reset family unpacked the inner reset into (``notes.reset_info_names``), or
``{}`` when the override has none; ``return f(self.env.reset(**kw))`` gets the inner
reset hoisted into ``obs, info = ...``. Pass-throughs stay. ``def reset(self)`` takes
Gymnasium's ``*, seed=None, options=None``, which outer wrappers always pass, and hands
them on to its inner resets: the seed to the first only (a reset again after another, a
no-op loop's, gets the options; a retry loop drops the seed once used).
"""

from __future__ import annotations

import ast
from collections.abc import Sequence

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.fall_through import may_fall_off
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.module import full_name, own_returns, self_attribute
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.base import RuleFamily
from gymmigrate.rules.wrappers.common import (
    INNER,
    _assigned_names,
    _fresh,
    _inner_call,
    _inner_calls,
    _names_in,
    _parenthesized,
    _single_assign,
    _statements,
    _target_names,
    _tuple,
    arguments_of,
    inner_env_names,
)


class ResetOverrides(RuleFamily):
    """GM601 (mixed into the family; no ``RULES``, so not registered itself)."""

    def _fix_reset(self, classdef: ast.ClassDef, function: ast.FunctionDef | ast.AsyncFunctionDef) -> None:
        self._report_reset_without_result(classdef, function)
        inner = inner_env_names(classdef)  # ``self._env`` kept beside ``self.env``
        bases = classdef.bases  # ``gym.Wrapper.reset(self)``: the base's reset, as ``super()``'s
        noted_info = self.notes.reset_info_names.get(f"{classdef.name}.{function.name}")
        info_name: str | None = None
        completed: set[ast.stmt] = set()  # one-name resets the reset family unpacks into ``obs, info``
        for line in _statements(function.body):
            assign = _single_assign(line)
            if assign is None or _inner_call(assign.value, "reset", inner, bases) is None:
                continue
            target = assign.targets[0]
            targets = _target_names(target)
            if targets is not None and len(targets) == 2 and targets[1] != "_":
                info_name = info_name or targets[1]
            elif isinstance(target, ast.Name) and noted_info is not None:
                info_name = info_name or noted_info
                completed.add(assign)
        passed_on = self._fix_reset_signature(function, inner, bases)
        taken = _names_in(function)
        needs_info_default = False
        for ret in own_returns(function):
            value = ret.value
            if value is None or _inner_call(value, "reset", inner, bases) is not None:
                continue  # a pass-through already returns (obs, info)
            if _retries(value, function):
                # ``return self.reset()`` inside reset (a retry; ``self._reset()`` renamed with
                # its hook): the retry returns (obs, info) itself, so it is passed on whole. It
                # resets again after an inner reset given the seed: the options only, as a
                # reset-again loop's resets get (the seed again would restart the episode).
                if passed_on is not None and isinstance(value, ast.Call) and not value.args and not value.keywords:
                    self.plan.replace(value, _pass_options)
                self.report(ret, "GM601", "reset returns a retry of itself, (obs, info) already: passed on whole, with the options", tier=Tier.NOTE)
                continue
            if _already_pair(value, info_name):
                continue
            calls = _inner_calls(value, "reset", inner, bases)
            if calls:
                self._hoist_reset(ret, calls, taken, passed_on, bases)
                continue
            info_code = "{}"
            if info_name is not None:
                info_code = info_name
                if not self._assigned_before(ret, info_name, function, completed):
                    needs_info_default = True
                    message = (
                        f"reset returns (obs, info): `{info_name}` is the inner reset's info when it ran, else "
                        "an empty dict"
                    )
                else:
                    message = f"reset returns (obs, info) with the inner reset's `{info_name}`"
            else:
                message = (
                    "reset returns (obs, info): this override has no info from an inner reset, so it returns "
                    "an empty dict; pass the inner info on if callers need it"
                )
            # Handing on the inner reset's own info is exact; an empty dict where no inner
            # reset ran is what Gymnasium's own wrappers return: both explain the rewrite.
            self.report(ret, "GM601", message, tier=Tier.NOTE)
            self.plan.replace(
                ret,
                lambda node, code=info_code: node.with_changes(
                    value=_tuple([_parenthesized(node.value), cst.parse_expression(code)])
                ),
            )
        if needs_info_default and info_name is not None:
            body = function.body
            if _is_docstring(body[0]):
                self.plan.insert_after(body[0], f"{info_name} = {{}}")
            else:
                self.plan.insert_before(body[0], f"{info_name} = {{}}")

    def _report_reset_without_result(self, classdef: ast.ClassDef, function: ast.FunctionDef | ast.AsyncFunctionDef) -> None:
        """A reset override that returns nothing on some path (a bare ``return``, the end of its
        body): gym never checked it, but Gymnasium's callers, outer wrappers and vector envs
        unpack ``obs, info = env.reset()``, a TypeError on None. What it should return (the
        inner reset's pair, or its own observation) is the class's decision: one item."""
        abstract = any((full_name(d) or "").endswith("abstractmethod") for d in function.decorator_list)
        if abstract or _placeholder_body(function) or any(isinstance(n, (ast.Yield, ast.YieldFrom)) for n in ast.walk(function)):
            return
        returns = own_returns(function)
        bare = [ret for ret in returns if ret.value is None or (isinstance(ret.value, ast.Constant) and ret.value.value is None)]
        falls = may_fall_off(function.body)
        if not bare and not falls:
            return
        places = [f"line {ret.lineno} (a bare `return`)" for ret in bare] + (["the end of its body"] if falls else [])
        some = len(bare) < len(returns)
        self.report(
            function,
            "GM601",
            f"`{classdef.name}.reset` returns nothing at {' and at '.join(places)}"
            + (", a value elsewhere" if some else "")
            + ": Gymnasium's callers, outer wrappers and vector envs unpack `obs, info = env.reset()`, a TypeError "
            "on None; return the inner reset's `(obs, info)` there (`return self.env.reset(...)` with the arguments it was given), "
            "or an observation of its own with an info dict, by hand",
            FixKind.FLAG,
        )

    def _fix_reset_signature(
        self, function: ast.FunctionDef | ast.AsyncFunctionDef, inner: Sequence[str] = INNER, bases: Sequence[ast.expr] = ()
    ) -> set[int] | None:
        """``def reset(self)`` cannot take the seed/options that every outer wrapper passes.
        The new signature's seed and options go on to the inner resets: the ids of those that
        reset again after another (options only) where the signature is new, else None."""
        args = function.args
        if len(args.args) != 1 or args.posonlyargs or args.kwonlyargs or args.kwarg or args.vararg:
            return None
        # The edits first, then the finding they carry out (how the plan ties an edit to the
        # finding it serves when the run leaves GM601 out: the pass-on must go with it).
        calls = _inner_calls(function, "reset", inner, bases)
        bare = [c for c in calls if not arguments_of(c, bases) and not c.keywords]
        again, reseeded = self._resets_again(function, calls, bare)
        for call in bare:
            self.plan.replace(call, _pass_options if id(call) in again else _pass_seed_and_options)
        for call in reseeded:
            self.plan.insert_after(self.facts.statement_of(call), "seed = None")
        self.plan.replace(function, _keyword_seed_and_options)
        self.report(function, "GM601", _signature_message(calls, [c for c in bare if id(c) in again], reseeded), tier=Tier.NOTE)
        return again

    def _resets_again(self, function: ast.AST, calls: list[ast.Call], bare: list[ast.Call]) -> tuple[set[int], list[ast.Call]]:
        """Which of the ``bare`` inner resets (no arguments yet) run only after another inner
        reset (``obs = self.env.reset()``, then ``if done: self.env.reset()`` in a no-op
        loop): their ids, for the options alone; and which of those given the seed may run
        before a reset given it too, their own loop's next turn included (a retry loop): the
        seed is dropped after them. The legacy env, seeded once by ``env.seed()``, went on to
        a new episode at each further reset; the seed passed again would restart the very
        episode it seeded."""
        flow = Flow.of(self.facts)
        again = {id(c) for c in bare if any(o is not c and flow.always_before(o, c) for o in calls)}
        seeded = [c for c in bare if id(c) not in again]
        reseeded = [c for c in seeded if any(flow.may_run_before(c, o, function) for o in seeded)]
        return again, reseeded

    def _hoist_reset(
        self, ret: ast.Return, calls: list[ast.Call], taken: set[str], passed_on: set[int] | None, bases: Sequence[ast.expr] = ()
    ) -> None:
        """``return f(self.env.reset(**kw))`` -> ``obs, info = self.env.reset(**kw)`` + ``return f(obs), info``."""
        if len(calls) != 1 or self._shares_line(ret):
            self.report(ret, "GM601", "reset must return (obs, info): rewrite this return by hand", kind=FixKind.FLAG)
            return
        call = calls[0]
        obs_name, info_name = _fresh("obs", taken), _fresh("info", taken)
        # The same function of the same observation, and the inner reset's own info: exact.
        self.report(ret, "GM601", f"reset returns (obs, info): the inner reset is unpacked into `{obs_name}, {info_name}`", tier=Tier.NOTE)
        call_text = self.facts.segment(call)
        if passed_on is not None and not arguments_of(call, bases) and not call.keywords:
            keywords = "options=options" if id(call) in passed_on else "seed=seed, options=options"
            if call.args:  # ``Base.reset(self)``: after the instance
                call_text = call_text[: call_text.rindex(")")].rstrip().rstrip(",") + ", " + keywords + ")"
            else:
                call_text = call_text[: call_text.rindex("(") + 1] + keywords + ")"
        self.plan.insert_before(ret, f"{obs_name}, {info_name} = {call_text}")
        spelled = frozenset(self.facts.segment(base) for base in bases)

        def rewrite(node: cst.Return) -> cst.Return:
            from gymmigrate.rules.wrappers.cst_builds import (
                ObservationOf,  # the apply layer: LibCST
            )

            value = node.value.visit(ObservationOf(obs_name, spelled))  # type: ignore[union-attr]
            return node.with_changes(value=_tuple([_parenthesized(value), cst.Name(info_name)]))  # type: ignore[arg-type]

        self.plan.replace(ret, rewrite)

    # -- helpers ----------------------------------------------------------------------------

    def _shares_line(self, statement: ast.stmt) -> bool:
        """``a; return x`` or ``if c: return x``: no room for a line before it."""
        parent = self.facts.parent(statement)
        for field in ("body", "orelse", "finalbody"):
            items = getattr(parent, field, None)
            if isinstance(items, list) and any(item is statement for item in items):
                return any(item is not statement and item.lineno == statement.lineno for item in items) or (
                    getattr(parent, "lineno", None) == statement.lineno and not isinstance(parent, ast.Module)
                )
        return False

    def _assigned_before(
        self, statement: ast.stmt, name: str, function: ast.AST, completed: set[ast.stmt]
    ) -> bool:
        """Is ``name`` surely bound when ``statement`` runs? (an earlier line of an enclosing block)"""
        current: ast.AST = statement
        while current is not function:
            parent = self.facts.parent(current)
            if parent is None:
                return False
            for field in ("body", "orelse", "finalbody"):
                items = getattr(parent, field, None)
                if isinstance(items, list) and any(item is current for item in items):
                    for sibling in items:
                        if sibling is current:
                            break
                        if name in _assigned_names(sibling) or sibling in completed:
                            return True
            current = parent
        return False


def _signature_message(calls: list[ast.Call], again: list[ast.Call], reseeded: list[ast.Call]) -> str:
    said = "reset now takes keyword-only `seed` and `options` (outer wrappers always pass them); "
    if not calls:
        return said + "this override calls no reset of the env it wraps, so they are not used (as the legacy reset took none)"
    said += "they are passed on to the inner reset"
    if again:
        lines = ", ".join(str(line) for line in sorted({c.lineno for c in again}))
        said += f"; the reset that runs again after it (line {lines}) gets the options only"
    if reseeded:
        lines = ", ".join(str(line) for line in sorted({c.lineno for c in reseeded}))
        said += f"; the seed is dropped after the reset that may run again (line {lines})"
    if again or reseeded:
        said += ": a seed starts one episode, not the same one again"
    return said


def _already_pair(value: ast.expr, info_name: str | None) -> bool:
    """``obs, info`` / ``obs, {}``: a reset return that already has Gymnasium's shape."""
    if not isinstance(value, ast.Tuple) or len(value.elts) != 2:
        return False
    last = value.elts[1]
    if isinstance(last, ast.Dict):
        return True
    return isinstance(last, ast.Name) and (last.id == info_name or "info" in last.id.lower())


def _is_docstring(statement: ast.stmt) -> bool:
    return isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Constant) and isinstance(
        statement.value.value, str
    )


def _assign_equal() -> cst.AssignEqual:
    return cst.AssignEqual(cst.SimpleWhitespace(""), cst.SimpleWhitespace(""))


def _comma() -> cst.Comma:
    return cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))


def _pass_seed_and_options(node: cst.BaseExpression) -> cst.BaseExpression:
    # The reset family may already have turned the call into ``self.env.reset()[0]``
    # (its result assigned to one name and used as the observation): seed the call inside.
    if isinstance(node, cst.Subscript):
        return node.with_changes(value=_pass_seed_and_options(node.value))
    if not isinstance(node, cst.Call) or not _bare(node):
        return node
    return node.with_changes(
        args=[
            *_instance(node),
            cst.Arg(keyword=cst.Name("seed"), value=cst.Name("seed"), equal=_assign_equal(), comma=_comma()),
            cst.Arg(keyword=cst.Name("options"), value=cst.Name("options"), equal=_assign_equal()),
        ]
    )


def _retries(value: ast.expr, function: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    """``self.reset(...)`` (or ``self.<the override's own name>(...)``): this reset again."""
    return isinstance(value, ast.Call) and self_attribute(value.func) in ("reset", function.name)


def _pass_options(node: cst.BaseExpression) -> cst.BaseExpression:
    """A reset after the first: the options again, not the seed (see ``_resets_again``)."""
    if isinstance(node, cst.Subscript):
        return node.with_changes(value=_pass_options(node.value))
    if not isinstance(node, cst.Call) or not _bare(node):
        return node
    return node.with_changes(
        args=[*_instance(node), cst.Arg(keyword=cst.Name("options"), value=cst.Name("options"), equal=_assign_equal())]
    )


def _bare(call: cst.Call) -> bool:
    """No arguments, or only the instance ``Base.reset(self)`` hands on (the rule chose the
    call on ``ast``: a lone ``self`` there is that instance)."""
    if not call.args:
        return True
    (only, *rest) = call.args
    return not rest and only.keyword is None and not only.star and isinstance(only.value, cst.Name) and only.value.value == "self"


def _instance(call: cst.Call) -> list[cst.Arg]:
    """``self`` of ``Base.reset(self)``, followed by a comma, or nothing."""
    return [call.args[0].with_changes(comma=_comma())] if call.args else []


def _keyword_seed_and_options(node: cst.FunctionDef) -> cst.FunctionDef:
    """``def reset(self)`` -> ``def reset(self, *, seed=None, options=None)``."""
    params = node.params

    def keyword(name: str) -> cst.Param:
        return cst.Param(name=cst.Name(name), default=cst.Name("None"), equal=_assign_equal())

    return node.with_changes(
        params=params.with_changes(
            params=[params.params[0].with_changes(comma=_comma())],
            star_arg=cst.ParamStar(comma=_comma()),
            kwonly_params=[keyword("seed").with_changes(comma=_comma()), keyword("options")],
        )
    )


def _placeholder_body(function: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    """A body of only a docstring, ``pass``, ``...`` or a ``raise``: a hook for subclasses, no reset to run."""
    body = function.body[1:] if _is_docstring(function.body[0]) else function.body
    return all(
        isinstance(s, (ast.Pass, ast.Raise)) or (isinstance(s, ast.Expr) and isinstance(s.value, ast.Constant) and s.value.value is Ellipsis)
        for s in body
    )
