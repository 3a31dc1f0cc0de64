"""Line-oriented dependency files: pip requirements/constraints files, conda
``environment.yml``, ``setup.cfg``.

Each finds the requirement text on its lines, as pip, conda and setuptools read them, and
hands the spans to ``core.migrate_sites``. Options (``-r``, ``--index-url``), comments,
markers, ``--hash`` options and line endings are never part of a span, so they stay.
"""

from __future__ import annotations

import re

from gymmigrate.dependencies import mapping
from gymmigrate.dependencies.core import (
    Outcome,
    Positions,
    Site,
    finding,
    line_span,
    migrate_sites,
)
from gymmigrate.dependencies.mapping import GYM_ONLY, Note
from gymmigrate.findings import FixKind

# pip: a comment starts at "#" at the start of a line or after whitespace.
_COMMENT = re.compile(r"(^|\s)#")
# Per-requirement options (--hash, --config-settings, --global-option) follow the requirement.
_OPTION = re.compile(r"\s--?[A-Za-z]")


def physical_lines(text: str) -> list[tuple[int, int]]:
    """(start, end) of each line, its line ending included. Only "\\n" ends a line."""
    return [(match.start(), match.end()) for match in re.finditer(r"[^\n]*\n|[^\n]+\Z", text)]


def _content_end(text: str, start: int, end: int) -> int:
    """Where a line's content ends: before its line ending."""
    while end > start and text[end - 1] in "\r\n":
        end -= 1
    return end


def requirements_sites(text: str, positions: Positions) -> tuple[list[Site], list]:
    sites: list[Site] = []
    findings = []
    lines = physical_lines(text)
    index = 0
    while index < len(lines):
        first = index
        start = lines[first][0]
        # A line ending with a backslash continues on the next (hash lists).
        while index + 1 < len(lines) and text[lines[index][0] : _content_end(text, *lines[index])].endswith("\\"):
            index += 1
        logical_end = lines[index][1]
        index += 1
        line_end = _content_end(text, *lines[first])
        content = text[start:line_end]
        comment = _COMMENT.search(content)
        body_end = start + (comment.start() if comment else len(content))
        stripped = text[start:body_end].strip()
        if not stripped:
            continue
        body_start = start + (len(text[start:body_end]) - len(text[start:body_end].lstrip()))
        if stripped.startswith("-"):
            if re.match(r"(-e|--editable)\b", stripped) and mapping.mentions_gym(stripped):
                note = Note(GYM_ONLY, FixKind.FLAG, f"`{stripped}` is an editable or VCS install; left as it is: check it by hand")
                findings.append(finding(positions, body_start, body_end, note))
            continue
        option = _OPTION.search(text, body_start, body_end)
        requirement_end = option.start() if option else body_end
        requirement_end = body_start + len(text[body_start:requirement_end].rstrip().removesuffix("\\").rstrip())
        hashed = "--hash" in text[start:logical_end]
        sites.append(Site(body_start, requirement_end, removal=(start, logical_end), hashed=hashed))
    return sites, findings


def migrate_requirements(text: str) -> Outcome:
    positions = Positions(text)
    sites, findings = requirements_sites(text, positions)
    outcome = migrate_sites(text, sites, positions)
    outcome.findings.extend(findings)
    return outcome


# -- conda environment.yml -----------------------------------------------------------------

_KEY = re.compile(r"(?P<indent>[ \t]*)(?P<key>[\w.-]+)\s*:")
_ITEM = re.compile(r"(?P<indent>[ \t]*)-[ \t]+(?P<value>[^\r\n]*)")


def migrate_environment(text: str) -> Outcome:
    """The ``dependencies:`` list (conda match specs) and its ``- pip:`` list (PEP 508)."""
    positions = Positions(text)
    sites: list[Site] = []
    in_dependencies = False
    pip_indent: int | None = None
    for start, end in physical_lines(text):
        content = text[start:_content_end(text, start, end)]
        if not content.strip() or content.lstrip().startswith("#"):
            continue
        key = _KEY.match(content)
        if key and not key["indent"]:
            in_dependencies = key["key"] == "dependencies"
            pip_indent = None
            continue
        item = _ITEM.fullmatch(content)
        if not in_dependencies or item is None:
            continue
        indent = len(item["indent"])
        if pip_indent is not None and indent <= pip_indent:
            pip_indent = None
        value = item["value"]
        if re.fullmatch(r"pip\s*:\s*(#.*)?", value):
            pip_indent = indent
            continue
        value_start = start + item.start("value")
        comment = _COMMENT.search(value)
        value_text = value[: comment.start()] if comment else value
        value_text = value_text.rstrip()
        quote = value_text[:1] if value_text[:1] in "\"'" and value_text.endswith(value_text[:1]) and len(value_text) > 1 else ""
        inner_start = value_start + len(quote)
        inner_end = value_start + len(value_text) - len(quote)
        if inner_end <= inner_start:
            continue
        sites.append(Site(inner_start, inner_end, removal=(start, end), conda=pip_indent is None, group=pip_indent is None))
    return migrate_sites(text, sites, positions)


# -- setup.cfg -----------------------------------------------------------------------------

_SECTION = re.compile(r"\[(?P<name>[^\]]+)\]\s*")
_CFG_KEY = re.compile(r"(?P<key>[\w.-]+)\s*[=:]\s*(?P<value>.*)")
_REQUIREMENT_KEYS = frozenset({"install_requires", "tests_require", "setup_requires"})


def migrate_setup_cfg(text: str) -> Outcome:
    """``[options] install_requires`` (and ``tests_require``, ``setup_requires``) and every
    key of ``[options.extras_require]``: one requirement per value line."""
    positions = Positions(text)
    sites: list[Site] = []
    section = ""
    key_name = ""
    collecting = False
    for start, end in physical_lines(text):
        content = text[start:_content_end(text, start, end)]
        stripped = content.strip()
        if not stripped or stripped.startswith(("#", ";")):
            continue
        continued = content[:1] in (" ", "\t")
        if not continued:
            header = _SECTION.fullmatch(content)
            if header:
                section = header["name"].strip()
                collecting = False
                continue
            key = _CFG_KEY.fullmatch(content)
            collecting = key is not None and (
                (section == "options" and key["key"] in _REQUIREMENT_KEYS) or section == "options.extras_require"
            )
            key_name = key["key"] if key else ""
            if key is None or not collecting or not key["value"].strip():
                continue
            value_start = start + key.start("value")
        elif collecting:
            value_start = start + len(content) - len(content.lstrip())
        else:
            continue
        value = text[value_start:start + len(content)]
        if value.startswith(("file:", "attr:")):
            continue
        comment = _COMMENT.search(value)
        value_end = value_start + len((value[: comment.start()] if comment else value).rstrip())
        removal = line_span(text, value_start, value_end) if continued else None
        sites.append(Site(value_start, value_end, removal=removal, group=(section, key_name)))
    return migrate_sites(text, sites, positions)
