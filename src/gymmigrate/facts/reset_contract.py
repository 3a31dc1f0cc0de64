"""A reset contract of the run (GM207): an env's own reset keywords that wrappers pass down.

Legacy envs could take keywords of their own in ``reset`` (``def reset(self, seed=None,
options=None, step_fn=None)``), and wrappers of the project handed them down the chain
(``return self.env.reset(step_fn=self.step)``): gym 0.24's ``Wrapper.reset(**kwargs)``
passed any keyword on. Gymnasium's wrappers, and the ``OrderEnforcing`` and
``PassiveEnvChecker`` that ``make`` puts around every env, take only ``seed`` and
``options``, so the first keyword of its own raises TypeError at the first wrapper
between. Gymnasium's way is ``options``: the keyword travels in that dict and each reset
reads it from there.

The run is the unit: one module defines the env, others the wrappers and the callers.
Each module's summary (``ResetSites``) says which extra keywords its env classes' resets
take, which keywords its ``reset(...)`` calls pass and what, and which sites the rewrite
could not carry (a keyword passed positionally, a required parameter, a call whose
``**kwargs`` may already hold ``options``). ``join`` keeps the keywords some env class of
the run takes and some call of the run passes: those are the contract, rewritten at every
site of the run or, when one site cannot be, at none (one review item names the places).

A keyword whose every value in the run is a wrapper's own ``self.step`` (directly, or the
wrapper's parameter of that name defaulting to it) is a step callable: a legacy
``ob, r, done, info = step_fn(a)`` in the env unpacks a Gymnasium step, five values.
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from dataclasses import dataclass

from gymmigrate.facts.module import FUNCTIONS, ModuleFacts, param_default, walk

STANDARD = frozenset({"self", "seed", "options", "return_info"})


@dataclass(frozen=True)
class ResetSites:
    """One module's part of the contract (``ModuleSummary.reset_sites``)."""

    env_params: frozenset[str] = frozenset()  # extra keywords of its Gym env classes' resets
    passed: frozenset[str] = frozenset()  # extra keywords its ``x.reset(...)`` calls pass
    step_values: frozenset[str] = frozenset()  # keywords passed a wrapper's ``self.step`` here
    other_values: frozenset[str] = frozenset()  # keywords passed anything else here
    blockers: tuple[tuple[str, int], ...] = ()  # (keyword, line) the rewrite cannot carry
    calls: tuple[tuple[str, int], ...] = ()  # (keyword, line) of the ``x.reset(...)`` calls passing it
    # top-level classes this module cannot tell are Gym envs (a base imported from another
    # module of the run) -> the extra keywords of their own resets: the run decides (``join``)
    class_params: tuple[tuple[str, frozenset[str]], ...] = ()

    def __bool__(self) -> bool:
        return bool(self.env_params or self.passed or self.blockers or self.class_params)


@dataclass(frozen=True)
class Contract:
    """The joined contract: the keywords that move into ``options``."""

    keywords: frozenset[str]
    step_callables: frozenset[str]
    blockers: tuple[tuple[str, int, str], ...]  # (path, line, keyword) of sites no rewrite can carry
    calls: tuple[tuple[str, int, str], ...] = ()  # (path, line, keyword) of the calls that pass a keyword


def extra_params(function: ast.FunctionDef | ast.AsyncFunctionDef) -> list[ast.arg]:
    args = function.args
    return [a for a in (*args.posonlyargs, *args.args, *args.kwonlyargs) if a.arg not in STANDARD]


def own_reset(classdef: ast.ClassDef) -> ast.FunctionDef | ast.AsyncFunctionDef | None:
    return next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "reset"), None)


def is_step_value(facts: ModuleFacts, value: ast.expr, keyword: str) -> bool:
    """``self.step``, or the enclosing reset's parameter ``keyword`` whose only other
    binding is ``keyword = self.step`` (``if step_fn is None: step_fn = self.step``)."""
    if _self_step(value):
        return True
    if not isinstance(value, ast.Name) or value.id != keyword:
        return False
    function = facts.enclosing_function(value)
    if function is None or function.name != "reset" or not any(a.arg == keyword for a in extra_params(function)):
        return False
    assigned = [
        node.value
        for node in walk(function)
        if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == keyword for t in node.targets)
    ]
    others = [node for node in walk(function) if isinstance(node, (ast.AugAssign, ast.AnnAssign, ast.NamedExpr, ast.For))]
    if any(isinstance(target := getattr(n, "target", None), ast.Name) and target.id == keyword for n in others):
        return False
    return bool(assigned) and all(_self_step(a) for a in assigned)


def _self_step(value: ast.AST) -> bool:
    return isinstance(value, ast.Attribute) and value.attr == "step" and isinstance(value.value, ast.Name) and value.value.id == "self"


def forwards_kwargs(facts: ModuleFacts, call: ast.Call) -> bool:
    """``x.reset(k=v, **kwargs)`` in a reset whose own ``**kwargs`` those are: the rewrite
    gives that reset an ``options`` parameter, so ``kwargs`` no longer holds one."""
    starred = [kw for kw in call.keywords if kw.arg is None]
    if not starred:
        return True
    function = facts.enclosing_function(call)
    if function is None or function.name != "reset" or function.args.kwarg is None or len(starred) != 1:
        return False
    value = starred[0].value
    return isinstance(value, ast.Name) and value.id == function.args.kwarg.arg


def sites(facts: ModuleFacts, is_env_class: Callable[[ast.ClassDef], bool]) -> ResetSites:
    """``is_env_class(classdef)``: a Gym env class (the receivers' answer)."""
    env_params: set[str] = set()
    blockers: list[tuple[str, int]] = []
    class_params: list[tuple[str, frozenset[str]]] = []
    top = {id(n) for n in facts.tree.body if isinstance(n, ast.ClassDef)}
    for classdef in [n for n in walk(facts.tree) if isinstance(n, ast.ClassDef)]:
        reset = own_reset(classdef)
        if reset is None:
            continue
        extras = extra_params(reset)
        if extras and is_env_class(classdef):
            env_params.update(a.arg for a in extras)
        elif extras and id(classdef) in top:
            class_params.append((classdef.name, frozenset(a.arg for a in extras)))
        for param in extras:
            if param in reset.args.posonlyargs or param_default(reset, param) is None or reset.args.vararg is not None:
                blockers.append((param.arg, reset.lineno))
    passed: set[str] = set()
    calls: list[tuple[str, int]] = []
    step_values: set[str] = set()
    other_values: set[str] = set()
    for call in facts.attribute_calls.get("reset", []):
        named = [kw for kw in call.keywords if kw.arg is not None and kw.arg not in STANDARD]
        for kw in named:
            passed.add(kw.arg)  # type: ignore[arg-type]
            calls.append((kw.arg, call.lineno))  # type: ignore[arg-type]
            (step_values if is_step_value(facts, kw.value, kw.arg) else other_values).add(kw.arg)  # type: ignore[arg-type]
            if not forwards_kwargs(facts, call) or any(isinstance(a, ast.Starred) for a in call.args):
                blockers.append((kw.arg, call.lineno))  # type: ignore[arg-type]
    return ResetSites(
        frozenset(env_params),
        frozenset(passed),
        frozenset(step_values),
        frozenset(other_values),
        tuple(blockers),
        tuple(calls),
        tuple(class_params),
    )


def join(parts: list[tuple[str, ResetSites]], is_env_class: Callable[[str, str], bool] = lambda path, name: False) -> Contract | None:
    """The contract of the run from each module's sites (path, sites); None without one.
    ``is_env_class(path, name)``: the run shows that top-level class to be a Gym env (its
    module alone could not tell, ``class TaskEnv(BaseSim)`` with ``BaseSim`` imported): its
    reset's keywords count as an env's too, or a caller elsewhere passing one through the
    wrappers would keep it and raise TypeError at the first of them."""
    env_params = frozenset().union(
        *(s.env_params for _, s in parts),
        *(params for path, s in parts for name, params in s.class_params if is_env_class(path, name)),
    )
    passed = frozenset().union(*(s.passed for _, s in parts))
    keywords = env_params & passed
    if not keywords:
        return None
    step = frozenset().union(*(s.step_values for _, s in parts))
    other = frozenset().union(*(s.other_values for _, s in parts))
    blockers = tuple(
        (path, line, keyword) for path, s in parts for keyword, line in s.blockers if keyword in keywords
    )
    calls = tuple((path, line, keyword) for path, s in parts for keyword, line in s.calls if keyword in keywords)
    return Contract(keywords, frozenset(k for k in keywords if k in step and k not in other), blockers, calls)
