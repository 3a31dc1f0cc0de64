"""Just enough data flow to follow one variable from a statement to its readers.

The step rules need to know, for a name bound by ``obs, r, done, info = env.step(a)``:
which reads of ``done`` can see that value (to decide whether ``done = terminated or
truncated`` is needed), and which reads are certainly *that* value (so rewriting them
to ``terminated`` cannot pick up some other ``done``). LibCST's scope analysis links
reads to names but not to one assignment, so this module adds a conservative,
position-based test on top of it: a read is *dominated* by a binding when it sits later
in the same block (or in a statement nested there), with no other binding of the name
in between and none inside a loop that would run the read again.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping

import libcst as cst
from libcst.metadata import (
    Assignment,
    CodeRange,
    ComprehensionScope,
    ParentNodeProvider,
    PositionProvider,
    Scope,
    ScopeProvider,
)

LOOPS = (cst.For, cst.While)


class Flow:
    """Position and scope queries over one module's metadata."""

    def __init__(self, metadata: Mapping[type, Mapping[cst.CSTNode, object]]) -> None:
        self._positions = metadata[PositionProvider]
        self._parents = metadata[ParentNodeProvider]
        self._scopes = metadata[ScopeProvider]
        self._names_in: dict[int, set[str]] = {}

    # -- basic queries ---------------------------------------------------------------

    def parent(self, node: cst.CSTNode) -> cst.CSTNode | None:
        return self._parents.get(node)  # type: ignore[return-value]

    def ancestors(self, node: cst.CSTNode) -> Iterator[cst.CSTNode]:
        current = self.parent(node)
        while current is not None:
            yield current
            current = self.parent(current)

    def span(self, node: cst.CSTNode) -> CodeRange:
        return self._positions[node]  # type: ignore[return-value]

    def line(self, node: cst.CSTNode) -> int:
        return self.span(node).start.line

    def scope(self, node: cst.CSTNode) -> Scope | None:
        return self._scopes.get(node)  # type: ignore[return-value]

    def is_after(self, node: cst.CSTNode, anchor: cst.CSTNode) -> bool:
        return _key(self.span(node).start) >= _key(self.span(anchor).end)

    def contains(self, outer: cst.CSTNode, inner: cst.CSTNode) -> bool:
        o, i = self.span(outer), self.span(inner)
        return _key(o.start) <= _key(i.start) and _key(i.end) <= _key(o.end)

    # -- bindings and reads ------------------------------------------------------------

    def bindings(self, name: cst.Name) -> list[cst.CSTNode]:
        """Every node that binds ``name`` in the scope where ``name`` is bound."""
        scope = self.scope(name)
        if scope is None:
            return []
        return [a.node for a in scope.assignments[name.value] if isinstance(a, Assignment)]

    def reads(self, name: cst.Name) -> list[cst.Name]:
        """Every read of the variable ``name`` binds, in its scope and nested scopes."""
        scope = self.scope(name)
        if scope is None:
            return []
        found: dict[int, cst.Name] = {}
        for assignment in scope.assignments[name.value]:
            if not isinstance(assignment, Assignment):
                continue
            for access in assignment.references:
                if isinstance(access.node, cst.Name):
                    found[id(access.node)] = access.node
        return sorted(found.values(), key=lambda n: _key(self.span(n).start))

    def same_frame(self, read: cst.CSTNode, binding_scope: Scope) -> bool:
        """The read runs in the binding's frame (comprehensions count; nested defs do not)."""
        scope = self.scope(read)
        while scope is not None and scope is not binding_scope:
            if not isinstance(scope, ComprehensionScope):
                return False
            scope = scope.parent
        return scope is binding_scope

    def observes(self, read: cst.CSTNode, statement: cst.CSTNode, name: cst.Name) -> bool:
        """Can ``read`` see a value bound by ``statement``? (later in the text, in a loop
        that runs the statement and then comes back to the read, or in a nested function
        that may be called at any time)."""
        scope = self.scope(name)
        if self.is_after(read, statement) or (scope is not None and not self.same_frame(read, scope)):
            return True
        return any(isinstance(a, LOOPS) and self.contains(a, read) for a in self.ancestors(statement))

    def dominates(self, statement: cst.BaseSmallStatement, read: cst.CSTNode, name: cst.Name) -> bool:
        """Is ``read`` certain to see the value ``statement`` bound to ``name``?"""
        scope = self.scope(name)
        if scope is None or not self.same_frame(read, scope) or not self.is_after(read, statement):
            return False
        if not self._follows_in_block(statement, read):
            return False
        others = [b for b in self.bindings(name) if not self.contains(statement, b)]
        for other in others:
            if self.is_after(other, statement) and not self.is_after(other, read):
                return False  # rebound between the statement and the read
        for loop in self.ancestors(read):
            if isinstance(loop, LOOPS) and not self.contains(loop, statement):
                if any(self.contains(loop, other) for other in others):
                    return False  # rebound later in a loop that runs the read again
        return True

    def _follows_in_block(self, statement: cst.BaseSmallStatement, read: cst.CSTNode) -> bool:
        line = self.parent(statement)
        if line is None:
            return False
        # Later in the same ``a; b; c`` list (a one-line suite or a simple line).
        for ancestor in [read, *self.ancestors(read)]:
            if self.parent(ancestor) is line:
                return True
        if not isinstance(line, cst.SimpleStatementLine):
            return False  # a one-line suite: later statements are outside its block
        block = self.parent(line)
        if not isinstance(block, (cst.IndentedBlock, cst.Module)):
            return False
        for ancestor in self.ancestors(read):
            if self.parent(ancestor) is block:
                return self.is_after(ancestor, line)
        return False

    # -- names ---------------------------------------------------------------------------

    def names_used_in(self, scope: Scope, scope_node: cst.CSTNode) -> set[str]:
        """Identifiers that mean something in ``scope``: its own names, and names that
        nested functions spell without binding them (they may refer to ``scope``'s).
        A nested function's own locals do not count: binding the same name here is safe."""
        key = id(scope_node)
        if key not in self._names_in:
            collector = _NameCollector()
            scope_node.visit(collector)
            taken = set()
            for name in collector.nodes:
                where = self.scope(name)
                if where is None or where is scope or not where.assignments[name.value]:
                    taken.add(name.value)
            self._names_in[key] = taken
        return self._names_in[key]


def _key(position: object) -> tuple[int, int]:
    return (position.line, position.column)  # type: ignore[attr-defined]


class _NameCollector(cst.CSTVisitor):
    def __init__(self) -> None:
        self.nodes: list[cst.Name] = []

    def visit_Name(self, node: cst.Name) -> None:
        self.nodes.append(node)


METADATA = (PositionProvider, ParentNodeProvider, ScopeProvider)
