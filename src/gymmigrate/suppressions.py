"""Suppression comments: what a team writes to silence one finding, or a whole file.

- ``# gymmigrate: ignore`` silences every finding on its line;
  ``# gymmigrate: ignore[GM301, GM201]`` only those rules (codes or prefixes).
- ``# noqa: GM301`` does the same the way ruff and flake8 users write it. A bare
  ``# noqa`` silences nothing here: it was written for those tools (an unused or star
  import, a long line), mostly long before the migration, and silencing every finding of
  its line would hide the very import of the removed package that breaks. Codes that are
  not gymmigrate's (``# noqa: E501``) silence nothing either.
- The comment sits on the finding's line or on the first line of the statement that
  holds it (a multi-line call is silenced from its first line).
- ``# gymmigrate: skip-file`` on a line of its own before the first statement (after
  the docstring at most) leaves the whole file alone.

A silenced finding is neither reported nor fixed. Files that do not mention
``gymmigrate:`` or ``noqa`` pay one regex search; only the others are tokenized, and
only when one of their marked lines could silence one of the findings to filter (a
``# noqa: F401`` of another tool cannot).
"""

from __future__ import annotations

import io
import re
import tokenize
from collections.abc import Iterable
from dataclasses import dataclass, field

_MARKER = re.compile(r"gymmigrate:|noqa", re.IGNORECASE)
_IGNORE = re.compile(r"gymmigrate:\s*ignore\b(?:\[(?P<codes>[^\]]*)\])?", re.IGNORECASE)
_NOQA = re.compile(r"\bnoqa\b(?::\s*(?P<codes>[A-Z]+[0-9]+(?:[\s,]+[A-Z]+[0-9]+)*))?", re.IGNORECASE)
_SKIP_FILE = re.compile(r"^[ \t]*#[ \t]*gymmigrate:[ \t]*skip-file\b", re.IGNORECASE | re.MULTILINE)

EVERY_RULE = "*"


@dataclass
class Suppressions:
    """The suppression comments of one file, by line."""

    by_line: dict[int, set[str]] = field(default_factory=dict)

    @classmethod
    def find(cls, text: str, rules: Iterable[str] | None = None) -> Suppressions | None:
        """The file's suppressions, or None when it has none (the common, cheap case).
        With ``rules`` (the codes of the findings to filter), also None when none of
        them could be silenced, which is decided without tokenizing."""
        if _MARKER.search(text) is None:
            return None
        if rules is not None and not _may_silence(text, set(rules)):
            return None
        found = cls()
        for line, comment in _comments(text):
            codes = _codes_silenced(comment)
            if codes:
                found.by_line.setdefault(line, set()).update(codes)
        return found if found.by_line else None

    def silences(self, rule: str, lines: Iterable[int]) -> bool:
        for line in lines:
            codes = self.by_line.get(line)
            if codes and (EVERY_RULE in codes or any(rule.startswith(code) for code in codes)):
                return True
        return False


def skips_file(text: str, first_statement_line: int | None) -> bool:
    """``# gymmigrate: skip-file`` on its own line before the first statement that is not
    the module docstring (anywhere in a file without statements)."""
    if "skip-file" not in text:
        return False
    for match in _SKIP_FILE.finditer(text):
        line = text.count("\n", 0, match.start()) + 1
        if first_statement_line is None or line < first_statement_line:
            return True
    return False


def _codes_silenced(comment: str) -> set[str]:
    codes: set[str] = set()
    for match in _IGNORE.finditer(comment):
        codes |= _code_list(match["codes"])
    for match in _NOQA.finditer(comment):
        if match["codes"] is not None:  # a bare noqa is the linters' (module docstring)
            codes |= _code_list(match["codes"])
    return codes


def _may_silence(text: str, rules: set[str]) -> bool:
    """Whether a comment of ``text`` could silence one of ``rules``, read generously:
    each line with a marker counts as if it were all comment, and every ``noqa`` in it
    as if it started a match. A comment is a line's tail and its matches are some of
    those, so a False here means tokenizing would find nothing that silences them."""
    if not rules:
        return False
    for marker in _MARKER.finditer(text):
        start = max(text.rfind("\n", 0, marker.start()), text.rfind("\r", 0, marker.start())) + 1
        ends = [end for end in (text.find("\n", marker.end()), text.find("\r", marker.end())) if end >= 0]
        line = text[start : min(ends, default=len(text))]
        if "gymmigrate:" in line.lower():
            return True
        for noqa in re.finditer("noqa", line, re.IGNORECASE):
            found = _NOQA.match(line, noqa.start())
            if found is not None and found["codes"] is not None and _silences_one_of(_code_list(found["codes"]), rules):
                return True
    return False


def _silences_one_of(codes: set[str], rules: set[str]) -> bool:
    return EVERY_RULE in codes or any(rule.startswith(code) for code in codes for rule in rules)


def _code_list(text: str | None) -> set[str]:
    if text is None:
        return {EVERY_RULE}
    return {code.strip().upper() for code in re.split(r"[\s,]+", text) if code.strip()}


def _comments(text: str) -> Iterable[tuple[int, str]]:
    """Every comment token (line, text); strings that look like comments are not comments."""
    try:
        for token in tokenize.generate_tokens(io.StringIO(text).readline):
            if token.type == tokenize.COMMENT and _MARKER.search(token.string):
                yield token.start[0], token.string
    except (tokenize.TokenError, SyntaxError):
        return
