"""Env classes that give no frames: their ``metadata`` declares render modes without
``"rgb_array"`` (or ``"ansi"``, the text frames legacy video recording also took).

Legacy gym's ``Monitor`` looked at those modes when it was built and, for such an env,
switched its video recorder off and wrote statistics only. Gymnasium's ``RecordVideo``
has no such switch: it needs ``render_mode="rgb_array"`` at the make, which such an env
cannot honour. So the rewrite of a ``Monitor`` over one is its statistics alone
(rules/wrapper_usage/monitor.py), and no make gets a frame mode for it
(rules/rendering/recorders.py).

A class's modes are the ``"render.modes"`` / ``"render_modes"`` list of the ``metadata``
dict its own body assigns, all literal strings; a class that assigns none has those of
its base where it has exactly one (gym's ``Env`` itself declares none, so a chain that
ends there without a declaration proves nothing). A module alone follows its own
classes; a run follows the classes of every module (``ModuleSummary.frame_classes``,
``RenderView.declares_no_frames``).
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.facts.creation import CreationFinder
from gymmigrate.facts.made_holders import is_make
from gymmigrate.facts.module import ModuleFacts, call_argument, string_value

if TYPE_CHECKING:
    from gymmigrate.facts.receivers import Receivers

_MODE_KEYS = ("render.modes", "render_modes")
# what a legacy video recorder could record: frames, or text frames
FRAME_MODES = frozenset({"rgb_array", "ansi"})
# Far longer than any real chain of env base classes.
_MAX_CHAIN = 20


def metadata_modes(classdef: ast.ClassDef) -> tuple[str, ...] | None:
    """The render modes ``metadata = {...}`` in the class body declares; None where the body
    assigns no such dict, or one whose modes are not all literal strings."""
    found: tuple[str, ...] | None = None
    for statement in classdef.body:
        if not (
            isinstance(statement, (ast.Assign, ast.AnnAssign))
            and any(isinstance(t, ast.Name) and t.id == "metadata" for t in _targets(statement))
        ):
            continue
        value = statement.value
        if not isinstance(value, ast.Dict):
            return None  # built otherwise: not read here
        found = None
        for key, modes in zip(value.keys, value.values):
            if isinstance(key, ast.Constant) and key.value in _MODE_KEYS:
                if not isinstance(modes, (ast.List, ast.Tuple)):
                    return None
                strings = [string_value(m) for m in modes.elts]
                if any(s is None for s in strings):
                    return None
                found = tuple(s for s in strings if s is not None)
    return found


def _targets(statement: ast.Assign | ast.AnnAssign) -> list[ast.expr]:
    return list(statement.targets) if isinstance(statement, ast.Assign) else [statement.target]


def frame_classes(facts: ModuleFacts) -> dict[str, tuple[str, ...] | None]:
    """For the summary: each top-level class that declares render modes (-> them) or has
    exactly one base to inherit them from (-> None)."""
    found: dict[str, tuple[str, ...] | None] = {}
    for name, classdef in facts.classes.items():
        modes = metadata_modes(classdef)
        if modes is not None or len(classdef.bases) == 1:
            found[name] = modes
    return found


def local_declares_no_frames(facts: ModuleFacts, classdef: ast.ClassDef) -> bool:
    """This module's class, or the one base of this module it inherits its metadata from,
    declares render modes and none is a frame mode."""
    for _ in range(_MAX_CHAIN):
        modes = metadata_modes(classdef)
        if modes is not None:
            return not FRAME_MODES & set(modes)
        if len(classdef.bases) != 1 or not isinstance(classdef.bases[0], ast.Name):
            return False
        base = facts.classes.get(classdef.bases[0].id)
        if base is None:
            return False
        classdef = base
    return False


def frameless_env(facts: ModuleFacts, receivers: Receivers, env: ast.expr) -> str | None:
    """The names of the env classes behind ``env`` where every path from it ends in a make
    of a registered id or a construction whose class declares no frame mode; None where one
    path does not (or is not followed to its end)."""
    finder = facts.memo(("frameless-finder", 0), lambda: CreationFinder(facts, receivers, lambda call: _creation(facts, receivers, call)))
    creation = finder.find(env)
    if not creation.complete or not creation.calls:
        return None
    names: set[str] = set()
    for call in creation.calls:
        name = _frameless_class(facts, receivers, call)
        if name is None:
            return None
        names.add(name)
    return ", ".join(f"`{n}`" for n in sorted(names))


def _creation(facts: ModuleFacts, receivers: Receivers, call: ast.Call) -> bool:
    if is_make(facts, call) or receivers.local_class(call.func) is not None:
        return True
    view = receivers.project
    return view is not None and any(view.class_where(q) is not None for q in facts.qualified_names(call.func))


def _frameless_class(facts: ModuleFacts, receivers: Receivers, call: ast.Call) -> str | None:
    view = receivers.project
    if is_make(facts, call):
        env_id = string_value(call_argument(call, 0, "id"))
        where = view.class_of_id(env_id) if view is not None and env_id is not None else None
        return where[1] if where is not None and view is not None and view.declares_no_frames(where) else None
    local = receivers.local_class(call.func)
    if local is not None:
        if view is not None and local.name in facts.classes:
            where = (view.path, local.name)
            return local.name if view.declares_no_frames(where) else None
        return local.name if local_declares_no_frames(facts, local) else None
    if view is None:
        return None
    for qualified in facts.qualified_names(call.func):
        found = view.class_where(qualified)
        if found is not None and view.declares_no_frames(found):
            return found[1]
    return None
