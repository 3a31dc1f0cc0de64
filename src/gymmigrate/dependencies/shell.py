"""``pip install ...`` commands: in Dockerfiles, and in the shell/console code blocks of
Markdown and reStructuredText pages.

A command is read as the shell splits it into words (whitespace, quotes, backslash-newline
continuations, and ``&&``, ``;``, ``|`` ending it). Words that are options are skipped
(with the value of an option that takes one, such as ``-r file`` or ``-i URL``); every
other word is a requirement and is migrated inside its quotes. A word holding a shell
variable or substitution is not read; if it mentions Gym it is reported.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from gymmigrate.dependencies import mapping
from gymmigrate.dependencies.core import (
    Outcome,
    Positions,
    Site,
    finding,
    migrate_sites,
)
from gymmigrate.dependencies.mapping import GYM_ONLY, Note
from gymmigrate.findings import FixKind

_PIP_INSTALL = re.compile(
    r"(?<![\w./-])(?:pip(?:3(?:\.\d+)?)?|python(?:3(?:\.\d+)?)?\s+-m\s+pip|uv\s+pip)\s+install(?=\s|$)"
)
_VALUE_OPTIONS = frozenset(
    "-r --requirement -c --constraint -e --editable -i --index-url --extra-index-url -f --find-links "
    "-t --target --prefix --root --src --platform --python-version --implementation --abi --upgrade-strategy "
    "--no-binary --only-binary --progress-bar --cache-dir --trusted-host --config-settings -C --log --timeout "
    "--retries --proxy --cert --client-cert --python --report --global-option --install-option".split()
)
_ENDS = ("&&", "||", ";", "|", ")", "\n", "#", ">", "<", "`")


@dataclass(frozen=True)
class Word:
    start: int  # the word's first character (a quote included)
    end: int
    value: str  # without quotes
    inner: tuple[int, int] | None  # the text between the quotes, when the word is one quoted or bare piece


def words(text: str, position: int, limit: int) -> list[Word]:
    """The words of one command starting at ``position``, up to where the command ends."""
    out: list[Word] = []
    i = position
    while i < limit:
        char = text[i]
        if char in " \t\r" or text.startswith("\\\n", i) or text.startswith("\\\r\n", i):
            i += 2 if char == "\\" and text[i + 1] == "\n" else 3 if char == "\\" else 1
            continue
        if any(text.startswith(end, i) for end in _ENDS):
            break
        start = i
        value: list[str] = []
        pieces = 0
        quoted: tuple[int, int] | None = None
        while i < limit and text[i] not in " \t\r\n" and not any(text.startswith(end, i) for end in _ENDS[:5]):
            if text[i] in "\"'":
                quote = text[i]
                close = text.find(quote, i + 1, limit)
                if close < 0:
                    return out
                value.append(text[i + 1 : close])
                quoted = (i + 1, close)
                i = close + 1
            else:
                value.append(text[i])
                i += 1
            pieces += 1
        word_value = "".join(value)
        inner: tuple[int, int] | None = (start, i)
        if quoted is not None:
            inner = quoted if (quoted[0] - 1, quoted[1] + 1) == (start, i) else None
        out.append(Word(start, i, word_value, inner))
    return out


def command_sites(text: str, positions: Positions, regions: list[tuple[int, int]]) -> tuple[list[Site], list]:
    sites: list[Site] = []
    findings = []
    for region_start, region_end in regions:
        for match in _PIP_INSTALL.finditer(text, region_start, region_end):
            line_start = text.rfind("\n", 0, match.start()) + 1
            if text[line_start : match.start()].lstrip().startswith("#"):
                continue  # a comment
            arguments = words(text, match.end(), region_end)
            requirements: list[tuple[Word, tuple[int, int]]] = []  # with the text between the quotes
            skip = False
            for word in arguments:
                if skip:
                    skip = False
                    if word.value and mapping.mentions_gym(word.value) and not word.value.endswith(".txt"):
                        note = Note(GYM_ONLY, FixKind.FLAG, f"`{word.value}` is installed from a path, URL or VCS; left as it is: check it by hand")
                        findings.append(finding(positions, word.start, word.end, note))
                    continue
                if word.value.startswith("-"):
                    skip = word.value in _VALUE_OPTIONS
                    continue
                if "$" in word.value or word.inner is None:
                    if mapping.mentions_gym(word.value):
                        note = Note(GYM_ONLY, FixKind.FLAG, f"`{word.value}` is not a plain requirement (a shell variable or mixed quoting); left as it is")
                        findings.append(finding(positions, word.start, word.end, note))
                    continue
                requirements.append((word, word.inner))
            for word, inner in requirements:
                # A word is dropped only while another requirement keeps the command valid.
                removal = None
                if len(requirements) > 1:
                    line_begin = text.rfind("\n", 0, word.start) + 1
                    if not text[line_begin : word.start].strip():  # first on its line: take the blanks after it
                        after = word.end
                        while after < len(text) and text[after] in " \t":
                            after += 1
                        removal = (word.start, after)
                    else:
                        before = word.start
                        while text[before - 1] in " \t":
                            before -= 1
                        removal = (before, word.end)
                bare = (inner[0], inner[1]) == (word.start, word.end)
                sites.append(Site(inner[0], inner[1], removal=removal, bare_word=bare, group=match.start()))
    return sites, findings


def migrate_dockerfile(text: str) -> Outcome:
    positions = Positions(text)
    sites, findings = command_sites(text, positions, [(0, len(text))])
    outcome = migrate_sites(text, sites, positions)
    outcome.findings.extend(findings)
    return outcome


# -- documentation pages -------------------------------------------------------------------

SHELL_LANGUAGES = frozenset(
    {"bash", "sh", "shell", "console", "zsh", "shell-session", "sh-session", "shellsession", "bash-session", "dockerfile", "docker", "powershell", "ps1", "bat", "cmd", "fish"}
)
_FENCE = re.compile(r"^(?P<indent>[ \t]*)(?P<fence>`{3,}|~{3,})[ \t]*(?P<info>[^\r\n]*)$", re.M)
_DIRECTIVE = re.compile(r"^(?P<indent>[ \t]*)\.\.[ \t]+(?:code-block|code|sourcecode|prompt)::[ \t]*(?P<language>[\w+-]*)", re.M)


def _language(info: str) -> str:
    word = info.strip().strip("{}").split(maxsplit=1)
    return word[0].lstrip(".").rstrip(",").lower() if word else ""


def markdown_regions(text: str) -> list[tuple[int, int]]:
    regions: list[tuple[int, int]] = []
    position = 0
    while True:
        opening = _FENCE.search(text, position)
        if opening is None:
            return regions
        fence = opening["fence"]
        closing = re.compile(rf"^[ \t]*{re.escape(fence[0])}{{{len(fence)},}}[ \t]*\r?$", re.M)
        end = closing.search(text, opening.end())
        if end is None:
            return regions
        if _language(opening["info"]) in SHELL_LANGUAGES:
            regions.append((opening.end(), end.start()))
        position = end.end()


def rst_regions(text: str) -> list[tuple[int, int]]:
    regions = []
    for directive in _DIRECTIVE.finditer(text):
        if directive["language"].lower() not in SHELL_LANGUAGES:
            continue
        indent = len(directive["indent"].expandtabs())
        start = text.find("\n", directive.end())
        if start < 0:
            continue
        end = position = start + 1
        for line in re.finditer(r"[^\n]*\n?", text[position:]):
            if not line.group():
                break
            content = line.group().rstrip("\r\n")
            if content.strip() and len(content) - len(content.lstrip()) <= indent:
                break
            end = position + line.end()
        regions.append((start + 1, end))
    return regions


def migrate_page(text: str, markdown: bool) -> Outcome:
    positions = Positions(text)
    regions = markdown_regions(text) if markdown else rst_regions(text)
    sites, findings = command_sites(text, positions, regions)
    outcome = migrate_sites(text, sites, positions)
    outcome.findings.extend(findings)
    return outcome
