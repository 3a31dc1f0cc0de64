"""What one test module takes from the ``conftest.py`` files above it (``FixtureView``, a
part of ``ProjectView``): pytest hands a test's parameter, and ``request.getfixturevalue``
its argument, the fixture of that name in the nearest ``conftest.py`` of the test's
directory or a directory above it. That is a proof of what the parameter holds, not a
guess from its name: the fixture's values (``ModuleSummary.fixtures``) say what it is.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from gymmigrate.facts.kinds import EnvKind, join_kinds
from gymmigrate.facts.module_summary import FIXTURE, MADE_VALUE, OWN, REF

if TYPE_CHECKING:
    from gymmigrate.facts.project import ProjectFacts

# Where a fixture's value comes from, as the forwarding rules name it (``origins.py``).
FIXTURE_MADE = "made"
FIXTURE_WRAPPED = "wrapped"
FIXTURE_RAW = "raw"
# Fixtures that hand on fixtures: beyond this many the chain is not followed.
_MAX_CHAIN = 12

# (origin or None, what the outermost wrapper defines for ``self``, None where unknown)
FixtureOrigin = tuple[str | None, frozenset[str] | None]


class FixtureView:
    """The run's conftest fixtures as one file sees them (``facts`` and ``path`` are ``ProjectView``'s)."""

    facts: ProjectFacts
    path: str

    def fixture_kind(self, name: str) -> EnvKind | None:
        """What the fixture ``name`` of the nearest conftest.py above this module gives: the
        kinds of its values, joined; None where no conftest of the run defines it."""
        found = self._fixture(name, os.path.dirname(self.path), 0)
        return None if found is None else join_kinds(kind for kind, _ in found)

    def fixture_origin(self, name: str) -> list[FixtureOrigin] | None:
        """Per value of that fixture, where it comes from (``made``, ``wrapped`` by a Gym
        wrapper class of the run, ``raw``: an env class's instance; None: not shown) and what
        its outermost wrapper defines; None where no conftest of the run defines it."""
        found = self._fixture(name, os.path.dirname(self.path), 0)
        return None if found is None else [origin for _, origin in found]

    def _fixture(self, name: str, directory: str, depth: int) -> list[tuple[EnvKind, FixtureOrigin]] | None:
        if depth > _MAX_CHAIN:
            return [(EnvKind.UNKNOWN, (None, None))]
        for conftest in _conftests_above(directory):
            fixture = self.facts.fixtures.get(conftest, {}).get(name)
            if fixture is not None:
                return [self._value(conftest, shape, depth) for shape in fixture[1]] or [(EnvKind.NOT_ENV, (None, None))]
        return None

    def _value(self, conftest: str, shape: str, depth: int) -> tuple[EnvKind, FixtureOrigin]:
        if shape == MADE_VALUE:
            return EnvKind.GYM_ENV, (FIXTURE_MADE, None)
        if shape.startswith(FIXTURE):
            # a fixture it takes and hands on: pytest looks it up from the conftest's own
            # directory, the conftest itself included
            found = self._fixture(shape[len(FIXTURE) :], os.path.dirname(conftest), depth + 1)
            if found is None or len(found) != 1:
                kinds = [kind for kind, _ in found or ()]
                return (join_kinds(kinds) if kinds else EnvKind.UNKNOWN), (None, None)
            return found[0]
        if shape.startswith(OWN):
            local = shape[len(OWN) :]
            key = (conftest, local)
            kind = self.facts.call_kinds.get(key, EnvKind.UNKNOWN)
            if local in self.facts.wrapper_classes.get(conftest, ()):
                return kind, (FIXTURE_WRAPPED, self.facts.wrapper_defined.get(key))
            if local in self.facts.env_classes.get(conftest, ()):
                return kind, (FIXTURE_RAW, None)
            return kind, ((FIXTURE_MADE if key in self.facts.made else None), None)
        if shape.startswith(REF):
            qualified = shape[len(REF) :]
            view = self.facts.view(conftest)
            kind = view.call_kind(qualified) or EnvKind.UNKNOWN
            if view.is_wrapper_class(qualified):
                return kind, (FIXTURE_WRAPPED, view.wrapper_defined(qualified))
            if view.returns_made(qualified):
                return kind, (FIXTURE_MADE, None)
            if view.makes_bare_env(qualified):
                return kind, (FIXTURE_RAW, None)
            return kind, (None, None)
        return EnvKind.UNKNOWN, (None, None)


def _conftests_above(directory: str) -> list[str]:
    """The ``conftest.py`` paths pytest reads for a test in ``directory``, nearest first."""
    found = []
    while True:
        found.append(os.path.join(directory, "conftest.py"))
        parent = os.path.dirname(directory)
        if parent == directory:
            return found
        directory = parent
