"""What the custom-env rules share: the rule table and one class's decision context."""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.facts.env_classes import ClassIndex, EnvClasses, FunctionIndex
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.base import Rule
from gymmigrate.rules.custom_env.rebuild import ClassPlan

if TYPE_CHECKING:
    from gymmigrate.rules.base import RuleFamily

CLASS_RULES = (
    Rule("GM405", "custom render(mode)", FixKind.ASSIST, "`render(self, mode)` reads `self.render_mode`, set in `__init__`."),
    Rule("GM501", "custom reset", FixKind.AUTO, "`reset` takes `seed`/`options`, calls `super().reset(seed=seed)`, returns `(obs, info)`."),
    Rule("GM502", "reset return_info", FixKind.ASSIST, "`return_info` and its branches are removed; reset always returns `(obs, info)`."),
    Rule("GM503", "custom seed()", FixKind.AUTO, "`seed()` methods are removed; their seeding moves into `reset`."),
    Rule("GM504", "custom step", FixKind.ASSIST, "`step` returns `(obs, reward, terminated, truncated, info)`."),
    Rule("GM508", "mujoco-py MujocoEnv", FixKind.FLAG, "Subclasses of the mujoco-py `MujocoEnv` are reported for a manual port."),
    Rule("GM509", "float64 observations", FixKind.FLAG, "`np.array(...)` observations for a float32 `Box` are reported."),
)

# gym < 0.9 spelled the API methods with a leading underscore.
UNDERSCORE_METHODS = {"_step": "step", "_reset": "reset", "_seed": "seed", "_render": "render"}
UNDERSCORE_RULE = {"step": "GM504", "reset": "GM501", "seed": "GM503", "render": "GM405"}

Method = ast.FunctionDef | ast.AsyncFunctionDef


class ClassDecision:
    """What the family decides for one custom env class, and the plan its build carries out."""

    def __init__(self, family: RuleFamily, env: EnvClasses, classdef: ast.ClassDef) -> None:
        self.family = family
        self.env = env
        self.classdef = classdef
        self.index: ClassIndex = env.index(classdef)
        self.methods = self.index.methods
        self.plan = ClassPlan()
        for old, new in UNDERSCORE_METHODS.items():
            if old in self.methods and new not in self.methods:
                self.plan.renamed[new] = old
        self.removed: set[str] = set()  # methods (by their source name) the build deletes
        self.deleted_statements: list[ast.stmt] = []  # statements that disappear with them

    @property
    def renamed(self) -> dict[str, str]:
        return self.plan.renamed

    def report(
        self, node: ast.AST, code: str, message: str, kind: FixKind | None = None, tier: Tier | None = None
    ) -> None:
        # ast places a decorated def on its ``def`` line, as LibCST's positions did.
        self.family.report(node, code, message, kind, tier)

    def method(self, name: str) -> Method | None:
        return self.methods.get(self.renamed.get(name, name))

    def function(self, function: ast.AST) -> FunctionIndex:
        return self.env.function(function)


def method_of(decision: ClassDecision, node: ast.AST) -> Method | None:
    """The method of the decided class that contains ``node`` (None outside its methods)."""
    facts = decision.family.facts
    for ancestor in facts.ancestors(node):
        if facts.parent(ancestor) is decision.classdef:
            return ancestor if isinstance(ancestor, (ast.FunctionDef, ast.AsyncFunctionDef)) else None
    return None




def is_docstring(group: list[ast.stmt]) -> bool:
    return (
        len(group) == 1
        and isinstance(group[0], ast.Expr)
        and isinstance(group[0].value, ast.Constant)
        and isinstance(group[0].value.value, str)
    )


def param_names(function: Method) -> list[str]:
    args = function.args
    found = [a.arg for a in (*args.posonlyargs, *args.args)]
    if args.vararg is not None:
        found.append(args.vararg.arg)
    found += [a.arg for a in args.kwonlyargs]
    if args.kwarg is not None:
        found.append(args.kwarg.arg)
    return found


def callable_without_arguments(function: Method) -> bool:
    """``self.function()`` is a valid call: every parameter after ``self`` has a default."""
    args = function.args
    positional = [*args.posonlyargs, *args.args][1:]
    if len(positional) > len(args.defaults):
        return False
    return all(default is not None for default in args.kw_defaults)


def tuple_len(value: ast.AST | None) -> int | None:
    if isinstance(value, ast.Tuple) and not any(isinstance(e, ast.Starred) for e in value.elts):
        return len(value.elts)
    return None
