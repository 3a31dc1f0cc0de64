"""What an env id site is, and the reads every search for one shares: ``IdSite`` (one
string literal used as an id), ``IdLiterals`` (the literal a name holds where it is read,
whether a call takes an id), the module's calls in source order, and the packages it
imports. ``handed_on_ids.py`` and ``id_sites.py`` build on it.
"""

from __future__ import annotations

import ast
from collections.abc import Hashable
from dataclasses import dataclass

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.receivers import Receivers
from gymmigrate.rules.env_ids.syntax import (
    FORWARDS_KWARGS,
    ID_FUNCTIONS,
    SB3_ID_FUNCTIONS,
    is_registry,
    plain_string,
    split_module_prefix,
)


@dataclass
class IdSite:
    """One string literal used as an env id, and the call that receives it (if known)."""

    string: ast.Constant
    env_id: str
    module_prefix: str  # "ale_py:" in "ale_py:ALE/Pong-v5"
    call: ast.Call | None
    forwards_kwargs: bool
    via: str = ""  # how the string reaches the call ("the constant ENV_ID"), for messages
    report_only: bool = False  # handed to another module's code from a file without Gym: say so, add nothing
    conditional: bool = False  # one branch of ``a if c else b``: keywords would hit both
    untraced: bool = False  # a known retired id handed to the project's code the run cannot follow to a make
    keywords_at_call: bool = False  # via a constant only ``call`` reads: new keywords go to that call
    question: Hashable | None = None  # what an untraced item asks, where other items ask the same
    # the call of this module that makes the env from this id, where the id reaches it through a
    # parameter, a stored attribute or a list (``call`` is None then): its registration goes there
    made_at: ast.Call | None = None
    # an argparse option's or absl flag's default: the command line may hand the make any other id
    command_line_default: bool = False


class IdLiterals:
    """The literals of one module's id sites: what a name holds, which calls take an id."""

    def __init__(self, facts: ModuleFacts, receivers: Receivers) -> None:
        self.facts = facts
        self.receivers = receivers

    def literal_of(self, name: ast.Name) -> ast.Constant | None:
        """The string literal ``name`` holds where it is read: the one literal a constant is
        ever assigned, or the literal of the assignment that certainly reaches the read
        (``env_id = "CartPole-v0"`` ... ``env_id = "PongNoFrameskip-v4"; make_atari(env_id)``)."""
        literal = self._single_literal_constant(name)
        if literal is not None:
            return literal
        flow = Flow.of(self.facts)
        last = flow.last_binding_of(name)
        statement = self.facts.parent(last) if isinstance(last, ast.Name) else None
        if not (isinstance(last, ast.Name) and isinstance(statement, ast.Assign) and statement.targets == [last]):
            return None
        if not flow.dominates(statement, name, last):
            return None  # another value may reach the read (a branch, a loop)
        value = statement.value
        return value if isinstance(value, ast.Constant) and isinstance(value.value, str) else None

    def _single_literal_constant(self, name: ast.Name) -> ast.Constant | None:
        """The literal of ``ENV_ID = "..."`` when that is the name's only assignment."""
        bindings = self.facts.bindings_of(name)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.Name):
            return None
        target = bindings[0]
        statement = self.facts.parent(target)
        value: ast.expr | None
        if isinstance(statement, ast.Assign) and statement.targets == [target]:
            value = statement.value
        elif isinstance(statement, ast.AnnAssign) and statement.target is target:
            value = statement.value
        else:
            return None
        return value if isinstance(value, ast.Constant) and isinstance(value.value, str) else None

    def _site(self, string: ast.AST, call: ast.Call | None, forwards: bool, via: str = "") -> IdSite | None:
        text = plain_string(self.facts, string)
        if text is None or not isinstance(string, ast.Constant):  # a text comes only from a Constant
            return None
        prefix, env_id = split_module_prefix(text)
        return IdSite(string, env_id, prefix, call, forwards, via)

    def _id_call(self, call: ast.Call) -> bool | None:
        """Does ``call`` take an env id? True if it also forwards keywords to the env, None if no id."""
        for qualified in self.facts.qualified_names(call.func):
            rest = N.strip_gym_prefix(qualified)
            if rest in ID_FUNCTIONS:
                return rest in FORWARDS_KWARGS
            if qualified in SB3_ID_FUNCTIONS:
                return False
        func = call.func
        if isinstance(func, ast.Attribute) and func.attr in ("spec", "make") and is_registry(self.facts, func.value):
            return func.attr == "make"
        return None


def calls_in_source_order(facts: ModuleFacts) -> list[ast.Call]:
    """Every call whose callee is a name or an attribute, outer calls before the calls inside them.

    The order decides which string a shared constant's finding names and which id a
    package's registration finding points at, as a walk of the tree would.
    """
    calls = [call for index in (facts.calls_by_name, facts.attribute_calls) for found in index.values() for call in found]
    calls.sort(key=lambda c: (c.lineno, c.col_offset, -(c.end_lineno or 0), -(c.end_col_offset or 0)))
    return calls


def imported_modules(tree: ast.Module, facts: ModuleFacts) -> set[str]:
    """Top-level package of every absolute import in the module (any scope, star imports too)."""
    found: set[str] = set()
    statements = {facts.parent(alias) for alias in facts.imports}
    statements.update(_star_imports(tree.body))
    for statement in statements:
        if isinstance(statement, ast.Import):
            found.update(alias.name.split(".")[0] for alias in statement.names)
        elif isinstance(statement, ast.ImportFrom) and statement.module and not statement.level:
            found.add(statement.module.split(".")[0])
    return found


def _star_imports(body: list[ast.stmt]) -> list[ast.ImportFrom]:
    """``from m import *`` (module level only, but possibly under ``if`` / ``try``)."""
    found = []
    for statement in body:
        if isinstance(statement, ast.ImportFrom) and statement.names[0].name == "*":
            found.append(statement)
        elif isinstance(statement, (ast.If, ast.Try, ast.With, ast.For, ast.While)):
            for block in ("body", "orelse", "finalbody"):
                found.extend(_star_imports(getattr(statement, block, [])))
            for handler in getattr(statement, "handlers", []):
                found.extend(_star_imports(handler.body))
    return found
