"""LibCST, loaded the first time an edit is built or applied.

``import libcst`` costs more than everything ``gymmigrate check`` needs on a clean file,
and a run with nothing to change never needs it. Rules record builds that name ``cst``
and ``m`` from here; the module is imported when a build first runs. Modules whose
classes derive from LibCST's (transformers, visitors) form the apply layer; the engine
loads them on first use. Type checkers see the real modules.
"""

from __future__ import annotations

import importlib
from types import ModuleType
from typing import TYPE_CHECKING, Any


class LazyModule:
    """Stands for a module; imports it on first attribute access, then keeps each
    attribute it hands out, so later reads cost a plain attribute lookup."""

    def __init__(self, name: str) -> None:
        self._name = name
        self._module: ModuleType | None = None

    def __getattr__(self, attribute: str) -> Any:
        if self._module is None:
            self._module = importlib.import_module(self._name)
        value = getattr(self._module, attribute)
        setattr(self, attribute, value)
        return value


if TYPE_CHECKING:
    import libcst as cst
    import libcst.matchers as matchers
else:
    cst = LazyModule("libcst")
    matchers = LazyModule("libcst.matchers")
