"""What the readers of a stored done flag do with it (GM302).

A flag stored beside the next observation (``memories.append(Memory(obs, new_obs, r,
done, v))``, ``self.buffer.append((s, a, s2, r, done))``) looks like a replay transition,
whose flag masks bootstrapping from that observation: ``terminated``. But the code that
reads the record back says what the flag is for. ``(1 - done) * gamma * v(s2)`` or
``if not done: y += gamma * q(s2)`` masks a next-state value (``terminated``). ``if done:
break`` cuts an n-step sum, and ``if m[t].done: ... else: ... m[t + 1].value`` takes the
next value from the neighbouring record, which after a reset is the next episode: there
the flag is the episode boundary, ``terminated or truncated`` as legacy ``done`` was.

Pure: the module's ``ast`` in, the readers' uses out. Only readers the module shows are
found (a field read ``rec.done``, an unpack or index of the same store); none found means
nothing is known.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
from typing import Literal

from gymmigrate.facts.done_uses import STORE_METHODS, DoneUse, classify_done_read
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts, full_name, walk

ReaderUse = Literal["boundary", "mask"]
_LEAVES = (ast.Break, ast.Return, ast.Continue, ast.Raise)


@dataclass(frozen=True)
class Reader:
    node: ast.expr  # the read of the stored flag
    use: ReaderUse


def stored_flag_readers(value: ast.expr, facts: ModuleFacts) -> list[Reader]:
    """The readers of the flag ``value`` (a read of a name) stores, when ``value`` is a
    field of a record of this module (``Memory(..., done=done)``) or an element of a tuple
    handed to a store method (``buffer.append((s, a, r, s2, done))``). Display reads are
    left out; an empty list: no reader is visible."""
    holder = facts.parent(value)
    if isinstance(holder, ast.keyword):
        call = facts.parent(holder)
        if isinstance(call, ast.Call) and holder.arg is not None and _record_fields(call.func, facts) is not None:
            return _field_readers(holder.arg, facts)
        return []
    if isinstance(holder, ast.Call) and value in holder.args and not any(isinstance(a, ast.Starred) for a in holder.args):
        fields = _record_fields(holder.func, facts)
        index = holder.args.index(value)
        if fields is not None and index < len(fields):
            return _field_readers(fields[index], facts)
        return []
    if isinstance(holder, (ast.Tuple, ast.List)) and not any(isinstance(e, ast.Starred) for e in holder.elts):
        call = facts.parent(holder)
        if (
            isinstance(call, ast.Call)
            and call.args == [holder]
            and isinstance(call.func, ast.Attribute)
            and call.func.attr in STORE_METHODS
            and (store := full_name(call.func.value))
        ):
            index = holder.elts.index(value)
            scope: ast.AST = facts.tree
            if store.startswith("self."):
                scope = facts.enclosing_class(call) or facts.tree
            return _tuple_readers(store, index, len(holder.elts), scope, facts)
    return []


def _record_fields(func: ast.expr, facts: ModuleFacts) -> list[str] | None:
    """The fields, in order, of the record class ``func`` names: a ``namedtuple`` with literal
    fields, or a ``NamedTuple``/``@dataclass`` class of this module. None: not such a record."""
    if not isinstance(func, ast.Name):
        return None
    for node in walk(facts.tree):
        if (
            isinstance(node, ast.Assign)
            and any(isinstance(t, ast.Name) and t.id == func.id for t in node.targets)
            and isinstance(node.value, ast.Call)
            and (full_name(node.value.func) or "").rsplit(".", 1)[-1] == "namedtuple"
            and len(node.value.args) >= 2
        ):
            fields = node.value.args[1]
            if isinstance(fields, ast.Constant) and isinstance(fields.value, str):
                return fields.value.replace(",", " ").split()
            if isinstance(fields, (ast.List, ast.Tuple)) and all(
                isinstance(e, ast.Constant) and isinstance(e.value, str) for e in fields.elts
            ):
                return [e.value for e in fields.elts]  # type: ignore[attr-defined]
            return None
        if isinstance(node, ast.ClassDef) and node.name == func.id:
            record = any((full_name(b) or "").rsplit(".", 1)[-1] == "NamedTuple" for b in node.bases) or any(
                (full_name(d.func if isinstance(d, ast.Call) else d) or "").rsplit(".", 1)[-1] == "dataclass"
                for d in node.decorator_list
            )
            if not record:
                return None
            return [s.target.id for s in node.body if isinstance(s, ast.AnnAssign) and isinstance(s.target, ast.Name)]
    return None


def _field_readers(field: str, facts: ModuleFacts) -> list[Reader]:
    """``memories[t].done``, ``m.done`` for a loop variable or a name bound from an index:
    reads of the record's field (``self.done`` and the like are an object's own state)."""
    readers = []
    for node in facts.attributes.get(field, ()):
        if not (isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Load)):
            continue
        owner = node.value
        if isinstance(owner, ast.Subscript) or (isinstance(owner, ast.Name) and _record_name(owner, facts)):
            use = reader_use(node, facts)
            if use is not None:
                readers.append(Reader(node, use))
    return readers


def _record_name(name: ast.Name, facts: ModuleFacts) -> bool:
    """``m`` bound as a loop variable (``for m in memories``) or from an index (``m = memories[t]``)."""
    if name.id in ("self", "cls"):
        return False
    function = facts.enclosing_function(name) or facts.tree
    for node in _own_nodes(function):
        if isinstance(node, (ast.For, ast.comprehension)) and isinstance(node.target, ast.Name) and node.target.id == name.id:
            return True
        if (
            isinstance(node, ast.Assign)
            and isinstance(node.value, ast.Subscript)
            and any(isinstance(t, ast.Name) and t.id == name.id for t in node.targets)
        ):
            return True
    return False


def _tuple_readers(store: str, index: int, size: int, scope: ast.AST, facts: ModuleFacts) -> list[Reader]:
    """Reads of element ``index`` of the ``size``-tuples kept in ``store``, in ``scope``:
    ``obs, a, s2, r, done = self.buffer[i]`` (also ``for ... in``, over the store or a name
    taken from it, like ``batch = random.sample(self.buffer, n)``), and ``self.buffer[i][4]``."""
    readers: list[Reader] = []
    functions: list[ast.AST] = [n for n in walk(scope) if isinstance(n, FUNCTIONS)]
    if isinstance(scope, ast.Module):
        functions.append(scope)  # module-level code too
    for function in functions:
        nodes = list(_own_nodes(function))
        sources = {store}
        for node in nodes:  # names taken from the store: one link
            if isinstance(node, ast.Assign) and _mentions(node.value, sources):
                sources.update(t.id for t in node.targets if isinstance(t, ast.Name))
        flags: set[str] = set()
        for node in nodes:
            if isinstance(node, ast.Assign) and len(node.targets) == 1:
                target, source = node.targets[0], node.value
            elif isinstance(node, (ast.For, ast.comprehension)):
                target, source = node.target, node.iter
            else:
                continue
            if (
                isinstance(target, (ast.Tuple, ast.List))
                and len(target.elts) == size
                and isinstance(target.elts[index], ast.Name)
                and _mentions(source, sources)
            ):
                flags.add(target.elts[index].id)  # type: ignore[attr-defined]
        for node in nodes:
            if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load) and node.id in flags:
                use = reader_use(node, facts)
                if use is not None:
                    readers.append(Reader(node, use))
            elif (
                isinstance(node, ast.Subscript)
                and isinstance(node.ctx, ast.Load)
                and isinstance(node.slice, ast.Constant)
                and node.slice.value == index
                and isinstance(node.value, ast.Subscript)
                and full_name(node.value.value) in sources
            ):
                use = reader_use(node, facts)
                if use is not None:
                    readers.append(Reader(node, use))
    return readers


def _mentions(node: ast.AST, names: set[str]) -> bool:
    return any(isinstance(n, (ast.Name, ast.Attribute)) and full_name(n) in names for n in walk(node))


def reader_use(node: ast.expr, facts: ModuleFacts) -> ReaderUse | None:
    """What one read of a stored flag does. ``boundary``: it ends something (``if done:
    break``, ``while not done``) or picks the neighbouring record's value (``m[t + 1]``);
    ``mask``: anything else that uses it as a value or a test; None: it is only shown."""
    current: ast.AST = node
    negated = False
    parent = facts.parent(current)
    while isinstance(parent, (ast.BoolOp, ast.UnaryOp)) and not (
        isinstance(parent, ast.UnaryOp) and not isinstance(parent.op, ast.Not)
    ):
        if isinstance(parent, ast.UnaryOp):
            negated = not negated
        current, parent = parent, facts.parent(parent)
    if isinstance(parent, ast.While) and parent.test is current:
        return "boundary"
    if isinstance(parent, (ast.If, ast.IfExp)) and parent.test is current:
        if isinstance(parent, ast.If):
            done_branch = parent.orelse if negated else parent.body
            if any(isinstance(n, _LEAVES) for s in done_branch for n in walk(s)):
                return "boundary"  # ``if done: break``: the flag cuts the sum there
        branches = [parent.body, parent.orelse] if isinstance(parent, ast.IfExp) else [*parent.body, *parent.orelse]
        if any(_neighbour(n) for b in branches for n in walk(b)):
            return "boundary"  # ``m[t + 1].value``: the next record, a new episode after a reset
        return "mask"
    if classify_done_read(node, facts) is DoneUse.NEUTRAL:  # type: ignore[arg-type]
        return None
    return "mask"


def _neighbour(node: ast.AST) -> bool:
    """``memories[t + 1]``, ``values[i - 1]``: an index one step away from a loop index."""
    if not (isinstance(node, ast.Subscript) and isinstance(node.slice, ast.BinOp)):
        return False
    index = node.slice
    return (
        isinstance(index.op, (ast.Add, ast.Sub))
        and isinstance(index.left, ast.Name)
        and isinstance(index.right, ast.Constant)
        and index.right.value == 1
    )


def _own_nodes(function: ast.AST):
    """The nodes of ``function`` (or a module) without nested defs and lambdas."""
    stack = list(ast.iter_child_nodes(function))
    while stack:
        node = stack.pop()
        if isinstance(node, (*FUNCTIONS, ast.Lambda)):
            continue
        yield node
        stack.extend(ast.iter_child_nodes(node))
