"""The render calls: which ``env.render(...)`` is a site (GM401 a mode to move, GM402 a
bare legacy render that meant "human"), which is left alone (another library's render,
a class that keeps its own mode, a render method forwarding to its env, code already
written for Gymnasium) and which is reported (other arguments, a mode that is no
literal); GM406's ``render(close=True)``."""

from __future__ import annotations

import ast
import os
from collections.abc import Hashable

from gymmigrate.facts.creation import CreationFinder
from gymmigrate.facts.creation_shapes import wrapped_env_argument
from gymmigrate.facts.decisions import Action, Decision, decide, receiver_text
from gymmigrate.facts.env_classes import EnvClasses
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import full_name, keyword, string_value, walk
from gymmigrate.facts.render_modes import modeless_render, own_object_render
from gymmigrate.facts.summaries.classes import (
    held_env_render_forward,
    takes_mode_unnamed,
)
from gymmigrate.findings import FixKind, Tier, kept_render_question
from gymmigrate.rules.render_calls import (
    arguments_in_order,
    close_call,
    unwrapped_render_call,
)
from gymmigrate.rules.render_schedule import never_run_guard, same_value_at_make
from gymmigrate.rules.rendering.common import (
    HUMAN,
    LEGACY_SINGLE_FRAME,
    RGB_ARRAY,
    RenderSite,
    forwards_to_first_argument,
    imports_legacy_gym_module,
    imports_legacy_make,
)
from gymmigrate.rules.rendering.recorders import RecorderSites
from gymmigrate.rules.wrapper_usage.atari_limits import make_ids

# Libraries whose env objects (and what hangs off them) are not Gym envs: their render()
# keeps its own signature.
_NON_GYM_ENV_LIBRARIES = frozenset({"tf_agents", "dm_control", "dm_env"})


class RenderSites(RecorderSites):
    """The render call sites (mixed into the family)."""

    def _helper_method(self, function: ast.AST, receiver: ast.expr) -> bool:
        """``render`` is a method of a plain class of the run (muzero's ``Game`` owning a
        ``gym.make`` env), not of an env or wrapper: its forwarded ``self.env.render()`` is a
        call site like any other, and the make gets the mode. An env class of another API
        (deriving RLlib's ``MultiAgentEnv``, a dm_env base) is an env: its render is that
        API's, and what it forwards to is a Gym call site only where the run proves a Gym env
        there (as ``_adapter_render`` says of a class of unknown kind)."""
        classdef = self.facts.parent(function)
        if not (isinstance(classdef, ast.ClassDef) and self.receivers.class_kind(classdef) is EnvKind.NOT_ENV):
            return False
        return not self.receivers.derives_own_api(classdef) or self.receivers.kind_of(receiver) is EnvKind.GYM_ENV

    def _adapter_render(self, function: ast.AST, receiver: ast.expr) -> bool:
        """``render(self, mode)`` of a class that is no Gym env or wrapper (an env of another
        API's base, garage's ``Environment``) forwarding to a Gym env it holds
        (``self._env.render(mode)``): no Env/Wrapper rule owns it, and on Gymnasium the call
        is a TypeError, so it is a call site like any other."""
        classdef = self.facts.parent(function)
        if not isinstance(classdef, ast.ClassDef) or self.receivers.is_gym_wrapper_class(classdef):
            return False
        if self.receivers.class_kind(classdef) is not EnvKind.UNKNOWN or EnvClasses.of(self.facts, self.receivers).is_custom_env(classdef):
            return False
        return self.receivers.kind_of(receiver) is EnvKind.GYM_ENV

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
        if (
            function is not None
            and function.name == "render"
            and isinstance(self.facts.parent(function), ast.ClassDef)  # a module's ``def render(env)`` is a caller
            and not (self._helper_method(function, receiver) or self._adapter_render(function, receiver))
        ):
            return None  # a render method forwarding to its env: the Env/Wrapper rules own it
        if mode_arg is None and close is None and self._report_own_forward(call, receiver):
            return None
        if mode_arg is not None and self._class_keeps_its_mode(receiver):
            return None  # ``render(mode)`` of a class that chooses its mode itself is kept (GM405 says so)
        if mode_arg is not None and self._varargs_render_instance(receiver):
            # ``env = Walker(cfg)`` whose render(self, *args) names no mode: the run leaves it,
            # so the mode still reaches it and no render_mode is wanted anywhere.
            return None
        if mode_arg is None and close is None and self._own_render_instance(receiver):
            # An instance of a class whose render(mode) stays the project's own (GM405 keeps
            # it): a bare call still runs it with its default mode, as it did. Or of a class
            # whose render() takes no mode and ignores render_mode: it draws as it did, and
            # no render_mode would change that.
            return None
        if self.receivers.legacy_step_class(receiver) is not None:
            # An instance of a class of the run kept on its own API (a batch of envs whose
            # step and reset stay legacy): its render(mode='human') stays with them (GM405
            # leaves it), so the call draws as before and no make of it exists to take a mode.
            return None
        if self._reached_from_other_library(receiver):
            return None  # ``tf_env.pyenv.envs[0].render(mode="rgb_array")``: tf_agents' API, not Gym's
        kind = self.receivers.kind_of(receiver)
        decision = decide(kind, receiver, self.context.profile, legacy_shape=mode_arg is not None or close is not None, origins=self.receivers)
        if decision.action is Action.LEAVE and mode_arg is not None and close is None:
            adapter = self._forwarding_adapter(receiver)
            if adapter is not None:
                # ``Logged(gym.make(...)).render(mode=...)``: the adapter has no render() of its
                # own and forwards every attribute to the env it holds, so this is that env's
                # render, a TypeError with ``mode`` on Gymnasium; rewritten as for the env, and
                # listed (the env is reached through the adapter).
                decision = Decision(
                    Action.REWRITE_FOR_REVIEW,
                    f"`{receiver_text(receiver)}` is a `{adapter}`, which forwards attribute reads (render included) "
                    "to the env it holds",
                )
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
            self._plan_close(call, receiver, decision)
            return None
        if mode_arg is None:
            if not (
                self.context.profile.imports_gym
                or self._has_legacy_mode_calls
                or imports_legacy_make(self.facts, self.context)
                or (kind is EnvKind.GYM_ENV and imports_legacy_gym_module(self.facts, self.context))
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
            off = never_run_guard(self.facts, call)
            if off is not None:
                # ``if render: env.render()`` with every call of the def passing False (or
                # leaving a False default): the call never runs, so it asks no render_mode of
                # the make (a recorder's "rgb_array" may take it); said, in case it is turned on.
                self.report(
                    call,
                    "GM402",
                    f"not rewritten: this render() never runs (every call of `{self.facts.enclosing_function(call).name}` "  # type: ignore[union-attr]
                    f'passes `{off.id}` False); if you turn it on, it draws only when the env is made with render_mode="human"',
                    FixKind.FLAG,
                    tier=Tier.NOTE,
                )
                return None
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
        if mode is None and self._report_kept_mode_call(call, receiver, decision):
            return None
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

    def _report_kept_mode_call(self, call: ast.Call, receiver: ast.expr, decision: Decision) -> bool:
        """``env.render(mode)`` on an env no make of this module is traced to, where the one
        env class of the run this module reaches whose render() takes a mode keeps ``mode``
        for such calls (GM405 at that def): the call stays, and asks that def's question
        (``kept_render_question``), decided once there. An env traced to a make keeps its
        own item: its render_mode goes to that make."""
        project = self.receivers.project
        kept = project.kept_mode_render() if project is not None else None
        if project is None or kept is None:
            return False
        creation = self.finder.find(receiver)
        if creation.found:
            # traced: only to constructions of that very class (its instance, no make)
            if not creation.complete or not all(self.facts.qualified_names(made.func) & kept[2] for made in creation.calls):
                return False
            what = "is an instance of"
        elif decision.action in (Action.REPORT, Action.REWRITE_FOR_REVIEW):
            what = "could not be traced; it may be an instance of"
        else:
            return False
        path, name, _ = kept
        where = os.path.relpath(path, os.path.dirname(project.path))
        self.report(
            call,
            "GM401",
            f"not rewritten: the render mode of `{receiver_text(receiver)}` is not a literal, and the env {what} `{name}` "
            f"({where}), the one env class of the run this module reaches whose render() takes a mode; that render() "
            "keeps `mode` for such calls (GM405 there): decided with it",
            FixKind.FLAG,
            question=kept_render_question(path, name),
        )
        return True

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

    def _forwarding_adapter(self, receiver: ast.expr) -> str | None:
        """The name of the class of this module every construction of ``receiver`` builds,
        when it has no render() and forwards attribute reads to the env its constructor takes
        (``forwards_to_first_argument``); else None."""
        if not hasattr(self, "_class_finder"):
            self._class_finder = CreationFinder(self.facts, self.receivers, lambda call: self.receivers.local_class(call.func) is not None)
        creation = self._class_finder.find(receiver)
        if not (creation.found and creation.complete):
            return None
        made = {self.receivers.local_class(call.func) for call in creation.calls}
        if len(made) != 1:
            return None
        classdef = made.pop()
        return classdef.name if classdef is not None and forwards_to_first_argument(classdef) else None

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

    def _varargs_render_instance(self, receiver: ast.expr) -> bool:
        """Every creation of ``receiver`` builds a class of this module (its own render or
        its local bases') or of the run whose render(self, *args) names no mode."""
        if not hasattr(self, "_varargs_finder"):
            self._varargs_finder = CreationFinder(self.facts, self.receivers, self._builds_varargs_render)
        creation = self._varargs_finder.find(receiver)
        return creation.found and creation.complete and bool(creation.calls) and all(self._builds_varargs_render(c) for c in creation.calls)

    def _builds_varargs_render(self, call: ast.Call) -> bool:
        classdef = self.receivers.local_class(call.func)
        seen: set[int] = set()
        while classdef is not None and id(classdef) not in seen:
            seen.add(id(classdef))
            render = next((s for s in classdef.body if isinstance(s, (ast.FunctionDef, ast.AsyncFunctionDef)) and s.name == "render"), None)
            if render is not None:
                return takes_mode_unnamed(render)
            classdef = next((b for b in map(self.receivers.local_class, classdef.bases) if b is not None), None)
        project = self.receivers.project
        if project is None or self.receivers.local_class(call.func) is not None:
            return False
        return any(project.varargs_render(q) for q in self.facts.qualified_names(call.func))

    def _own_render_instance(self, receiver: ast.expr, depth: int = 0) -> bool:
        """Every value ``receiver`` may hold is built by a class (of this module or of the run)
        whose render(mode) stays the project's own (``own_object_render``) or whose render()
        no render mode changes (``modeless_render``), or by a subclass that inherits that
        render, maybe inside Gym wrappers of the run that hand a bare
        render() on. A name is followed through the values that may reach this read
        (``values_reaching``: a wrapper put on in another branch does not count), anything
        else through its creation."""
        if isinstance(receiver, ast.Call) and depth < 8:
            if self._builds_own_render(receiver):
                return True
            inner = wrapped_env_argument(receiver)
            return inner is not None and self._hands_bare_render_on(receiver.func) and self._own_render_instance(inner, depth + 1)
        reaching = self.receivers.values_reaching(receiver) if isinstance(receiver, ast.Name) and depth < 8 else None
        if reaching:
            return all(self._own_render_instance(value, depth + 1) for value in reaching)
        if not hasattr(self, "_own_render_finder"):
            self._own_render_finder = CreationFinder(self.facts, self.receivers, self._builds_own_render)
        creation = self._own_render_finder.find(receiver)
        return creation.found and creation.complete

    def _hands_bare_render_on(self, func: ast.expr) -> bool:
        """``func`` is a Gym wrapper class of the run that defines no render() (nor do its bases
        of this module): Gymnasium's ``Wrapper.render()`` calls the env's render() bare."""
        local = self.receivers.local_class(func)
        if local is not None:
            if not self.receivers.is_gym_wrapper_class(local):
                return False
            chain, seen = [local], set()
            while chain:
                classdef = chain.pop()
                if id(classdef) in seen:
                    continue
                seen.add(id(classdef))
                if any(isinstance(s, (ast.FunctionDef, ast.AsyncFunctionDef)) and s.name == "render" for s in classdef.body):
                    return False
                chain.extend(b for b in map(self.receivers.local_class, classdef.bases) if b is not None)
            return True
        project = self.receivers.project
        return project is not None and any(
            project.is_wrapper_class(q) and (defined := project.wrapper_defined(q)) is not None and "render" not in defined
            for q in self.facts.qualified_names(func)
        )

    def _builds_own_render(self, call: ast.Call) -> bool:
        local = classdef = self.receivers.local_class(call.func)
        project = self.receivers.project
        seen: set[int] = set()
        while classdef is not None and id(classdef) not in seen:
            seen.add(id(classdef))
            if any(isinstance(s, (ast.FunctionDef, ast.AsyncFunctionDef)) and s.name == "render" for s in classdef.body):
                if own_object_render(self.facts, self.receivers, classdef) is not None:
                    return True
                return local is not None and self._modeless_instance(local)
            classdef = next((b for b in map(self.receivers.local_class, classdef.bases) if b is not None), None)
        if project is None:
            return False
        if local is not None:  # its render() comes from a base of another module of the run
            top_level = self.facts.classes.get(local.name) is local
            return top_level and (project.own_render_here(local.name) or project.modeless_render_here(local.name))
        return any(project.own_render(q) or project.modeless_render(q) for q in self.facts.qualified_names(call.func))

    def _modeless_instance(self, classdef: ast.ClassDef) -> bool:
        """An instance of ``classdef`` renders with a render() no render mode changes
        (``modeless_render``), and no module of the run registers the class: a ``make`` of
        it would be another creation, with its own question."""
        project = self.receivers.project
        if project is not None and self.facts.classes.get(classdef.name) is classdef and project.registered_here(classdef.name):
            return False
        return modeless_render(self.facts, self.receivers, classdef)

    def _report_other_signature(self, call: ast.Call, receiver: ast.expr) -> None:
        imports_gym = self.context.profile.imports_gym
        if imports_gym and self._report_unpacked_arguments(call, receiver):
            return
        if isinstance(receiver, ast.Attribute) and receiver.attr == "unwrapped":
            return  # the env's own render, past the wrappers: its own signature
        if self.receivers.kind_of(receiver) is not EnvKind.GYM_ENV:
            return
        creation = self.finder.find(receiver)
        # every creation a make: gym.make here, or a def of another module returning make()
        # results (the only creation a file that never names gym can know is made)
        made_here = creation.found and imports_gym and all(self._is_gym_make(make) for make in creation.calls)
        made_elsewhere = not creation.calls and bool(creation.made_elsewhere) and not creation.untraced
        if not (made_here or made_elsewhere):
            return
        keeper = self._render_keeps(receiver, call, modeless=True)
        if keeper is not None:
            # The render of the class every make builds takes these arguments and no mode:
            # the run leaves it as it is, so it draws as it did; the wrappers make adds take
            # no render arguments, so the env's own render is reached through unwrapped, as
            # the bare env was before. (A render taking a mode becomes one that draws only
            # with a render_mode: that call is reported below.)
            self.plan.replace(call, unwrapped_render_call)
            self.report(
                call,
                "GM401",
                f"render(...) -> unwrapped.render(...): the render() of this env's class (defined in `{keeper}`) takes "
                f"these arguments; Gymnasium's wrappers (gym.make adds some) take none in render()",
                FixKind.ASSIST,
            )
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
        if function is not None and function.name == "render" and not self._plain_class_method(function):
            return True  # a render method handing its own arguments on: the Env/Wrapper rules own it
        if function is not None and function.name == "render" and self._forward_of_bare_callers(call, receiver, function):
            return True  # its callers' renders decide the make's mode, as a direct render does
        kind = self.receivers.kind_of(receiver)
        dispatcher = None
        if function is not None and function.name == "render" and kind is not EnvKind.GYM_ENV:
            classdef = self.facts.parent(function)
            dispatcher = self.receivers.built_for_gym_by(classdef) if isinstance(classdef, ast.ClassDef) else None
            if dispatcher is None:
                return True  # an adapter's render() handing on to what is not shown to be a Gym env
        decision = decide(kind, receiver, self.context.profile, legacy_shape=True, origins=self.receivers)
        if decision.action is Action.LEAVE and dispatcher is None:
            return True
        name = receiver_text(receiver)
        # ``wrap_env`` builds this class for the envs its ``isinstance(env, gym.Env)`` check
        # passes: it forwards to Gym envs, and a bare ``render()`` drew a window with legacy Gym
        which = (
            f"`{name}` is a Gym env where `{dispatcher}` builds this class for Gym envs; legacy render() drew a window, "
            "a Gymnasium env draws only when made with render_mode=\"human\": "
            if dispatcher is not None
            else f"if `{name}` is a Gym env, "
        )
        self.report(
            call,
            "GM401",
            f"`{self.facts.segment(call)}` passes on what its callers give (legacy: mode=...), and Gymnasium's render() "
            f"takes no arguments: {which}pass the mode as render_mode= (and any size) to gym.make "
            f"where it is made and call `{name}.render()` bare",
            FixKind.FLAG,
            # the same call in reset and step: one decision; an adapter's render() forwarding
            # in several branches: one decision, its own signature with the make's
            question=("render-forward", id(function)) if function is not None and function.name == "render" else self._same_render_call(call, receiver),
        )
        return True

    def _forward_of_bare_callers(self, call: ast.Call, receiver: ast.expr, function: ast.AST) -> bool:
        """``def render(self, *arg): self.env.render(*arg)`` in a plain class of the run
        holding an env this module makes with ``gym.make``, where every render call of the
        module passes nothing and only this module builds the class: what the forward hands
        on is always nothing, so each caller's ``x.render()`` is a bare render of that env.
        Those callers become the sites (their schedule moves to the make, as for a direct
        ``env.render()``), and the forward drops its arguments once the make has a mode."""
        classdef = self.facts.parent(function)
        if not isinstance(classdef, ast.ClassDef) or not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
            return False
        args = function.args
        if args.posonlyargs or args.args[1:] or args.kwonlyargs or len(args.args) != 1:
            return False  # only ``self`` and the packed arguments it hands on
        own = {a.arg for a in (args.vararg, args.kwarg) if a is not None}
        handed = [a.value for a in call.args if isinstance(a, ast.Starred)] + [k.value for k in call.keywords if k.arg is None]
        if not handed or len(handed) != len(call.args) + len(call.keywords):
            return False  # only ``*arg`` / ``**kw`` handed on, nothing of its own
        if not all(isinstance(h, ast.Name) and h.id in own for h in handed):
            return False
        project = self.receivers.project
        if project is not None and (
            project.built_elsewhere(classdef.name) or project.subclassed_elsewhere(classdef.name) or project.render_called_elsewhere()
        ):
            return False  # callers the module does not show may pass a mode
        creation = self.finder.find(receiver)
        if not (creation.found and creation.complete and all(self._is_gym_make(make) for make in creation.calls)):
            return False
        callers: list[ast.Call] = []
        instances = CreationFinder(self.facts, self.receivers, lambda c: self.receivers.local_class(c.func) is classdef)
        for render in self.facts.attribute_calls.get("render", []):
            if render is call:
                continue
            if render.args or render.keywords:
                return False  # some render of the module passes a mode: it may reach this forward
            inner = render.func.value  # type: ignore[attr-defined]
            if self.receivers.is_self(inner) and self.facts.enclosing_class(render) is classdef:
                callers.append(render)
                continue
            made = instances.find(inner)
            if made.found and made.calls and all(self.receivers.local_class(c.func) is classdef for c in made.calls):
                callers.append(render)
        if not callers:
            return False
        if self._steps_drawn(instances, classdef, callers):
            self._drawn_by_forward.update(id(make) for make in creation.calls)
        for caller in callers:
            self._forwarded_sites.append(RenderSite(caller, "GM402", HUMAN, (), Action.REWRITE, creation))
        self._forwards.append((call, [id(make) for make in creation.calls]))
        return True

    def _steps_drawn(self, instances: CreationFinder, classdef: ast.ClassDef, callers: list[ast.Call]) -> bool:
        """Every ``x.step(...)`` of the class's instances sits in a loop that holds one of the
        ``callers``: the legacy code drew each step, as a human-mode env does."""
        drawn = {id(caller) for caller in callers}
        steps = [
            step
            for step in self.facts.attribute_calls.get("step", [])
            if (made := instances.find(step.func.value)).found  # type: ignore[attr-defined]
            and all(self.receivers.local_class(c.func) is classdef for c in made.calls)
        ]
        for step in steps:
            loop = next((a for a in self.facts.ancestors(step) if isinstance(a, (ast.For, ast.While, ast.AsyncFor))), None)
            if loop is None or not any(id(node) in drawn for node in walk(loop)):
                return False
        return bool(steps)

    def _plan_forwards(self) -> None:
        """The forwards whose make was given a mode hand on nothing now (``render()`` bare)."""
        for call, keys in self._forwards:
            if keys and all(key in self._added for key in keys):
                self.plan.replace(call, lambda node: node.with_changes(args=()))
                self.report(
                    call,
                    "GM401",
                    "every render() that reaches this forward passes nothing, so it hands on nothing: called bare, "
                    "with the mode at the make",
                    tier=Tier.NOTE,
                )

    def _report_own_forward(self, call: ast.Call, receiver: ast.expr) -> bool:
        """``holder.render()`` on an instance of a plain class (of this module or of the
        run) whose own ``render()`` forwards bare to the env it holds (``self.env.render()``):
        that forward is the render site, and its make's mode is decided there; this call
        repeats the decision, so it is a note pointing at it, not a second question."""
        statement = self.receivers.statement_seen(receiver) if isinstance(receiver, ast.Name) else None
        value = statement.value if isinstance(statement, ast.Assign) and len(statement.targets) == 1 else None
        if not isinstance(value, ast.Call):
            return False
        classdef = self.receivers.local_class(value.func)
        where: str | None = None
        if classdef is not None:
            forward = held_env_render_forward(self.facts, self.receivers, classdef)
            where = f"line {forward.lineno}" if forward is not None else None
        elif self.receivers.project is not None:
            found = {f for q in self.facts.qualified_names(value.func) if (f := self.receivers.project.render_forward(q)) is not None}
            if len(found) == 1:
                where = f"in {found.pop()}"
        if where is None:
            return False
        self.report(
            call,
            "GM402",
            f"not rewritten: `{self.facts.segment(call)}` calls `{self.facts.segment(value.func)}.render()`, which forwards "
            f"to the env it holds ({where}): the render mode is decided there",
            FixKind.FLAG,
            tier=Tier.NOTE,
        )
        return True

    def _plain_class_method(self, function: ast.AST) -> bool:
        """A method of a class that is neither an env nor a wrapper (an adapter holding an
        env, maybe on a base of the project's own): no Env/Wrapper rule looks at its
        render(), so what it hands on to the env's render() is reported here."""
        classdef = self.facts.parent(function)
        if not isinstance(classdef, ast.ClassDef):
            return False
        if self.receivers.is_gym_wrapper_class(classdef) or EnvClasses.of(self.facts, self.receivers).is_custom_env(classdef):
            return False
        names = [q for base in classdef.bases for q in self.facts.qualified_names(base)]
        return not any(q.split(".", 1)[0] in ("gym", "gymnasium") for q in names)

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

    def _render_keeps(self, receiver: ast.expr, call: ast.Call, modeless: bool = False) -> str | None:
        """The classes of the run every make behind ``receiver`` builds, where their render
        takes the arguments ``call`` passes, each by its own parameter
        (``RegistryView.render_takes_of_id``, ``modeless`` too); else None."""
        if any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords):
            return None
        keywords = tuple(k.arg for k in call.keywords if k.arg is not None)
        project = self.receivers.project
        if project is None:
            return None
        # the makes behind the name, through the wrappers it is rebound to (legacy wrappers
        # handed render(close=...) on to the env)
        creation = self.finder.find(receiver)
        if not creation.complete or not creation.calls:
            return None
        found = set()
        for make in creation.calls:
            ids = make_ids(self.facts, self.receivers, make)
            if not ids or None in ids:
                return None
            for env_id in ids:
                assert env_id is not None
                keeper = project.render_takes_of_id(env_id, keywords, len(call.args), modeless)
                if keeper is None:
                    return None
                found.add(keeper)
        return ", ".join(sorted(found)) or None

    def _plan_close(self, call: ast.Call, receiver: ast.expr, decision: Decision) -> None:
        action, reason = decision.action, decision.reason
        if action is Action.REPORT:
            # whether it is a Gym env is the receiver's one question, asked by its reset and
            # step too (a parameter: once for the def)
            question = self.receiver_question(receiver, decision)
            self.report(call, "GM406", f"{reason}: render(close=True) is close() on a Gym env", FixKind.FLAG, question=question)
            return
        if isinstance(receiver, ast.Attribute) and receiver.attr == "unwrapped" and self._render_keeps(receiver.value, call):
            return  # the env's own render(close=...), as the branch below writes it
        keeper = self._render_keeps(receiver, call)
        if keeper is not None:
            # The run keeps that class's render(close=...) (its render is migrated with the
            # parameter), so the call means "close only the viewer"; close() would shut the
            # whole env down, and Gymnasium's wrappers (make adds some) take no render
            # arguments: the env's own render is reached through unwrapped.
            self.plan.replace(call, unwrapped_render_call)
            self.report(
                call,
                "GM406",
                f"render(close=True) -> unwrapped.render(close=True): the render() of this env's class (defined in "
                f"`{keeper}`) keeps its `close` parameter, which closes only the viewer, where close() shuts the env "
                "down; Gymnasium's wrappers' render() takes no arguments",
                FixKind.ASSIST,
            )
            return
        self.plan.replace(call, close_call)
        if action is Action.REWRITE_FOR_REVIEW:
            self.report(call, "GM406", f"render(close=True) -> close(); {reason}", FixKind.ASSIST)
        else:
            self.report(call, "GM406", "render(close=True) -> close()")
