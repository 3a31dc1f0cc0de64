"""Using wrappers: forwarding, renamed, changed and removed wrappers (GM604-GM606, GM608-GM615).

Gymnasium 1.0 reworked ``gymnasium.wrappers`` (1.0 release notes; ``wrappers/__init__.py``
``_renamed_wrapper``) and removed ``Wrapper.__getattr__``:

* GM604 (ASSIST) attribute forwarding is gone: on an env built through ``make``/wrappers,
  ``env.x_threshold`` raises ``AttributeError`` on 1.x. Base-env state and methods become
  ``env.unwrapped.foo``; anything a wrapper may define becomes ``env.get_wrapper_attr("foo")``
  (outermost to base, exactly what forwarding did). Writes are reported (forwarding never
  applied to them). A raw env built by its own constructor never had the problem.
* GM605 (ASSIST) ``env._max_episode_steps`` -> ``env.spec.max_episode_steps`` for envs from
  ``make``; ``env.get_wrapper_attr("_max_episode_steps")`` when the spec may be ``None``.
* GM606 (FLAG) ``gym.make(id).env`` (legacy: "drop the TimeLimit"), ``env.env.env`` chains
  and ``isinstance(env, TimeLimit)``: ``make`` now stacks three wrappers.
* GM608 (AUTO; ASSIST for PixelObservationWrapper) renamed wrappers, in imports, attribute
  paths and every use of an imported name; FrameStack's ``num_stack``/``lz4_compress`` too.
* GM609 (AUTO; FLAG where a person must choose) changed signatures of kept wrappers.
* GM610 (FLAG) removed wrappers: EnvCompatibility, StepAPICompatibility, LazyFrames, VideoRecorder.
* GM611 (ASSIST) ``Monitor(env, dir, ...)`` -> ``RecordVideo(RecordEpisodeStatistics(env),
  video_folder=dir, episode_trigger=...)``. Stable-Baselines3's ``Monitor`` is another
  class and is never touched (SB108).
* GM612 (ASSIST) ``AutoResetWrapper`` -> ``Autoreset``, which now resets on the *next* step
  and no longer fills ``info["final_observation"]`` (reads of it are reported).
* GM613 (ASSIST) single-env wrappers around a Gym vector env -> ``gymnasium.wrappers.vector.X``
  (1.x ``Wrapper.__init__`` raises for a ``VectorEnv``).
* GM614 (AUTO) ``gymnasium.experimental.wrappers.XxxV0`` (0.28-0.29) -> ``gymnasium.wrappers.Xxx``.
* GM615 (FLAG) ``AtariPreprocessing`` on a base env that already skips frames (it raises).
"""

from __future__ import annotations

import re
from collections.abc import Sequence

import libcst as cst
from libcst.codemod.visitors import AddImportsVisitor, RemoveImportsVisitor
from libcst.metadata import Assignment, PositionProvider, ScopeProvider

from gymmigrate.analysis import names as N
from gymmigrate.analysis.receivers import METADATA, EnvKind, ReceiverAnalysis, call_argument, join_kinds
from gymmigrate.analysis.syntax import dotted_node, keyword_argument, string_value
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileProfile, Rule, RulePass

ATTRIBUTE_RULES = (
    Rule("GM604", "attribute forwarding removed", FixKind.ASSIST, "`env.foo` -> `env.unwrapped.foo` / `env.get_wrapper_attr(\"foo\")`."),
    Rule("GM605", "env._max_episode_steps", FixKind.ASSIST, "`env._max_episode_steps` -> `env.spec.max_episode_steps`."),
    Rule("GM606", "wrapper-stack assumptions", FixKind.FLAG, "`gym.make(id).env`, `env.env.env` and `isinstance(env, TimeLimit)` are reported."),
)
RENAME_RULES = (
    Rule("GM608", "renamed wrappers", FixKind.AUTO, "`FrameStack` -> `FrameStackObservation` and the other 1.0 renames."),
    Rule("GM609", "wrapper signature changes", FixKind.AUTO, "Arguments of TransformObservation, ResizeObservation... follow 1.x."),
    Rule("GM610", "removed wrappers", FixKind.FLAG, "EnvCompatibility, StepAPICompatibility, LazyFrames and VideoRecorder are reported."),
    Rule("GM611", "Monitor", FixKind.ASSIST, "`Monitor(env, dir)` -> `RecordVideo(RecordEpisodeStatistics(env), video_folder=dir)`."),
    Rule("GM612", "Autoreset semantics", FixKind.ASSIST, "`AutoResetWrapper` -> `Autoreset` (resets on the next step); `final_observation` reads are reported."),
    Rule("GM613", "single-env wrappers on vector envs", FixKind.ASSIST, "Wrappers around a Gym vector env come from `gymnasium.wrappers.vector`."),
    Rule("GM614", "gymnasium.experimental wrappers", FixKind.AUTO, "`gymnasium.experimental.wrappers.XxxV0` -> `gymnasium.wrappers.Xxx`."),
    Rule("GM615", "AtariPreprocessing frameskip", FixKind.FLAG, "`AtariPreprocessing` on a base env that skips frames is reported."),
)

# -- tables (gymnasium 1.4 ``wrappers/__init__.py`` and ``wrappers/vector/__init__.py``) ------

RENAMED = {
    "AutoResetWrapper": "Autoreset",
    "FrameStack": "FrameStackObservation",
    "GrayScaleObservation": "GrayscaleObservation",
    "PixelObservationWrapper": "AddRenderObservation",
    "FilterObservationWrapper": "FilterObservation",
}
EXPERIMENTAL_SPECIAL = {
    "LambdaObservationV0": "TransformObservation",
    "LambdaActionV0": "TransformAction",
    "LambdaRewardV0": "TransformReward",
    "PixelObservationV0": "AddRenderObservation",
    "AutoresetV0": "Autoreset",
    "NormalizeRewardV1": "NormalizeReward",
}
REMOVED = {
    "EnvCompatibility": "use Shimmy's GymV21Environment-v0 / GymV26Environment-v0 to load a legacy env",
    "StepAPICompatibility": "use gymnasium.utils.step_api_compatibility's converters",
    "LazyFrames": "frame stacks are plain numpy arrays now (FrameStackObservation)",
    "VideoRecorder": "use gymnasium.wrappers.RecordVideo or gymnasium.utils.save_video.save_video",
}
VECTOR_WRAPPERS = frozenset(
    {
        "TransformObservation", "FilterObservation", "FlattenObservation", "GrayscaleObservation",
        "ResizeObservation", "ReshapeObservation", "RescaleObservation", "DtypeObservation",
        "NormalizeObservation", "TransformAction", "ClipAction", "RescaleAction", "TransformReward",
        "ClipReward", "NormalizeReward", "RecordEpisodeStatistics", "RecordVideo", "HumanRendering",
        "ArrayConversion", "JaxToNumpy", "JaxToTorch", "NumpyToTorch",
    }
)  # fmt: skip
SINGLE_ENV_WRAPPERS = VECTOR_WRAPPERS | {
    "AtariPreprocessing", "DelayObservation", "FrameStackObservation", "TimeAwareObservation",
    "MaxAndSkipObservation", "AddRenderObservation", "StickyAction", "RepeatAction", "TimeLimit",
    "Autoreset", "PassiveEnvChecker", "OrderEnforcing", "RenderCollection", "AddWhiteNoise", "ObstructView",
}  # fmt: skip

# Defined on gymnasium.Wrapper itself (``dir(gymnasium.Wrapper)``, 1.4): reads never needed forwarding.
# ``seed`` is the seeding rules' business (GM203).
SAFE_ATTRIBUTES = frozenset(
    {
        "env", "unwrapped", "spec", "action_space", "observation_space", "metadata", "render_mode",
        "np_random", "np_random_seed", "reset", "step", "render", "close", "get_wrapper_attr",
        "set_wrapper_attr", "has_wrapper_attr", "class_name", "wrapper_spec", "seed", "reward_range",
    }
)  # fmt: skip
# State and methods of the base envs that legacy code reached through forwarding.
BASE_ENV_ATTRIBUTES = frozenset(
    {
        "state", "x_threshold", "theta_threshold_radians", "gravity", "masscart", "masspole", "length",
        "force_mag", "tau", "max_speed", "max_torque", "goal_position", "goal_velocity", "ale", "lives",
        "get_action_meanings", "get_keys_to_action", "desc", "P", "s", "lastaction", "nS", "nA", "model",
        "data", "sim", "lander", "world", "game", "compute_reward", "goal", "frameskip", "_frameskip",
    }
)  # fmt: skip
# Attributes a gymnasium wrapper class sets itself: reading them on that wrapper is fine.
OWN_ATTRIBUTES = {
    "RecordEpisodeStatistics": {"return_queue", "length_queue", "time_queue", "episode_count", "buffer_length",
                                "episode_returns", "episode_lengths", "episode_start_time", "stats_key"},
    "NormalizeObservation": {"obs_rms", "epsilon", "update_running_mean"},
    "NormalizeReward": {"return_rms", "discounted_reward", "gamma", "epsilon", "update_running_mean"},
    "TimeLimit": {"_max_episode_steps", "_elapsed_steps"},
    "RecordVideo": {"video_folder", "episode_trigger", "step_trigger", "video_length", "name_prefix", "episode_id"},
}  # fmt: skip

FINAL_INFO_KEYS = ("final_observation", "final_info")
# The single-env Autoreset wrapper in code (not ``AutoresetMode``, not comments).
_AUTORESET_USE = re.compile(r"^[^#\n]*\b(?:AutoResetWrapper|Autoreset)\b", re.M)

# Where an env came from, for GM604-GM606.
MADE = "made"  # gym.make (+ wrappers): a wrapper stack with a spec
WRAPPED = "wrapped"  # wrapper constructors around something else: a stack, maybe no spec
INNER = "inner"  # a wrapper's ``self.env`` / ``env`` argument: almost always a make() result
RAW = "raw"  # an env class's constructor or ``.unwrapped``: no wrapper in between


def _wrapper_rest(qualified: str) -> str | None:
    """``gymnasium.wrappers.frame_stack.FrameStack`` -> ``FrameStack``; ``experimental.wrappers.X`` -> ``X``."""
    rest = N.strip_gym_prefix(qualified)
    if rest is None:
        return None
    for prefix in ("wrappers.", "experimental.wrappers."):
        if rest.startswith(prefix):
            tail = rest[len(prefix) :]
            if tail.startswith("vector."):
                return None
            return tail.rsplit(".", 1)[-1]
    return None


def experimental_name(name: str) -> str | None:
    """``ClipActionV0`` -> ``ClipAction``; None for a name that is not an experimental wrapper."""
    if name in EXPERIMENTAL_SPECIAL:
        return EXPERIMENTAL_SPECIAL[name]
    for suffix in ("V0", "V1"):
        if name.endswith(suffix) and name[:1].isupper():
            return name[: -len(suffix)]
    return None


def _dotted(node: cst.CSTNode) -> str:
    if isinstance(node, cst.Name):
        return node.value
    if isinstance(node, cst.Attribute):
        return f"{_dotted(node.value)}.{node.attr.value}"
    return ""






def _positional(call: cst.Call) -> list[cst.Arg]:
    return [a for a in call.args if a.keyword is None and not a.star]


def _parameter(call: cst.Call, name: str, position: int) -> cst.Arg | None:
    """The argument bound to a wrapper parameter, passed by keyword or at ``position``."""
    found = keyword_argument(call, name)
    if found is None:
        positional = _positional(call)
        if len(positional) > position:
            found = positional[position]
    return found


def _missing_or_none(call: cst.Call, name: str, position: int) -> bool:
    """A required parameter left out (and not possibly in *args/**kwargs) or passed None."""
    found = _parameter(call, name, position)
    if found is None:
        return not any(a.star for a in call.args)
    return _is_none(found.value)


def _is_none(node: cst.BaseExpression) -> bool:
    return isinstance(node, cst.Name) and node.value == "None"




def _without_args(call: cst.Call, drop: list[cst.Arg]) -> list[cst.Arg]:
    """The call's arguments minus ``drop``, keeping the last comma style right."""
    kept = [a for a in call.args if not any(a is d for d in drop)]
    if kept and call.args and kept[-1] is not call.args[-1]:
        kept[-1] = kept[-1].with_changes(comma=call.args[-1].comma)
    return kept


def _renamed_keyword(arg: cst.Arg, new: str) -> cst.Arg:
    assert arg.keyword is not None
    return arg.with_changes(keyword=arg.keyword.with_changes(value=new))


def _replace_arg(args: list[cst.Arg], old: cst.Arg, new: cst.Arg) -> list[cst.Arg]:
    return [new if a is old else a for a in args]


class _SkipsImportedNames:
    """Names inside import statements are the imports rules' business, not a use.

    Returning False skips an import's children; its own leave_ method still runs.
    """

    def visit_Import(self, node: cst.Import) -> bool:
        return False

    def visit_ImportFrom(self, node: cst.ImportFrom) -> bool:
        return False


class WrapperRenamesPass(_SkipsImportedNames, RulePass):
    """GM608-GM615: wrapper names, arguments and stacks.

    Runs right after the make() keyword pass and before the rendering pass (ORDER 32), so
    the RecordVideo that replaces Monitor gets its ``render_mode="rgb_array"`` in the same run.
    """

    RULES = RENAME_RULES
    ORDER = 31
    METADATA_DEPENDENCIES = (PositionProvider, *METADATA)

    def __init__(self, context) -> None:  # type: ignore[no-untyped-def]
        super().__init__(context)
        self._renamed_locals: dict[str, str] = {}  # imported name -> new name
        self._monitor_locals: set[str] = set()
        self._gymnasium_alias: str | None = None
        self._uses_autoreset = False
        self._resolving: set[int] = set()

    @classmethod
    def applies_to(cls, source: str, profile: FileProfile) -> bool:
        return "gym" in source

    def visit_Module(self, node: cst.Module) -> None:
        self.analysis = ReceiverAnalysis(node, self.metadata)
        code = node.code
        self._uses_autoreset = _AUTORESET_USE.search(code) is not None
        for statement in node.body:
            if isinstance(statement, cst.SimpleStatementLine):
                for small in statement.body:
                    if isinstance(small, cst.Import):
                        for alias in small.names:
                            if _dotted(alias.name) == "gymnasium":
                                self._gymnasium_alias = alias.asname.name.value if alias.asname else "gymnasium"  # type: ignore[union-attr]

    # -- imports: GM608, GM611, GM614 --------------------------------------------------------

    def leave_ImportFrom(
        self, original_node: cst.ImportFrom, updated_node: cst.ImportFrom
    ) -> cst.ImportFrom | cst.RemovalSentinel:
        if updated_node.relative or updated_node.module is None or isinstance(updated_node.names, cst.ImportStar):
            return updated_node
        module = _dotted(updated_node.module)
        rest = N.strip_gym_prefix(module)
        if rest is None:
            return updated_node
        if rest.startswith("experimental.wrappers") or rest.startswith("experimental.vector"):
            return self._experimental_import(original_node, updated_node, rest)
        if rest not in ("wrappers", "wrappers.vector", "wrappers.monitor"):
            return updated_node
        if module.startswith("gym.") and not (
            len(updated_node.names) == 1 and _dotted(updated_node.names[0].name) == "Monitor"
        ):
            # The imports rules left this legacy import (it names something removed): its
            # names stay as they are until a person splits it.
            return updated_node
        new_names: list[cst.ImportAlias] = []
        new_module = module
        changed = False
        for alias in updated_node.names:
            name = _dotted(alias.name)
            bound = alias.asname.name.value if alias.asname else name  # type: ignore[union-attr]
            if name in RENAMED and rest == "wrappers":
                new = RENAMED[name]
                new_names.append(alias.with_changes(name=cst.Name(new)))
                if alias.asname is None:
                    self._renamed_locals[bound] = new
                code, kind = self._rename_code(name)
                self.report(original_node, code, f"`{name}` was renamed `{new}` in Gymnasium 1.0", kind=kind)
                changed = True
            elif name == "VectorListInfo" and rest in ("wrappers", "wrappers.vector"):
                if rest == "wrappers" and len(updated_node.names) > 1:
                    new_names.append(alias)  # moved by hand below would reorder imports: report instead
                    self.report(
                        original_node,
                        "GM608",
                        "`VectorListInfo` is now `gymnasium.wrappers.vector.DictInfoToList`: import it from there",
                        kind=FixKind.FLAG,
                    )
                    continue
                new_module = "gymnasium.wrappers.vector"
                new_names.append(alias.with_changes(name=cst.Name("DictInfoToList")))
                if alias.asname is None:
                    self._renamed_locals[bound] = "DictInfoToList"
                self.report(original_node, "GM608", "`VectorListInfo` is now `gymnasium.wrappers.vector.DictInfoToList`")
                changed = True
            elif name == "Monitor" and rest in ("wrappers", "wrappers.monitor"):
                present = {_dotted(a.name) for a in updated_node.names}
                for replacement in ("RecordEpisodeStatistics", "RecordVideo"):
                    if replacement not in present:
                        new_names.append(cst.ImportAlias(name=cst.Name(replacement)))
                        # ``Monitor(..., video_callable=False)`` needs no RecordVideo: drop it if unused.
                        RemoveImportsVisitor.remove_unused_import(self.context.codemod, "gymnasium.wrappers", replacement)
                self._monitor_locals.add(bound)
                new_module = "gymnasium.wrappers"
                self.report(original_node, "GM611", "`Monitor` is gone: it is replaced by RecordVideo and RecordEpisodeStatistics")
                changed = True
            else:
                new_names.append(alias)
        if not changed:
            return updated_node
        if not new_names:
            return cst.RemoveFromParent()
        return updated_node.with_changes(module=dotted_node(new_module), names=_with_commas(new_names, updated_node.names))

    def _experimental_import(
        self, original_node: cst.ImportFrom, updated_node: cst.ImportFrom, rest: str
    ) -> cst.ImportFrom:
        new_module = "gymnasium." + rest.replace("experimental.wrappers", "wrappers", 1).replace(
            "experimental.vector", "vector", 1
        )
        names = []
        for alias in updated_node.names:  # type: ignore[union-attr]
            name = _dotted(alias.name)
            new = experimental_name(name) if rest.startswith("experimental.wrappers") else None
            if new is None:
                names.append(alias)
                continue
            names.append(alias.with_changes(name=cst.Name(new)))
            if alias.asname is None:
                self._renamed_locals[name] = new
        self.report(original_node, "GM614", f"gymnasium.{rest} -> {new_module}: the experimental wrappers became the 1.0 wrappers")
        return updated_node.with_changes(module=dotted_node(new_module), names=_with_commas(names, updated_node.names))  # type: ignore[arg-type]

    def _rename_code(self, old: str) -> tuple[str, FixKind | None]:
        if old == "AutoResetWrapper":
            return "GM612", None
        if old == "PixelObservationWrapper":
            return "GM608", FixKind.ASSIST
        return "GM608", None

    # -- names and attribute paths: GM608, GM610, GM612, GM614 ----------------------------------

    def leave_Name(self, original_node: cst.Name, updated_node: cst.Name) -> cst.Name:
        if original_node.value not in self._renamed_locals:
            return updated_node
        parent = self.analysis.parent(original_node)
        if isinstance(parent, cst.Attribute) and parent.attr is original_node:
            return updated_node
        if not any(_wrapper_rest(q) == original_node.value or q.endswith("VectorListInfo") for q in self.analysis.qualified_names(original_node)):
            return updated_node
        new = self._renamed_locals[original_node.value]
        if not isinstance(parent, cst.Call) or parent.func is not original_node:
            self._report_reference(original_node, original_node.value, new)
        return updated_node.with_changes(value=new)

    def _report_reference(self, node: cst.CSTNode, old: str, new: str) -> None:
        if old.endswith(("V0", "V1")) or old in EXPERIMENTAL_SPECIAL:
            self.report(node, "GM614", f"`{old}` is `{new}` in Gymnasium 1.x")
            return
        code, kind = self._rename_code(old)
        message = f"`{old}` was renamed `{new}` in Gymnasium 1.0"
        if code == "GM612":
            message = _AUTORESET_MESSAGE
        elif old == "PixelObservationWrapper":
            message = _PIXELS_MESSAGE
        self.report(node, code, message, kind=kind)

    def leave_Attribute(
        self, original_node: cst.Attribute, updated_node: cst.Attribute
    ) -> cst.BaseExpression:
        qualified = self.analysis.qualified_names(original_node)
        for q in qualified:
            rest = N.strip_gym_prefix(q)
            if rest is None:
                continue
            name = rest.rsplit(".", 1)[-1]
            if rest.startswith("wrappers.") and not rest.startswith("wrappers.vector.") and name in RENAMED:
                parent = self.analysis.parent(original_node)
                if not isinstance(parent, cst.Call) or parent.func is not original_node:
                    self._report_reference(original_node, name, RENAMED[name])
                return updated_node.with_changes(attr=cst.Name(RENAMED[name]))
            if rest in ("wrappers.VectorListInfo", "wrappers.vector_list_info.VectorListInfo"):
                self.report(original_node, "GM608", "`VectorListInfo` is now `gymnasium.wrappers.vector.DictInfoToList`")
                root = _root_name(original_node)
                return dotted_node(f"{root}.wrappers.vector.DictInfoToList")  # type: ignore[return-value]
            if rest.startswith("experimental.wrappers.") and experimental_name(name):
                new = experimental_name(name)
                if ".experimental.wrappers." not in _dotted(original_node):
                    self.report(original_node, "GM614", f"`{name}` is `gymnasium.wrappers.{new}` in Gymnasium 1.x: "
                                "import it from there", kind=FixKind.FLAG)
                    return updated_node
                parent = self.analysis.parent(original_node)
                if not isinstance(parent, cst.Call) or parent.func is not original_node:
                    self.report(original_node, "GM614", f"`{name}` is `gymnasium.wrappers.{new}` in Gymnasium 1.x")
                vector = ".vector" if rest.startswith("experimental.wrappers.vector.") else ""
                return dotted_node(f"{_root_name(original_node)}.wrappers{vector}.{new}")  # type: ignore[return-value]
        return updated_node

    def visit_Name(self, node: cst.Name) -> None:
        self._check_removed(node)

    def visit_Attribute(self, node: cst.Attribute) -> None:
        self._check_removed(node)

    def _check_removed(self, node: cst.Name | cst.Attribute) -> None:
        """GM610: each use (not the import, which the imports rules report) of a removed wrapper."""
        parent = self.analysis.parent(node)
        if isinstance(parent, cst.Attribute) and parent.attr is node:
            return  # the attribute around it is the reference
        for q in self.analysis.qualified_names(node):
            rest = N.strip_gym_prefix(q)
            if rest is None or not rest.startswith("wrappers."):
                continue
            name = rest.rsplit(".", 1)[-1]
            if name in REMOVED and _dotted(node).endswith(name):
                self.report(node, "GM610", f"`{name}` was removed in Gymnasium 1.0: {REMOVED[name]}")
                return

    # -- calls: GM609, GM611, GM613, GM615, GM606 isinstance --------------------------------------

    def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.BaseExpression:
        wrapper = self._called_wrapper(original_node)
        if wrapper is None:
            self._check_final_info_get(original_node)
            return updated_node
        old, new = wrapper
        if old in self._monitor_locals or old == "Monitor":
            return self._monitor(original_node, updated_node)
        if new in REMOVED:
            return updated_node
        if old != new:
            self._report_reference(original_node, old, new)
        updated_node = self._vector(original_node, updated_node, new)
        handler = getattr(self, f"_args_{new}", None)
        if handler is not None:
            updated_node = handler(original_node, updated_node)
        return updated_node

    def _called_wrapper(self, call: cst.Call) -> tuple[str, str] | None:
        """(legacy name, 1.x name) of the gym/gymnasium wrapper class this call constructs."""
        func = call.func
        if isinstance(func, cst.Name) and func.value in self._monitor_locals:
            return func.value, "Monitor"
        for q in self.analysis.qualified_names(func):
            if q.startswith("gym."):
                continue  # imported by a legacy import the imports rules left alone: not migrated yet
            name = _wrapper_rest(q)
            if name is None:
                if q in ("gym.wrappers.monitor.Monitor", "gymnasium.wrappers.monitor.Monitor"):
                    return "Monitor", "Monitor"
                continue
            rest = N.strip_gym_prefix(q) or ""
            if rest.startswith("experimental."):
                return name, experimental_name(name) or name
            return name, RENAMED.get(name, name)
        if isinstance(func, cst.Name) and func.value in self._monitor_locals:
            return func.value, "Monitor"
        return None

    # GM609 argument fixes, one method per 1.x wrapper name.

    def _args_FrameStackObservation(self, original: cst.Call, call: cst.Call) -> cst.Call:
        args = list(call.args)
        notes = []
        kind: FixKind | None = None
        num_stack = keyword_argument(call, "num_stack")
        if num_stack is not None:
            args = _replace_arg(args, num_stack, _renamed_keyword(num_stack, "stack_size"))
            notes.append("`num_stack=` is `stack_size=`")
        lz4 = _parameter(call, "lz4_compress", 2)
        if lz4 is not None:
            args = [a for a in args if a is not lz4]
            notes.append("`lz4_compress` is gone (frames are a plain ndarray now)")
            if not (isinstance(lz4.value, cst.Name) and lz4.value.value == "False"):
                kind = FixKind.ASSIST
        if not notes:
            return call
        self.report(original, "GM609", "FrameStackObservation: " + "; ".join(notes), kind=kind)
        return call.with_changes(args=_fix_last_comma(args, call.args))

    def _args_AddRenderObservation(self, original: cst.Call, call: cst.Call) -> cst.Call:
        args = list(call.args)
        positional = _positional(call)
        if len(positional) > 2 or keyword_argument(call, "render_kwargs") is not None:
            self.report(
                original,
                "GM609",
                "AddRenderObservation has no render_kwargs: create the env with render_mode=\"rgb_array\" (and "
                "its render options) instead, then pass render_only/render_key",
                kind=FixKind.FLAG,
            )
            return call
        pixels_only = keyword_argument(call, "pixels_only")
        if pixels_only is not None:
            args = _replace_arg(args, pixels_only, _renamed_keyword(pixels_only, "render_only"))
        keys = keyword_argument(call, "pixel_keys")
        if keys is not None:
            value = keys.value
            single = (
                value.elements[0].value
                if isinstance(value, (cst.Tuple, cst.List)) and len(value.elements) == 1
                else None
            )
            if single is None:
                self.report(original, "GM609", "AddRenderObservation takes one `render_key`, not a list of pixel keys", kind=FixKind.FLAG)
                return call
            args = _replace_arg(args, keys, keys.with_changes(keyword=cst.Name("render_key"), value=single))
        return call.with_changes(args=args)

    def _args_TransformObservation(self, original: cst.Call, call: cst.Call) -> cst.Call:
        args = list(call.args)
        f = keyword_argument(call, "f")
        if f is not None:
            args = _replace_arg(args, f, _renamed_keyword(f, "func"))
        positional = _positional(call)
        has_space = keyword_argument(call, "observation_space") is not None or len(positional) >= 3
        func = f.value if f is not None else positional[1].value if len(positional) >= 2 else None
        if has_space:
            if f is not None:
                self.report(original, "GM609", "TransformObservation's `f=` is `func=`")
                return call.with_changes(args=args)
            return call
        if func is None or any(a.star for a in call.args):
            return call
        last = args[-1]
        comma = cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))
        space = cst.Arg(value=cst.Name("None"))
        if last.keyword is not None or f is not None:
            space = cst.Arg(
                keyword=cst.Name("observation_space"),
                value=cst.Name("None"),
                equal=cst.AssignEqual(cst.SimpleWhitespace(""), cst.SimpleWhitespace("")),
            )
        args = [*args[:-1], last.with_changes(comma=comma), space.with_changes(comma=last.comma)]
        if _keeps_shape(func):
            self.report(original, "GM609", "TransformObservation needs an observation_space: None keeps the env's, as before")
        else:
            self.report(
                original,
                "GM609",
                "TransformObservation needs an observation_space: None keeps the env's space, as legacy did; pass "
                "the new space if `func` changes the observation's shape or dtype",
                kind=FixKind.ASSIST,
            )
        return call.with_changes(args=args)

    def _args_TransformReward(self, original: cst.Call, call: cst.Call) -> cst.Call:
        f = keyword_argument(call, "f")
        if f is None:
            return call
        self.report(original, "GM609", "TransformReward's `f=` is `func=`")
        return call.with_changes(args=_replace_arg(list(call.args), f, _renamed_keyword(f, "func")))

    def _args_ResizeObservation(self, original: cst.Call, call: cst.Call) -> cst.Call:
        shape = _parameter(call, "shape", 1)
        if shape is None or not isinstance(shape.value, cst.Integer):
            return call
        size = shape.value
        pair = cst.Tuple(
            elements=[
                cst.Element(value=size, comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))),
                cst.Element(value=size.deep_clone()),
            ]
        )
        self.report(original, "GM609", f"ResizeObservation takes a (height, width) pair: {size.value} -> ({size.value}, {size.value})")
        return call.with_changes(args=_replace_arg(list(call.args), shape, shape.with_changes(value=pair)))

    def _args_RecordEpisodeStatistics(self, original: cst.Call, call: cst.Call) -> cst.Call:
        deque_size = keyword_argument(call, "deque_size")
        if deque_size is None:
            return call
        self.report(original, "GM609", "RecordEpisodeStatistics' `deque_size=` is `buffer_length=`")
        return call.with_changes(args=_replace_arg(list(call.args), deque_size, _renamed_keyword(deque_size, "buffer_length")))

    def _args_RecordVideo(self, original: cst.Call, call: cst.Call) -> cst.Call:
        new_step_api = keyword_argument(call, "new_step_api")
        if new_step_api is None:
            return call
        self.report(original, "GM609", "RecordVideo has no `new_step_api` (the five-value step is the only API)")
        return call.with_changes(args=_without_args(call, [new_step_api]))

    def _args_TimeLimit(self, original: cst.Call, call: cst.Call) -> cst.Call:
        if _missing_or_none(call, "max_episode_steps", 1):
            self.report(
                original,
                "GM609",
                "TimeLimit needs max_episode_steps in Gymnasium 1.x (legacy read it from the spec): pass the "
                "limit, e.g. env.spec.max_episode_steps",
                kind=FixKind.FLAG,
            )
        return call

    def _args_FilterObservation(self, original: cst.Call, call: cst.Call) -> cst.Call:
        if _missing_or_none(call, "filter_keys", 1):
            self.report(
                original,
                "GM609",
                "FilterObservation needs filter_keys in Gymnasium 1.x (None no longer means every key): list the keys",
                kind=FixKind.FLAG,
            )
        return call

    def _args_ClipAction(self, original: cst.Call, call: cst.Call) -> cst.Call:
        self.report(
            original,
            "GM609",
            "ClipAction now exposes action_space Box(-inf, inf): code or agents that read the bounds or sample "
            "from this env's action_space must use the inner env's space",
            kind=FixKind.FLAG,
        )
        return call

    def _args_AtariPreprocessing(self, original: cst.Call, call: cst.Call) -> cst.Call:
        frame_skip = _parameter(call, "frame_skip", 2)
        if frame_skip is not None and isinstance(frame_skip.value, cst.Integer) and frame_skip.value.value == "1":
            return call
        original_positional = _positional(original)
        if not original_positional:
            return call
        make = self._make_call(original_positional[0].value)
        if make is None or _frameskip_is_one(make):
            return call
        self.report(
            original,
            "GM615",
            "AtariPreprocessing skips frames itself and raises if the base env skips too: make the env with "
            "frameskip=1 (e.g. gym.make(\"ALE/Pong-v5\", frameskip=1))",
        )
        return call

    # GM611

    def _monitor(self, original: cst.Call, call: cst.Call) -> cst.BaseExpression:
        func = call.func
        if isinstance(func, cst.Attribute):
            prefix = _dotted(func.value) + "."
            if prefix.endswith(".monitor."):
                prefix = prefix[: -len("monitor.")]
        else:
            prefix = ""
        positional = _positional(call)
        named = {a.keyword.value: a for a in call.args if a.keyword is not None}
        if not positional or any(a.star for a in call.args):
            self.report(original, "GM611", "Monitor is gone: wrap with RecordEpisodeStatistics and RecordVideo", kind=FixKind.FLAG)
            return call
        order = ["env", "directory", "video_callable", "force", "resume", "write_upon_reset", "uid", "mode"]
        values: dict[str, cst.BaseExpression] = {}
        for key, arg in zip(order, positional):
            values[key] = arg.value
        for key, arg in named.items():
            values[key] = arg.value
        env = values.get("env")
        directory = values.get("directory")
        if env is None or directory is None:
            self.report(original, "GM611", "Monitor is gone: wrap with RecordEpisodeStatistics and RecordVideo", kind=FixKind.FLAG)
            return call
        stats = cst.Call(func=dotted_node(prefix + "RecordEpisodeStatistics"), args=[cst.Arg(value=env)])
        trigger = values.get("video_callable")
        dropped = sorted(k for k in values if k in ("force", "resume", "write_upon_reset", "uid", "mode"))
        note = ""
        if dropped:
            listed = ", ".join(f"`{k}`" for k in dropped)
            note = f"; {listed} {'has' if len(dropped) == 1 else 'have'} no equivalent and {'was' if len(dropped) == 1 else 'were'} dropped"
        if isinstance(trigger, cst.Name) and trigger.value == "False":
            self.report(original, "GM611", f"Monitor without videos is RecordEpisodeStatistics{note}")
            return stats
        eq = cst.AssignEqual(cst.SimpleWhitespace(""), cst.SimpleWhitespace(""))
        comma = cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))
        args = [
            cst.Arg(value=stats, comma=comma),
            cst.Arg(keyword=cst.Name("video_folder"), value=directory, equal=eq),
        ]
        if trigger is not None and not _is_none(trigger):
            args[-1] = args[-1].with_changes(comma=comma)
            args.append(cst.Arg(keyword=cst.Name("episode_trigger"), value=trigger, equal=eq))
        self.report(
            original,
            "GM611",
            "Monitor is RecordVideo(RecordEpisodeStatistics(env)): the env must be made with "
            f"render_mode=\"rgb_array\" for videos{note}",
        )
        return cst.Call(func=dotted_node(prefix + "RecordVideo"), args=args)

    # GM613

    def _vector(self, original: cst.Call, call: cst.Call, new: str) -> cst.Call:
        if new not in SINGLE_ENV_WRAPPERS:
            return call
        positional = _positional(original)
        if not positional or self._vector_kind(positional[0].value) is not EnvKind.GYM_VEC:
            return call
        if new not in VECTOR_WRAPPERS:
            self.report(
                original,
                "GM613",
                f"{new} wraps one env and has no vector version: apply it to each env, e.g. "
                f"gym.make_vec(..., wrappers=[...])",
                kind=FixKind.FLAG,
            )
            return call
        func = call.func
        if isinstance(func, cst.Attribute) and _dotted(func.value).endswith("wrappers"):
            new_func: cst.BaseExpression = cst.Attribute(value=cst.Attribute(value=func.value, attr=cst.Name("vector")), attr=cst.Name(new))
        else:
            root = self._gymnasium_alias
            if root is None:
                AddImportsVisitor.add_needed_import(self.context.codemod, "gymnasium")
                root = "gymnasium"
            new_func = dotted_node(f"{root}.wrappers.vector.{new}")
            if isinstance(func, cst.Name):
                # the single-env import may now be unused
                RemoveImportsVisitor.remove_unused_import(self.context.codemod, "gymnasium.wrappers", func.value)
        self.report(
            original,
            "GM613",
            f"a vector env needs gymnasium.wrappers.vector.{new} (the single-env wrapper raises on a VectorEnv); "
            "its info layout is per-env arrays",
        )
        return call.with_changes(func=new_func)

    def _make_call(self, expr: cst.BaseExpression, depth: int = 0) -> cst.Call | None:
        """The ``gym.make(...)`` call at the bottom of ``expr``'s wrapper stack, when it is clear."""
        if depth > 20:
            return None
        if isinstance(expr, cst.Call):
            for q in self.analysis.qualified_names(expr.func):
                rest = N.strip_gym_prefix(q)
                if rest in N.GYM_ENV_FACTORIES:
                    return expr
                if rest is not None and rest.startswith("wrappers.") and expr.args:
                    return self._make_call(expr.args[0].value, depth + 1)
            return None
        if isinstance(expr, cst.Name):
            try:
                scope = self.get_metadata(ScopeProvider, expr)
            except KeyError:
                return None
            found = []
            for assignment in scope[expr.value] if scope is not None else ():
                parent = self.analysis.parent(assignment.node) if isinstance(assignment, Assignment) else None
                assign = self.analysis.parent(parent) if isinstance(parent, cst.AssignTarget) else None
                if not isinstance(assign, cst.Assign):
                    return None
                if id(assign) in self._resolving:
                    continue
                self._resolving.add(id(assign))
                try:
                    found.append(self._make_call(assign.value, depth + 1))
                finally:
                    self._resolving.discard(id(assign))
            makes = {id(f): f for f in found if f is not None}
            return next(iter(makes.values())) if len(makes) == 1 and None not in found else None
        return None

    def _vector_kind(self, expr: cst.BaseExpression, depth: int = 0) -> EnvKind:
        """Like ``kind_of``, but a single-env wrapper around an env has that env's kind.

        The shared analysis calls every ``gym.wrappers.X(...)`` a single env, which is what
        this rule is about to correct, so ``envs = RecordEpisodeStatistics(envs)`` must not
        hide that ``envs`` was a vector env.
        """
        if depth > 20:
            return EnvKind.UNKNOWN
        if isinstance(expr, cst.Call):
            for q in self.analysis.qualified_names(expr.func):
                if _wrapper_rest(q) is not None and expr.args:
                    return self._vector_kind(expr.args[0].value, depth + 1)
            return self.analysis.kind_of(expr)
        if isinstance(expr, cst.Name):
            try:
                scope = self.get_metadata(ScopeProvider, expr)
            except KeyError:
                return EnvKind.UNKNOWN
            kinds = []
            for assignment in scope[expr.value] if scope is not None else ():
                parent = self.analysis.parent(assignment.node) if isinstance(assignment, Assignment) else None
                assign = self.analysis.parent(parent) if isinstance(parent, cst.AssignTarget) else None
                if not isinstance(assign, cst.Assign):
                    return self.analysis.kind_of(expr)
                if id(assign) in self._resolving:
                    continue
                self._resolving.add(id(assign))
                try:
                    kinds.append(self._vector_kind(assign.value, depth + 1))
                finally:
                    self._resolving.discard(id(assign))
            return join_kinds(kinds)
        return self.analysis.kind_of(expr)

    # -- GM612: final_observation reads ---------------------------------------------------------

    def visit_Subscript(self, node: cst.Subscript) -> None:
        if not self._uses_autoreset or len(node.slice) != 1:
            return
        index = node.slice[0].slice
        if isinstance(index, cst.Index) and string_value(index.value) in FINAL_INFO_KEYS:
            self._report_final_info(node, string_value(index.value))  # type: ignore[arg-type]

    def _check_final_info_get(self, call: cst.Call) -> None:
        if not self._uses_autoreset:
            return
        func = call.func
        if isinstance(func, cst.Attribute) and func.attr.value == "get" and call.args:
            key = string_value(call.args[0].value)
            if key in FINAL_INFO_KEYS:
                self._report_final_info(call, key)  # type: ignore[arg-type]

    def _report_final_info(self, node: cst.CSTNode, key: str) -> None:
        self.report(
            node,
            "GM612",
            f"Autoreset no longer fills info[\"{key}\"]: the step after an episode ends returns the reset "
            "observation (reward 0, action ignored); keep the last observation of the episode yourself",
            kind=FixKind.FLAG,
        )


class WrapperAttributesPass(_SkipsImportedNames, RulePass):
    """GM604-GM606: what legacy code read through ``Wrapper.__getattr__``."""

    RULES = ATTRIBUTE_RULES
    ORDER = 61
    METADATA_DEPENDENCIES = (PositionProvider, *METADATA)

    def __init__(self, context) -> None:  # type: ignore[no-untyped-def]
        super().__init__(context)
        self._resolving: set[int] = set()

    @classmethod
    def applies_to(cls, source: str, profile: FileProfile) -> bool:
        return "gym" in source

    def visit_Module(self, node: cst.Module) -> None:
        self.analysis = ReceiverAnalysis(node, self.metadata)

    def leave_Attribute(self, original_node: cst.Attribute, updated_node: cst.Attribute) -> cst.BaseExpression:
        return self._attribute_access(original_node, updated_node)

    def visit_Call(self, node: cst.Call) -> None:
        if _is_isinstance_timelimit(self.analysis, node):
            self.report(
                node,
                "GM606",
                "gym.make now returns TimeLimit(OrderEnforcing(PassiveEnvChecker(env))) and other wrappers may "
                "sit on top: test `env.spec.max_episode_steps` instead of the wrapper class",
            )

    # -- GM604 / GM605 / GM606: attribute access on envs ------------------------------------------

    def _attribute_access(self, original: cst.Attribute, updated: cst.Attribute) -> cst.BaseExpression:
        name = original.attr.value
        receiver = original.value
        if name == "env":
            self._check_env_chain(original)
            return updated
        if name in SAFE_ATTRIBUTES or (name.startswith("__") and name.endswith("__")):
            return updated
        if isinstance(receiver, cst.Name) and receiver.value in ("self", "cls"):
            return updated
        if self.analysis.kind_of(receiver) is not EnvKind.GYM_ENV:
            return updated
        origin = self._origin(receiver)
        if origin == RAW:
            return updated
        if name in self._outer_attributes(receiver):
            return updated  # the outermost wrapper has it: no forwarding involved
        code = "GM605" if name == "_max_episode_steps" else "GM604"
        if self._is_write(original):
            if origin is not None:
                self.report(
                    original,
                    code,
                    f"writing `{_dotted(original) or name}` sets it on the outermost wrapper only (it never forwarded): "
                    f"use `.unwrapped.{name} = ...` or `.set_wrapper_attr(\"{name}\", ...)` to change the env",
                    kind=FixKind.FLAG,
                )
            return updated
        text = _dotted(receiver) or "the env"
        if origin is None:
            self.report(
                original,
                code,
                f"could not tell whether `{text}` is wrapped: if it is, `.{name}` raises AttributeError on Gymnasium "
                f"1.x; use `.unwrapped.{name}` or `.get_wrapper_attr(\"{name}\")`",
                kind=FixKind.FLAG,
            )
            return updated
        if name == "_max_episode_steps":
            if origin == MADE:
                self.report(original, code, "`_max_episode_steps` is read from the spec: `.spec.max_episode_steps`")
                return cst.Attribute(
                    value=cst.Attribute(value=updated.value, attr=cst.Name("spec")), attr=cst.Name("max_episode_steps")
                )
            self.report(
                original,
                code,
                "`_max_episode_steps` is on the TimeLimit wrapper, not forwarded any more: read it with "
                "get_wrapper_attr (env.spec may be None for an env built without make)",
            )
            return _get_wrapper_attr(updated.value, name)
        if name in BASE_ENV_ATTRIBUTES and name not in self._local_wrapper_attributes():
            self.report(
                original,
                code,
                f"attribute forwarding is gone in Gymnasium 1.0: `{name}` belongs to the base env, read it through "
                "`.unwrapped`",
            )
            return cst.Attribute(value=cst.Attribute(value=updated.value, attr=cst.Name("unwrapped")), attr=updated.attr)
        self.report(
            original,
            code,
            f"attribute forwarding is gone in Gymnasium 1.0: `get_wrapper_attr(\"{name}\")` searches the wrappers "
            "and the base env as forwarding did",
        )
        return _get_wrapper_attr(updated.value, name)

    def _check_env_chain(self, original: cst.Attribute) -> None:
        parent = self.analysis.parent(original)
        if isinstance(parent, cst.Attribute) and parent.value is original and parent.attr.value == "env":
            return  # report the outermost ``.env`` of a chain once
        receiver = original.value
        depth = 1
        while isinstance(receiver, cst.Attribute) and receiver.attr.value == "env":
            receiver = receiver.value
            depth += 1
        if isinstance(receiver, cst.Name) and receiver.value == "self":
            return
        if self.analysis.kind_of(receiver) is not EnvKind.GYM_ENV:
            return
        origin = self._origin(receiver)
        if origin == MADE or (depth >= 2 and origin in (WRAPPED, INNER)):
            self.report(
                original,
                "GM606",
                "gym.make now returns TimeLimit(OrderEnforcing(PassiveEnvChecker(env))), so `.env` chains reach "
                "a different layer: use gym.make(id, max_episode_steps=-1) to drop the time limit, or `.unwrapped`",
            )

    def _is_write(self, node: cst.Attribute) -> bool:
        parent = self.analysis.parent(node)
        if isinstance(parent, cst.AssignTarget):
            return True
        if isinstance(parent, (cst.AugAssign, cst.AnnAssign)) and parent.target is node:
            return True
        if isinstance(parent, cst.Element):
            holder = self.analysis.parent(self.analysis.parent(parent) or parent)
            return isinstance(holder, cst.AssignTarget)
        return isinstance(parent, cst.Del)

    def _local_wrapper_attributes(self) -> set[str]:
        """Attributes and methods defined by wrapper classes of this module (they shadow the base env's)."""
        if not hasattr(self, "_local_attrs"):
            attrs: set[str] = set()
            module = self.analysis._module
            for statement in module.body:
                if isinstance(statement, cst.ClassDef) and self.analysis.is_gym_wrapper_class(statement):
                    collector = _DefinedAttributes()
                    statement.visit(collector)
                    attrs |= collector.names
            self._local_attrs = attrs
        return self._local_attrs

    # -- origins -------------------------------------------------------------------------------

    def _origin(self, expr: cst.BaseExpression, depth: int = 0) -> str | None:
        """MADE / WRAPPED / INNER / RAW, or None when it cannot be told."""
        if depth > 20:
            return None
        if isinstance(expr, cst.Call):
            return self._call_origin(expr, depth)
        if isinstance(expr, cst.Attribute):
            if expr.attr.value == "unwrapped":
                return RAW
            if isinstance(expr.value, cst.Name) and expr.value.value == "self":
                classdef = self.analysis.enclosing(expr, cst.ClassDef)
                if expr.attr.value == "env" and isinstance(classdef, cst.ClassDef) and self.analysis.is_gym_wrapper_class(classdef):
                    return INNER
                if isinstance(classdef, cst.ClassDef):
                    collector = _SelfStores(expr.attr.value)
                    classdef.visit(collector)
                    return _join([self._origin(v, depth + 1) for v in collector.values])
            return None
        if isinstance(expr, cst.Name):
            return self._name_origin(expr, depth)
        return None

    def _call_origin(self, call: cst.Call, depth: int) -> str | None:
        for q in self.analysis.qualified_names(call.func):
            rest = N.strip_gym_prefix(q)
            if rest is None:
                continue
            if rest in N.GYM_ENV_FACTORIES:
                return MADE
            if rest.startswith("wrappers.") and not rest.startswith("wrappers.vector."):
                inner = self._origin(call.args[0].value, depth + 1) if call.args else None
                return MADE if inner == MADE else WRAPPED
            if rest.startswith("envs."):
                return RAW
        local = self.analysis.local_class(call.func)
        if local is not None:
            if self.analysis.is_gym_wrapper_class(local):
                inner = self._origin(call.args[0].value, depth + 1) if call.args else None
                return MADE if inner == MADE else WRAPPED
            if self.analysis.class_kind(local) is EnvKind.GYM_ENV:
                return RAW
        local_function = self.analysis.local_function(call.func)
        if local_function is not None:
            collector = _ReturnValues()
            local_function.body.visit(collector)
            return _join([self._origin(v, depth + 1) for v in collector.values])
        return None

    def _name_origin(self, name: cst.Name, depth: int) -> str | None:
        try:
            scope = self.get_metadata(ScopeProvider, name)
        except KeyError:
            return None
        if scope is None:
            return None
        origins = []
        for assignment in scope[name.value]:
            if not isinstance(assignment, Assignment):
                return None
            node = assignment.node
            if isinstance(node, cst.Param):
                origins.append(self._param_origin(node))
                continue
            parent = self.analysis.parent(node)
            if isinstance(parent, cst.AssignTarget):
                assign = self.analysis.parent(parent)
                if isinstance(assign, cst.Assign):
                    if id(assign) in self._resolving:
                        continue  # ``env = Wrapper(env)``: the other bindings decide
                    self._resolving.add(id(assign))
                    try:
                        origins.append(self._origin(assign.value, depth + 1))
                    finally:
                        self._resolving.discard(id(assign))
                    continue
            if isinstance(parent, cst.AnnAssign) and parent.value is not None:
                origins.append(self._origin(parent.value, depth + 1))
                continue
            return None
        return _join(origins)

    def _param_origin(self, param: cst.Param) -> str | None:
        function = self.analysis.enclosing(param, cst.FunctionDef)
        classdef = self.analysis.enclosing(param, cst.ClassDef)
        if (
            isinstance(function, cst.FunctionDef)
            and function.name.value == "__init__"
            and param.name.value == "env"
            and isinstance(classdef, cst.ClassDef)
            and self.analysis.is_gym_wrapper_class(classdef)
        ):
            return INNER
        if not isinstance(function, cst.FunctionDef) or classdef is not None:
            return None
        # A module function: the env is whatever its callers in this module pass.
        params = list(function.params.posonly_params) + list(function.params.params)
        position = next((i for i, p in enumerate(params) if p is param), None)
        calls = self.analysis.call_sites(function, None)
        if not calls or id(param) in self._resolving:
            return None
        self._resolving.add(id(param))
        try:
            origins = []
            for call in calls:
                argument = call_argument(call, position, param.name.value)
                origins.append(self._origin(argument) if argument is not None else None)
        finally:
            self._resolving.discard(id(param))
        return _join(origins)

    def _outer_wrapper(self, expr: cst.BaseExpression) -> str | None:
        """The gymnasium wrapper class that is the outermost layer of ``expr`` where it is read.

        For a name, the binding is the nearest assignment above the read in the same scope
        (``env = RecordEpisodeStatistics(env)`` then ``env.return_queue``): straight-line
        script code, which is where such reads live.
        """
        value: cst.BaseExpression | None = expr
        if isinstance(expr, cst.Name):
            value = self._nearest_assignment(expr)
        if not isinstance(value, cst.Call):
            return None
        names = {_wrapper_rest(q) for q in self.analysis.qualified_names(value.func)} - {None}
        if len(names) == 1:
            return names.pop()  # type: ignore[return-value]
        local = self.analysis.local_class(value.func)
        if local is not None and self.analysis.is_gym_wrapper_class(local):
            return local.name.value
        return None

    def _outer_attributes(self, expr: cst.BaseExpression) -> set[str]:
        """Attributes the outermost wrapper of ``expr`` defines itself (gymnasium's or this module's)."""
        owner = self._outer_wrapper(expr)
        if owner is None:
            return set()
        if owner in OWN_ATTRIBUTES:
            return OWN_ATTRIBUTES[owner]
        local = self.analysis.local_class(cst.Name(owner))
        if local is None:
            return set()
        collector = _DefinedAttributes()
        local.visit(collector)
        return collector.names

    def _nearest_assignment(self, name: cst.Name) -> cst.BaseExpression | None:
        try:
            scope = self.get_metadata(ScopeProvider, name)
            read_line = self.get_metadata(PositionProvider, name).start.line
        except KeyError:
            return None
        best: tuple[int, cst.BaseExpression] | None = None
        for assignment in scope[name.value] if scope is not None else ():
            parent = self.analysis.parent(assignment.node) if isinstance(assignment, Assignment) else None
            assign = self.analysis.parent(parent) if isinstance(parent, cst.AssignTarget) else None
            if not isinstance(assign, cst.Assign):
                return None
            line = self.get_metadata(PositionProvider, assign).start.line
            if line < read_line and (best is None or line > best[0]):
                best = (line, assign.value)
        return best[1] if best is not None else None


_PIXELS_MESSAGE = (
    "PixelObservationWrapper is AddRenderObservation: the env must be made with render_mode=\"rgb_array\", "
    "`pixels_only`/`pixel_keys` are `render_only`/`render_key`, and a non-dict observation is stored under "
    "obs_key=\"state\""
)
_AUTORESET_MESSAGE = (
    "AutoResetWrapper is Autoreset: it now resets on the step after the episode ends (that step ignores the "
    "action and returns the reset observation with reward 0) and sets no final_observation/final_info"
)


def _with_commas(names: list[cst.ImportAlias], original: object) -> list[cst.ImportAlias]:
    """Separators for a rebuilt import list: ``, `` between names, the original's last comma kept."""
    originals = list(original) if isinstance(original, (list, tuple)) else []
    last = originals[-1].comma if originals else cst.MaybeSentinel.DEFAULT
    result = []
    for i, alias in enumerate(names):
        if i < len(names) - 1:
            keep = originals[i].comma if i < len(originals) - 1 and originals[i].comma is not cst.MaybeSentinel.DEFAULT else None
            result.append(alias.with_changes(comma=keep or cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))))
        else:
            result.append(alias.with_changes(comma=last))
    return result


def _fix_last_comma(args: list[cst.Arg], original: Sequence[cst.Arg]) -> list[cst.Arg]:
    if args and original and args[-1] is not original[-1]:
        args[-1] = args[-1].with_changes(comma=original[-1].comma)
    return args


def _root_name(node: cst.BaseExpression) -> str:
    while isinstance(node, cst.Attribute):
        node = node.value
    return node.value if isinstance(node, cst.Name) else "gymnasium"


def _get_wrapper_attr(receiver: cst.BaseExpression, name: str) -> cst.Call:
    return cst.Call(
        func=cst.Attribute(value=receiver, attr=cst.Name("get_wrapper_attr")),
        args=[cst.Arg(value=cst.SimpleString(f'"{name}"'))],
    )


def _keeps_shape(func: cst.BaseExpression) -> bool:
    """``lambda obs: obs / 255.0``-like functions: arithmetic with numbers keeps shape (not dtype, see ASSIST)."""
    if not isinstance(func, cst.Lambda) or len(func.params.params) != 1:
        return False
    param = func.params.params[0].name.value
    body = func.body

    def simple(node: cst.BaseExpression) -> bool:
        if isinstance(node, cst.Name):
            return node.value == param
        if isinstance(node, (cst.Integer, cst.Float)):
            return True
        if isinstance(node, cst.BinaryOperation) and isinstance(node.operator, (cst.Add, cst.Subtract, cst.Multiply)):
            return simple(node.left) and simple(node.right)
        if isinstance(node, cst.UnaryOperation) and isinstance(node.operator, cst.Minus):
            return simple(node.expression)
        return False

    return simple(body)


def _frameskip_is_one(make: cst.Call) -> bool:
    """Does this make() call build an env that does not skip frames (or can it not be told)?"""
    frameskip = keyword_argument(make, "frameskip")
    if frameskip is not None:
        return isinstance(frameskip.value, cst.Integer) and frameskip.value.value == "1"
    positional = _positional(make)
    env_id = string_value(positional[0].value) if positional else None
    if env_id is None:
        return True  # cannot tell: stay quiet rather than guess
    # ``ALE/X-v5`` skips 4 frames, ``X-v4`` 2-4, ``XDeterministic-v4`` 4; only NoFrameskip ids do not.
    return "NoFrameskip" in env_id


def _is_isinstance_timelimit(analysis: ReceiverAnalysis, call: cst.Call) -> bool:
    if not (isinstance(call.func, cst.Name) and call.func.value == "isinstance" and len(call.args) == 2):
        return False
    classes = call.args[1].value
    candidates = [e.value for e in classes.elements] if isinstance(classes, cst.Tuple) else [classes]
    return any(
        _wrapper_rest(q) == "TimeLimit" for candidate in candidates for q in analysis.qualified_names(candidate)
    )


def _join(origins: list[str | None]) -> str | None:
    found = set(origins)
    if not found or None in found:
        return None
    if len(found) == 1:
        return found.pop()
    if RAW in found:
        return None
    return WRAPPED if WRAPPED in found or INNER in found else MADE


class _DefinedAttributes(cst.CSTVisitor):
    def __init__(self) -> None:
        self.names: set[str] = set()

    def visit_FunctionDef(self, node: cst.FunctionDef) -> None:
        self.names.add(node.name.value)

    def visit_AssignTarget(self, node: cst.AssignTarget) -> None:
        target = node.target
        if isinstance(target, cst.Attribute) and isinstance(target.value, cst.Name) and target.value.value == "self":
            self.names.add(target.attr.value)


class _SelfStores(cst.CSTVisitor):
    def __init__(self, name: str) -> None:
        self.name = name
        self.values: list[cst.BaseExpression] = []

    def visit_Assign(self, node: cst.Assign) -> None:
        for target in node.targets:
            t = target.target
            if isinstance(t, cst.Attribute) and isinstance(t.value, cst.Name) and t.value.value == "self" and t.attr.value == self.name:
                self.values.append(node.value)


class _ReturnValues(cst.CSTVisitor):
    def __init__(self) -> None:
        self.values: list[cst.BaseExpression] = []

    def visit_FunctionDef(self, node: cst.FunctionDef) -> bool:
        return False

    def visit_Return(self, node: cst.Return) -> None:
        if node.value is not None:
            self.values.append(node.value)


