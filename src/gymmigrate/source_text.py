"""A file's source text: decoding, the cheap prefilter, and CPython's parse.

The floor every other layer stands on: what a file says before any rule reads it.
Nothing here imports LibCST; ``check`` and a file with nothing to change never need it.
"""

from __future__ import annotations

import ast
import io
import re
import tokenize

# A file that mentions none of these cannot hold Gym code: skip it before parsing.
# ``envs?\b`` catches env, envs, vec_env, CartPoleEnv, but not os.environ.
_MAY_HOLD_GYM_CODE = re.compile(rb"gym|pettingzoo|baselines|envs?\b|environments?\b", re.IGNORECASE)

_PY2_HINTS = re.compile(rb"^\s*(print\s+[^\s(=]|exec\s+[\"']|except\s+[\w.]+\s*,\s*\w+\s*:)|\bur[\"']|`[^`\n]+`", re.M)


class TransformError(Exception):
    """The file could not be processed; the message says why in one sentence."""


def may_hold_gym_code(source: bytes) -> bool:
    return _MAY_HOLD_GYM_CODE.search(source) is not None


def decode(source: bytes) -> tuple[str, str]:
    """The text of ``source`` and its encoding (PEP 263 cookie or BOM, else UTF-8)."""
    try:
        encoding, _ = tokenize.detect_encoding(io.BytesIO(source).readline)
        text = source.decode(encoding)
    except UnicodeDecodeError as exc:
        raise TransformError(f"cannot decode the file ({exc.reason} at byte {exc.start})") from None
    except (LookupError, SyntaxError) as exc:  # unknown or malformed encoding cookie
        raise TransformError(f"cannot decode the file: {exc}") from None
    if encoding == "utf-8-sig":
        text = text.removeprefix("\ufeff")
    return text, encoding


def looks_like_python2(source: bytes) -> bool:
    return _PY2_HINTS.search(source) is not None


def parse_python(text: str, source: bytes, path: str) -> ast.Module:
    """CPython's parse of ``text``, or TransformError saying in one sentence why not.

    CPython's parser is cheap, has exact positions, and rejects cleanly what would crash
    LibCST's native parser (pathological nesting segfaults it).
    """
    try:
        return ast.parse(text, filename=path)
    except SyntaxError as exc:
        # Gymnasium runs on Python 3 only: such a file needs its Python 3 port first.
        python2 = " (this looks like Python 2 code: port it to Python 3 first, e.g. with 2to3, then run gymmigrate on it)"
        hint = python2 if looks_like_python2(source) else ""
        where = f" at line {exc.lineno}" if exc.lineno else ""
        raise TransformError(f"syntax error{where}: {exc.msg}{hint}") from None
    except (ValueError, RecursionError, MemoryError) as exc:
        raise TransformError(f"cannot parse the file: {exc}") from None


def first_statement_line(tree: ast.Module) -> int | None:
    """The line of the first statement after the module docstring (where ``skip-file`` counts)."""
    body = tree.body
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) and isinstance(body[0].value.value, str):
        body = body[1:]
    return body[0].lineno if body else None
