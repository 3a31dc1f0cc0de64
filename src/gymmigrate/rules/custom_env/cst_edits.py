"""LibCST pieces the custom-env builds use to rewrite a class's methods (the apply layer:
loaded by the first build that runs, never while the family decides).

Everything here runs inside ``plan.replace(classdef, build)`` callbacks: it receives
LibCST nodes already changed by inner edits and returns new ones. The decisions (what
to rewrite, what to report) are taken on ``ast`` by the family; these helpers only
carry them out, and are purely syntactic.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import cast

import libcst as cst
import libcst.matchers as m

from gymmigrate.rules.custom_env.cst_queries import OwnBodyOnly, _index
from gymmigrate.rules.custom_env.plans import STEP_LIMIT_WORD, SUPER_RESET

_LIMIT_OPS = (cst.GreaterThan, cst.GreaterThanEqual, cst.LessThan, cst.LessThanEqual, cst.Equal)


def is_super_method_call(node: cst.CSTNode, method: str) -> bool:
    """``super().method(...)`` or ``super(Cls, self).method(...)``."""
    return m.matches(node, m.Call(func=m.Attribute(value=m.Call(func=m.Name("super")), attr=m.Name(method))))


def is_base_reset(node: cst.CSTNode, bases: frozenset[str]) -> bool:
    """``super().reset(...)``, or ``Base.reset(self, ...)`` for a base in ``bases``
    (``reset.is_base_reset``, decided on ``ast``)."""
    if is_super_method_call(node, "reset"):
        return True
    return (
        isinstance(node, cst.Call)
        and m.matches(node.func, m.Attribute(value=m.Name(), attr=m.Name("reset")))
        and node.func.value.value in bases  # type: ignore[attr-defined]
        and bool(node.args)
        and node.args[0].keyword is None
        and not node.args[0].star
        and m.matches(node.args[0].value, m.Name("self"))
    )


def _identifiers(node: cst.CSTNode) -> list[str]:
    return [n.value for n in m.findall(node, m.Name())]  # type: ignore[attr-defined]


def _append_element(elements: Sequence[cst.BaseDictElement], new: cst.DictElement) -> list[cst.BaseDictElement]:
    """Append keeping the layout: a one-line dict stays one line, a multi-line one gets a new line."""
    items = list(elements)
    if not items:
        return [new]
    last = items[-1]
    if isinstance(last.comma, cst.Comma):  # trailing comma: the new element takes over the closing layout
        between = items[-2].comma if len(items) > 1 and isinstance(items[-2].comma, cst.Comma) else cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))
        items[-1] = last.with_changes(comma=between)
        return [*items, new.with_changes(comma=last.comma)]
    items[-1] = last.with_changes(comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" ")))
    return [*items, new]


def _contains(node: cst.CSTNode, matcher: m.BaseMatcherNode) -> bool:
    return bool(m.findall(node, matcher))


def _param_names(fn: cst.FunctionDef) -> list[str]:
    params = fn.params
    found = [p.name.value for p in (*params.posonly_params, *params.params)]
    if isinstance(params.star_arg, cst.Param):
        found.append(params.star_arg.name.value)
    found += [p.name.value for p in params.kwonly_params]
    if params.star_kwarg is not None:
        found.append(params.star_kwarg.name.value)
    return found


def _body_statements(fn: cst.FunctionDef) -> list[cst.BaseStatement]:
    return list(fn.body.body) if isinstance(fn.body, cst.IndentedBlock) else []


def _is_docstring(stmt: cst.CSTNode) -> bool:
    return m.matches(stmt, m.SimpleStatementLine([m.Expr(m.SimpleString() | m.ConcatenatedString())]))


def _modern_reset_params(fn: cst.FunctionDef) -> cst.FunctionDef:
    params = fn.params
    keep = [p for p in params.params if p.name.value not in ("seed", "options", "return_info")]
    old = {p.name.value: p for p in (*params.params, *params.kwonly_params)}
    kwonly = [p for p in params.kwonly_params if p.name.value not in ("seed", "options", "return_info")]
    for name in ("seed", "options"):
        param = old.get(name) or cst.Param(cst.Name(name), default=cst.Name("None"))
        param = param.with_changes(
            default=param.default or cst.Name("None"),
            equal=cst.AssignEqual(whitespace_before=cst.SimpleWhitespace(""), whitespace_after=cst.SimpleWhitespace(""))
            if param.annotation is None
            else param.equal,
            comma=cst.MaybeSentinel.DEFAULT,
            whitespace_after_param=cst.SimpleWhitespace(""),
        )
        kwonly.append(param)
    keep = [p.with_changes(comma=cst.MaybeSentinel.DEFAULT) for p in keep]
    star_arg = params.star_arg if isinstance(params.star_arg, cst.Param) else cst.ParamStar()
    star_kwarg = params.star_kwarg.with_changes(comma=cst.MaybeSentinel.DEFAULT) if params.star_kwarg else None
    return fn.with_changes(
        params=params.with_changes(params=keep, star_arg=star_arg, kwonly_params=kwonly, star_kwarg=star_kwarg)
    )


def _add_keyword_param(params: cst.Parameters, name: str) -> cst.Parameters:
    new = cst.Param(
        cst.Name(name),
        default=cst.Name("None"),
        equal=cst.AssignEqual(whitespace_before=cst.SimpleWhitespace(""), whitespace_after=cst.SimpleWhitespace("")),
    )
    if isinstance(params.star_arg, cst.Param) or params.kwonly_params:
        return params.with_changes(kwonly_params=_append_param(params.kwonly_params, new))
    return params.with_changes(params=_append_param(params.params, new))


def _append_param(existing: Sequence[cst.Param], new: cst.Param) -> list[cst.Param]:
    items = list(existing)
    if not items:
        return [new]
    last = items[-1]
    if isinstance(last.comma, cst.Comma):
        between = items[-2].comma if len(items) > 1 and isinstance(items[-2].comma, cst.Comma) else cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))
        items[-1] = last.with_changes(comma=between)
        return [*items, new.with_changes(comma=last.comma)]
    return [*items, new]


def _insert_at_top(body: cst.BaseSuite, statements: list[cst.BaseStatement]) -> cst.BaseSuite:
    if not isinstance(body, cst.IndentedBlock):
        return body
    existing = list(body.body)
    at = 1 if existing and _is_docstring(existing[0]) else 0
    return body.with_changes(body=[*existing[:at], *statements, *existing[at:]])


def _insert_after_super_init(body: cst.BaseSuite, statement: cst.BaseStatement) -> cst.BaseSuite:
    if not isinstance(body, cst.IndentedBlock):
        return body
    existing = list(body.body)
    at = 1 if existing and _is_docstring(existing[0]) else 0
    for index, stmt in enumerate(existing[at:], start=at):
        if _contains(stmt, m.Call(func=m.Attribute(attr=m.Name("__init__")))):
            at = index + 1
            break
        if index > at + 2:
            break
    # A later base __init__ (``A.__init__(self)`` then ``B.__init__(self)`` for two bases)
    # may set the attribute itself (Gymnasium's own envs store self.render_mode from their
    # parameter, None when not given): the statement goes after the last one, or that base
    # would undo it.
    for index in range(len(existing) - 1, at - 1, -1):
        if _contains(existing[index], _BASE_INIT):
            at = index + 1
            break
    return body.with_changes(body=[*existing[:at], statement, *existing[at:]])


# ``super().__init__(...)`` / ``super(C, self).__init__(...)`` or ``Base.__init__(self, ...)``.
_BASE_INIT = m.Call(func=m.Attribute(value=m.Call(func=m.Name("super")), attr=m.Name("__init__"))) | m.Call(
    func=m.Attribute(attr=m.Name("__init__")), args=[m.Arg(value=m.Name("self")), m.ZeroOrMore()]
)


def _is_tuple_annotation(annotation: cst.BaseExpression, length: int) -> bool:
    return (
        isinstance(annotation, cst.Subscript)
        and m.matches(annotation.value, m.Name("Tuple") | m.Name("tuple") | m.Attribute(attr=m.Name("Tuple")))
        and len(annotation.slice) == length
    )


def _calls_super_reset(fn: cst.FunctionDef, bases: frozenset[str] = frozenset()) -> bool:
    return any(is_base_reset(c, bases) for c in _index(fn).calls)


def _ensure_super_reset(fn: cst.FunctionDef, bases: frozenset[str] = frozenset()) -> tuple[cst.FunctionDef, bool]:
    """Insert ``super().reset(seed=seed)`` first, or add ``seed=seed`` to an existing call."""
    if _calls_super_reset(fn, bases):
        return fn.with_changes(body=fn.body.visit(_SuperResetFixer(bases))), False
    return fn.with_changes(body=_insert_at_top(fn.body, [cst.parse_statement(SUPER_RESET)])), True


def _insert_after_super_reset(fn: cst.FunctionDef, statements: list[cst.BaseStatement], bases: frozenset[str] = frozenset()) -> cst.FunctionDef:
    body = fn.body
    if not isinstance(body, cst.IndentedBlock):
        return fn
    existing = list(body.body)
    guard = cst.If(
        test=cst.parse_expression("seed is not None"),
        body=cst.IndentedBlock([s.with_changes(leading_lines=[]) if i == 0 else s for i, s in enumerate(statements)]),
    )
    for index, stmt in enumerate(existing):
        if any(is_base_reset(c, bases) for c in m.findall(stmt, m.Call())):
            return fn.with_changes(body=body.with_changes(body=[*existing[: index + 1], guard, *existing[index + 1 :]]))
    return fn.with_changes(body=_insert_at_top(body, [guard]))


def _drop_return_info(fn: cst.FunctionDef) -> cst.FunctionDef:
    return fn.with_changes(body=fn.body.visit(_ReturnInfoRemover()))


def pair_untested_returns(fn: cst.FunctionDef) -> cst.FunctionDef:
    """``return obs`` -> ``return obs, {}`` for the returns ``reset.untested_returns`` lists
    (run on the legacy body, before the return_info branches are resolved)."""
    return fn.with_changes(body=fn.body.visit(_UntestedReturnPairer()))


def _tests_flag(test: cst.BaseExpression) -> bool:
    if m.matches(test, m.UnaryOperation(operator=m.Not())):
        test = test.expression  # type: ignore[attr-defined]
    return m.matches(test, m.Name("return_info"))


class _UntestedReturnPairer(OwnBodyOnly, cst.CSTTransformer):
    def __init__(self) -> None:
        super().__init__()
        self.after_flag_test: set[int] = set()  # statements after an ``if return_info`` in their block

    def on_visit(self, node: cst.CSTNode) -> bool:
        if id(node) in self.after_flag_test:
            return False
        return super().on_visit(node)

    def visit_IndentedBlock(self, node: cst.IndentedBlock) -> bool:
        for index, statement in enumerate(node.body):
            if isinstance(statement, cst.If) and _tests_flag(statement.test):
                self.after_flag_test.update(id(s) for s in node.body[index:])
                break
        return True

    def visit_Match(self, node: cst.Match) -> bool:
        return False

    def visit_If(self, node: cst.If) -> bool:
        return not _tests_flag(node.test)

    def leave_Return(self, original_node: cst.Return, updated_node: cst.Return) -> cst.Return:
        value = updated_node.value
        if value is None or isinstance(value, (cst.Tuple, cst.IfExp)) or m.matches(value, m.Name("None")):
            return updated_node
        if m.matches(value, m.Call(func=m.Attribute(attr=m.Name("reset") | m.Name("_reset")))):
            return updated_node
        return updated_node.with_changes(value=cst.Tuple([cst.Element(value), cst.Element(cst.Dict([]))], lpar=[], rpar=[]))


def _tuple_len(value: cst.BaseExpression | None) -> int | None:
    if isinstance(value, cst.Tuple) and not any(isinstance(el, cst.StarredElement) for el in value.elements):
        return len(value.elements)
    return None


def _is_step_limit(expr: cst.BaseExpression, data_ends: frozenset[str] = frozenset()) -> bool:
    """``facts.limit_tests.is_step_limit`` on LibCST: a comparison that names a step counter,
    not a period (``self.t % FREQ == 0``) nor one of the class's tests that are no step limit
    (``data_ends``: of the end of its data or of a run of consecutive steps, whitespace-free
    source, as the decision found them: ``ClassPlan.non_limit_tests``)."""
    if not isinstance(expr, cst.Comparison) or not all(isinstance(t.operator, _LIMIT_OPS) for t in expr.comparisons):
        return False
    if data_ends and "".join(_code(expr.with_changes(lpar=[], rpar=[])).split()) in data_ends:
        return False
    if m.findall(expr, m.BinaryOperation(operator=m.Modulo())):
        return False
    return any(STEP_LIMIT_WORD.search(word.lower()) and "beyond" not in word for word in _identifiers(expr))


def _or_operands(expr: cst.BaseExpression) -> list[cst.BaseExpression]:
    if isinstance(expr, cst.BooleanOperation) and isinstance(expr.operator, cst.Or) and not expr.lpar:
        return _or_operands(expr.left) + _or_operands(expr.right)
    if isinstance(expr, cst.BooleanOperation) and isinstance(expr.operator, cst.Or):
        return _or_operands(expr.with_changes(lpar=[], rpar=[]))
    return [expr]


def _split_done(
    expr: cst.BaseExpression, data_ends: frozenset[str] = frozenset()
) -> tuple[list[cst.BaseExpression], list[cst.BaseExpression]] | None:
    """``bool(task or self.steps >= self.max_steps)`` -> ([task], [limit]); None if no clear limit."""
    if m.matches(expr, m.Call(func=m.Name("bool"), args=[m.Arg(keyword=None)])):
        expr = expr.args[0].value  # type: ignore[attr-defined]
    operands = _or_operands(expr)
    limit = [op for op in operands if _is_step_limit(op, data_ends)]
    if not limit:
        return None
    task = [op for op in operands if not _is_step_limit(op, data_ends)]
    return task, limit


def _code(node: cst.CSTNode) -> str:
    return cst.Module([]).code_for_node(node)


def _bool_of(parts: list[cst.BaseExpression]) -> cst.BaseExpression:
    if not parts:
        return cst.Name("False")
    # A lone operand loses its own parentheses inside ``bool(...)``, except a ``yield``,
    # which is only an argument in them.
    single = len(parts) == 1 and not isinstance(parts[0], cst.Yield)
    text = " or ".join(_code(p.with_changes(lpar=[], rpar=[]) if single else p).strip() for p in parts)
    return cst.parse_expression(f"bool({text})")


def _needs_bool(expr: cst.BaseExpression) -> bool:
    return isinstance(expr, (cst.Comparison, cst.BooleanOperation, cst.UnaryOperation))


def _five(terminated: cst.BaseExpression, truncated: cst.BaseExpression) -> Callable[[cst.Return], cst.Return]:
    def rewrite(ret: cst.Return) -> cst.Return:
        value = ret.value
        assert isinstance(value, cst.Tuple)
        elements = list(value.elements)
        third = elements[2]
        elements[2:3] = [
            third.with_changes(value=terminated, comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))),
            cst.Element(truncated, comma=third.comma),
        ]
        if m.matches(elements[-1].value, m.Name("None")):
            # gym passed a step's info through as it came; Gymnasium's env checker (which make
            # puts around the env) asserts a dict, so a literal None info is the empty one
            elements[-1] = elements[-1].with_changes(value=cst.Dict([]))
        return ret.with_changes(value=value.with_changes(elements=elements))

    return rewrite


def _step_limit_text(fn: cst.FunctionDef) -> str | None:
    for comparison in _index(fn).comparisons:
        if _is_step_limit(comparison):
            return _code(comparison).strip()
    return None


def visit_suite(body: cst.BaseSuite, transformer: cst.CSTTransformer) -> cst.BaseSuite:
    """``body.visit(transformer)`` for this package's transformers: they rewrite inside the
    block and never remove or flatten the block itself (their leave_IndentedBlock returns one)."""
    return cast(cst.BaseSuite, body.visit(transformer))


def _leading_lines(stmt: cst.BaseStatement) -> Sequence[cst.EmptyLine]:
    """A statement's leading lines: every BaseStatement is a SimpleStatementLine or a
    BaseCompoundStatement, both with the field, which BaseStatement itself does not declare."""
    return cast("cst.SimpleStatementLine | cst.BaseCompoundStatement", stmt).leading_lines


def _bool_wrap_assignments(body: cst.BaseSuite, name: str) -> cst.BaseSuite:
    """``terminated = x > 1`` -> ``terminated = bool(x > 1)``: check_env wants a Python bool."""

    class Wrap(cst.CSTTransformer):
        def leave_Assign(self, original_node: cst.Assign, updated_node: cst.Assign) -> cst.Assign:
            if m.matches(updated_node, m.Assign(targets=[m.AssignTarget(m.Name(name))])) and _needs_bool(updated_node.value):
                return updated_node.with_changes(value=_bool_of([updated_node.value]))
            return updated_node

    return visit_suite(body, Wrap())


def _rename_names(node: cst.CSTNodeT, renames: dict[str, str]) -> cst.CSTNodeT:
    if not renames:
        return node
    return node.visit(_NameRenamer(renames))  # type: ignore[return-value]


# -- transformers ---------------------------------------------------------------------------------


class _ReturnRewriter(OwnBodyOnly, cst.CSTTransformer):
    def __init__(self, rewrite: Callable[[cst.Return], cst.Return]) -> None:
        self.rewrite = rewrite

    def leave_Return(self, original_node: cst.Return, updated_node: cst.Return) -> cst.Return:
        return self.rewrite(updated_node)


class _HelperReturnUnpacker(OwnBodyOnly, cst.CSTTransformer):
    """``return self._observe()`` (the function's return at a planned position) ->
    ``obs, reward, terminated, info = self._observe()`` and
    ``return obs, reward, terminated, False, info``: the helper keeps its four values."""

    def __init__(self, positions: dict[int, tuple[str, ...]]) -> None:
        self.positions = positions
        self.count = 0
        # id of a (left) Return -> the Return and its names. The node is kept alive with its id:
        # a Return dropped by the traversal frees its id, which a later bare ``return`` may then
        # reuse and be taken for it (an AssertionError on some runs, not others).
        self.split: dict[int, tuple[cst.Return, tuple[str, ...]]] = {}

    def leave_Return(self, original_node: cst.Return, updated_node: cst.Return) -> cst.Return:
        names = self.positions.get(self.count)
        self.count += 1
        if names is not None:
            self.split[id(updated_node)] = (updated_node, names)
        return updated_node

    def leave_SimpleStatementLine(
        self, original_node: cst.SimpleStatementLine, updated_node: cst.SimpleStatementLine
    ) -> cst.BaseStatement | cst.FlattenSentinel[cst.BaseStatement]:
        if len(updated_node.body) != 1:
            return updated_node
        ret = updated_node.body[0]
        split = self.split.get(id(ret))
        if split is None or split[0] is not ret:
            return updated_node
        assert isinstance(ret, cst.Return) and ret.value is not None
        obs, reward, done, info = split[1]
        targets = cst.parse_expression(f"{obs}, {reward}, {done}, {info}")
        assert isinstance(targets, cst.Tuple)
        unpack = cst.Assign(targets=[cst.AssignTarget(targets)], value=ret.value)
        five = ret.with_changes(value=cst.parse_expression(f"{obs}, {reward}, {done}, False, {info}"))
        return cst.FlattenSentinel(
            [
                updated_node.with_changes(body=[unpack], trailing_whitespace=cst.TrailingWhitespace()),
                cst.SimpleStatementLine(body=[five], trailing_whitespace=updated_node.trailing_whitespace),
            ]
        )


class _NameRenamer(cst.CSTTransformer):
    """Renames variables, not attributes, keywords or parameters spelled the same."""

    def __init__(self, renames: dict[str, str]) -> None:
        self.renames = renames

    def leave_Name(self, original_node: cst.Name, updated_node: cst.Name) -> cst.Name:
        new = self.renames.get(updated_node.value)
        return updated_node.with_changes(value=new) if new else updated_node

    def leave_Attribute(self, original_node: cst.Attribute, updated_node: cst.Attribute) -> cst.Attribute:
        return updated_node.with_changes(attr=original_node.attr)

    def leave_Arg(self, original_node: cst.Arg, updated_node: cst.Arg) -> cst.Arg:
        return updated_node.with_changes(keyword=original_node.keyword)

    def leave_Param(self, original_node: cst.Param, updated_node: cst.Param) -> cst.Param:
        return updated_node.with_changes(name=original_node.name)


def _passes_mode(arg: cst.Arg) -> bool:
    """`mode` or `mode=mode`: the render's own mode handed on."""
    named_mode = isinstance(arg.value, cst.Name) and arg.value.value == "mode"
    return named_mode and (arg.keyword is None or arg.keyword.value == "mode") and not arg.star


class _ModeReader(cst.CSTTransformer):
    """``mode`` -> ``self.render_mode`` in a render body; ``super().render(mode)`` loses its
    argument, and so does an inner env's ``env.render(mode)``, but not the render of an
    object of ``kept`` (its source text: the project's own object, which still takes it)."""

    def __init__(self, kept: frozenset[str] = frozenset()) -> None:
        super().__init__()
        self.kept = kept

    def visit_FunctionDef(self, node: cst.FunctionDef) -> bool:
        return False

    def leave_Name(self, original_node: cst.Name, updated_node: cst.Name) -> cst.BaseExpression:
        if updated_node.value == "mode":
            return cst.Attribute(value=cst.Name("self"), attr=cst.Name("render_mode"))
        return updated_node

    def leave_Attribute(self, original_node: cst.Attribute, updated_node: cst.Attribute) -> cst.Attribute:
        return updated_node.with_changes(attr=original_node.attr)

    def leave_Arg(self, original_node: cst.Arg, updated_node: cst.Arg) -> cst.Arg:
        return updated_node.with_changes(keyword=original_node.keyword)

    def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.Call:
        if is_super_method_call(original_node, "render"):
            return updated_node.with_changes(args=[])
        if (
            isinstance(original_node.func, cst.Attribute)
            and original_node.func.attr.value == "render"
            and _code(original_node.func.value) not in self.kept
        ):
            # A forwarding `env.render(mode, ...)` to an inner env: Gymnasium's render()
            # takes no mode (the inner env renders in the mode it was made with).
            args = [
                new
                for old, new in zip(original_node.args, updated_node.args)
                if not _passes_mode(old)
            ]
            if len(args) != len(updated_node.args):
                if args:
                    args[-1] = args[-1].with_changes(comma=cst.MaybeSentinel.DEFAULT)
                return updated_node.with_changes(args=args)
        return updated_node


class _SuperResetFixer(cst.CSTTransformer):
    """An existing ``super().reset(...)`` (or ``Base.reset(self)``): pass ``seed=seed`` and drop ``return_info``."""

    def __init__(self, bases: frozenset[str] = frozenset()) -> None:
        super().__init__()
        self.bases = bases

    def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.Call:
        if not is_base_reset(original_node, self.bases):
            return updated_node
        args = [a for a in updated_node.args if not (a.keyword is not None and m.matches(a.keyword, m.Name("return_info")))]
        changed = len(args) != len(updated_node.args)
        if not any(a.keyword is not None and m.matches(a.keyword, m.Name("seed")) for a in args) and not any(a.star for a in args):
            if args:
                args[-1] = args[-1].with_changes(comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" ")))
            args.append(cst.Arg(cst.Name("seed"), keyword=cst.Name("seed"), equal=cst.AssignEqual(cst.SimpleWhitespace(""), cst.SimpleWhitespace(""))))
            changed = True
        if not changed:
            return updated_node
        if args:
            args[-1] = args[-1].with_changes(comma=cst.MaybeSentinel.DEFAULT)
        return updated_node.with_changes(args=args)


class _ReturnInfoRemover(cst.CSTTransformer):
    """Keeps the ``return_info=True`` branch of ``if return_info:`` / ``... if return_info else ...``."""

    def visit_FunctionDef(self, node: cst.FunctionDef) -> bool:
        return False

    def leave_IndentedBlock(self, original_node: cst.IndentedBlock, updated_node: cst.IndentedBlock) -> cst.IndentedBlock:
        statements: list[cst.BaseStatement] = []
        # Tests are read on the original nodes: leave_Name has already replaced return_info below.
        for original, stmt in zip(original_node.body, updated_node.body):
            branch = _return_info_branch(original, stmt)
            if branch is None:
                statements.append(stmt)
                continue
            kept = list(branch.body) if isinstance(branch, cst.IndentedBlock) else []
            if kept:
                kept[0] = kept[0].with_changes(leading_lines=_leading_lines(stmt))
            statements.extend(kept)
            if kept and m.matches(kept[-1], m.SimpleStatementLine([m.Return()])):
                break  # what followed was the return_info=False path
        if not statements:
            statements = [cst.SimpleStatementLine([cst.Pass()])]
        return updated_node.with_changes(body=statements)

    def leave_IfExp(self, original_node: cst.IfExp, updated_node: cst.IfExp) -> cst.BaseExpression:
        if m.matches(original_node.test, m.Name("return_info")):
            return updated_node.body
        if m.matches(original_node.test, m.UnaryOperation(operator=m.Not(), expression=m.Name("return_info"))):
            return updated_node.orelse
        return updated_node

    def leave_Name(self, original_node: cst.Name, updated_node: cst.Name) -> cst.Name:
        return cst.Name("True") if updated_node.value == "return_info" else updated_node

    def leave_Arg(self, original_node: cst.Arg, updated_node: cst.Arg) -> cst.Arg:
        return updated_node.with_changes(keyword=original_node.keyword)

    def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.Call:
        args = [a for a in updated_node.args if not (a.keyword is not None and m.matches(a.keyword, m.Name("return_info")))]
        if len(args) == len(updated_node.args):
            return updated_node
        if args:
            args[-1] = args[-1].with_changes(comma=cst.MaybeSentinel.DEFAULT)
        return updated_node.with_changes(args=args)


def _return_info_branch(original: cst.BaseStatement, stmt: cst.BaseStatement) -> cst.BaseSuite | None:
    """For ``if return_info:`` (or ``if not return_info:``) the suite that runs when it is True."""
    if not isinstance(original, cst.If) or not isinstance(stmt, cst.If):
        return None
    if m.matches(original.test, m.Name("return_info")):
        return stmt.body
    if m.matches(original.test, m.UnaryOperation(operator=m.Not(), expression=m.Name("return_info"))):
        if isinstance(stmt.orelse, cst.Else):
            return stmt.orelse.body
        return cst.IndentedBlock([])
    return None


def _assigns_alone(line: cst.SimpleStatementLine, name: str) -> bool:
    """``name = value`` as the whole line (not ``a = name = v``, not one of several
    statements on the line): the line the done splitters replace by the ``terminated`` and
    ``truncated`` lines."""
    return m.matches(line, m.SimpleStatementLine([m.Assign(targets=[m.AssignTarget(m.Name(name))])]))


class _DoneSplitter(cst.CSTTransformer):
    """``done = bool(task or limit)`` -> ``terminated = bool(task)`` / ``truncated = bool(limit)``."""

    def __init__(self, name: str, task: list[cst.BaseExpression], limit: list[cst.BaseExpression], keep_done: bool) -> None:
        self.name = name
        self.task = task
        self.limit = limit
        self.keep_done = keep_done

    def leave_SimpleStatementLine(
        self, original_node: cst.SimpleStatementLine, updated_node: cst.SimpleStatementLine
    ) -> cst.BaseStatement | cst.FlattenSentinel[cst.BaseStatement]:
        if not _assigns_alone(updated_node, self.name):
            return updated_node
        lines = [
            updated_node.with_changes(body=[cst.Assign([cst.AssignTarget(cst.Name("terminated"))], _bool_of(self.task))]),
            cst.SimpleStatementLine([cst.Assign([cst.AssignTarget(cst.Name("truncated"))], _bool_of(self.limit))]),
        ]
        if self.keep_done:
            lines.append(cst.parse_statement(f"{self.name} = terminated or truncated"))  # type: ignore[arg-type]
        return cst.FlattenSentinel(lines)


class _PerAgentSplitter(cst.CSTTransformer):
    """``flags = <arrangement of per-agent dones>`` -> ``terminated = <it over terminations>``
    / ``truncated = <it over truncations>``, the old line kept first where other code reads it
    (arrays of flags have no ``or`` to rebuild it from the two)."""

    def __init__(self, name: str, terminated: str, truncated: str, keep: bool) -> None:
        self.name = name
        self.terminated = terminated
        self.truncated = truncated
        self.keep = keep

    def leave_SimpleStatementLine(
        self, original_node: cst.SimpleStatementLine, updated_node: cst.SimpleStatementLine
    ) -> cst.BaseStatement | cst.FlattenSentinel[cst.BaseStatement]:
        if not _assigns_alone(updated_node, self.name):
            return updated_node
        lines: list[cst.BaseStatement] = [
            updated_node.with_changes(body=[cst.Assign([cst.AssignTarget(cst.Name("terminated"))], cst.parse_expression(self.terminated))]),
            cst.SimpleStatementLine([cst.Assign([cst.AssignTarget(cst.Name("truncated"))], cst.parse_expression(self.truncated))]),
        ]
        if self.keep:
            lines.insert(0, updated_node)
            lines[1] = lines[1].with_changes(leading_lines=[])
        return cst.FlattenSentinel(lines)


class _SelfSeedCallRemover(cst.CSTTransformer):
    """Drops ``self.seed(...)`` statements, or puts ``replacement`` statements in their place;
    with ``reseed`` (the seed parameter's name, the statement), a call that passes a seed
    becomes that statement on it: the generator the call built stays built from its seed."""

    def __init__(self, replacement: list[cst.BaseStatement] | None = None, reseed: tuple[str, str] | None = None) -> None:
        self.replacement = replacement or []
        self.reseed = reseed

    def leave_IndentedBlock(self, original_node: cst.IndentedBlock, updated_node: cst.IndentedBlock) -> cst.IndentedBlock:
        kept: list[cst.BaseStatement] = []
        carried: Sequence[cst.EmptyLine] = ()
        reseeded = False
        for stmt in updated_node.body:
            if m.matches(stmt, m.SimpleStatementLine([m.Expr(m.Call(func=m.Attribute(value=m.Name("self"), attr=m.Name("seed") | m.Name("_seed"))))])):
                carried = _leading_lines(stmt)
                seed = _passed_seed(stmt, self.reseed[0]) if self.reseed is not None else None
                if seed is not None and self.reseed is not None:
                    text = self.reseed[1].format(cst.Module([]).code_for_node(seed))
                    line = cast("cst.SimpleStatementLine", cst.parse_statement(text + "\n"))
                    kept.append(line.with_changes(leading_lines=carried, trailing_whitespace=stmt.trailing_whitespace))  # type: ignore[attr-defined]
                    carried = ()
                    reseeded = True
                    continue
                if self.replacement:
                    kept.extend([self.replacement[0].with_changes(leading_lines=carried), *self.replacement[1:]])
                    carried = ()
                continue
            if carried:
                stmt = stmt.with_changes(leading_lines=[*carried, *_leading_lines(stmt)])
                carried = ()
            kept.append(stmt)
        if len(kept) == len(updated_node.body) and not self.replacement and not reseeded:
            return updated_node
        if not kept:
            kept = [cst.SimpleStatementLine([cst.Pass()])]
        return updated_node.with_changes(body=kept)


def _passed_seed(stmt: cst.BaseStatement, parameter: str) -> cst.BaseExpression | None:
    """The one seed ``self.seed(s)`` (or ``self.seed(seed=s)``) passes; None for
    ``self.seed()``, ``self.seed(None)`` or anything starred (as ``seed.passes_one_seed``)."""
    call = cast("cst.Call", cast("cst.Expr", cast("cst.SimpleStatementLine", stmt).body[0]).value)
    if len(call.args) != 1:
        return None
    arg = call.args[0]
    if arg.star or (arg.keyword is not None and arg.keyword.value != parameter):
        return None
    if isinstance(arg.value, cst.Name) and arg.value.value == "None":
        return None
    return arg.value


class _SelfMethodCallRenamer(cst.CSTTransformer):
    def __init__(self, renames: dict[str, str]) -> None:
        self.renames = renames

    def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.Call:
        func = updated_node.func
        if m.matches(func, m.Attribute(value=m.Name("self"))) and func.attr.value in self.renames:  # type: ignore[attr-defined]
            return updated_node.with_changes(func=func.with_changes(attr=cst.Name(self.renames[func.attr.value])))  # type: ignore[attr-defined]
        return updated_node


class _SelfResetUnpacker(cst.CSTTransformer):
    """``x = self.reset()`` -> ``x, _ = self.reset()``; so for the base's reset a helper
    calls, ``super().reset()`` or ``Base.reset(self)`` (``bases``)."""

    def __init__(self, bases: frozenset[str] = frozenset()) -> None:
        super().__init__()
        self.bases = bases

    def leave_Assign(self, original_node: cst.Assign, updated_node: cst.Assign) -> cst.Assign:
        reset = m.Call(func=m.Attribute(value=m.Name("self"), attr=m.Name("reset") | m.Name("_reset")))
        value = updated_node.value
        if not (m.matches(value, reset) or is_base_reset(value, self.bases)):
            return updated_node
        if not m.matches(updated_node, m.Assign(targets=[m.AssignTarget(m.Name() | m.Attribute())])):
            return updated_node
        target = cst.Tuple([cst.Element(updated_node.targets[0].target), cst.Element(cst.Name("_"))], lpar=[], rpar=[])
        return updated_node.with_changes(targets=[updated_node.targets[0].with_changes(target=target)])
