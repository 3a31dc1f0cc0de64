"""Wrapper subclasses: ``reset`` and ``step`` overrides keep Gymnasium's contract (GM601-GM603).

Gymnasium 0.26 changed ``Wrapper.reset`` to return ``(obs, info)`` and ``Wrapper.step``
to return ``(obs, reward, terminated, truncated, info)``; every wrapper that overrides
them must return the new shapes, or the next wrapper up (``TimeLimit`` from
``gym.make`` first) fails with "not enough values to unpack".

By the time this pass runs, the reset pass (ORDER 50) and the step pass (ORDER 55) have
rewritten the *calls* inside the overrides (``obs, info = self.env.reset(**kwargs)``,
``obs, reward, terminated, truncated, info = self.env.step(action)`` plus
``done = terminated or truncated`` when ``done`` is read later). This pass fixes what the
override itself returns:

* GM601 (ASSIST) ``reset`` returns ``(obs, info)``: ``return self._process(obs)`` ->
  ``return self._process(obs), info`` with the info of the inner reset (``{}`` when the
  override has none, e.g. baselines' FireResetEnv, which resets and then steps).
  Pass-throughs (``return self.env.reset(**kwargs)``) stay. A ``def reset(self)`` gets
  Gymnasium's ``*, seed=None, options=None`` keywords, because outer wrappers always pass them.
* GM602 (AUTO, ASSIST when the override changes ``done`` itself) ``step`` returns five
  values: ``return obs, reward, done, info`` -> ``return obs, reward, terminated,
  truncated, info``, with the names of the five-target unpack; the inserted ``done = ...``
  line is dropped when nothing reads ``done`` any more.
* GM603 (FLAG) ``__init__`` that never calls ``super().__init__(env)``: Gymnasium's
  ``Wrapper.__init__`` sets up ``env`` and the space/metadata properties.

GM607 (``ActionWrapper.reverse_action``) is deliberately not a rule: a user definition
is harmless (Gymnasium just never calls it), so a finding would only add review noise.

If the earlier passes left a legacy call in an override (four-target step unpack,
one-target reset), this pass completes it in the same way, so a wrapper always comes
out whole. Sources: Gymnasium ``core.py`` (``Wrapper.reset``/``step``/``__init__``);
migration guide "Step API" and "Reset".

Wrapper *usage* (attribute forwarding, renamed and removed wrappers, Monitor...) lives in
the ``wrapper_usage`` package, which ``rules/__init__.py`` imports so that its families register.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import libcst as cst
from libcst.metadata import PositionProvider

from gymmigrate.analysis.receivers import METADATA, ReceiverAnalysis
from gymmigrate.analysis.syntax import own_returns
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileProfile, Rule, RulePass

RULES = (
    Rule(
        "GM601",
        "wrapper reset returns (obs, info)",
        FixKind.ASSIST,
        "A wrapper's `reset` override returns `(obs, info)`; pass-throughs stay.",
    ),
    Rule(
        "GM602",
        "wrapper step returns five values",
        FixKind.AUTO,
        "A wrapper's `step` override returns `(obs, reward, terminated, truncated, info)`.",
    ),
    Rule(
        "GM603",
        "wrapper __init__ without super().__init__",
        FixKind.FLAG,
        "A wrapper whose `__init__` never calls `super().__init__(env)` is reported.",
    ),
)

_INNER_METHODS = ("reset", "step")


# -- small syntax helpers -------------------------------------------------------------


def _is_inner_env(node: cst.BaseExpression) -> bool:
    """``self.env`` or ``super()`` / ``super(Cls, self)``: what an override delegates to."""
    if isinstance(node, cst.Attribute):
        return isinstance(node.value, cst.Name) and node.value.value == "self" and node.attr.value == "env"
    return isinstance(node, cst.Call) and isinstance(node.func, cst.Name) and node.func.value == "super"


def _inner_call(node: cst.BaseExpression | None, method: str) -> cst.Call | None:
    """``node`` if it is ``self.env.<method>(...)`` or ``super().<method>(...)``."""
    if (
        isinstance(node, cst.Call)
        and isinstance(node.func, cst.Attribute)
        and node.func.attr.value == method
        and _is_inner_env(node.func.value)
    ):
        return node
    return None


def _target_names(target: cst.BaseExpression) -> list[str] | None:
    """``a, b, _`` -> ["a", "b", "_"]; None when an element is not a plain name."""
    if not isinstance(target, (cst.Tuple, cst.List)):
        return None
    names = []
    for element in target.elements:
        if isinstance(element, cst.StarredElement) or not isinstance(element.value, cst.Name):
            return None
        names.append(element.value.value)
    return names


def _single_assign(line: cst.CSTNode) -> cst.Assign | None:
    if isinstance(line, cst.SimpleStatementLine) and len(line.body) == 1 and isinstance(line.body[0], cst.Assign):
        assign = line.body[0]
        if len(assign.targets) == 1:
            return assign
    return None


def _assigned_names(line: cst.CSTNode) -> set[str]:
    names: set[str] = set()
    if not isinstance(line, cst.SimpleStatementLine):
        return names
    for small in line.body:
        targets: list[cst.BaseExpression] = []
        if isinstance(small, cst.Assign):
            targets = [t.target for t in small.targets]
        elif isinstance(small, cst.AnnAssign) and small.value is not None:
            targets = [small.target]
        for target in targets:
            if isinstance(target, cst.Name):
                names.add(target.value)
            else:
                names.update(_target_names(target) or ())
    return names


def _tuple(elements: Sequence[cst.BaseExpression], like: cst.Tuple | None = None) -> cst.Tuple:
    """A tuple with ``, `` separators, keeping the parentheses of ``like`` if it had any."""
    items = [
        cst.Element(value=e, comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" ")))
        for e in elements[:-1]
    ] + [cst.Element(value=elements[-1])]
    if like is not None:
        return like.with_changes(elements=items)
    return cst.Tuple(elements=items, lpar=[], rpar=[])


def _needs_parens(expr: cst.BaseExpression) -> bool:
    return isinstance(expr, (cst.BooleanOperation, cst.IfExp, cst.Lambda, cst.NamedExpr, cst.Tuple)) and not expr.lpar


def _parenthesized(expr: cst.BaseExpression) -> cst.BaseExpression:
    if _needs_parens(expr):
        return expr.with_changes(lpar=[cst.LeftParen()], rpar=[cst.RightParen()])
    return expr


def _fresh(base: str, taken: set[str]) -> str:
    name = base
    while name in taken:
        name += "_"
    taken.add(name)
    return name


class _Names(cst.CSTVisitor):
    """Every name in a function, and how often each is read (not assigned)."""

    def __init__(self) -> None:
        self.all: set[str] = set()
        self.reads: dict[str, int] = {}
        self._targets: set[int] = set()
        self._not_names: set[int] = set()  # ``self.done``'s attr, ``f(done=1)``'s keyword

    def _mark_targets(self, target: cst.BaseExpression) -> None:
        if isinstance(target, cst.Name):
            self._targets.add(id(target))
        elif isinstance(target, (cst.Tuple, cst.List)):
            for element in target.elements:
                self._mark_targets(element.value)

    def visit_AssignTarget(self, node: cst.AssignTarget) -> None:
        self._mark_targets(node.target)

    def visit_For(self, node: cst.For) -> None:
        self._mark_targets(node.target)

    def visit_Param(self, node: cst.Param) -> None:
        self._targets.add(id(node.name))

    def visit_Attribute(self, node: cst.Attribute) -> None:
        self._not_names.add(id(node.attr))

    def visit_Arg(self, node: cst.Arg) -> None:
        if node.keyword is not None:
            self._not_names.add(id(node.keyword))

    def visit_Name(self, node: cst.Name) -> None:
        if id(node) in self._not_names:
            return
        self.all.add(node.value)
        if id(node) not in self._targets:
            self.reads[node.value] = self.reads.get(node.value, 0) + 1


class _Lines(cst.CSTVisitor):
    """Statement lines of one function body, in order, not entering nested definitions."""

    def __init__(self) -> None:
        self.lines: list[cst.SimpleStatementLine] = []

    def visit_FunctionDef(self, node: cst.FunctionDef) -> bool:
        return False

    def visit_ClassDef(self, node: cst.ClassDef) -> bool:
        return False

    def visit_SimpleStatementLine(self, node: cst.SimpleStatementLine) -> None:
        self.lines.append(node)


class _Edit(cst.CSTTransformer):
    """Apply edits keyed by the identity of nodes of the tree being visited."""

    def __init__(self, edits: dict[int, Callable[[cst.CSTNode], object]]) -> None:
        super().__init__()
        self.edits = edits

    def on_leave(self, original_node: cst.CSTNode, updated_node: cst.CSTNode):  # type: ignore[no-untyped-def]
        edit = self.edits.get(id(original_node))
        if edit is None:
            return updated_node
        return edit(updated_node)


def _insert_after_docstring(body: cst.BaseSuite, line: cst.SimpleStatementLine) -> cst.BaseSuite:
    if not isinstance(body, cst.IndentedBlock):
        return body
    statements = list(body.body)
    index = 0
    if statements and isinstance(statements[0], cst.SimpleStatementLine):
        first = statements[0].body[0] if statements[0].body else None
        if isinstance(first, cst.Expr) and isinstance(first.value, (cst.SimpleString, cst.ConcatenatedString)):
            index = 1
    statements.insert(index, line)
    return body.with_changes(body=statements)


# -- the pass -----------------------------------------------------------------------------


class WrapperClassPass(RulePass):
    RULES = RULES
    ORDER = 60
    METADATA_DEPENDENCIES = (PositionProvider, *METADATA)

    def __init__(self, context) -> None:  # type: ignore[no-untyped-def]
        super().__init__(context)
        self._classes: list[tuple[cst.ClassDef, bool]] = []
        self._skip_done_insert: set[int] = set()

    @classmethod
    def applies_to(cls, source: str, profile: FileProfile) -> bool:
        return "Wrapper" in source or "wrappers" in source

    def visit_Module(self, node: cst.Module) -> None:
        self.analysis = ReceiverAnalysis(node, self.metadata)

    def visit_ClassDef(self, node: cst.ClassDef) -> None:
        is_wrapper = self.analysis.is_gym_wrapper_class(node)
        self._classes.append((node, is_wrapper))
        if is_wrapper:
            self._check_init(node)

    def leave_ClassDef(self, original_node: cst.ClassDef, updated_node: cst.ClassDef) -> cst.ClassDef:
        self._classes.pop()
        return updated_node

    def leave_FunctionDef(self, original_node: cst.FunctionDef, updated_node: cst.FunctionDef) -> cst.FunctionDef:
        if not self._is_wrapper_method(original_node):
            return updated_node
        name = original_node.name.value
        if name == "step":
            return self._fix_step(original_node)
        if name == "reset":
            return self._fix_reset(original_node)
        return updated_node

    def _is_wrapper_method(self, node: cst.FunctionDef) -> bool:
        if not self._classes or not self._classes[-1][1]:
            return False
        classdef = self._classes[-1][0]
        block = self.analysis.parent(node)
        return block is not None and self.analysis.parent(block) is classdef

    # -- GM603 -------------------------------------------------------------------------

    def _check_init(self, classdef: cst.ClassDef) -> None:
        body = classdef.body.body if isinstance(classdef.body, cst.IndentedBlock) else ()
        for statement in body:
            if isinstance(statement, cst.FunctionDef) and statement.name.value == "__init__":
                finder = _SuperInitFinder()
                statement.visit(finder)
                if not finder.found:
                    self.report(
                        statement,
                        "GM603",
                        f"`{classdef.name.value}.__init__` never calls `super().__init__(env)`: gymnasium.Wrapper "
                        "needs it to set `env` and the action/observation space and metadata properties; call it "
                        "instead of setting `self.env` by hand",
                    )

    # -- GM602: step --------------------------------------------------------------------

    def _fix_step(self, function: cst.FunctionDef) -> cst.FunctionDef:
        names = _Names()
        function.visit(names)
        taken = set(names.all)
        edits: dict[int, Callable[[cst.CSTNode], object]] = {}
        lines = _lines(function)
        flags: tuple[str, str] | None = None
        done_line: cst.SimpleStatementLine | None = None
        done_name: str | None = None
        consistent = True
        unpack_lines: list[int] = []
        for index, line in enumerate(lines):
            assign = _single_assign(line)
            if assign is None or _inner_call(assign.value, "step") is None:
                continue
            targets = _target_names(assign.targets[0].target)
            if targets is None:
                continue
            if len(targets) == 4:
                found, legacy_done = self._complete_step_unpack(line, assign, targets, names, taken, edits)
                if legacy_done is not None and done_name is None:
                    done_name = legacy_done
                    done_line = line  # marker: the inserted line is ours, not in the tree
            elif len(targets) == 5:
                found = (targets[2], targets[3])
                following = lines[index + 1] if index + 1 < len(lines) else None
                if following is not None and _is_done_line(following, found):
                    done_line, done_name = following, _assigned_single_name(following)
            else:
                continue
            unpack_lines.append(id(line))
            if flags is not None and flags != found:
                consistent = False
            flags = flags or found
        returns = own_returns(function)
        bound = {name for line in lines for name in _assigned_names(line)}
        replaced_done_reads = 0
        done_modified = done_name is not None and _has_other_assignments(lines, done_name, done_line, unpack_lines)
        for ret in returns:
            value = ret.value
            if not isinstance(value, cst.Tuple) or len(value.elements) != 4:
                continue
            if any(isinstance(e, cst.StarredElement) for e in value.elements):
                continue
            if flags is None or not consistent or "_" in flags:
                self.report(
                    ret,
                    "GM602",
                    "this step override returns four values but the inner step's terminated/truncated could "
                    "not be found; return (obs, reward, terminated, truncated, info)",
                    kind=FixKind.FLAG,
                )
                continue
            terminated, truncated = flags
            obs, reward, done, info = (e.value for e in value.elements)
            plain_done = isinstance(done, cst.Name) and (
                (done.value == done_name and not done_modified) or done.value not in bound
            )
            if plain_done:
                middle: list[cst.BaseExpression] = [cst.Name(terminated), cst.Name(truncated)]
                replaced_done_reads += done.value == done_name
                self.report(ret, "GM602", "step returns (obs, reward, terminated, truncated, info)")
            else:
                cut = cst.BooleanOperation(
                    left=_parenthesized(done),
                    operator=cst.And(),
                    right=cst.UnaryOperation(operator=cst.Not(), expression=cst.Name(terminated)),
                )
                middle = [cst.Name(terminated), cut]
                self.report(
                    ret,
                    "GM602",
                    "this step override decides `done` itself; its own end condition is now returned as truncation "
                    f"(`... and not {terminated}`): if it really ends the episode (e.g. a lost life), return it as "
                    "terminated instead",
                    kind=FixKind.ASSIST,
                )
            new_elements = [obs, reward, *middle, info]
            edits[id(value)] = lambda node, new=new_elements: _tuple(new, node if node.lpar else None)  # type: ignore[misc]
        if done_name is not None and done_line is not None and replaced_done_reads:
            still_read = names.reads.get(done_name, 0) - replaced_done_reads
            if still_read <= 0:
                if id(done_line) in unpack_lines:
                    # our own fallback unpack: simply do not insert the line
                    self._skip_done_insert.add(id(done_line))
                else:
                    edits[id(done_line)] = lambda node: cst.RemoveFromParent()
        return self._apply(function, edits)

    def _complete_step_unpack(
        self,
        line: cst.SimpleStatementLine,
        assign: cst.Assign,
        targets: list[str],
        names: _Names,
        taken: set[str],
        edits: dict[int, Callable[[cst.CSTNode], object]],
    ) -> tuple[tuple[str, str], str | None]:
        """Fallback for a four-target unpack the step pass left: split ``done`` in two."""
        terminated = _fresh("terminated", taken)
        truncated = _fresh("truncated", taken)
        done = targets[2]
        read = done != "_" and names.reads.get(done, 0) > 0
        target = assign.targets[0].target
        elements = [e.value for e in target.elements]  # type: ignore[union-attr]
        new_target = _tuple([elements[0], elements[1], cst.Name(terminated), cst.Name(truncated), elements[3]])
        if isinstance(target, cst.Tuple) and target.lpar:
            new_target = new_target.with_changes(lpar=target.lpar, rpar=target.rpar)
        self.report(
            line,
            "GM602",
            f"{_callee_text(assign.value)} returns five values: `{done}` is split into terminated and truncated",
        )

        def rewrite(node: cst.CSTNode, done: str = done, read: bool = read, line_id: int = id(line)) -> object:
            assert isinstance(node, cst.SimpleStatementLine)
            small = node.body[0]
            assert isinstance(small, cst.Assign)
            new_line = node.with_changes(
                body=[small.with_changes(targets=[small.targets[0].with_changes(target=new_target)])]
            )
            if not read or line_id in self._skip_done_insert:
                return new_line
            done_assign = cst.SimpleStatementLine(
                body=[
                    cst.Assign(
                        targets=[cst.AssignTarget(target=cst.Name(done))],
                        value=cst.BooleanOperation(left=cst.Name(terminated), operator=cst.Or(), right=cst.Name(truncated)),
                    )
                ]
            )
            return cst.FlattenSentinel([new_line, done_assign])

        edits[id(line)] = rewrite
        return (terminated, truncated), (done if read else None)

    # -- GM601: reset ---------------------------------------------------------------------

    def _fix_reset(self, function: cst.FunctionDef) -> cst.FunctionDef:
        names = _Names()
        function.visit(names)
        taken = set(names.all)
        edits: dict[int, Callable[[cst.CSTNode], object]] = {}
        lines = _lines(function)
        info_name: str | None = None
        completed: set[int] = set()  # lines this pass turns into ``obs, info = ...``
        for line in lines:
            assign = _single_assign(line)
            if assign is None or _inner_call(assign.value, "reset") is None:
                continue
            target = assign.targets[0].target
            targets = _target_names(target)
            if targets is not None and len(targets) == 2 and targets[1] != "_":
                info_name = info_name or targets[1]
            elif isinstance(target, cst.Name):
                # Fallback for a one-target reset the reset pass left.
                info_name = info_name or _fresh("info", taken)
                self._complete_reset_unpack(line, target, info_name, edits)
                completed.add(id(line))
        original = function
        function = self._fix_reset_signature(function, edits)
        needs_info_default = False
        for ret in own_returns(function):
            value = ret.value
            if value is None or _inner_call(value, "reset") is not None:
                continue  # a pass-through already returns (obs, info)
            if _already_pair(value, info_name):
                continue
            statement = self.analysis.parent(ret)
            if _contains_inner_reset(value):
                self._hoist_reset(ret, value, statement, taken, edits)
                continue
            if info_name is not None:
                if not _assigned_before(self.analysis, statement, info_name, original, completed):
                    needs_info_default = True
                    message = (
                        f"reset returns (obs, info): `{info_name}` is the inner reset's info when it ran, else "
                        "an empty dict"
                    )
                else:
                    message = f"reset returns (obs, info) with the inner reset's `{info_name}`"
                info: cst.BaseExpression = cst.Name(info_name)
            else:
                info = cst.Dict(elements=[])
                message = (
                    "reset returns (obs, info): this override has no info from an inner reset, so it returns "
                    "an empty dict; pass the inner info on if callers need it"
                )
            self.report(ret, "GM601", message)
            edits[id(ret)] = lambda node, info=info: node.with_changes(  # type: ignore[misc]
                value=_tuple([_parenthesized(node.value), info])
            )
        function = self._apply(function, edits)
        if needs_info_default and info_name is not None:
            default = cst.SimpleStatementLine(
                body=[cst.Assign(targets=[cst.AssignTarget(target=cst.Name(info_name))], value=cst.Dict(elements=[]))]
            )
            function = function.with_changes(body=_insert_after_docstring(function.body, default))
        return function

    def _complete_reset_unpack(
        self,
        line: cst.SimpleStatementLine,
        target: cst.Name,
        info_name: str,
        edits: dict[int, Callable[[cst.CSTNode], object]],
    ) -> None:
        self.report(line, "GM601", f"the inner reset returns (obs, info): unpacked into `{target.value}, {info_name}`")

        def rewrite(node: cst.CSTNode) -> object:
            assert isinstance(node, cst.SimpleStatementLine)
            small = node.body[0]
            assert isinstance(small, cst.Assign)
            pair = _tuple([cst.Name(target.value), cst.Name(info_name)])
            return node.with_changes(body=[small.with_changes(targets=[small.targets[0].with_changes(target=pair)])])

        edits[id(line)] = rewrite

    def _fix_reset_signature(
        self, function: cst.FunctionDef, edits: dict[int, Callable[[cst.CSTNode], object]]
    ) -> cst.FunctionDef:
        """``def reset(self)`` cannot take the seed/options that every outer wrapper passes."""
        params = function.params
        if (
            len(params.params) != 1
            or params.posonly_params
            or params.kwonly_params
            or params.star_kwarg is not None
            or not isinstance(params.star_arg, cst.MaybeSentinel)
        ):
            return function
        self.report(
            function,
            "GM601",
            "reset now takes keyword-only `seed` and `options` (outer wrappers always pass them); they are "
            "passed on to the inner reset",
        )
        calls = _InnerCalls("reset")
        function.visit(calls)
        for call in calls.calls:
            if not call.args:
                edits[id(call)] = lambda node: node.with_changes(
                    args=[
                        cst.Arg(
                            keyword=cst.Name("seed"),
                            value=cst.Name("seed"),
                            equal=cst.AssignEqual(cst.SimpleWhitespace(""), cst.SimpleWhitespace("")),
                            comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" ")),
                        ),
                        cst.Arg(
                            keyword=cst.Name("options"),
                            value=cst.Name("options"),
                            equal=cst.AssignEqual(cst.SimpleWhitespace(""), cst.SimpleWhitespace("")),
                        ),
                    ]
                )
        keyword = lambda name: cst.Param(  # noqa: E731
            name=cst.Name(name),
            default=cst.Name("None"),
            equal=cst.AssignEqual(cst.SimpleWhitespace(""), cst.SimpleWhitespace("")),
        )
        self_param = params.params[0].with_changes(comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" ")))
        new_params = params.with_changes(
            params=[self_param],
            star_arg=cst.ParamStar(comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))),
            kwonly_params=[
                keyword("seed").with_changes(comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))),
                keyword("options"),
            ],
        )
        return function.with_changes(params=new_params)

    def _hoist_reset(
        self,
        ret: cst.Return,
        value: cst.BaseExpression,
        statement: cst.CSTNode | None,
        taken: set[str],
        edits: dict[int, Callable[[cst.CSTNode], object]],
    ) -> None:
        """``return f(self.env.reset(**kw))`` -> ``obs, info = self.env.reset(**kw)`` + ``return f(obs), info``."""
        if not isinstance(statement, cst.SimpleStatementLine) or len(statement.body) != 1:
            self.report(ret, "GM601", "reset must return (obs, info): rewrite this return by hand", kind=FixKind.FLAG)
            return
        finder = _InnerCalls("reset")
        value.visit(finder)
        if len(finder.calls) != 1:
            self.report(ret, "GM601", "reset must return (obs, info): rewrite this return by hand", kind=FixKind.FLAG)
            return
        call = finder.calls[0]
        subscript = _first_item_of(self.analysis, call)
        replaced: cst.CSTNode = subscript if subscript is not None else call
        obs_name, info_name = _fresh("obs", taken), _fresh("info", taken)
        self.report(ret, "GM601", f"reset returns (obs, info): the inner reset is unpacked into `{obs_name}, {info_name}`")
        inner = _Edit({id(replaced): lambda node: cst.Name(obs_name)})
        new_value = value.visit(inner)

        def rewrite(node: cst.CSTNode) -> object:
            assert isinstance(node, cst.SimpleStatementLine)
            unpack_call = call.visit(_Edit(edits))  # with the seed/options a signature fix added
            unpack = cst.SimpleStatementLine(
                body=[
                    cst.Assign(
                        targets=[cst.AssignTarget(target=_tuple([cst.Name(obs_name), cst.Name(info_name)]))],
                        value=unpack_call,  # type: ignore[arg-type]
                    )
                ],
                leading_lines=node.leading_lines,
            )
            small = node.body[0]
            assert isinstance(small, cst.Return)
            returned = small.with_changes(value=_tuple([_parenthesized(new_value), cst.Name(info_name)]))  # type: ignore[arg-type]
            return cst.FlattenSentinel([unpack, node.with_changes(body=[returned], leading_lines=[])])

        edits[id(statement)] = rewrite

    # -- helpers -----------------------------------------------------------------------------

    def _apply(self, function: cst.FunctionDef, edits: dict[int, Callable[[cst.CSTNode], object]]) -> cst.FunctionDef:
        if not edits:
            return function
        return function.visit(_Edit(edits))  # type: ignore[return-value]


# -- analysis helpers ---------------------------------------------------------------------------


def _lines(function: cst.FunctionDef) -> list[cst.SimpleStatementLine]:
    collector = _Lines()
    function.body.visit(collector)
    return collector.lines


def _assigned_single_name(line: cst.SimpleStatementLine) -> str | None:
    assign = _single_assign(line)
    if assign is not None and isinstance(assign.targets[0].target, cst.Name):
        return assign.targets[0].target.value
    return None


def _is_done_line(line: cst.SimpleStatementLine, flags: tuple[str, str]) -> bool:
    """``done = terminated or truncated`` (what the step pass inserts after the unpack)."""
    assign = _single_assign(line)
    if assign is None or not isinstance(assign.targets[0].target, cst.Name):
        return False
    value = assign.value
    return (
        isinstance(value, cst.BooleanOperation)
        and isinstance(value.operator, cst.Or)
        and isinstance(value.left, cst.Name)
        and isinstance(value.right, cst.Name)
        and (value.left.value, value.right.value) == flags
    )


def _is_initializer(line: cst.SimpleStatementLine) -> bool:
    """``done = None`` / ``done = False`` before a loop: not a change of the inner result."""
    assign = _single_assign(line)
    return assign is not None and isinstance(assign.value, cst.Name) and assign.value.value in ("None", "False")


def _has_other_assignments(
    lines: list[cst.SimpleStatementLine],
    name: str,
    done_line: cst.SimpleStatementLine | None,
    unpack_lines: list[int],
) -> bool:
    """Is ``name`` changed anywhere but by the unpack, its ``done = ...`` line or an initializer?"""
    seen_unpack = False
    for line in lines:
        if id(line) in unpack_lines:
            seen_unpack = True
            continue
        if line is done_line:
            continue
        if name not in _assigned_names(line):
            if any(isinstance(s, cst.AugAssign) and isinstance(s.target, cst.Name) and s.target.value == name for s in line.body):
                return True
            continue
        if not seen_unpack and _is_initializer(line):
            continue
        return True
    return False


def _already_pair(value: cst.BaseExpression, info_name: str | None) -> bool:
    """``obs, info`` / ``obs, {}``: a reset return that already has Gymnasium's shape."""
    if not isinstance(value, cst.Tuple) or len(value.elements) != 2:
        return False
    last = value.elements[1].value
    if isinstance(last, cst.Dict):
        return True
    return isinstance(last, cst.Name) and (last.value == info_name or "info" in last.value.lower())


def _contains_inner_reset(value: cst.BaseExpression) -> bool:
    finder = _InnerCalls("reset")
    value.visit(finder)
    return bool(finder.calls)


def _first_item_of(analysis: ReceiverAnalysis, call: cst.Call) -> cst.Subscript | None:
    """``self.env.reset(...)[0]``, which the reset pass writes for a reset used as a value."""
    parent = analysis.parent(call)
    if isinstance(parent, cst.Subscript) and parent.value is call and len(parent.slice) == 1:
        index = parent.slice[0].slice
        if isinstance(index, cst.Index) and isinstance(index.value, cst.Integer) and index.value.value == "0":
            return parent
    return None


def _assigned_before(
    analysis: ReceiverAnalysis,
    statement: cst.CSTNode | None,
    name: str,
    function: cst.FunctionDef,
    completed: set[int],
) -> bool:
    """Is ``name`` surely bound when ``statement`` runs? (an earlier line of an enclosing block)"""
    current = statement
    while current is not None and current is not function:
        block = analysis.parent(current)
        if isinstance(block, (cst.IndentedBlock, cst.Module)):
            for sibling in block.body:
                if sibling is current:
                    break
                if name in _assigned_names(sibling) or id(sibling) in completed:
                    return True
        current = block
    return False


def _callee_text(call: cst.BaseExpression) -> str:
    if isinstance(call, cst.Call) and isinstance(call.func, cst.Attribute):
        owner = "super()" if isinstance(call.func.value, cst.Call) else "self.env"
        return f"`{owner}.{call.func.attr.value}`"
    return "the inner step"


class _InnerCalls(cst.CSTVisitor):
    def __init__(self, method: str) -> None:
        self.method = method
        self.calls: list[cst.Call] = []

    def visit_Lambda(self, node: cst.Lambda) -> bool:
        return False

    def visit_Call(self, node: cst.Call) -> None:
        if _inner_call(node, self.method) is not None:
            self.calls.append(node)


class _SuperInitFinder(cst.CSTVisitor):
    """``super().__init__(...)``, ``super(Cls, self).__init__(...)`` or ``Base.__init__(self, ...)``."""

    def __init__(self) -> None:
        self.found = False

    def visit_Call(self, node: cst.Call) -> None:
        func = node.func
        if isinstance(func, cst.Attribute) and func.attr.value == "__init__":
            owner = func.value
            if isinstance(owner, cst.Call) and isinstance(owner.func, cst.Name) and owner.func.value == "super":
                self.found = True
            elif isinstance(owner, (cst.Name, cst.Attribute)) and node.args:
                first = node.args[0].value
                if isinstance(first, cst.Name) and first.value == "self":
                    self.found = True

