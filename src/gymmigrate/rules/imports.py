"""Imports: ``gym`` becomes ``gymnasium`` (GM101-GM105, GM108).

* GM101 ``import gym`` -> ``import gymnasium as gym``; a name the user chose stays.
* GM102 ``from gym import X`` -> ``from gymnasium import X``.
* GM103 dotted submodule paths (``gym.spaces``, ``gym.utils.seeding``...) -> ``gymnasium...``.
* GM104 wrapper modules that Gymnasium 1.0 folded away (``gym.wrappers.time_limit``)
  -> the package root ``gymnasium.wrappers``.
* GM105 removed modules and symbols (GoalEnv, classic_control.rendering, DiscreteEnv,
  robotics, VideoRecorder, EnvCompatibility...) are reported and left as they are.
* GM108 gym-or-gymnasium ``try/except ImportError`` fallbacks, ``sys.modules`` hacks
  and ``gym.__version__`` checks are reported, not rewritten: after the migration one
  branch is dead and a person should delete it.

Source: Gymnasium migration guide, "Package Import"; gymnasium 1.0 release notes.
"""

from __future__ import annotations

import libcst as cst
from libcst.helpers import get_full_name_for_node

from gymmigrate.analysis.syntax import dotted_node
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileProfile, Rule, RulePass

RULES = (
    Rule("GM101", "import gym", FixKind.AUTO, "`import gym` becomes `import gymnasium as gym`."),
    Rule("GM102", "from gym import X", FixKind.AUTO, "`from gym import X` becomes `from gymnasium import X`."),
    Rule("GM103", "gym submodule paths", FixKind.AUTO, "`gym.spaces`, `gym.utils...` paths move under `gymnasium`."),
    Rule(
        "GM104",
        "moved wrapper modules",
        FixKind.AUTO,
        "`gym.wrappers.<module>` imports come from the package root `gymnasium.wrappers`.",
    ),
    Rule("GM105", "removed modules and symbols", FixKind.FLAG, "Imports of things Gymnasium removed are reported."),
    Rule(
        "GM108",
        "version sniffing and import fallbacks",
        FixKind.FLAG,
        "gym-or-gymnasium fallbacks, `sys.modules` hacks and `gym.__version__` checks are reported.",
    ),
)

# Wrapper modules of gym (and gymnasium <= 0.29) whose classes now live at the root of
# gymnasium.wrappers (the submodule names are not a stable API any more).
LEGACY_WRAPPER_MODULES = frozenset(
    {
        "time_limit",
        "order_enforcing",
        "env_checker",
        "record_episode_statistics",
        "autoreset",
        "clip_action",
        "rescale_action",
        "filter_observation",
        "flatten_observation",
        "gray_scale_observation",
        "resize_observation",
        "transform_observation",
        "pixel_observation",
        "frame_stack",
        "time_aware_observation",
        "normalize",
        "transform_reward",
        "record_video",
        "human_rendering",
        "render_collection",
        "atari_preprocessing",
    }
)
# Names imported from a legacy wrapper module that do not live in gymnasium.wrappers.
MOVED_NAMES = {("record_video", "capped_cubic_video_schedule"): "gymnasium.utils.save_video"}

# Module paths (under gym) that are gone, with what to use instead.
REMOVED_MODULES = {
    "envs.classic_control.rendering": "render with pygame or matplotlib; the rendering module is gone",
    "envs.toy_text.discrete": "subclass gymnasium.Env with Discrete spaces; DiscreteEnv is gone",
    "envs.robotics": "use gymnasium_robotics and gymnasium.register_envs(gymnasium_robotics)",
    "wrappers.monitor": "use RecordVideo and RecordEpisodeStatistics",
    "wrappers.monitoring": "use gymnasium.wrappers.RecordVideo or gymnasium.utils.save_video",
    "wrappers.monitoring.video_recorder": "use gymnasium.wrappers.RecordVideo or gymnasium.utils.save_video",
    "wrappers.compatibility": "use Shimmy's GymV21Environment-v0 / GymV26Environment-v0",
    "wrappers.step_api_compatibility": "use gymnasium.utils.step_api_compatibility",
}
# (module under gym, name) pairs that are gone.
REMOVED_NAMES = {
    ("", "GoalEnv"): "use gymnasium_robotics.core.GoalEnv or a gymnasium.Env with compute_reward",
    ("core", "GoalEnv"): "use gymnasium_robotics.core.GoalEnv or a gymnasium.Env with compute_reward",
    ("envs.classic_control", "rendering"): "render with pygame or matplotlib; the rendering module is gone",
    ("envs.toy_text", "discrete"): "subclass gymnasium.Env with Discrete spaces; DiscreteEnv is gone",
    ("envs", "robotics"): "use gymnasium_robotics and gymnasium.register_envs(gymnasium_robotics)",
    ("envs.registration", "load"): "use gymnasium.envs.registration.load_env_creator",
    ("envs.registration", "load_env_plugins"): "plugins are gone: import the env package instead",
    ("envs.registration", "EnvRegistry"): "gymnasium.registry is a plain dict of EnvSpec",
    ("envs.registration", "EnvSpecTree"): "gymnasium.registry is a plain dict of EnvSpec",
    ("wrappers", "EnvCompatibility"): "use Shimmy's GymV21Environment-v0 / GymV26Environment-v0",
    ("wrappers", "StepAPICompatibility"): "use gymnasium.utils.step_api_compatibility",
    ("wrappers", "LazyFrames"): "frame stacks are plain numpy arrays now",
    ("wrappers.monitoring", "video_recorder"): "use gymnasium.wrappers.RecordVideo",
}
LEGACY_PACKAGES = ("gym", "gymnasium")


def _dotted(node: cst.BaseExpression) -> str:
    return get_full_name_for_node(node) or ""




def _under_gym(module: str) -> str | None:
    """``gym.spaces.box`` -> ``spaces.box``; ``gym`` -> ``""``; None for other modules."""
    if module == "gym":
        return ""
    if module.startswith("gym."):
        return module[4:]
    return None


def _removed_module(rest: str) -> str | None:
    for removed, hint in REMOVED_MODULES.items():
        if rest == removed or rest.startswith(removed + "."):
            return hint
    return None


class ImportsPass(RulePass):
    RULES = RULES
    ORDER = 10

    def __init__(self, context) -> None:  # type: ignore[no-untyped-def]
        super().__init__(context)
        self._fallback_depth = 0
        self._guarded_depth = 0
        self._plain_gym_import = False

    @classmethod
    def applies_to(cls, source: str, profile: FileProfile) -> bool:
        return "gym" in source

    def visit_Module(self, node: cst.Module) -> None:
        # Does a plain ``import gym`` bind the name ``gym`` (so ``import gym.x`` needs no alias)?
        finder = _PlainGymImportFinder()
        node.visit(finder)
        self._plain_gym_import = finder.found

    # -- GM108: fallbacks ----------------------------------------------------------

    def visit_Try(self, node: cst.Try) -> None:
        guard = self._import_guard(node)
        if guard == "fallback":
            self._fallback_depth += 1
            self.report(
                node,
                "GM108",
                "gym-or-gymnasium import fallback: keep the gymnasium branch and delete the legacy one",
            )
        elif guard == "detector":
            self._fallback_depth += 1
            self.report(
                node,
                "GM108",
                "this try/except ImportError detects whether legacy gym is installed (the file already uses "
                "gymnasium): left as it is; delete it if legacy gym support is no longer wanted",
            )
        elif guard == "guarded":
            self._guarded_depth += 1

    def leave_Try(self, original_node: cst.Try, updated_node: cst.Try) -> cst.Try:
        guard = self._import_guard(original_node)
        if guard in ("fallback", "detector"):
            self._fallback_depth -= 1
        elif guard == "guarded":
            self._guarded_depth -= 1
        return updated_node

    def _import_guard(self, node: cst.Try) -> str | None:
        """How a try statement that imports gym treats a missing package.

        fallback: it tries gym and gymnasium (one branch is dead after the migration);
        detector: an ImportError guard around gym in a file that already uses gymnasium
        (it asks whether *legacy* gym is installed: rewriting it would change the answer);
        guarded: an ImportError guard around gym alone (rewritten, but listed for review).
        """
        collector = _ImportedPackages()
        node.visit(collector)
        if "gym" not in collector.packages:
            return None
        if "gymnasium" in collector.packages:
            return "fallback"
        if not any(_catches_import_error(handler) for handler in node.handlers):
            return None
        return "detector" if self.context.profile.imports_gymnasium else "guarded"

    def visit_Assign(self, node: cst.Assign) -> None:
        for target in node.targets:
            subscript = target.target
            if isinstance(subscript, cst.Subscript) and _dotted(subscript.value) == "sys.modules":
                for element in subscript.slice:
                    index = element.slice
                    if isinstance(index, cst.Index) and isinstance(index.value, cst.SimpleString):
                        if index.value.evaluated_value in ("gym", "gymnasium") or str(
                            index.value.evaluated_value
                        ).startswith("gym."):
                            self.report(node, "GM108", "sys.modules hack aliasing gym: remove it once the code uses gymnasium")

    def visit_Attribute(self, node: cst.Attribute) -> None:
        if node.attr.value == "__version__" and isinstance(node.value, cst.Name) and node.value.value in self._gym_names:
            self.report(node, "GM108", "gym version check: after the migration one branch is dead; delete the legacy one")

    @property
    def _gym_names(self) -> set[str]:
        return self.context.notes.setdefault("gym_import_names", set())  # type: ignore[return-value]

    # -- GM101 / GM103: import gym[.x] [as y] -------------------------------------------

    def leave_Import(self, original_node: cst.Import, updated_node: cst.Import) -> cst.Import:
        if self._fallback_depth:
            for alias in updated_node.names:
                if _dotted(alias.name).split(".")[0] in LEGACY_PACKAGES:
                    self._gym_names.add(_dotted(alias.asname.name) if alias.asname else _dotted(alias.name).split(".")[0])
            return updated_node
        names = []
        changed = False
        for alias in updated_node.names:
            module = _dotted(alias.name)
            rest = _under_gym(module)
            if rest is None:
                names.append(alias)
                continue
            bound = alias.asname.name.value if alias.asname else module.split(".")[0]  # type: ignore[union-attr]
            self._gym_names.add(bound)
            hint = _removed_module(rest)
            if hint:
                self.report(original_node, "GM105", f"`{module}` was removed: {hint}")
                names.append(alias)
                continue
            changed = True
            if rest == "":
                asname = alias.asname or cst.AsName(name=cst.Name("gym"))
                names.append(alias.with_changes(name=cst.Name("gymnasium"), asname=asname))
                if self._guarded_depth:
                    self.report(
                        original_node,
                        "GM101",
                        "import gym -> import gymnasium as gym inside a try/except ImportError: the guard now "
                        "asks whether gymnasium is installed",
                        FixKind.ASSIST,
                    )
                else:
                    self.report(original_node, "GM101", "import gym -> import gymnasium as gym")
                continue
            new_module = "gymnasium." + _legacy_wrapper_path(rest)
            names.append(alias.with_changes(name=dotted_node(new_module)))
            self.report(original_node, "GM103", f"{module} -> {new_module}")
            if alias.asname is None and not self._plain_gym_import:
                # ``import gym.spaces`` bound ``gym``; keep that name working.
                names.append(
                    cst.ImportAlias(name=cst.Name("gymnasium"), asname=cst.AsName(name=cst.Name("gym")))
                )
                self._plain_gym_import = True
        if not changed:
            return updated_node
        if len(names) == len(updated_node.names):
            # Keep the user's own separators.
            names = [new.with_changes(comma=old.comma) for new, old in zip(names, updated_node.names)]
        else:
            last_comma = updated_node.names[-1].comma
            names = [n.with_changes(comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))) for n in names[:-1]] + [
                names[-1].with_changes(comma=last_comma)
            ]
        return updated_node.with_changes(names=names)

    # -- GM102 / GM103 / GM104: from gym[.x] import y ----------------------------------

    def leave_ImportFrom(self, original_node: cst.ImportFrom, updated_node: cst.ImportFrom) -> cst.ImportFrom:
        if self._fallback_depth or updated_node.relative or updated_node.module is None:
            return updated_node
        module = _dotted(updated_node.module)
        rest = _under_gym(module)
        legacy_gymnasium_wrappers = module.startswith("gymnasium.wrappers.") and module[19:] in LEGACY_WRAPPER_MODULES
        if rest is None and not legacy_gymnasium_wrappers:
            return updated_node
        if rest is None:
            rest = module[len("gymnasium.") :]
        hint = _removed_module(rest)
        if hint is None and not isinstance(updated_node.names, cst.ImportStar):
            for alias in updated_node.names:
                hint = REMOVED_NAMES.get((rest, _dotted(alias.name)))
                if hint:
                    hint = f"`{_dotted(alias.name)}` was removed: {hint}"
                    break
        elif hint is not None:
            hint = f"`{module}` was removed: {hint}"
        if hint:
            self.report(original_node, "GM105", hint)
            return updated_node
        new_rest = _legacy_wrapper_path(rest)
        if not isinstance(updated_node.names, cst.ImportStar) and new_rest != rest:
            moved = [MOVED_NAMES.get((rest.split(".")[-1], _dotted(a.name))) for a in updated_node.names]
            if any(moved) and len(set(moved)) == 1:
                new_rest = moved[0][len("gymnasium.") :]  # type: ignore[index]
        new_module = "gymnasium" + ("." + new_rest if new_rest else "")
        if new_module == module:
            return updated_node
        code = "GM102" if rest == "" else "GM104" if new_rest != rest else "GM103"
        self.report(original_node, code, f"from {module} import ... -> from {new_module} import ...")
        return updated_node.with_changes(module=dotted_node(new_module))


def _legacy_wrapper_path(rest: str) -> str:
    """``wrappers.time_limit`` -> ``wrappers``; ``wrappers.vector_list_info`` -> ``wrappers.vector``."""
    parts = rest.split(".")
    if len(parts) >= 2 and parts[0] == "wrappers":
        if parts[1] in LEGACY_WRAPPER_MODULES:
            return "wrappers"
        if parts[1] == "vector_list_info":
            return "wrappers.vector"
    return rest


def _catches_import_error(handler: cst.ExceptHandler) -> bool:
    if handler.type is None:
        return True  # a bare except catches it too
    caught = handler.type.elements if isinstance(handler.type, cst.Tuple) else [handler.type]
    names = {_dotted(item.value if isinstance(item, cst.Element) else item) for item in caught}
    return bool(names & {"ImportError", "ModuleNotFoundError", "Exception", "BaseException"})


class _ImportedPackages(cst.CSTVisitor):
    def __init__(self) -> None:
        self.packages: set[str] = set()

    def visit_Import(self, node: cst.Import) -> None:
        for alias in node.names:
            self.packages.add(_dotted(alias.name).split(".")[0])

    def visit_ImportFrom(self, node: cst.ImportFrom) -> None:
        if node.module is not None and not node.relative:
            self.packages.add(_dotted(node.module).split(".")[0])


class _PlainGymImportFinder(cst.CSTVisitor):
    def __init__(self) -> None:
        self.found = False

    def visit_Import(self, node: cst.Import) -> None:
        for alias in node.names:
            bound = _dotted(alias.asname.name) if alias.asname else _dotted(alias.name)
            if bound == "gym" and _dotted(alias.name) in LEGACY_PACKAGES:
                self.found = True
