"""Where was this env created? Finds the ``gym.make(...)`` calls behind an expression.

Rendering (GM401-GM403, GM407) and vector rules (GM705, GM706) must change the call
that *created* an env, not the call site that uses it: Gymnasium fixes the render mode
and the vector autoreset mode at construction. This module follows an expression back
to those calls through the same evidence the receiver analysis trusts: assignments in
the scope (``env = gym.make(...)``, then ``env = SomeWrapper(env)``), ``self.env = ...``
stores in the same class, ``with ... as env``, returns of functions defined in the
module, and the env factories in an SB3 ``DummyVecEnv([lambda: gym.make(...)])`` list.

The answer says whether the search was complete: a rule may only rewrite a creation
site when every path was followed (a parameter, an import or an unknown factory makes
the answer incomplete, and the rule reports instead).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import libcst as cst
from libcst.metadata import Assignment, ScopeProvider

from gymmigrate.analysis import names as N
from gymmigrate.analysis.receivers import ReceiverAnalysis
from gymmigrate.analysis.syntax import keyword_argument, own_return_values

try:  # LibCST resolves some providers lazily
    from libcst._metadata_dependent import LazyValue
except ImportError:  # pragma: no cover
    LazyValue = ()  # type: ignore[assignment,misc]

# SB3 / baselines VecEnv constructors that take a list of env factories.
_ENV_FN_LIST_CONSTRUCTORS = ("DummyVecEnv", "SubprocVecEnv", "SyncVectorEnv", "AsyncVectorEnv")


@dataclass
class Creation:
    """The creation calls found for one expression, and whether the search was complete."""

    calls: list[cst.Call] = field(default_factory=list)
    complete: bool = True
    # Why the search stopped, for the report ("`env` is a function parameter").
    gap: str = ""

    def add(self, call: cst.Call) -> None:
        if not any(c is call for c in self.calls):
            self.calls.append(call)

    def merge(self, other: Creation) -> None:
        for call in other.calls:
            self.add(call)
        if not other.complete:
            self.complete = False
            self.gap = self.gap or other.gap

    def fail(self, gap: str) -> None:
        self.complete = False
        self.gap = self.gap or gap

    @property
    def found(self) -> bool:
        return self.complete and bool(self.calls)


class CreationFinder:
    """Follows expressions of one module back to the calls that created them.

    ``is_creation(call)`` says which calls end the search (``gym.make`` for render
    modes; vector constructors for autoreset); every other call is followed only if it
    looks like a wrapper around its first argument.
    """

    def __init__(
        self,
        analysis: ReceiverAnalysis,
        metadata: Mapping[type, Mapping[cst.CSTNode, object]],
        is_creation: Callable[[cst.Call], bool],
    ) -> None:
        self.analysis = analysis
        self._scopes = metadata[ScopeProvider]
        self._is_creation = is_creation
        self._calls_by_name: dict[str, list[cst.Call]] | None = None

    def find(self, expr: cst.BaseExpression) -> Creation:
        return self._expr(expr, set())

    # -- expressions --------------------------------------------------------------------

    def _expr(self, expr: cst.BaseExpression, seen: set[int]) -> Creation:
        result = Creation()
        if isinstance(expr, cst.Call):
            return self._call(expr, seen)
        if isinstance(expr, cst.Name):
            return self._name(expr, seen)
        if isinstance(expr, cst.Attribute):
            return self._attribute(expr, seen)
        if isinstance(expr, cst.IfExp):
            result.merge(self._expr(expr.body, seen))
            result.merge(self._expr(expr.orelse, seen))
            return result
        if isinstance(expr, cst.NamedExpr):
            return self._expr(expr.value, seen)
        if isinstance(expr, cst.Subscript):
            return self._items(expr.value, seen)
        result.fail(f"`{_text(expr)}` is not a call or a name")
        return result

    def _items(self, container: cst.BaseExpression, seen: set[int]) -> Creation:
        """The envs held in a list: ``envs[0]``, ``for env in envs``."""
        result = Creation()
        if isinstance(container, (cst.List, cst.Tuple)):
            for element in container.elements:
                if isinstance(element, cst.StarredElement):
                    result.fail("a starred element")
                else:
                    result.merge(self._expr(element.value, seen))
            return result
        if isinstance(container, (cst.ListComp, cst.GeneratorExp)):
            return self._expr(container.elt, seen)
        if isinstance(container, cst.Name):
            scope = _metadata(self._scopes, container)
            assignments = list(scope[container.value]) if scope is not None else []  # type: ignore[index]
            if not assignments:
                result.fail(f"`{container.value}` is never assigned here")
            for assignment in assignments:
                target = assignment.node if isinstance(assignment, Assignment) else None
                parent = self.analysis.parent(target) if target is not None else None
                assign = self.analysis.parent(parent) if isinstance(parent, cst.AssignTarget) else None
                if isinstance(assign, cst.Assign) and id(target) not in seen:
                    result.merge(self._items(assign.value, seen | {id(target)}))
                else:
                    result.fail(f"`{container.value}` is not a list built here")
            return result
        result.fail(f"`{_text(container)}` is not a list built here")
        return result

    def _call(self, call: cst.Call, seen: set[int]) -> Creation:
        result = Creation()
        if self._is_creation(call):
            result.add(call)
            return result
        callee = _text(call.func)
        last = callee.rsplit(".", 1)[-1]
        if last in _ENV_FN_LIST_CONSTRUCTORS and call.args:
            return self._env_fn_list(call.args[0].value, seen)
        function = self.analysis.local_function(call.func)
        if function is not None:
            return self._returns(function, seen)
        inner = _wrapped_env_argument(call)
        if inner is not None and _looks_like_wrapper(call, self.analysis):
            return self._expr(inner, seen)
        result.fail(f"`{callee}(...)` is not a known env factory")
        return result

    def _env_fn_list(self, fns: cst.BaseExpression, seen: set[int]) -> Creation:
        """``[lambda: gym.make(...)]``, ``[make_env(i) for i in range(n)]``, ``[fn] * n``."""
        result = Creation()
        if isinstance(fns, cst.BinaryOperation) and isinstance(fns.operator, cst.Multiply):
            fns = fns.left
        if isinstance(fns, (cst.List, cst.Tuple)):
            items = [el.value for el in fns.elements]
        elif isinstance(fns, (cst.ListComp, cst.GeneratorExp)):
            items = [fns.elt]
        else:
            result.fail(f"`{_text(fns)}` is not a list of env factories")
            return result
        for item in items:
            if isinstance(item, cst.Lambda):
                result.merge(self._expr(item.body, seen))
            elif isinstance(item, cst.Name) and self.analysis.local_function(item) is not None:
                result.merge(self._returns(self.analysis.local_function(item), seen))
            elif isinstance(item, cst.Call) and self.analysis.local_function(item.func) is not None:
                # ``make_env(i)`` returning a thunk ``def thunk(): return gym.make(...)``
                result.merge(self._thunk_factory(self.analysis.local_function(item.func), seen))
            else:
                result.fail(f"`{_text(item)}` is not an env factory defined here")
        return result

    def _thunk_factory(self, function: cst.FunctionDef, seen: set[int]) -> Creation:
        result = Creation()
        returned = own_return_values(function)
        if not returned:
            result.fail(f"`{function.name.value}` returns nothing")
        for value in returned:
            if isinstance(value, cst.Lambda):
                result.merge(self._expr(value.body, seen))
                continue
            inner = _nested_function(function, value)
            if inner is None:
                result.fail(f"`{function.name.value}` does not return an env factory")
            else:
                result.merge(self._returns(inner, seen))
        return result

    def _returns(self, function: cst.FunctionDef, seen: set[int]) -> Creation:
        result = Creation()
        if id(function) in seen:
            return result
        seen = seen | {id(function)}
        values = own_return_values(function)
        if not values:
            result.fail(f"`{function.name.value}` returns nothing")
        for value in values:
            result.merge(self._expr(value, seen))
        return result

    def _name(self, name: cst.Name, seen: set[int]) -> Creation:
        result = Creation()
        scope = _metadata(self._scopes, name)
        if scope is None:
            result.fail(f"`{name.value}` has no scope")
            return result
        assignments = list(scope[name.value])  # type: ignore[index]
        if not assignments:
            result.fail(f"`{name.value}` is never assigned here")
        for assignment in assignments:
            if not isinstance(assignment, Assignment):
                result.fail(f"`{name.value}` is imported or a builtin")
                continue
            target = assignment.node
            if id(target) in seen:  # ``env = Wrapper(env)``: the chain loops back
                continue
            result.merge(self._assignment(target, name.value, seen | {id(target)}))
        return result

    def _assignment(self, target: cst.CSTNode, label: str, seen: set[int]) -> Creation:
        result = Creation()
        if isinstance(target, cst.Param):
            return self._parameter(target, label, seen)
        parent = self.analysis.parent(target)
        if isinstance(parent, cst.AssignTarget):
            assign = self.analysis.parent(parent)
            if isinstance(assign, cst.Assign):
                return self._expr(assign.value, seen)
        if isinstance(parent, cst.AnnAssign) and parent.value is not None:
            return self._expr(parent.value, seen)
        if isinstance(parent, cst.NamedExpr):
            return self._expr(parent.value, seen)
        if isinstance(parent, cst.AsName):
            item = self.analysis.parent(parent)
            if isinstance(item, cst.WithItem):
                return self._expr(item.item, seen)
        if isinstance(parent, (cst.For, cst.CompFor)) and parent.target is target:
            return self._items(parent.iter, seen)
        result.fail(f"`{label}` is assigned in a way that is not followed")
        return result

    def _parameter(self, param: cst.Param, label: str, seen: set[int]) -> Creation:
        """A parameter of a module-level function: the arguments at its call sites in this module."""
        result = Creation()
        function = self.analysis.enclosing(param, cst.FunctionDef)
        if not isinstance(function, cst.FunctionDef) or self.analysis.parent(function) is not self._module_of(function):
            result.fail(f"`{label}` is a function parameter")
            return result
        params = list(function.params.posonly_params) + list(function.params.params)
        position = next((i for i, p in enumerate(params) if p is param), None)
        calls = [c for c in self._calls_to(function) if not any(a.star for a in c.args)]
        if not calls:
            result.fail(f"`{label}` is a parameter of `{function.name.value}`, which is not called here")
            return result
        for call in calls:
            argument = keyword_argument(call, label)
            positional = [a for a in call.args if a.keyword is None]
            if argument is None and position is not None and position < len(positional):
                argument = positional[position]
            if argument is None:
                result.fail(f"`{label}` is not passed at every call of `{function.name.value}`")
            else:
                result.merge(self._expr(argument.value, seen))
        return result

    def _module_of(self, node: cst.CSTNode) -> cst.CSTNode | None:
        current: cst.CSTNode | None = node
        while current is not None and not isinstance(current, cst.Module):
            current = self.analysis.parent(current)
        return current

    def _calls_to(self, function: cst.FunctionDef) -> list[cst.Call]:
        if self._calls_by_name is None:
            module = self._module_of(function)
            if module is None:
                return []
            collector = _NamedCalls()
            module.visit(collector)
            self._calls_by_name = collector.calls
        calls = self._calls_by_name.get(function.name.value, [])
        return [c for c in calls if self.analysis.local_function(c.func) is function]

    def _attribute(self, attr: cst.Attribute, seen: set[int]) -> Creation:
        result = Creation()
        if isinstance(attr.value, cst.Name) and attr.value.value == "self":
            classdef = self.analysis.enclosing(attr, cst.ClassDef)
            if not isinstance(classdef, cst.ClassDef):
                result.fail("`self` outside a class")
                return result
            key = hash((id(classdef), attr.attr.value))
            if key in seen:
                return result
            values = _self_stores(classdef, attr.attr.value)
            if not values:
                result.fail(f"`self.{attr.attr.value}` is never assigned in the class")
            for value in values:
                result.merge(self._expr(value, seen | {key}))
            return result
        if attr.attr.value in ("env", "unwrapped", "venv"):
            # ``wrapper.env`` / ``env.unwrapped``: the same underlying env
            return self._expr(attr.value, seen)
        result.fail(f"`{_text(attr)}` is not followed")
        return result


# -- helpers ---------------------------------------------------------------------------


def _metadata(mapping: Mapping[cst.CSTNode, object], node: cst.CSTNode) -> object:
    value = mapping.get(node)
    if LazyValue and isinstance(value, LazyValue):
        value = value()
    return value


def _text(node: cst.CSTNode) -> str:
    return cst.Module(body=[]).code_for_node(node)


def _wrapped_env_argument(call: cst.Call) -> cst.BaseExpression | None:
    for arg in call.args:
        if arg.keyword is not None and arg.keyword.value in ("env", "venv"):
            return arg.value
    if call.args and call.args[0].keyword is None and not call.args[0].star:
        return call.args[0].value
    return None


def _looks_like_wrapper(call: cst.Call, analysis: ReceiverAnalysis) -> bool:
    """``SomeWrapper(env, ...)``: a gym wrapper, a wrapper class of this module, or a class."""
    for q in analysis.qualified_names(call.func):
        rest = N.strip_gym_prefix(q)
        if rest is not None:
            return rest.startswith("wrappers.")
        if q.startswith(N.SB3_VEC_PREFIXES) or N.top_package(q) in N.SB3_PACKAGES:
            name = q.rsplit(".", 1)[-1]
            return name[:1].isupper()
        if N.top_package(q) in N.NOT_ENV_PACKAGES:
            return False
    local = analysis.local_class(call.func)
    if local is not None:
        return True
    name = _text(call.func).rsplit(".", 1)[-1]
    return name[:1].isupper() and not name.isupper()


def _nested_function(function: cst.FunctionDef, value: cst.BaseExpression) -> cst.FunctionDef | None:
    if not isinstance(value, cst.Name) or not isinstance(function.body, cst.IndentedBlock):
        return None
    for statement in function.body.body:
        if isinstance(statement, cst.FunctionDef) and statement.name.value == value.value:
            return statement
    return None


def _self_stores(classdef: cst.ClassDef, name: str) -> list[cst.BaseExpression]:
    collector = _SelfStores(name)
    classdef.body.visit(collector)
    return collector.values


class _NamedCalls(cst.CSTVisitor):
    """Calls of plain names (``evaluate(env)``), by name."""

    def __init__(self) -> None:
        self.calls: dict[str, list[cst.Call]] = {}

    def visit_Call(self, node: cst.Call) -> None:
        if isinstance(node.func, cst.Name):
            self.calls.setdefault(node.func.value, []).append(node)


class _SelfStores(cst.CSTVisitor):
    def __init__(self, name: str) -> None:
        self.name = name
        self.values: list[cst.BaseExpression] = []

    def visit_ClassDef(self, node: cst.ClassDef) -> bool:
        return False

    def _is_target(self, node: cst.BaseExpression) -> bool:
        return (
            isinstance(node, cst.Attribute)
            and isinstance(node.value, cst.Name)
            and node.value.value == "self"
            and node.attr.value == self.name
        )

    def visit_Assign(self, node: cst.Assign) -> None:
        for target in node.targets:
            if self._is_target(target.target):
                self.values.append(node.value)

    def visit_AnnAssign(self, node: cst.AnnAssign) -> None:
        if self._is_target(node.target) and node.value is not None:
            self.values.append(node.value)


# -- argument editing (shared by the render and vector passes) ----------------------------




def has_star_kwargs(call: cst.Call) -> bool:
    return any(arg.star == "**" for arg in call.args)


def append_keyword(call: cst.Call, name: str, value: cst.BaseExpression) -> cst.Call:
    """Add ``name=value`` as the last argument, in the call's own layout.

    In a one-line call it follows ``, ``; in a call with one argument per line it gets
    its own line with the same indentation and the trailing comma is kept.
    """
    new_arg = cst.Arg(
        keyword=cst.Name(name),
        value=value,
        equal=cst.AssignEqual(whitespace_before=cst.SimpleWhitespace(""), whitespace_after=cst.SimpleWhitespace("")),
    )
    args = list(call.args)
    if not args:
        return call.with_changes(args=[new_arg])
    last = args[-1]
    if isinstance(last.comma, cst.Comma):
        # Trailing comma: the separator before ``last`` carries the per-line indentation.
        if len(args) >= 2 and isinstance(args[-2].comma, cst.Comma):
            separator = args[-2].comma
        else:
            separator = cst.Comma(whitespace_after=call.whitespace_before_args)
        args[-1] = last.with_changes(comma=separator)
        args.append(new_arg.with_changes(comma=last.comma))
    else:
        args[-1] = last.with_changes(comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" ")))
        args.append(new_arg.with_changes(whitespace_after_arg=last.whitespace_after_arg))
        args[-2] = args[-2].with_changes(whitespace_after_arg=cst.SimpleWhitespace(""))
    return call.with_changes(args=args)


def remove_args(call: cst.Call, drop: Callable[[cst.Arg], bool]) -> cst.Call:
    """Drop some arguments, keeping the separators of those that stay."""
    args = list(call.args)
    kept = [arg for arg in args if not drop(arg)]
    if len(kept) == len(args):
        return call
    if not kept:
        return call.with_changes(args=[], whitespace_before_args=cst.SimpleWhitespace(""))
    if args[-1] is not kept[-1]:
        # The old last argument went away: the new last one takes its comma (or none).
        kept[-1] = kept[-1].with_changes(comma=args[-1].comma, whitespace_after_arg=args[-1].whitespace_after_arg)
    return call.with_changes(args=kept)
