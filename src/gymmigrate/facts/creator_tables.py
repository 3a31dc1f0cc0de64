"""Tables of creators: a module-level dict (or list, tuple) display whose values are
callables, called through a lookup: ``CREATORS[name](**cfg)``, ``ENVS[key]["make"]()``,
or ``cls = CLASSES[kind]; cls(params)``.

What such a call returns is what calling every value of the table (or the named field of
every record of it) returns, joined: a Gym env only when each of them makes one, an object
of the project's own only when each does. The table must be closed for that to hold: bound
once, and never written into, here or in a module that imports it (``T[k] = v``,
``del T[k]``, ``T.update(...)``, a record's ``T[k]["make"] = f``); a table that a
``register()`` of the project fills at run time holds what its callers hand it, which the
run does not see.

``Receivers`` asks ``table_entries`` for a table of its own module; a module's summary
lists its tables' entries for the modules that import them (``ModuleSummary.tables``) and
the imported names it writes into (``ModuleSummary.altered``).
"""

from __future__ import annotations

import ast
import re
import sys
from typing import cast

from gymmigrate.facts.module import ModuleFacts

# Methods of dicts and lists that change what they hold.
_MUTATORS = frozenset(
    {"update", "setdefault", "pop", "popitem", "clear", "__setitem__", "__delitem__", "append", "extend", "insert", "remove"}
)

Display = ast.Dict | ast.List | ast.Tuple

# What a lookup calls of each record: a key of dict records (``T[k]["make"]``) or a
# position of tuple records (``T[k][0]`` over ``{"a": (A, "2D")}``); "" for the values themselves.
Field = str | int

# Mapping constructors whose arguments are the table itself: ``OrderedDict(((k, v), ...))``,
# ``dict([(k, v), ...])``, ``dict(k=v)``: as closed as the display they copy.
_MAPPING_TYPES = frozenset({"collections.OrderedDict", "dict"})


def lookup(facts: ModuleFacts, callee: ast.Subscript) -> tuple[ast.expr, Field | None] | None:
    """``T[k]`` -> (``T``, None); ``T[k]["make"]`` -> (``T``, ``"make"``); ``T[k][0]`` ->
    (``T``, 0): the table a called lookup reads, and the field of its records it calls.
    None for other shapes."""
    value = callee.value
    if isinstance(value, ast.Subscript):
        field = callee.slice
        # a key of the records, or a position in them (not a bool, which is an int too)
        if not (isinstance(field, ast.Constant) and (isinstance(field.value, str) or type(field.value) is int)):
            return None
        if isinstance(value.value, (ast.Name, ast.Attribute)):
            return value.value, field.value
        return None
    if isinstance(value, (ast.Name, ast.Attribute)):
        return value, None
    return None


def table_display(facts: ModuleFacts, name: ast.Name) -> Display | None:
    """The display a name of this module is bound to, when it is a closed table: one
    module-level binding ``T = {...}`` (or a list or tuple) that nothing of the module
    writes into."""
    bindings = facts.bindings_of(name)
    if len(bindings) != 1 or not isinstance(bindings[0], ast.Name):
        return None
    return module_table(facts, bindings[0])


def module_table(facts: ModuleFacts, binding: ast.Name) -> Display | None:
    """The display of the module-level assignment ``binding`` heads, when it is a closed table."""
    assign = facts.parent(binding)
    if not (isinstance(assign, ast.Assign) and assign.targets == [binding] and facts.parent(assign) is facts.tree):
        return None
    if len(facts.module_scope.bindings.get(binding.id, ())) != 1:
        return None
    value: ast.expr | None = assign.value
    if isinstance(value, ast.Call):
        value = facts.memo(("mapping-display", id(value)), lambda: _mapping_display(facts, cast(ast.Call, assign.value)))
    if not isinstance(value, (ast.Dict, ast.List, ast.Tuple)):
        return None
    display = value
    return facts.memo(("table-closed", id(binding)), lambda: _closed(facts, binding, display))


def _closed(facts: ModuleFacts, binding: ast.Name, display: Display) -> Display | None:
    """``display`` with the items this module stores into the dict it builds at top level
    (``T[k] = v``, maybe under an ``if`` or a ``try``: each is an entry the table may hold, shown here),
    or None when the module writes into it any other way (``del``, ``update``, a store
    into a record)."""
    stored: list[tuple[ast.expr, ast.expr]] = []
    for read in facts.reads_of(binding.id, binding):
        if not written(facts, read):
            continue
        item = facts.parent(read)
        assign = facts.parent(item)
        if not (
            isinstance(item, ast.Subscript)
            and item.value is read
            and isinstance(item.ctx, ast.Store)
            and isinstance(assign, ast.Assign)
            and assign.targets == [item]
            # at top level: a def storing into it fills it with what its callers hand it
            and facts.scope_of(assign) is facts.module_scope
        ):
            return None
        stored.append((item.slice, assign.value))
    if not stored:
        return display
    if not isinstance(display, ast.Dict):
        return None  # an item stored into a list or tuple replaces one the run cannot name
    return ast.Dict(keys=[*display.keys, *(k for k, _ in stored)], values=[*display.values, *(v for _, v in stored)])


def _mapping_display(facts: ModuleFacts, call: ast.Call) -> ast.Dict | None:
    """The dict a mapping constructor call builds, as a display of the same key and value
    nodes: ``OrderedDict((("a", A), ("b", B)))`` is ``{"a": A, "b": B}``, ``dict(a=A)`` is
    ``{"a": A}``. None for any other call, or one whose pairs are not all shown."""
    func = call.func
    qualified = facts.qualified_names(func)
    if isinstance(func, ast.Name) and not qualified and facts.resolve(func.id, facts.scope_of(func))[0] is None:
        qualified = {func.id}  # the builtin, not rebound
    if not qualified & _MAPPING_TYPES or len(call.args) > 1:
        return None
    keys: list[ast.expr | None] = []
    values: list[ast.expr] = []
    if call.args:
        pairs = call.args[0]
        if not isinstance(pairs, (ast.Tuple, ast.List)):
            return None
        for pair in pairs.elts:
            if not (isinstance(pair, ast.Tuple) and len(pair.elts) == 2):
                return None
            keys.append(pair.elts[0])
            values.append(pair.elts[1])
    for keyword in call.keywords:
        if keyword.arg is None:
            return None  # ``dict(**other)``: entries not shown
        keys.append(ast.Constant(keyword.arg))
        values.append(keyword.value)
    return ast.Dict(keys=keys, values=values)


def entries(display: Display, field: Field | None) -> list[ast.expr] | None:
    """The table's values (``field`` None), or the ``field`` of each of its records (dict
    displays; a record without it cannot be called through it and is skipped; for a
    position, tuple or list displays that all hold it). None when a value is not shown
    (``**other``, ``*more``, a record that is no display) or none is left."""
    if isinstance(display, ast.Dict):
        if any(key is None for key in display.keys):
            return None
        values = list(display.values)
    else:
        if any(isinstance(e, ast.Starred) for e in display.elts):
            return None
        values = list(display.elts)
    if field is None:
        return values or None
    if isinstance(field, int):
        # ``T[k][0]``: every record a tuple or list display that shows that position
        held = [r for r in values if isinstance(r, (ast.Tuple, ast.List)) and not any(isinstance(e, ast.Starred) for e in r.elts)]
        if len(held) != len(values) or not all(0 <= field < len(r.elts) for r in held):
            return None
        return [r.elts[field] for r in held] or None
    found = []
    for record in values:
        if not isinstance(record, ast.Dict) or any(key is None for key in record.keys):
            return None
        found += [v for k, v in zip(record.keys, record.values) if isinstance(k, ast.Constant) and k.value == field]
    return found or None


def record_positions(display: Display) -> range:
    """The positions every record shows, when every value is a tuple or list display
    without ``*more``."""
    values = display.values if isinstance(display, ast.Dict) else display.elts
    records = [v for v in values if isinstance(v, (ast.Tuple, ast.List)) and not any(isinstance(e, ast.Starred) for e in v.elts)]
    if not values or len(records) != len(values):
        return range(0)
    return range(min(len(r.elts) for r in records))


def record_fields(display: Display) -> set[str]:
    """The string keys of the table's records, when every value is a dict display."""
    values = display.values if isinstance(display, ast.Dict) else display.elts
    records = [v for v in values if isinstance(v, ast.Dict)]
    if not values or len(records) != len(values):
        return set()
    return {k.value for record in records for k in record.keys if isinstance(k, ast.Constant) and isinstance(k.value, str)}


def written(facts: ModuleFacts, read: ast.expr) -> bool:
    """``read`` (a table, or an item of it through ``[...]``) is written into: the target of
    a store or a ``del``, or the owner of a mutating method's call."""
    node: ast.AST = read
    parent = facts.parent(node)
    while isinstance(parent, ast.Subscript) and parent.value is node:
        if not isinstance(parent.ctx, ast.Load):
            return True
        node, parent = parent, facts.parent(parent)
    if isinstance(parent, ast.Attribute) and parent.value is node and parent.attr in _MUTATORS:
        call = facts.parent(parent)
        return isinstance(call, ast.Call) and call.func is parent
    return False


def altered_imports(facts: ModuleFacts) -> frozenset[str]:
    """The qualified names of imported names this module writes into: ``T[k] = v`` on
    ``from registry import T``, ``registry.T.update(...)`` on ``import registry``."""
    found: set[str] = set()
    for alias, qualified in facts.imports.items():
        for read in facts.reads_of(alias.asname or alias.name.split(".", 1)[0], alias):
            node: ast.expr = read
            name = qualified
            while True:
                if written(facts, node):
                    found.add(name)
                parent = facts.parent(node)
                if not (isinstance(parent, ast.Attribute) and parent.value is node):
                    break
                node, name = parent, f"{name}.{parent.attr}"
    return frozenset(found)


# The names a module imports (``from registry import CREATORS, add``, ``import registry as r``).
_IMPORTED = re.compile(rb"^[ \t]*(?:from[ \t]+([\w.]+)[ \t]+import[ \t]+\(?([\w ,\t]+)|import[ \t]+([\w., \t]+))", re.MULTILINE)
# A standard library module holds no table of the run (``os.environ[k] = v``, ``sys.modules[k] = m``).
_STDLIB = frozenset(name.encode() for name in sys.stdlib_module_names)


def writes_into_import(source: bytes) -> bool:
    """A cheap test of a module's text, before any parse: it may write into a name it imports
    from outside the standard library (``NAME[k] = v``, ``NAME.attr[k]["f"] = v``,
    ``del NAME[k]``, ``NAME.update(...)``)."""
    if b"import" not in source:
        return False
    names: set[bytes] = set()
    for match in _IMPORTED.finditer(source):
        origin, imported, modules = match.groups()
        if origin is not None and origin.split(b".")[0] in _STDLIB:
            continue
        for part in (imported or modules or b"").split(b","):
            words = part.split()
            if words and (origin is not None or words[0].split(b".")[0] not in _STDLIB):
                names.add(words[-1].split(b".")[0])
    if not names:
        return False
    alternatives = b"|".join(re.escape(n) for n in sorted(names))
    write = rb"\b(?:" + alternatives + rb")(?:\.\w+)*(?:\[[^\n]*\]\s*=(?!=)|\.(?:" + b"|".join(sorted(m.encode() for m in _MUTATORS)) + rb")\()"
    return re.search(write, source) is not None or re.search(rb"\bdel[ \t]+(?:" + alternatives + rb")\b", source) is not None
