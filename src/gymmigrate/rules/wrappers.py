"""Wrapper subclasses: ``reset`` and ``step`` overrides keep Gymnasium's contract (GM601-GM603).

Gymnasium 0.26 changed ``Wrapper.reset`` to return ``(obs, info)`` and ``Wrapper.step``
to return ``(obs, reward, terminated, truncated, info)``; every wrapper that overrides
them must return the new shapes, or the next wrapper up (``TimeLimit`` from
``gym.make`` first) fails with "not enough values to unpack".

The reset family (ORDER 50) and the step family (ORDER 55) rewrite the *calls* inside the
overrides (``obs, info = self.env.reset(**kwargs)``, ``obs, reward, terminated, truncated,
info = self.env.step(action)`` plus ``done = terminated or truncated`` when ``done`` is
read later) and say so in ``plan.notes`` (``reset_info_names``, ``step_unpacks``). This
family (ORDER 60), deciding on the same original source, fixes what the override itself
returns:

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

A legacy call that those families leave alone (they never do for ``self.env`` or
``super()`` in a Gym wrapper) leaves the returns to fix by hand: four-value returns are
reported. Sources: Gymnasium ``core.py`` (``Wrapper.reset``/``step``/``__init__``);
migration guide "Step API" and "Reset".

Wrapper *usage* (attribute forwarding, renamed and removed wrappers, Monitor...) lives in
the ``wrapper_usage`` package, which ``rules/__init__.py`` imports so that its families register.
"""

from __future__ import annotations

import ast
from collections.abc import Iterator, Sequence

import libcst as cst

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.module import FUNCTIONS, own_returns
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.step_done.common import STEP_UNPACKS, StepUnpack

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

# ``plan.notes`` key of the reset family: "Class.method" -> the info name it unpacked into.
RESET_INFO_NAMES = "reset_info_names"


class WrapperClasses(RuleFamily):
    RULES = RULES
    ORDER = 60

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        return "Wrapper" in facts.text or "wrappers" in facts.text

    def decide(self) -> None:
        for classdef in self.facts.all_classes:
            if not self.receivers.is_gym_wrapper_class(classdef):
                continue
            for statement in classdef.body:
                if not isinstance(statement, FUNCTIONS):
                    continue
                if statement.name == "__init__":
                    self._check_init(classdef, statement)
                elif statement.name == "step":
                    self._fix_step(statement)
                elif statement.name == "reset":
                    self._fix_reset(classdef, statement)

    # -- GM603 ------------------------------------------------------------------------------

    def _check_init(self, classdef: ast.ClassDef, init: ast.FunctionDef | ast.AsyncFunctionDef) -> None:
        if not any(_is_super_init(node) for node in ast.walk(init)):
            self.report(
                init,
                "GM603",
                f"`{classdef.name}.__init__` never calls `super().__init__(env)`: gymnasium.Wrapper "
                "needs it to set `env` and the action/observation space and metadata properties; call it "
                "instead of setting `self.env` by hand",
            )

    # -- GM602: step ------------------------------------------------------------------------

    def _fix_step(self, function: ast.FunctionDef | ast.AsyncFunctionDef) -> None:
        """Return the inner step's terminated/truncated instead of ``done``.

        The flags are those of the step unpack in the override, as the step family
        rewrote it (``plan.notes[STEP_UNPACKS]``) or as it already was (five targets).
        """
        noted_unpacks: dict[ast.Assign, StepUnpack] = self.plan.notes.get(STEP_UNPACKS, {})
        lines = list(_statements(function.body))
        flags: tuple[str, str] | None = None
        done_name: str | None = None
        done_line: ast.stmt | None = None  # an existing ``done = ...`` line, or the unpack it is inserted after
        inserted: tuple[ast.Assign, StepUnpack] | None = None
        consistent = True
        unpacks: dict[ast.stmt, StepUnpack | None] = {}
        bound: set[str] = set()
        for index, line in enumerate(lines):
            assign = _single_assign(line)
            if assign is None or _inner_call(assign.value, "step") is None:
                bound |= _assigned_names(line)
                continue
            targets = _target_names(assign.targets[0])
            if targets is None or len(targets) not in (4, 5):
                bound |= _assigned_names(line)
                continue
            noted = noted_unpacks.get(assign) if len(targets) == 4 else None
            found: tuple[str, str] | None
            if len(targets) == 4:
                if noted is None:  # a legacy step the step family left: nothing to return
                    found, consistent = None, False
                    bound.update(targets)
                else:
                    names = noted.names
                    found = ("_", "_") if noted.discarded else (names.terminated, names.truncated)
                    bound.update((targets[0], targets[1], *found, targets[3]))
                    if noted.done_line is not None:
                        bound.add(targets[2])
                        if done_name is None:
                            done_name, done_line, inserted = targets[2], assign, (assign, noted)
            else:
                found = (targets[2], targets[3])
                bound.update(targets)
                following = lines[index + 1] if index + 1 < len(lines) else None
                if following is not None and _is_done_line(following, found):
                    done_line, done_name = following, following.targets[0].id  # type: ignore[attr-defined]
            unpacks[line] = noted
            if found is not None:
                if flags is not None and flags != found:
                    consistent = False
                flags = flags or found
        done_modified = done_name is not None and _has_other_assignments(lines, done_name, done_line, unpacks, inserted)
        replaced_done_reads = 0
        for ret in own_returns(function):
            value = ret.value
            if not isinstance(value, ast.Tuple) or len(value.elts) != 4:
                continue
            if any(isinstance(e, ast.Starred) for e in value.elts):
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
            done = value.elts[2]
            plain_done = isinstance(done, ast.Name) and (
                (done.id == done_name and not done_modified) or done.id not in bound
            )
            if plain_done:
                replaced_done_reads += done.id == done_name  # type: ignore[union-attr]
                self.report(ret, "GM602", "step returns (obs, reward, terminated, truncated, info)")
                self.plan.replace(value, lambda node, t=terminated, u=truncated: _five(node, [cst.Name(t), cst.Name(u)]))
            else:
                self.report(
                    ret,
                    "GM602",
                    "this step override decides `done` itself; its own end condition is now returned as truncation "
                    f"(`... and not {terminated}`): if it really ends the episode (e.g. a lost life), return it as "
                    "terminated instead",
                    kind=FixKind.ASSIST,
                )
                self.plan.replace(value, lambda node, t=terminated: _five(node, _cut(node, t)))
        if done_name is not None and done_line is not None and replaced_done_reads:
            claimed = sum(noted.claimed_reads for noted in unpacks.values() if noted is not None)
            reads = sum(
                1
                for node in ast.walk(function)
                if isinstance(node, ast.Name) and node.id == done_name and isinstance(node.ctx, ast.Load)
            )
            if reads - claimed - replaced_done_reads <= 0:
                # nothing reads ``done`` any more: drop the line that kept it
                if inserted is not None and done_line is inserted[0]:
                    self.plan.withdraw(inserted[0], inserted[1].done_line)
                else:
                    self.plan.remove(done_line)

    # -- GM601: reset -----------------------------------------------------------------------

    def _fix_reset(self, classdef: ast.ClassDef, function: ast.FunctionDef | ast.AsyncFunctionDef) -> None:
        noted_info = self.plan.notes.get(RESET_INFO_NAMES, {}).get(f"{classdef.name}.{function.name}")
        info_name: str | None = None
        completed: set[ast.stmt] = set()  # one-name resets the reset family unpacks into ``obs, info``
        for line in _statements(function.body):
            assign = _single_assign(line)
            if assign is None or _inner_call(assign.value, "reset") is None:
                continue
            target = assign.targets[0]
            targets = _target_names(target)
            if targets is not None and len(targets) == 2 and targets[1] != "_":
                info_name = info_name or targets[1]
            elif isinstance(target, ast.Name) and noted_info is not None:
                info_name = info_name or noted_info
                completed.add(assign)
        fixed_signature = self._fix_reset_signature(function)
        taken = _names_in(function)
        needs_info_default = False
        for ret in own_returns(function):
            value = ret.value
            if value is None or _inner_call(value, "reset") is not None:
                continue  # a pass-through already returns (obs, info)
            if _already_pair(value, info_name):
                continue
            inner = _inner_calls(value, "reset")
            if inner:
                self._hoist_reset(ret, inner, taken, fixed_signature)
                continue
            info_code = "{}"
            if info_name is not None:
                info_code = info_name
                if not self._assigned_before(ret, info_name, function, completed):
                    needs_info_default = True
                    message = (
                        f"reset returns (obs, info): `{info_name}` is the inner reset's info when it ran, else "
                        "an empty dict"
                    )
                else:
                    message = f"reset returns (obs, info) with the inner reset's `{info_name}`"
            else:
                message = (
                    "reset returns (obs, info): this override has no info from an inner reset, so it returns "
                    "an empty dict; pass the inner info on if callers need it"
                )
            self.report(ret, "GM601", message)
            self.plan.replace(
                ret,
                lambda node, code=info_code: node.with_changes(
                    value=_tuple([_parenthesized(node.value), cst.parse_expression(code)])
                ),
            )
        if needs_info_default and info_name is not None:
            body = function.body
            if _is_docstring(body[0]):
                self.plan.insert_after(body[0], f"{info_name} = {{}}")
            else:
                self.plan.insert_before(body[0], f"{info_name} = {{}}")

    def _fix_reset_signature(self, function: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
        """``def reset(self)`` cannot take the seed/options that every outer wrapper passes."""
        args = function.args
        if len(args.args) != 1 or args.posonlyargs or args.kwonlyargs or args.kwarg or args.vararg:
            return False
        self.report(
            function,
            "GM601",
            "reset now takes keyword-only `seed` and `options` (outer wrappers always pass them); they are "
            "passed on to the inner reset",
        )
        for call in _inner_calls(function, "reset"):
            if not call.args and not call.keywords:
                self.plan.replace(call, _pass_seed_and_options)
        self.plan.replace(function, _keyword_seed_and_options)
        return True

    def _hoist_reset(self, ret: ast.Return, calls: list[ast.Call], taken: set[str], fixed_signature: bool) -> None:
        """``return f(self.env.reset(**kw))`` -> ``obs, info = self.env.reset(**kw)`` + ``return f(obs), info``."""
        if len(calls) != 1 or self._shares_line(ret):
            self.report(ret, "GM601", "reset must return (obs, info): rewrite this return by hand", kind=FixKind.FLAG)
            return
        call = calls[0]
        obs_name, info_name = _fresh("obs", taken), _fresh("info", taken)
        self.report(ret, "GM601", f"reset returns (obs, info): the inner reset is unpacked into `{obs_name}, {info_name}`")
        call_text = self.facts.segment(call)
        if fixed_signature and not call.args and not call.keywords:
            call_text = call_text[: call_text.rindex("(") + 1] + "seed=seed, options=options)"
        self.plan.insert_before(ret, f"{obs_name}, {info_name} = {call_text}")

        def rewrite(node: cst.Return) -> cst.Return:
            value = node.value.visit(_ObservationOf(obs_name))  # type: ignore[union-attr]
            return node.with_changes(value=_tuple([_parenthesized(value), cst.Name(info_name)]))  # type: ignore[arg-type]

        self.plan.replace(ret, rewrite)

    # -- helpers ----------------------------------------------------------------------------

    def _shares_line(self, statement: ast.stmt) -> bool:
        """``a; return x`` or ``if c: return x``: no room for a line before it."""
        parent = self.facts.parent(statement)
        for field in ("body", "orelse", "finalbody"):
            items = getattr(parent, field, None)
            if isinstance(items, list) and any(item is statement for item in items):
                return any(item is not statement and item.lineno == statement.lineno for item in items) or (
                    getattr(parent, "lineno", None) == statement.lineno and not isinstance(parent, ast.Module)
                )
        return False

    def _assigned_before(
        self, statement: ast.stmt, name: str, function: ast.AST, completed: set[ast.stmt]
    ) -> bool:
        """Is ``name`` surely bound when ``statement`` runs? (an earlier line of an enclosing block)"""
        current: ast.AST = statement
        while current is not function:
            parent = self.facts.parent(current)
            if parent is None:
                return False
            for field in ("body", "orelse", "finalbody"):
                items = getattr(parent, field, None)
                if isinstance(items, list) and any(item is current for item in items):
                    for sibling in items:
                        if sibling is current:
                            break
                        if name in _assigned_names(sibling) or sibling in completed:
                            return True
            current = parent
        return False


# -- syntax helpers (ast) ---------------------------------------------------------------------


def _is_inner_env(node: ast.expr) -> bool:
    """``self.env`` or ``super()`` / ``super(Cls, self)``: what an override delegates to."""
    if isinstance(node, ast.Attribute):
        return isinstance(node.value, ast.Name) and node.value.id == "self" and node.attr == "env"
    return isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "super"


def _inner_call(node: ast.AST | None, method: str) -> ast.Call | None:
    """``node`` if it is ``self.env.<method>(...)`` or ``super().<method>(...)``."""
    if (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and node.func.attr == method
        and _is_inner_env(node.func.value)
    ):
        return node
    return None


def _inner_calls(root: ast.AST, method: str) -> list[ast.Call]:
    """Inner ``method`` calls under ``root``, not inside lambdas, in source order."""
    found: list[ast.Call] = []
    stack = [root]
    while stack:
        node = stack.pop()
        if isinstance(node, ast.Lambda):
            continue
        if _inner_call(node, method) is not None:
            found.append(node)  # type: ignore[arg-type]
        stack.extend(ast.iter_child_nodes(node))
    found.sort(key=lambda call: (call.lineno, call.col_offset))
    return found


def _statements(body: list[ast.stmt]) -> Iterator[ast.stmt]:
    """Simple statements of a function body, in order, not entering nested definitions."""
    for statement in body:
        if isinstance(statement, (*FUNCTIONS, ast.ClassDef)):
            continue
        blocks = [getattr(statement, field, None) for field in ("body", "orelse", "finalbody")]
        blocks += [handler.body for handler in getattr(statement, "handlers", ())]
        blocks += [case.body for case in getattr(statement, "cases", ())]
        blocks = [block for block in blocks if isinstance(block, list)]
        if not blocks:
            yield statement
        for block in blocks:
            yield from _statements(block)


def _single_assign(statement: ast.stmt) -> ast.Assign | None:
    if isinstance(statement, ast.Assign) and len(statement.targets) == 1:
        return statement
    return None


def _target_names(target: ast.expr) -> list[str] | None:
    """``a, b, _`` -> ["a", "b", "_"]; None when an element is not a plain name."""
    if not isinstance(target, (ast.Tuple, ast.List)):
        return None
    if not all(isinstance(element, ast.Name) for element in target.elts):
        return None
    return [element.id for element in target.elts]  # type: ignore[attr-defined]


def _assigned_names(statement: ast.stmt) -> set[str]:
    targets: list[ast.expr] = []
    if isinstance(statement, ast.Assign):
        targets = statement.targets
    elif isinstance(statement, ast.AnnAssign) and statement.value is not None:
        targets = [statement.target]
    names: set[str] = set()
    for target in targets:
        if isinstance(target, ast.Name):
            names.add(target.id)
        else:
            names.update(_target_names(target) or ())
    return names


def _is_done_line(statement: ast.stmt, flags: tuple[str, str]) -> bool:
    """``done = terminated or truncated`` right after a five-target step unpack."""
    assign = _single_assign(statement)
    if assign is None or not isinstance(assign.targets[0], ast.Name):
        return False
    value = assign.value
    return (
        isinstance(value, ast.BoolOp)
        and isinstance(value.op, ast.Or)
        and len(value.values) == 2
        and all(isinstance(v, ast.Name) for v in value.values)
        and tuple(v.id for v in value.values) == flags  # type: ignore[attr-defined]
    )


def _is_initializer(statement: ast.stmt) -> bool:
    """``done = None`` / ``done = False`` before a loop: not a change of the inner result."""
    assign = _single_assign(statement)
    return (
        assign is not None
        and isinstance(assign.value, ast.Constant)
        and (assign.value.value is None or assign.value.value is False)
    )


def _has_other_assignments(
    lines: list[ast.stmt],
    name: str,
    done_line: ast.stmt | None,
    unpacks: dict[ast.stmt, StepUnpack | None],
    inserted: tuple[ast.Assign, StepUnpack] | None,
) -> bool:
    """Is ``name`` changed anywhere but by the unpack, its ``done = ...`` line or an initializer?"""
    seen_unpack = False
    for line in lines:
        if line in unpacks:
            seen_unpack = True
            noted = unpacks[line]
            # another unpack after which the step family keeps ``done`` too assigns it again
            if noted is not None and noted.done_line is not None and (inserted is None or line is not inserted[0]):
                if name in _assigned_names(line):
                    return True
            continue
        if line is done_line:
            continue
        if name not in _assigned_names(line):
            if isinstance(line, ast.AugAssign) and isinstance(line.target, ast.Name) and line.target.id == name:
                return True
            continue
        if not seen_unpack and _is_initializer(line):
            continue
        return True
    return False


def _already_pair(value: ast.expr, info_name: str | None) -> bool:
    """``obs, info`` / ``obs, {}``: a reset return that already has Gymnasium's shape."""
    if not isinstance(value, ast.Tuple) or len(value.elts) != 2:
        return False
    last = value.elts[1]
    if isinstance(last, ast.Dict):
        return True
    return isinstance(last, ast.Name) and (last.id == info_name or "info" in last.id.lower())


def _is_docstring(statement: ast.stmt) -> bool:
    return isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Constant) and isinstance(
        statement.value.value, str
    )


def _is_super_init(node: ast.AST) -> bool:
    """``super().__init__(...)``, ``super(Cls, self).__init__(...)`` or ``Base.__init__(self, ...)``."""
    if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "__init__"):
        return False
    owner = node.func.value
    if isinstance(owner, ast.Call) and isinstance(owner.func, ast.Name) and owner.func.id == "super":
        return True
    if isinstance(owner, (ast.Name, ast.Attribute)) and node.args:
        first = node.args[0]
        return isinstance(first, ast.Name) and first.id == "self"
    return False


def _names_in(function: ast.AST) -> set[str]:
    """Every name a function binds or reads (parameters included): fresh names avoid them."""
    names: set[str] = {function.name} if isinstance(function, FUNCTIONS) else set()
    for node in ast.walk(function):
        if isinstance(node, ast.Name):
            names.add(node.id)
        elif isinstance(node, ast.arg):
            names.add(node.arg)
    return names


def _fresh(base: str, taken: set[str]) -> str:
    name = base
    while name in taken:
        name += "_"
    taken.add(name)
    return name


# -- builders (LibCST) ------------------------------------------------------------------------


def _tuple(elements: Sequence[cst.BaseExpression], like: cst.Tuple | None = None) -> cst.Tuple:
    """A tuple with ``, `` separators, keeping the parentheses of ``like`` if it had any."""
    items = [
        cst.Element(value=e, comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" ")))
        for e in elements[:-1]
    ] + [cst.Element(value=elements[-1])]
    if like is not None:
        return like.with_changes(elements=items)
    return cst.Tuple(elements=items, lpar=[], rpar=[])


def _parenthesized(expr: cst.BaseExpression) -> cst.BaseExpression:
    if isinstance(expr, (cst.BooleanOperation, cst.IfExp, cst.Lambda, cst.NamedExpr, cst.Tuple)) and not expr.lpar:
        return expr.with_changes(lpar=[cst.LeftParen()], rpar=[cst.RightParen()])
    return expr


def _five(node: cst.Tuple, flags: list[cst.BaseExpression]) -> cst.Tuple:
    """``obs, reward, done, info`` -> ``obs, reward, <flags>, info``."""
    obs, reward, _, info = (element.value for element in node.elements)
    return _tuple([obs, reward, *flags, info], node if node.lpar else None)


def _cut(node: cst.Tuple, terminated: str) -> list[cst.BaseExpression]:
    """The override's own ``done`` becomes truncation: ``terminated, done and not terminated``."""
    done = node.elements[2].value
    cut = cst.BooleanOperation(
        left=_parenthesized(done),
        operator=cst.And(),
        right=cst.UnaryOperation(operator=cst.Not(), expression=cst.Name(terminated)),
    )
    return [cst.Name(terminated), cut]


def _assign_equal() -> cst.AssignEqual:
    return cst.AssignEqual(cst.SimpleWhitespace(""), cst.SimpleWhitespace(""))


def _comma() -> cst.Comma:
    return cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))


def _pass_seed_and_options(node: cst.Call) -> cst.Call:
    if node.args:
        return node
    return node.with_changes(
        args=[
            cst.Arg(keyword=cst.Name("seed"), value=cst.Name("seed"), equal=_assign_equal(), comma=_comma()),
            cst.Arg(keyword=cst.Name("options"), value=cst.Name("options"), equal=_assign_equal()),
        ]
    )


def _keyword_seed_and_options(node: cst.FunctionDef) -> cst.FunctionDef:
    """``def reset(self)`` -> ``def reset(self, *, seed=None, options=None)``."""
    params = node.params

    def keyword(name: str) -> cst.Param:
        return cst.Param(name=cst.Name(name), default=cst.Name("None"), equal=_assign_equal())

    return node.with_changes(
        params=params.with_changes(
            params=[params.params[0].with_changes(comma=_comma())],
            star_arg=cst.ParamStar(comma=_comma()),
            kwonly_params=[keyword("seed").with_changes(comma=_comma()), keyword("options")],
        )
    )


def _is_inner_reset(node: cst.BaseExpression) -> bool:
    if not (isinstance(node, cst.Call) and isinstance(node.func, cst.Attribute) and node.func.attr.value == "reset"):
        return False
    owner = node.func.value
    if isinstance(owner, cst.Attribute):
        return isinstance(owner.value, cst.Name) and owner.value.value == "self" and owner.attr.value == "env"
    return isinstance(owner, cst.Call) and isinstance(owner.func, cst.Name) and owner.func.value == "super"


class _ObservationOf(cst.CSTTransformer):
    """The inner reset (or the ``[0]`` of it the reset family wrote) becomes the observation name."""

    def __init__(self, obs_name: str) -> None:
        super().__init__()
        self.obs_name = obs_name

    def visit_Lambda(self, node: cst.Lambda) -> bool:
        return False

    def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.BaseExpression:
        return cst.Name(self.obs_name) if _is_inner_reset(original_node) else updated_node

    def leave_Subscript(self, original_node: cst.Subscript, updated_node: cst.Subscript) -> cst.BaseExpression:
        if _is_inner_reset(original_node.value) and len(original_node.slice) == 1:
            index = original_node.slice[0].slice
            if isinstance(index, cst.Index) and isinstance(index.value, cst.Integer) and index.value.value == "0":
                return cst.Name(self.obs_name)
        return updated_node
