"""``[tool.gymmigrate]`` in ``pyproject.toml``: a project's standing choices.

The table is looked for from each path given, walking up to the file system root; the
nearest ``pyproject.toml`` that has a ``[tool.gymmigrate]`` table applies to the files
under it. Command-line flags win over it. An unknown key or a value of the wrong type
is an error that names the key and the file, never silently ignored.

    [tool.gymmigrate]
    select = ["GM"]            # rule codes or prefixes (default: every rule)
    ignore = ["GM9"]
    extend-select = []         # added to select / ignore (also on the command line)
    extend-ignore = []
    exclude = ["legacy/*"]     # globs, relative to this file's folder
    extend-exclude = []
    seed = 0                   # default of rewrite --seed
    docs = false               # also migrate code blocks in Markdown/RST
"""

from __future__ import annotations

import fnmatch
import os
import sys
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from gymmigrate.rules import all_rules
from gymmigrate.selection import SelectionError, check_selector

LIST_KEYS = ("select", "ignore", "extend-select", "extend-ignore", "exclude", "extend-exclude")
KEYS = (*LIST_KEYS, "seed", "docs")


class ConfigError(ValueError):
    """The configuration cannot be used; the message names the key and the file."""


@dataclass(frozen=True)
class Config:
    path: Path | None = None  # the pyproject.toml it came from
    select: tuple[str, ...] | None = None
    ignore: tuple[str, ...] = ()
    extend_select: tuple[str, ...] = ()
    extend_ignore: tuple[str, ...] = ()
    exclude: tuple[str, ...] = ()
    seed: int | None = None
    docs: bool = False

    @property
    def root(self) -> Path | None:
        return self.path.parent if self.path is not None else None

    def excludes(self, file: Path) -> bool:
        """Whether ``file`` matches an ``exclude``/``extend-exclude`` glob: against its path
        relative to the config's folder, that path's leading folders, or its name."""
        if not self.exclude or self.root is None:
            return False
        try:
            relative = Path(os.path.realpath(file)).relative_to(os.path.realpath(self.root)).as_posix()
        except ValueError:
            relative = file.as_posix()
        parts = relative.split("/")
        candidates = {relative, file.name, *("/".join(parts[:i]) for i in range(1, len(parts)))}
        return any(fnmatch.fnmatch(candidate, pattern) for pattern in self.exclude for candidate in candidates)


def find_config(start: Path) -> Config:
    """The configuration that applies at ``start`` (a file, a folder, or a name that need
    not exist, like ``--stdin-filename``); an empty one when there is none."""
    folder = start.absolute()
    if not folder.is_dir():
        folder = folder.parent
    return _config_of(folder)


def forget_configs() -> None:
    _config_of.cache_clear()


@cache
def _config_of(folder: Path) -> Config:
    for candidate in (folder, *folder.parents):
        pyproject = candidate / "pyproject.toml"
        if pyproject.is_file():
            table = _table(pyproject)
            if table is not None:
                return load(pyproject, table)
    return Config()


def _table(pyproject: Path) -> dict | None:
    # The TOML parser loads only where a pyproject.toml is found.
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover
        import tomli as tomllib
    try:
        data = tomllib.loads(pyproject.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError) as exc:
        raise ConfigError(f"{pyproject}: cannot read the file: {exc}") from None
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{pyproject}: not valid TOML: {exc}") from None
    table = data.get("tool", {}).get("gymmigrate")
    if table is not None and not isinstance(table, dict):
        raise ConfigError(f"{pyproject}: [tool.gymmigrate] must be a table")
    return table


def load(path: Path, table: dict) -> Config:
    """Check every key and value of the table."""
    values: dict[str, object] = {}
    for key, value in table.items():
        where = f"{path}: [tool.gymmigrate] {key}"
        if key not in KEYS:
            raise ConfigError(f"{where}: unknown key (known: {', '.join(KEYS)})")
        if key in LIST_KEYS:
            if not isinstance(value, list) or not all(isinstance(item, str) for item in value):
                raise ConfigError(f"{where}: must be a list of strings, got {value!r}")
            value = tuple(item.strip().upper() if "exclude" not in key else item for item in value)
            if "exclude" not in key:
                _check_codes(value, where)
        elif key == "seed" and (isinstance(value, bool) or not isinstance(value, int) or value < 0):
            raise ConfigError(f"{where}: must be a non-negative integer, got {value!r}")
        elif key == "docs" and not isinstance(value, bool):
            raise ConfigError(f"{where}: must be true or false, got {value!r}")
        values[key] = value
    return Config(
        path=path,
        select=values.get("select"),  # type: ignore[arg-type]
        ignore=values.get("ignore", ()),  # type: ignore[arg-type]
        extend_select=values.get("extend-select", ()),  # type: ignore[arg-type]
        extend_ignore=values.get("extend-ignore", ()),  # type: ignore[arg-type]
        exclude=(*values.get("exclude", ()), *values.get("extend-exclude", ())),  # type: ignore[misc]
        seed=values.get("seed"),  # type: ignore[arg-type]
        docs=bool(values.get("docs", False)),
    )


def _check_codes(selectors: tuple[str, ...], where: str) -> None:
    if not selectors:
        return  # nothing to check: the families need not load
    codes = [rule.code for rule in all_rules()]
    for selector in selectors:
        try:
            check_selector(selector, codes)
        except SelectionError as exc:
            raise ConfigError(f"{where}: {exc}") from None
