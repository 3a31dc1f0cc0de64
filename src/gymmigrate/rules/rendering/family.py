"""The rendering family: which files it may fire on, and one file's decision, in order: the
render and recorder sites (``sites.py``, ``recorders.py``), the makes they need a mode at
(``planning.py``, ``makes.py``), gym 0.25's modes at makes, and the render calls that
still pass a mode (``notes.render_mode_calls_left``)."""

from __future__ import annotations

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.creation import CreationFinder
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext
from gymmigrate.rules.render_calls import fetched_render, in_source_order, is_render
from gymmigrate.rules.rendering.common import (
    LEGACY_SINGLE_FRAME,
    RULES,
    RenderSite,
    four_value_steps,
    imports_legacy_gym_module,
    imports_legacy_make,
)
from gymmigrate.rules.rendering.planning import SitePlanning
from gymmigrate.rules.rendering.recorders import RECORDER_ATTRIBUTES
from gymmigrate.rules.rendering.sites import RenderSites


class Rendering(RenderSites, SitePlanning):
    RULES = RULES
    after = ("WrapperRenames",)

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        text = facts.text
        project = context.options.project
        if project is not None and (project.view(context.path).gives_render_modes() or project.view(context.path).gives_handed_modes()):
            return True  # a constructor or a make here gets the mode another module's renders need
        if LEGACY_SINGLE_FRAME in text or any(word in text for word in RECORDER_ATTRIBUTES):
            return True
        renders = facts.attribute_calls.get("render", [])
        # Migrated code calls render() bare, in a file that imports gymnasium, not gym.
        if any(call.args or call.keywords for call in renders):
            return True
        if not renders:
            # An env this file makes may be drawn by a wrapper another module of the run
            # defines (its reset/step render): the make is reported here.
            if project is not None and project.rendering_wrappers and context.profile.imports_gym:
                return True
            # ``return venv.envs[0].render``: a render method fetched and called by name
            # (``_report_fetched_renders``)
            return context.profile.imports_gym and ".render" in text and bool(facts.calls_by_name)
        return (
            context.profile.imports_gym
            or imports_legacy_make(facts, context)
            or four_value_steps(facts)
            or imports_legacy_gym_module(facts, context)
        )

    def decide(self) -> None:
        self.finder = CreationFinder(self.facts, self.receivers, self._is_make)
        self._legacy_025 = LEGACY_SINGLE_FRAME in self.facts.text
        self._added = self.notes.render_modes_added
        self._mode_builds = {}  # id(make) -> (make, its build)
        self._noted = dict(self._added)  # modes another family gives a make in this run
        self._scheduled: dict[int, str] = {}  # id(make) -> the creation-time condition of its renders
        self._unscheduled: dict[int, str] = {}  # id(make) -> the run-time condition of its renders
        self._switched_off: dict[int, str] = {}  # id(make) -> the constant that keeps its renders off
        self._framed: dict[int, tuple[str, int]] = {}  # id(make) -> the recorder that gives it rgb_array over bare renders
        self._idle_recorders: dict[int, str] = {}  # id(recorder call) -> why it never runs
        self._mode_dropped: set[int] = set()  # render calls that lose their mode argument
        render_calls = self.facts.attribute_calls.get("render", [])
        # A file that still passes modes to render() is legacy code even once its imports
        # say gymnasium (e.g. a conflict reported on a first run): its bare render()
        # calls still mean "human", so a second run decides the same way.
        self._has_legacy_mode_calls = any(self._mode_argument(call) is not None for call in render_calls)
        sites: list[RenderSite] = []
        self._forwarded_sites = []
        self._forwards = []
        self._drawn_by_forward = set()
        for call in in_source_order([*render_calls, *self._recorder_candidates()]):
            site = self._render_site(call) if is_render(call) else self._recorder_site(call)
            if site is not None:
                sites.append(site)
        sites.extend(self._forwarded_sites)
        self._wrapped = self._rendering_wrappers()
        self._plan_sites(sites)
        self._plan_handed_constructions()
        self._plan_handed_makes()
        self._plan_forwards()
        self._report_rendering_wrappers()
        self._plan_make_literals()
        self._report_fetched_renders()
        # Render calls that still pass a mode after this run: a local env class whose
        # render(mode) they may reach keeps its signature (custom_env/render.py).
        # (Calls inside a render method forward its mode: the Env/Wrapper rules own them.)
        self.notes.render_mode_calls_left = [
            call
            for call in render_calls
            if self._mode_argument(call) is not None
            and id(call) not in self._mode_dropped
            and getattr(self.facts.enclosing_function(call), "name", None) != "render"
        ]

    def _report_fetched_renders(self) -> None:
        """``render_func = get_render_func(env)`` then ``render_func()``, where a def of this
        module returns the render method of what it is given (``return venv.envs[0].render``):
        a legacy render that drew a window by default, out of reach of the sites above
        (no ``x.render()`` call). The env's make is not followed through the def, so the
        call is named for a person to give that make render_mode="human"."""
        if not self.context.profile.imports_gym:
            return
        for name, calls in self.facts.calls_by_name.items():
            for call in calls:
                getter = fetched_render(self.facts, self.receivers, call)
                if getter is None:
                    continue
                self.report(
                    call,
                    "GM401",
                    f"not rewritten: `{name}()` calls the render method that `{self.facts.segment(getter)}` returns; legacy "
                    'render() drew a window by default, Gymnasium\'s draws only when the env is made with render_mode="human": '
                    "pass it where that env is made",
                    FixKind.FLAG,
                    question=("GM401", "fetched render", self.facts.segment(getter)),
                )

