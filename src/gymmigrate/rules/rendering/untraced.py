"""Renders of an env whose make this file cannot reach: an env another module of the run
makes and passes in (``Agent(env, args)`` in run.py), reported with where it comes from
and the mode to give it there, or, for a frame mode every such make takes now, moved
there; an env of a Gym-only library stack; and the one question the renders and recorders
of one untraced env share.

Separate from ``planning.py`` because no make here can take these envs' mode: the
finding names the other place (a module, a library's stack) where it is chosen, and
its question joins the run's sites that ask it.
"""

from __future__ import annotations

import ast
import os
from collections.abc import Hashable

from gymmigrate.facts.mode_handovers import rendered_param
from gymmigrate.facts.module import full_name, keyword, walk
from gymmigrate.findings import RUN_QUESTION, FixKind, Tier, gym_only_question
from gymmigrate.rules.render_calls import without_mode_argument
from gymmigrate.rules.render_schedule import local_condition
from gymmigrate.rules.rendering.common import RenderSite
from gymmigrate.rules.rendering.makes import MakeEdits


class UntracedEnvs(MakeEdits):
    """The renders of envs made out of this file's reach (mixed into the family)."""

    def _report_made_elsewhere(self, site: RenderSite) -> bool:
        """A bare render of an env another module of the run makes and passes in (``Agent(env,
        args)`` in run.py, ``self.env = env`` here): the make is out of this file's reach, so
        the item names where the env comes from and, for a render under a flag, the
        conditional mode that keeps its schedule."""
        func = site.node.func
        if not isinstance(func, ast.Attribute):
            return False
        callers = self._gym_env_callers(func.value)
        if not callers:
            return False
        receiver = self.facts.segment(func.value)
        condition = local_condition(self.facts, site.node)
        mode = (
            f'render_mode="human" if <{condition}, as it is known there> else None'
            if condition is not None
            else 'render_mode="human"'
        )
        runs = f"; here it runs only when {condition}" if condition is not None else ""
        self.report(
            site.node,
            "GM402",
            f"`{receiver}` is the Gym env passed in at {', '.join(callers)}: render() draws only when that env is made "
            f"with a render_mode now{runs}: pass {mode} where it is made there (to its gym.make, or to the "
            "constructor of its env class, which takes render_mode once migrated)",
            FixKind.FLAG,
            question=self._made_elsewhere_question(callers, condition),
        )
        return True

    def _settled_elsewhere(self, site: RenderSite) -> bool:
        """A bare render of a parameter whose every caller, in other modules, builds the env
        with a run class that takes ``render_mode``: that module gives the constructor
        ``render_mode="human"`` (``_plan_handed_constructions``), so this render is a note."""
        func = site.node.func
        project = self.receivers.project
        if project is None or not isinstance(func, ast.Attribute) or not isinstance(func.value, ast.Name):
            return False
        if local_condition(self.facts, site.node) is not None:
            return False
        bindings = self.facts.bindings_of(func.value)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.arg):
            return False
        function = self.facts.enclosing_function(bindings[0])
        if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)) or self.facts.parent(function) is not self.facts.tree:
            return False
        places = project.settled_render(function.name, bindings[0].arg)
        if not places:
            return False
        self.report(
            site.node,
            "GM402",
            f'`{func.value.id}` is made with render_mode="human" now, by its constructor in another module '
            f'({", ".join(places)}): a human-mode env draws inside step()/reset(), so this call is redundant',
            FixKind.FLAG,
            tier=Tier.NOTE,
        )
        return True

    def _plan_handed_constructions(self) -> None:
        """``env = Game(rom)`` passed to a def of another module that renders it bare (every
        call of that def passes such an env, ``facts/render_handovers.py``): the constructor,
        whose migrated ``__init__`` takes ``render_mode``, gets ``render_mode="human"``, the
        mode legacy ``render()`` drew in."""
        project = self.receivers.project
        if project is None or not project.gives_render_modes():
            return
        for node in walk(self.facts.tree):
            if isinstance(node, ast.Call) and project.gets_render_mode(node) and id(node) not in self._added:
                self._add_mode(node, "human", self._quote_style(node, []))
                self.report(
                    node,
                    "GM402",
                    f'added render_mode="human" to {self.facts.segment(node)}: the def of another module it is '
                    'passed to renders this env with a bare render(), which drew in "human" mode',
                    tier=Tier.NOTE,
                )

    def _plan_handed_makes(self) -> None:
        """``env = gym.make(id)`` handed only to calls of other modules whose renders ask one
        frame mode (``Player(env)`` with ``self.env.render(mode="rgb_array")`` in player.py,
        ``facts/mode_handovers.py``): the make gets that mode, where the render module drops it."""
        project = self.receivers.project
        if project is None or not project.gives_handed_modes():
            return
        for node in walk(self.facts.tree):
            mode = project.handed_render_mode(node) if isinstance(node, ast.Call) else None
            if mode is None or not isinstance(node, ast.Call) or id(node) in self._added or keyword(node, "render_mode") is not None:
                continue
            self._add_mode(node, mode, self._quote_style(node, []))
            self.report(
                node,
                "GM401",
                f'added render_mode="{mode}" to {self.facts.segment(node)}: the calls of other modules this env is handed '
                f'to render it with render(mode="{mode}"), which takes no mode now',
                tier=Tier.NOTE,
            )

    def _moved_to_handed_make(self, site: RenderSite) -> bool:
        """``self.env.render(mode="rgb_array")`` where every construction of the run passes a
        ``gym.make`` of another module that gets this mode (``_plan_handed_makes`` there):
        the mode goes, a note says where it went."""
        project = self.receivers.project
        func = site.node.func
        if project is None or site.variable or site.code != "GM401" or not isinstance(func, ast.Attribute):
            return False
        param = rendered_param(self.facts, self.receivers, func.value)
        settled = project.settled_mode_render(*param) if param is not None else None
        if settled is None or settled[0] != site.mode:
            return False
        mode, places = settled
        self.plan.replace(site.node, without_mode_argument)
        self._mode_dropped.add(id(site.node))
        self.report(
            site.node,
            "GM401",
            f'render mode moved to where this env is made, in another module ({", ".join(places)}: render_mode="{mode}"); '
            "render() takes no arguments",
            tier=Tier.NOTE,
        )
        return True

    def _made_elsewhere_question(self, callers: list[str], condition: str | None) -> Hashable:
        """One question for the run: the agents of several modules that render the env one
        make passes them (``Agent(env, args)`` in run.py) ask where to choose its mode once."""
        project = self.receivers.project
        if project is None:
            return ("render-made-elsewhere", tuple(callers), condition)
        here = os.path.dirname(project.path)
        places = sorted({os.path.normpath(os.path.join(here, caller)) for caller in callers})
        home = places[0].rsplit(":", 1)[0]
        return (RUN_QUESTION, "render-made-elsewhere", home, tuple(places), condition or "")

    def _gym_env_callers(self, receiver: ast.expr) -> list[str]:
        """``run.py:18``: the calls in other modules that pass the Gym env ``receiver`` holds,
        a parameter of its function or, through ``self.x = x``, of its class's ``__init__``."""
        project = self.receivers.project
        if project is None:
            return []
        if isinstance(receiver, ast.Attribute) and isinstance(receiver.value, ast.Name) and self.receivers.is_self(receiver.value):
            values = self.receivers.self_attribute_values(receiver, receiver.attr)
        elif isinstance(receiver, ast.Name):
            values = [receiver]
        else:
            return []
        callers: list[str] = []
        for value in values:
            if not isinstance(value, ast.Name):
                return []
            bindings = self.facts.bindings_of(value)
            if len(bindings) != 1 or not isinstance(bindings[0], ast.arg):
                return []
            function = self.facts.enclosing_function(bindings[0])
            if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
                return []
            classdef = self.facts.parent(function)
            if isinstance(classdef, ast.ClassDef):
                names = [f"{classdef.name}.{function.name}"] + ([classdef.name] if function.name == "__init__" else [])
            else:
                names = [function.name]
            found = [c for name in names for c in project.gym_env_callers(name, bindings[0].arg)]
            if not found:
                return []
            callers.extend(c for c in found if c not in callers)
        return callers

    def _gym_only_library(self, receiver: ast.AST) -> str | None:
        """The Gym-only library stack every value of ``receiver`` comes from (a call of that
        library here, or the run's own factories and wrappers around its envs), or None."""
        return self._gym_only_origin(receiver) or self.receivers.gym_only_stack(receiver)

    def _parameter_owner(self, classdef: ast.ClassDef, gap: str) -> ast.ClassDef | None:
        """The base class of this module (``classdef`` itself or an ancestor) whose
        constructor parameter the finder stopped at (the gap names it): a subclass that
        inherits ``self.env`` from ``Agent.__init__`` asks Agent's question, not one of its own."""
        return next((current for current in self.receivers.local_lineage(classdef) if f" is a parameter of `{current.name}`," in gap), None)

    def _untraced_question(self, site: RenderSite, where: str) -> Hashable | None:
        """The renders and recorders of one untraced env ask one question: where it is made,
        and in which mode. One env is one spelling read through the same bindings (a module's
        ``env`` in each of its callbacks; ``self.x``: one class),
        or, where the finder stopped at a named constructor or function parameter (``env`` is a
        parameter of ``Evaluation``), that parameter in one class: a recorder built on ``env``
        and ``self.env.render()``."""
        func = site.node.func
        library = self._gym_only_library(func.value) if isinstance(func, ast.Attribute) else None
        if library is not None:
            return gym_only_question(library)  # an env of a Gym-only stack: ported with it (GM107)
        class_ = self.facts.enclosing_class(site.node)
        if site.creation.gap and " is a parameter of `" in site.creation.gap:
            base = self._parameter_owner(class_, site.creation.gap) if class_ is not None else None
            return ("render-untraced", id(base or class_ or self.facts.enclosing_function(site.node)), where)
        name = full_name(func.value) if isinstance(func, ast.Attribute) else None
        if not name:
            return None
        if name.split(".", 1)[0] == "self":
            return ("render-untraced", site.mode, id(class_), name, where)
        root: ast.expr = func.value if isinstance(func, ast.Attribute) else func
        while isinstance(root, ast.Attribute):
            root = root.value
        bindings = self.facts.bindings_of(root) if isinstance(root, ast.Name) else []
        if bindings:
            # One env is what one set of bindings holds: a module's ``env`` read in each of
            # its callbacks is one env, a local ``env`` of each function another.
            return ("render-untraced", site.mode, tuple(sorted(id(b) for b in bindings)), name, where)
        return ("render-untraced", site.mode, id(self.facts.enclosing_function(func)), name, where)
