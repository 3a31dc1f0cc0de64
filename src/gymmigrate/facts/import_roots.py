"""Which file of the run a dotted import name may name: a relative name's level and
dotted parts, every name a file may be imported as, and of several candidates the one whose
import root is nearest the importer.
"""

from __future__ import annotations

import os
from functools import lru_cache
from pathlib import Path


def import_parts(qualified: str) -> tuple[int, list[str]]:
    """The level of an import name (its leading dots; 0 for an absolute one) and the dotted
    names after them: ``..pkg.Base`` gives ``(2, ["pkg", "Base"])``. A bare ``.`` (``from .
    import *``) gives no names, not one empty name: ``ProjectFacts._module_path`` reads an
    empty module as the package's own ``__init__.py``."""
    names = qualified.lstrip(".")
    return len(qualified) - len(names), names.split(".") if names else []


# Asked again for each name an importer reads from an ambiguous module (thousands of times a
# run), and each answer builds Paths: a pure function of strings, so kept. Bounded, since one
# process may make many runs (the API, the tests).
@lru_cache(maxsize=4096)
def nearest_root(paths: tuple[str, ...], depth: int, importer: str) -> str | None:
    """Of the files a dotted name of ``depth`` parts may name, the one whose import root (the
    folder the name is taken from) is the nearest folder above ``importer``: Python finds
    ``import utils`` from the script's folder or a folder above it (the working directory),
    not from a sibling project's package. None when no root is above it or two are as near."""
    above = {str(p) for p in Path(importer).parents}
    roots: dict[str, list[str]] = {}
    for path in paths:
        folder = Path(path).parent if Path(path).name == "__init__.py" else Path(path).with_suffix("")
        for _ in range(depth):
            folder = folder.parent
        if str(folder) in above:
            roots.setdefault(str(folder), []).append(path)
    if not roots:
        return None
    nearest = roots[max(roots, key=len)]
    return nearest[0] if len(nearest) == 1 else None


def module_names(path: str) -> list[str]:
    """Every dotted name the file may be imported as: ``c``, ``b.c``, ``a.b.c`` for a/b/c.py."""
    parts = list(Path(path).with_suffix("").parts[1:])
    if parts and parts[-1] == "__init__":
        parts.pop()
    return [".".join(parts[i:]) for i in range(len(parts) - 1, -1, -1) if parts[i:]]


_TEST_DIRECTORIES = frozenset({"test", "tests", "testing"})


def is_test_path(path: str) -> bool:
    """A module of the project's tests by the conventions pytest and unittest collect:
    under a ``test``/``tests`` directory, or named ``test_*.py``, ``*_test.py``, ``conftest.py``."""
    parts = os.path.normpath(path).split(os.sep)
    name = parts[-1]
    return (
        any(part in _TEST_DIRECTORIES for part in parts[:-1])
        or name.startswith("test_")
        or name.endswith("_test.py")
        or name == "conftest.py"
    )
