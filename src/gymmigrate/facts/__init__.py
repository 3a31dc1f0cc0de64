"""Facts about a module, computed once from CPython's ``ast`` and shared by every rule."""

from gymmigrate.facts.module import ModuleFacts, Scope

__all__ = ["ModuleFacts", "Scope"]
