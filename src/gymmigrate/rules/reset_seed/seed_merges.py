"""Merging a seed into a later reset the seed's block leads to through a loop or an if (GM203, GM208).

``SeedMerges`` (a mixin of ``SeedCalls``): ``env.seed(s)`` before a counted loop whose first
iteration resets the env becomes ``env.reset(seed=s if i == 0 else None)`` there; the seed
ending a branch of an if followed by the env's reset becomes ``env.reset(seed=s if c else
None)`` after the if. Either way the reset that returned legacy's seeded episode still does.
"""

from __future__ import annotations

import ast
from collections.abc import Callable

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.decisions import Action, Decision, receiver_text
from gymmigrate.facts.module import COMPOUND_STATEMENTS, statement_lines, walk
from gymmigrate.facts.reset_flow import segment
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.reset_seed.call_edits import SeedValue
from gymmigrate.rules.reset_seed.common import _seed_argument
from gymmigrate.rules.reset_seed.next_reset import (
    NextReset,
    _independent_of,
    _root_name,
)


class SeedMerges(NextReset):
    def _merge_into_counted_loop(
        self,
        call: ast.Call,
        statement: ast.Expr,
        receiver: ast.expr,
        decision: Decision,
        code: str,
        called: str,
        numpy: bool,
    ) -> bool:
        """``env.seed(s)`` followed in its block by a counted loop (``for i in range(n)``,
        ``for i, x in enumerate(xs)``, ``i = 0 ... while i < n: ... i += 1``) whose body's first
        statement touching the env resets it, at the body's top level: legacy's seeded episode
        is the one the first iteration's reset returns. A reset in the seed's place would start
        an extra episode before it, so the seed goes to that reset on the first iteration only:
        ``env.reset(seed=s if i == 0 else None)`` (``seed=None`` continues the stream as
        ``reset()`` did). Statements between the seed and the loop must leave the env alone, and
        nothing may rebind the counter or the seed's names before that reset."""
        found = self._place_in_block(statement)
        if found is None:
            return False
        block, position = found
        if not self._alone_on_its_line(statement, block, position):
            return False
        wanted = segment(self.facts, receiver)
        root = _root_name(receiver)
        if root is None:
            return False
        between: list[ast.stmt] = []
        for line in statement_lines(block, position + 1):
            if isinstance(line[0], (ast.For, ast.While)):
                loop = line[0]
                break
            if not _independent_of(line, root):
                return False
            between.extend(line)
        else:
            return False
        counter = _loop_counter(loop, [*block[:position], *between])
        if counter is None:
            return False
        reset_statement = _first_touching(loop.body, root)
        if reset_statement is None or isinstance(reset_statement, COMPOUND_STATEMENTS):
            return False
        resets = self._resets_in(reset_statement, wanted)
        if len(resets) != 1 or resets[0].args or resets[0].keywords:
            return False
        reset = resets[0]
        before = loop.body[: loop.body.index(reset_statement)]
        if any(self._calls_local(part) for part in before):
            return False  # a function of the module may reset the env first
        read = {node.id for node in walk(statement.value) if isinstance(node, ast.Name)} | {root}
        # the counter is 0 when the loop starts (the for binds it; a while's ``i = 0`` was
        # checked): only what the body does before the reset may change it
        bound = _bound_names([*between, *before])
        if isinstance(loop, ast.For):
            bound |= {node.id for node in walk(loop.target) if isinstance(node, ast.Name)}
        if "*" in bound or counter in _bound_names(before) or read & (bound | {counter}):
            return False
        value = SeedValue()
        self.plan.replace(call, value.take)
        self.plan.remove(statement, keep_comments=True)
        seed = value.get(as_int=numpy, moved=lambda: statement in self.plan.removed)
        self._edit(reset).add_seed = _conditional_seed(seed, f"{counter} == 0", True)
        self.report(
            call,
            code,
            f"`{called}(s)` merged into the reset of the loop's first iteration (line {reset.lineno}): "
            f"`{receiver_text(receiver)}.reset(seed=s if {counter} == 0 else None)`; that reset returns the seeded "
            f"episode, as legacy's did, and no extra episode starts{self._why(decision)}",
            self._kind(decision, FixKind.AUTO),
            tier=Tier.NOTE if decision.action is Action.REWRITE else None,  # it explains the rewrite: nothing to decide
            question=self.receiver_question(receiver, decision),
        )
        return True

    def _calls_local(self, statement: ast.stmt) -> bool:
        """Does ``statement`` call a function or method of this module (which may touch the env)?"""
        local = self.facts.memo(("seed-local-defs", 0), lambda: _defined_names(self.facts.tree))
        for node in walk(statement):
            if isinstance(node, ast.Call):
                func = node.func
                if isinstance(func, ast.Name) and func.id in local:
                    return True
                if isinstance(func, ast.Attribute) and func.attr in local:
                    return True
        return False

    def _merge_from_branch(
        self,
        call: ast.Call,
        statement: ast.Expr,
        receiver: ast.expr,
        decision: Decision,
        code: str,
        called: str,
        numpy: bool,
    ) -> bool:
        """``if c: env.seed(s)`` (or the seed ending an else) followed, after the if, by the
        reset of the same env: legacy's seeded episode is the one that reset returns. A reset
        put in the seed's place would play that episode and hand the program the next one,
        so the seed goes to the reset after the if, on the path that seeded:
        ``env.reset(seed=s if c else None)`` (``reset(seed=None)`` continues the stream as
        ``reset()`` did). That needs a test without side effects whose names, like the seed's,
        nothing rebinds before the reset; otherwise the call is reported and left. Where no
        reset of the env follows the if in its block, the seeded reset in place stays."""
        branch = self.facts.parent(statement)
        if not isinstance(branch, ast.If):
            return False
        in_body = bool(branch.body) and branch.body[-1] is statement
        in_else = bool(branch.orelse) and branch.orelse[-1] is statement
        if not (in_body or in_else):
            return False
        reset, setup = self._next_reset(branch, receiver)  # type: ignore[arg-type]  # any statement of a block
        if reset is None:
            return False
        name = receiver_text(receiver)
        why = self._why(decision)
        blocker = self._branch_blocker(branch, statement, reset, receiver, setup)
        whole_if = in_body and len(branch.body) == 1 and not branch.orelse
        if blocker is None and in_body and len(branch.body) == 1 and branch.orelse:
            blocker = "the seed is all the if does and an else follows"
        if blocker is not None:
            self.report(
                call,
                code,
                f"`{called}(s)` seeds in a branch the reset after the if (line {reset.lineno}) follows: that reset "
                f"gave the seeded episode, so `{name}.reset(seed=s)` here would hand the program the next one; "
                f"pass the seed to that reset on this path only ({blocker}){why}",
                FixKind.FLAG,
                question=self.receiver_question(receiver, decision),
            )
            return True
        value = SeedValue()
        self.plan.replace(call, value.take)
        if whole_if:
            self.plan.remove(branch, keep_comments=True)
            removed: ast.stmt = branch
        else:
            self.plan.remove(statement, keep_comments=True)
            removed = statement
            if in_else and len(branch.orelse) == 1:
                self.plan.replace(branch, _without_else)
        test = segment(self.facts, branch.test)
        seed = value.get(as_int=numpy, moved=lambda: removed in self.plan.removed)
        shown = f"s if {test} else None" if in_body else f"None if {test} else s"
        argument = _seed_argument(call)
        if argument is not None and _none_guard(branch.test, in_body) == ast.unparse(argument):
            # ``if s is not None: env.seed(s)``: reset(seed=None) is what the other path does anyway
            self._edit(reset).add_seed = seed
            shown = "s"
        else:
            self._edit(reset).add_seed = _conditional_seed(seed, test, in_body)
        self.report(
            call,
            code,
            f"`{called}(s)` merged into the reset after the if (line {reset.lineno}), on the path that seeded: "
            f"`{name}.reset(seed={shown})`; that reset returns the seeded episode, as legacy's did{why}",
            self._kind(decision, FixKind.AUTO),
            question=self.receiver_question(receiver, decision),
        )
        return True

    def _branch_blocker(
        self, branch: ast.If, statement: ast.Expr, reset: ast.Call, receiver: ast.expr, setup: ast.Call | None
    ) -> str | None:
        """Why the seed of ``statement`` cannot move to ``reset`` as a conditional seed, or None."""
        if setup is not None:
            return f"set-up on the env runs before that reset (line {setup.lineno})"
        for node in walk(branch.test):
            if isinstance(node, (ast.Call, ast.NamedExpr, ast.Await, ast.Yield, ast.YieldFrom, ast.Lambda, ast.IfExp)):
                return "the if's test does more than read values"
        wanted = segment(self.facts, receiver)
        for part in (*branch.body, *branch.orelse):
            for node in walk(part):
                if (
                    node is not statement.value
                    and isinstance(node, ast.Call)
                    and isinstance(node.func, ast.Attribute)
                    and node.func.attr in ("seed", "_seed")
                    and segment(self.facts, node.func.value) == wanted
                ):
                    return "the env is seeded elsewhere in the if"
        read = {node.id for node in walk(branch.test) if isinstance(node, ast.Name)}
        read |= {node.id for node in walk(statement.value) if isinstance(node, ast.Name)}
        root = _root_name(receiver)
        if root is not None:
            read.add(root)
        between = self._statements_between(branch, reset)
        if between is None:
            return "the reset is not in the if's block"
        bound = _bound_names([*branch.body, *branch.orelse, *between])
        if "*" in bound:
            return "names are rebound globally before that reset"
        rebound = bound & read
        if rebound:
            return f"{', '.join(sorted(rebound))} may change before that reset"
        return None


def _without_else(node: cst.If) -> cst.If:
    """The if whose else held only the seed merged after it: the else goes."""
    return node.with_changes(orelse=None)


def _conditional_seed(
    seed: Callable[[], cst.BaseExpression | None], test: str, in_body: bool
) -> Callable[[], cst.BaseExpression | None]:
    """``s if test else None`` (``None if test else s`` for a seed in the else)."""

    def value() -> cst.BaseExpression | None:
        taken = seed()
        if taken is None:
            return None
        if isinstance(taken, (cst.IfExp, cst.Lambda, cst.NamedExpr)) and not taken.lpar:
            taken = taken.with_changes(lpar=[cst.LeftParen()], rpar=[cst.RightParen()])
        condition = cst.parse_expression(f"({test})")
        if isinstance(condition, (cst.Name, cst.Attribute, cst.Comparison, cst.UnaryOperation, cst.Subscript)):
            condition = condition.with_changes(lpar=[], rpar=[])  # plain enough to read without them
        none = cst.Name("None")
        body, orelse = (taken, none) if in_body else (none, taken)
        return cst.IfExp(test=condition, body=body, orelse=orelse)

    return value


def _none_guard(test: ast.expr, in_body: bool) -> str | None:
    """``x`` of ``if x is not None:`` (seed in the body) or ``if x is None:`` (seed in the else)."""
    if not (isinstance(test, ast.Compare) and len(test.ops) == 1 and isinstance(test.comparators[0], ast.Constant)):
        return None
    if test.comparators[0].value is not None or not isinstance(test.ops[0], ast.IsNot if in_body else ast.Is):
        return None
    return ast.unparse(test.left)


def _bound_names(statements: list[ast.stmt]) -> set[str]:
    """Names any of ``statements`` (re)binds, at any depth."""
    bound: set[str] = set()
    for statement in statements:
        for node in walk(statement):
            targets: list[ast.expr] = []
            if isinstance(node, ast.Assign):
                targets = list(node.targets)
            elif isinstance(node, (ast.AugAssign, ast.AnnAssign, ast.NamedExpr, ast.For, ast.AsyncFor)):
                targets = [node.target]
            elif isinstance(node, (ast.With, ast.AsyncWith)):
                targets = [item.optional_vars for item in node.items if item.optional_vars is not None]
            elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                bound.add(node.name)
            elif isinstance(node, (ast.Import, ast.ImportFrom)):
                bound.update((alias.asname or alias.name).split(".")[0] for alias in node.names)
            elif isinstance(node, (ast.Global, ast.Nonlocal, ast.Delete)):
                return {"*"} | bound  # too much to follow: treat every name as rebound
            for target in targets:
                bound.update(inner.id for inner in walk(target) if isinstance(inner, ast.Name))
    return bound


def _defined_names(tree: ast.AST) -> frozenset[str]:
    return frozenset(
        node.name for node in ast.walk(tree) if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef))
    )


def _first_touching(body: list[ast.stmt], root: str) -> ast.stmt | None:
    """The first statement of ``body`` that names ``root``."""
    for statement in body:
        if any(isinstance(node, ast.Name) and node.id == root for node in walk(statement)):
            return statement
    return None


def _loop_counter(loop: ast.For | ast.While, earlier: list[ast.stmt]) -> str | None:
    """The counter that is 0 on a loop's first iteration and never again: ``for i in range(n)``,
    ``range(0, n)``, ``for i, x in enumerate(xs)``, or ``i = 0`` (the last binding of ``i`` in
    ``earlier``) then ``while i < n:`` whose body does ``i += 1`` at its top level, binds ``i``
    nowhere else and never continues."""
    if isinstance(loop, ast.For):
        it = loop.iter
        if not (isinstance(it, ast.Call) and isinstance(it.func, ast.Name) and not it.keywords):
            return None
        if it.func.id == "range" and isinstance(loop.target, ast.Name):
            if len(it.args) == 1 or (len(it.args) == 2 and _is_zero(it.args[0])):
                return loop.target.id
        if it.func.id == "enumerate" and len(it.args) == 1 and isinstance(loop.target, ast.Tuple):
            first = loop.target.elts[0] if loop.target.elts else None
            if isinstance(first, ast.Name):
                return first.id
        return None
    test = loop.test
    if not (
        isinstance(test, ast.Compare)
        and len(test.ops) == 1
        and isinstance(test.ops[0], ast.Lt)
        and isinstance(test.left, ast.Name)
    ):
        return None
    counter = test.left.id
    steps = [
        s
        for s in loop.body
        if isinstance(s, ast.AugAssign)
        and isinstance(s.op, ast.Add)
        and isinstance(s.target, ast.Name)
        and s.target.id == counter
        and isinstance(s.value, ast.Constant)
        and s.value.value == 1
    ]
    if len(steps) != 1 or any(isinstance(node, ast.Continue) for part in loop.body for node in walk(part)):
        return None
    if counter in _bound_names([s for s in loop.body if s is not steps[0]]):
        return None
    for index in range(len(earlier) - 1, -1, -1):
        part = earlier[index]
        if counter in _bound_names([part]):
            if (
                isinstance(part, ast.Assign)
                and len(part.targets) == 1
                and isinstance(part.targets[0], ast.Name)
                and _is_zero(part.value)
            ):
                return counter
            return None
    return None


def _is_zero(node: ast.expr) -> bool:
    return isinstance(node, ast.Constant) and type(node.value) is int and node.value == 0
