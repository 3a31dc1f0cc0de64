"""What the custom-env rules share: the rule table and one class's decision context."""

from __future__ import annotations

import ast
from collections.abc import Hashable
from typing import TYPE_CHECKING

from gymmigrate.facts.decisions import Action, decide
from gymmigrate.facts.env_classes import (
    UNDERSCORE_HOOKS,
    ClassIndex,
    EnvClasses,
    FunctionIndex,
    class_level_bindings,
    hook_renames,
    is_super_method_call,
)
from gymmigrate.facts.module import full_name, own_returns
from gymmigrate.facts.step_calls import foreign_step
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.base import Rule
from gymmigrate.rules.custom_env.plans import ClassPlan

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
    Rule(
        "GM511",
        "spaces unset or lists",
        FixKind.FLAG,
        "An env class an entry point makes that never sets `action_space` or `observation_space`, or any env class that sets one "
        "to a plain list of spaces, is reported (make's env checker raises).",
    ),
)

# gym <= 0.9 spelled the API methods with a leading underscore: its ``Env.step`` called
# ``self._step`` and so on. Gymnasium's base class calls none of them, so a class that
# only defines the underscore names gets the public ones, unless a base class of the run
# defines the public one: then that base's ``step`` calls the subclass's ``_step`` (a hook
# of the project's own, ``TrialEnv.step`` -> ``self._step(action)``), and a rename would
# override the base's step with the hook (``facts.env_classes.hook_renames``).
UNDERSCORE_METHODS = UNDERSCORE_HOOKS
UNDERSCORE_RULE = {"step": "GM504", "reset": "GM501", "seed": "GM503", "render": "GM405", "close": "GM405", "configure": "GM405"}

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
        # ``reset = _reset`` in the class body (often under a gym version test): the hooks
        # keep their names, which subclasses call (``Base._reset(self)``); only the public
        # names change contract (``reset.py``). Renaming the hooks would leave the aliases
        # naming nothing: NameError when the class body runs.
        self.aliases, _ = class_level_bindings(classdef, self.methods)
        self.plan.published = {new: alias.value.id for new, alias in self.aliases.items()}  # type: ignore[attr-defined]
        self.plan.renamed.update(hook_renames(classdef, self.methods, lambda: inherited_methods(family, classdef)))
        # ``def seed(self, seed=None): return self._seed(seed)``: seeding moves into reset,
        # so the helper is the method to migrate and the forwarding one goes with it.
        public, helper = self.methods.get("seed"), self.methods.get("_seed")
        if public is not None and helper is not None and not self.plan.published and _forwards(public, "_seed"):
            self.plan.renamed["seed"] = "_seed"
            self.plan.dropped.add("seed")
        self.removed: set[str] = set()  # methods (by their source name) the build deletes
        self.deleted_statements: list[ast.stmt] = []  # statements that disappear with them

    @property
    def renamed(self) -> dict[str, str]:
        return self.plan.renamed

    def report(
        self,
        node: ast.AST,
        code: str,
        message: str,
        kind: FixKind | None = None,
        tier: Tier | None = None,
        question: Hashable | None = None,
    ) -> None:
        # ast places a decorated def on its ``def`` line, as LibCST's positions did.
        self.family.report(node, code, message, kind, tier, question)

    def method(self, name: str) -> Method | None:
        return self.methods.get(self.renamed.get(name, name))

    def function(self, function: ast.AST) -> FunctionIndex:
        return self.env.function(function)


def inherited_methods(family: RuleFamily, classdef: ast.ClassDef) -> frozenset[str]:
    """The methods the class's bases of the run define (``Receivers.base_methods``)."""
    return family.receivers.base_methods(classdef)


def method_of(decision: ClassDecision, node: ast.AST) -> Method | None:
    """The method of the decided class that contains ``node`` (None outside its methods)."""
    facts = decision.family.facts
    for ancestor in facts.ancestors(node):
        if facts.parent(ancestor) is decision.classdef:
            return ancestor if isinstance(ancestor, (ast.FunctionDef, ast.AsyncFunctionDef)) else None
    return None




def _forwards(function: Method, helper: str) -> bool:
    """The body (docstring aside) only passes the parameters on: ``return self.<helper>(seed)``."""
    body = function.body[1:] if is_docstring(function.body[:1]) else function.body
    if len(body) != 1 or not isinstance(body[0], (ast.Return, ast.Expr)):
        return False
    call = body[0].value
    params = param_names(function)[1:]
    return (
        is_self_call(call, {helper})
        and not call.keywords  # type: ignore[union-attr]
        and [a.id if isinstance(a, ast.Name) else None for a in call.args] == params[: len(call.args)]  # type: ignore[union-attr]
    )


def local_subclasses(decision: ClassDecision) -> list[ast.ClassDef]:
    """Classes of this module that extend the decided class, directly or through others."""
    facts = decision.family.facts
    receivers = decision.family.receivers

    def compute() -> dict[int, list[ast.ClassDef]]:
        children: dict[int, list[ast.ClassDef]] = {}
        for classdef in facts.all_classes:
            for base in classdef.bases:
                parent = receivers.local_class(base)
                if parent is not None and parent is not classdef:
                    children.setdefault(id(parent), []).append(classdef)
        return children

    children: dict[int, list[ast.ClassDef]] = facts.memo(("local-subclasses", 0), compute)
    found: list[ast.ClassDef] = []
    todo = [decision.classdef]
    while todo:
        for child in children.get(id(todo.pop()), ()):
            if child not in found and child is not decision.classdef:
                found.append(child)
                todo.append(child)
    return found


def local_bases(decision: ClassDecision) -> list[ast.ClassDef]:
    """Classes of this module the decided class extends, directly or through others."""
    found: list[ast.ClassDef] = []
    todo = [decision.classdef]
    while todo:
        for base in todo.pop().bases:
            parent = decision.family.receivers.local_class(base)
            if parent is not None and parent is not decision.classdef and parent not in found:
                found.append(parent)
                todo.append(parent)
    return found


def called_in_hierarchy(decision: ClassDecision, name: str) -> bool:
    """A class above or below the decided one (in this module, or another of the run)
    calls ``self.<name>(...)``: ``RobotEnv.step`` reading ``self._get_observation()``
    that its subclass defines gets what that method returns."""
    related = [*local_bases(decision), *local_subclasses(decision)]
    if any(decision.env.index(classdef).self_calls.get(name) for classdef in related):
        return True
    project = decision.family.receivers.project
    if project is None:
        return False
    facts = decision.family.facts
    return any(
        project.called_in_hierarchy_elsewhere(classdef.name, name)
        for classdef in (decision.classdef, *related)
        if facts.parent(classdef) is facts.tree
    )


def called_on_instances(decision: ClassDecision, name: str) -> bool:
    """Some code of the run calls ``x.<name>(...)`` on another receiver than ``self`` or
    ``super()``, in this module or another: it may hold an instance of the class (an
    ``isinstance`` check or a construction shows it), and reads what the method returns
    as it is. Any such call counts: the run cannot widen a return it does not see used."""
    facts = decision.family.facts
    if any(
        not (isinstance(call.func.value, ast.Name) and call.func.value.id == "self")  # type: ignore[attr-defined]
        and not is_super_method_call(call, name)
        for call in facts.attribute_calls.get(name, ())
    ):
        return True
    project = decision.family.receivers.project
    return project is not None and bool(project.called_on_instances_elsewhere(name))


def delegates(decision: ClassDecision, function: Method) -> list[Method]:
    """The class's helpers that ``function`` returns the result of (``return self._step(a)``).

    Only helpers no other code of the class calls (their returns can take the new
    contract of ``function`` without changing what another caller receives) and that
    return something themselves (an abstract helper's overrides live elsewhere).
    """
    found: list[Method] = []
    for ret in own_returns(function):
        call = ret.value
        if not (isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute)):
            continue
        owner, name = call.func.value, call.func.attr
        helper = decision.methods.get(name)
        if not (isinstance(owner, ast.Name) and owner.id == "self") or helper is None or helper is function or helper in found:
            continue
        if not any(r.value is not None for r in own_returns(helper)):
            continue  # abstract (``raise NotImplementedError``): subclasses return, nothing here to follow
        callers = decision.index.self_calls.get(name, ())
        if called_in_hierarchy(decision, name):
            continue  # another class's method reads the helper's value: its contract stays
        if called_on_instances(decision, name):
            continue  # ``env.postprocess(...)`` elsewhere may be this class's: it reads four values
        if all(method_of(decision, c) is function for c in callers) and name not in decision.renamed.values():
            found.append(helper)
    return found


def is_self_call(node: ast.AST | None, names: set[str]) -> bool:
    """``self.<one of names>(...)``."""
    return (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and isinstance(node.func.value, ast.Name)
        and node.func.value.id == "self"
        and node.func.attr in names
    )


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


def inner_gym_env_call(decision: ClassDecision, node: ast.AST, method: str) -> bool:
    """``self.sim.<method>(...)`` on a receiver that the call-site rules (GM201, GM203)
    rewrite as a Gym env: an env class that holds another env and delegates to it. Such
    a call is theirs to migrate; the class rules must not treat its result as their own."""
    if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == method):
        return False
    receiver = node.func.value
    if isinstance(receiver, ast.Name) and receiver.id == "self":
        return False
    if isinstance(receiver, ast.Call):
        return False  # super().<method>(...): the class rules' own business
    family = decision.family
    if method == "step" and foreign_step(node, family.receivers, family.facts):
        return False  # ``self.sim.step(a, b)``: the held object's own API, left as it is
    kind = family.receivers.kind_of(receiver)
    return decide(kind, receiver, family.context.profile).action in (Action.REWRITE, Action.REWRITE_FOR_REVIEW)


def random_state_np_random(decision: ClassDecision) -> ast.expr | None:
    """The ``np.random.RandomState(...)`` the class (or a base of this module) assigns to
    ``self.np_random``."""
    receivers = decision.family.receivers
    seen: set[int] = set()
    todo = [decision.classdef]
    while todo:
        classdef = todo.pop()
        if id(classdef) in seen:
            continue
        seen.add(id(classdef))
        index = decision.env.index(classdef)
        for value in index.stores_to_self("np_random") + index.stores_to_self("_np_random"):
            if isinstance(value, ast.Call) and (full_name(value.func) or "").endswith("RandomState"):
                return value
        todo.extend(base for b in classdef.bases if (base := receivers.local_class(b)) is not None)
    return None
