"""The pytest fixtures a ``conftest.py`` gives the tests of its directory and those below
it (``ModuleSummary.fixtures``): pytest hands a test's parameter the value of the fixture
of that name in the nearest ``conftest.py`` above the test, so what each fixture gives is
known to the test modules through the join (``ProjectView.fixture_kind``)."""

from __future__ import annotations

import ast
import os

from gymmigrate.facts import names as N
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts
from gymmigrate.facts.module_summary import FIXTURE, MADE_VALUE, OWN, REF
from gymmigrate.facts.pytest_params import fixture_values, module_fixtures
from gymmigrate.facts.receivers import Receivers
from gymmigrate.facts.summaries.defs import made_value

# Beyond this many names bound to names, a returned value is not followed.
_MAX_HOPS = 8


def conftest_fixtures(path: str, facts: ModuleFacts, receivers: Receivers) -> dict[str, tuple[str, tuple[str, ...]]]:
    """For a ``conftest.py``: each fixture by the name pytest gives it -> (its def, what
    each of its values is: ``made`` a ``make(...)`` result maybe in Gym wrappers, ``ref:``
    a call of an imported name of the run as this module spells it, ``@`` a call of a class
    or def of this module, ``fixture:`` another fixture it takes and hands on as it is,
    ``""`` anything else). Empty for any other module: only a conftest's fixtures reach
    other modules."""
    if os.path.basename(path) != "conftest.py":
        return {}
    return {
        name: (function.name, tuple(_shape(facts, receivers, name, function, value) for value in fixture_values(facts, function)))
        for name, function in module_fixtures(facts).items()
    }


def _shape(facts: ModuleFacts, receivers: Receivers, own: str, function: ast.AST, value: ast.expr) -> str:
    """What ``value``, returned or yielded by the fixture ``own`` (the def ``function``), is (``conftest_fixtures``)."""
    if made_value(facts, value, function, receivers):
        return MADE_VALUE
    for _ in range(_MAX_HOPS):
        if not isinstance(value, ast.Name):
            break
        bindings = facts.bindings_of(value)
        if len(bindings) == 1 and isinstance(bindings[0], ast.arg):
            # a fixture it requests, handed on as it is (one that asks for its own name gets
            # the fixture it overrides: not followed)
            requested = bindings[0].arg
            owner = facts.parent(facts.parent(bindings[0]))
            return FIXTURE + requested if owner is function and requested != own else ""
        reaching = receivers.values_reaching(value)
        if reaching is None or len(reaching) != 1:
            return ""
        value = reaching[0]
    if not isinstance(value, ast.Call) or not isinstance(value.func, (ast.Name, ast.Attribute)):
        return ""
    if isinstance(value.func, ast.Name):
        bindings = facts.bindings_of(value.func)
        if len(bindings) == 1 and isinstance(bindings[0], (ast.ClassDef, *FUNCTIONS)) and facts.parent(bindings[0]) is facts.tree:
            return OWN + value.func.id
    qualified = facts.qualified_names(value.func)
    if len(qualified) != 1:
        return ""
    name = next(iter(qualified))
    return "" if N.is_library(name) or "." not in name else REF + name
