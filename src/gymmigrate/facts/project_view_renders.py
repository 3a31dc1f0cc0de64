"""What one file asks of the run about renders (``RenderView``, a part of ``ProjectView``):
which constructors of the run get a render mode, and which classes keep render(mode).
"""

from __future__ import annotations

import ast
import os
from collections.abc import Collection, Mapping
from typing import TYPE_CHECKING

from gymmigrate.facts.frame_modes import FRAME_MODES

if TYPE_CHECKING:
    from gymmigrate.facts.project import ProjectFacts


class RenderView:
    """The run's render facts as one file sees them (``facts`` and ``path`` are ``ProjectView``'s)."""

    facts: ProjectFacts
    path: str

    def render_called_elsewhere(self) -> bool:
        """The same for ``x.render(mode)``: this module's env classes keep render(mode)."""
        return self.path in self.facts.render_called

    def kept_mode_render(self) -> tuple[str, str, frozenset[str]] | None:
        """(path, class, the names this module imports it by) of the one env class of the run
        this module reaches whose render() takes ``mode``, where this module renders an
        untraced ``x.render(mode)`` (``ProjectFacts.kept_mode_renders``): that def keeps
        ``mode`` for its calls."""
        return self.facts.kept_mode_renders.get(self.path)

    def settled_render(self, qualname: str, param: str) -> list[str]:
        """``cli.py:5`` for each constructor in another module that gets ``render_mode="human"``
        for the bare renders of ``param`` of this file's ``qualname``, when every call of the
        def passes an env it builds (``ProjectFacts.settled_renders``); empty otherwise."""
        return [
            f"{os.path.relpath(path, os.path.dirname(self.path))}:{line}"
            for path, line, _ in self.facts.settled_renders.get((self.path, qualname, param), ())
        ]

    def gives_render_modes(self) -> bool:
        """This file has a constructor that ``gets_render_mode``."""
        return any(path == self.path for path, _, _ in self.facts.render_mode_constructions)

    def gets_render_mode(self, call: ast.Call) -> bool:
        """``call`` of this file is a constructor that gets ``render_mode="human"`` for the bare
        renders of a def of another module it is passed to (``settled_render``)."""
        return (self.path, call.lineno, call.col_offset) in self.facts.render_mode_constructions

    def handed_render_mode(self, call: ast.Call) -> str | None:
        """The frame mode ``call``, a ``gym.make`` of this file, gets for the renders of the
        calls of other modules it is handed to (``ProjectFacts.handed_render_modes``)."""
        return self.facts.handed_render_modes.get((self.path, call.lineno, call.col_offset))

    def gives_handed_modes(self) -> bool:
        """This file has a make that gets a ``handed_render_mode``."""
        return any(path == self.path for path, _, _ in self.facts.handed_render_modes)

    def settled_mode_render(self, qualname: str, param: str) -> tuple[str, list[str]] | None:
        """(mode, ``main.py:32`` for each make) where every call of the run passes ``param`` of
        this file's ``qualname`` an env made in another module that gets the one frame mode
        its renders ask (``ProjectFacts.settled_mode_renders``); None otherwise."""
        found = self.facts.settled_mode_renders.get((self.path, qualname, param))
        if found is None:
            return None
        mode, makes = found
        return mode, sorted({f"{os.path.relpath(path, os.path.dirname(self.path))}:{line}" for path, line, _ in makes})

    def kept_render_behind_registry(self) -> str | None:
        """A class of the run that keeps its legacy render(mode) and takes no render_mode,
        where this module imports one that registers envs from data (``opaque_kept_renders``)."""
        return self.facts.opaque_kept_renders.get(self.path)

    def registered_without_render_mode(self, env_id: str | None, script: bool = False) -> str | None:
        """The class of the run that ``gymnasium.make(env_id)`` builds (any registered one
        when ``env_id`` is None: not a literal) if its constructor takes no ``render_mode``.
        In a ``script`` (a module run by itself), an id that is not a literal names only the
        classes whose registering module its imports may run."""
        ids = self.facts.no_render_mode_ids
        if env_id is not None:
            return ids.get(env_id)
        # A registration runs when its module is imported: an id whose registering modules a
        # script's imports never run does not exist where it makes its env. Every id counts
        # in a module that is not a script (a module with no Gym code, which the run does not
        # read, may import the registrar before it), in a run with a packaging file (an
        # installed package may be imported by an id's ``pkg:`` prefix, a ``gym.envs`` entry
        # point by gym itself), and for a registrar below the script's directory (importable
        # by such a prefix from the command line).
        everything = not script or bool(self.facts.plugin_routes)
        registrars = self.facts.no_render_mode_registrars
        reached = self._imports_reach()
        below = os.path.dirname(self.path) + os.sep

        def counts(key: str | None) -> bool:
            paths = registrars.get(key)
            return everything or paths is None or bool(paths & reached) or any(p.startswith(below) for p in paths)

        return next(iter(sorted(name for key, name in ids.items() if counts(key))), None)

    def _imports_reach(self) -> set[str]:
        """The modules of the run that may have been imported in a process that runs this
        one: those its imports run, and, for each module that imports it (at any depth),
        those that module's imports run (a script may import the registrar, then this)."""
        imports = self.facts.module_imports
        importers: dict[str, set[str]] = {}
        for path, found in imports.items():
            for imported in found:
                importers.setdefault(imported, set()).add(path)
        roots = _closure({self.path}, importers)
        return _closure(roots, imports)

    def bare_render_keeps_default(self, env_id: str | None) -> bool:
        """``gymnasium.make(env_id)`` builds a class of the run that takes no ``render_mode``
        but whose render() gives ``mode`` a default (``ProjectFacts.default_mode_ids``)."""
        return env_id is not None and env_id in self.facts.default_mode_ids

    def made_render(self, name: str) -> bool:
        """This module's class ``name`` defines the render() that ``gymnasium.make`` of an id
        the run registers reaches (``ProjectFacts.registered_renders``)."""
        return (self.path, name) in self.facts.registered_renders

    def draws_only_in_render(self, env_id: str) -> bool:
        """``gymnasium.make(env_id)`` builds an env class of the run whose drawing is its
        render() alone (``ProjectFacts.render_only_ids``); ``module:id`` names the id after
        the colon."""
        return env_id.rpartition(":")[2] in self.facts.render_only_ids

    def takes_render_mode(self, qualified: str) -> bool:
        """An imported class of the run whose constructor takes ``render_mode`` once migrated
        (its own, or threaded down from a base: ``thread_render_mode``)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split[1] in self.facts.render_mode_classes.get(split[0], ())

    def steps_draw_on_own_flags(self, qualified: str) -> bool:
        """An imported class of the run whose step() and reset() draw only under conditions of
        its own, never by ``render_mode`` (``render_modes.steps_draw_on_own_flags``)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.own_flag_steps

    def renders_nothing(self, qualified: str) -> bool:
        """An imported class of the run whose render() is a stub (it renders no env)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.silent_renders

    def class_where(self, qualified: str) -> tuple[str, str] | None:
        """(module path, class) of an imported class of the run that ``frame_modes`` knows."""
        split = self.facts._split(qualified, self.path)
        return split if split is not None and split in self.facts.frame_classes else None

    def declares_no_frames(self, where: tuple[str, str]) -> bool:
        """The class of the run, or the one base it inherits its metadata from (each of the
        run), declares render modes and none is a frame mode (``frame_modes``)."""
        seen: set[tuple[str, str]] = set()
        current: tuple[str, str] | None = where
        while current is not None and current not in seen and current in self.facts.frame_classes:
            seen.add(current)
            modes = self.facts.frame_classes[current]
            if modes is not None:
                return not FRAME_MODES & set(modes)
            bases = self.facts.class_bases.get(current, ())
            current = bases[0] if len(bases) == 1 else None
        return False

    def render_forward(self, qualified: str) -> str | None:
        """For an imported class of the run whose render() forwards bare to the env it holds
        (``ModuleSummary.render_forwards``), the module of that forward as a reader of this
        file finds it (no line: the run may move it, adding imports above it)."""
        split = self.facts._split(qualified, self.path)
        found = self.facts.render_forwards.get(split) if split is not None else None
        if found is None or found[0] == self.path:
            return None
        return os.path.relpath(found[0], os.path.dirname(self.path))

    def renders_wrapped_env(self, qualified: str) -> bool:
        """An imported name of the run is a Gym wrapper class whose reset/step render the env
        it wraps."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.rendering_wrappers

    def own_render_here(self, name: str) -> bool:
        """A class of this module whose render(mode) stays the project's own
        (``ProjectFacts.own_renders``): it takes no render_mode."""
        return (self.path, name) in self.facts.own_renders

    def own_render(self, qualified: str) -> bool:
        """``own_render_here`` for a name this module imports (re-exports followed)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.own_renders

    def varargs_render(self, qualified: str) -> bool:
        """An imported name of the run is a class whose render(self, *args) names no mode
        (``ProjectFacts.varargs_renders``): a mode passed to it still reaches it."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.varargs_renders

    def modeless_render_here(self, name: str) -> bool:
        """A class of this module whose render() no render mode changes
        (``ProjectFacts.modeless_renders``)."""
        return (self.path, name) in self.facts.modeless_renders

    def modeless_render(self, qualified: str) -> bool:
        """``modeless_render_here`` for a name this module imports (re-exports followed)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.modeless_renders


def _closure(start: set[str], edges: Mapping[str, Collection[str]]) -> set[str]:
    """``start`` and every path ``edges`` lead to from it, through any number of steps."""
    seen = set(start)
    pending = list(start)
    while pending:
        for path in edges.get(pending.pop(), ()):
            if path not in seen:
                seen.add(path)
                pending.append(path)
    return seen
