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


class _Origins(Protocol):
    def run_defined(self, expr: ast.AST) -> bool: ...


def extra_actions(call: ast.Call) -> int:
    """How many positional arguments beyond one action ``call`` passes (a starred one
    counts as none: its length is unknown)."""
    if any(isinstance(arg, ast.Starred) for arg in call.args):
        return 0
    return max(len(call.args) - 1, 0)


def foreign_step(call: ast.Call, origins: _Origins) -> bool:
    """``receiver.step(a, b)`` on an object the run does not define: not Gym's step."""
    func = call.func
    return isinstance(func, ast.Attribute) and extra_actions(call) > 0 and not origins.run_defined(func.value)
