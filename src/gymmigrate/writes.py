"""Writing a rewrite back: atomically, never over someone else's edit, and tidy after a kill.

A rewrite goes to a temporary file next to its target (``.{name}.XXXXXXXX.gymmigrate``,
same folder so the final rename stays on one filesystem) and replaces the target with
one ``os.replace``: a reader, or a run killed at any instant, sees either the old bytes
or the complete new ones, never a mix.

A run killed between creating the temporary file and the rename leaves that file behind.
While it writes, a run holds an exclusive ``flock`` on its temporary file, so a later
run can tell an abandoned one (nobody holds the lock) from one another run is still
writing, and removes only the former, and only names of exactly its own pattern.
"""

from __future__ import annotations

import os
import re
import stat
import time
from collections.abc import Iterable
from pathlib import Path

try:
    import fcntl
except ImportError:  # pragma: no cover - not on POSIX (Windows)
    fcntl = None  # type: ignore[assignment]

TEMPORARY_SUFFIX = ".gymmigrate"
# mkstemp's random part is 8 characters of [a-z0-9_]. Anything else is not ours.
_TEMPORARY_NAME = re.compile(r"\..+\.[a-z0-9_]{8}" + re.escape(TEMPORARY_SUFFIX))
# Without flock (not POSIX) an abandoned file is recognised by age alone: no write of a
# single source file takes anywhere near this long.
_ABANDONED_AFTER_SECONDS = 3600.0


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
    import tempfile  # only a run that writes needs it

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


def remove_abandoned_temporaries(directories: Iterable[Path]) -> list[Path]:
    """Delete temporary files an interrupted run left in ``directories``; return them.

    Only regular files named exactly as ``write_atomically`` names them, and only when no
    running gymmigrate is writing them.
    """
    removed: list[Path] = []
    for directory in directories:
        try:
            entries = list(os.scandir(directory))
        except OSError:
            continue  # discovery reports folders it cannot read
        for entry in entries:
            if is_temporary_name(entry.name) and entry.is_file(follow_symlinks=False) and _abandoned(entry.path):
                try:
                    os.unlink(entry.path)
                except OSError:
                    continue
                removed.append(Path(entry.path))
    return removed


def _abandoned(path: str) -> bool:
    """Nobody holds the writer's lock (or, without flock, the file is old)."""
    if fcntl is None:
        try:
            return time.time() - os.stat(path).st_mtime > _ABANDONED_AFTER_SECONDS
        except OSError:
            return False
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0))
    except OSError:
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        return False  # a live run is writing it
    finally:
        os.close(fd)
    # A writer that created its file but has not locked it yet could lose it here; its
    # rename then fails and that file is reported, never half-written.
    return True
