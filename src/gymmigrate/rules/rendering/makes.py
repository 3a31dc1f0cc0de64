"""The edits of make sites: ``render_mode=`` given to a ``gym.make`` (quoted as the call
quotes its strings), gym 0.25's ``"single_rgb_array"`` at a make (GM403), the local
aliases of ``make``, and the makes that cannot take a mode (a registered class whose
``__init__`` has no ``render_mode``)."""

from __future__ import annotations

import ast

from gymmigrate.facts import names as N
from gymmigrate.facts.env_classes import EnvClasses
from gymmigrate.facts.module import keyword, string_value
from gymmigrate.findings import FixKind
from gymmigrate.rules.render_calls import (
    arguments_in_order,
    in_source_order,
    single_frame_fixed,
    with_keyword,
)
from gymmigrate.rules.rendering.common import (
    LEGACY_SINGLE_FRAME,
    RGB_ARRAY,
    RenderingBase,
    RenderSite,
)


class MakeEdits(RenderingBase):
    """The edits of ``gym.make`` calls (mixed into the family)."""

    def _add_mode(self, make: ast.Call, mode: str, quote: str) -> None:
        self._added[id(make)] = mode
        func = self.facts.segment(make.func)
        literal = f"{quote}{mode}{quote}"
        self._give_mode(make, func, literal)

    def _give_mode(self, make: ast.Call, func: str, value: str) -> None:
        def build(node: object) -> object:
            return with_keyword(node, func, "render_mode", value)

        self._mode_builds[id(make)] = (make, build)
        self.plan.replace(make, build)

    def _claim_makes(self, keys: list[int]) -> None:
        """Each site that reports a mode added to its make carries that edit too (the same
        build again, a no-op once applied): selected alone (``--select GM407``), a recorder's
        note still comes with the make's ``render_mode``, whichever site decided it first."""
        for key in keys:
            found = self._mode_builds.get(key)
            if found is not None:
                self.plan.replace(*found)

    def _quote_style(self, make: ast.Call, sites: list[RenderSite]) -> str:
        """Write the mode the way the make call already quotes its strings (else like the render call)."""
        for arg in arguments_in_order(make):
            quote = self._quote(arg.value if isinstance(arg, ast.keyword) else arg)
            if quote is not None:
                return quote
        return next((site.quote for site in sites if site.code == "GM401"), '"')

    def _plan_make_literals(self) -> None:
        """``gym.make(..., render_mode="single_rgb_array")`` (GM403) and 0.25 list readers."""
        calls = [c for name in ("make", *self._make_aliases()) for c in self.facts.calls_by_name.get(name, [])]
        calls.extend(self.facts.attribute_calls.get("make", []))
        for call in in_source_order(calls):
            existing = keyword(call, "render_mode")
            if existing is None or not self._is_make(call):
                continue
            value = string_value(existing.value)
            if value == LEGACY_SINGLE_FRAME:
                self.plan.replace(existing.value, single_frame_fixed)
                self.report(call, "GM403", 'gym 0.25 render_mode "single_rgb_array" is "rgb_array" in Gymnasium')
            elif value == RGB_ARRAY and self._legacy_025:
                self.report(
                    call,
                    "GM403",
                    'in gym 0.25 render_mode="rgb_array" made render() return a list of frames; if this code expects '
                    'a list, use "rgb_array_list"',
                    FixKind.FLAG,
                )

    def _make_aliases(self) -> list[str]:
        """Local names bound to a gym ``make`` by ``from gym import make as ...``."""
        return [
            alias.asname
            for alias, q in self.facts.imports.items()
            if alias.asname and N.strip_gym_prefix(q) in N.GYM_ENV_FACTORIES
        ]

    def _registered_without_render_mode(self, make: ast.Call) -> str | None:
        """A make whose id is not a literal, in a file that registers one of its own classes
        that will not take ``render_mode``: that class may be what the make builds."""
        first = make.args[0] if make.args else None
        project = self.receivers.project
        if project is not None and first is not None:
            # A class another module of the run registers (``pkg/__init__.py``), render_mode
            # not threaded down to it (custom_env/render.py reports why).
            # ``gym.make("pkg:" + name)`` imports ``pkg`` first: what it registers counts too
            prefixed = any(isinstance(n, ast.Constant) and isinstance(n.value, str) and ":" in n.value for n in ast.walk(first))
            found = project.registered_without_render_mode(
                string_value(first) if isinstance(first, ast.Constant) else None,
                script=_is_script(self.facts.tree) and not prefixed,
            )
            if found is not None:
                return found
            # A module of the run registers envs from a data file (ids not visible), and one
            # env class of the run keeps render(mode) with no render_mode (custom_env/render.py).
            kept = project.kept_render_behind_registry()
            if kept is not None:
                return f"{kept} (or a subclass; the run registers envs from data it cannot read, and {kept} keeps its legacy render(mode))"
        if first is None or isinstance(first, ast.Constant):
            return None
        env = EnvClasses.of(self.facts, self.receivers)
        for call in (*self.facts.calls_by_name.get("register", ()), *self.facts.attribute_calls.get("register", ())):
            entry = keyword(call, "entry_point")
            target = entry.value if entry is not None else (call.args[1] if len(call.args) > 1 else None)
            name = target.id if isinstance(target, ast.Name) else None
            text = string_value(target) if target is not None else None
            if name is None and text is not None and ":" in text:
                name = text.rsplit(":", 1)[1]
            classdef = self.facts.classes.get(name) if name else None
            if classdef is not None and not env.takes_render_mode(classdef):
                return classdef.name
        return None


def _is_script(tree: ast.Module) -> bool:
    """A module with an ``if __name__ == "__main__":`` block: a program run by itself, so
    what registers ids in its process is what its own imports run."""
    for statement in tree.body:
        test = statement.test if isinstance(statement, ast.If) else None
        if (
            isinstance(test, ast.Compare)
            and isinstance(test.left, ast.Name)
            and test.left.id == "__name__"
            and len(test.comparators) == 1
            and isinstance(test.comparators[0], ast.Constant)
            and test.comparators[0].value == "__main__"
        ):
            return True
    return False
