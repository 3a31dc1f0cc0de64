"""GM407: consumers of frames need ``render_mode="rgb_array"`` at the make that feeds them:
``RecordVideo``, ``gymnasium.utils.play.play``, Stable-Baselines3's ``VecVideoRecorder``
(SB3's ``make_vec_env`` takes the mode in ``env_kwargs``), and a legacy ``Monitor`` that
records videos, which the wrapper family replaces by ``RecordVideo`` (GM611). Also the
frame an SB3 VecEnv's ``render()`` returns, used where its envs may have no frame mode."""

from __future__ import annotations

import ast

from gymmigrate.facts import names as N
from gymmigrate.facts.class_shapes import renders_nothing
from gymmigrate.facts.decisions import Action, receiver_text
from gymmigrate.facts.frame_modes import frameless_env
from gymmigrate.facts.import_guards import import_error_guard
from gymmigrate.facts.module import keyword
from gymmigrate.findings import FixKind
from gymmigrate.rules.render_calls import first_argument
from gymmigrate.rules.rendering.common import RGB_ARRAY, RenderingBase, RenderSite

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
RECORDER_ATTRIBUTES = ("RecordVideo", "play", "VecVideoRecorder", "Monitor")


class RecorderSites(RenderingBase):
    """The recorder sites and the frames of SB3 VecEnvs (mixed into the family)."""

    def _recorder_candidates(self) -> list[ast.Call]:
        found = [call for calls in self.facts.calls_by_name.values() for call in calls]
        found.extend(call for attr in RECORDER_ATTRIBUTES for call in self.facts.attribute_calls.get(attr, []))
        return found

    def _recorder_site(self, call: ast.Call) -> RenderSite | None:
        consumer: str | None = None
        accepted: tuple[str, ...] = (RGB_ARRAY,)
        monitor = False
        qualified = self.facts.qualified_names(call.func)
        for q in qualified:
            rest = N.strip_gym_prefix(q)
            if rest in _GYM_RECORDERS:
                consumer, accepted = _GYM_RECORDERS[rest]
            elif q in _SB3_RECORDERS:
                consumer = "VecVideoRecorder"
            elif rest in _MONITORS and not self._guarded_import(call.func):
                consumer, monitor = "RecordVideo", True
        if monitor and not all(N.strip_gym_prefix(q) in _MONITORS for q in qualified):
            return None  # maybe the project's own Monitor: the wrapper family leaves it, asking (GM611)
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

    def _guarded_import(self, func: ast.expr) -> bool:
        """``func`` is a name imported under ``try: ... except ImportError:``: the wrapper
        family leaves such a Monitor as it is (under Gymnasium the fallback is what runs)."""
        if not isinstance(func, ast.Name):
            return False
        for binding in self.facts.bindings_of(func):
            statement = self.facts.parent(binding)
            if isinstance(binding, ast.alias) and isinstance(statement, ast.ImportFrom) and import_error_guard(self.facts, statement):
                return True
        return False

    def _monitor_env(self, call: ast.Call) -> ast.expr | None:
        """The env of a ``Monitor`` that becomes ``RecordVideo`` (GM611), else None.

        Mirrors the wrapper family's rewrite: it needs the env and the directory, no
        star arguments, and videos (``video_callable=False``, or an env whose class declares
        no frame mode, ``frame_modes``, becomes RecordEpisodeStatistics).
        """
        if not call.args or any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords):
            return None
        values: dict[str, ast.expr] = dict(zip(_MONITOR_POSITIONS, call.args))
        values.update((k.arg, k.value) for k in call.keywords if k.arg is not None)
        trigger = values.get("video_callable")
        if "directory" not in values or (isinstance(trigger, ast.Constant) and trigger.value is False):
            return None
        env = values.get("env")
        if env is not None and frameless_env(self.facts, self.receivers, env) is not None:
            return None  # an env that gives no frames: its Monitor recorded none, and becomes statistics alone
        return env

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
