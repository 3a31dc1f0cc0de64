"""What pytest gives a test's parameter: the module's ``@pytest.fixture`` of that name,
the fixtures a pytest-cases ``fixture_ref`` parametrization refers to, or the values a
``@pytest.mark.parametrize`` decorator lists. Plain facts of one module; the receiver
analysis (``facts/receiver_params.py``) and the wrapper rules classify what they find.
"""

from __future__ import annotations

import ast

from gymmigrate.facts.module import (
    FUNCTIONS,
    ModuleFacts,
    own_returns,
    string_value,
    walk,
)


def pytest_fixture(facts: ModuleFacts, name: str) -> ast.FunctionDef | ast.AsyncFunctionDef | None:
    """The module's ``@pytest.fixture`` function pytest knows as ``name``: pytest passes
    what it returns (or yields) to a test's parameter of that name."""
    return module_fixtures(facts).get(name)


def module_fixtures(facts: ModuleFacts) -> dict[str, ast.FunctionDef | ast.AsyncFunctionDef]:
    """The module's top-level ``@pytest.fixture`` defs by the name pytest gives them: the
    decorator's ``name=`` where it sets one (``@pytest.fixture(name="env")`` on ``def
    make_env()``: only ``env`` asks for it), else the def's own name."""
    return facts.memo(("pytest-fixtures", 0), lambda: _module_fixtures(facts))


def _module_fixtures(facts: ModuleFacts) -> dict[str, ast.FunctionDef | ast.AsyncFunctionDef]:
    found: dict[str, ast.FunctionDef | ast.AsyncFunctionDef] = {}
    for function in facts.functions.values():
        for decorator in function.decorator_list:
            target = decorator.func if isinstance(decorator, ast.Call) else decorator
            if not any(q in ("pytest.fixture", "_pytest.fixtures.fixture") for q in facts.qualified_names(target)):
                continue
            named = next((k.value for k in decorator.keywords if k.arg == "name"), None) if isinstance(decorator, ast.Call) else None
            if named is None:
                found[function.name] = function
            elif (text := string_value(named)) is not None:
                found[text] = function
            break
    return found


def injected(facts: ModuleFacts, function: ast.AST) -> bool:
    """pytest fills the parameters of ``function`` with fixtures by their names: a test
    (``test*`` at module level, or a ``test*`` method of a ``Test*`` class) or a fixture."""
    if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
        return False
    if function in module_fixtures(facts).values():
        return True
    if not function.name.startswith("test"):
        return False
    # pytest collects the module's attributes: a def under ``if not missing:`` is one too
    if facts.enclosing_function(function) is not None:
        return False
    holder = facts.enclosing_class(function)
    return holder is None or (
        holder.name.startswith("Test") and facts.is_method(function) and facts.enclosing(holder, (ast.ClassDef, *FUNCTIONS)) is None
    )


def requested_fixtures(facts: ModuleFacts, call: ast.Call) -> list[str] | None:
    """The fixture names ``request.getfixturevalue(name)`` asks for, where ``request`` is
    pytest's own fixture (a parameter of that name of a test or fixture that no fixture of
    the module overrides) and the name is a string, or a parameter of the test whose every
    ``@pytest.mark.parametrize`` value is one (``["env_a", "env_b"]``). None otherwise."""
    func = call.func
    if not (
        isinstance(func, ast.Attribute)
        and func.attr == "getfixturevalue"
        and isinstance(func.value, ast.Name)
        and func.value.id == "request"
        and len(call.args) == 1
        and not call.keywords
        and "request" not in module_fixtures(facts)
    ):
        return None
    bindings = facts.bindings_of(func.value)
    if not (len(bindings) == 1 and isinstance(bindings[0], ast.arg)):
        return None
    function = facts.parent(facts.parent(bindings[0]))
    if function is None or not injected(facts, function):
        return None
    argument = call.args[0]
    literal = string_value(argument)
    if literal is not None:
        return [literal]
    if not isinstance(argument, ast.Name):
        return None
    named = facts.bindings_of(argument)
    if not (len(named) == 1 and isinstance(named[0], ast.arg) and facts.parent(facts.parent(named[0])) is function):
        return None
    values = param_values(facts, function, argument.id)  # type: ignore[arg-type]
    if not values:
        return None
    names = [string_value(value) for value in values]
    return None if any(n is None for n in names) else names  # type: ignore[return-value]


def param_fixtures(facts: ModuleFacts, function: ast.FunctionDef | ast.AsyncFunctionDef, name: str) -> list[ast.FunctionDef | ast.AsyncFunctionDef]:
    """The module's pytest fixtures that give a test's parameter ``name`` its values:
    the fixture of that name, or, where the test is parametrized over that name with
    ``fixture_ref`` (pytest-cases: ``@parametrize("env", [fixture_ref(env_4),
    fixture_ref(env_10)])``), every fixture referred to; empty when any value is
    something else."""
    for decorator in function.decorator_list:
        if not (isinstance(decorator, ast.Call) and len(decorator.args) >= 2):
            continue
        if not any(q.endswith("parametrize") for q in facts.qualified_names(decorator.func)):
            continue
        argnames = string_value(decorator.args[0])
        if argnames is None or [n.strip() for n in argnames.split(",")] != [name]:
            continue
        values = decorator.args[1]
        if not isinstance(values, (ast.List, ast.Tuple)) or not values.elts:
            return []
        found = []
        for value in values.elts:
            if not (isinstance(value, ast.Call) and len(value.args) == 1):
                return []
            referred = value.args[0]
            if not (
                any(q.endswith("fixture_ref") for q in facts.qualified_names(value.func))
                and isinstance(referred, ast.Name)
                and (fixture := pytest_fixture(facts, referred.id)) is not None
            ):
                return []
            found.append(fixture)
        return found
    fixture = pytest_fixture(facts, name)
    return [fixture] if fixture is not None else []

def param_values(facts: ModuleFacts, function: ast.FunctionDef | ast.AsyncFunctionDef, name: str) -> list[ast.expr] | None:
    """What ``@pytest.mark.parametrize`` gives a test's parameter ``name``: the values of
    a list or tuple display written in the decorator, or bound once in this module to a
    name the decorator reads (``wrappers = [wrap(make_env()), ...]``), or the element of
    a comprehension; with several argnames (``"env, n"``) the item at the parameter's
    place in each tuple. ``pytest.param(value, id=...)`` gives its value. None when any
    value cannot be read so (a starred item, a list extended elsewhere, ``indirect``)."""
    for decorator in function.decorator_list:
        if not (isinstance(decorator, ast.Call) and len(decorator.args) >= 2):
            continue
        if not any(q.endswith("parametrize") for q in facts.qualified_names(decorator.func)):
            continue
        argnames = _argnames(decorator.args[0])
        if argnames is None or name not in argnames:
            continue
        if any(k.arg == "indirect" for k in decorator.keywords):
            return None
        container = _param_container(facts, decorator.args[1])
        if container is None:
            return None
        if isinstance(container, (ast.ListComp, ast.GeneratorExp)):
            rows: list[ast.expr] = [container.elt]
        else:
            rows = list(container.elts)
        index = argnames.index(name)
        values: list[ast.expr] = []
        for row in rows:
            if isinstance(row, ast.Call) and any(q.endswith("pytest.param") for q in facts.qualified_names(row.func)):
                items: list[ast.expr] | None = list(row.args)
            elif len(argnames) == 1:
                items = [row]
            elif isinstance(row, (ast.Tuple, ast.List)):
                items = list(row.elts)
            else:
                items = None
            if items is None or len(items) != len(argnames) or any(isinstance(i, ast.Starred) for i in items):
                return None
            values.append(items[index])
        return values
    return None

def _param_container(facts: ModuleFacts, values: ast.expr) -> ast.List | ast.Tuple | ast.ListComp | ast.GeneratorExp | None:
    """The display a parametrize decorator's values come from (see ``param_values``)."""
    if isinstance(values, (ast.List, ast.Tuple, ast.ListComp, ast.GeneratorExp)):
        return values
    if not isinstance(values, ast.Name):
        return None
    bindings = facts.bindings_of(values)
    if len(bindings) != 1 or not isinstance(bindings[0], ast.Name):
        return None
    statement = facts.parent(bindings[0])
    if not (isinstance(statement, ast.Assign) and statement.targets == [bindings[0]]):
        return None
    if not isinstance(statement.value, (ast.List, ast.Tuple, ast.ListComp)):
        return None
    # ``wrappers.append(...)`` or ``wrappers[0] = ...`` elsewhere add values the display does not show.
    for attr in _MUTATORS:
        if any(isinstance(a.value, ast.Name) and a.value.id == values.id for a in facts.attributes.get(attr, ())):
            return None
    if values.id in facts.memo(("subscript-stores", 0), lambda: _subscript_stores(facts)):
        return None
    return statement.value

def _subscript_stores(facts: ModuleFacts) -> frozenset[str]:
    """Names of this module written through a subscript (``xs[0] = v``, ``del xs[0]``)."""
    return frozenset(
        node.value.id
        for node in walk(facts.tree)
        if isinstance(node, ast.Subscript) and isinstance(node.ctx, (ast.Store, ast.Del)) and isinstance(node.value, ast.Name)
    )

def fixture_values(facts: ModuleFacts, fixture: ast.FunctionDef | ast.AsyncFunctionDef) -> list[ast.expr]:
    """What a fixture gives its tests: what it yields, else what it returns."""
    yielded = [
        node.value
        for node in walk(fixture)
        if isinstance(node, ast.Yield) and node.value is not None and facts.enclosing_function(node) is fixture
    ]
    return yielded or [r.value for r in own_returns(fixture) if r.value is not None]


_MUTATORS = frozenset({"append", "extend", "insert", "__setitem__", "__iadd__"})


def _argnames(node: ast.AST) -> list[str] | None:
    """A parametrize decorator's argnames: ``"env"``, ``"env, n"`` or ``("env", "n")``."""
    text = string_value(node)
    if text is not None:
        return [n.strip() for n in text.split(",") if n.strip()]
    if isinstance(node, (ast.List, ast.Tuple)):
        names = [string_value(el) for el in node.elts]
        return None if any(n is None for n in names) else names  # type: ignore[return-value]
    return None
