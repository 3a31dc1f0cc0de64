"""Where a module hands a value on: the calls that receive it as an argument, followed
through the names and ``self`` attributes it is bound to, the tables (dicts, lists, tuples)
that hold it, the items read from them and the loops over them, and the returns of the
module's defs. The env id rules (GM803-GM805, GM809) ask it about a retired id that no
call taking an id receives directly: ``{"task": "Ant-v2"}`` in a table whose entry is
handed to another library's ``Simulator(settings=...)`` reaches a make there.

A value is tracked with the containers that hold it, outermost first: reading an item
(``table[k]``, ``table.get(k)``) or looping over a list or tuple takes the outermost one
off; a loop over a dict gives its keys, never the value, and a key is not followed.
"""

from __future__ import annotations

import ast
from collections.abc import Iterator
from dataclasses import dataclass

from gymmigrate.facts.flow import Flow
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts
from gymmigrate.facts.receivers import Receivers

# names, ``self`` attributes and returns followed from the value: a table built at the top of
# a module reaches its use a few bindings later, and a longer chain is a guess
_HOPS = 6
_LIST, _DICT = "list", "dict"


@dataclass(frozen=True)
class Handover:
    """A call that receives the value itself (``held`` False) or a container holding it."""

    call: ast.Call
    key: str  # the argument's position ("0") or keyword; "**" for ``**table``
    held: bool
    table: str  # the first name or ``self`` attribute bound to a container holding it ("" if none)


# a state: the node holding the value, its containers outermost first, hops used, the table's name
_State = tuple[ast.AST, tuple[str, ...], int, str]


def handovers(facts: ModuleFacts, receivers: Receivers, value: ast.expr) -> list[Handover]:
    """Every call ``value`` reaches as an argument (or inside one), nearest first."""
    return facts.memo(("handovers", id(value)), lambda: _follow(facts, receivers, value))


def _follow(facts: ModuleFacts, receivers: Receivers, value: ast.expr) -> list[Handover]:
    found: list[Handover] = []
    seen: set[tuple[int, tuple[str, ...]]] = set()
    work: list[_State] = [(value, (), 0, "")]
    while work:
        node, held, hops, table = work.pop(0)
        if (id(node), held) in seen:
            continue
        seen.add((id(node), held))
        for step in _steps(facts, receivers, node, held, table):
            if isinstance(step, Handover):
                found.append(step)
            elif hops + step[2] <= _HOPS:
                work.append((step[0], step[1], hops + step[2], step[3]))
    return found


def _steps(facts: ModuleFacts, receivers: Receivers, node: ast.AST, held: tuple[str, ...], table: str) -> Iterator[Handover | _State]:
    parent = facts.parent(node)
    if isinstance(parent, (ast.List, ast.Tuple, ast.Set)):
        yield (parent, (_LIST, *held), 0, table)
    elif isinstance(parent, ast.Dict):
        if any(v is node for v in parent.values):  # a key names an entry: it goes nowhere as a value
            yield (parent, (_DICT, *held), 0, table)
    elif isinstance(parent, ast.IfExp):
        if node is not parent.test:
            yield (parent, held, 0, table)
    elif isinstance(parent, ast.Subscript):
        if parent.value is node and isinstance(parent.ctx, ast.Load) and held:
            if not isinstance(parent.slice, ast.Slice):
                yield (parent, held[1:], 0, table)
            elif held[0] == _LIST:  # a slice of a list is a list
                yield (parent, held, 0, table)
    elif isinstance(parent, ast.Attribute):
        yield from _method_result(facts, parent, held, table)
    elif isinstance(parent, ast.keyword):
        call = facts.parent(parent)
        if isinstance(call, ast.Call):
            if _builds_dict(facts, call):  # ``dict(task="Ant-v2")``
                yield (call, (_DICT, *held), 0, table)
            else:
                yield Handover(call, parent.arg or "**", bool(held), table)
    elif isinstance(parent, ast.Call):
        position = next((i for i, argument in enumerate(parent.args) if argument is node), None)
        if position is not None:
            yield Handover(parent, str(position), bool(held), table)
    elif isinstance(parent, (ast.Assign, ast.AnnAssign)):
        if parent.value is node:
            targets = parent.targets if isinstance(parent, ast.Assign) else [parent.target]
            for target in targets:
                yield from _reads_of_target(facts, receivers, target, held, table)
    elif isinstance(parent, ast.For):
        if parent.iter is node and held and held[0] == _LIST and isinstance(parent.target, ast.Name):
            for read in facts.reads_of(parent.target.id, parent.target):
                yield (read, held[1:], 1, table)
    elif isinstance(parent, ast.Return):
        yield from _calls_of_returning_def(facts, parent, held, table)


def _method_result(facts: ModuleFacts, attribute: ast.Attribute, held: tuple[str, ...], table: str) -> Iterator[_State]:
    """``table.get(k)``: the item; ``table.values()``: the items as a list; ``table.copy()``."""
    call = facts.parent(attribute)
    if not (held and isinstance(call, ast.Call) and call.func is attribute):
        return
    if attribute.attr == "get" and held[0] == _DICT:
        yield (call, held[1:], 0, table)
    elif attribute.attr == "values" and held[0] == _DICT:
        yield (call, (_LIST, *held[1:]), 0, table)
    elif attribute.attr == "copy":
        yield (call, held, 0, table)


def _reads_of_target(facts: ModuleFacts, receivers: Receivers, target: ast.expr, held: tuple[str, ...], table: str) -> Iterator[_State]:
    if isinstance(target, ast.Name):
        named = table or (target.id if held else "")
        flow = Flow.of(facts)
        for read in facts.reads_of(target.id, target):
            reaching = flow.reaching(read)
            if reaching is None or target in reaching:  # ``e = "..."; e = e.upper()``: the first no longer reaches
                yield (read, held, 1, named)
    elif isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and receivers.is_self(target.value):
        # ``self.config = table[name]`` in one method, ``Library(self.config)`` in another
        classdef = facts.enclosing_class(target)
        named = table or (f"self.{target.attr}" if held else "")
        for stored in facts.attributes.get(target.attr, ()):
            if (
                isinstance(stored.ctx, ast.Load)
                and isinstance(stored.value, ast.Name)
                and receivers.is_self(stored.value)
                and facts.enclosing_class(stored) is classdef
            ):
                yield (stored, held, 1, named)


def _calls_of_returning_def(facts: ModuleFacts, statement: ast.Return, held: tuple[str, ...], table: str) -> Iterator[_State]:
    """``def config(): return {...}``: each call of that module-level def gives the value."""
    function = facts.enclosing_function(statement)
    if not isinstance(function, FUNCTIONS) or facts.parent(function) is not facts.tree:
        return
    for call in facts.calls_by_name.get(function.name, ()):
        if isinstance(call.func, ast.Name) and function in facts.bindings_of(call.func):
            yield (call, held, 1, table)


def _builds_dict(facts: ModuleFacts, call: ast.Call) -> bool:
    func = call.func
    return isinstance(func, ast.Name) and func.id == "dict" and not facts.bindings_of(func)
