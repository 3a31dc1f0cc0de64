"""Control-flow and data-flow questions asked by the reset/seed rules (GM201-GM208, GM704).

* Is a call inside a loop of its own function, and does it run on every iteration?
* Does a seed expression take the same value on every iteration (a constant seed)?
* Is a seed a numpy scalar (``np.random.randint(...)``, ``rng.integers(...)``, an element
  of a numpy array), which Gymnasium rejects (``Seed must be a python integer``)?
* Which name can hold the ``info`` dict a rewritten ``reset()`` now returns without
  changing what an existing read of that name sees?

All answers are syntactic approximations over one module; each one errs on the side of
a fresh name or a review item.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

import libcst as cst
from libcst.metadata import Assignment, Scope

from gymmigrate.analysis.receivers import ReceiverAnalysis

Position = tuple[int, int]
PositionOf = Callable[[cst.CSTNode], Position]

_SCOPE_BOUNDARIES = (cst.FunctionDef, cst.Lambda, cst.ClassDef, cst.Module)
_COMPREHENSIONS = (cst.ListComp, cst.SetComp, cst.GeneratorExp, cst.DictComp)
Loop = cst.For | cst.While | cst.ListComp | cst.SetComp | cst.GeneratorExp | cst.DictComp

# Methods of numpy Generators / RandomStates (and of gym's np_random) that return numpy scalars.
_NUMPY_RNG_METHODS = frozenset(
    {"integers", "randint", "random_integers", "choice", "permutation", "random", "uniform", "normal"}
)
# Methods that turn a numpy value back into Python objects.
_TO_PYTHON = frozenset({"item", "tolist"})
_RNG_LIKE_NAMES = ("rng", "np_random", "random_state", "generator")
# Methods whose result carries the env's info dict when unpacked.
ENV_RESULT_METHODS = frozenset({"step", "reset", "last"})


# -- loops -------------------------------------------------------------------------


def enclosing_loops(analysis: ReceiverAnalysis, node: cst.CSTNode) -> list[Loop]:
    """Loops of ``node``'s own function whose repeated part contains it, innermost first.

    A ``for`` loop's iterable and an ``else`` clause run once, so they do not count.
    """
    loops: list[Loop] = []
    child: cst.CSTNode = node
    parent = analysis.parent(child)
    while parent is not None and not isinstance(parent, _SCOPE_BOUNDARIES):
        if isinstance(parent, (cst.For, cst.While)) and child is parent.body:
            loops.append(parent)
        elif isinstance(parent, cst.While) and child is parent.test:
            loops.append(parent)
        elif isinstance(parent, _COMPREHENSIONS) and child is not parent.for_in:
            loops.append(parent)
        child, parent = parent, analysis.parent(parent)
    return loops


def guarded_to_run_once(analysis: ReceiverAnalysis, node: cst.CSTNode, loop: cst.CSTNode) -> bool:
    """Is ``node`` under an ``if`` (inside ``loop``) that reads like "first iteration only"?

    Recognised tests: ``ep == 0``, ``x is None``, ``not seeded``, and names containing
    ``first``. Anything else (``if done:``) runs on many iterations.
    """
    child: cst.CSTNode = node
    parent = analysis.parent(child)
    while parent is not None and parent is not loop:
        if isinstance(parent, cst.If) and child is parent.body and _reads_as_once(parent.test):
            return True
        child, parent = parent, analysis.parent(parent)
    return False


def _reads_as_once(test: cst.BaseExpression) -> bool:
    if isinstance(test, cst.UnaryOperation) and isinstance(test.operator, cst.Not):
        return True
    if isinstance(test, cst.Comparison):
        for target in test.comparisons:
            if isinstance(target.operator, (cst.Equal, cst.Is)):
                for side in (test.left, target.comparator):
                    if isinstance(side, cst.Integer) and side.value == "0":
                        return True
                    if isinstance(side, cst.Name) and side.value == "None":
                        return True
    return any("first" in name.lower() for name in _dotted_names(test))


def is_iteration_invariant(expr: cst.BaseExpression, loop: cst.CSTNode) -> bool:
    """Does ``expr`` take the same value on every iteration of ``loop``?

    It does unless it calls something (``rng.integers()`` may vary) or reads a name or
    attribute the loop binds (its target, an assignment in its body).
    """
    if _contains(expr, cst.Call):
        return False
    bound = _BoundNames()
    loop.visit(bound)
    return not (set(_dotted_names(expr)) & bound.names)


class _BoundNames(cst.CSTVisitor):
    """Names and dotted attributes a piece of code (re)binds."""

    def __init__(self) -> None:
        self.names: set[str] = set()

    def _add(self, target: cst.BaseExpression) -> None:
        if isinstance(target, (cst.Tuple, cst.List)):
            for element in target.elements:
                self._add(element.value)
        elif isinstance(target, cst.StarredElement):
            self._add(target.value)
        else:
            name = _dotted(target)
            if name:
                self.names.add(name)

    def visit_AssignTarget(self, node: cst.AssignTarget) -> None:
        self._add(node.target)

    def visit_AugAssign(self, node: cst.AugAssign) -> None:
        self._add(node.target)

    def visit_AnnAssign(self, node: cst.AnnAssign) -> None:
        self._add(node.target)

    def visit_For(self, node: cst.For) -> None:
        self._add(node.target)

    def visit_CompFor(self, node: cst.CompFor) -> None:
        self._add(node.target)

    def visit_NamedExpr(self, node: cst.NamedExpr) -> None:
        self._add(node.target)


def _dotted(node: cst.BaseExpression) -> str | None:
    if isinstance(node, cst.Name):
        return node.value
    if isinstance(node, cst.Attribute):
        owner = _dotted(node.value)
        return f"{owner}.{node.attr.value}" if owner else None
    return None


def _dotted_names(expr: cst.CSTNode) -> Iterable[str]:
    """Every name and dotted attribute chain read in ``expr`` (``a.b.c`` gives a, a.b, a.b.c)."""
    collector = _DottedCollector()
    expr.visit(collector)
    return collector.names


class _DottedCollector(cst.CSTVisitor):
    def __init__(self) -> None:
        self.names: list[str] = []

    def visit_Name(self, node: cst.Name) -> None:
        self.names.append(node.value)

    def visit_Attribute(self, node: cst.Attribute) -> None:
        name = _dotted(node)
        if name:
            self.names.append(name)


def _contains(node: cst.CSTNode, kind: type[cst.CSTNode]) -> bool:
    finder = _KindFinder(kind)
    node.visit(finder)
    return finder.found


class _KindFinder(cst.CSTVisitor):
    def __init__(self, kind: type[cst.CSTNode]) -> None:
        self.kind = kind
        self.found = False

    def on_visit(self, node: cst.CSTNode) -> bool:
        if isinstance(node, self.kind):
            self.found = True
        return not self.found


# -- numpy seeds ---------------------------------------------------------------------


class NumpySeeds:
    """Recognises seeds that are numpy scalars, following simple assignments."""

    def __init__(self, analysis: ReceiverAnalysis, scope_of: Callable[[cst.CSTNode], Scope | None]) -> None:
        self._analysis = analysis
        self._scope_of = scope_of

    def is_numpy(self, expr: cst.BaseExpression, depth: int = 0) -> bool:
        if depth > 4:
            return False
        if isinstance(expr, cst.Call):
            return self._call_is_numpy(expr, depth)
        if isinstance(expr, cst.Subscript):
            return self.is_numpy(expr.value, depth + 1)
        if isinstance(expr, cst.BinaryOperation):
            return self.is_numpy(expr.left, depth + 1) or self.is_numpy(expr.right, depth + 1)
        if isinstance(expr, cst.Attribute):
            return expr.attr.value in ("np_random",) or self._rng_like(expr)
        if isinstance(expr, cst.Name):
            return self._name_is_numpy(expr, depth)
        return False

    def _call_is_numpy(self, call: cst.Call, depth: int) -> bool:
        func = call.func
        if isinstance(func, cst.Name) and func.value in ("int", "len", "hash", "sum", "round"):
            return False
        if any(q == "numpy" or q.startswith("numpy.") for q in self._analysis.qualified_names(func)):
            return True
        if isinstance(func, cst.Attribute):
            if func.attr.value in _TO_PYTHON:
                return False
            if func.attr.value in _NUMPY_RNG_METHODS and (self._rng_like(func.value) or self.is_numpy(func.value, depth + 1)):
                return True
            return self.is_numpy(func.value, depth + 1) and func.attr.value not in ("seed",)
        return False

    def _rng_like(self, node: cst.BaseExpression) -> bool:
        name = (_dotted(node) or "").rsplit(".", 1)[-1].lower()
        return any(part in name for part in _RNG_LIKE_NAMES)

    def _name_is_numpy(self, name: cst.Name, depth: int) -> bool:
        scope = self._scope_of(name)
        if scope is None or name.value not in scope:
            return False
        for assignment in scope[name.value]:
            if not isinstance(assignment, Assignment) or not isinstance(assignment.node, cst.Name):
                continue
            value = self._bound_value(assignment.node)
            if value is not None and self.is_numpy(value, depth + 1):
                return True
        return False

    def _bound_value(self, target: cst.Name) -> cst.BaseExpression | None:
        parent = self._analysis.parent(target)
        if isinstance(parent, cst.AssignTarget):
            assign = self._analysis.parent(parent)
            return assign.value if isinstance(assign, cst.Assign) else None
        if isinstance(parent, (cst.For, cst.CompFor)) and parent.target is target:
            # ``for seed in np.arange(5)``: the loop variable is an element of the iterable.
            return parent.iter
        if isinstance(parent, cst.AnnAssign):
            return parent.value
        return None


# -- names for info -----------------------------------------------------------------------


class InfoNames:
    """Chooses the name that receives ``info`` in a rewritten ``obs, info = env.reset()``.

    ``info`` (``infos`` for vector envs) is kept when the scope binds it only from env
    results (``..., info = env.step(a)``) and no read of it would now see the reset's
    info instead (a read after the reset with no other env-result binding in between,
    or a read earlier in a loop that also holds the reset). Otherwise ``reset_info``
    (``reset_infos``), then numbered variants, are tried; those must be entirely unused.
    """

    def __init__(self, analysis: ReceiverAnalysis, position_of: PositionOf) -> None:
        self._analysis = analysis
        self._position_of = position_of
        # Names this pass already introduced, per scope (they are not in the metadata).
        self._introduced: dict[int, set[str]] = {}

    def choose(self, scope: Scope | None, reset: cst.CSTNode, base: str) -> str:
        candidates = [base, f"reset_{base}"] + [f"reset_{base}_{n}" for n in range(2, 10)]
        for candidate in candidates:
            if scope is None:
                return candidate
            if candidate == base and self._reusable(scope, reset, candidate):
                break
            if candidate != base and self._unused(scope, candidate):
                break
        self._introduced.setdefault(id(scope), set()).add(candidate)
        return candidate

    def _unused(self, scope: Scope, name: str) -> bool:
        if name in self._introduced.get(id(scope), set()):
            return True
        return name not in scope and not scope.accesses[name] and not scope.assignments[name]

    def _reusable(self, scope: Scope, reset: cst.CSTNode, name: str) -> bool:
        if name in self._introduced.get(id(scope), set()) and not scope.assignments[name]:
            return not scope.accesses[name]
        own = list(scope.assignments[name])
        if not own:
            # Bound only in an enclosing scope (or nowhere): a new local binding would
            # hide the outer one from every read in this scope.
            return not scope.accesses[name]
        env_bindings: list[cst.CSTNode] = []
        for assignment in own:
            statement = self._env_result_binding(assignment)
            if statement is None:
                return False
            env_bindings.append(statement)
        reset_at = self._position_of(reset)
        for access in scope.accesses[name]:
            if not self._covered(access.node, reset, reset_at, env_bindings):
                return False
        return True

    def _env_result_binding(self, assignment: object) -> cst.CSTNode | None:
        """The statement if ``assignment`` is the last target of ``... , info = env.<step|reset|last>(...)``."""
        if not isinstance(assignment, Assignment) or not isinstance(assignment.node, cst.Name):
            return None
        element = self._analysis.parent(assignment.node)
        if not isinstance(element, cst.Element):
            return None
        container = self._analysis.parent(element)
        if not isinstance(container, (cst.Tuple, cst.List)) or container.elements[-1] is not element:
            return None
        holder = self._analysis.parent(container)
        if isinstance(holder, cst.Element):  # ``(obs, info), done = env.reset(), False``
            holder = self._analysis.parent(self._analysis.parent(holder))
        if not isinstance(holder, cst.AssignTarget):
            return None
        assign = self._analysis.parent(holder)
        if not isinstance(assign, cst.Assign):
            return None
        values = assign.value.elements if isinstance(assign.value, cst.Tuple) else [assign.value]
        for value in values:
            value = value.value if isinstance(value, cst.Element) else value
            if (
                isinstance(value, cst.Call)
                and isinstance(value.func, cst.Attribute)
                and value.func.attr.value in ENV_RESULT_METHODS
            ):
                return assign
        return None

    def _covered(
        self,
        read: cst.CSTNode,
        reset: cst.CSTNode,
        reset_at: Position,
        bindings: list[cst.CSTNode],
    ) -> bool:
        """Will ``read`` still see an env-result binding, not the reset's info?"""
        read_at = self._position_of(read)
        binding_positions = [self._position_of(b) for b in bindings]
        if read_at > reset_at:
            return any(reset_at < at < read_at for at in binding_positions)
        # The read comes first in the text; only a loop around both can carry the reset's
        # info back to it, unless a binding inside that loop precedes the read.
        read_loops = enclosing_loops(self._analysis, read)
        reset_loops = {id(loop) for loop in enclosing_loops(self._analysis, reset)}
        common = next((loop for loop in read_loops if id(loop) in reset_loops), None)
        if common is None:
            return True
        loop_at = self._position_of(common)
        return any(loop_at < at < read_at for at in binding_positions)
