"""Control-flow and data-flow questions asked by the reset/seed rules (GM201-GM208, GM704).

* Is a call inside a loop of its own function, and does it run on every iteration?
* Does a seed expression take the same value on every iteration (a constant seed)?
* Is a seed a numpy scalar (``np.random.randint(...)``, ``rng.integers(...)``, an element
  of a numpy array), which Gymnasium rejects (``Seed must be a python integer``)?
* Which name can hold the ``info`` dict a rewritten ``reset()`` now returns without
  changing what an existing read of that name sees?

All answers are syntactic approximations over one module, read from CPython's ``ast``
through ``ModuleFacts``; each one errs on the side of a fresh name or a review item.
Walks go up the parent links (bounded by the nesting depth) or over one loop, whose
bound names are memoized, so asking about every call of a file stays linear in practice.
"""

from __future__ import annotations

import ast
import re
from bisect import bisect_left, bisect_right

from gymmigrate.facts.flow import Flow
from gymmigrate.facts.module import (
    COMPREHENSIONS,
    FUNCTIONS,
    ModuleFacts,
    Scope,
    dotted_name,
    parenthesized_if_needed,
    walk,
)

Position = tuple[int, int]
Loop = ast.For | ast.AsyncFor | ast.While | ast.ListComp | ast.SetComp | ast.GeneratorExp | ast.DictComp

# A loop's repeated part ends at the function (or class, lambda, module) that holds it.
_SCOPE_BOUNDARIES = (*FUNCTIONS, ast.Lambda, ast.ClassDef, ast.Module)

# Methods of numpy Generators / RandomStates (and of gym's np_random) that return numpy scalars.
_NUMPY_RNG_METHODS = frozenset(
    {"integers", "randint", "random_integers", "choice", "permutation", "random", "uniform", "normal"}
)
# Methods that turn a numpy value back into Python objects.
_TO_PYTHON = frozenset({"item", "tolist"})
# Builtins whose result is a Python int whatever their argument.
_PYTHON_INT_BUILTINS = frozenset({"int", "len", "hash", "sum", "round"})
_RNG_LIKE_NAMES = ("rng", "np_random", "random_state", "generator")
# Methods whose result carries the env's info dict when unpacked.
ENV_RESULT_METHODS = frozenset({"step", "reset", "last"})
# How far ``seed = other`` chains are followed when looking for a numpy value.
_NUMPY_DEPTH = 4


def position(node: ast.AST) -> Position:
    return (node.lineno, node.col_offset)  # type: ignore[attr-defined]


def source_lines(facts: ModuleFacts) -> list[bytes]:
    """The file's lines as ``ast`` counts them (only \\n, \\r\\n and \\r end a line;
    ``str.splitlines`` would also split at form feeds), UTF-8 encoded like its columns."""

    def compute() -> list[bytes]:
        return re.split(rb"(?<=\r\n)|(?<=\r)(?!\n)|(?<=\n)", facts.text.encode("utf-8"))

    return facts.memo(("reset-flow-lines", 0), compute)


def segment(facts: ModuleFacts, node: ast.AST) -> str:
    """The source text of ``node``, like ``ast.get_source_segment`` without re-splitting
    the whole file on every call."""
    lines = source_lines(facts)
    first, last = node.lineno - 1, node.end_lineno - 1  # type: ignore[attr-defined]
    start, end = node.col_offset, node.end_col_offset  # type: ignore[attr-defined]
    if first == last:
        return parenthesized_if_needed(node, lines[first][start:end].decode("utf-8"))
    text = b"".join([lines[first][start:], *lines[first + 1 : last], lines[last][:end]]).decode("utf-8")
    return parenthesized_if_needed(node, text)


def line_before(facts: ModuleFacts, node: ast.AST) -> str:
    """The text on ``node``'s first line before it."""
    return source_lines(facts)[node.lineno - 1][: node.col_offset].decode("utf-8")  # type: ignore[attr-defined]


# -- loops -------------------------------------------------------------------------


def enclosing_loops(facts: ModuleFacts, node: ast.AST) -> list[Loop]:
    """Loops of ``node``'s own function whose repeated part contains it, innermost first.

    A ``for`` loop's iterable and an ``else`` clause run once, so they do not count;
    neither do the ``for ... in ... if ...`` clauses of a comprehension.
    """

    def compute() -> list[Loop]:
        loops: list[Loop] = []
        child = node
        parent = facts.parent(child)
        while parent is not None and not isinstance(parent, _SCOPE_BOUNDARIES):
            if isinstance(parent, (ast.For, ast.AsyncFor, ast.While)) and _in_body(child, parent):
                loops.append(parent)
            elif isinstance(parent, ast.While) and child is parent.test:
                loops.append(parent)
            elif isinstance(parent, COMPREHENSIONS) and not isinstance(child, ast.comprehension):
                loops.append(parent)
            child, parent = parent, facts.parent(parent)
        return loops

    return facts.memo(("reset-flow-loops", id(node)), compute)


def guarded_to_run_once(facts: ModuleFacts, node: ast.AST, loop: ast.AST) -> bool:
    """Is ``node`` under an ``if`` (inside ``loop``) that reads like "first iteration only"?

    Recognised tests: ``ep == 0``, ``x is None``, ``not seeded``, and names containing
    ``first``. Anything else (``if done:``) runs on many iterations.
    """
    child = node
    parent = facts.parent(child)
    while parent is not None and parent is not loop:
        if isinstance(parent, ast.If) and _in_body(child, parent) and _reads_as_once(parent.test):
            return True
        child, parent = parent, facts.parent(parent)
    return False


def made_anew_in(facts: ModuleFacts, receiver: ast.expr, loop: ast.AST) -> bool:
    """``for name in names: env = gym.make(name); env.seed(7)``: the receiver is a name that a
    call's result is assigned to inside ``loop`` before the read, on every path: each
    iteration seeds an object of its own once, which reseeds nothing."""
    if not isinstance(receiver, ast.Name):
        return False
    flow = Flow.of(facts)
    binding = flow.last_binding_of(receiver)
    statement = facts.parent(binding) if isinstance(binding, ast.Name) else None
    if not (isinstance(binding, ast.Name) and isinstance(statement, ast.Assign) and statement.targets == [binding]):
        return False
    if not isinstance(statement.value, ast.Call) or not any(a is loop for a in facts.ancestors(statement)):
        return False
    return flow.dominates(statement, receiver, binding)


def _in_list(node: ast.AST, items: list[ast.AST]) -> bool:
    return any(item is node for item in items)


def _in_body(child: ast.AST, parent: ast.For | ast.AsyncFor | ast.While | ast.If) -> bool:
    """Is ``child`` (a child of ``parent``) one of its body's statements, not of its ``else``?

    Told by position, not by a scan of a body that may hold thousands of statements.
    """
    if not isinstance(child, ast.stmt):
        return False
    return not parent.orelse or position(child) < position(parent.orelse[0])


def _reads_as_once(test: ast.expr) -> bool:
    if isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not):
        return True
    if isinstance(test, ast.Compare):
        for operator, comparator in zip(test.ops, test.comparators):
            if isinstance(operator, (ast.Eq, ast.Is)):
                for side in (test.left, comparator):
                    if isinstance(side, ast.Constant) and (side.value is None or (type(side.value) is int and side.value == 0)):
                        return True
    return any("first" in name.lower() for name in read_names(test))


def is_iteration_invariant(facts: ModuleFacts, expr: ast.expr, loop: ast.AST) -> bool:
    """Does ``expr`` take the same value on every iteration of ``loop``?

    It does unless it calls something (``rng.integers()`` may vary) or reads a name or
    attribute the loop binds (its target, an assignment in its body).
    """
    if any(isinstance(node, ast.Call) for node in walk(expr)):
        return False
    bound = facts.memo(("reset-flow-bound", id(loop)), lambda: _bound_names(loop))
    return not (read_names(expr) & bound)


def _bound_names(code: ast.AST) -> set[str]:
    """Names and dotted attributes a piece of code (re)binds."""
    names: set[str] = set()

    def add(target: ast.AST) -> None:
        if isinstance(target, (ast.Tuple, ast.List)):
            for element in target.elts:
                add(element)
        elif isinstance(target, ast.Starred):
            add(target.value)
        else:
            name = dotted_name(target)
            if name:
                names.add(name)

    for node in walk(code):
        if isinstance(node, ast.Assign):
            for target in node.targets:
                add(target)
        elif isinstance(node, (ast.AugAssign, ast.AnnAssign, ast.For, ast.AsyncFor, ast.comprehension, ast.NamedExpr)):
            add(node.target)
    return names


def read_names(expr: ast.AST) -> set[str]:
    """Every identifier spelled in ``expr`` and every dotted chain (``a.b.c`` gives a, b, c,
    a.b and a.b.c): attribute and keyword names count, as a reader sees them."""
    names: set[str] = set()
    for node in walk(expr):
        if isinstance(node, ast.Name):
            names.add(node.id)
        elif isinstance(node, ast.Attribute):
            names.add(node.attr)
            dotted = dotted_name(node)
            if dotted:
                names.add(dotted)
        elif isinstance(node, ast.keyword) and node.arg:
            names.add(node.arg)
        elif isinstance(node, ast.arg):
            names.add(node.arg)
    return names


# -- numpy seeds ---------------------------------------------------------------------


class NumpySeeds:
    """Recognises seeds that are numpy scalars, following simple assignments."""

    def __init__(self, facts: ModuleFacts) -> None:
        self._facts = facts

    def is_numpy(self, expr: ast.AST, depth: int = 0) -> bool:
        if depth > _NUMPY_DEPTH:
            return False
        if isinstance(expr, ast.Call):
            return self._call_is_numpy(expr, depth)
        if isinstance(expr, ast.Subscript):
            return self.is_numpy(expr.value, depth + 1)
        if isinstance(expr, ast.BinOp):
            return self.is_numpy(expr.left, depth + 1) or self.is_numpy(expr.right, depth + 1)
        if isinstance(expr, ast.Attribute):
            return expr.attr == "np_random" or _rng_like(expr)
        if isinstance(expr, ast.Name):
            return self._name_is_numpy(expr, depth)
        return False

    def _call_is_numpy(self, call: ast.Call, depth: int) -> bool:
        func = call.func
        if isinstance(func, ast.Name) and func.id in _PYTHON_INT_BUILTINS:
            return False
        if any(q == "numpy" or q.startswith("numpy.") for q in self._facts.qualified_names(func)):
            return True
        if isinstance(func, ast.Attribute):
            if func.attr in _TO_PYTHON:
                return False
            if func.attr in _NUMPY_RNG_METHODS and (_rng_like(func.value) or self.is_numpy(func.value, depth + 1)):
                return True
            return self.is_numpy(func.value, depth + 1) and func.attr != "seed"
        return False

    def _name_is_numpy(self, name: ast.Name, depth: int) -> bool:
        for binding in self._facts.bindings_of(name):
            if not isinstance(binding, ast.Name):
                continue
            value = self._bound_value(binding)
            if value is not None and self.is_numpy(value, depth + 1):
                return True
        return False

    def _bound_value(self, target: ast.Name) -> ast.expr | None:
        parent = self._facts.parent(target)
        if isinstance(parent, ast.Assign) and _in_list(target, parent.targets):  # type: ignore[arg-type]
            return parent.value
        if isinstance(parent, (ast.For, ast.AsyncFor, ast.comprehension)) and parent.target is target:
            # ``for seed in np.arange(5)``: the loop variable is an element of the iterable.
            return parent.iter
        if isinstance(parent, ast.AnnAssign) and parent.target is target:
            return parent.value
        return None


def _rng_like(node: ast.AST) -> bool:
    name = (dotted_name(node) or "").rsplit(".", 1)[-1].lower()
    return any(part in name for part in _RNG_LIKE_NAMES)


# -- names for info -----------------------------------------------------------------------


class InfoNames:
    """Chooses the name that receives ``info`` in a rewritten ``obs, info = env.reset()``.

    ``info`` (``infos`` for vector envs) is kept when the scope binds it only from env
    results (``..., info = env.step(a)``) and no read of it would now see the reset's
    info instead (a read after the reset with no other env-result binding in between,
    or a read earlier in a loop that also holds the reset). Otherwise ``reset_info``
    (``reset_infos``), then numbered variants, are tried; those must be entirely unused.
    """

    def __init__(self, facts: ModuleFacts) -> None:
        self._facts = facts
        # Names this family already introduced, per scope (they are not in the facts).
        self._introduced: dict[int, set[str]] = {}

    def choose(self, scope: Scope, reset: ast.Call, base: str) -> str:
        candidates = [base, f"reset_{base}"] + [f"reset_{base}_{n}" for n in range(2, 10)]
        for candidate in candidates:
            if candidate == base and self._reusable(scope, reset, candidate):
                break
            if candidate != base and self._unused(scope, candidate):
                break
        self._introduced.setdefault(id(scope), set()).add(candidate)
        return candidate

    def _unused(self, scope: Scope, name: str) -> bool:
        if name in self._introduced.get(id(scope), set()):
            return True
        visible = self._facts.resolve(name, scope)[1]
        return not visible and not scope.reads.get(name) and not scope.bindings.get(name)

    def _reusable(self, scope: Scope, reset: ast.Call, name: str) -> bool:
        own = scope.bindings.get(name, [])
        reads = scope.reads.get(name, [])
        if not own:
            # Bound only in an enclosing scope (or nowhere): a new local binding would
            # hide the outer one from every read in this scope.
            return not reads
        uses = self._uses(scope, name)
        if uses is None:
            return False  # bound to something other than an env result
        bindings, read_positions, sorted_reads = uses
        reset_at = position(reset)
        # A read after the reset sees the reset's info unless an env-result binding comes
        # between them: only reads up to the first binding after the reset can.
        after = bisect_right(read_positions, reset_at)
        following = bisect_right(bindings, reset_at)
        if after < len(read_positions) and (following == len(bindings) or read_positions[after] <= bindings[following]):
            return False
        # A read before the reset can see it only through a loop around both, and then
        # only if no binding inside that loop precedes the read: for each loop, only the
        # reads up to the loop's first binding can.
        loops = enclosing_loops(self._facts, reset)
        reset_loops = {id(loop) for loop in loops}
        for loop in loops:
            loop_at = position(loop)
            first_binding = bisect_right(bindings, loop_at)
            limit = min(bindings[first_binding], reset_at) if first_binding < len(bindings) else reset_at
            candidates = sorted_reads[bisect_left(read_positions, loop_at) : bisect_right(read_positions, limit)]
            for read in candidates:
                common = next((outer for outer in enclosing_loops(self._facts, read) if id(outer) in reset_loops), None)
                if common is loop:
                    return False
        return True

    def _uses(self, scope: Scope, name: str) -> tuple[list[Position], list[Position], list[ast.Name]] | None:
        """Sorted positions of ``name``'s env-result bindings in ``scope`` (None if it has
        another kind of binding) and of its reads there, with the reads."""

        def compute() -> tuple[list[Position], list[Position], list[ast.Name]] | None:
            statements = [self._env_result_binding(binding) for binding in scope.bindings.get(name, [])]
            if any(statement is None for statement in statements):
                return None
            reads = sorted(scope.reads.get(name, []), key=position)
            return sorted(position(s) for s in statements), [position(r) for r in reads], reads  # type: ignore[arg-type]

        return self._facts.memo((f"reset-flow-info-uses:{name}", id(scope)), compute)

    def _env_result_binding(self, binding: ast.AST) -> ast.Assign | None:
        """The statement if ``binding`` is the last target of ``... , info = env.<step|reset|last>(...)``."""
        if not isinstance(binding, ast.Name):
            return None
        container = self._facts.parent(binding)
        if not isinstance(container, (ast.Tuple, ast.List)) or container.elts[-1] is not binding:
            return None
        holder = self._facts.parent(container)
        if isinstance(holder, (ast.Tuple, ast.List)):  # ``(obs, info), done = env.reset(), False``
            holder = self._facts.parent(holder)
        if not isinstance(holder, ast.Assign) or holder.value is container:
            return None
        values = holder.value.elts if isinstance(holder.value, ast.Tuple) else [holder.value]
        for value in values:
            if isinstance(value, ast.Call) and isinstance(value.func, ast.Attribute) and value.func.attr in ENV_RESULT_METHODS:
                return holder
        return None


def scope_of_expression(facts: ModuleFacts, node: ast.AST) -> Scope:
    """The scope an expression is evaluated in.

    A class body is a scope for the expressions of its own statements; decorators, bases
    and defaults belong to the enclosing one.
    """
    child = node
    for ancestor in facts.ancestors(node):
        scope = facts.scopes.get(ancestor)
        if scope is not None:
            if isinstance(ancestor, (*FUNCTIONS, ast.ClassDef)) and not isinstance(child, ast.stmt):
                child = ancestor
                continue
            if isinstance(ancestor, ast.Lambda) and child is not ancestor.body:
                child = ancestor
                continue
            return scope
        child = ancestor
    return facts.module_scope
