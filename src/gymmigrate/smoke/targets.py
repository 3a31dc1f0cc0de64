"""What ``gymmigrate smoke TARGET`` points at, and loading it.

TARGET is a script (``path/to/train.py``), a class (``path/to/file.py:ClassName`` or
``package.module:ClassName``) or a registered env id (``CartPole-v1``). Every way
loading can fail becomes a ``LoadError`` with one sentence, so the command exits 2
with a message instead of a traceback.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING, TypeVar

if TYPE_CHECKING:  # gymnasium loads only when a target is loaded
    import gymnasium

_T = TypeVar("_T")


class LoadError(Exception):
    """The target could not be loaded or run; the message says why in one sentence."""


class NothingToCheck(LoadError):
    """The script ran to its end without resetting or stepping any gymnasium env."""


@dataclass(frozen=True)
class Target:
    text: str
    kind: str  # "env-id" | "class" | "script"
    location: str  # env id, module path or file, or script path
    class_name: str | None = None


def parse_target(text: str) -> Target:
    if ":" in text:
        location, _, class_name = text.rpartition(":")
        if not location or not class_name.isidentifier():
            raise LoadError(f"{text!r} is not of the form path/to/file.py:ClassName or package.module:ClassName")
        return Target(text, "class", location, class_name)
    if text.endswith(".py") or Path(text).is_file():
        return Target(text, "script", text)
    return Target(text, "env-id", text)


def check_env_id(env_id: str) -> None:
    """Fail early, with gymnasium's own suggestion, on an id that is not registered."""
    import gymnasium

    try:
        gymnasium.spec(env_id)
    except gymnasium.error.Error as exc:
        raise LoadError(f"unknown env id {env_id!r}: {_first_line(exc)}") from None
    except ModuleNotFoundError as exc:  # a namespaced id whose package is missing
        raise LoadError(f"cannot load env id {env_id!r}: {exc}") from None


def load_class(target: Target) -> type[gymnasium.Env]:
    import gymnasium

    module = _import_file(target.location) if target.location.endswith(".py") else _import_module(target.location)
    cls = getattr(module, target.class_name or "", None)
    if cls is None:
        raise LoadError(f"{target.location} has no class {target.class_name!r}")
    if not (isinstance(cls, type) and issubclass(cls, gymnasium.Env)):
        raise LoadError(f"{target.text} is not a gymnasium.Env subclass")
    return cls


def instantiate(cls: type[_T]) -> _T:
    try:
        return cls()
    except Exception as exc:
        raise LoadError(f"cannot construct {cls.__name__}() without arguments: {describe_exception(exc)}") from None


def _import_module(name: str) -> ModuleType:
    try:
        return importlib.import_module(name)
    except Exception as exc:
        raise LoadError(f"cannot import {name}: {describe_exception(exc)}") from None


def _import_file(path_text: str) -> ModuleType:
    path = Path(path_text)
    if not path.is_file():
        raise LoadError(f"no such file: {path_text}")
    module_name = f"_gymmigrate_smoke_{path.stem}"
    spec = importlib.util.spec_from_file_location(module_name, path)
    if spec is None or spec.loader is None:
        raise LoadError(f"cannot import {path_text}")
    module = importlib.util.module_from_spec(spec)
    sys.modules[module_name] = module  # dataclasses and pickling look classes up here
    sys.path.insert(0, str(path.resolve().parent))  # so the file's sibling imports resolve
    try:
        spec.loader.exec_module(module)
    except Exception as exc:
        sys.modules.pop(module_name, None)
        raise LoadError(f"cannot import {path_text}: {describe_exception(exc)}") from None
    finally:
        sys.path.remove(str(path.resolve().parent))
    return module


def describe_exception(exc: BaseException) -> str:
    text = _first_line(exc)
    described = f"{type(exc).__name__}: {text}" if text else type(exc).__name__
    if isinstance(exc, ModuleNotFoundError) and (exc.name or "").split(".")[0] == "gym":
        described += " (this is legacy Gym code: run gymmigrate rewrite on it first)"
    return described


def _first_line(exc: BaseException) -> str:
    lines = str(exc).strip().splitlines()
    return lines[0] if lines else ""
