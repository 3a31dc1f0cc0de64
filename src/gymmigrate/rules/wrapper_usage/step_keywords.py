"""The action passed to a made env's ``step`` by the env class's own keyword (GM606).

``env.step(action_dict=a)`` names the parameter of the env class's ``step(self,
action_dict)``. On what ``make`` returns, the outermost layer is a Gymnasium wrapper, whose
``step(self, action)`` has no such parameter: ``TypeError: OrderEnforcing.step() got an
unexpected keyword argument 'action_dict'``. Where the receiver holds a ``make`` result on
every path and every id made there is one the run registers for a class whose ``step``
takes that keyword first, the action is passed by position, which each layer hands down
to that parameter. Where the receiver may be a wrapper stack the run cannot see through
(an id of another package, wrappers around the make), the call is reported. An env built
by its own class's constructor is left: its ``step`` takes the keyword.
"""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.module import dotted_name, string_value
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.base import RuleFamily
from gymmigrate.rules.wrapper_usage.atari_limits import made_on_every_path
from gymmigrate.rules.wrapper_usage.origins import INNER, MADE, WRAPPED, EnvOrigins

_ACTION = "action"  # the parameter of Gymnasium's Wrapper.step


def decide_step_keyword(family: RuleFamily, origins: EnvOrigins, call: ast.Call) -> None:
    """``x.step(<keyword>=a)`` with no positional argument and a keyword other than ``action``."""
    if call.args or len(call.keywords) != 1 or not isinstance(call.func, ast.Attribute):
        return
    keyword = call.keywords[0].arg
    if keyword is None or keyword == _ACTION:
        return
    receiver = call.func.value
    makes = made_on_every_path(family.facts, receiver)
    text = dotted_name(receiver) or "the env"
    if makes and all(_takes_first(family, make, keyword) for make in makes):
        family.report(
            call,
            "GM606",
            f"`{text}` is what make() returns: its outermost layer is a Gymnasium wrapper, whose step(self, action) "
            f"has no `{keyword}` (TypeError); the action is passed by position, which reaches the env's `{keyword}`",
            FixKind.ASSIST,
            tier=Tier.NOTE,
        )
        family.plan.replace(call, _positional)
        return
    if makes is None and origins.at_read(receiver) not in (MADE, WRAPPED, INNER):
        return  # nothing says a wrapper is outermost: the env's own step may take the keyword
    family.report(
        call,
        "GM606",
        f"`{text}.step({keyword}=...)`: where `{text}` is a wrapper stack (make() returns one), its outermost "
        f"wrapper's step(self, action) has no `{keyword}` and raises TypeError; pass the action by position "
        "if that is what the env's step takes first",
        FixKind.FLAG,
    )


def _takes_first(family: RuleFamily, make: ast.Call, keyword: str) -> bool:
    """The id ``make`` makes is one the run registers for a class whose step takes ``keyword`` first."""
    project = family.receivers.project
    env_id = string_value(make.args[0]) if make.args and not isinstance(make.args[0], ast.Starred) else None
    return project is not None and env_id is not None and project.step_action_of_id(env_id) == keyword


def _positional(node: cst.CSTNode) -> cst.CSTNode:
    assert isinstance(node, cst.Call)
    argument = node.args[0]
    return node.with_changes(args=[argument.with_changes(keyword=None, equal=cst.MaybeSentinel.DEFAULT)])
