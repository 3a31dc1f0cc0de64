"""GM207 across the run: an env's own reset keywords that its wrappers pass down move into ``options``.

``facts/reset_contract.py`` joins the run: the keywords some Gym env class's reset takes
beyond seed/options and some ``reset(...)`` call of the run passes. Gymnasium's wrappers
(and the ``OrderEnforcing``/``PassiveEnvChecker`` of ``make``) take only ``seed`` and
``options``, so each such keyword travels in ``options`` instead, at every site:

* a reset of a Gym env or wrapper class that takes the keyword reads it from ``options``
  first (``step_fn = (options or {}).get("step_fn", step_fn)``: its parameter stays, with
  its default, for direct callers); a wrapper's reset without ``options`` gets
  ``*, seed=None, options=None`` (only ``options`` beside its own ``**kwargs``);
* every call passing it puts it into ``options``, merged into the options the call or
  the enclosing reset already has (``options={**(options or {}), "step_fn": step_fn}``),
  and a wrapper's reset hands its seed on.

When one site of the run cannot be carried (the keyword positional, a required parameter,
a call whose ``**kwargs`` may already hold ``options``), no site is: the env class's reset
gets one review item naming the places, and the calls keep their GM207 report. Under rule
selection or a suppression comment the same holds within a file: its sites are kept or
left out together (``together=``), and an env's reset without ``options`` is read from
there only with the signature GM501 gives it (``Need``).
"""

from __future__ import annotations

import ast
import os

from gymmigrate.edits.lazy import cst
from gymmigrate.edits.plan import Need
from gymmigrate.facts.decisions import Action, Decision, receiver_text
from gymmigrate.facts.env_classes import is_super_method_call
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import ModuleFacts, walk
from gymmigrate.facts.receivers import Receivers
from gymmigrate.facts.reset_contract import (
    Contract,
    extra_params,
    join,
    own_reset,
    sites,
)
from gymmigrate.findings import FixKind
from gymmigrate.rules.reset_seed.common import ResetSeedBase

# The contract's changes of a file are made at every place or at none: a keyword moved into
# options at one call and not read from there by the reset it reaches is lost.
_CONTRACT = "GM207 reset contract"
# the calls an item names before it counts the rest
_MAX_LISTED = 8


def run_contract(facts: ModuleFacts, receivers: Receivers) -> Contract | None:
    """The run's reset contract as this module sees it (this module alone without a run)."""
    project = receivers.project
    if project is not None:
        return project.reset_contract()
    return join([("this file", sites(facts, lambda c: receivers.class_kind(c) is EnvKind.GYM_ENV))])


def blocked_params(contract: Contract | None, reset: ast.FunctionDef | ast.AsyncFunctionDef) -> list[str]:
    """The parameters of an env's ``reset`` that the contract names while a site of the run
    blocks it: the GM207 item at that reset carries the decision about them."""
    if contract is None or not contract.blockers:
        return []
    return [a.arg for a in extra_params(reset) if a.arg in contract.keywords]


class ResetContractSites(ResetSeedBase):
    """GM207 (mixed into the family)."""

    def _contract(self) -> Contract | None:
        return run_contract(self.facts, self.receivers)

    def _shown_path(self, path: str) -> str:
        # Like the run's other cross-module items: relative to this module, never the
        # checkout's absolute location (the report must read the same wherever it runs).
        if path == "this file" or not os.path.isabs(path):
            return path
        return os.path.relpath(path, os.path.dirname(os.path.abspath(self.context.path)))

    def _here(self, path: str) -> bool:
        return path == "this file" or os.path.abspath(path) == os.path.abspath(self.context.path)

    def _order(self, place: tuple[str, int]) -> tuple[bool, str, int]:
        return not self._here(place[0]), self._shown_path(place[0]), place[1]

    def _at(self, path: str, line: int) -> str:
        return f"line {line}" if self._here(path) else f"{self._shown_path(path)}:{line}"

    def _place(self, path: str, line: int, keyword: str, reset: ast.FunctionDef | ast.AsyncFunctionDef) -> str:
        if line == reset.lineno and self._here(path):
            return f"this reset's own `{keyword}` parameter"  # not a place elsewhere: its parameter cannot take the value from options
        return f"{self._shown_path(path)}:{line} (`{keyword}=`)"

    @staticmethod
    def _listed(places: list[str]) -> str:
        shown = ", ".join(places[:_MAX_LISTED])
        return shown + (f" and {len(places) - _MAX_LISTED} more" if len(places) > _MAX_LISTED else "")

    def _plan_contract(self) -> frozenset[str]:
        """Plans the contract's edits in this module; the keywords it moved (the calls'
        GM207 reports skip them)."""
        contract = self._contract()
        if contract is None:
            return frozenset()
        resets = [
            (classdef, reset)
            for classdef in walk(self.facts.tree)
            if isinstance(classdef, ast.ClassDef) and (reset := own_reset(classdef)) is not None
        ]
        if contract.blockers:
            for classdef, reset in resets:
                moved = blocked_params(contract, reset)
                if moved and self.receivers.class_kind(classdef) is EnvKind.GYM_ENV:
                    shown = ", ".join(f"`{k}=`" for k in moved)
                    places = ", ".join(self._place(path, line, keyword, reset) for path, line, keyword in contract.blockers)
                    # the calls that pass them are where a person changes something: name them
                    callers = self._listed(
                        [self._at(path, line) for path, line in sorted({(p, n) for p, n, k in contract.calls if k in moved}, key=self._order)]
                    )
                    self.report(
                        reset,
                        "GM207",
                        f"the run passes {shown} down its wrappers to this reset{f' (at {callers})' if callers else ''}, "
                        "which Gymnasium's wrappers and the "
                        "checkers of make() refuse (they take only seed= and options=); not moved into options, because "
                        f"these places cannot be rewritten: {places}",
                        FixKind.FLAG,
                    )
            return frozenset()
        for classdef, reset in resets:
            wrapper = self.receivers.is_gym_wrapper_class(classdef)
            if wrapper or self.receivers.class_kind(classdef) is EnvKind.GYM_ENV:
                self._read_from_options(reset, contract, env=not wrapper)
        for call in self.facts.attribute_calls.get("reset", []):
            passed = tuple(kw.arg for kw in call.keywords if kw.arg is not None and kw.arg in contract.keywords)
            if not passed:
                continue
            if self._parent_reset_takes(call, passed):
                continue  # ``super().reset(step_fn=...)``: no wrapper in between, the parent's parameters stay
            decision = self._contract_decision(call)
            if decision.action is Action.LEAVE:
                continue  # another API's reset (an SB3 VecEnv, a PettingZoo env, a class of the run) takes it
            if decision.action is Action.REPORT:
                shown = ", ".join(f"`{k}=`" for k in passed)
                self.report(
                    call,
                    "GM207",
                    f"{decision.reason}: if it is a Gym env, pass {shown} in options={{...}} (Gymnasium's wrappers and "
                    "the checkers of make() pass only seed= and options= down to the env, whose reset reads them from there)",
                    FixKind.FLAG,
                    question=self.receiver_question(call.func.value, decision),  # type: ignore[attr-defined]
                )
                continue
            self._move_into_options(call, passed, decision)
        return contract.keywords

    def _parent_reset_takes(self, call: ast.Call, passed: tuple[str, ...]) -> bool:
        """``super().reset(k=...)`` (or ``Base.reset(self, k=...)``) in a method of a class
        whose nearest reset above it is a class of the run's own that takes every keyword
        passed as a parameter: a direct call, which no wrapper sits in; that reset keeps
        its parameters (``_read_from_options``)."""
        func = call.func
        if not isinstance(func, ast.Attribute):
            return False
        function = self.facts.enclosing_function(call)
        classdef = self.facts.enclosing_class(function) if function is not None else None
        if classdef is None:
            return False
        if is_super_method_call(call, "reset"):
            bases = list(classdef.bases)
        elif (
            isinstance(func.value, ast.Name)
            and any(isinstance(b, ast.Name) and b.id == func.value.id for b in classdef.bases)
            and call.args
            and isinstance(call.args[0], ast.Name)
            and call.args[0].id == "self"
        ):
            bases = [func.value]
        else:
            return False
        seen: set[int] = set()
        while bases:
            base = bases.pop(0)
            local = self.receivers.local_class(base)
            if local is not None:
                if id(local) in seen:
                    continue
                seen.add(id(local))
                reset = own_reset(local)
                if reset is None:
                    bases.extend(local.bases)
                    continue
                names = {a.arg for a in extra_params(reset)}
                return reset.args.kwarg is not None or set(passed) <= names
            return self._run_reset_takes(base, passed)
        return False

    def _run_reset_takes(self, base: ast.expr, passed: tuple[str, ...]) -> bool:
        """An imported base that is a class of the run whose reset (its own, or the first a
        base of the run up its chain defines) takes every keyword passed as a parameter."""
        project = self.receivers.project
        if project is None:
            return False
        for qualified in self.facts.qualified_names(base):
            if project.class_of_run(qualified) is None:
                continue
            params = project.inherited_params(qualified, "reset")
            return params is not None and set(passed) <= set(params)
        return False

    def _contract_decision(self, call: ast.Call) -> Decision:
        """Whose reset the call reaches: the keyword is the contract's only on a Gym env (or
        where the file's fallback says so); a receiver the run shows to be something else
        keeps its own keyword, and one nobody can tell is asked about once."""
        receiver = call.func.value  # type: ignore[attr-defined]
        decision, _ = self._decide(receiver, legacy_shape=True)
        if decision.action is Action.LEAVE and self._receiver_kind(receiver) is EnvKind.UNKNOWN:
            # not env-like by name, but it passes a keyword of an env's reset of the run
            return Decision(Action.REPORT, f"could not tell whether `{receiver_text(receiver)}` is a Gym env; not rewritten")
        return decision

    def _read_from_options(self, reset: ast.FunctionDef | ast.AsyncFunctionDef, contract: Contract, env: bool) -> None:
        text = self.facts.segment(reset) or ""
        # a reset already reading a keyword from options (a second round, a hand port) keeps it
        moved = [a.arg for a in extra_params(reset) if a.arg in contract.keywords and f'.get("{a.arg}"' not in text]
        if not moved:
            return
        args = reset.args
        names = {a.arg for a in (*args.posonlyargs, *args.args, *args.kwonlyargs)}
        needs = None
        if "options" not in names and env:
            needs = _env_signature(reset)  # an env's signature is the custom env rules'
        elif "options" not in names:
            added = ["options"] if args.kwarg is not None or "seed" in names else ["seed", "options"]
            self.plan.replace(reset, lambda node, added=added: _keyword_params(node, added))
        lines = [f'{k} = (options or {{}}).get("{k}", {k})' for k in moved]
        body = reset.body
        if _is_docstring(body[0]) and len(body) > 1:
            self.plan.insert_after(body[0], *lines)
        else:
            self.plan.insert_before(body[0], *lines)
        shown = ", ".join(f"`{k}`" for k in moved)
        self.report(
            reset,
            "GM207",
            f"Gymnasium's wrappers pass only seed= and options= to a reset, so the run's {shown} "
            f"{'travel' if len(moved) > 1 else 'travels'} in `options` now: this reset reads "
            f"{'them' if len(moved) > 1 else 'it'} from there (the parameters stay for direct callers)",
            FixKind.AUTO,
            needs=needs,
            together=_CONTRACT,
        )

    def _move_into_options(self, call: ast.Call, moved: tuple[str, ...], decision: Decision) -> None:
        function = self.facts.enclosing_function(call)
        own = {a.arg for a in (*function.args.posonlyargs, *function.args.args, *function.args.kwonlyargs)} if function else set()
        classdef = self.facts.enclosing_class(function) if function is not None else None
        in_moving_reset = (
            function is not None
            and function.name == "reset"
            and classdef is not None
            and own_reset(classdef) is function
            and any(a.arg in moved for a in extra_params(function))
            # only a Gym env's or wrapper's reset takes part in the contract (``sites``): a
            # batch of envs of the project's own (``def reset(self, task=None)`` of its vec
            # env) keeps its keyword and no ``options`` of its own to hand on
            and self.receivers.class_kind(classdef) is EnvKind.GYM_ENV
        )
        edit = self._edit(call)
        edit.to_options = moved
        passed = {kw.arg for kw in call.keywords}
        needs = None
        if in_moving_reset and "options" not in passed:
            # the enclosing reset has (or is given) ``options``: a caller's options go on down
            edit.options_base = "options"
            if "seed" not in passed and None not in passed and ("seed" in own or function.args.kwarg is None):  # type: ignore[union-attr]
                edit.seed_name = "seed"
            if function is not None and classdef is not None and ("options" not in own or (edit.seed_name and "seed" not in own)):
                # given by the signature edit of that reset: this family's for a wrapper
                # (``_read_from_options``), the custom env rules' for an env
                wrapper = self.receivers.is_gym_wrapper_class(classdef)
                needs = _wrapper_signature(function) if wrapper else _env_signature(function)
        shown = ", ".join(f"`{k}=`" for k in moved)
        self.report(
            call,
            "GM207",
            f"{shown} moved into `options`: Gymnasium's wrappers and the checkers of make() pass only seed= and options= "
            f"down to the env, whose reset reads them from there{self._why(decision)}",
            self._kind(decision, FixKind.AUTO),
            question=self.receiver_question(call.func.value, decision),  # type: ignore[attr-defined]
            needs=needs,
            together=_CONTRACT,
        )


def _env_signature(reset: ast.FunctionDef | ast.AsyncFunctionDef) -> Need:
    return Need("EnvClassFamily", reset, "the `seed` and `options` parameters GM501 gives this env's reset")


def _wrapper_signature(reset: ast.FunctionDef | ast.AsyncFunctionDef) -> Need:
    return Need("ResetSeed", reset, "the `seed` and `options` parameters GM207 gives this wrapper's reset")


def _is_docstring(statement: ast.stmt) -> bool:
    return isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Constant) and isinstance(statement.value.value, str)


def _keyword_params(node: cst.FunctionDef, added: list[str]) -> cst.FunctionDef:
    """``def reset(self, step_fn=None)`` -> ``def reset(self, step_fn=None, *, seed=None, options=None)``."""
    params = node.params
    equal = cst.AssignEqual(cst.SimpleWhitespace(""), cst.SimpleWhitespace(""))
    comma = cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))
    new = [cst.Param(name=cst.Name(name), default=cst.Name("None"), equal=equal) for name in added]
    kwonly = [p.with_changes(comma=comma) for p in params.kwonly_params] + [p.with_changes(comma=comma) for p in new]
    if params.star_kwarg is None:
        kwonly[-1] = kwonly[-1].with_changes(comma=cst.MaybeSentinel.DEFAULT)
    positional = list(params.params)
    if positional:
        positional[-1] = positional[-1].with_changes(comma=comma)
    star = params.star_arg
    if not isinstance(star, cst.Param) and not isinstance(star, cst.ParamStar):
        star = cst.ParamStar(comma=comma)
    return node.with_changes(params=params.with_changes(params=positional, star_arg=star, kwonly_params=kwonly))
