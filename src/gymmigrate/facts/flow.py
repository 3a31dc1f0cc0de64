"""Just enough data flow to follow one variable from a statement to its readers.

The step rules need to know, for a name bound by ``obs, r, done, info = env.step(a)``:
which reads of ``done`` can see that value (to decide whether ``done = terminated or
truncated`` is needed), and which reads are certainly *that* value (so rewriting them
to ``terminated`` cannot pick up some other ``done``). Scopes link reads to a name but
not to one assignment, so this module adds a conservative, position-based test on top
of them: a read is *dominated* by a binding when it sits later in the same block (or
in a statement nested there), with no other binding of the name in between and none
inside a loop that would run the read again.

Everything is computed from ``ModuleFacts`` (CPython ``ast`` nodes carry their
positions) and memoized: the reads and the sorted binding positions of a name are
indexed once per scope, so a dominance test costs the depth of the read plus a binary
search, not a walk over the function.
"""

from __future__ import annotations

import ast
from bisect import bisect_left
from collections import defaultdict
from collections.abc import Callable, Iterator

from gymmigrate.facts.module import (
    COMPREHENSIONS,
    FUNCTIONS,
    LOOPS,
    ModuleFacts,
    Scope,
    child_nodes,
)

Position = tuple[int, int]


def start(node: ast.AST) -> Position:
    return (node.lineno, node.col_offset)  # type: ignore[attr-defined]


def end(node: ast.AST) -> Position:
    return (node.end_lineno, node.end_col_offset)  # type: ignore[attr-defined]


def is_after(node: ast.AST, anchor: ast.AST) -> bool:
    """``node`` starts where ``anchor`` has ended (or later)."""
    return start(node) >= end(anchor)


def contains(outer: ast.AST, inner: ast.AST) -> bool:
    return start(outer) <= start(inner) and end(inner) <= end(outer)


_STATEMENT_LISTS = ("body", "orelse", "finalbody")


class Flow:
    """Reads, bindings and dominance over one module's facts. One per file (``Flow.of``)."""

    def __init__(self, facts: ModuleFacts) -> None:
        self.facts = facts
        self._readers: dict[str, list[Scope]] | None = None  # name -> scopes that read it
        self._reads: dict[str, dict[int, list[ast.Name]]] = {}  # name -> binding scope -> reads
        self._binding_starts: dict[tuple[int, str], tuple[list[Position], list[ast.AST]]] = {}
        self._slots: dict[int, dict[int, tuple[str, int]]] = {}  # parent -> statement -> (field, index)
        self._names_in: dict[int, set[str]] = {}

    @classmethod
    def of(cls, facts: ModuleFacts) -> Flow:
        return facts.memo(("flow", id(facts.tree)), lambda: cls(facts))

    # -- scopes ---------------------------------------------------------------------------

    def binding_scope(self, name: ast.Name) -> Scope | None:
        """The scope whose variable ``name`` (a store) binds; None when it is declared
        ``global``/``nonlocal`` there (its readers live in other scopes)."""
        scope = self.facts.scope_of(name)
        if name.id in scope.declared_global or name.id in scope.declared_nonlocal:
            return None
        return scope

    def same_frame(self, read: ast.AST, binding_scope: Scope) -> bool:
        """The read runs in the binding's frame (comprehensions count; nested defs do not)."""
        scope: Scope | None = self.facts.scope_of(read)
        while scope is not None and scope is not binding_scope:
            if not isinstance(scope.node, COMPREHENSIONS):
                return False
            scope = scope.parent
        return scope is binding_scope

    # -- bindings and reads -------------------------------------------------------------

    def bindings(self, name: ast.Name) -> list[ast.AST]:
        """Every node that binds ``name`` in the scope where ``name`` is bound."""
        scope = self.binding_scope(name)
        return list(scope.bindings.get(name.id, ())) if scope is not None else []

    def reads(self, name: ast.Name) -> list[ast.Name]:
        """Every read of the variable ``name`` binds, in its scope and nested scopes, in order."""
        scope = self.binding_scope(name)
        if scope is None or not scope.bindings.get(name.id):
            return []
        by_scope = self._reads.get(name.id)
        if by_scope is None:
            by_scope = self._reads[name.id] = self._index_reads(name.id)
        return by_scope.get(id(scope), [])

    def _index_reads(self, name: str) -> dict[int, list[ast.Name]]:
        if self._readers is None:
            readers: dict[str, list[Scope]] = defaultdict(list)
            for scope in self.facts.scopes.values():
                for read_name in scope.reads:
                    readers[read_name].append(scope)
            self._readers = readers
        found: dict[int, list[ast.Name]] = defaultdict(list)
        for scope in self._readers.get(name, ()):
            bound_in, _ = self.facts.resolve(name, scope)
            if bound_in is not None:
                found[id(bound_in)].extend(scope.reads[name])
        for reads in found.values():
            reads.sort(key=start)
        return found

    def _sorted_bindings(self, scope: Scope, name: str) -> tuple[list[Position], list[ast.AST]]:
        """Every binding of ``name`` in ``scope`` and their start positions, in source order."""
        key = (id(scope), name)
        found = self._binding_starts.get(key)
        if found is None:
            ordered = sorted(scope.bindings.get(name, ()), key=start)
            found = self._binding_starts[key] = ([start(b) for b in ordered], ordered)
        return found

    def last_binding_before(self, read: ast.AST, name: ast.Name) -> ast.AST | None:
        """The binding of ``name``'s variable that starts last before ``read`` ends."""
        scope = self.binding_scope(name)
        return None if scope is None else self._last_in(scope, name.id, read)

    def last_binding_of(self, read: ast.Name) -> ast.AST | None:
        """The binding of the variable ``read`` reads that starts last before the read ends."""
        scope, _ = self.facts.resolve(read.id, self.facts.scope_of(read))
        return None if scope is None else self._last_in(scope, read.id, read)

    def _last_in(self, scope: Scope, name: str, read: ast.AST) -> ast.AST | None:
        starts, ordered = self._sorted_bindings(scope, name)
        index = bisect_left(starts, end(read)) - 1
        return ordered[index] if index >= 0 else None

    def _any_binding_in(self, scope: Scope, name: str, low: Position, high: Position) -> bool:
        starts, _ = self._sorted_bindings(scope, name)
        index = bisect_left(starts, low)
        return index < len(starts) and starts[index] < high

    # -- flow ---------------------------------------------------------------------------

    def observes(self, read: ast.AST, statement: ast.stmt, name: ast.Name) -> bool:
        """Can ``read`` see a value bound by ``statement``? (later in the text, in a loop
        that runs the statement and then comes back to the read, or in a nested function
        that may be called at any time)."""
        if is_after(read, statement) or not self.same_frame(read, self.facts.scope_of(name)):
            return True
        return any(isinstance(a, LOOPS) and contains(a, read) for a in self.facts.ancestors(statement))

    def binding_above(self, read: ast.Name, statement: ast.stmt) -> ast.AST | None:
        """The binding of the variable ``read`` reads that starts last before ``statement``
        starts: what a read in the value of an assignment that rebinds it sees
        (``envs = Wrapper(envs)``), when that binding sits before it in the same block."""
        scope, _ = self.facts.resolve(read.id, self.facts.scope_of(read))
        if scope is None:
            return None
        starts, ordered = self._sorted_bindings(scope, read.id)
        index = bisect_left(starts, start(statement)) - 1
        if index < 0:
            return None
        binding = ordered[index]
        above = self.facts.statement_of(binding)
        holder = self.facts.parent(statement)
        if above is None or holder is None or self.facts.parent(above) is not holder:
            return None
        slots = self._slots_of(holder)
        mine, theirs = slots.get(id(above)), slots.get(id(statement))
        return binding if mine is not None and theirs is not None and mine[0] == theirs[0] and mine[1] < theirs[1] else None

    def dominates(self, statement: ast.stmt, read: ast.AST, name: ast.Name) -> bool:
        """Is ``read`` certain to see the value ``statement`` bound to ``name``?"""
        scope = self.binding_scope(name)
        if scope is None or not self.same_frame(read, scope) or not is_after(read, statement):
            return False
        if not self._follows_in_block(statement, read):
            return False
        # Bindings inside ``statement`` start before it ends, so they are never "between".
        if self._any_binding_in(scope, name.id, end(statement), end(read)):
            return False  # rebound between the statement and the read
        for loop in self.facts.ancestors(read):
            if isinstance(loop, LOOPS) and not contains(loop, statement):
                if self._any_binding_in(scope, name.id, start(loop), end(loop)):
                    return False  # rebound later in a loop that runs the read again
        return True

    def may_run_before(self, first: ast.AST, second: ast.AST, function: ast.AST) -> bool:
        """In one call of ``function``, ``first`` may run before ``second``: it comes earlier
        in the text, or a loop of the function runs both and comes round to ``second`` again
        after ``first``; never from the other arm of an ``if``/``match``/``except`` that
        ``second`` is in, nor where a ``return``/``raise`` after ``first`` leaves before
        ``second`` is reached (a ``break`` of that loop too, for the loop's next turn)."""
        facts = self.facts
        above_first = {id(a) for a in facts.ancestors(first)}
        common = next((a for a in facts.ancestors(second) if id(a) in above_first), None)
        if common is None or not contains(function, common):
            return False
        if _alternatives(common, _child_toward(facts, common, first), _child_toward(facts, common, second)):
            return False
        if start(first) < start(second) and not self._leaves(first, common, (ast.Return, ast.Raise), before=second):
            return True
        for loop in [common, *facts.ancestors(common)]:
            if loop is function or not contains(function, loop):
                break
            if (
                isinstance(loop, LOOPS)
                and any(contains(s, first) for s in loop.body)
                and any(contains(s, second) for s in loop.body)
                and not self._leaves(first, loop, (ast.Return, ast.Raise, ast.Break))
            ):
                return True
        return False

    def always_before(self, first: ast.AST, second: ast.AST) -> bool:
        """Wherever ``second`` runs, ``first`` has run before it: ``first`` is evaluated
        whenever its statement runs (not in one arm of a conditional value or of ``and``/
        ``or``, nor in a comprehension or lambda), and ``second`` sits in a later statement of
        the same block."""
        statement = self.facts.statement_of(first)
        child = first
        for ancestor in self.facts.ancestors(first):
            if ancestor is statement:
                break
            if isinstance(ancestor, (ast.Lambda, *COMPREHENSIONS)):
                return False
            if isinstance(ancestor, ast.IfExp) and child is not ancestor.test:
                return False
            if isinstance(ancestor, ast.BoolOp) and child is not ancestor.values[0]:
                return False
            child = ancestor
        return self._follows_in_block(statement, second)

    def _leaves(self, node: ast.AST, outer: ast.AST, exits: tuple[type[ast.stmt], ...], before: ast.AST | None = None) -> bool:
        """Below ``outer``, a statement of an ``exits`` kind follows ``node`` in a block that
        holds it (or is ``node``'s own statement), ahead of ``before`` when given: the run
        never gets from ``node`` past that block. A ``break`` counts only where it leaves
        ``outer`` (no loop nearer)."""
        for ancestor in [node, *self.facts.ancestors(node)]:
            if ancestor is outer:
                return False
            if not isinstance(ancestor, ast.stmt):
                continue
            loop = next((a for a in self.facts.ancestors(ancestor) if isinstance(a, LOOPS)), None)
            kinds = tuple(k for k in exits if k is not ast.Break or loop is outer)
            block = self.block_of(ancestor)
            later = [s for s in block[0][block[1] + 1 :] if before is None or end(s) <= start(before)] if block is not None else []
            if isinstance(ancestor, kinds) or any(isinstance(s, kinds) for s in later):
                return True
        return False
    def left_by_loop(self, statement: ast.stmt, read: ast.Name) -> bool:
        """Is ``read`` certain to see the value ``statement`` bound, the last one of a loop
        around ``statement`` that the read comes after? That holds when no other binding of the
        name can reach the read: a loop may run no time at all, so a binding above the loop
        (``done = False``) reaches the read as well, and the loop's last value is then one of
        two. Without one, a loop that never ran leaves the name unbound: the read fails
        rather than see anything else."""
        if not any(isinstance(loop, LOOPS) and is_after(read, loop) for loop in self.facts.ancestors(statement)):
            return False
        reaching = self.reaching(read)
        return bool(reaching) and all(contains(statement, binding) for binding in reaching or ())

    def reaching(self, read: ast.Name) -> list[ast.AST] | None:
        """The bindings of the variable ``read`` reads whose value may reach it: not those
        the read cannot observe (later in the text, outside any loop around the read), nor
        those a later assignment of the same block overwrites before the read (``env =
        lib.make(...)`` then ``env = Wrapper(env)``). None when a binding is not a plain name
        of the read's own frame (a parameter, a global of a nested def): no positional answer."""
        scope, bindings = self.facts.resolve(read.id, self.facts.scope_of(read))
        if scope is None or not self.same_frame(read, scope):
            return None
        found: list[ast.AST] = []
        for binding in bindings:
            statement = self.facts.statement_of(binding) if isinstance(binding, ast.Name) else None
            if statement is None:
                return None
            if not self.observes(read, statement, binding):  # type: ignore[arg-type]
                continue
            if is_after(read, statement) and self._overwritten(statement, read):
                continue
            found.append(binding)
        return found

    def source_of(self, read: ast.Name) -> str | None:
        """The variable ``read`` reads, as text that is the same for every read that can see
        only the same bindings of it: its name and where those bindings are (``env@12:4,15:4``).
        Two calls that hand on reads with one source pass the same values. The bindings that
        reach the read where the flow tells them apart (``reaching``), else every binding of
        the variable (a read in a nested def). None for a name nothing here binds."""
        bindings = self.reaching(read)
        if not bindings:
            bindings = self.facts.bindings_of(read)
        if not bindings:
            return None
        return f"{read.id}@" + ",".join(f"{line}:{column}" for line, column in sorted(start(b) for b in bindings))

    def _overwritten(self, statement: ast.stmt, read: ast.Name) -> bool:
        """A later statement of ``statement``'s block assigns ``read``'s name unconditionally
        before the read runs (the read is not in it, nor in a loop that returns above it)."""
        block = self.block_of(statement)
        if block is None or any(isinstance(a, LOOPS) and contains(a, statement) and contains(a, read) for a in self.facts.ancestors(read)):
            return False
        statements, index = block
        for later in statements[index + 1 :]:
            if contains(later, read) or not is_after(read, later):
                return False
            if isinstance(later, ast.Assign) and any(isinstance(t, ast.Name) and t.id == read.id for t in later.targets):
                return True
        return False

    def _follows_in_block(self, statement: ast.stmt, read: ast.AST) -> bool:
        """``read`` sits in a statement after ``statement`` in the same statement list."""
        holder = self.facts.parent(statement)
        if holder is None:
            return False
        slots = self._slots_of(holder)
        mine = slots.get(id(statement))
        node: ast.AST | None = read
        while node is not None:
            parent = self.facts.parent(node)
            if parent is holder:
                theirs = slots.get(id(node))
                return theirs is not None and mine is not None and theirs[0] == mine[0] and theirs[1] > mine[1]
            node = parent
        return False

    def block_of(self, statement: ast.stmt) -> tuple[list[ast.stmt], int] | None:
        """The statement list that holds ``statement`` (a body, an else, a finally) and its
        index there; None for a statement of no such list."""
        holder = self.facts.parent(statement)
        slot = self._slots_of(holder).get(id(statement)) if holder is not None else None
        if slot is None:
            return None
        field, index = slot
        return getattr(holder, field), index

    def _slots_of(self, holder: ast.AST) -> dict[int, tuple[str, int]]:
        slots = self._slots.get(id(holder))
        if slots is None:
            slots = {}
            for field in _STATEMENT_LISTS:
                for index, item in enumerate(getattr(holder, field, None) or ()):
                    if isinstance(item, ast.stmt):
                        slots[id(item)] = (field, index)
            self._slots[id(holder)] = slots
        return slots

    # -- names ----------------------------------------------------------------------------

    def names_used_in(self, scope: Scope) -> set[str]:
        """Identifiers that mean something in ``scope``: its own names, attribute and
        keyword names spelled there, and names that nested functions spell without binding
        them (they may refer to ``scope``'s). A nested function's own locals do not count:
        binding the same name here is safe."""
        taken = self._names_in.get(id(scope))
        if taken is not None:
            return taken
        facts = self.facts
        taken = set()
        stack: list[tuple[ast.AST, Scope]] = [(scope.node, scope)]
        while stack:
            node, around = stack.pop()
            for identifier, where in _identifiers(node, around, facts):
                if where is None or where is scope or identifier not in where.bindings:
                    taken.add(identifier)
            inner = facts.scopes.get(node, around) if node is not scope.node else scope
            stack.extend((child, inner) for child in child_nodes(node))
        self._names_in[id(scope)] = taken
        return taken


def _identifiers(node: ast.AST, around: Scope, facts: ModuleFacts) -> Iterator[tuple[str, Scope | None]]:
    """The identifiers ``node`` spells itself, each with the scope it belongs to (None: no scope)."""
    if isinstance(node, ast.Name):
        yield node.id, facts.scope_of(node)
    elif isinstance(node, ast.Attribute):
        yield node.attr, around
    elif isinstance(node, ast.arg):
        yield node.arg, facts.scope_of(node)
    elif isinstance(node, (*FUNCTIONS, ast.ClassDef)):
        yield node.name, facts.scope_of(node)
    elif isinstance(node, ast.keyword) and node.arg is not None:
        yield node.arg, None
    elif isinstance(node, ast.alias):
        for part in node.name.split("."):
            yield part, around
        if node.asname:
            yield node.asname, around
    elif isinstance(node, ast.ExceptHandler) and node.name:
        yield node.name, facts.scope_of(node)
    elif isinstance(node, (ast.Global, ast.Nonlocal)):
        for name in node.names:
            yield name, around


def _child_toward(facts: ModuleFacts, holder: ast.AST, node: ast.AST) -> ast.AST:
    """The child of ``holder`` that ``node`` sits in (``node`` itself when it is one)."""
    return next((a for a in [node, *facts.ancestors(node)] if facts.parent(a) is holder), node)


def _alternatives(holder: ast.AST, one: ast.AST, other: ast.AST) -> bool:
    """``one`` and ``other`` (children of ``holder``) sit in arms of ``holder`` of which one
    call runs one at most: the body and the else of an ``if`` (or of a conditional value),
    two handlers of a ``try`` (or a handler and its else), two cases of a ``match``."""
    if isinstance(holder, (ast.If, ast.IfExp)):
        arms: list[list[ast.AST]] = [_as_list(holder.body), _as_list(holder.orelse)]
    elif isinstance(holder, _TRIES):
        arms = [[handler] for handler in holder.handlers] + [list(holder.orelse)]  # type: ignore[attr-defined]
    elif _MATCH is not None and isinstance(holder, _MATCH):
        arms = [[case] for case in holder.cases]  # type: ignore[attr-defined]
    else:
        return False
    one_arm = next((i for i, arm in enumerate(arms) if any(item is one for item in arm)), None)
    other_arm = next((i for i, arm in enumerate(arms) if any(item is other for item in arm)), None)
    return one_arm is not None and other_arm is not None and one_arm != other_arm


def _as_list(arm: ast.AST | list[ast.stmt]) -> list[ast.AST]:
    return list(arm) if isinstance(arm, list) else [arm]


_TRIES: tuple[type[ast.AST], ...] = tuple(t for t in (ast.Try, getattr(ast, "TryStar", None)) if t is not None)
_MATCH: type[ast.AST] | None = getattr(ast, "Match", None)


def bound_names(target: ast.AST) -> set[str]:
    """Names a target binds: ``a``, ``a, (b, *c)``; attributes and subscripts bind none."""
    if isinstance(target, ast.Name):
        return {target.id}
    if isinstance(target, (ast.Tuple, ast.List)):
        return {name for element in target.elts for name in bound_names(element)}
    if isinstance(target, ast.Starred):
        return bound_names(target.value)
    return set()


def bound_on_every_path(
    function: ast.FunctionDef | ast.AsyncFunctionDef,
    target: ast.stmt,
    names: frozenset[str],
    binds: Callable[[ast.stmt], frozenset[str]],
) -> frozenset[str] | None:
    """Which of ``names`` every path from the start of ``function`` to ``target`` binds:
    a plain binding of the statements on the way, or what ``binds`` says a statement will
    bind once rewritten (an inner step unpack binds the flags). An ``if`` binds what both
    arms bind, a ``try``'s handlers only what was bound before it. A loop's body counts as
    run (a name it binds counts as bound after it, as the legacy names it binds do: a loop
    that never runs leaves those unbound alike), ended at any ``break``. None where no
    path reaches ``target``."""
    walker = _MustBind(target, names, binds)
    walker.block(function.body, frozenset())
    return walker.found


class _MustBind:
    """The walk ``bound_on_every_path`` makes: a state is the set of names bound on every
    path so far, None where no path runs on (after a ``return``, ``raise``, ``break``)."""

    def __init__(self, target: ast.stmt, names: frozenset[str], binds: Callable[[ast.stmt], frozenset[str]]) -> None:
        self.target, self.names, self.binds = target, names, binds
        self.found: frozenset[str] | None = None
        self.breaks: list[list[frozenset[str]]] = []

    def block(self, statements: list[ast.stmt], state: frozenset[str] | None) -> frozenset[str] | None:
        for statement in statements:
            if state is None:
                return None
            state = self.statement(statement, state)
        return state

    def statement(self, statement: ast.stmt, state: frozenset[str]) -> frozenset[str] | None:
        if statement is self.target:
            self.found = state if self.found is None else self.found & state
        state = state | (self.binds(statement) & self.names)
        if isinstance(statement, (ast.Return, ast.Raise, ast.Continue)):
            return None
        if isinstance(statement, ast.Break):
            if self.breaks:
                self.breaks[-1].append(state)
            return None
        if isinstance(statement, ast.If):
            return _meet(self.block(statement.body, state), self.block(statement.orelse, state))
        if isinstance(statement, LOOPS):
            if isinstance(statement, (ast.For, ast.AsyncFor)):
                state = state | (bound_names(statement.target) & self.names)
            self.breaks.append([])
            ran = self.block(statement.body, state)
            broken = self.breaks.pop()
            out = self.block(statement.orelse, ran) if ran is not None else None
            for left in broken:
                out = _meet(out, left)
            return out
        if isinstance(statement, (ast.With, ast.AsyncWith)):
            for item in statement.items:
                if item.optional_vars is not None:
                    state = state | (bound_names(item.optional_vars) & self.names)
            return self.block(statement.body, state)
        if isinstance(statement, _TRIES):
            ran = self.block(statement.body, state)  # type: ignore[attr-defined]
            out = self.block(statement.orelse, ran) if ran is not None else None  # type: ignore[attr-defined]
            for handler in statement.handlers:  # type: ignore[attr-defined]
                out = _meet(out, self.block(handler.body, state))
            final = statement.finalbody  # type: ignore[attr-defined]
            if final:
                self.block(final, state)  # the target there: reached after the body or a handler
                return self.block(final, out) if out is not None else None
            return out
        if _MATCH is not None and isinstance(statement, _MATCH):
            matched: frozenset[str] | None = state  # no case may match
            for case in statement.cases:  # type: ignore[attr-defined]
                matched = _meet(matched, self.block(case.body, state))
            return matched
        if isinstance(statement, (*FUNCTIONS, ast.ClassDef)):
            return state | (frozenset({statement.name}) & self.names)
        return state | (_plain_bindings(statement) & self.names)


def _meet(one: frozenset[str] | None, other: frozenset[str] | None) -> frozenset[str] | None:
    if one is None:
        return other
    if other is None:
        return one
    return one & other


def _plain_bindings(statement: ast.stmt) -> frozenset[str]:
    """Names a simple statement binds: assignments' targets, walrus names, imports."""
    found: set[str] = set()
    stack: list[ast.AST] = [statement]
    while stack:
        node = stack.pop()
        if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            found.add(node.id)
        elif isinstance(node, ast.alias):
            found.add((node.asname or node.name).split(".")[0])
        if not isinstance(node, (ast.Lambda, *COMPREHENSIONS)):  # their names are their own
            stack.extend(ast.iter_child_nodes(node))
    return frozenset(found)
