"""``pyproject.toml``: PEP 621 ``[project] dependencies`` / ``optional-dependencies``,
PEP 735 ``[dependency-groups]``, and Poetry's ``[tool.poetry.dependencies]`` (and
``dev-dependencies``, ``group.<name>.dependencies``).

``tomllib`` says what the file means; a small scanner finds where each string and each
table entry is written (it knows TOML's strings, comments and brackets and nothing else),
and only those characters change. The result is parsed again with ``tomllib`` and must
equal the original data with exactly the intended changes, or the file is left as it is
and reported: a string that also appears elsewhere in the file, a key written in a way
the scanner does not place, any surprise costs a rewrite, never the file.
"""

from __future__ import annotations

import copy
import re
import sys
from bisect import bisect_right
from dataclasses import dataclass

from packaging.requirements import InvalidRequirement, Requirement
from packaging.specifiers import InvalidSpecifier, SpecifierSet
from packaging.utils import canonicalize_name

from gymmigrate.dependencies import mapping
from gymmigrate.dependencies.core import (
    Edit,
    Outcome,
    Positions,
    Site,
    apply_edits,
    finding,
    line_span,
    migrate_sites,
)
from gymmigrate.dependencies.mapping import GYM_ONLY, Note
from gymmigrate.findings import FixKind

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


class PyprojectError(ValueError):
    pass


@dataclass(frozen=True)
class Token:
    """A one-line string: its content is ``text[start:end]``; ``table`` is the header above it."""

    start: int
    end: int
    table: tuple[str, ...]
    escaped: bool


@dataclass(frozen=True)
class Entry:
    """A ``key = value`` line at the top level of a table, starting at ``start``."""

    start: int
    table: tuple[str, ...]


def scan(text: str) -> tuple[list[Token], list[Entry]]:
    tokens: list[Token] = []
    entries: list[Entry] = []
    table: tuple[str, ...] = ()
    depth = 0
    line_start = True
    i, n = 0, len(text)
    while i < n:
        char = text[i]
        if char == "\n":
            line_start = True
            i += 1
            continue
        if char in " \t\r":
            i += 1
            continue
        if char == "#":
            newline = text.find("\n", i)
            i = n if newline < 0 else newline
            continue
        if line_start and depth == 0:
            line_start = False
            if char == "[":
                newline = text.find("\n", i)
                end = n if newline < 0 else newline
                table = _header_path(text[i:end].rstrip("\r"))
                i = end
                continue
            entries.append(Entry(i, table))
        line_start = False
        if char in "\"'":
            if text.startswith(char * 3, i):
                close = text.find(char * 3, i + 3)
                while char == '"' and close > 0 and _escaped(text, close):
                    close = text.find(char * 3, close + 1)
                if close < 0:
                    raise PyprojectError("unterminated multi-line string")
                i = close + 3
                while i < n and text[i] == char:
                    i += 1
                continue
            j = i + 1
            escaped = False
            while j < n and text[j] != char and text[j] != "\n":
                if char == '"' and text[j] == "\\":
                    escaped = True
                    j += 1
                j += 1
            tokens.append(Token(i + 1, j, table, escaped))
            i = j + 1
            continue
        if char in "[{":
            depth += 1
        elif char in "]}":
            depth -= 1
        i += 1
    return tokens, entries


def _escaped(text: str, index: int) -> bool:
    backslashes = 0
    while index - backslashes - 1 >= 0 and text[index - backslashes - 1] == "\\":
        backslashes += 1
    return backslashes % 2 == 1


def _header_path(header: str) -> tuple[str, ...]:
    try:
        data = tomllib.loads(header)
    except tomllib.TOMLDecodeError:
        raise PyprojectError(f"cannot read the table header {header.strip()!r}") from None
    path: list[str] = []
    node: object = data
    while isinstance(node, (dict, list)) and node:
        if isinstance(node, list):
            node = node[-1]
            continue
        (key, node), *_ = node.items()
        path.append(key)
    return tuple(path)


_PEP621_TABLES = {("project",), ("project", "optional-dependencies"), ("dependency-groups",)}


def _requirement_lists(data: dict) -> list[list]:
    lists: list[list] = []
    project = data.get("project", {})
    if isinstance(project.get("dependencies"), list):
        lists.append(project["dependencies"])
    for value in (project.get("optional-dependencies") or {}).values():
        if isinstance(value, list):
            lists.append(value)
    for value in (data.get("dependency-groups") or {}).values():
        if isinstance(value, list):
            lists.append(value)
    return lists


def _poetry_tables(data: dict) -> list[tuple[tuple[str, ...], dict]]:
    poetry = data.get("tool", {}).get("poetry", {})
    tables: list[tuple[tuple[str, ...], dict]] = []
    for key in ("dependencies", "dev-dependencies"):
        if isinstance(poetry.get(key), dict):
            tables.append((("tool", "poetry", key), poetry[key]))
    for name, group in (poetry.get("group") or {}).items():
        if isinstance(group, dict) and isinstance(group.get("dependencies"), dict):
            tables.append((("tool", "poetry", "group", name, "dependencies"), group["dependencies"]))
    return tables


def migrate_pyproject(text: str) -> Outcome:
    try:
        data = tomllib.loads(text)
        tokens, entries = scan(text)
    except (tomllib.TOMLDecodeError, PyprojectError) as exc:
        raise PyprojectError(f"pyproject.toml does not parse: {exc}") from None
    positions = Positions(text)
    wanted = {value for values in _requirement_lists(data) for value in values if isinstance(value, str)}
    starts = [entry.start for entry in entries]
    sites = [
        # group: the entry (``dependencies = [...]``) the string belongs to
        Site(token.start, token.end, removal=line_span(text, token.start, token.end), group=starts[bisect_right(starts, token.start) - 1] if starts else None)
        for token in tokens
        if token.table in _PEP621_TABLES and not token.escaped and text[token.start : token.end] in wanted
    ]
    outcome = migrate_sites(text, sites, positions)
    poetry_changes = _migrate_poetry(text, data, tokens, entries, positions, outcome)
    if not outcome.edits:
        return outcome
    expected = copy.deepcopy(data)
    for values in _requirement_lists(expected):
        values[:] = [outcome.decided.get(v, v) if isinstance(v, str) else v for v in values]
        values[:] = [v for v in values if v != ""]
    for path, table in _poetry_tables(expected):
        for old_key, (new_key, new_value) in poetry_changes.get(path, {}).items():
            del table[old_key]
            table[new_key] = new_value
    try:
        again = tomllib.loads(apply_edits(text, outcome.edits))
    except (tomllib.TOMLDecodeError, ValueError):
        again = None
    if again != expected:
        note = Note(GYM_ONLY, FixKind.FLAG, "the dependency rewrite could not be placed exactly (a requirement string also used elsewhere, or written in a way not read here); file left unchanged: migrate its Gym requirements by hand")
        return Outcome(findings=[finding(positions, 0, 0, note)] + [f for f in outcome.findings if not f.is_change])
    return outcome


# -- Poetry --------------------------------------------------------------------------------

_KEY = re.compile(r"""(?P<quote>["']?)(?P<key>[A-Za-z0-9_.-]+)(?P=quote)[ \t]*=[ \t]*""")
_EXTRAS = re.compile(r"""extras[ \t]*=[ \t]*\[[^\]\n]*\]""")


def poetry_to_pep440(constraint: str) -> SpecifierSet | None:
    """A Poetry version constraint (``^1.2``, ``~1.2``, ``1.2.*``, ``>=1,<2``) as PEP 440."""
    parts: list[str] = []
    for piece in re.split(r"\s*,\s*|\s+(?=[<>=!~^])", constraint.strip()):
        if piece in ("", "*"):
            continue
        if "||" in piece or "|" in piece:
            return None
        operator = re.match(r"[\^~]=?|[<>=!]=?|===?", piece)
        version = piece[operator.end() :].strip() if operator else piece
        op = operator.group() if operator else ""
        if op in ("^", "~"):
            numbers = [int(x) for x in version.split(".") if x.isdigit()]
            if not numbers or len(numbers) != len(version.split(".")):
                return None
            if op == "^":
                bump = next((k for k, x in enumerate(numbers) if x), len(numbers) - 1)
            else:
                bump = 1 if len(numbers) > 1 else 0
            upper = numbers[:bump] + [numbers[bump] + 1]
            parts += [f">={version}", "<" + ".".join(map(str, upper))]
        elif op == "":
            parts.append(f"=={version}")
        else:
            parts.append(f"{'==' if op == '=' else op}{version}")
    try:
        return SpecifierSet(",".join(parts))
    except InvalidSpecifier:
        return None


def _migrate_poetry(
    text: str, data: dict, tokens: list[Token], entries: list[Entry], positions: Positions, outcome: Outcome
) -> dict[tuple[str, ...], dict[str, tuple[str, object]]]:
    """Edits and findings for Poetry dependency tables; returns the intended changes per
    table (old key -> new key, new value) for the verification."""
    tables = dict(_poetry_tables(data))
    changes: dict[tuple[str, ...], dict[str, tuple[str, object]]] = {}
    for entry in entries:
        table = tables.get(entry.table)
        if table is None:
            continue
        key_match = _KEY.match(text, entry.start)
        if key_match is None or (not key_match["quote"] and "." in key_match["key"]):
            continue
        key = key_match["key"]
        if key not in table or key == "python":
            continue
        value = table[key]
        line_end = text.find("\n", key_match.end())
        line_end = len(text) if line_end < 0 else line_end
        value_tokens = [t for t in tokens if key_match.end() <= t.start < line_end]
        change = _poetry_entry(text, key, value, key_match, value_tokens, line_end, positions, outcome)
        if change is not None:
            changes.setdefault(entry.table, {})[key] = change
    return changes


def _poetry_entry(
    text: str,
    key: str,
    value: object,
    key_match: re.Match[str],
    value_tokens: list[Token],
    line_end: int,
    positions: Positions,
    outcome: Outcome,
) -> tuple[str, object] | None:
    """One Poetry entry (``gym = "^0.21"``, ``gym = {version = ..., extras = [...]}``):
    its edits and findings go to ``outcome``; returns the new key and value, or None."""
    if isinstance(value, str):
        constraint, extras, version_token = value, [], (value_tokens[0] if value_tokens else None)
    elif isinstance(value, dict) and not ({"git", "path", "url"} & set(value)):
        constraint, extras = value.get("version", "*"), list(value.get("extras", []))
        version_token = next((t for t in value_tokens if re.search(r"version[ \t]*=[ \t]*[\"']$", text[: t.start])), None)
    else:
        if mapping.mentions_gym(key):
            note = Note(GYM_ONLY, FixKind.FLAG, f"`{key}` is a Poetry dependency read from git, a path or a URL, or a list of constraints; left as it is")
            outcome.findings.append(finding(positions, key_match.start("key"), key_match.end("key"), note))
        return None
    specifier = poetry_to_pep440(constraint) if isinstance(constraint, str) else None
    extras_text = f"[{','.join(extras)}]" if extras else ""
    try:
        requirement = Requirement(f"{key}{extras_text}{specifier if specifier is not None else ''}")
    except InvalidRequirement:  # a key that is no package name: not ours
        return None
    if specifier is None and canonicalize_name(key) != "gym":
        if mapping.decide(Requirement(f"{key}{extras_text}")).notes:
            note = Note(GYM_ONLY, FixKind.FLAG, f"cannot read the Poetry constraint `{constraint}` of `{key}`; left as it is")
            outcome.findings.append(finding(positions, key_match.start("key"), key_match.end("key"), note))
        return None
    decision = mapping.decide(requirement)
    start, end = key_match.start("key"), key_match.end("key")
    if decision.name is None:  # the decision does not rewrite
        outcome.findings.extend(finding(positions, start, end, note) for note in decision.notes)
        return None
    new_value: object
    code = next((note.code for note in decision.notes if note.kind.rewrites), mapping.GYM_PACKAGE)
    edits: list[Edit] = []
    if decision.name != key and canonicalize_name(decision.name) != canonicalize_name(key):
        edits.append(Edit(start, end, decision.name, code=code))
    new_key = decision.name if edits else key
    if isinstance(value, str):
        if version_token is None:
            return None
        edits.append(Edit(version_token.start, version_token.end, decision.specifier, code=code))
        new_value = decision.specifier
    else:
        new_value = dict(value)
        if version_token is not None:
            edits.append(Edit(version_token.start, version_token.end, decision.specifier, code=code))
            new_value["version"] = decision.specifier
        elif decision.specifier:
            return None  # an inline table without a version: nothing to pin in place
        if extras != decision.extras:
            found = _EXTRAS.search(text, key_match.end(), line_end)
            if found is None:
                return None
            if decision.extras:
                quote = '"' if '"' in found.group() or "'" not in found.group() else "'"
                rendered = "extras = [" + ", ".join(f"{quote}{e}{quote}" for e in decision.extras) + "]"
                edits.append(Edit(found.start(), found.end(), rendered, code=code))
                new_value["extras"] = decision.extras
            else:
                span = _without_extras(text, found.start(), found.end())
                edits.append(Edit(span[0], span[1], "", code=code))
                del new_value["extras"]
    outcome.edits.extend(edits)
    outcome.findings.extend(finding(positions, start, end, note) for note in decision.notes)
    return new_key, new_value


def _without_extras(text: str, start: int, end: int) -> tuple[int, int]:
    """The span of ``extras = [...]`` with the comma that separates it from its neighbour."""
    after = re.match(r"[ \t]*,[ \t]*", text[end:])
    if after:
        return start, end + after.end()
    before = re.search(r"[ \t]*,[ \t]*$", text[:start])
    return (before.start() if before else start), end


__all__ = ["PyprojectError", "migrate_pyproject", "poetry_to_pep440"]
