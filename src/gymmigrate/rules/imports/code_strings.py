"""GM101 (flag): Gym code that runs from a string. ``timeit.timeit(stmt, setup)``,
``timeit.repeat``, ``timeit.Timer``, ``exec``, ``eval`` and ``compile`` run the Python held in
a string constant against the same envs as the code around them: an ``import gym`` in a
setup string, or ``env.reset(morph)`` on an env the module makes, still runs the legacy API
after the migration. The run never rewrites inside strings (their bytes stay as written), so
one item per module names every such string for a person to port by hand."""

from __future__ import annotations

import ast
import re
import textwrap

from gymmigrate.facts.kinds import EnvKind, join_kinds
from gymmigrate.facts.module import call_argument, string_value
from gymmigrate.findings import FixKind
from gymmigrate.rules.imports.common import ImportsBase

# Cheap pre-check: a module that never names one of these calls has no code string.
_RUNNER_TEXT = re.compile(r"\b(?:timeit|repeat|Timer|exec|eval|compile)\b")

# The timeit API: which parameters hold code (name, position); ``globals`` is its namespace.
_TIMEIT = frozenset({"timeit.timeit", "timeit.repeat", "timeit.Timer"})
_TIMEIT_CODE = (("stmt", 0), ("setup", 1))
# Builtins that run their first argument, with the position of their globals argument.
_BUILTINS = {"exec": ("source", 1), "eval": ("source", 1), "compile": ("source", None)}


def _constant_text(node: ast.expr | None) -> str | None:
    """A string constant, or a ``+`` of string constants (``"import gym;" + "import x"``)."""
    text = string_value(node)
    if text is not None:
        return text
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add):
        left, right = _constant_text(node.left), _constant_text(node.right)
        if left is not None and right is not None:
            return left + right
    return None


def _parsed(text: str) -> ast.Module | None:
    """The code of ``text`` as Python (timeit and exec take indented blocks too), or None."""
    for candidate in (text, textwrap.dedent(text)):
        try:
            return ast.parse(candidate)
        except (SyntaxError, ValueError, RecursionError, MemoryError):
            continue
    return None


def _gym_imports(code: ast.Module) -> set[str] | None:
    """The names ``code`` binds by importing gym (empty: it imports gym without a name to
    read, ``from gym import *``), or None if it imports no gym."""
    names: set[str] | None = None
    for node in ast.walk(code):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name == "gym" or alias.name.startswith("gym."):
                    names = names or set()
                    names.add(alias.asname or "gym")
        elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
            if node.module == "gym" or node.module.startswith("gym."):
                names = names or set()
                names.update(alias.asname or alias.name for alias in node.names if alias.name != "*")
    return names


def _called_receivers(code: ast.Module) -> set[str]:
    """The names ``code`` calls a method on: ``env`` in ``env.reset(r)``."""
    return {
        node.func.value.id
        for node in ast.walk(code)
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and isinstance(node.func.value, ast.Name)
    }


def _read_names(code: ast.Module) -> set[str]:
    return {node.id for node in ast.walk(code) if isinstance(node, ast.Name)}


def _main_imports(code: ast.Module | None) -> set[str]:
    """The names a timeit setup takes from the running script (``from __main__ import env``)."""
    if code is None:
        return set()
    return {
        alias.asname or alias.name
        for node in ast.walk(code)
        if isinstance(node, ast.ImportFrom) and node.module == "__main__"
        for alias in node.names
    }


class CodeStrings(ImportsBase):
    """GM101's item on Gym code held in strings (mixed into the family)."""

    def _code_strings(self) -> None:
        if not _RUNNER_TEXT.search(self.facts.text):
            return
        found: list[ast.expr] = []
        for call in self._string_runners():
            found.extend(self._gym_strings(call))
        if not found:
            return
        found.sort(key=lambda node: (node.lineno, node.col_offset))
        lines = ", ".join(str(line) for line in dict.fromkeys(node.lineno for node in found))
        self.report(
            found[0],
            "GM101",
            "this code runs from a string (timeit/exec): gymmigrate does not rewrite inside strings; port "
            f"`import gym` -> `import gymnasium as gym` and the env calls in it by hand (lines {lines})",
            FixKind.FLAG,
        )

    def _string_runners(self) -> list[ast.Call]:
        calls = [
            call
            for attr in ("timeit", "repeat", "Timer")
            for call in self.facts.attribute_calls.get(attr, ())
            if self.facts.qualified_names(call.func) & _TIMEIT
        ]
        for name, named in self.facts.calls_by_name.items():
            for call in named:
                if not isinstance(call.func, ast.Name):
                    continue
                if name in _BUILTINS and not self.facts.bindings_of(call.func):
                    calls.append(call)
                elif self.facts.qualified_names(call.func) & _TIMEIT:
                    calls.append(call)  # ``from timeit import timeit as measure``
        return calls

    def _gym_strings(self, call: ast.Call) -> list[ast.expr]:
        """The code strings of ``call`` that hold Gym code: an import of gym, a read of a name
        such an import of the same call binds, or a method call on an env the namespace the
        code runs in holds."""
        builtin = isinstance(call.func, ast.Name) and call.func.id in _BUILTINS and not self.facts.bindings_of(call.func)
        slots: tuple[tuple[str, int], ...] = _TIMEIT_CODE
        globals_at: int | None = None
        if builtin and isinstance(call.func, ast.Name):
            param, globals_at = _BUILTINS[call.func.id]
            slots = ((param, 0),)
        codes: list[tuple[ast.expr, ast.Module]] = []
        for name, position in slots:
            node = call_argument(call, position, name)
            text = _constant_text(node)
            code = _parsed(text) if text is not None else None
            if node is not None and code is not None:
                codes.append((node, code))
        gym_names: set[str] = set()
        for _, code in codes:
            gym_names |= _gym_imports(code) or set()
        namespace = call_argument(call, globals_at, "globals")
        setup = call_argument(call, 1, "setup") if not builtin else None
        setup_text = _constant_text(setup)
        from_main = _main_imports(_parsed(setup_text) if setup_text is not None else None)
        found = []
        for node, code in codes:
            if _gym_imports(code) is not None or _read_names(code) & gym_names:
                found.append(node)
            elif any(self._holds_gym_env(call, namespace, name, builtin or name in from_main) for name in _called_receivers(code)):
                found.append(node)
        return found

    def _holds_gym_env(self, call: ast.Call, namespace: ast.expr | None, name: str, sees_the_module: bool) -> bool:
        """Whether ``name``, read by code ``call`` runs, is a Gym env: through the dict handed
        as its globals, else (exec, eval, or a timeit setup importing from ``__main__``) through
        the names the surrounding code binds."""
        if namespace is not None:
            entries = self._dict_entries(namespace)
            value = entries.get(name)
            return value is not None and self.receivers.kind_of(value).is_gym
        if not sees_the_module:
            return False  # timeit runs its statement in a namespace of its own
        _, bindings = self.facts.resolve(name, self.facts.scope_of(call))
        kinds = []
        for binding in bindings:
            assign = self.facts.parent(binding)
            if isinstance(assign, ast.Assign) and binding in assign.targets:
                kinds.append(self.receivers.kind_of(assign.value))
            else:
                kinds.append(EnvKind.UNKNOWN)
        return bool(kinds) and join_kinds(kinds).is_gym

    def _dict_entries(self, namespace: ast.expr) -> dict[str, ast.expr]:
        """The constant keys of a dict literal, or of the one dict literal a name is bound to."""
        if isinstance(namespace, ast.Name):
            bindings = self.facts.bindings_of(namespace)
            if len(bindings) != 1:
                return {}
            assign = self.facts.parent(bindings[0])
            if not (isinstance(assign, ast.Assign) and bindings[0] in assign.targets):
                return {}
            namespace = assign.value
        if not isinstance(namespace, ast.Dict):
            return {}
        return {
            key.value: value
            for key, value in zip(namespace.keys, namespace.values, strict=True)
            if isinstance(key, ast.Constant) and isinstance(key.value, str)
        }
