"""Writing a rewrite back: atomically, never over someone else's edit, and tidy after a kill.

A rewrite goes to a temporary file next to its target (``.{name}.XXXXXXXX.gymmigrate``,
same folder so the final rename stays on one filesystem) and replaces the target with
one ``os.replace``: a reader, or a run killed at any instant, sees either the old bytes
or the complete new ones, never a mix.

While it writes, a run holds an exclusive ``flock`` on its temporary file, so that one
left behind by a killed run can be told from one another run is still writing.
"""

from __future__ import annotations

import os
import re
import stat
import tempfile
from pathlib import Path

try:
    import fcntl
except ImportError:  # pragma: no cover - not on POSIX (Windows)
    fcntl = None  # type: ignore[assignment]

TEMPORARY_SUFFIX = ".gymmigrate"
# mkstemp's random part is 8 characters of [a-z0-9_]. Anything else is not ours.
_TEMPORARY_NAME = re.compile(r"\..+\.[a-z0-9_]{8}" + re.escape(TEMPORARY_SUFFIX))


class ChangedOnDisk(Exception):
    """The file is no longer what was read: someone edited (or removed) it meanwhile."""


def is_temporary_name(name: str) -> bool:
    """True for the names ``write_atomically`` gives its temporary files."""
    return _TEMPORARY_NAME.fullmatch(name) is not None


def write_atomically(path: Path, data: bytes, *, expected: bytes | None = None) -> None:
    """Replace ``path``'s content with ``data`` in one rename, keeping mode and owner.

    ``expected``: the bytes the rewrite was computed from. If the file holds anything
    else just before the rename (an editor saved it meanwhile), raise ChangedOnDisk and
    leave it as it is. A symbolic link is written through: its target is replaced and
    the link stays a link.
    """
    target = Path(os.path.realpath(path))
    try:
        status = target.stat()
    except FileNotFoundError:
        raise ChangedOnDisk("it was deleted while gymmigrate ran") from None
    fd, temporary = tempfile.mkstemp(prefix=f".{target.name}.", suffix=TEMPORARY_SUFFIX, dir=target.parent)
    try:
        _lock(fd)
        _write_all(fd, data)
        os.fsync(fd)  # the data is on disk before the rename makes it the file
        os.chmod(temporary, stat.S_IMODE(status.st_mode))
        _copy_owner(temporary, status)
        if expected is not None:
            _check_unchanged(target, expected)
        os.replace(temporary, target)
    except BaseException:
        _remove_quietly(temporary)
        raise
    finally:
        os.close(fd)  # releases the lock; on POSIX an open file may be renamed


def _lock(fd: int) -> None:
    if fcntl is not None:
        fcntl.flock(fd, fcntl.LOCK_EX)


def _write_all(fd: int, data: bytes) -> None:
    view = memoryview(data)
    while view:
        written = os.write(fd, view)
        view = view[written:]


def _copy_owner(temporary: str, status: os.stat_result) -> None:
    """Keep the file's owner and group (a run as root must not hand files to root)."""
    if not hasattr(os, "chown"):
        return
    mine = os.stat(temporary)
    if (mine.st_uid, mine.st_gid) == (status.st_uid, status.st_gid):
        return
    try:
        os.chown(temporary, status.st_uid, status.st_gid)
    except PermissionError:
        pass  # an ordinary user cannot give a file away; the file is theirs to write anyway


def _check_unchanged(target: Path, expected: bytes) -> None:
    # The last moment before the rename: an edit that lands after this instant and
    # before the rename is lost, an unavoidable window of microseconds (no file lock
    # binds editors), against the seconds a rewrite takes.
    try:
        current = target.read_bytes()
    except FileNotFoundError:
        raise ChangedOnDisk("it was deleted while gymmigrate ran") from None
    if current != expected:
        raise ChangedOnDisk("it changed while gymmigrate ran")


def _remove_quietly(path: str) -> None:
    try:
        os.unlink(path)
    except FileNotFoundError:
        pass
