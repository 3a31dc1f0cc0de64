"""Where a seed's reset is: the reset of the same env a seeding statement leads to (GM203, GM208).

``NextReset`` (a mixin of ``SeedCalls``) looks only at the seed's own block: the reset a
seed merges into, the set-up calls of the env it moves past, the statements in between
and a statement's block and index there. ``seeds`` and ``seed_merges`` build on it.
"""

from __future__ import annotations

import ast

from gymmigrate.facts.module import COMPOUND_STATEMENTS, statement_lines, walk
from gymmigrate.facts.reset_flow import line_before, segment
from gymmigrate.rules.reset_seed.common import ResetSeedBase

_BLOCK_FIELDS = ("body", "orelse", "finalbody")
# methods of an env a seed never moves past: they run or end episodes
_NOT_SETUP = frozenset({"reset", "step", "seed", "close", "render", "step_async", "step_wait"})


class NextReset(ResetSeedBase):
    # -- merging into the next reset ---------------------------------------------------------

    def _next_reset(self, statement: ast.Expr, receiver: ast.expr) -> tuple[ast.Call | None, ast.Call | None]:
        """The reset of the same env that the seeding ``statement`` leads to, if merging is
        safe, and the first set-up call on the env the seed moves past (None if none).

        Only statements of the same block are looked at, so a seed is never moved into a
        loop; statements in between must not touch the env (space seeding and other
        seeding calls are fine), except set-up calls of the env's own methods
        (``env.set_agents(...)``): the reset that comes next in program order follows them,
        and a reset put in the seed's place would run before them. The seed must have its
        line to itself.
        """
        found = self._place_in_block(statement)
        if found is None:
            return None, None
        block, position = found
        if not self._alone_on_its_line(statement, block, position):
            return None, None
        wanted = segment(self.facts, receiver)
        root = _root_name(receiver)
        setup: ast.Call | None = None
        for line in statement_lines(block, position + 1):
            reset = self._reset_statement(line, wanted)
            if reset is not None:
                return reset, setup
            if _independent_of(line, root):
                continue
            call = self._setup_call(line, wanted, root)
            if call is None:
                return None, None
            setup = setup or call
        return None, None

    def _setup_call(self, line: list[ast.stmt], receiver_code: str, root: str | None) -> ast.Call | None:
        """``env.set_agents(agents)`` on a line of its own: a method of the env itself or of
        what it wraps (not reset, step, seed, close or render) called for its effect, whose arguments neither
        hand the env on nor rebind anything."""
        if root is None or len(line) != 1 or not isinstance(line[0], ast.Expr):
            return None
        call = line[0].value
        if not (isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute)):
            return None
        owner = call.func.value  # the env, or what it wraps: ``env.unwrapped.set_agents(...)``
        while isinstance(owner, ast.Attribute) and segment(self.facts, owner) != receiver_code:
            owner = owner.value
        if call.func.attr in _NOT_SETUP or segment(self.facts, owner) != receiver_code:
            return None
        for argument in [*call.args, *(kw.value for kw in call.keywords)]:
            for node in walk(argument):
                if isinstance(node, ast.NamedExpr) or (isinstance(node, ast.Name) and node.id == root):
                    return None
        return call

    def _alone_on_its_line(self, statement: ast.stmt, block: list[ast.stmt], position: int) -> bool:
        """Not in a one-line suite (``if x: env.seed(1)``) nor sharing its line (``a; env.seed(1)``)."""
        if line_before(self.facts, statement).strip():
            return False
        following = block[position + 1] if position + 1 < len(block) else None
        return following is None or following.lineno > (statement.end_lineno or statement.lineno)

    def _place_in_block(self, statement: ast.stmt) -> tuple[list[ast.stmt], int] | None:
        """The block that holds ``statement`` (a body, an else, a handler...) and its index there."""
        parent = self.facts.parent(statement)

        def index() -> dict[int, tuple[list[ast.stmt], int]]:
            places: dict[int, tuple[list[ast.stmt], int]] = {}
            for name in _BLOCK_FIELDS:
                items = getattr(parent, name, None)
                if isinstance(items, list):
                    places.update((id(item), (items, i)) for i, item in enumerate(items))
            return places

        return self.facts.memo(("reset-seed-block", id(parent)), index).get(id(statement))

    def _resets_in(self, part: ast.AST, receiver_code: str) -> list[ast.Call]:
        """The calls ``<receiver>.reset(...)`` anywhere in ``part``, the receiver spelled as
        ``receiver_code``."""
        return [
            node
            for node in walk(part)
            if isinstance(node, ast.Call)
            and isinstance(node.func, ast.Attribute)
            and node.func.attr == "reset"
            and segment(self.facts, node.func.value) == receiver_code
        ]

    def _reset_statement(self, line: list[ast.stmt], receiver_code: str) -> ast.Call | None:
        if len(line) != 1 or not isinstance(line[0], (ast.Expr, ast.Assign)):
            return None
        value = line[0].value
        if not (isinstance(value, ast.Call) and isinstance(value.func, ast.Attribute) and value.func.attr == "reset"):
            return None
        if segment(self.facts, value.func.value) != receiver_code:
            return None
        if value.args or any(kw.arg is None or kw.arg == "seed" for kw in value.keywords):
            return None
        return value

    def _statements_between(self, first: ast.stmt, reset: ast.Call) -> list[ast.stmt] | None:
        found = self._place_in_block(first)
        if found is None:
            return None
        block, position = found
        holder = self.facts.parent(reset)
        for index in range(position + 1, len(block)):
            if block[index] is holder:
                return block[position + 1 : index]
        return None


def _root_name(node: ast.expr) -> str | None:
    while isinstance(node, (ast.Attribute, ast.Subscript, ast.Call)):
        node = node.func if isinstance(node, ast.Call) else node.value
    return node.id if isinstance(node, ast.Name) else None


def _independent_of(line: list[ast.stmt], root: str | None) -> bool:
    """Can a seed move past ``line``? Only simple lines that leave the env alone qualify.

    Reading the env's attributes is fine; rebinding the name or calling anything but a
    seeding function (env.action_space.seed, np.random.seed...) is not.
    """
    if root is None or isinstance(line[0], COMPOUND_STATEMENTS):
        return False
    bound: set[str] = set()

    def bind(target: ast.expr) -> None:
        if isinstance(target, (ast.Tuple, ast.List)):
            for element in target.elts:
                bind(element.value if isinstance(element, ast.Starred) else element)
        else:
            name = _root_name(target)
            if name is not None:
                bound.add(name)

    for statement in line:
        for node in walk(statement):
            if isinstance(node, ast.Assign):
                for target in node.targets:
                    bind(target)
            elif isinstance(node, (ast.AugAssign, ast.AnnAssign, ast.NamedExpr)):
                bind(node.target)
            elif isinstance(node, ast.Call):
                func = node.func
                called = func.attr if isinstance(func, ast.Attribute) else func.id if isinstance(func, ast.Name) else ""
                if "seed" not in called:
                    return False
    return root not in bound
