"""Whether a ``x.step(...)`` call can be Gym's step at all, from its arguments.

Gym's ``Env.step`` (legacy or Gymnasium's) and every wrapper's take one action. A step
called with two actions or more (``env.step(action, opponent_action)``, a two-player
package's own signature) is the env's own API, not Gym's: Shimmy's compatibility env takes
one action, and a hand port decides what the second becomes. Nothing about such a call
follows from the Gym migration, unless the run defines the class (then its own step,
migrated in the same run, is what the call reaches).
"""

from __future__ import annotations

import ast
from typing import Protocol

from gymmigrate.facts.module import ModuleFacts


class _Origins(Protocol):
    def run_defined(self, expr: ast.AST) -> bool: ...


def extra_actions(call: ast.Call, facts: ModuleFacts) -> int:
    """How many positional arguments beyond one action ``call`` passes (a starred one
    counts as none: its length is unknown). ``Base.step(self, a)`` hands the method's own
    instance first: that argument is the receiver, not an action."""
    args = call.args
    if any(isinstance(arg, ast.Starred) for arg in args):
        return 0
    function = facts.enclosing_function(call)
    if args and function is not None and isinstance(args[0], ast.Name) and _first_parameter(function) == args[0].id:
        args = args[1:]
    return max(len(args) - 1, 0)


def _first_parameter(function: ast.FunctionDef | ast.AsyncFunctionDef) -> str | None:
    positional = [*function.args.posonlyargs, *function.args.args]
    return positional[0].arg if positional else None


def foreign_step(call: ast.Call, origins: _Origins, facts: ModuleFacts) -> bool:
    """``receiver.step(a, b)`` on an object the run does not define: not Gym's step."""
    func = call.func
    return isinstance(func, ast.Attribute) and extra_actions(call, facts) > 0 and not origins.run_defined(func.value)
