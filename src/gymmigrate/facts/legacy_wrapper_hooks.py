"""gym < 0.9 API hooks of a Gym wrapper that must stay dead (GM616, ``rules/legacy_hooks.py``).

Before gym 0.9.6 ``Wrapper.step`` called ``self._step(action)``, so a wrapper overrode the
hook; GM616 renames such a ``_step`` to ``step``, which Gymnasium calls. From gym 0.10 on
the hook was dead code: the wrapper behaved as its base wrapper class. A hook whose body
reads private names of that base which Gymnasium's class of it does not have (gym 0.9's
``TimeLimit._episode_started_at`` and ``_past_limit()``) was written for those internals:
renamed, it would raise AttributeError on its first call. It stays as it is, dead, and
the class keeps behaving as Gymnasium's base class does; the call-site rules leave its
body alone too (a person ports it, or deletes it).
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.facts import names as N
from gymmigrate.facts.module import FUNCTIONS, walk
from gymmigrate.facts.wrapper_attributes import self_defined

if TYPE_CHECKING:
    from gymmigrate.facts.receivers import Receivers

# gym < 0.9's wrapper hooks and the public names Gymnasium's wrappers call instead.
API_HOOKS = {"_step": "step", "_reset": "reset", "_render": "render", "_seed": "seed", "_close": "close"}

# Private names Gymnasium's wrapper base classes have (1.4: ``dir()`` of the class and
# ``vars()`` of an instance), by the class's last name.
_WRAPPER_PRIVATE = frozenset(
    {"_action_space", "_observation_space", "_metadata", "_cached_spec", "_np_random", "_np_random_seed",
     "_saved_kwargs", "_is_protocol"}
)  # fmt: skip
BASE_WRAPPER_PRIVATE = {
    "Wrapper": _WRAPPER_PRIVATE,
    "ObservationWrapper": _WRAPPER_PRIVATE,
    "ActionWrapper": _WRAPPER_PRIVATE,
    "RewardWrapper": _WRAPPER_PRIVATE,
    "TimeLimit": _WRAPPER_PRIVATE | {"_elapsed_steps", "_max_episode_steps"},
}
_CORE_WRAPPERS = frozenset({"Wrapper", "ObservationWrapper", "ActionWrapper", "RewardWrapper"})


def dead_hook_internals(receivers: Receivers, function: ast.AST) -> tuple[str, tuple[str, ...]] | None:
    """For a gym < 0.9 hook (``_step``...) of a Gym wrapper class that no public name of the
    class or of a base of the run overrides, and whose body reads private names that neither
    the class nor a base of this module defines, nor Gymnasium's class of its library base
    has: that base's last name and the names read (``self._past_limit()`` with its call).
    None for anything else, and where a base is not a Gym wrapper class whose private names
    are known (a class of another module)."""
    facts = receivers.facts
    return facts.memo(("dead-hook-internals", id(function)), lambda: _dead_hook_internals(receivers, function))


def in_dead_hook(receivers: Receivers, node: ast.AST) -> bool:
    """``node`` is in the body of such a hook: the call-site rules leave it as it is."""
    function = receivers.facts.enclosing_function(node)
    return function is not None and function.name in API_HOOKS and dead_hook_internals(receivers, function) is not None


def _dead_hook_internals(receivers: Receivers, function: ast.AST) -> tuple[str, tuple[str, ...]] | None:
    facts = receivers.facts
    classdef = facts.parent(function)
    if not isinstance(function, FUNCTIONS) or function.name not in API_HOOKS or not isinstance(classdef, ast.ClassDef):
        return None
    public = API_HOOKS[function.name]
    if any(isinstance(s, FUNCTIONS) and s.name == public for s in classdef.body) or public in receivers.base_methods(classdef):
        return None  # not dead: the class's own step, or a base's, calls it
    if not receivers.is_gym_wrapper_class(classdef):
        return None
    base = _library_base(receivers, classdef)
    if base is None:
        return None
    defined = {name for current in receivers.local_lineage(classdef) for name in self_defined(current)}
    gone: set[str] = set()
    for node in walk(function):
        if not (
            isinstance(node, ast.Attribute)
            and isinstance(node.ctx, ast.Load)
            and isinstance(node.value, ast.Name)
            and node.value.id == "self"
            and node.attr.startswith("_")
            and not node.attr.startswith("__")
        ):
            continue
        if node.attr in defined or node.attr in BASE_WRAPPER_PRIVATE[base]:
            continue
        call = facts.parent(node)
        gone.add(f"self.{node.attr}()" if isinstance(call, ast.Call) and call.func is node else f"self.{node.attr}")
    return (base, tuple(sorted(gone))) if gone else None


def _library_base(receivers: Receivers, classdef: ast.ClassDef) -> str | None:
    """The one Gym wrapper class ``classdef`` derives from through bases of this module, by
    its last name, where Gymnasium's private names of it are known."""
    facts = receivers.facts
    found: str | None = None
    for current in receivers.local_lineage(classdef):
        for base in current.bases:
            if receivers.local_class(base) is not None:
                continue  # local_lineage visits it
            rests = [rest for q in facts.qualified_names(base) if (rest := N.strip_gym_prefix(q)) is not None]
            if not rests:
                return None  # a class of another module, or another library's
            rest = rests[0]
            name = rest.rsplit(".", 1)[-1]
            known = rest.startswith("wrappers.") or rest in _CORE_WRAPPERS or rest.removeprefix("core.") in _CORE_WRAPPERS
            if not known or name not in BASE_WRAPPER_PRIVATE or found not in (None, name):
                return None
            found = name
    return found
