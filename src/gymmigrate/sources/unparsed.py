"""What a code cell or block that does not parse holds of Gym's API (GM001's tier).

An exercise cell with ``<YOUR CODE>`` placeholders cannot be migrated; whether a person
must port it by hand depends on the code it holds, not on the words around it: an Actor
class whose docstring says "environment" has nothing to port, a cell that steps an env
or masks a next-state value with ``done`` has. CPython's tokenizer reads such a cell (the
placeholders are operators and names to it) without parsing it; comments and strings
(docstrings too) are skipped.
"""

from __future__ import annotations

import io
import re
import tokenize
from enum import Enum

# A receiver named as an env: ``env``, ``envs``, ``test_env``, ``env_1``, ``environment``.
_ENV_LIKE = re.compile(r"(^|_)(env|envs|environment|environments)(_|$|\d)", re.IGNORECASE)
# A flag that holds the old ``done``: ``done``, ``dones``, ``is_done``, ``done_t``, ``batch_dones``.
_DONE_LIKE = re.compile(r"(^|_)dones?($|_)", re.IGNORECASE)
_ENV_METHODS = frozenset({"reset", "step", "render"})
_GYM_NAMES = frozenset({"gym", "gymnasium", "spaces"})
_SKIPPED = frozenset({tokenize.COMMENT, tokenize.STRING, tokenize.NL, tokenize.NEWLINE, tokenize.INDENT, tokenize.DEDENT})


class UnparsedCode(str, Enum):
    NO_GYM = "no-gym"  # nothing of Gym's API in the code: a note
    GYM_SITES = "gym-sites"  # an env in the code, a make, spaces, done unpacking: port it by hand
    DONE_MASK = "done-mask"  # a done flag masks a value: it must be terminated (GM302)


def classify_unparsed(code: str) -> UnparsedCode:
    tokens = _code_tokens(code)
    texts = [text for _, text in tokens]
    sites = False
    for index, (kind, text) in enumerate(tokens):
        before = texts[index - 1] if index else ""
        after = texts[index + 1] if index + 1 < len(texts) else ""
        if kind == tokenize.NAME and _DONE_LIKE.search(text):
            if _masks(texts, index):
                return UnparsedCode.DONE_MASK
            if _unpacked(tokens, index):
                sites = True  # ``obs, reward, done, info = ...``
        elif kind == tokenize.NAME and (text in _GYM_NAMES or _ENV_LIKE.search(text)):
            sites = True  # gym itself, or code that holds an env (``def play(agent, env)``, ``env.seed(s)``)
        elif kind == tokenize.NAME and text == "make" and after == "(":
            sites = True
        elif kind == tokenize.NAME and text in _ENV_METHODS and before == "." and after == "(":
            receiver = texts[index - 2] if index >= 2 else ""
            if text == "render" or _ENV_LIKE.search(receiver):
                sites = True
    return UnparsedCode.GYM_SITES if sites else UnparsedCode.NO_GYM


def _masks(texts: list[str], index: int) -> bool:
    """``1 - done`` (``1.0 - is_done``), ``~done``, ``not done`` in arithmetic or ``done``
    multiplied: a value kept or dropped by the flag."""
    before = texts[index - 1] if index else ""
    earlier = texts[index - 2] if index >= 2 else ""
    after = texts[index + 1] if index + 1 < len(texts) else ""
    if before == "-" and re.fullmatch(r"1(\.0*)?", earlier):
        return True
    if before == "~":
        return True
    if before == "(" and earlier == "where":
        return True  # ``torch.where(is_done, rewards, target)``: the reward alone where done
    return before == "*" or after == "*"


def _unpacked(tokens: list[tuple[int, str]], index: int) -> bool:
    """The name at ``index`` is a target of a tuple assignment (``s, r, done, _ = ...``):
    no bracket around it, a comma beside it and an ``=`` after it on its logical line (a
    parameter list or a tuple value is no unpacking)."""
    start = index
    while start > 0 and tokens[start - 1][0] != tokenize.NEWLINE:
        start -= 1
    depth, comma = 0, False
    for position in range(start, len(tokens)):
        kind, text = tokens[position]
        if kind == tokenize.NEWLINE:
            return False
        if kind == tokenize.OP and text in ("(", "[", "{"):
            depth += 1
        elif kind == tokenize.OP and text in (")", "]", "}"):
            depth -= 1
        elif position == index and depth != 0:
            return False
        elif depth == 0 and text == ",":
            comma = True
        elif depth == 0 and text == "=":
            return comma and position > index
    return False


def _code_tokens(code: str) -> list[tuple[int, str]]:
    """The NAME, NUMBER and OP tokens of ``code``, as far as the tokenizer gets."""
    out: list[tuple[int, str]] = []
    try:
        for token in tokenize.generate_tokens(io.StringIO(code).readline):
            if token.type == tokenize.NEWLINE:
                out.append((token.type, ""))  # ends a logical line (``_unpacked``)
            elif token.type not in _SKIPPED and token.type != tokenize.ENDMARKER:
                out.append((token.type, token.string))
    except (tokenize.TokenError, SyntaxError, IndentationError, ValueError):
        pass  # an unclosed bracket at the end, an odd indent: what was read still counts
    return out
