"""Modules that only edits need, imported the first time an edit uses them.

``libcst.matchers`` costs more to import than everything ``gymmigrate check`` needs on
a clean file; build callbacks that match nodes run only for files that change.
"""

from __future__ import annotations

import importlib
from types import ModuleType
from typing import Any


class LazyModule:
    """Stands for a module; imports it on first attribute access."""

    def __init__(self, name: str) -> None:
        self._name = name
        self._module: ModuleType | None = None

    def __getattr__(self, attribute: str) -> Any:
        if self._module is None:
            self._module = importlib.import_module(self._name)
        return getattr(self._module, attribute)


matchers: Any = LazyModule("libcst.matchers")
