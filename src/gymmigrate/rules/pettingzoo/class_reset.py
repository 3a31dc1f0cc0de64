"""PZ105 / PZ106 in custom env classes: ``reset(self, seed=None, options=None)``.

Every ``reset`` takes ``seed=None, options=None`` (PettingZoo 1.23 dropped
``return_info``: of the ``if return_info`` branches the one that returns infos stays), and
a parallel env's ``reset`` returns ``(observations, infos)``. A class that seeds itself in
``seed()``, which PettingZoo no longer calls, calls it from ``reset`` when that does what a
caller's ``env.seed(s)`` before ``env.reset()`` did. ``env_classes.py`` finds the classes.
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.edits.arguments import remove_args
from gymmigrate.edits.lazy import cst
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import own_returns, walk
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.pettingzoo.common import (
    AGENT,
    insert_first,
    with_params,
    without_param,
)

if TYPE_CHECKING:
    from gymmigrate.rules.pettingzoo.env_classes import EnvClasses


def plan_reset(family: EnvClasses, reset: ast.FunctionDef | ast.AsyncFunctionDef, kind: EnvKind, seed: ast.FunctionDef | ast.AsyncFunctionDef | None) -> None:
    dropped: list[ast.If] = []  # the ``if return_info`` tests planned away: their returns are decided
    args = reset.args
    names = [a.arg for a in (*args.posonlyargs, *args.args, *args.kwonlyargs)]
    return_info = next((a for a in args.args if a.arg == "return_info"), None)
    missing = [name for name in ("seed", "options") if name not in names]
    if args.vararg is not None or args.kwarg is not None:
        missing = []
    uses_info = [read for read in family.facts.scopes[reset].reads.get("return_info", [])] if return_info else []
    if return_info is not None and not _plan_return_info_branches(family, uses_info, dropped):
        family.report(reset, "PZ105", "`return_info` was removed in PettingZoo 1.23: return `(observations, infos)` "
                    "by hand", FixKind.FLAG)
        return
    if missing or return_info is not None:
        family.changed()
        family.plan.replace(reset, lambda node: _reset_signature(node, missing))
        family.report(reset, "PZ105", "`reset` takes `seed=None, options=None` (PettingZoo 1.23 dropped `return_info`)",
                    FixKind.AUTO)
    if "seed" in missing and seed is not None:
        doubt = _seed_doubt(seed)
        if doubt is None:
            # ``env.seed(s); env.reset()`` ran the same two bodies in the same order.
            insert_first(family.plan, reset, "if seed is not None:\n    self.seed(seed)")
            family.report(reset, "PZ106", "the env seeds itself in `seed()`, which PettingZoo no longer calls: "
                        "`reset(seed=...)` calls it first, as `env.seed(s)` before `env.reset()` did",
                        FixKind.ASSIST, tier=Tier.NOTE)
        else:
            family.report(reset, "PZ106", "the env seeds itself in `seed()`, which PettingZoo no longer calls, "
                        f"and {doubt}: seed the env from `reset(seed=...)` by hand", FixKind.FLAG)
    if kind is EnvKind.PZ_PARALLEL:
        for returned in own_returns(reset):
            value = returned.value
            if value is None or isinstance(value, ast.Tuple) and len(value.elts) == 2:
                continue
            if _is_reset_of(value) and family.multi_agent.kind(value.func.value) is not None:  # type: ignore[attr-defined]
                continue  # a wrapper handing its env's reset on: that returns the pair already
            if any(family.facts.enclosing(returned, ast.If) is branch for branch in dropped):
                continue
            text = family.facts.segment(value)
            family.replace_text(value, f"{text}, {{{AGENT}: {{}} for {AGENT} in self.agents}}")
            family.report(returned, "PZ105", "a parallel `reset` returns `(observations, infos)` since PettingZoo 1.23",
                        FixKind.AUTO)

def _plan_return_info_branches(family: EnvClasses, reads: list[ast.Name], dropped: list[ast.If]) -> bool:
    """``if not return_info: return obs`` / ``else: ...``: keep the branch that returns infos.

    Decides every read first and plans only when each one is such a test (or the
    keyword that hands ``return_info`` on to a wrapped env); otherwise nothing changes.
    """
    branches: list[tuple[ast.If, bool]] = []  # (the if, keep its body rather than its else)
    handed_on: list[ast.Call] = []
    for read in reads:
        test = family.facts.parent(read)
        if isinstance(test, ast.keyword) and test.arg == "return_info":
            # ``self.env.reset(..., return_info=return_info)``: the keyword goes with the
            # parameter (parallel.py drops it on a PettingZoo env; here on any other).
            call = family.facts.parent(test)
            if isinstance(call, ast.Call) and not (
                isinstance(call.func, ast.Attribute) and family.multi_agent.kind(call.func.value) is not None
            ):
                handed_on.append(call)
            continue
        negated = isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not)
        if isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not):
            branch, test = family.facts.parent(test), test
        else:
            branch, test = test, read
        if not (isinstance(branch, ast.If) and branch.test is test):
            return False
        kept = branch.orelse if negated else branch.body
        if kept and (not family.own_line(kept[0]) or (len(kept) == 1 and isinstance(kept[0], ast.If) and branch.orelse is kept)):
            return False  # ``if x: return obs`` on one line, or an ``elif``: by hand
        branches.append((branch, not negated))
    for call in handed_on:
        family.changed()
        family.plan.replace(call, lambda node: remove_args(node, lambda arg: arg.keyword is not None and arg.keyword.value == "return_info"))
    for branch, keep_body in branches:
        dropped.append(branch)
        family.changed()
        if keep_body:
            family.plan.replace(branch, lambda node: cst.FlattenSentinel(node.body.body))
        elif branch.orelse:
            family.plan.replace(branch, lambda node: cst.FlattenSentinel(node.orelse.body.body))
        else:
            family.plan.remove(branch)
    return True

def _reset_signature(node: cst.FunctionDef, missing: list[str]) -> cst.FunctionDef:
    return with_params(without_param(node, "return_info"), missing)



def _seed_doubt(seed: ast.FunctionDef | ast.AsyncFunctionDef) -> str | None:
    """Why ``self.seed(seed)`` at the top of ``reset`` may not do what a caller's
    ``env.seed(s)`` before ``env.reset()`` did; None when it does."""
    args = seed.args
    positional = [*args.posonlyargs, *args.args][1:]  # after ``self``
    required = len(positional) - len(args.defaults)
    if not positional and args.vararg is None:
        return "its `seed()` takes no seed by position"
    if required > 1 or any(default is None for default in args.kw_defaults):
        return "its `seed()` takes more than the seed"
    if isinstance(seed, ast.AsyncFunctionDef):
        return "its `seed()` is a coroutine"
    for node in walk(seed):
        if (
            isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "reset"
            and isinstance(node.func.value, ast.Name) and node.func.value.id == "self"
        ):
            return "its `seed()` calls `self.reset()` (calling it from `reset` would loop)"
    return None



def _is_reset_of(value: ast.AST) -> bool:
    return isinstance(value, ast.Call) and isinstance(value.func, ast.Attribute) and value.func.attr == "reset"

