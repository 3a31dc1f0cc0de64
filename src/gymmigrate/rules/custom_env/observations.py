"""GM508 mujoco-py ``MujocoEnv`` subclasses and GM509 float64 observations (reports only).

Gymnasium's ``MujocoEnv`` needs ``observation_space`` in ``__init__`` and reads
``self.data`` where mujoco-py had ``self.sim.data``: a port by hand. An observation
built with ``np.array(...)`` from Python floats is float64, which ``check_env`` rejects
for a float32 ``Box``.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import names as N
from gymmigrate.facts.env_classes import MUJOCO_BASES, identifiers, is_self_attribute
from gymmigrate.facts.module import own_returns
from gymmigrate.facts.summaries.classes import mujoco_py_uses
from gymmigrate.rules.custom_env.common import ClassDecision, tuple_len


def decide_mujoco(decision: ClassDecision) -> None:
    if decision.env.mujoco_base(decision.classdef) and _uses_mujoco_py(decision):
        decision.report(
            decision.classdef,
            "GM508",
            "mujoco-py MujocoEnv: Gymnasium's MujocoEnv needs observation_space (and render settings) in __init__, and "
            f"self.sim.data becomes self.data; port by hand{_uses_elsewhere(decision)}",
        )
        return
    builtin = decision.env.legacy_mujoco_env_base(decision.classdef)
    if builtin is None:
        return
    relies = _relies_on_mujoco_py_base(decision)
    if relies:
        # The import rules retarget the base to Gymnasium's v4 class of the same name, which
        # runs on the mujoco bindings and fixes its observation space: what the subclass
        # takes from the old base does not carry over, and nothing else says so.
        decision.report(
            decision.classdef,
            "GM508",
            f"subclass of mujoco-py `{builtin}`, whose base becomes Gymnasium's v4 class (mujoco bindings, "
            f"a fixed observation_space, render through mujoco_renderer): it {', '.join(relies)}; port by hand"
            f"{_uses_elsewhere(decision)}",
        )


def _uses_elsewhere(decision: ClassDecision) -> str:
    """The places that read the mujoco-py MujocoEnv's API on an object outside such a class
    (``summaries.classes.mujoco_py_uses``): on an instance of this one they break with it,
    so the one item of the port names them."""
    project = decision.family.receivers.project
    if project is not None:
        places = project.mujoco_py_uses()
    else:
        lines = mujoco_py_uses(decision.family.facts)
        places = [f"line {lines[0]}" + (f" and {len(lines) - 1} more" if len(lines) > 1 else "")] if lines else []
    if not places:
        return ""
    reader = "module" if project is None else "project (the modules its imports connect)"
    more = len(places) - 8
    shown = ", ".join(places[:8]) + (f", and {more} more module{'s' if more > 1 else ''}" if more > 0 else "")
    return (
        f"; the {reader} also reads the mujoco-py API outside its MujocoEnv classes ({shown}): on an instance of this "
        "class those uses change with the port (`model.data` becomes `data`, `model.geom_names.index(n)` "
        "`model.geom(n).id`, `_render(mode)` `render()`)"
    )


def _relies_on_mujoco_py_base(decision: ClassDecision) -> list[str]:
    """What the class takes from a mujoco-py base that Gymnasium's v4 class does not give."""
    found: list[str] = []
    nodes = decision.index.nodes
    attributes = [a for a in nodes.get(ast.Attribute, ()) if isinstance(a, ast.Attribute)]
    if any(is_self_attribute(a.value, ("sim",)) for a in attributes):
        found.append("reads self.sim (self.data on the mujoco bindings)")
    if any(is_self_attribute(a, ("_get_viewer",)) for a in attributes):
        found.append("calls self._get_viewer() (gone: self.mujoco_renderer)")
    if "_get_obs" in decision.methods and "observation_space" not in identifiers(decision.classdef):
        found.append("overrides _get_obs, from which the old base derived observation_space (v4 fixes its shape)")
    if "viewer_setup" in decision.methods:
        found.append("overrides viewer_setup (never called: v4 takes default_camera_config)")
    constructor = _legacy_mujoco_constructor(decision)
    if constructor is not None:
        found.append(
            f"calls `{decision.family.facts.segment(constructor.func)}(...)` on line {constructor.lineno} with mujoco-py's "
            "(model_path, frame_skip), where Gymnasium's MujocoEnv also requires observation_space (TypeError)"
        )
    return found


def _legacy_mujoco_constructor(decision: ClassDecision) -> ast.Call | None:
    """``mujoco_env.MujocoEnv.__init__(self, path, 4)`` in the class: the mujoco-py base's
    constructor called by name, with no ``observation_space`` (the third parameter of
    Gymnasium's, which the import rules make it)."""
    facts = decision.family.facts
    for call in decision.index.nodes.get(ast.Call, ()):
        func = call.func  # type: ignore[attr-defined]
        if not (isinstance(func, ast.Attribute) and func.attr == "__init__"):
            continue
        if not any(N.strip_gym_prefix(q) in MUJOCO_BASES for q in facts.qualified_names(func.value)):
            continue
        args = call.args  # type: ignore[attr-defined]
        if any(isinstance(a, ast.Starred) for a in args) or any(k.arg in (None, "observation_space") for k in call.keywords):  # type: ignore[attr-defined]
            continue
        if len(args) <= 3:  # self, model_path, frame_skip
            return call  # type: ignore[return-value]
    return None


def _uses_mujoco_py(decision: ClassDecision) -> bool:
    nodes = decision.index.nodes
    if any(isinstance(a, ast.Attribute) and is_self_attribute(a.value, ("sim",)) for a in nodes.get(ast.Attribute, ())):
        return True
    if _legacy_mujoco_constructor(decision) is not None:
        return True  # Gymnasium's constructor requires the observation_space this call omits
    return "observation_space" not in identifiers(decision.classdef)


def decide_float64_observations(decision: ClassDecision) -> None:
    if not _declares_float32_box(decision):
        return
    for name in ("reset", "step"):
        function = decision.methods.get(decision.renamed.get(name, name))
        if function is None:
            continue
        for ret in own_returns(function):
            obs = _observation_of(ret.value, name)
            if obs is not None and _is_float64_array(obs) and not _state_is_float32(decision):
                # one question per class: each return building the observation the same way
                # is a note pointing at the first
                decision.report(
                    obs,
                    "GM509",
                    f"observation built with np.array(...) {_built_dtype(obs)} but observation_space is a float32 Box; "
                    "pass dtype=np.float32 (check_env rejects it)",
                    question=("GM509", id(decision.classdef)),
                )


def _declares_float32_box(decision: ClassDecision) -> bool:
    for value in _plain_self_stores(decision, "observation_space"):
        if not isinstance(value, ast.Call):
            continue
        func = value.func
        if not ((isinstance(func, ast.Name) and func.id == "Box") or (isinstance(func, ast.Attribute) and func.attr == "Box")):
            continue
        dtype = next((k.value for k in value.keywords if k.arg == "dtype"), None)
        if dtype is None or (isinstance(dtype, ast.Attribute) and dtype.attr == "float32") or (isinstance(dtype, ast.Name) and dtype.id == "float32"):
            return True
    return False


def _plain_self_stores(decision: ClassDecision, attribute: str) -> list[ast.expr]:
    """``self.<attribute> = value`` (a single target), in source order."""
    return [
        a.value
        for a in decision.index.assigns
        if len(a.targets) == 1 and is_self_attribute(a.targets[0], (attribute,))
    ]


def _state_is_float32(decision: ClassDecision) -> bool:
    """``self.state`` is stored as a float32 array somewhere, so ``np.array(self.state)`` keeps float32."""
    facts = decision.family.facts
    return any("float32" in facts.segment(value) for value in _plain_self_stores(decision, "state"))


def _observation_of(value: ast.AST | None, method: str) -> ast.AST | None:
    if value is None:
        return None
    if method == "step":
        return value.elts[0] if tuple_len(value) in (4, 5) else None  # type: ignore[attr-defined]
    if tuple_len(value) == 2:
        return None  # (obs, info) or a tuple observation: cannot tell
    return value


def _built_dtype(array: ast.AST) -> str:
    """What numpy makes of the array's one argument: Python ints give int64, floats float64;
    elements of unknown type (``self.position[0]``) name no dtype."""
    first = array.args[0] if isinstance(array, ast.Call) and array.args else None
    if isinstance(first, (ast.List, ast.Tuple)) and first.elts:
        kinds = {type(e.value) for e in first.elts if isinstance(e, ast.Constant)} if all(
            isinstance(e, ast.Constant) for e in first.elts
        ) else set()
        if kinds == {int}:
            return "is int64"
        if kinds and kinds <= {int, float}:
            return "is float64"
        return "is not float32 (numpy makes int64 of Python ints, float64 of floats)"
    return "is float64"


def _is_float64_array(expr: ast.AST) -> bool:
    if not (
        isinstance(expr, ast.Call)
        and isinstance(expr.func, ast.Attribute)
        and expr.func.attr in ("array", "asarray")
        and isinstance(expr.func.value, ast.Name)
        and expr.func.value.id in ("np", "numpy")
    ):
        return False
    if any(k.arg == "dtype" for k in expr.keywords) or len(expr.args) + len(expr.keywords) != 1 or len(expr.args) != 1:
        return False
    first = expr.args[0]
    return is_self_attribute(first, ("state",)) or isinstance(first, (ast.List, ast.Tuple))
