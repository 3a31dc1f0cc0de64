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
from gymmigrate.findings import FixKind
from gymmigrate.rules.vector.common import VectorFamilyBase, gym_rest

LEGACY_NAME = "VectorEnvWrapper"
NEW_NAME = "VectorWrapper"
_VECTOR_WRAPPER_BASES = frozenset({"vector.VectorEnvWrapper", "vector.vector_env.VectorEnvWrapper"})
_VECTOR_MODULES = ("gym.vector", "gymnasium.vector", "gym.vector.vector_env", "gymnasium.vector.vector_env")
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
        for node in ast.walk(self.facts.tree):
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
                if self.receivers.kind_of(call.args[0]) is EnvKind.GYM_VEC:
                    self.report(
                        call,
                        "GM708",
                        "a Gymnasium vector env is not a gym.Env any more, so this is False: test for "
                        "gymnasium.vector.VectorEnv",
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
