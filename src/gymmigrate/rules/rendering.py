"""Rendering at call sites: the render mode moves from ``render()`` to ``make()`` (GM401-GM403, GM406, GM407).

Gym 0.26 made the render mode a property of the env instance: ``gym.make(id,
render_mode=...)`` fixes it and ``env.render()`` takes no arguments (Gymnasium 1.x:
``TypeError: ... render() got an unexpected keyword argument 'mode'``). So each rule
here edits two places: the ``render`` call and the ``gym.make`` that created that env,
found through ``gymmigrate.analysis.creation``.

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
  ``render_mode="rgb_array"`` on the make that feeds them.

Receivers go through ``analysis.decisions.decide``: Stable-Baselines3 VecEnvs keep
``vec_env.render("human")`` (SB105, their 2.x API) and PettingZoo envs are left alone.
A make that already has ``render_mode`` is not given another (idempotence).
Sources: gym 0.25/0.26 release notes ("Env.Render", "Render modes"); Gymnasium
``core.py::Env.render``, ``wrappers/rendering.py::RecordVideo``, ``utils/play.py``.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, field

import libcst as cst
from libcst.metadata import Assignment, PositionProvider, ScopeProvider

from gymmigrate.analysis import names as N
from gymmigrate.analysis.creation import Creation, CreationFinder, append_keyword, remove_args
from gymmigrate.analysis.decisions import Action, decide, receiver_text
from gymmigrate.analysis.receivers import METADATA, ReceiverAnalysis
from gymmigrate.analysis.syntax import keyword_argument, string_value
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileProfile, Rule, RulePass

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


@dataclass
class RenderSite:
    """One call that needs its env created in one render mode."""

    node: cst.Call  # the render / recorder call (input tree)
    code: str  # GM401, GM402 or GM407
    mode: str  # the mode it needs
    accepted: tuple[str, ...]  # modes at the make that satisfy it
    decision: Action
    creation: Creation
    legacy_spelling: bool = False  # it said "single_rgb_array" (GM403)
    consumer: str = "render()"
    quote: str = '"'  # the user's quote style, taken from their mode literal


@dataclass
class _Plan:
    """What the pass will do, decided before the traversal rewrites anything."""

    add_mode: dict[int, str] = field(default_factory=dict)  # id(make call) -> mode to add
    quotes: dict[int, str] = field(default_factory=dict)  # id(make call) -> quote character to write it with
    rewrite_render: set[int] = field(default_factory=set)  # id(render call) -> drop its mode argument
    close_calls: set[int] = field(default_factory=set)  # id(render(close=True) call)
    single_frame_modes: set[int] = field(default_factory=set)  # id(SimpleString) "single_rgb_array"




def _replace_string(node: cst.SimpleString, value: str) -> cst.SimpleString:
    quote = node.quote
    return node.with_changes(value=f"{node.prefix}{quote}{value}{quote}")


def _mode_argument(call: cst.Call) -> cst.Arg | None:
    """The ``mode`` argument of a legacy ``render`` call (keyword or first positional)."""
    found = keyword_argument(call, "mode")
    if found is not None:
        return found
    if call.args and call.args[0].keyword is None and not call.args[0].star:
        return call.args[0]
    return None


def _code(node: cst.CSTNode) -> str:
    return cst.Module(body=[]).code_for_node(node)


def _call_summary(call: cst.Call) -> str:
    """``gym.make("CartPole-v1", ...)``: names a make call in a message (lines move between passes)."""
    first = _code(call.args[0].value) if call.args else ""
    more = ", ..." if len(call.args) > 1 else ""
    return f"{_code(call.func)}({first}{more})"


def _argument_names(args: list[cst.Arg]) -> str:
    return ", ".join(a.keyword.value if a.keyword is not None else _code(a.value) for a in args)


def _quote_style(make: cst.Call, sites: list[RenderSite]) -> str:
    """Write the mode the way the make call already quotes its strings (else like the render call)."""
    for arg in make.args:
        if isinstance(arg.value, cst.SimpleString):
            return arg.value.quote[0]
    return next((site.quote for site in sites if site.code == "GM401"), '"')


def _is_true(node: cst.BaseExpression) -> bool:
    return isinstance(node, cst.Name) and node.value == "True"


class RenderingPass(RulePass):
    RULES = RULES
    ORDER = 32
    METADATA_DEPENDENCIES = (PositionProvider, *METADATA)

    @classmethod
    def applies_to(cls, source: str, profile: FileProfile) -> bool:
        return any(word in source for word in ("render", "RecordVideo", "VecVideoRecorder", "play", LEGACY_SINGLE_FRAME))

    # -- planning (on the input tree) ----------------------------------------------------

    def visit_Module(self, node: cst.Module) -> None:
        self.analysis = ReceiverAnalysis(node, self.metadata)
        self.finder = CreationFinder(self.analysis, self.metadata, self._is_make)
        collector = _CallCollector()
        node.visit(collector)
        self.plan = _Plan()
        self._legacy_025 = LEGACY_SINGLE_FRAME in node.code
        # A file that still passes modes to render() is legacy code even once its imports
        # say gymnasium (e.g. a conflict reported on a first run): its bare render()
        # calls still mean "human", so a second run decides the same way.
        self._has_legacy_mode_calls = any(
            isinstance(call.func, cst.Attribute) and call.func.attr.value == "render" and _mode_argument(call) is not None
            for call in collector.calls
        )
        sites: list[RenderSite] = []
        for call in collector.calls:
            site = self._render_site(call) or self._recorder_site(call)
            if site is not None:
                sites.append(site)
        self._plan_sites(sites)
        self._plan_make_literals(collector.calls)

    def _is_make(self, call: cst.Call) -> bool:
        return any(N.strip_gym_prefix(q) in N.GYM_ENV_FACTORIES for q in self.analysis.qualified_names(call.func))

    def _render_site(self, call: cst.Call) -> RenderSite | None:
        func = call.func
        if not (isinstance(func, cst.Attribute) and func.attr.value == "render"):
            return None
        receiver = func.value
        close = keyword_argument(call, "close")
        mode_arg = _mode_argument(call)
        if close is None and mode_arg is None and call.args:
            return None  # some other render(...) signature: not the Gym one
        function = self.analysis.enclosing(call, cst.FunctionDef)
        if isinstance(function, cst.FunctionDef) and function.name.value == "render":
            return None  # a render method forwarding to its env: the Env/Wrapper rules own it
        kind = self.analysis.kind_of(receiver)
        decision = decide(kind, receiver, self.context.profile, legacy_shape=mode_arg is not None or close is not None)
        if decision.action is Action.LEAVE:
            return None
        if close is not None and _is_true(close.value):
            self._plan_close(call, decision.action, decision.reason)
            return None
        if mode_arg is None:
            if not (self.context.profile.imports_gym or self._has_legacy_mode_calls):
                return None  # code already written for Gymnasium: a bare render() is its API
            return RenderSite(call, "GM402", HUMAN, (), decision.action, self.finder.find(receiver))
        extra = [a for a in call.args if a is not mode_arg and a is not close]
        if extra:
            self.report(
                call,
                "GM401",
                f"render() takes no arguments in Gymnasium: pass {_argument_names(extra)} and the render mode to gym.make "
                "where the env is created (MuJoCo envs take width/height/camera_id there)",
                FixKind.FLAG,
            )
            return None
        mode = string_value(mode_arg.value)
        if mode is None:
            self.report(
                call,
                "GM401",
                f"the render mode of `{receiver_text(receiver)}` is not a literal; pass it as render_mode= to "
                "gym.make where the env is created and call render() without arguments",
                FixKind.FLAG,
            )
            return None
        legacy = mode == LEGACY_SINGLE_FRAME
        if legacy:
            mode = RGB_ARRAY
        quote = mode_arg.value.quote[0] if isinstance(mode_arg.value, cst.SimpleString) else '"'
        return RenderSite(
            call, "GM401", mode, (), decision.action, self.finder.find(receiver), legacy_spelling=legacy, quote=quote
        )

    def _recorder_site(self, call: cst.Call) -> RenderSite | None:
        qualified = self.analysis.qualified_names(call.func)
        consumer, accepted = None, (RGB_ARRAY,)
        for q in qualified:
            rest = N.strip_gym_prefix(q)
            if rest in _GYM_RECORDERS:
                consumer, accepted = _GYM_RECORDERS[rest]
            elif q in _SB3_RECORDERS:
                consumer = "VecVideoRecorder"
        if consumer is None or not call.args:
            return None
        env_arg = keyword_argument(call, "env") or keyword_argument(call, "venv") or call.args[0]
        if env_arg.keyword is not None and env_arg.keyword.value not in ("env", "venv"):
            return None
        creation = self.finder.find(env_arg.value)
        if not creation.found:
            sb3_factory = self._sb3_make_vec_env(env_arg.value)
            if sb3_factory:
                creation.gap = f"it comes from {sb3_factory}(...): pass env_kwargs={{\"render_mode\": \"rgb_array\"}} to it"
        return RenderSite(call, "GM407", RGB_ARRAY, accepted, Action.REWRITE, creation, consumer=consumer)

    def _sb3_make_vec_env(self, expr: cst.BaseExpression) -> str | None:
        """``make_vec_env`` builds the envs itself: the mode goes in its ``env_kwargs``."""
        values: list[cst.BaseExpression] = [expr]
        scope = self.metadata[ScopeProvider].get(expr) if isinstance(expr, cst.Name) else None
        if isinstance(expr, cst.Name) and scope is not None:
            for assignment in scope[expr.value]:
                if not isinstance(assignment, Assignment):
                    continue
                target = self.analysis.parent(assignment.node)
                assign = self.analysis.parent(target) if isinstance(target, cst.AssignTarget) else None
                if isinstance(assign, cst.Assign):
                    values.append(assign.value)
        for value in values:
            if isinstance(value, cst.Call):
                for q in self.analysis.qualified_names(value.func):
                    if q in _SB3_MAKE_VEC_ENV:
                        return q.rsplit(".", 1)[-1]
        return None

    def _plan_close(self, call: cst.Call, action: Action, reason: str) -> None:
        if action is Action.REPORT:
            self.report(call, "GM406", f"{reason}: render(close=True) is close() on a Gym env", FixKind.FLAG)
            return
        self.plan.close_calls.add(id(call))
        if action is Action.REWRITE_FOR_REVIEW:
            self.report(call, "GM406", f"render(close=True) -> close(); {reason}", FixKind.ASSIST)
        else:
            self.report(call, "GM406", "render(close=True) -> close()")

    def _plan_sites(self, sites: list[RenderSite]) -> None:
        by_make: dict[int, list[RenderSite]] = defaultdict(list)
        makes: dict[int, cst.Call] = {}
        for site in sites:
            if site.creation.found:
                for make in site.creation.calls:
                    by_make[id(make)].append(site)
                    makes[id(make)] = make
        # The mode each make will have: its own render_mode, or the one its sites agree on.
        final_mode: dict[int, str | None] = {}
        blocked: dict[int, str] = {}  # id(make) -> why its sites cannot be rewritten
        for key, make_sites in by_make.items():
            existing = keyword_argument(makes[key], "render_mode")
            if existing is not None:
                value = string_value(existing.value)
                final_mode[key] = RGB_ARRAY if value == LEGACY_SINGLE_FRAME else value
                if value is None:
                    blocked[key] = "its gym.make passes a render_mode that is not a literal"
                continue
            if any(arg.star == "**" for arg in makes[key].args):
                final_mode[key] = None
                blocked[key] = "its gym.make passes **kwargs that may already hold render_mode: set it there by hand"
                continue
            wanted = {s.mode for s in make_sites}
            if len(wanted) == 1:
                final_mode[key] = wanted.pop()
                self.plan.add_mode[key] = final_mode[key]  # type: ignore[assignment]
                self.plan.quotes[key] = _quote_style(makes[key], make_sites)
            else:
                final_mode[key] = None
                modes = " and ".join(sorted(f'"{m}"' for m in wanted))
                blocked[key] = (
                    f"the env is rendered in {modes}, but a Gymnasium env has one render_mode: "
                    "create two envs (e.g. a training env and an eval env with its own render_mode)"
                )
        for site in sites:
            self._plan_site(site, makes, final_mode, blocked)

    def _plan_site(
        self,
        site: RenderSite,
        makes: dict[int, cst.Call],
        final_mode: dict[int, str | None],
        blocked: dict[int, str],
    ) -> None:
        code, call = site.code, site.node
        target = f'render_mode="{site.mode}"'
        if not site.creation.found:
            where = site.creation.gap or "no gym.make was found"
            self.report(
                call,
                code,
                f"{site.consumer} needs the env created with {target}, but its creation site was not found "
                f"({where}); add it there by hand",
                FixKind.FLAG,
            )
            return
        keys = [id(m) for m in site.creation.calls]
        if code == "GM402" and all(keyword_argument(makes[k], "render_mode") is not None for k in keys):
            return  # the make already chose a mode: this bare render() is Gymnasium's API
        reasons = [blocked[k] for k in keys if k in blocked]
        if reasons:
            self.report(call, code, f"not rewritten: {reasons[0]}", FixKind.FLAG)
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
            )
            return
        where = " and ".join(_call_summary(makes[k]) for k in keys)
        added = any(k in self.plan.add_mode for k in keys)
        if site.legacy_spelling:
            self.report(call, "GM403", 'gym 0.25 "single_rgb_array" is "rgb_array" in Gymnasium')
        if code == "GM407":
            if added:
                self.report(call, code, f"added {target} to {where} so {site.consumer} gets frames")
            return
        if code == "GM402":
            if added:
                self.report(
                    call,
                    code,
                    f'legacy render() meant "human": added {target} to {where}; a human-mode env '
                    "now draws every step inside step()/reset(), so this call is redundant (keep or remove it)",
                )
            return
        self.plan.rewrite_render.add(id(call))
        if self._legacy_025 and site.mode == RGB_ARRAY and not site.legacy_spelling:
            self.report(
                call,
                "GM403",
                'in gym 0.25 "rgb_array" returned a list of frames; if this code expects a list, use "rgb_array_list"',
                FixKind.FLAG,
            )
        if added:
            message = f"render mode moved to {where} ({target}); render() takes no arguments"
            if site.decision is Action.REWRITE_FOR_REVIEW or site.decision is Action.REPORT:
                message += "; the env's origin was inferred, check it"
            self.report(call, code, message)
        else:
            self.report(call, code, f"{where} already has {target}; render() takes no arguments", FixKind.AUTO)

    def _plan_make_literals(self, calls: list[cst.Call]) -> None:
        """``gym.make(..., render_mode="single_rgb_array")`` (GM403) and 0.25 list readers."""
        for call in calls:
            if not self._is_make(call):
                continue
            existing = keyword_argument(call, "render_mode")
            if existing is None:
                continue
            value = string_value(existing.value)
            if value == LEGACY_SINGLE_FRAME:
                self.plan.single_frame_modes.add(id(existing.value))
                self.report(call, "GM403", 'gym 0.25 render_mode "single_rgb_array" is "rgb_array" in Gymnasium')
            elif value == RGB_ARRAY and self._legacy_025:
                self.report(
                    call,
                    "GM403",
                    'in gym 0.25 render_mode="rgb_array" made render() return a list of frames; if this code expects '
                    'a list, use "rgb_array_list"',
                    FixKind.FLAG,
                )

    # -- rewriting ------------------------------------------------------------------------

    def leave_SimpleString(self, original_node: cst.SimpleString, updated_node: cst.SimpleString) -> cst.SimpleString:
        if id(original_node) in self.plan.single_frame_modes:
            return _replace_string(updated_node, RGB_ARRAY)
        return updated_node

    def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.BaseExpression:
        key = id(original_node)
        if key in self.plan.close_calls and isinstance(updated_node.func, cst.Attribute):
            return updated_node.with_changes(
                func=updated_node.func.with_changes(attr=cst.Name("close")),
                args=[],
                whitespace_before_args=cst.SimpleWhitespace(""),
            )
        if key in self.plan.rewrite_render:
            mode_arg = _mode_argument(original_node)
            index = original_node.args.index(mode_arg) if mode_arg is not None else -1
            dropped = updated_node.args[index] if index >= 0 else None
            updated_node = remove_args(updated_node, lambda arg: arg is dropped)
        if key in self.plan.add_mode:
            updated_node = append_keyword(
                updated_node, "render_mode", cst.SimpleString(f"{self.plan.quotes[key]}{self.plan.add_mode[key]}{self.plan.quotes[key]}")
            )
        return updated_node


class _CallCollector(cst.CSTVisitor):
    def __init__(self) -> None:
        self.calls: list[cst.Call] = []

    def visit_Call(self, node: cst.Call) -> None:
        self.calls.append(node)
