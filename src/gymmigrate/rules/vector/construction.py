"""Constructing vector envs (GM701, GM702).

* GM701 ``gym.vector.make(id, n, asynchronous=..., wrappers=w, **kw)`` ->
  ``gym.make_vec(id, num_envs=n, vectorization_mode="async"/"sync", wrappers=[w], **kw)``.
  Gymnasium 1.0 removed ``gymnasium.vector.make``. The mode is always written out: the
  legacy default was async, while ``make_vec`` without a mode picks the env's
  ``vector_entry_point`` (for CartPole a different class, which rejects ``wrappers=``).
  ``wrappers`` must be a sequence; arguments of the vector class go in ``vector_kwargs``.
* GM702 ``SyncVectorEnv/AsyncVectorEnv(fns, observation_space, action_space)``: those
  parameters are gone (1.x has ``observation_mode``); reported. Dropped where they are
  ``env.observation_space``/``env.action_space`` of one env every function of ``fns``
  copies (``[lambda: env] * n``, a def returning ``cloudpickle.loads(cloudpickle.dumps(env))``),
  also when they come in a tuple a def of the module returns (``constructor(*args)``
  -> ``constructor(args[0])``): they are then the sub-envs' own spaces, which is what
  Gymnasium takes when none are passed (gym 0.26 checked that every sub-env's matched).

Source: Gymnasium ``envs/registration.py::make_vec``, ``vector/sync_vector_env.py``,
``vector/async_vector_env.py``.
"""

from __future__ import annotations

import ast
import builtins
from collections.abc import Callable, Sequence
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
        if self._drop_own_spaces(call):
            return
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

    # GM702's certain case: the spaces of the one env that every env function copies.

    def _drop_own_spaces(self, call: ast.Call) -> bool:
        """Drop legacy spaces that are certainly the sub-envs' own; True if it did."""
        if len(call.args) == 1 and isinstance(call.args[0], ast.Starred):
            if any(kw.arg in ("observation_space", "action_space") or kw.arg is None for kw in call.keywords):
                return False
            source = call.args[0].value
            returned = self._returned_tuples(source)
            if not returned or not all(self._own_spaces(items[0], items[1:]) for items in returned):
                return False
            self.plan.replace(call, _first_of_starred)
            self.report(
                call,
                "GM702",
                f"`*{self.facts.segment(source)}` holds (env functions, legacy spaces) and the spaces are those of "
                f"the env each function copies: only the env functions are passed (Gymnasium takes the sub-envs' "
                "own spaces, equal to those of the env they copy)",
                FixKind.AUTO,
            )
            return True
        if any(isinstance(a, ast.Starred) for a in call.args) or any(kw.arg is None for kw in call.keywords):
            return False
        if not call.args:
            return False
        given: dict[str, ast.expr] = dict(zip(("observation_space", "action_space"), call.args[1:3]))
        for kw in call.keywords:
            if kw.arg in ("observation_space", "action_space"):
                if kw.arg in given:
                    return False  # a space both by position and by name: legacy's own TypeError
                given[kw.arg] = kw.value
        if not given or not self._own_spaces(call.args[0], [given.get("observation_space"), given.get("action_space")]):
            return False
        dropped_positions = frozenset(range(1, min(len(call.args), 3)))
        dropped_names = frozenset(kw.arg for kw in call.keywords if kw.arg in ("observation_space", "action_space"))
        self.plan.replace(call, lambda node: _without_arguments(node, dropped_positions, dropped_names))
        self.report(
            call,
            "GM702",
            "the legacy spaces are those of the env each function copies: dropped (Gymnasium takes the sub-envs' own "
            "spaces, equal to those of the env they copy)",
            FixKind.AUTO,
        )
        return True

    def _returned_tuples(self, source: ast.expr) -> list[list[ast.expr]]:
        """The (fns, observation_space[, action_space]) tuples ``source`` can be: every return
        of the def of this module it calls (directly or through a name bound once)."""
        if isinstance(source, ast.Name):
            bindings = self.facts.bindings_of(source)
            if len(bindings) != 1 or not isinstance(bindings[0], ast.Name):
                return []
            assign = self.facts.parent(bindings[0])
            if not (isinstance(assign, ast.Assign) and len(assign.targets) == 1 and assign.targets[0] is bindings[0]):
                return []
            source = assign.value
        if not (isinstance(source, ast.Call) and isinstance(source.func, ast.Name)):
            return []
        defs = self.facts.bindings_of(source.func)
        if len(defs) != 1 or not isinstance(defs[0], ast.FunctionDef) or defs[0].decorator_list:
            return []  # a decorator may return something else
        returns = _own_returns(defs[0])
        if returns is None:
            return []
        tuples: list[list[ast.expr]] = []
        for value in returns:
            if not (isinstance(value, ast.Tuple) and len(value.elts) in (2, 3)):
                return []
            if any(isinstance(e, ast.Starred) for e in value.elts):
                return []
            tuples.append(list(value.elts))
        return tuples

    def _own_spaces(self, fns: ast.expr, spaces: Sequence[ast.expr | None]) -> bool:
        """``spaces`` are ``env.observation_space``/``env.action_space`` of one name ``env``,
        bound once, and every function of ``fns`` returns ``env`` or a copy of it."""
        env: ast.Name | None = None
        for space, attr in zip(spaces, ("observation_space", "action_space")):
            if space is None:
                continue
            if not (isinstance(space, ast.Attribute) and space.attr == attr and isinstance(space.value, ast.Name)):
                return False
            if env is not None and space.value.id != env.id:
                return False
            env = space.value
        if env is None:
            return False
        binding = self.facts.bindings_of(env)
        if len(binding) != 1:
            return False  # a name rebound later may be another env when the functions run
        functions = _env_functions(fns)
        return bool(functions) and all(self._returns_copy_of(f, binding[0]) for f in functions)

    def _returns_copy_of(self, function: ast.expr, binding: ast.AST) -> bool:
        if isinstance(function, ast.Lambda):
            return not _has_parameters(function.args) and self._copy_of(function.body, binding)
        if not isinstance(function, ast.Name):
            return False
        defs = self.facts.bindings_of(function)
        if len(defs) != 1 or not isinstance(defs[0], ast.FunctionDef) or _has_parameters(defs[0].args):
            return False
        if defs[0].decorator_list:
            return False  # a decorator may return something else
        returns = _own_returns(defs[0])
        return bool(returns) and all(self._copy_of(value, binding) for value in returns or ())

    def _copy_of(self, value: ast.expr | None, binding: ast.AST, depth: int = 0) -> bool:
        """``value`` is the env bound at ``binding``, ``copy.deepcopy`` of it, or a pickle round trip."""
        if value is None or depth > 3:
            return False
        if isinstance(value, ast.Name):
            bindings = self.facts.bindings_of(value)
            if bindings == [binding]:
                return True
            # ``env_copy = cloudpickle.loads(cloudpickle.dumps(env)); return env_copy``
            if len(bindings) == 1 and isinstance(bindings[0], ast.Name):
                assign = self.facts.parent(bindings[0])
                if isinstance(assign, ast.Assign) and assign.targets == [bindings[0]]:
                    return self._copy_of(assign.value, binding, depth + 1)
            return False
        if not (isinstance(value, ast.Call) and len(value.args) == 1 and not value.keywords):
            return False
        names = self.facts.qualified_names(value.func)
        if names & {"copy.deepcopy", "copy.copy"}:
            return self._copy_of(value.args[0], binding, depth + 1)
        inner = value.args[0]
        if any(n.endswith(".loads") and n.split(".")[0] in _PICKLERS for n in names) and isinstance(inner, ast.Call):
            dumps = self.facts.qualified_names(inner.func)
            if any(n.endswith(".dumps") and n.split(".")[0] in _PICKLERS for n in dumps) and len(inner.args) == 1:
                return self._copy_of(inner.args[0], binding, depth + 1)
        return False


_PICKLERS = frozenset({"pickle", "cloudpickle", "dill"})


def _has_parameters(args: ast.arguments) -> bool:
    return bool(args.posonlyargs or args.args or args.vararg or args.kwonlyargs or args.kwarg)


def _own_returns(function: ast.FunctionDef) -> list[ast.expr | None] | None:
    """The values ``function`` itself returns (not its nested defs'); None for a generator
    or a body that can end without a return."""
    values: list[ast.expr | None] = []
    stack: list[ast.AST] = list(function.body)
    while stack:
        node = stack.pop()
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)):
            continue
        if isinstance(node, (ast.Yield, ast.YieldFrom)):
            return None
        if isinstance(node, ast.Return):
            values.append(node.value)
        stack.extend(ast.iter_child_nodes(node))
    if not function.body or not isinstance(function.body[-1], ast.Return):
        return None
    return values


def _env_functions(fns: ast.expr) -> list[ast.expr]:
    """The functions a literal list of env functions holds: ``[f] * n``, ``[f, g]``,
    ``[f for _ in range(n)]``; empty when it is not such a literal."""
    if isinstance(fns, ast.BinOp) and isinstance(fns.op, ast.Mult):
        for side in (fns.left, fns.right):
            if isinstance(side, (ast.List, ast.Tuple)):
                return _env_functions(side)
        return []
    if isinstance(fns, (ast.List, ast.Tuple)):
        if not fns.elts or any(isinstance(e, ast.Starred) for e in fns.elts):
            return []
        return list(fns.elts)
    if isinstance(fns, ast.ListComp):
        return [fns.elt]
    return []


# -- builds (LibCST) ------------------------------------------------------------------------


def _first_of_starred(node: cst.Call) -> cst.Call:
    """``f(*args)`` -> ``f(args[0])``."""
    arg = node.args[0]
    index = cst.Subscript(value=arg.value, slice=[cst.SubscriptElement(cst.Index(cst.Integer("0")))])
    return node.with_changes(args=[arg.with_changes(star="", value=index), *node.args[1:]])


def _without_arguments(node: cst.Call, positions: frozenset[int], names: frozenset[str]) -> cst.Call:
    """``node`` without its positional arguments at ``positions`` and keywords ``names``;
    the last kept argument takes the old last one's trailing comma."""
    args = list(node.args)
    kept: list[cst.Arg] = []
    position = 0
    for arg in args:
        if arg.keyword is None and not arg.star:
            position += 1
            if position - 1 in positions:
                continue
        elif arg.keyword is not None and arg.keyword.value in names:
            continue
        kept.append(arg)
    if kept and kept[-1] is not args[-1]:
        kept[-1] = kept[-1].with_changes(comma=args[-1].comma)
    return node.with_changes(args=kept)


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
