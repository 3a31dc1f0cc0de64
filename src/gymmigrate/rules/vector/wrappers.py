"""Vector wrappers and vector envs where a single env is expected (GM707, GM708).

* GM707 ``VectorEnvWrapper`` -> ``VectorWrapper`` (renamed in Gymnasium 1.0, and it no
  longer forwards attributes); ``step_wait``/``reset_wait`` overrides are reported (the
  base class no longer calls them).
* GM708 ``VectorEnv`` is no longer an ``Env``: ``isinstance(envs, gym.Env)`` and
  single-env utilities (``check_env``, ``play``, a ``gym.Wrapper`` of this module) given
  a vector env are reported.

Source: Gymnasium 1.0 release notes ("Vector environments"), ``vector/vector_env.py``.
"""

from __future__ import annotations

import ast
from typing import Any

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import names as N
from gymmigrate.facts.decisions import receiver_text
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import walk
from gymmigrate.facts.self_attributes import class_self_stores
from gymmigrate.facts.version_checks import dead_version_branch
from gymmigrate.findings import FixKind
from gymmigrate.rules.vector.common import VECTOR_CLASSES, VectorFamilyBase, gym_rest

LEGACY_NAME = "VectorEnvWrapper"
NEW_NAME = "VectorWrapper"
_VECTOR_WRAPPER_BASES = frozenset({"vector.VectorEnvWrapper", "vector.vector_env.VectorEnvWrapper"})
_VECTOR_MODULES = ("gym.vector", "gymnasium.vector", "gym.vector.vector_env", "gymnasium.vector.vector_env")
# Gym's vector env classes: a class that tests what it holds against one wraps vector envs
_VECTOR_ENV_CLASSES = frozenset({"vector.VectorEnv", "vector.vector_env.VectorEnv"}) | VECTOR_CLASSES
_OVERRIDES = ("step_wait", "reset_wait", "step_async", "reset_async")
# Single-env utilities (under gym/gymnasium) that reject vector envs.
_SINGLE_ENV_UTILITIES = frozenset(
    {"utils.env_checker.check_env", "utils.play.play", "utils.passive_env_checker.env_reset_passive_checker"}
)


class VectorWrappers(VectorFamilyBase):
    """GM707 and GM708, mixed into the vector family."""

    # -- GM707 --------------------------------------------------------------------------------

    def plan_vector_wrappers(self) -> None:
        if LEGACY_NAME not in self.facts.text:
            return
        renamed_bases: dict[ast.ClassDef, list[int]] = {}
        for classdef in self.facts.all_classes:
            indexes = [i for i, base in enumerate(classdef.bases) if self._is_legacy_base(base)]
            if indexes:
                renamed_bases[classdef] = indexes
                self._report_wrapper_class(classdef)
        in_bases = {id(classdef.bases[i]) for classdef, indexes in renamed_bases.items() for i in indexes}
        for classdef, indexes in renamed_bases.items():
            self.plan.replace(classdef, lambda node, indexes=indexes: _with_renamed_bases(node, indexes))
        # Every other spelling of the legacy class: annotations, isinstance checks...
        for node in walk(self.facts.tree):
            if id(node) in in_bases:
                continue
            if isinstance(node, ast.Attribute) and node.attr == LEGACY_NAME and self._is_legacy_base(node):
                self.plan.replace(node, lambda n: n.with_changes(attr=cst.Name(NEW_NAME)))
            elif isinstance(node, ast.Name) and node.id == LEGACY_NAME and self._is_legacy_base(node):
                self.plan.replace(node, lambda n: n.with_changes(value=NEW_NAME))
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module in _VECTOR_MODULES:
                if any(alias.name == LEGACY_NAME for alias in node.names):
                    self.plan.replace(node, _with_renamed_import)

    def _is_legacy_base(self, node: ast.AST) -> bool:
        return bool(gym_rest(self.facts, node) & _VECTOR_WRAPPER_BASES)

    def _report_wrapper_class(self, classdef: ast.ClassDef) -> None:
        self.report(
            _header(classdef),
            "GM707",
            "VectorEnvWrapper -> VectorWrapper: attribute forwarding is gone (use envs.get_attr/call or .unwrapped)",
        )
        for statement in classdef.body:
            if isinstance(statement, (ast.FunctionDef, ast.AsyncFunctionDef)) and statement.name in _OVERRIDES:
                public = statement.name.split("_")[0]
                self.report(
                    _header(statement),
                    "GM707",
                    f"VectorWrapper never calls {statement.name}(): move this logic into {public}()",
                    FixKind.FLAG,
                )

    # -- GM708 --------------------------------------------------------------------------------

    def check_single_env_use(self, call: ast.Call) -> None:
        func = call.func
        if isinstance(func, ast.Name) and func.id == "isinstance" and len(call.args) == 2 and not call.keywords:
            classes = call.args[1]
            candidates = list(classes.elts) if isinstance(classes, ast.Tuple) else [classes]
            if any(gym_rest(self.facts, c) & N.GYM_ENV_BASE_CLASSES for c in candidates):
                tested = call.args[0]
                if self.receivers.kind_of(tested) is EnvKind.GYM_VEC:
                    self.report(
                        call,
                        "GM708",
                        "a Gymnasium vector env is not a gym.Env any more, so this is False: test for "
                        "gymnasium.vector.VectorEnv",
                    )
                elif self._vector_passed_in(tested):
                    self.report(
                        call,
                        "GM708",
                        f"a call of the run passes `{receiver_text(tested)}` a Gymnasium vector env, which is not a gym.Env "
                        "any more, so this is False for it (legacy vector envs were gym.Env): add gymnasium.vector.VectorEnv "
                        "to the classes tested",
                    )
            return
        if not call.args or isinstance(call.args[0], ast.Starred):
            return
        if call.keywords and min((k.lineno, k.col_offset) for k in call.keywords) < (call.args[0].lineno, call.args[0].col_offset):
            return  # the first argument is a keyword
        rests = gym_rest(self.facts, func)
        what = None
        if rests & _SINGLE_ENV_UTILITIES:
            what = f"{self.facts.segment(func)}() expects a single env"
        elif any(r.startswith("wrappers.") for r in rests):
            return  # gymnasium's own wrappers on a vector env are GM613's (wrapper_usage.py)
        else:
            local = self.receivers.local_class(func)
            project = self.receivers.project
            name = None
            if local is not None and self.receivers.is_gym_wrapper_class(local):
                name = local.name
            elif project is not None and any(project.is_wrapper_class(q) for q in self.facts.qualified_names(func)):
                name = self.facts.segment(func)  # a wrapper class of another module of the run
            if name is not None:
                what = f"{name} is a single-env gym.Wrapper (port it to gymnasium.vector.VectorWrapper or apply it per sub-env)"
        if what and self._wrapped_kind(call) is EnvKind.GYM_VEC:
            self.report(
                call,
                "GM708",
                f"`{receiver_text(call.args[0])}` is a vector env, which is not a gym.Env in Gymnasium 1.x: {what}",
            )

    def plan_wrapper_autoreset(self) -> None:
        """GM706 for a plain class that wraps Gym vector envs (it tests what it holds with
        ``isinstance(env, gym.vector.SyncVectorEnv)``) and hands on each ``self._env.step``:
        Gymnasium resets a finished sub-env on the next step, whose result (the reset
        observation, reward 0, not done) is no transition; whoever stores what this step
        returns stores those too. One item at the step, once per class."""
        if "vector" not in self.facts.text:
            return
        for classdef in self.facts.all_classes:
            if self.receivers.is_gym_wrapper_class(classdef):
                continue  # a gym.Wrapper on a vector env is GM708's (check_single_env_use)
            held = self._vector_tested_attributes(classdef)
            if not held:
                continue
            for method in classdef.body:
                if not (isinstance(method, (ast.FunctionDef, ast.AsyncFunctionDef)) and method.name == "step"):
                    continue
                steps = [
                    call
                    for call in walk(method)
                    if isinstance(call, ast.Call)
                    and isinstance(call.func, ast.Attribute)
                    and call.func.attr == "step"
                    and isinstance(call.func.value, ast.Attribute)
                    and call.func.value.attr in held
                    and isinstance(call.func.value.value, ast.Name)
                    and self.receivers.is_self(call.func.value.value)
                    and dead_version_branch(call, self.facts) is None
                ]
                if steps:
                    tested, check = held[steps[0].func.value.attr]  # type: ignore[attr-defined]
                    self.report(
                        steps[0],
                        "GM706",
                        f"`{classdef.name}` wraps vector envs (it tests `{self.facts.segment(check)}`): a Gymnasium vector "
                        "env resets a finished sub-env on the next step, which returns its reset observation with reward 0 "
                        "and not done; what this step returns then is no transition. Skip those steps where they are "
                        "stored (the sub-envs done on the step before), or make the vector env with "
                        "vector_kwargs={\"autoreset_mode\": gym.vector.AutoresetMode.SAME_STEP}",
                        FixKind.FLAG,
                        question=("GM706", "autoreset"),  # the file's one autoreset question (infos.py)
                    )
                break

    def _vector_tested_attributes(self, classdef: ast.ClassDef) -> dict[str, tuple[str, ast.Call]]:
        """``self.X`` the class tests for a Gym vector env class, directly or through the
        ``__init__`` parameter it stores there: X -> (what is tested, the check)."""
        found: dict[str, tuple[str, ast.Call]] = {}
        for call in walk(classdef):
            if not (isinstance(call, ast.Call) and isinstance(call.func, ast.Name) and call.func.id == "isinstance" and len(call.args) == 2):
                continue
            classes = call.args[1]
            candidates = list(classes.elts) if isinstance(classes, ast.Tuple) else [classes]
            if not any(gym_rest(self.facts, c) & _VECTOR_ENV_CLASSES for c in candidates):
                continue
            tested = call.args[0]
            if isinstance(tested, ast.Attribute) and isinstance(tested.value, ast.Name) and self.receivers.is_self(tested.value):
                found.setdefault(tested.attr, (tested.attr, call))
            elif isinstance(tested, ast.Name):
                bindings = self.facts.bindings_of(tested)
                if len(bindings) != 1 or not isinstance(bindings[0], ast.arg):
                    continue
                for attribute, values in class_self_stores(self.facts, classdef).items():
                    if any(isinstance(v, ast.Name) and self.facts.bindings_of(v) == bindings for v in values):
                        found.setdefault(attribute, (tested.id, call))
                # ``super().__init__(env)`` storing it in a base of this module
                for base in classdef.bases:
                    local = self.receivers.local_class(base)
                    if local is not None and self._passed_up(call, tested):
                        for attribute, values in class_self_stores(self.facts, local).items():
                            if any(isinstance(v, ast.Name) and v.id == tested.id for v in values):
                                found.setdefault(attribute, (tested.id, call))
        return found

    def _passed_up(self, check: ast.Call, tested: ast.Name) -> bool:
        """The def of ``check`` hands ``tested`` to ``super().__init__`` first."""
        function = self.facts.enclosing_function(check)
        if function is None:
            return False
        for call in walk(function):
            if (
                isinstance(call, ast.Call)
                and isinstance(call.func, ast.Attribute)
                and call.func.attr == "__init__"
                and call.args
                and isinstance(call.args[0], ast.Name)
                and call.args[0].id == tested.id
            ):
                return True
        return False

    def _vector_passed_in(self, tested: ast.expr) -> bool:
        """``tested`` is a parameter of a def that some call of another module of the run
        passes a Gym vector env (``ProjectView.param_kinds``), though others pass other envs."""
        if not isinstance(tested, ast.Name):
            return False
        bindings = self.facts.bindings_of(tested)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.arg):
            return False
        function = self.facts.enclosing_function(tested)
        if function is None or bindings[0] not in function.args.args + function.args.posonlyargs + function.args.kwonlyargs:
            return False
        classdef = self.facts.parent(function)
        method = isinstance(classdef, ast.ClassDef)
        kinds = self.receivers.callables.external_param_kinds(function, classdef if method else None, bindings[0].arg)  # type: ignore[arg-type]
        return EnvKind.GYM_VEC in kinds

    def _wrapped_kind(self, call: ast.Call) -> EnvKind:
        """The kind of the env ``call`` wraps; in ``envs = Wrapper(envs)``, the value the
        binding above it in the same block gave ``envs``."""
        wrapped = call.args[0]
        kind = self.receivers.kind_of(wrapped)
        statement = self.facts.statement_of(call)
        if (
            kind is EnvKind.GYM_VEC
            or not isinstance(wrapped, ast.Name)
            or not isinstance(statement, ast.Assign)
            or statement.value is not call
            or not any(isinstance(t, ast.Name) and t.id == wrapped.id for t in statement.targets)
        ):
            return kind
        above = Flow.of(self.facts).binding_above(wrapped, statement)
        found = self.receivers.binding_kind(above) if above is not None else None
        return found if found is not None else kind


def _header(definition: ast.AST) -> ast.AST:
    """Where LibCST placed a definition: its first decorator, else the def/class line."""
    decorators = getattr(definition, "decorator_list", None)
    return decorators[0] if decorators else definition


def _renamed(expression: Any) -> Any:
    if isinstance(expression, cst.Attribute):
        return expression.with_changes(attr=cst.Name(NEW_NAME))
    if isinstance(expression, cst.Name):
        return expression.with_changes(value=NEW_NAME)
    return expression


def _with_renamed_bases(node: Any, indexes: list[int]) -> Any:
    bases = list(node.bases)
    for i in indexes:
        if i < len(bases):
            bases[i] = bases[i].with_changes(value=_renamed(bases[i].value))
    return node.with_changes(bases=bases)


def _with_renamed_import(node: Any) -> Any:
    if isinstance(node.names, cst.ImportStar):
        return node
    names = [
        alias.with_changes(name=cst.Name(NEW_NAME)) if isinstance(alias.name, cst.Name) and alias.name.value == LEGACY_NAME else alias
        for alias in node.names
    ]
    return node.with_changes(names=names)
