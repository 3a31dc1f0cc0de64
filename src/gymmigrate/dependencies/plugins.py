"""GM111: ``gym.envs`` plugin entry points, which Gymnasium no longer loads.

gym 0.22-0.26 called, on ``import gym``, every function a package declared in the
``gym.envs`` entry-point group (``entry_points={"gym.envs": ["__root__ = pkg:register"]}``
in ``setup.py``, ``[options.entry_points]`` in ``setup.cfg``,
``[project.entry-points."gym.envs"]`` in ``pyproject.toml``); a package registered its
env ids that way and never called its own register function. Gymnasium 1.x loads no
plugins, so after the migration no such id exists.

``plugin_entries`` finds the entries (pure: text in, entries out); the run resolves each
to the module of the run it names (``runner``), the Python engine appends the call to that
module (``rules/env_ids/plugins.py``: importing the package registers its envs, as
Gymnasium-era packages do), and ``plugin_findings`` reports each entry point in the
dependency file with what became of it. The entry point itself stays: it is harmless,
and gym still reads it where gym is installed.
"""

from __future__ import annotations

import ast
import re
import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING

from gymmigrate.dependencies.positions import Positions
from gymmigrate.findings import Finding, FixKind

if TYPE_CHECKING:
    from collections.abc import Mapping

CODE = "GM111"
GROUP = "gym.envs"
# Plugin names gym 0.26 loaded into the root namespace; any other name was a namespace.
ROOT_NAMES = frozenset({"__root__", "__internal__"})

_SPEC = re.compile(r"\s*(?P<name>[^=\s]+)\s*=\s*(?P<module>[\w.]+)\s*(?::\s*(?P<attr>[\w.]+))?\s*(?:\[[^\]]*\])?\s*")


@dataclass(frozen=True)
class PluginEntry:
    """One ``name = module:attr`` of the ``gym.envs`` group, where the file spells it."""

    name: str
    module: str
    attr: str  # "" when the entry names no attribute (gym refused those)
    line: int
    column: int

    @property
    def target(self) -> str:
        return f"{self.module}:{self.attr}" if self.attr else self.module

    @property
    def namespace(self) -> str | None:
        """The namespace gym registered the plugin's ids in (None: the root one)."""
        return None if self.name in ROOT_NAMES else self.name


# What the run did with one entry (its target): the module (as shown) that now calls the
# function on import, or None and the reason why no module does.
Route = tuple[str | None, str]


def plugin_entries(kind: str, text: str) -> list[PluginEntry]:
    """The ``gym.envs`` entries of a ``setup.py``, ``setup.cfg`` or ``pyproject.toml`` text;
    [] for other kinds, for a text without the group, and for a file that does not parse."""
    if GROUP not in text:
        return []
    if kind == "setup.py":
        return _from_setup_py(text)
    if kind == "setup.cfg":
        return _from_setup_cfg(text)
    if kind == "pyproject.toml":
        return _from_pyproject(text)
    return []


def plugin_findings(kind: str, text: str, routes: Mapping[str, Route] | None) -> list[Finding]:
    """One GM111 finding per entry point. ``routes`` (target -> route) comes from the run;
    None when the file is migrated on its own."""
    findings = []
    for entry in plugin_entries(kind, text):
        called_in, reason = (None, "this file was migrated without the package") if routes is None else routes.get(entry.target, (None, "its module is not part of this run"))
        call = f"`{entry.attr}()`" if entry.attr else "the register function"
        if entry.namespace:
            call += f" inside `gymnasium.envs.registration.namespace({entry.namespace!r})`"
        head = f"Gymnasium loads no `{GROUP}` plugins: the entry point `{entry.name} = {entry.target}` registers nothing now"
        if called_in:
            message = (
                f"{head}; {call} is called at the end of `{called_in}`, so importing the package registers its envs "
                f"(import it before `gymnasium.make`, or make `\"{entry.module.split('.')[0]}:ID\"`); the entry point is left for gym"
            )
            kind_of_fix = FixKind.ASSIST
        else:
            message = (
                f"{head}, and `{entry.target}` was not changed ({reason}): call {call} when the package is imported "
                "(at the end of that module), or migrate the package with this file"
            )
            kind_of_fix = FixKind.FLAG
        findings.append(Finding(entry.line, entry.column, CODE, kind_of_fix, message))
    return findings


def parse_spec(name_and_value: str, line: int, column: int) -> PluginEntry | None:
    match = _SPEC.fullmatch(name_and_value)
    if match is None:
        return None
    return PluginEntry(match["name"], match["module"], match["attr"] or "", line, column)


# --- setup.py ---------------------------------------------------------------------------


def _from_setup_py(text: str) -> list[PluginEntry]:
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            tree = ast.parse(text)
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        return []
    assigned: dict[str, ast.expr] = {}
    for statement in tree.body:
        if isinstance(statement, ast.Assign) and len(statement.targets) == 1 and isinstance(statement.targets[0], ast.Name):
            assigned[statement.targets[0].id] = statement.value
    entries: list[PluginEntry] = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        func = node.func
        if not ((isinstance(func, ast.Name) and func.id == "setup") or (isinstance(func, ast.Attribute) and func.attr == "setup")):
            continue
        for keyword in node.keywords:
            if keyword.arg != "entry_points":
                continue
            value = keyword.value
            if isinstance(value, ast.Name):
                value = assigned.get(value.id, value)
            entries.extend(_group_of_setup_value(value))
    return entries


def _group_of_setup_value(value: ast.expr) -> list[PluginEntry]:
    found: list[PluginEntry] = []
    if isinstance(value, ast.Dict):
        for key, item in zip(value.keys, value.values):
            if isinstance(key, ast.Constant) and key.value == GROUP:
                found.extend(_setup_strings(item))
    elif isinstance(value, ast.Constant) and isinstance(value.value, str):  # an ini-style text
        found.extend(_ini_group(value.value, value.lineno, value.col_offset))
    return found


def _setup_strings(item: ast.expr) -> list[PluginEntry]:
    elements = item.elts if isinstance(item, (ast.List, ast.Tuple)) else [item]
    found = []
    for element in elements:
        if isinstance(element, ast.Constant) and isinstance(element.value, str):
            for line in element.value.splitlines():
                if line.strip():
                    entry = parse_spec(line, element.lineno, element.col_offset)
                    if entry is not None:
                        found.append(entry)
    return found


def _ini_group(text: str, line: int, column: int) -> list[PluginEntry]:
    found, inside = [], False
    for raw in text.splitlines():
        stripped = raw.strip()
        if stripped.startswith("["):
            inside = stripped == f"[{GROUP}]"
        elif inside and stripped and not stripped.startswith(("#", ";")):
            entry = parse_spec(stripped, line, column)
            if entry is not None:
                found.append(entry)
    return found


# --- setup.cfg --------------------------------------------------------------------------

_SECTION = re.compile(r"\[(?P<name>[^\]]+)\]\s*")


def _from_setup_cfg(text: str) -> list[PluginEntry]:
    positions = Positions(text)
    found: list[PluginEntry] = []
    section, collecting = "", False
    for match in re.finditer(r"[^\n]*", text):
        content = match.group().rstrip("\r")
        stripped = content.strip()
        if not stripped or stripped.startswith(("#", ";")):
            continue
        line, _ = positions.of(match.start())
        if content[:1] not in (" ", "\t"):
            header = _SECTION.fullmatch(content)
            if header:
                section, collecting = header["name"].strip(), False
                continue
            key, _, value = content.partition("=")
            collecting = section == "options.entry_points" and key.strip() == GROUP
            if collecting and value.strip():
                entry = parse_spec(value, line, 0)
                if entry is not None:
                    found.append(entry)
        elif collecting:
            entry = parse_spec(stripped, line, len(content) - len(content.lstrip()))
            if entry is not None:
                found.append(entry)
    return found


# --- pyproject.toml ---------------------------------------------------------------------

_TOML_GROUP = re.compile(r"""^\s*\[\s*(?:project\s*\.\s*entry-points|tool\s*\.\s*poetry\s*\.\s*plugins)\s*\.\s*(["'])gym\.envs\1\s*\]\s*$""")
_TOML_ENTRY = re.compile(r"""^\s*(?P<name>"[^"]+"|'[^']+'|[\w.-]+)\s*=\s*(["'])(?P<value>[^"']+)\2\s*(?:#.*)?$""")


def _from_pyproject(text: str) -> list[PluginEntry]:
    found: list[PluginEntry] = []
    inside = False
    for number, content in enumerate(text.splitlines(), start=1):
        stripped = content.strip()
        if stripped.startswith("["):
            inside = _TOML_GROUP.match(content) is not None
            continue
        if not inside or not stripped or stripped.startswith("#"):
            continue
        match = _TOML_ENTRY.match(content)
        if match is None:
            continue
        name = match["name"].strip("\"'")
        entry = parse_spec(f"{name} = {match['value']}", number, len(content) - len(content.lstrip()))
        if entry is not None:
            found.append(entry)
    return found
