"""Constructing vector envs (GM701, GM702).

* GM701 ``gym.vector.make(id, n, asynchronous=..., wrappers=w, **kw)`` ->
  ``gym.make_vec(id, num_envs=n, vectorization_mode="async"/"sync", wrappers=[w], **kw)``.
  Gymnasium 1.0 removed ``gymnasium.vector.make``. The mode is always written out: the
  legacy default was async, while ``make_vec`` without a mode picks the env's
  ``vector_entry_point`` (for CartPole a different class, which rejects ``wrappers=``).
  ``wrappers`` must be a sequence; arguments of the vector class go in ``vector_kwargs``.
* GM702 ``SyncVectorEnv/AsyncVectorEnv(fns, observation_space, action_space)``: those
  parameters are gone (1.x has ``observation_mode``); reported.

Source: Gymnasium ``envs/registration.py::make_vec``, ``vector/sync_vector_env.py``,
``vector/async_vector_env.py``.
"""

from __future__ import annotations

import ast
import builtins
from collections.abc import Callable
from typing import Any

from gymmigrate.edits.arguments import append_keyword
from gymmigrate.edits.lazy import cst
from gymmigrate.findings import FixKind
from gymmigrate.rules.vector.common import (
    ASYNC_ONLY_KWARGS,
    LEGACY_POSITIONS,
    VECTOR_CLASS_KWARGS,
    VECTOR_CLASSES,
    VectorFamilyBase,
    gym_rest,
    is_false,
    quote_style,
)

_BUILTINS = frozenset(dir(builtins))


class Construction(VectorFamilyBase):
    """GM701 and GM702, mixed into the vector family."""

    # -- GM701 ------------------------------------------------------------------------------

    def is_legacy_vector_make(self, call: ast.Call) -> bool:
        return "vector.make" in gym_rest(self.facts, call.func)

    def legacy_argument(self, call: ast.Call, name: str) -> ast.expr | None:
        """The value ``gym.vector.make`` receives for parameter ``name``, if passed."""
        for kw in call.keywords:
            if kw.arg == name:
                return kw.value
        index = LEGACY_POSITIONS.index(name)
        positional = call.args
        if any(isinstance(a, ast.Starred) for a in positional[: index + 1]):
            return None
        return positional[index] if index < len(positional) else None

    def is_sync(self, call: ast.Call) -> bool:
        return is_false(self.legacy_argument(call, "asynchronous"))

    def report_vector_make(self, call: ast.Call) -> None:
        segment = self.facts.segment
        moved = [kw.arg for kw in call.keywords if kw.arg in VECTOR_CLASS_KWARGS]
        if self.is_sync(call) and any(name in ASYNC_ONLY_KWARGS for name in moved):
            dropped = [name for name in moved if name in ASYNC_ONLY_KWARGS]
            self.report(
                call,
                "GM701",
                f"gym.vector.make -> gym.make_vec(vectorization_mode=\"sync\"); dropped {', '.join(dropped)}: "
                "SyncVectorEnv has no such parameter (gym.vector.make passed it to each sub-env's constructor)",
                FixKind.ASSIST,
            )
            return
        wrappers = self.legacy_argument(call, "wrappers")
        unknown_wrappers = wrappers is not None and self.wrappers_shape(wrappers) == "unknown"
        mode = self.legacy_argument(call, "asynchronous")
        if mode is None:
            mode_text = '"async" (the legacy default, written out)'
        elif isinstance(mode, ast.Constant) and isinstance(mode.value, bool):
            mode_text = '"async"' if mode.value else '"sync"'
        else:
            mode_text = f"chosen from asynchronous={segment(mode)}"
        message = f"gym.vector.make -> gym.make_vec with vectorization_mode {mode_text}"
        star = next((kw for kw in call.keywords if kw.arg is None), None)
        if star is not None:
            self.report(
                call,
                "GM701",
                f"{message}; make sure {segment(star.value)} holds no asynchronous/wrappers entry (make_vec would pass it "
                "to each sub-env's constructor)",
                FixKind.ASSIST,
            )
            return
        if moved:
            caveat = ""
            if mode is not None and mode_text.startswith("chosen") and any(n in ASYNC_ONLY_KWARGS for n in moved):
                caveat = "; in sync mode SyncVectorEnv rejects shared_memory/context/daemon/worker"
            self.report(
                call,
                "GM701",
                f"{message}; {', '.join(moved)} moved into vector_kwargs: gym.vector.make passed them to each "
                f"sub-env's constructor, make_vec gives them to the vector env class{caveat}",
                FixKind.ASSIST,
            )
        elif unknown_wrappers and wrappers is not None:  # ``unknown_wrappers`` implies an argument
            self.report(
                call,
                "GM701",
                f"{message}; make_vec needs wrappers= to be a list and `{segment(wrappers)}` could not be "
                "checked: wrap a single callable in [...]",
                FixKind.ASSIST,
            )
        else:
            self.report(call, "GM701", message)

    def wrappers_shape(self, value: ast.AST) -> str:
        """"sequence", "callable", "none" or "unknown": legacy accepted one callable or a list."""
        # A binding reached again while its shape is computed (``w = w``) says nothing.
        return self.facts.memo(
            ("vector-wrappers-shape", id(value)), lambda: self._wrappers_shape(value), while_computing="unknown"
        )

    def _wrappers_shape(self, value: ast.AST) -> str:
        if isinstance(value, (ast.List, ast.Tuple, ast.ListComp)):
            return "sequence"
        if isinstance(value, ast.Constant) and value.value is None:
            return "none"
        if isinstance(value, ast.Lambda):
            return "callable"
        if isinstance(value, ast.Attribute) and self.facts.qualified_names(value):
            return "callable"
        if isinstance(value, ast.Name):
            bindings = self.facts.bindings_of(value)
            if not bindings and value.id in _BUILTINS:
                return "callable"
            shapes = set()
            for binding in bindings:
                if isinstance(binding, (ast.alias, ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                    shapes.add("callable")  # an imported wrapper class or function, or one defined here
                    continue
                assign = self.facts.parent(binding)
                if isinstance(binding, ast.Name) and isinstance(assign, ast.Assign):
                    shapes.add(self.wrappers_shape(assign.value))
                else:
                    shapes.add("unknown")
            if len(shapes) == 1:
                return shapes.pop()
        return "unknown"

    def make_vec_build(self, call: ast.Call, same_step: str | None) -> Callable[[Any], Any]:
        """The edit turning ``gym.vector.make(...)`` into ``make_vec(...)`` (with SAME_STEP if asked)."""
        wrappers = self.legacy_argument(call, "wrappers")
        wrappers_callable = wrappers is not None and self.wrappers_shape(wrappers) == "callable"
        sync = self.is_sync(call)
        q = quote_style(self.facts, call)
        new_func = self._make_vec_func(call)

        def build(node: Any) -> Any:
            return _make_vec_call(node, new_func, wrappers_callable=wrappers_callable, sync=sync, q=q, same_step=same_step)

        return build

    def _make_vec_func(self, call: ast.Call) -> Callable[[Any], cst.BaseExpression]:
        """``gym.make_vec`` through the user's own ``gym`` name, else an imported ``make_vec``."""
        func = call.func
        if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Attribute) and isinstance(func.value.value, ast.Name):
            if self.facts.qualified_names(func.value.value) & {"gymnasium", "gym"}:
                return lambda node: node.with_changes(value=node.value.value, attr=cst.Name("make_vec"))
        if isinstance(func, ast.Name):
            self._replace_imported_make(func)
        else:
            self.plan.ensure_import("gymnasium", "make_vec")
        return lambda node: cst.Name("make_vec")

    def _replace_imported_make(self, func: ast.Name) -> None:
        """``from gym.vector import make``: the import gives way to ``from gymnasium import make_vec``."""
        self.plan.add_import("from gymnasium import make_vec")
        for binding in self.facts.bindings_of(func):
            statement = self.facts.parent(binding) if isinstance(binding, ast.alias) else None
            if (
                not isinstance(binding, ast.alias)
                or not isinstance(statement, ast.ImportFrom)
                or self.facts.parent(statement) is not self.facts.tree
            ):
                continue
            still_used = any(
                binding in self.facts.bindings_of(read) and not self._is_rewritten_make(read)
                for scope in self.facts.scopes.values()
                for read in scope.reads.get(func.id, ())
            )
            if still_used:
                continue
            if len(statement.names) == 1:
                self.plan.remove(statement)
            else:
                bound = binding.asname or binding.name
                self.plan.replace(statement, lambda node, bound=bound: _without_alias(node, bound))

    def _is_rewritten_make(self, read: ast.Name) -> bool:
        parent = self.facts.parent(read)
        return isinstance(parent, ast.Call) and parent.func is read and id(parent) in self.decisions.vector_makes

    # -- GM702 ------------------------------------------------------------------------------

    def is_vector_class(self, call: ast.Call) -> bool:
        if gym_rest(self.facts, call.func) & VECTOR_CLASSES:
            return True
        # ``constructor = gym.vector.AsyncVectorEnv if multi else gym.vector.SyncVectorEnv``
        if not isinstance(call.func, ast.Name):
            return False
        bindings = self.facts.bindings_of(call.func)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.Name):
            return False
        statement = self.facts.parent(bindings[0])
        if not (isinstance(statement, ast.Assign) and isinstance(statement.value, ast.IfExp)):
            return False
        branches = (statement.value.body, statement.value.orelse)
        return all(gym_rest(self.facts, b) & VECTOR_CLASSES for b in branches)

    def check_spaces_arguments(self, call: ast.Call) -> None:
        named = [kw.arg for kw in call.keywords if kw.arg in ("observation_space", "action_space")]
        positional = [a for a in call.args if not isinstance(a, ast.Starred)]
        if not named and call.args and isinstance(call.args[0], ast.Starred):
            self.report(
                call,
                "GM702",
                f"the arguments unpacked from `{self.facts.segment(call.args[0])}` go by position: if they are gym's "
                "(env_fns, observation_space, action_space), the spaces land on Gymnasium 1.x's copy and "
                "observation_mode (a ValueError): pass the env functions alone",
            )
            return
        if named or len(positional) > 1:
            what = (
                f"{'/'.join(named)} are no longer parameters of Gymnasium vector envs"
                if named
                else "legacy positional observation_space/action_space would now land on copy/shared_memory"
            )
            self.report(
                call,
                "GM702",
                f"{what}: remove them, or pass observation_mode=\"different\" or (batched_space, single_space) "
                "if the sub-env spaces differ",
            )


# -- builds (LibCST) ------------------------------------------------------------------------


def _equal() -> cst.AssignEqual:
    return cst.AssignEqual(whitespace_before=cst.SimpleWhitespace(""), whitespace_after=cst.SimpleWhitespace(""))


def kwarg(name: str, value: cst.BaseExpression, comma: cst.Comma | cst.MaybeSentinel | None = None) -> cst.Arg:
    # None for LibCST's default comma: a default of cst.MaybeSentinel.DEFAULT would load LibCST on import.
    return cst.Arg(keyword=cst.Name(name), value=value, equal=_equal(), comma=cst.MaybeSentinel.DEFAULT if comma is None else comma)


def dict_literal(items: list[tuple[str, cst.BaseExpression]], q: str = '"') -> cst.Dict:
    elements = []
    for i, (name, value) in enumerate(items):
        comma = cst.Comma(whitespace_after=cst.SimpleWhitespace(" ")) if i < len(items) - 1 else cst.MaybeSentinel.DEFAULT
        elements.append(cst.DictElement(cst.SimpleString(f"{q}{name}{q}"), value, comma=comma))
    return cst.Dict(elements)


def _make_vec_call(
    node: cst.Call,
    new_func: Callable[[Any], cst.BaseExpression],
    *,
    wrappers_callable: bool,
    sync: bool,
    q: str,
    same_step: str | None,
) -> cst.Call:
    """Build ``make_vec(...)`` from ``gym.vector.make(...)``, editing arguments in place."""
    args = list(node.args)
    positional_index = 0
    new_args: list[cst.Arg] = []
    vector_kwargs: list[tuple[str, cst.BaseExpression]] = []
    mode_value: cst.BaseExpression = cst.SimpleString(f"{q}async{q}")
    saw_mode = False
    last_kept = False
    for i, arg in enumerate(args):
        name = arg.keyword.value if arg.keyword is not None else None
        if name is None and not arg.star:
            name = LEGACY_POSITIONS[positional_index] if positional_index < len(LEGACY_POSITIONS) else None
            positional_index += 1
            if name in ("num_envs", "asynchronous", "wrappers", "disable_env_checker"):
                arg = arg.with_changes(keyword=cst.Name(name), equal=_equal())
        if name == "asynchronous":
            mode_value = _mode_expression(arg.value, q)
            saw_mode = True
            arg = arg.with_changes(keyword=cst.Name("vectorization_mode"), value=mode_value)
        elif name == "wrappers" and wrappers_callable:
            arg = arg.with_changes(value=cst.List([cst.Element(arg.value)]))
        elif name in VECTOR_CLASS_KWARGS and arg.keyword is not None:
            if not (name in ASYNC_ONLY_KWARGS and sync):
                vector_kwargs.append((name, arg.value))
            continue
        new_args.append(arg)
        last_kept = i == len(args) - 1
    if new_args and not last_kept:
        # The old last argument moved into vector_kwargs: keep its trailing comma style.
        new_args[-1] = new_args[-1].with_changes(comma=args[-1].comma, whitespace_after_arg=args[-1].whitespace_after_arg)
    if same_step is not None:
        vector_kwargs.append(("autoreset_mode", cst.parse_expression(same_step)))
    if not saw_mode:
        new_args = _insert_mode(new_args, node, mode_value)
    if vector_kwargs:
        new_args = _insert_after_mode(new_args, node, "vector_kwargs", dict_literal(vector_kwargs, q))
    return node.with_changes(func=new_func(node.func), args=new_args)


def _mode_expression(value: cst.BaseExpression, q: str) -> cst.BaseExpression:
    if isinstance(value, cst.Name) and value.value in ("True", "False"):
        return cst.SimpleString(f"{q}async{q}" if value.value == "True" else f"{q}sync{q}")
    return cst.IfExp(test=value, body=cst.SimpleString(f"{q}async{q}"), orelse=cst.SimpleString(f"{q}sync{q}"))


def _insert_mode(args: list[cst.Arg], call: cst.Call, value: cst.BaseExpression) -> list[cst.Arg]:
    """``vectorization_mode=`` goes right after num_envs (or the id)."""
    index = 1
    for i, arg in enumerate(args):
        if arg.keyword is not None and arg.keyword.value == "num_envs":
            index = i + 1
    return _insert(args, index, kwarg("vectorization_mode", value), call)


def _insert_after_mode(args: list[cst.Arg], call: cst.Call, name: str, value: cst.BaseExpression) -> list[cst.Arg]:
    index = None
    for i, arg in enumerate(args):
        if arg.keyword is not None and arg.keyword.value in ("vectorization_mode", "num_envs"):
            index = i + 1
    if index is None:
        index = min(len([a for a in args if a.keyword is None and not a.star]), len(args))
        index = max(index, 1)
    return _insert(args, index, kwarg(name, value), call)


def _insert(args: list[cst.Arg], index: int, new: cst.Arg, call: cst.Call) -> list[cst.Arg]:
    """Insert ``new`` at ``index`` with the separators of its neighbours."""
    index = min(max(index, 0), len(args))
    if index == len(args):
        return list(append_keyword(call.with_changes(args=args), new.keyword.value, new.value).args)  # type: ignore[union-attr]
    previous_comma = args[index - 1].comma if index > 0 else cst.MaybeSentinel.DEFAULT
    comma = previous_comma if isinstance(previous_comma, cst.Comma) else cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))
    return [*args[:index], new.with_changes(comma=comma), *args[index:]]


def _without_alias(node: Any, bound: str) -> Any:
    """``from m import a, make, b`` without ``make`` (the names around it keep their commas)."""
    names = list(node.names)
    kept = [alias for alias in names if (alias.asname.name.value if alias.asname else alias.name.value) != bound]
    if len(kept) == len(names) or not kept:
        return node
    if names[-1] is not kept[-1]:
        kept[-1] = kept[-1].with_changes(comma=names[-1].comma)
    return node.with_changes(names=kept)
