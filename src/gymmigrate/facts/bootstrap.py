"""Which parameters of a def mask bootstrapping from which others.

``agent.append_sample(state, action, reward, next_state, done)`` or
``agent.train_model(state, action, reward, next_state, done)``: the call site alone does
not say what the flag is for. The callee does, when it stores the flag beside the next
state (``self.memory.append((state, action, reward, next_state, done))``) or computes a
target from the next state that the flag masks (``target = reward if done else reward +
gamma * value(next_state)``, ``next_v = zeros if done else self.forward(new_states)``,
``(1 - done) * v(next_state)``). Then the flag masks bootstrapping from the next state,
and GM302 passes ``terminated`` there.

Pure: one def's ``ast`` in, pairs ``(flag parameter, next-state parameter)`` out, read
from the body alone. The summary of a module (``facts/summaries/``) records them per
def, so a caller in another module of the run can ask (``ProjectView.bootstrap_masks``).
"""

from __future__ import annotations

import ast

from gymmigrate.facts.done_uses import (
    DISPLAY_FUNCTIONS,
    DISPLAY_METHODS,
    multiplies_bare,
)
from gymmigrate.facts.module import FUNCTIONS, full_name, walk

Masks = frozenset[tuple[str, str]]
_LEAVES = (ast.Return, ast.Break, ast.Continue, ast.Raise)


def next_state_masks(function: ast.FunctionDef | ast.AsyncFunctionDef) -> Masks:
    """``(flag, next_state)`` parameter pairs: in the body, ``flag`` masks a value computed
    from (or a transition that stores) ``next_state``. A flag rebound in the body, or tested
    by a branch that leaves (``if done: return``), is loop control, not a mask.

    Every def of every module of a run is asked, so the body is walked once and each node's
    reads are computed once, whatever the number of parameters."""
    params = [a.arg for a in (*function.args.posonlyargs, *function.args.args, *function.args.kwonlyargs)]
    params = [p for p in params if p not in ("self", "cls")]
    if len(params) < 2:
        return frozenset()
    body = _Body(function)
    rebound = body.stored
    flags = [p for p in params if p not in rebound and p in body.tested_or_valued]
    if not flags:
        return frozenset()
    found: set[tuple[str, str]] = set()
    for next_param in params:
        if next_param not in body.loaded:
            continue
        derived = body.derived(next_param)
        for flag in flags:
            if flag == next_param or flag in derived:
                continue
            if body.masks(flag, derived):
                found.add((flag, next_param))
    return frozenset(found)


def next_state_factors(function: ast.FunctionDef | ast.AsyncFunctionDef) -> Masks:
    """``(flag, next_state)`` parameter pairs where ``flag`` is only ever a bare factor of a
    value computed from ``next_state`` (``reward + gamma * q(next_state) * done``): an
    inverted mask, which bootstraps only at the episode's end (``_Body._only_factor``)."""
    params = [a.arg for a in (*function.args.posonlyargs, *function.args.args, *function.args.kwonlyargs)]
    params = [p for p in params if p not in ("self", "cls")]
    body = _Body(function)
    found: set[tuple[str, str]] = set()
    for next_param in params:
        derived = body.derived(next_param)
        for flag in params:
            if flag == next_param or flag in derived or flag in body.stored:
                continue
            values = [node for node, kind, reads in body.checks if kind == "value" and flag in reads and reads & derived]
            if values and all(body._only_factor(node, flag) for node in values):
                found.add((flag, next_param))
    return frozenset(found)


class _Body:
    """One def's own nodes (nested defs and lambdas left out), with their reads."""

    def __init__(self, function: ast.AST) -> None:
        self.nodes = list(_walk_own(function))
        self.stored = {
            n.id for n in self.nodes if isinstance(n, ast.Name) and isinstance(n.ctx, (ast.Store, ast.Del))
        }
        self.loaded = {n.id for n in self.nodes if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load)}
        self.assigns = [
            (n, _loads(n.value)) for n in self.nodes if isinstance(n, (ast.Assign, ast.AnnAssign)) and n.value is not None
        ]
        # (node, kind, reads): the tests and the stored values ``masks`` looks at
        self.checks: list[tuple[ast.AST, str, set[str]]] = []
        for node in self.nodes:
            if isinstance(node, (ast.If, ast.IfExp)):
                self.checks.append((node, "test", _loads(node.test)))
            elif isinstance(node, (ast.Assign, ast.AugAssign, ast.Expr)) and not _displays(node.value):
                self.checks.append((node, "value", _value_loads(node.value)))
        self.tested_or_valued = set().union(*(reads for _, _, reads in self.checks)) if self.checks else set()
        self._branch_loads: dict[int, list[set[str]]] = {}
        # ``next_state_factors`` asks ``_only_factor`` of the same value for every parameter
        # pair: the answer depends only on the value and the flag, the parents only on the value.
        self._factor_only: dict[tuple[int, str], bool] = {}
        self._value_parents: dict[int, dict[int, ast.AST]] = {}

    def derived(self, name: str) -> set[str]:
        """``name`` and the names assigned from it (``next_value = critic(next_state)``),
        followed until nothing new is found."""
        derived = {name}
        changed = True
        while changed:
            changed = False
            for assign, reads in self.assigns:
                if reads & derived:
                    targets = assign.targets if isinstance(assign, ast.Assign) else [assign.target]
                    for target in targets:
                        if isinstance(target, ast.Name) and target.id not in derived:
                            derived.add(target.id)
                            changed = True
        return derived

    def masks(self, flag: str, derived: set[str]) -> bool:
        if any(
            kind == "test" and flag in reads and isinstance(node, ast.If) and _starts_afresh(node)
            for node, kind, reads in self.checks
        ):
            # ``if done: ...; self.window = deque(maxlen=n)``: the flag also ends per-episode
            # state, an episode boundary a time-limit truncation must still reach; whatever
            # else it masks, ``terminated`` there would carry that state into the next episode.
            return False
        for node, kind, reads in self.checks:
            if flag not in reads:
                continue
            if kind == "test":
                branches = [node.body, node.orelse] if isinstance(node, ast.IfExp) else [*node.body, *node.orelse]  # type: ignore[attr-defined]
                if isinstance(node, ast.If) and any(isinstance(n, _LEAVES) for s in branches for n in walk(s)):
                    return False  # ``if done: return``: the flag ends something, it is control
                loads = self._branch_loads.get(id(node))
                if loads is None:
                    loads = self._branch_loads[id(node)] = [_loads(branch) for branch in branches]
                if any(branch & derived for branch in loads):
                    return True
            elif reads & derived and not self._only_factor(node, flag):
                return True  # ``memory.append((s, a, r, next_state, done))``, ``(1 - done) * v(next_state)``
        return False


    def _only_factor(self, node: ast.AST, flag: str) -> bool:
        """Every read of ``flag`` in this value is a bare factor (``q * gamma * done``): an
        inverted mask (``done_uses.multiplies_bare``), not one to pass ``terminated`` to."""
        key = (id(node), flag)
        found = self._factor_only.get(key)
        if found is None:
            found = self._factor_only[key] = self._compute_only_factor(node, flag)
        return found

    def _compute_only_factor(self, node: ast.AST, flag: str) -> bool:
        parents = self._value_parents.get(id(node))
        if parents is None:
            parents = self._value_parents[id(node)] = {
                id(child): parent for parent in walk(node) for child in ast.iter_child_nodes(parent)
            }
        reads = [n for n in walk(node) if isinstance(n, ast.Name) and n.id == flag and isinstance(n.ctx, ast.Load)]
        return bool(reads) and all(multiplies_bare(n, lambda child: parents.get(id(child))) for n in reads)


# Calls that build an empty container when given no elements (``deque(maxlen=n)``).
_EMPTY_CONTAINERS = frozenset({"list", "dict", "set", "deque", "OrderedDict", "defaultdict"})


def episode_flushes(function: ast.FunctionDef | ast.AsyncFunctionDef, flag: str) -> list[ast.If]:
    """The branches of ``function``'s own body that test ``flag`` and empty state kept
    across calls (``if done: ...; self.window = deque(maxlen=n)``): there the flag is the
    episode boundary, whatever else it masks."""
    return [
        node
        for node in _walk_own(function)
        if isinstance(node, ast.If) and flag in _loads(node.test) and _starts_afresh(node)
    ]


def _starts_afresh(branch: ast.If) -> bool:
    """A branch of ``branch`` empties state kept across calls: rebinds an attribute to an
    empty container (``self.window = deque(maxlen=n)``, ``self.rewards = []``) or clears
    one (``self.window.clear()``). A local name emptied is left out: it may be scratch."""
    for statement in [*branch.body, *branch.orelse]:
        for node in walk(statement):
            if isinstance(node, ast.Assign) and any(isinstance(t, ast.Attribute) for t in node.targets) and _empty(node.value):
                return True
            if (
                isinstance(node, ast.Call)
                and isinstance(node.func, ast.Attribute)
                and node.func.attr == "clear"
                and isinstance(node.func.value, ast.Attribute)
                and not node.args
            ):
                return True
    return False


def _empty(value: ast.expr) -> bool:
    """``[]``, ``{}``, ``()``, ``deque(maxlen=n)``, ``list()``: a container with no elements."""
    if isinstance(value, (ast.List, ast.Tuple, ast.Set)):
        return not value.elts
    if isinstance(value, ast.Dict):
        return not value.keys
    if isinstance(value, ast.Call) and not value.args:
        return (full_name(value.func) or "").rsplit(".", 1)[-1] in _EMPTY_CONTAINERS
    return False


def _walk_own(function: ast.AST):
    """The nodes of ``function``'s body, nested defs and lambdas left out."""
    stack = list(ast.iter_child_nodes(function))
    while stack:
        node = stack.pop()
        if isinstance(node, (*FUNCTIONS, ast.Lambda, ast.ClassDef)):
            continue
        yield node
        stack.extend(ast.iter_child_nodes(node))


def _loads(node: ast.AST) -> set[str]:
    return {n.id for n in walk(node) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load)}


def _displays(value: ast.AST) -> bool:
    """``print(next_state, done)``, ``logger.info(...)``: shown, not stored."""
    if not isinstance(value, ast.Call):
        return False
    last = (full_name(value.func) or "").rsplit(".", 1)[-1]
    return last in (DISPLAY_METHODS if isinstance(value.func, ast.Attribute) else DISPLAY_FUNCTIONS)


def _value_loads(node: ast.AST) -> set[str]:
    """Names read as values, not as tests (``x if done else y`` reads ``done`` as a test)."""
    names: set[str] = set()
    stack = [node]
    while stack:
        current = stack.pop()
        if isinstance(current, ast.IfExp):
            stack.extend([current.body, current.orelse])
            continue
        if isinstance(current, ast.Name) and isinstance(current.ctx, ast.Load):
            names.add(current.id)
        stack.extend(ast.iter_child_nodes(current))
    return names
