"""Rendering at call sites: the render mode moves from ``render()`` to ``make()`` (GM401-GM403, GM406, GM407).

Gym 0.26 made the render mode a property of the env instance: ``gym.make(id,
render_mode=...)`` fixes it and ``env.render()`` takes no arguments (Gymnasium 1.x:
``TypeError: ... render() got an unexpected keyword argument 'mode'``). So each rule
here edits two places: the ``render`` call and the ``gym.make`` that created that env,
found through ``gymmigrate.facts.creation``.

* GM401 ``env.render(mode="rgb_array")`` -> ``render_mode="rgb_array"`` at the make and
  ``env.render()``. One env rendered in two modes, a make that already has another
  mode, or an env whose make cannot be found: reported, not rewritten (the fix is two
  envs, e.g. a training env and an eval env).
* GM402 bare ``env.render()`` (legacy default ``"human"``) -> ``render_mode="human"`` at
  the make. The call stays: "human" envs now draw inside ``step()``/``reset()``, so the
  call is redundant, and the review item says so.
* GM403 gym 0.25's ``"single_rgb_array"`` -> ``"rgb_array"``; in a file written for 0.25
  a ``"rgb_array"`` render returned a list of frames, and is reported.
* GM406 ``env.render(close=True)`` -> ``env.close()``.
* GM407 ``RecordVideo``, ``gymnasium.utils.play.play`` and SB3 ``VecVideoRecorder`` need
  ``render_mode="rgb_array"`` on the make that feeds them; so does a legacy ``Monitor``
  that records videos, which the wrapper family replaces by ``RecordVideo`` (GM611) in
  the same run.

Receivers go through ``facts.decisions.decide``: Stable-Baselines3 VecEnvs keep
``vec_env.render("human")`` (SB105, their 2.x API) and PettingZoo envs are left alone.
A make that already has ``render_mode`` is not given another (idempotence).

One make, one ``render_mode``, whichever family adds it: ``notes.render_modes_added``
is a dict ``{id(ast.Call): mode}`` of the creation calls given a ``render_mode`` in this
run. A family that adds one (the wrapper family may, where ``Monitor`` becomes
``RecordVideo``) records it there; this family (``after = ("WrapperRenames",)``)
treats a noted make as already having that mode, adds none of its own, and records
every make it gives a mode.
Sources: gym 0.25/0.26 release notes ("Env.Render", "Render modes"); Gymnasium
``core.py::Env.render``, ``wrappers/rendering.py::RecordVideo``, ``utils/play.py``.
"""

from __future__ import annotations

import ast
from collections import defaultdict
from collections.abc import Callable, Hashable
from dataclasses import dataclass

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.creation import (
    Creation,
    CreationFinder,
    local_env_class_takes_render_mode,
    not_a_mode_call,
)
from gymmigrate.facts.decisions import Action, decide, receiver_text
from gymmigrate.facts.env_classes import EnvClasses
from gymmigrate.facts.env_specs import is_spec_make
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import full_name, keyword, string_value
from gymmigrate.facts.receiver_classes import renders_nothing
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.render_calls import (
    arguments_in_order,
    close_call,
    first_argument,
    in_source_order,
    is_render,
    mode_argument,
    single_frame_fixed,
    with_keyword,
    without_mode_argument,
)
from gymmigrate.rules.render_schedule import same_value_at_make, schedule

RULES = (
    Rule(
        "GM401",
        "render mode at make",
        FixKind.ASSIST,
        "`env.render(mode=X)` becomes `env.render()` with `render_mode=X` on the `gym.make` that created the env.",
    ),
    Rule(
        "GM402",
        "bare render() was human",
        FixKind.ASSIST,
        "A bare `env.render()` drew to a window: the make gets `render_mode=\"human\"`.",
    ),
    Rule("GM403", "gym 0.25 render modes", FixKind.AUTO, "`\"single_rgb_array\"` becomes `\"rgb_array\"`."),
    Rule("GM406", "render(close=True)", FixKind.AUTO, "`env.render(close=True)` becomes `env.close()`."),
    Rule(
        "GM407",
        "recording needs rgb_array",
        FixKind.ASSIST,
        "RecordVideo, `utils.play.play` and VecVideoRecorder need `render_mode=\"rgb_array\"` at the make.",
    ),
)

HUMAN = "human"
RGB_ARRAY = "rgb_array"
LEGACY_SINGLE_FRAME = "single_rgb_array"  # gym 0.25 only

# Consumers of frames (GM407): qualified name suffix under gym/gymnasium or the full
# SB3 name -> the modes they accept.
_GYM_RECORDERS = {
    "wrappers.RecordVideo": ("RecordVideo", (RGB_ARRAY,)),
    "wrappers.record_video.RecordVideo": ("RecordVideo", (RGB_ARRAY,)),
    "wrappers.rendering.RecordVideo": ("RecordVideo", (RGB_ARRAY,)),
    "utils.play.play": ("play()", (RGB_ARRAY, "rgb_array_list")),
    "utils.play": ("play()", (RGB_ARRAY, "rgb_array_list")),
}
_SB3_RECORDERS = {
    "stable_baselines3.common.vec_env.VecVideoRecorder",
    "stable_baselines3.common.vec_env.vec_video_recorder.VecVideoRecorder",
}
_SB3_MAKE_VEC_ENV = {
    "stable_baselines3.common.env_util.make_vec_env",
    "stable_baselines3.common.env_util.make_atari_env",
    "stable_baselines3.common.cmd_util.make_vec_env",
}


# How many assignments and wrapping calls are followed back to a VecEnv's maker.
MAX_VEC_CHAIN = 12

# The legacy ``gym.wrappers.Monitor`` that the wrapper family turns into ``RecordVideo``
# (GM611) when it records videos: its env needs ``render_mode="rgb_array"`` too.
_MONITORS = frozenset({"wrappers.Monitor", "wrappers.monitor.Monitor"})
_MONITOR_POSITIONS = ("env", "directory", "video_callable")
# Callee spellings worth a qualified-name lookup (the last part of ``x.y.Name``).
_RECORDER_ATTRIBUTES = ("RecordVideo", "play", "VecVideoRecorder", "Monitor")


@dataclass
class RenderSite:
    """One call that needs its env created in one render mode."""

    node: ast.Call  # the render / recorder call
    code: str  # GM401, GM402 or GM407
    mode: str  # the mode it needs
    accepted: tuple[str, ...]  # modes at the make that satisfy it
    decision: Action
    creation: Creation
    legacy_spelling: bool = False  # it said "single_rgb_array" (GM403)
    consumer: str = "render()"
    quote: str = '"'  # the user's quote style, taken from their mode literal
    variable: bool = False  # ``mode`` is a name holding the mode (its text), not a literal


class Rendering(RuleFamily):
    RULES = RULES
    after = ("WrapperRenames",)

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        text = facts.text
        if LEGACY_SINGLE_FRAME in text or any(word in text for word in _RECORDER_ATTRIBUTES):
            return True
        renders = facts.attribute_calls.get("render", [])
        # Migrated code calls render() bare, in a file that imports gymnasium, not gym.
        if any(call.args or call.keywords for call in renders):
            return True
        if not renders:
            return False
        return (
            context.profile.imports_gym
            or _imports_legacy_make(facts, context)
            or _four_value_steps(facts)
            or _imports_legacy_gym_module(facts, context)
        )

    def _helper_method(self, function: ast.AST) -> bool:
        """``render`` is a method of a plain class of the run (muzero's ``Game`` owning a
        ``gym.make`` env), not of an env or wrapper: its forwarded ``self.env.render()`` is a
        call site like any other, and the make gets the mode."""
        classdef = self.facts.parent(function)
        return isinstance(classdef, ast.ClassDef) and self.receivers.class_kind(classdef) is EnvKind.NOT_ENV

    def decide(self) -> None:
        self.finder = CreationFinder(self.facts, self.receivers, self._is_make)
        self._legacy_025 = LEGACY_SINGLE_FRAME in self.facts.text
        self._added: dict[int, str] = self.notes.render_modes_added
        self._mode_builds: dict[int, tuple[ast.Call, Callable[[object], object]]] = {}  # id(make) -> (make, its build)
        self._noted = dict(self._added)  # modes another family gives a make in this run
        self._scheduled: dict[int, str] = {}  # id(make) -> the creation-time condition of its renders
        self._unscheduled: dict[int, str] = {}  # id(make) -> the run-time condition of its renders
        self._mode_dropped: set[int] = set()  # render calls that lose their mode argument
        render_calls = self.facts.attribute_calls.get("render", [])
        # A file that still passes modes to render() is legacy code even once its imports
        # say gymnasium (e.g. a conflict reported on a first run): its bare render()
        # calls still mean "human", so a second run decides the same way.
        self._has_legacy_mode_calls = any(self._mode_argument(call) is not None for call in render_calls)
        sites: list[RenderSite] = []
        for call in in_source_order([*render_calls, *self._recorder_candidates()]):
            site = self._render_site(call) if is_render(call) else self._recorder_site(call)
            if site is not None:
                sites.append(site)
        self._plan_sites(sites)
        self._plan_make_literals()
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

    def _mode_argument(self, call: ast.Call) -> ast.AST | None:
        """The mode a legacy render call passes; None when its argument is certainly no mode
        string (``obj.render(img)`` on a grid cell drawing into an array: not a Gym render)."""
        found = mode_argument(call)
        return None if found is None or not_a_mode_call(call, self.facts) else found

    def _is_make(self, call: ast.Call) -> bool:
        return self.facts.memo(
            ("rendering-is-make", id(call)),
            lambda: self._is_gym_make(call) or local_env_class_takes_render_mode(self.facts, self.receivers, call),
        )

    def _is_gym_make(self, call: ast.Call) -> bool:
        """gym.make and its aliases (not the construction of an env class, whose own render
        signature may take more)."""
        return (
            any(N.strip_gym_prefix(q) in N.GYM_ENV_FACTORIES for q in self.facts.qualified_names(call.func))
            or self._is_project_make(call)
            or is_spec_make(self.facts, self.receivers.project, call)
        )

    def _is_project_make(self, call: ast.Call) -> bool:
        """``make(...)`` / ``pkg.make(...)`` where the run binds that name to ``gym.make``."""
        project = self.receivers.project
        if project is None:
            return False
        return any(
            (alias := project.library_alias(q)) is not None and N.strip_gym_prefix(alias) in N.GYM_ENV_FACTORIES
            for q in self.facts.qualified_names(call.func)
        )

    def _recorder_candidates(self) -> list[ast.Call]:
        found = [call for calls in self.facts.calls_by_name.values() for call in calls]
        found.extend(call for attr in _RECORDER_ATTRIBUTES for call in self.facts.attribute_calls.get(attr, []))
        return found

    # -- sites ------------------------------------------------------------------------------

    def _render_site(self, call: ast.Call) -> RenderSite | None:
        func = call.func
        if not isinstance(func, ast.Attribute):  # ``x.method(...)`` calls only
            return None
        receiver = func.value
        close = keyword(call, "close")
        mode_arg = self._mode_argument(call)
        if close is None and mode_arg is None and (call.args or call.keywords):
            # Some other render(...) signature: not the Gym one. Through the wrappers make
            # adds it is a TypeError in Gymnasium (Wrapper.render takes no arguments).
            self._report_other_signature(call, receiver)
            return None
        function = self.facts.enclosing_function(call)
        if function is not None and function.name == "render" and not self._helper_method(function):
            return None  # a render method forwarding to its env: the Env/Wrapper rules own it
        if mode_arg is not None and self._class_keeps_its_mode(receiver):
            return None  # ``render(mode)`` of a class that chooses its mode itself is kept (GM405 says so)
        if self._reached_from_other_library(receiver):
            return None  # ``tf_env.pyenv.envs[0].render(mode="rgb_array")``: tf_agents' API, not Gym's
        kind = self.receivers.kind_of(receiver)
        decision = decide(kind, receiver, self.context.profile, legacy_shape=mode_arg is not None or close is not None, origins=self.receivers)
        if decision.action is Action.LEAVE:
            if kind is EnvKind.SB3_VEC and mode_arg is None and close is None and not self.receivers.run_defined(receiver):
                self._check_vec_frames(call, receiver)
                return None
            if kind is EnvKind.SB3_VEC and mode_arg is None and close is None and self._stub_render(receiver):
                return None  # the project's class renders no env (its render() logs, or does nothing)
            if kind is EnvKind.SB3_VEC and mode_arg is None and close is None and self.context.profile.imports_gym and self.receivers.run_defined(receiver):
                # The project's own vector env (left alone) draws through its envs' render():
                # one item per file, for where those envs are made.
                self.report(
                    call,
                    "GM402",
                    f"`{full_name(receiver) or 'the env'}` is a vector env of the project (left as it is): if its render() "
                    "calls its envs' render(), those draw only when made with render_mode=\"human\" now; pass it where "
                    "they are made",
                    FixKind.FLAG,
                    question=("GM402", "vector env of the project"),
                )
            return None
        if close is not None and isinstance(close.value, ast.Constant) and close.value.value is True:
            self._plan_close(call, decision.action, decision.reason)
            return None
        if mode_arg is None:
            if not (
                self.context.profile.imports_gym
                or self._has_legacy_mode_calls
                or _imports_legacy_make(self.facts, self.context)
                or (kind is EnvKind.GYM_ENV and _imports_legacy_gym_module(self.facts, self.context))
                or self._stepped_the_legacy_way(receiver)
            ):
                if decision.action in (Action.REPORT, Action.REWRITE_FOR_REVIEW) and self._stepped_the_legacy_way(receiver, traced=False):
                    # An env whose origin is unknown, stepped the legacy way: its reset and
                    # step ask whether it is a Gym env; the same question names this render.
                    self.report(
                        call,
                        "GM402",
                        f"{decision.reason}: if it is a Gym env, render() draws only when the env is made with "
                        'render_mode="human" now: pass it where this env is made',
                        FixKind.FLAG,
                        question=self.receiver_question(receiver, decision),
                    )
                return None  # code already written for Gymnasium: a bare render() is its API
            return RenderSite(call, "GM402", HUMAN, (), decision.action, self.finder.find(receiver))
        extra = [a for a in arguments_in_order(call) if a is not mode_arg and a is not close]
        if extra:
            names = ", ".join(self._argument_name(a) for a in extra)
            self.report(
                call,
                "GM401",
                f"render() takes no arguments in Gymnasium: pass {names} and the render mode to gym.make "
                "where the env is created (MuJoCo envs take width/height/camera_id there)",
                FixKind.FLAG,
                question=self._same_render_call(call, receiver),
            )
            return None
        value = mode_arg.value if isinstance(mode_arg, ast.keyword) else mode_arg
        mode = string_value(value)
        if mode is None and isinstance(value, ast.Name):
            creation = self.finder.find(receiver)
            if creation.found and all(same_value_at_make(self.facts, value, call, make) for make in creation.calls):
                return RenderSite(call, "GM401", value.id, (), decision.action, creation, variable=True)
        if mode is None:
            self.report(
                call,
                "GM401",
                f"the render mode of `{receiver_text(receiver)}` is not a literal; pass it as render_mode= to "
                "gym.make where the env is created and call render() without arguments",
                FixKind.FLAG,
                question=self._same_render_call(call, receiver),
            )
            return None
        legacy = mode == LEGACY_SINGLE_FRAME
        if legacy:
            mode = RGB_ARRAY
        quote = self._quote(value) or '"'
        return RenderSite(call, "GM401", mode, (), decision.action, self.finder.find(receiver), legacy_spelling=legacy, quote=quote)

    def _reached_from_other_library(self, receiver: ast.expr) -> bool:
        """``tf_env.pyenv.envs[0]`` with ``tf_env`` made by tf_agents (or dm_control): an
        object reached through attributes and items of one another library made, whose
        ``render(mode=...)`` is that library's own."""
        root: ast.expr = receiver
        while isinstance(root, (ast.Attribute, ast.Subscript)):
            root = root.value
        if root is receiver or not isinstance(root, ast.Name):
            return False
        library = self.receivers.library_made(root)
        return library is not None and library.split(".", 1)[0] in _NON_GYM_ENV_LIBRARIES

    def _class_keeps_its_mode(self, receiver: ast.expr) -> bool:
        """``env = MyEnv()`` whose class chooses its render mode itself (``set_render_mode``):
        its ``render(mode)`` is kept, so a call passing a mode still works as it is."""
        if not hasattr(self, "_class_finder"):
            self._class_finder = CreationFinder(self.facts, self.receivers, lambda call: self.receivers.local_class(call.func) is not None)
        creation = self._class_finder.find(receiver)
        if not creation.found:
            return False
        classes = EnvClasses.of(self.facts, self.receivers)
        made = [self.receivers.local_class(call.func) for call in creation.calls]
        return all(c is not None and classes.own_render_mode(c) is not None for c in made)

    def _report_other_signature(self, call: ast.Call, receiver: ast.expr) -> None:
        if not self.context.profile.imports_gym:
            return
        if self._report_unpacked_arguments(call, receiver):
            return
        if self.receivers.kind_of(receiver) is not EnvKind.GYM_ENV:
            return
        creation = self.finder.find(receiver)
        if not (creation.found and all(self._is_gym_make(make) for make in creation.calls)):
            return
        self.report(
            call,
            "GM401",
            f"`{receiver_text(receiver)}` comes from gym.make, and Gymnasium's wrappers take no arguments in "
            f"render(): `{self._call_summary(call)}` raises TypeError; call `{receiver_text(receiver)}.unwrapped.render(...)` "
            "for the env's own signature, or pass the settings to gym.make",
            FixKind.FLAG,
        )

    def _report_unpacked_arguments(self, call: ast.Call, receiver: ast.expr) -> bool:
        """``env.render(**kwargs)`` (or ``*args``) outside a render method: what it passes is
        decided by its callers, and legacy callers passed ``mode=``, which Gymnasium's
        render() refuses (TypeError) and a Gym env made without a render_mode ignores. On an
        env the run does not show to be something else, it is reported, not left silent."""
        if not (any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords)):
            return False
        function = self.facts.enclosing_function(call)
        if function is not None and function.name == "render":
            return True  # a render method handing its own arguments on: the Env/Wrapper rules own it
        kind = self.receivers.kind_of(receiver)
        decision = decide(kind, receiver, self.context.profile, legacy_shape=True, origins=self.receivers)
        if decision.action is Action.LEAVE:
            return True
        name = receiver_text(receiver)
        self.report(
            call,
            "GM401",
            f"`{self.facts.segment(call)}` passes on what its callers give (legacy: mode=...), and Gymnasium's render() "
            f"takes no arguments: if `{name}` is a Gym env, pass the mode as render_mode= (and any size) to gym.make "
            f"where it is made and call `{name}.render()` bare",
            FixKind.FLAG,
        )
        return True

    def _recorder_site(self, call: ast.Call) -> RenderSite | None:
        consumer: str | None = None
        accepted: tuple[str, ...] = (RGB_ARRAY,)
        monitor = False
        for q in self.facts.qualified_names(call.func):
            rest = N.strip_gym_prefix(q)
            if rest in _GYM_RECORDERS:
                consumer, accepted = _GYM_RECORDERS[rest]
            elif q in _SB3_RECORDERS:
                consumer = "VecVideoRecorder"
            elif rest in _MONITORS:
                consumer, monitor = "RecordVideo", True
        if consumer is None or not (call.args or call.keywords):
            return None
        env: ast.AST | None
        if monitor:
            env = self._monitor_env(call)
        else:
            named = keyword(call, "env") or keyword(call, "venv")
            env = named.value if named is not None else first_argument(call)
            if isinstance(env, ast.keyword):
                return None  # the first argument is some other keyword
        if env is None:  # a monitor without its env (a call here always has an argument)
            return None
        creation = self.finder.find(env)
        if not creation.found:
            sb3_factory = self._sb3_make_vec_env(env)
            if sb3_factory:
                creation.gap = f"it comes from {sb3_factory}(...): pass env_kwargs={{\"render_mode\": \"rgb_array\"}} to it"
        return RenderSite(call, "GM407", RGB_ARRAY, accepted, Action.REWRITE, creation, consumer=consumer)

    def _monitor_env(self, call: ast.Call) -> ast.expr | None:
        """The env of a ``Monitor`` that becomes ``RecordVideo`` (GM611), else None.

        Mirrors the wrapper family's rewrite: it needs the env and the directory, no
        star arguments, and videos (``video_callable=False`` becomes RecordEpisodeStatistics).
        """
        if not call.args or any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords):
            return None
        values: dict[str, ast.expr] = dict(zip(_MONITOR_POSITIONS, call.args))
        values.update((k.arg, k.value) for k in call.keywords if k.arg is not None)
        trigger = values.get("video_callable")
        if "directory" not in values or (isinstance(trigger, ast.Constant) and trigger.value is False):
            return None
        return values.get("env")

    def _sb3_make_vec_env(self, expr: ast.AST) -> str | None:
        """``make_vec_env`` builds the envs itself: the mode goes in its ``env_kwargs``."""
        values: list[ast.AST] = [expr]
        if isinstance(expr, ast.Name):
            for binding in self.facts.bindings_of(expr):
                assign = self.facts.parent(binding)
                if isinstance(binding, ast.Name) and isinstance(assign, ast.Assign):
                    values.append(assign.value)
        for value in values:
            if isinstance(value, ast.Call):
                for q in self.facts.qualified_names(value.func):
                    if q in _SB3_MAKE_VEC_ENV:
                        return q.rsplit(".", 1)[-1]
        return None

    # -- GM406 ------------------------------------------------------------------------------

    def _plan_close(self, call: ast.Call, action: Action, reason: str) -> None:
        if action is Action.REPORT:
            self.report(call, "GM406", f"{reason}: render(close=True) is close() on a Gym env", FixKind.FLAG)
            return
        self.plan.replace(call, close_call)
        if action is Action.REWRITE_FOR_REVIEW:
            self.report(call, "GM406", f"render(close=True) -> close(); {reason}", FixKind.ASSIST)
        else:
            self.report(call, "GM406", "render(close=True) -> close()")

    # -- the makes --------------------------------------------------------------------------

    def _plan_sites(self, sites: list[RenderSite]) -> None:
        by_make: dict[int, list[RenderSite]] = defaultdict(list)
        makes: dict[int, ast.Call] = {}
        for site in sites:
            if site.creation.found:
                for make in site.creation.calls:
                    by_make[id(make)].append(site)
                    makes[id(make)] = make
        # The mode each make will have: its own render_mode, the one another family gives
        # it, or the one its sites agree on.
        final_mode: dict[int, str | None] = {}
        blocked: dict[int, str] = {}  # id(make) -> why its sites cannot be rewritten
        for key, make_sites in by_make.items():
            make = makes[key]
            existing = keyword(make, "render_mode")
            if existing is not None:
                value = string_value(existing.value)
                final_mode[key] = RGB_ARRAY if value == LEGACY_SINGLE_FRAME else value
                if value is None:
                    blocked[key] = "its gym.make passes a render_mode that is not a literal"
                continue
            if key in self._noted:
                final_mode[key] = self._noted[key]
                continue
            if any(k.arg is None for k in make.keywords):
                final_mode[key] = None
                blocked[key] = "its gym.make passes **kwargs that may already hold render_mode: set it there by hand"
                continue
            unready = self._registered_without_render_mode(make)
            if unready is not None:
                final_mode[key] = None
                blocked[key] = (
                    f"the id may name {unready}, registered in this run, whose __init__ takes no render_mode "
                    "(make would raise TypeError): give it a render_mode parameter first"
                )
                continue
            wanted = {s.mode for s in make_sites}
            if wanted == {HUMAN} and not any(s.variable for s in make_sites) and self._keeps_schedule(make, make_sites, final_mode, blocked):
                continue
            if len(wanted) == 1:
                mode = final_mode[key] = wanted.pop()
                variable = any(s.variable for s in make_sites)
                self._add_mode(make, mode, "" if variable else self._quote_style(make, make_sites))
            else:
                final_mode[key] = None
                modes = " and ".join(sorted(f'"{m}"' for m in wanted))
                blocked[key] = (
                    f"the env is rendered in {modes}, but a Gymnasium env has one render_mode: "
                    "create two envs (e.g. a training env and an eval env with its own render_mode)"
                )
        self._makes_by_id = makes
        self._rendered_nodes = {id(site.node) for site in sites}
        for site in sites:
            self._plan_site(site, makes, final_mode, blocked)

    def _keeps_schedule(
        self, make: ast.Call, sites: list[RenderSite], final_mode: dict[int, str | None], blocked: dict[int, str]
    ) -> bool:
        """Human renders that run only on a condition (render_schedule.py): the condition
        moves to the make when it is fixed at creation, else the sites are reported.
        False when a render runs on every pass (human mode then draws as before)."""
        key = id(make)
        trained = self._used_where_nothing_renders(make, sites)
        if trained is not None:
            # Train, then watch: human mode would draw every training step too.
            final_mode[key] = None
            self._unscheduled[key] = f"the watch loop runs (the env is also {trained}, where nothing renders)"
            return True
        how, condition = schedule(self.facts, [site.node for site in sites], make, self._stepping_function(make))
        if how == "always" or condition is None:  # the condition is None only "always"
            return False
        if how == "fixed":
            quote = self._quote_style(make, sites)
            final_mode[key] = HUMAN
            self._added[key] = HUMAN
            func = self.facts.segment(make.func)
            self._give_mode(make, func, f"{quote}{HUMAN}{quote} if {condition} else None")
            self._scheduled[key] = condition
            return True
        final_mode[key] = None
        self._unscheduled[key] = condition
        return True

    def _registered_without_render_mode(self, make: ast.Call) -> str | None:
        """A make whose id is not a literal, in a file that registers one of its own classes
        that will not take ``render_mode``: that class may be what the make builds."""
        first = make.args[0] if make.args else None
        project = self.receivers.project
        if project is not None and first is not None:
            # A class another module of the run registers (``pkg/__init__.py``), render_mode
            # not threaded down to it (custom_env/render.py reports why).
            found = project.registered_without_render_mode(string_value(first) if isinstance(first, ast.Constant) else None)
            if found is not None:
                return found
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

    def _used_where_nothing_renders(self, make: ast.Call, sites: list[RenderSite]) -> str | None:
        """How the env made by ``make`` (``env = gym.make(...)``) is used away from its renders:
        ``"stepped at line N"`` in a loop without a render call, ``"passed to f()"`` (a
        training function, an agent) — or None when every use renders as it goes (a
        legacy script that watches what it runs, where human mode draws as before)."""
        assign = self.facts.parent(make)
        if not (isinstance(assign, ast.Assign) and len(assign.targets) == 1 and isinstance(assign.targets[0], ast.Name)):
            return None
        target = assign.targets[0]
        rendered = {id(site.node) for site in sites}
        # Every read of that binding, in the functions of the module too (a training
        # function that steps the module's ``env``): the scopes already index their reads.
        reads = [read for scope in self.facts.scopes.values() for read in scope.reads.get(target.id, ())]
        for read in reads:
            if target not in self.facts.bindings_of(read):
                continue
            parent = self.facts.parent(read)
            if isinstance(parent, ast.Call) and read in parent.args and not self._under_gym(parent.func):
                return f"passed to {self.facts.segment(parent.func)}()"
            if isinstance(parent, ast.Attribute) and parent.attr == "step":
                call = self.facts.parent(parent)
                if isinstance(call, ast.Call) and call.func is parent and not self._loop_renders(call, rendered):
                    return f"stepped at line {call.lineno}"
        return None

    def _steps_render(self, key: int) -> bool:
        """Every ``step`` of the env made by ``key`` sits in a loop that renders it."""
        make = self._makes_by_id.get(key)
        steps = (self._steps_of_make(make) if make is not None else None) or []
        return bool(steps) and all(self._loop_renders(call, self._rendered_nodes) for call in steps)

    def _stepped_the_legacy_way(self, receiver: ast.expr, traced: bool = True) -> bool:
        """A file that never names gym but steps this env the legacy way (four values):
        an env another module of the run made and passed in, so its bare render() is a
        legacy human render too. ``traced=False``: any receiver, a Gym env or not."""
        if not isinstance(receiver, ast.Name) or (traced and self.receivers.kind_of(receiver) is not EnvKind.GYM_ENV):
            return False
        bindings = self.facts.bindings_of(receiver)
        return any(_unpacks_four(self.facts, call) for call in self._steps_of(receiver.id, lambda read: self.facts.bindings_of(read) == bindings))

    def _steps_of(self, name: str, same: Callable[[ast.Name], bool]) -> list[ast.Call]:
        """The ``name.step(...)`` calls of the module whose ``name`` passes ``same`` (it reads
        the binding in question), in any function: the scopes already index their reads."""
        steps = []
        for scope in self.facts.scopes.values():
            for read in scope.reads.get(name, ()):
                attribute = self.facts.parent(read)
                if isinstance(attribute, ast.Attribute) and attribute.attr == "step" and same(read):
                    call = self.facts.parent(attribute)
                    if isinstance(call, ast.Call) and call.func is attribute:
                        steps.append(call)
        return steps

    def _steps_of_make(self, make: ast.Call) -> list[ast.Call] | None:
        """The steps of the env ``env = make(...)`` binds; None when the make binds no name."""
        assign = self.facts.parent(make)
        if not (isinstance(assign, ast.Assign) and len(assign.targets) == 1 and isinstance(assign.targets[0], ast.Name)):
            return None
        target = assign.targets[0]
        return self._steps_of(target.id, lambda read: target in self.facts.bindings_of(read))

    def _stepping_function(self, make: ast.Call) -> ast.AST | None:
        """The one function (not the make's own) where the env ``make`` binds is stepped, or
        None: ``env = gym.make(...)`` at the top, ``env.step`` only inside ``main()``."""
        homes = {self.facts.enclosing_function(call) for call in self._steps_of_make(make) or ()}
        if len(homes) != 1:
            return None
        home = next(iter(homes))
        return home if home is not None and home is not self.facts.enclosing_function(make) else None

    def _under_gym(self, func: ast.expr) -> bool:
        """A gym/gymnasium callable (a wrapper taking the env is no training function)."""
        return any(N.strip_gym_prefix(q) is not None for q in self.facts.qualified_names(func))

    def _loop_renders(self, call: ast.Call, rendered: set[int]) -> bool:
        """The innermost loop around ``call`` holds one of the render sites."""
        loop = next((a for a in self.facts.ancestors(call) if isinstance(a, (ast.For, ast.While, ast.AsyncFor))), None)
        return loop is not None and any(id(node) in rendered for node in ast.walk(loop) if isinstance(node, ast.Call))

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

    def _plan_site(
        self,
        site: RenderSite,
        makes: dict[int, ast.Call],
        final_mode: dict[int, str | None],
        blocked: dict[int, str],
    ) -> None:
        code, call = site.code, site.node
        target = f"render_mode={site.mode}" if site.variable else f'render_mode="{site.mode}"'
        if not site.creation.found:
            where = site.creation.gap or "no gym.make was found"
            self.report(
                call,
                code,
                f"{site.consumer} needs the env created with {target}, but its creation site was not found "
                f"({where}); add it there by hand",
                FixKind.FLAG,
                question=self._untraced_question(site, where),
            )
            return
        keys = [id(m) for m in site.creation.calls]
        # The render calls of one env ask one question (which mode it is made with).
        def question(outcome: str) -> tuple[object, ...]:
            return ("render", code, tuple(sorted(keys)), outcome)

        if code == "GM402" and all(keyword(makes[k], "render_mode") is not None for k in keys):
            return  # the make already chose a mode: this bare render() is Gymnasium's API
        unscheduled = [self._unscheduled[k] for k in keys if k in self._unscheduled]
        if unscheduled:
            choice = (
                f"render() runs only when {unscheduled[0]}, but render_mode=\"human\" would draw every step: keep "
                'the schedule by creating the env with render_mode="rgb_array" and showing the frame render() '
                'returns here, or choose render_mode="human" if drawing every step is intended'
            )
            if code == "GM401":  # render(mode=...) raises TypeError in Gymnasium: the mode goes
                self.plan.replace(call, without_mode_argument)
                self._mode_dropped.add(id(call))
                self.report(call, code, f"mode dropped, no render_mode added (it draws nothing until you choose): {choice}")
            else:
                self.report(call, code, f"not rewritten: {choice}", FixKind.FLAG, question=question("unscheduled"))
            return
        reasons = [blocked[k] for k in keys if k in blocked]
        if reasons:
            # the make's one question, whichever render or recorder meets it
            self.report(call, code, f"not rewritten: {reasons[0]}", FixKind.FLAG, question=("render", tuple(sorted(keys)), reasons[0]))
            return
        accepted = site.accepted or (site.mode,)
        conflicting = [final_mode[k] for k in keys if final_mode[k] not in accepted]
        if conflicting:
            self.report(
                call,
                code,
                f'not rewritten: the env is created with render_mode="{conflicting[0]}" but {site.consumer} needs '
                f'"{site.mode}"; create a separate env for it',
                FixKind.FLAG,
                question=question("conflict"),
            )
            return
        where = " and ".join(self._call_summary(makes[k]) for k in keys)
        added = any(k in self._added for k in keys)
        if site.legacy_spelling:
            self.report(call, "GM403", 'gym 0.25 "single_rgb_array" is "rgb_array" in Gymnasium')
        if code == "GM407":
            if added:
                self._claim_makes(keys)
                self.report(call, code, f"added {target} to {where} so {site.consumer} gets frames", tier=Tier.NOTE)
            return
        scheduled = [self._scheduled[k] for k in keys if k in self._scheduled]
        if scheduled:
            # Rendered in the same loop as every step of the env: it drew each step before,
            # and does now; only a render away from the steps (once an episode) is a question.
            per_step = all(self._steps_render(k) for k in keys)
            self._claim_makes(keys)
            self.report(
                call,
                code,
                f'render() ran only when {scheduled[0]}, which is known when the env is made: added render_mode="human" '
                f"if {scheduled[0]} else None to {where}; that env now draws every step inside step()/reset()"
                + (", as it drew every step here" if per_step else ""),
                tier=Tier.NOTE if per_step else None,
            )
            if code == "GM401":
                self.plan.replace(call, without_mode_argument)
                self._mode_dropped.add(id(call))
            return
        if code == "GM402":
            if added:
                # Rendered in the loop that steps the env: it drew each step before and
                # does now, so the line only explains the rewrite.
                per_step = all(self._steps_render(k) for k in keys)
                self._claim_makes(keys)
                self.report(
                    call,
                    code,
                    f'legacy render() meant "human": added {target} to {where}; a human-mode env '
                    "now draws every step inside step()/reset(), so this call is redundant (keep or remove it)",
                    tier=Tier.NOTE if per_step else None,
                )
            return
        self.plan.replace(call, without_mode_argument)
        self._mode_dropped.add(id(call))
        if self._legacy_025 and site.mode == RGB_ARRAY and not site.legacy_spelling:
            self.report(
                call,
                "GM403",
                'in gym 0.25 "rgb_array" returned a list of frames; if this code expects a list, use "rgb_array_list"',
                FixKind.FLAG,
            )
        if added:
            message = f"render mode moved to {where} ({target}); render() takes no arguments"
            inferred = site.decision is Action.REWRITE_FOR_REVIEW or site.decision is Action.REPORT
            if inferred:
                message += "; the env's origin was inferred, check it"
            # A frame or text mode draws nothing by itself: the env renders when render() is
            # called, as before, so the move explains itself. "human" draws every step.
            exact = not inferred and site.mode != HUMAN and not site.variable
            if site.variable:
                message += f'; the mode is read once per env now: where {site.mode} is "human", that env draws every step inside step()/reset()'
            self._claim_makes(keys)
            self.report(call, code, message, tier=Tier.NOTE if exact else None, question=question("moved"))
        else:
            self.report(call, code, f"{where} already has {target}; render() takes no arguments", FixKind.AUTO)

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

    # -- text -------------------------------------------------------------------------------

    def _quote(self, node: ast.AST) -> str | None:
        """The quote character of a plain string literal, as written."""
        if not (isinstance(node, ast.Constant) and isinstance(node.value, str)):
            return None
        text = self.facts.segment(node).lstrip("rRuU")
        return text[0] if text[:1] in ("'", '"') else None

    def _quote_style(self, make: ast.Call, sites: list[RenderSite]) -> str:
        """Write the mode the way the make call already quotes its strings (else like the render call)."""
        for arg in arguments_in_order(make):
            quote = self._quote(arg.value if isinstance(arg, ast.keyword) else arg)
            if quote is not None:
                return quote
        return next((site.quote for site in sites if site.code == "GM401"), '"')

    def _stub_render(self, receiver: ast.expr) -> bool:
        """``receiver`` is an instance of a class of the run (this module's or imported)
        whose render() renders no env: a stub of the project's own vector env."""
        statement = self.receivers.statement_seen(receiver) if isinstance(receiver, ast.Name) else None
        value = statement.value if isinstance(statement, ast.Assign) else None
        if not isinstance(value, ast.Call):
            return False
        local = self.receivers.local_class(value.func)
        if local is not None:
            return renders_nothing(self.facts, local)
        project = self.receivers.project
        return project is not None and any(project.renders_nothing(q) for q in self.facts.qualified_names(value.func))

    def _check_vec_frames(self, call: ast.Call, receiver: ast.expr) -> None:
        """``img = venv.render()`` on a Stable-Baselines3 VecEnv, the frame used: SB3 2.x
        returns one only when its envs are made with ``render_mode="rgb_array"`` (legacy SB3
        rendered by mode at the call), so the envs' maker needs it, whatever wrappers and
        converters (supersuit's) stand between."""
        if isinstance(self.facts.parent(call), ast.Expr):
            return  # drawn, not used: SB3's own API (SB105 keeps it)
        maker = self._vec_env_maker(receiver)
        if maker is not None and (keyword(maker, "render_mode") is not None or keyword(maker, "env_kwargs") is not None):
            return
        where = f"where `{self.facts.segment(maker.func)}(...)` makes them" if maker is not None else "where they are made"
        self.report(
            call,
            "GM407",
            f"`{receiver_text(receiver)}` is a Stable-Baselines3 VecEnv and the frame its render() returns is used here: "
            f'SB3 2.x returns one only when its envs are made with render_mode="rgb_array"; pass it {where}',
            FixKind.FLAG,
            question=("vec-frames", receiver_text(receiver)),
        )

    def _vec_env_maker(self, receiver: ast.expr) -> ast.Call | None:
        """The call that made the envs under ``receiver``: back through the assignments and
        the calls that take the env first (``VecMonitor(env)``, ``concat_vec_envs_v1(env, 2)``)
        to the first that does not (``sumo_rl.grid4x4(...)``, ``make_vec_env("CartPole-v1")``)."""
        expr: ast.expr | None = receiver
        for _ in range(MAX_VEC_CHAIN):
            if isinstance(expr, ast.Name):
                statement = self.receivers.statement_seen(expr)
                expr = statement.value if isinstance(statement, ast.Assign) and len(statement.targets) == 1 else None
            elif isinstance(expr, ast.Call):
                first = expr.args[0] if expr.args else None
                if not isinstance(first, (ast.Name, ast.Call)):
                    return expr
                expr = first
            else:
                return None
        return None

    def _same_render_call(self, call: ast.Call, receiver: ast.expr) -> Hashable:
        """The same render call written at several places of the file (``env.render("pyglet",
        view=view_mode)`` in each key handler) asks one question: where that env is made, with
        which mode and options."""
        arguments = ", ".join(self.facts.segment(argument) for argument in arguments_in_order(call))
        # one env: the same bindings of a name (a module's ``env`` read in its functions too),
        # or the same ``self.x`` of one class
        if isinstance(receiver, ast.Name):
            env: Hashable = tuple(sorted(id(binding) for binding in self.facts.bindings_of(receiver)))
        else:
            env = id(self.facts.enclosing_class(call) or self.facts.enclosing_function(call))
        return ("render-arguments", receiver_text(receiver), env, arguments)

    def _untraced_question(self, site: RenderSite, where: str) -> Hashable | None:
        """The renders and recorders of one untraced env ask one question: where it is made,
        and in which mode. One env is one spelling in one function (``self.x``: one class),
        or, where the finder stopped at a named constructor or function parameter (``env`` is a
        parameter of ``Evaluation``), that parameter in one class: a recorder built on ``env``
        and ``self.env.render()``."""
        func = site.node.func
        library = self._gym_only_origin(func.value) if isinstance(func, ast.Attribute) else None
        if library is not None:
            return ("gym-only-library", library)  # an env of a Gym-only stack: ported with it (GM107)
        class_ = self.facts.enclosing_class(site.node)
        if site.creation.gap and " is a parameter of `" in site.creation.gap:
            return ("render-untraced", id(class_ or self.facts.enclosing_function(site.node)), where)
        name = full_name(func.value) if isinstance(func, ast.Attribute) else None
        if not name:
            return None
        owner = class_ if name.split(".", 1)[0] == "self" else self.facts.enclosing_function(func)
        return ("render-untraced", site.mode, id(owner), name, where)

    def _call_summary(self, call: ast.Call) -> str:
        """``gym.make("CartPole-v1", ...)``: names a make call in a message."""
        arguments = arguments_in_order(call)
        first = ""
        if arguments:
            value = arguments[0].value if isinstance(arguments[0], (ast.keyword, ast.Starred)) else arguments[0]
            first = self.facts.segment(value)
        more = ", ..." if len(arguments) > 1 else ""
        return f"{self.facts.segment(call.func)}({first}{more})"

    def _argument_name(self, argument: ast.AST) -> str:
        if isinstance(argument, ast.keyword) and argument.arg is not None:
            return argument.arg
        value = argument.value if isinstance(argument, (ast.keyword, ast.Starred)) else argument
        return self.facts.segment(value)


# Libraries whose env objects (and what hangs off them) are not Gym envs: their render()
# keeps its own signature.
_NON_GYM_ENV_LIBRARIES = frozenset({"tf_agents", "dm_control", "dm_env"})


def _four_value_steps(facts: ModuleFacts) -> bool:
    """``obs, reward, done, info = x.step(a)`` somewhere in the file: legacy stepping, though
    the file never names gym (an env another module of the run passes in)."""
    return any(_unpacks_four(facts, call) for call in facts.attribute_calls.get("step", ()))


def _unpacks_four(facts: ModuleFacts, call: ast.AST) -> bool:
    """``a, b, c, d = call``: the legacy step's four values."""
    statement = facts.parent(call)
    return (
        isinstance(statement, ast.Assign)
        and len(statement.targets) == 1
        and isinstance(statement.targets[0], (ast.Tuple, ast.List))
        and len(statement.targets[0].elts) == 4
    )


def _imports_legacy_make(facts: ModuleFacts, context: FileContext) -> bool:
    """The file imports a name another module of the run binds to the legacy ``gym.make``
    (``from .utils import make``): its bare ``render()`` calls are legacy Gym code too."""
    project = context.options.project
    if project is None:
        return False
    view = project.view(context.path)
    return any(_is_legacy_gym_make(view.library_alias(q)) for q in facts.imports.values())


def _imports_legacy_gym_module(facts: ModuleFacts, context: FileContext) -> bool:
    """The file imports a module of the run that imports legacy ``gym`` (the project's
    wrappers, whose factories it calls): a bare ``render()`` of a Gym env there (one the
    run traced, ``holder.gym_env``) renders a legacy env."""
    project = context.options.project
    if project is None:
        return False
    view = project.view(context.path)
    return facts.memo(("imports-legacy-gym-module", 0), lambda: any(view.imports_legacy_gym(q) for q in facts.imports.values()))


def _is_legacy_gym_make(alias: str | None) -> bool:
    return alias is not None and alias.split(".", 1)[0] == "gym" and N.strip_gym_prefix(alias) in N.GYM_ENV_FACTORIES
