"""Renamed, changed and removed wrappers (GM608-GM615).

Gymnasium 1.0 reworked ``gymnasium.wrappers`` (1.0 release notes; ``wrappers/__init__.py``
``_renamed_wrapper``):

* GM608 (AUTO; ASSIST for PixelObservationWrapper) renamed wrappers, in imports, attribute
  paths and every use of an imported name; FrameStack's ``num_stack``/``lz4_compress`` too.
* GM609 (AUTO; FLAG where a person must choose) changed signatures of kept wrappers
  (``arguments.py``), and subclasses of TimeLimit (``time_limit_subclasses.py``).
* GM610 (FLAG) removed wrappers: EnvCompatibility, StepAPICompatibility, LazyFrames, VideoRecorder.
* GM611 (ASSIST) ``Monitor`` -> ``RecordVideo(RecordEpisodeStatistics(env), ...)`` (``monitor.py``);
  other code built on gym's Monitor is reported (``monitor_consumers.py``).
* GM612 (ASSIST) ``AutoResetWrapper`` -> ``Autoreset``, which now resets on the *next* step
  and no longer fills ``info["final_observation"]`` (reads of it are reported).
* GM613 (ASSIST) single-env wrappers around a Gym vector env -> ``gymnasium.wrappers.vector.X``
  (1.x ``Wrapper.__init__`` raises for a ``VectorEnv``).
* GM614 (AUTO) ``gymnasium.experimental.wrappers.XxxV0`` (0.28-0.29) -> ``gymnasium.wrappers.Xxx``.
* GM615 (FLAG) ``AtariPreprocessing`` on a base env that already skips frames (it raises).

In the pipeline right after the make() keywords (GM305 owns ``new_step_api=`` on wrappers) and
before the rendering rules, which read the RecordVideo that replaces Monitor. Decided on
the original source: an import from ``gym.wrappers`` keeps its module here (the imports
rules move it to ``gymnasium`` in the same run) unless those rules leave it alone
(``legacy_imports.py``), in which case its wrappers are left alone too.

This module is the family: it finds the uses of wrapper names and paths and the calls
that construct wrappers, and decides GM610, GM612 and GM613 itself; what the import
statements become is ``wrapper_imports.py``.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Callable

from gymmigrate.edits.lazy import cst
from gymmigrate.edits.syntax import dotted_node
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import dotted_name, string_value
from gymmigrate.findings import FixKind, removed_helper_question
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.imports.table import removed_module_hint, removed_name_hint
from gymmigrate.rules.repeats import Repeats
from gymmigrate.rules.wrapper_usage.arguments import HANDLERS, positional
from gymmigrate.rules.wrapper_usage.legacy_imports import LegacyImports
from gymmigrate.rules.wrapper_usage.monitor import plan_monitor
from gymmigrate.rules.wrapper_usage.monitor_consumers import (
    MONITOR_NAME,
    report_monitor_consumers,
    report_unsure_monitor,
)
from gymmigrate.rules.wrapper_usage.stacks import WrapperStacks
from gymmigrate.rules.wrapper_usage.tables import (
    EXPERIMENTAL_SPECIAL,
    FINAL_INFO_KEYS,
    REMOVED,
    RENAMED,
    SINGLE_ENV_WRAPPERS,
    VECTOR_WRAPPERS,
    experimental_name,
    rename_code,
    wrapper_rest,
)
from gymmigrate.rules.wrapper_usage.time_limit_subclasses import (
    time_limit_subclass_call,
)
from gymmigrate.rules.wrapper_usage.wrapper_imports import WrapperImports

RULES = (
    Rule("GM608", "renamed wrappers", FixKind.AUTO, "`FrameStack` -> `FrameStackObservation` and the other 1.0 renames."),
    Rule("GM609", "wrapper signature changes", FixKind.AUTO, "Arguments of TransformObservation, ResizeObservation... follow 1.x."),
    Rule("GM610", "removed wrappers", FixKind.FLAG, "EnvCompatibility, StepAPICompatibility, LazyFrames and VideoRecorder are reported."),
    Rule("GM611", "Monitor", FixKind.ASSIST, "`Monitor(env, dir)` -> `RecordVideo(RecordEpisodeStatistics(env), video_folder=dir)`."),
    Rule("GM612", "Autoreset semantics", FixKind.ASSIST, "`AutoResetWrapper` -> `Autoreset` (resets on the next step); `final_observation` reads are reported."),
    Rule("GM613", "single-env wrappers on vector envs", FixKind.ASSIST, "Wrappers around a Gym vector env come from `gymnasium.wrappers.vector`."),
    Rule("GM614", "gymnasium.experimental wrappers", FixKind.AUTO, "`gymnasium.experimental.wrappers.XxxV0` -> `gymnasium.wrappers.Xxx`."),
    Rule("GM615", "AtariPreprocessing frameskip", FixKind.FLAG, "`AtariPreprocessing` on a base env that skips frames is reported."),
)

# The single-env Autoreset wrapper in code (not ``AutoresetMode``, not comments).
_AUTORESET_USE = re.compile(r"^[^#\n]*\b(?:AutoResetWrapper|Autoreset)\b", re.M)
_PIXELS_MESSAGE = (
    "PixelObservationWrapper is AddRenderObservation: the env must be made with render_mode=\"rgb_array\", "
    "`pixels_only`/`pixel_keys` are `render_only`/`render_key`, and a non-dict observation is stored under "
    "obs_key=\"state\""
)
_AUTORESET_MESSAGE = (
    "AutoResetWrapper is Autoreset: it now resets on the step after the episode ends (that step ignores the "
    "action and returns the reset observation with reward 0) and sets no final_observation/final_info"
)
_REMOVED_SUFFIXES = tuple(REMOVED)



# The imports family's GM105 questions, one per move (``Repeats("GM105")`` there): a removed
# wrapper used from a removed module asks the question of that module's import.
_REMOVED_MODULE_QUESTIONS = Repeats("GM105")

class WrapperRenames(RuleFamily):
    RULES = RULES

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        # Every wrapper these rules know is reached through a ``wrappers`` module path; a
        # wrapper stack searched for gym's Monitor by name (GM611) need not name it.
        return "gym" in facts.text and ("wrappers" in facts.text or f'"{MONITOR_NAME}"' in facts.text or f"'{MONITOR_NAME}'" in facts.text)

    def decide(self) -> None:
        self._legacy = LegacyImports(self.facts, self.context.profile)
        self._imports = WrapperImports(self, self._legacy)
        self._removed_repeats = Repeats("GM610")  # GM610: one review item per removed wrapper and file
        self._monitor_calls: set[int] = set()  # ids of the Monitor calls rewritten
        self._names_used: set[str] = set()  # bare names the rewritten Monitor calls use
        self._unused_after: list[ast.Name] = []  # funcs replaced by a vector wrapper path
        self.stacks = WrapperStacks(self.facts, self.receivers)
        self._uses_autoreset = _AUTORESET_USE.search(self.facts.text) is not None
        nodes = list(self.facts.parents)
        for node in nodes:
            if isinstance(node, ast.ImportFrom):
                self._imports.decide(node)
        for node in nodes:
            if isinstance(node, ast.Name):
                if isinstance(node.ctx, ast.Load):
                    self._check_removed(node)
                    self._rename_name(node)
            elif isinstance(node, ast.Attribute):
                self._check_removed(node)
                self._rename_attribute(node)
            elif isinstance(node, ast.Call):
                self._call(node)
            elif isinstance(node, ast.Subscript):
                self._check_final_info_subscript(node)
        self._imports.finish(self._names_used, self._unused_after)
        report_monitor_consumers(
            self, self._imports.monitor_aliases, self._monitor_calls, self._legacy, self.context.profile.imports_sb3
        )

    # -- names and attribute paths: GM608, GM610, GM612, GM614 ----------------------------------

    def _rename_name(self, node: ast.Name) -> None:
        new = self._imports.renamed_locals.get(node.id)
        if new is None:
            return
        if not any(wrapper_rest(q) == node.id or q.endswith("VectorListInfo") for q in self.facts.qualified_names(node)):
            return
        if not self._is_call_func(node):
            self._report_reference(node, node.id, new)
        self.plan.replace(node, lambda n: n.with_changes(value=new))

    def _report_reference(self, node: ast.AST, old: str, new: str) -> None:
        if old.endswith(("V0", "V1")) or old in EXPERIMENTAL_SPECIAL:
            self.report(node, "GM614", f"`{old}` is `{new}` in Gymnasium 1.x")
            return
        code, kind = rename_code(old)
        message = f"`{old}` was renamed `{new}` in Gymnasium 1.0"
        if code == "GM612":
            message = _AUTORESET_MESSAGE
        elif old == "PixelObservationWrapper":
            message = _PIXELS_MESSAGE
        self.report(node, code, message, kind=kind)

    def _rename_attribute(self, node: ast.Attribute) -> None:
        for q in self.facts.qualified_names(node):
            rest = N.strip_gym_prefix(q)
            if rest is None:
                continue
            name = rest.rsplit(".", 1)[-1]
            if rest.startswith("wrappers.") and not rest.startswith("wrappers.vector.") and name in RENAMED:
                if not self._is_call_func(node):
                    self._report_reference(node, name, RENAMED[name])
                new = RENAMED[name]
                self.plan.replace(node, lambda n, new=new: n.with_changes(attr=cst.Name(new)))
                return
            if rest in ("wrappers.VectorListInfo", "wrappers.vector_list_info.VectorListInfo"):
                self.report(node, "GM608", "`VectorListInfo` is now `gymnasium.wrappers.vector.DictInfoToList`")
                self.plan.replace(node, _dotted_build(f"{_root_name(node)}.wrappers.vector.DictInfoToList"))
                return
            experimental = experimental_name(name) if rest.startswith("experimental.wrappers.") else None
            if experimental:
                if ".experimental.wrappers." not in (dotted_name(node) or ""):
                    self.report(
                        node,
                        "GM614",
                        f"`{name}` is `gymnasium.wrappers.{experimental}` in Gymnasium 1.x: import it from there",
                        kind=FixKind.FLAG,
                    )
                    return
                if not self._is_call_func(node):
                    self.report(node, "GM614", f"`{name}` is `gymnasium.wrappers.{experimental}` in Gymnasium 1.x")
                vector = ".vector" if rest.startswith("experimental.wrappers.vector.") else ""
                self.plan.replace(node, _dotted_build(f"{_root_name(node)}.wrappers{vector}.{experimental}"))
                return

    def _check_removed(self, node: ast.Name | ast.Attribute) -> None:
        """GM610: each use (not the import, which the imports rules report) of a removed wrapper."""
        spelled = node.id if isinstance(node, ast.Name) else node.attr
        if not spelled.endswith(_REMOVED_SUFFIXES):
            return  # cheap: resolving every ``env`` read is linear in its bindings
        for q in self.facts.qualified_names(node):
            rest = N.strip_gym_prefix(q)
            if rest is None or not rest.startswith("wrappers."):
                continue
            name = rest.rsplit(".", 1)[-1]
            if name in REMOVED and (dotted_name(node) or "").endswith(name):
                question = self._removed_repeats.question(name)
                module = rest.rsplit(".", 1)[0]
                hint = removed_module_hint(module, unknown=False)
                if hint is not None:
                    # from a module Gymnasium removed: its import (or the chain naming it) is
                    # GM105's item, which asks what replaces it; the uses ask the same
                    question = _REMOVED_MODULE_QUESTIONS.question(hint.split(": ", 1)[0])
                elif removed_name_hint(module, name) is not None:
                    # a name its module no longer has: its import asks what replaces it (GM105)
                    question = removed_helper_question(module, name)
                self.report(node, "GM610", f"`{name}` was removed in Gymnasium 1.0: {REMOVED[name]}", question=question)
                return

    def _is_call_func(self, node: ast.AST) -> bool:
        parent = self.facts.parent(node)
        return isinstance(parent, ast.Call) and parent.func is node

    # -- calls: GM609, GM611, GM613, GM615 ------------------------------------------------------

    def _call(self, call: ast.Call) -> None:
        wrapper = self._called_wrapper(call)
        if wrapper is not None and isinstance(call.func, ast.Name) and self._imports.guarded_monitors.intersection(self.facts.bindings_of(call.func)):
            return  # under Gymnasium the name is the ImportError fallback's: reported at the import
        if wrapper is None:
            time_limit_subclass_call(self, call)
            self._check_final_info_get(call)
            return
        old, new = wrapper
        if old in self._imports.monitor_locals or old == "Monitor":
            rewrite = plan_monitor(self, call)
            if rewrite is not None:
                self._names_used.update(rewrite.uses)
                self._monitor_calls.add(id(call.func))
            return
        if new in REMOVED:
            return
        if old != new:
            self._report_reference(call, old, new)
        builds: list[Callable[[cst.Call], cst.Call]] = []
        vector = self._vector(call, new)
        if vector is not None:
            builds.append(vector)
        handler = HANDLERS.get(new)
        if handler is not None:
            build = handler(self, call)
            if build is not None:
                builds.append(build)
        for build in builds:
            self.plan.replace(call, build)

    def _called_wrapper(self, call: ast.Call) -> tuple[str, str] | None:
        """(legacy name, 1.x name) of the gym/gymnasium wrapper class this call constructs."""
        func = call.func
        if isinstance(func, ast.Name) and func.id in self._imports.monitor_locals:
            # By the binding that reaches the call, not by its spelling: a later import of
            # the project's own ``Monitor`` replaces gym's.
            reaching = self.facts.reaching_bindings(func)
            dropped = {alias for alias, _ in self._imports.monitor_aliases}
            if dropped.issuperset(reaching):
                return func.id, "Monitor"
            if dropped.intersection(reaching):
                report_unsure_monitor(self, call, [b for b in reaching if b not in dropped])
                self._monitor_calls.add(id(call.func))  # asked here: not asked again as an uncovered read
                return None
        qualified = self.facts.qualified_names(func)
        if not qualified:
            return None
        legacy = self._legacy.binds_legacy(func)
        for q in sorted(qualified):
            if q.startswith("gym.") and legacy:
                continue  # imported by a legacy import the imports rules leave alone: not migrated yet
            name = wrapper_rest(q)
            if name is None:
                if q in ("gym.wrappers.monitor.Monitor", "gymnasium.wrappers.monitor.Monitor"):
                    return "Monitor", "Monitor"
                continue
            rest = N.strip_gym_prefix(q) or ""
            if rest.startswith("experimental."):
                return name, experimental_name(name) or name
            return name, RENAMED.get(name, name)
        return None

    def _vector(self, call: ast.Call, new: str) -> Callable[[cst.Call], cst.Call] | None:
        if new not in SINGLE_ENV_WRAPPERS:
            return None
        args = positional(call)
        if not args or self.stacks.vector_kind(args[0]) is not EnvKind.GYM_VEC:
            return None
        if new not in VECTOR_WRAPPERS:
            self.report(
                call,
                "GM613",
                f"{new} wraps one env and has no vector version: apply it to each env, e.g. "
                f"gym.make_vec(..., wrappers=[...])",
                kind=FixKind.FLAG,
            )
            return None
        self.report(
            call,
            "GM613",
            f"a vector env needs gymnasium.wrappers.vector.{new} (the single-env wrapper raises on a VectorEnv); "
            "its info layout is per-env arrays",
        )
        func = call.func
        if isinstance(func, ast.Attribute) and (dotted_name(func.value) or "").endswith("wrappers"):

            def under_wrappers(node: cst.Call) -> cst.Call:
                owner = node.func.value  # type: ignore[attr-defined]
                return node.with_changes(
                    func=cst.Attribute(value=cst.Attribute(value=owner, attr=cst.Name("vector")), attr=cst.Name(new))
                )

            return under_wrappers
        root = self._gymnasium_alias() or self.plan.ensure_import("gymnasium")
        if isinstance(func, ast.Name):
            self._unused_after.append(func)  # the single-env import may now be unused
        path = f"{root}.wrappers.vector.{new}"
        return lambda node: node.with_changes(func=dotted_node(path))

    def _gymnasium_alias(self) -> str | None:
        """The module-level name ``gymnasium`` will be bound to once the imports rules ran."""
        for statement in self.facts.tree.body:
            if isinstance(statement, ast.Import):
                for alias in statement.names:
                    if alias.name == "gymnasium" or (alias.name == "gym" and not self._legacy.stays_legacy(statement)):
                        return alias.asname or ("gym" if alias.name == "gym" else "gymnasium")
        return None

    # -- GM612: final_observation reads ---------------------------------------------------------

    def _check_final_info_subscript(self, node: ast.Subscript) -> None:
        if not self._uses_autoreset:
            return
        key = string_value(node.slice)
        if key in FINAL_INFO_KEYS:
            self._report_final_info(node, key)

    def _check_final_info_get(self, call: ast.Call) -> None:
        if not self._uses_autoreset:
            return
        func = call.func
        if isinstance(func, ast.Attribute) and func.attr == "get" and call.args:
            key = string_value(call.args[0])
            if key in FINAL_INFO_KEYS:
                self._report_final_info(call, key)

    def _report_final_info(self, node: ast.AST, key: str) -> None:
        self.report(
            node,
            "GM612",
            f"Autoreset no longer fills info[\"{key}\"]: the step after an episode ends returns the reset "
            "observation (reward 0, action ignored); keep the last observation of the episode yourself",
            kind=FixKind.FLAG,
        )


def _root_name(node: ast.AST) -> str:
    while isinstance(node, ast.Attribute):
        node = node.value
    return node.id if isinstance(node, ast.Name) else "gymnasium"


def _dotted_build(text: str):
    def build(node: cst.BaseExpression) -> cst.BaseExpression:
        return dotted_node(text).with_changes(lpar=node.lpar, rpar=node.rpar)

    return build
