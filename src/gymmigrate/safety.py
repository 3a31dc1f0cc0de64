"""Inputs gymmigrate refuses before parsing, each with a one-sentence reason.

A ``.py`` name does not make a file Python source. Binary data and UTF-16 text (both
hold NUL bytes, which CPython never accepts in source) get a reason a person recognises
instead of a parser's complaint, and a file too large for any hand-written module is
refused without being parsed, since parsing and rule analysis grow with its size.
"""

from __future__ import annotations

import mmap
from collections.abc import Callable
from pathlib import Path

# The largest hand-written modules are a few hundred kilobytes; past this a file is
# generated or data, and analysing it would take minutes.
MAX_SOURCE_BYTES = 1024 * 1024

_UTF16_OR_32_BOMS = (b"\xff\xfe", b"\xfe\xff", b"\x00\x00\xfe\xff")  # UTF-32 LE starts as UTF-16 LE


class Refused(Exception):
    """The file is not something gymmigrate will parse; the message says why."""


def read_source(
    path: Path, may_hold_gym_code: Callable[[bytes], bool], limit: int = MAX_SOURCE_BYTES
) -> bytes | None:
    """The file's bytes; None if it is too large but cannot hold Gym code (skip it).

    Raise Refused if it is too large and may hold Gym code. An oversized file is searched
    through a memory map, never read into memory whole.
    """
    size = path.stat().st_size
    if size <= limit:
        return path.read_bytes()
    with path.open("rb") as handle, mmap.mmap(handle.fileno(), 0, access=mmap.ACCESS_READ) as mapped:
        if not may_hold_gym_code(mapped):  # type: ignore[arg-type]
            return None
    what = "one module" if limit == MAX_SOURCE_BYTES else "this kind of file"
    raise Refused(
        f"the file is too large ({size / 1024 / 1024:.1f} MB; the limit for {what} is"
        f" {limit // 1024 // 1024} MB); left unchanged"
    )


def screen(source: bytes, may_hold_gym_code: Callable[[bytes], bool]) -> bool:
    """True: parse the file. False: skip it, it cannot hold Gym code. Refused: it is not
    Python source.

    UTF-16/32 text is refused even though its interleaved NULs hide any ``gym`` from the
    byte search: it is a script saved in the wrong encoding, which may well be Gym code,
    and skipping it silently would hide it.
    """
    if source.startswith(_UTF16_OR_32_BOMS) and b"\0" in source:
        raise Refused("the file is UTF-16 or UTF-32 text, which Python cannot run as source; left unchanged")
    if not may_hold_gym_code(source):
        return False
    if b"\0" in source:
        raise Refused("binary file (NUL bytes), not Python source; left unchanged")
    return True
