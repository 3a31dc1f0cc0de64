"""Renamed, changed and removed wrappers (GM608-GM615).

Gymnasium 1.0 reworked ``gymnasium.wrappers`` (1.0 release notes; ``wrappers/__init__.py``
``_renamed_wrapper``):

* GM608 (AUTO; ASSIST for PixelObservationWrapper) renamed wrappers, in imports, attribute
  paths and every use of an imported name; FrameStack's ``num_stack``/``lz4_compress`` too.
* GM609 (AUTO; FLAG where a person must choose) changed signatures of kept wrappers
  (``arguments.py``).
* GM610 (FLAG) removed wrappers: EnvCompatibility, StepAPICompatibility, LazyFrames, VideoRecorder.
* GM611 (ASSIST) ``Monitor`` -> ``RecordVideo(RecordEpisodeStatistics(env), ...)`` (``monitor.py``).
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
"""

from __future__ import annotations

import ast
import re
from collections.abc import Callable

from gymmigrate.edits.lazy import cst
from gymmigrate.edits.syntax import dotted_node
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.import_guards import import_error_guard
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import dotted_name, string_value
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.env_ids.syntax import gym_alias
from gymmigrate.rules.repeats import Repeats
from gymmigrate.rules.wrapper_usage.arguments import (
    HANDLERS,
    missing_or_none,
    parameter,
    positional,
    time_limit_without_limit,
)
from gymmigrate.rules.wrapper_usage.import_edits import ImportEdit, import_build
from gymmigrate.rules.wrapper_usage.legacy_imports import (
    LegacyImports,
    import_move,
    migrated_path,
    removed_import,
)
from gymmigrate.rules.wrapper_usage.monitor import plan_monitor
from gymmigrate.rules.wrapper_usage.monitor_consumers import (
    MONITOR_NAME,
    class_uses,
    derived_class,
    lines_text,
    name_lookups,
    reads_of,
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
    wrapper_rest,
)

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


# gym's Monitor by its attribute path (``gym.wrappers.Monitor``), before and after GM101
_GYM_MONITORS = frozenset(
    f"{package}.wrappers{sub}.Monitor" for package in ("gym", "gymnasium") for sub in ("", ".monitor")
)


class WrapperRenames(RuleFamily):
    RULES = RULES

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        # Every wrapper these rules know is reached through a ``wrappers`` module path; a
        # wrapper stack searched for gym's Monitor by name (GM611) need not name it.
        return "gym" in facts.text and ("wrappers" in facts.text or f'"{MONITOR_NAME}"' in facts.text or f"'{MONITOR_NAME}'" in facts.text)

    def decide(self) -> None:
        self._legacy = LegacyImports(self.facts, self.context.profile)
        self._removed_repeats = Repeats()  # GM610: one review item per removed wrapper and file
        self._renamed_locals: dict[str, str] = {}  # imported name -> new name
        self._monitor_locals: set[str] = set()
        self._monitor_aliases: list[tuple[ast.alias, str]] = []  # plain Monitor imports the rewrite drops
        self._monitor_calls: set[int] = set()  # ids of the Monitor calls rewritten
        self._guarded_monitors: set[ast.alias] = set()  # Monitor imports under ``except ImportError``: left alone
        self._lookup_repeats = Repeats()
        self._import_edits: dict[ast.ImportFrom, ImportEdit] = {}
        self._monitor_imports: list[ImportEdit] = []
        self._names_used: set[str] = set()  # bare names the rewritten Monitor calls use
        self._unused_after: list[ast.Name] = []  # funcs replaced by a vector wrapper path
        self.stacks = WrapperStacks(self.facts, self.receivers)
        self._uses_autoreset = _AUTORESET_USE.search(self.facts.text) is not None
        nodes = list(self.facts.parents)
        for node in nodes:
            if isinstance(node, ast.ImportFrom):
                self._plan_import_from(node)
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
        self._finish_imports()
        self._report_monitor_consumers()

    # -- imports: GM608, GM611, GM614 --------------------------------------------------------

    def _plan_import_from(self, statement: ast.ImportFrom) -> None:
        if statement.level or statement.module is None or any(a.name == "*" for a in statement.names):
            return
        module = statement.module
        rest = N.strip_gym_prefix(module)
        if rest is None:
            return
        if rest.startswith(("experimental.wrappers", "experimental.vector")):
            self._experimental_import(statement, rest)
            return
        stays = self._legacy.stays_legacy(statement)
        if not stays:
            rest = migrated_path(rest)  # where the imports rules put it in the same run
        if rest not in ("wrappers", "wrappers.vector", "wrappers.monitor"):
            return
        names = statement.names
        if stays and module.startswith("gym.") and not (len(names) == 1 and names[0].name == "Monitor"):
            # The imports rules leave this legacy import (it names something removed): its
            # names stay as they are until a person splits it.
            return
        edit = ImportEdit(statement)
        for index, alias in enumerate(names):
            name = alias.name
            bound = alias.asname or name
            if name in RENAMED and rest == "wrappers":
                new = RENAMED[name]
                edit.renames[index] = new
                if alias.asname is None:
                    self._renamed_locals[bound] = new
                code, kind = _rename_code(name)
                self.report(statement, code, f"`{name}` was renamed `{new}` in Gymnasium 1.0", kind=kind)
            elif name == "VectorListInfo" and rest in ("wrappers", "wrappers.vector"):
                if rest == "wrappers" and len(names) > 1:
                    self.report(
                        statement,
                        "GM608",
                        "`VectorListInfo` is now `gymnasium.wrappers.vector.DictInfoToList`: import it from there",
                        kind=FixKind.FLAG,
                    )
                    continue
                edit.module = "wrappers.vector"
                edit.renames[index] = "DictInfoToList"
                if alias.asname is None:
                    self._renamed_locals[bound] = "DictInfoToList"
                self.report(statement, "GM608", "`VectorListInfo` is now `gymnasium.wrappers.vector.DictInfoToList`")
            elif name == "Monitor" and rest in ("wrappers", "wrappers.monitor") and import_error_guard(self.facts, statement):
                self._report_guarded_monitor(statement, alias, bound)
            elif name == "Monitor" and rest in ("wrappers", "wrappers.monitor"):
                self._monitor_aliases.append((alias, bound))
                present = {a.name for a in names}
                edit.added[index] = [r for r in ("RecordEpisodeStatistics", "RecordVideo") if r not in present]
                edit.dropped.add(index)
                self._monitor_locals.add(bound)
                if stays:
                    edit.absolute_module = "gymnasium.wrappers"
                elif rest != "wrappers":
                    edit.module = "wrappers"
                self._monitor_imports.append(edit)
                shadowed = not reads_of(self.facts, alias, bound) and bool(self.facts.reads_of(bound))
                self.report(
                    statement,
                    "GM611",
                    f"`Monitor` is gone: its import is dropped; a later binding of `{bound}` replaces it before any use"
                    if shadowed
                    else "`Monitor` is gone: it is replaced by RecordVideo and RecordEpisodeStatistics",
                    tier=Tier.NOTE,
                )
        if edit.changed:
            self._import_edits[statement] = edit

    def _report_guarded_monitor(self, statement: ast.ImportFrom, alias: ast.alias, bound: str) -> None:
        """``try: from gym.wrappers import Monitor as M / except ImportError: <fallback>``: left as
        it is (see monitor_consumers); the import and each class derived from ``M`` are items."""
        self._guarded_monitors.add(alias)
        reads = reads_of(self.facts, alias, bound)
        derived = [c for c in (derived_class(self.facts, r) for r in reads) if c is not None]
        others = sorted({r.lineno for r in reads if derived_class(self.facts, r) is None})
        used = [f"`{c.name}` (line {c.lineno}) derives from it" for c in derived]
        if others:
            used.append(f"it is read at {lines_text(others)}")
        self.report(
            statement,
            "GM611",
            f"`Monitor` is gone: under Gymnasium this import fails and the `except ImportError` branch runs, as on "
            f"an install without Monitor; left as it is. Rebuild what uses `{bound}` on RecordVideo and "
            f"RecordEpisodeStatistics" + (f" ({'; '.join(used)})" if used else ""),
            kind=FixKind.FLAG,
        )
        for classdef in derived:
            uses = lines_text(class_uses(self.facts, classdef))
            self.report(
                classdef,
                "GM611",
                f"`{classdef.name}` derives from gym's removed `Monitor` (`{bound}`); under Gymnasium it derives from "
                f"the `except ImportError` fallback instead: rebuild it on RecordVideo and RecordEpisodeStatistics"
                + (f" (used at {uses} here, and wherever other modules make it)" if uses else " (and wherever other modules make it)"),
                kind=FixKind.FLAG,
            )

    def _report_monitor_consumers(self) -> None:
        """Reads of a dropped Monitor name that no rewritten call covers, and lookups by name."""
        for alias, bound in self._monitor_aliases:
            for read in reads_of(self.facts, alias, bound):
                if id(read) in self._monitor_calls:
                    continue
                classdef = derived_class(self.facts, read)
                what = f"`{classdef.name}` derives from it" if classdef is not None else "this use is left as it is"
                spelled = "gym's `Monitor`" + (f" (`{bound}`)" if bound != MONITOR_NAME else "")
                self.report(
                    read,
                    "GM611",
                    f"{spelled} is gone and its import is replaced: {what}; rebuild it on RecordVideo "
                    "and RecordEpisodeStatistics",
                    kind=FixKind.FLAG,
                )
        self._report_monitor_attributes()
        if self.context.profile.imports_sb3:
            return  # Stable-Baselines' own Monitor is still there
        for call in name_lookups(self.facts):
            tier, same = self._lookup_repeats.tier(MONITOR_NAME, call)
            self.report(
                call,
                "GM611",
                f"`{self.facts.segment(call)}` looks for a wrapper named `{MONITOR_NAME}`: gym's Monitor is gone (it "
                "becomes RecordEpisodeStatistics/RecordVideo), so the search finds nothing on Gymnasium; "
                f"RecordEpisodeStatistics keeps `episode_count`, `return_queue`, `length_queue`{same}",
                kind=FixKind.FLAG,
                tier=tier,
            )

    def _report_monitor_attributes(self) -> None:
        """``gym.wrappers.Monitor`` read other than as the call it constructs (an
        ``isinstance`` test, a base, a stored class): the attribute is gone from Gymnasium's
        wrappers, so the read raises AttributeError; what replaces the test is a person's call."""
        for attribute in self.facts.attributes.get("Monitor", ()):
            parent = self.facts.parent(attribute)
            if isinstance(parent, ast.Call) and parent.func is attribute:
                continue  # a construction: planned (or asked about) by the Monitor rewrite
            if not self.facts.qualified_names(attribute) & _GYM_MONITORS or self._legacy.binds_legacy(attribute):
                continue
            self.report(
                attribute,
                "GM611",
                f"`{self.facts.segment(attribute)}` is gone (AttributeError on Gymnasium): videos and statistics come "
                "from RecordVideo and RecordEpisodeStatistics now (it keeps `episode_count`, `return_queue`, "
                "`length_queue`); test for those or drop this use",
                kind=FixKind.FLAG,
            )

    def _experimental_import(self, statement: ast.ImportFrom, rest: str) -> None:
        new_module = "gymnasium." + rest.replace("experimental.wrappers", "wrappers", 1).replace(
            "experimental.vector", "vector", 1
        )
        edit = ImportEdit(statement, absolute_module=new_module)
        for index, alias in enumerate(statement.names):
            new = experimental_name(alias.name) if rest.startswith("experimental.wrappers") else None
            if new is None:
                continue
            edit.renames[index] = new
            if alias.asname is None:
                self._renamed_locals[alias.name] = new
        self.report(statement, "GM614", f"gymnasium.{rest} -> {new_module}: the experimental wrappers became the 1.0 wrappers")
        self._import_edits[statement] = edit

    def _finish_imports(self) -> None:
        # Monitor's replacements that no rewritten call uses are not imported (as the
        # LibCST pass's RemoveImportsVisitor dropped them).
        for edit in self._monitor_imports:
            edit.added = {i: [n for n in names if n in self._names_used] for i, names in edit.added.items()}
        # A single-env wrapper whose only uses became ``gym.wrappers.vector.X``.
        for func in self._unused_after:
            for binding in self.facts.bindings_of(func):
                statement = self.facts.parent(binding)
                if not (isinstance(binding, ast.alias) and isinstance(statement, ast.ImportFrom)):
                    continue
                if self._legacy.stays_legacy(statement) or self._other_reads(binding, func.id):
                    continue
                edit = self._import_edits.setdefault(statement, ImportEdit(statement))
                edit.dropped.add(statement.names.index(binding))
        for statement, edit in self._import_edits.items():
            if not edit.changed:
                continue
            if len(edit.dropped) == len(statement.names) and not any(edit.added.values()):
                self.plan.remove(statement)
                move = None if self._legacy.stays_legacy(statement) else import_move(statement)
                if move is not None:
                    code, message = move
                    self.plan.report(statement, code, FixKind.AUTO, message)
                continue
            self.plan.replace(statement, import_build(edit))
            removed = removed_import(statement) if edit.absolute_module and self._legacy.stays_legacy(statement) else None
            if removed is not None:
                self.plan.report(statement, "GM105", FixKind.FLAG, removed)

    def _other_reads(self, alias: ast.alias, name: str) -> bool:
        """Does any read of ``name`` bound by ``alias`` stay in the output?"""
        removed = {id(func) for func in self._unused_after}
        return any(id(read) not in removed for read in self.facts.reads_of(name, alias))

    # -- names and attribute paths: GM608, GM610, GM612, GM614 ----------------------------------

    def _rename_name(self, node: ast.Name) -> None:
        new = self._renamed_locals.get(node.id)
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
        code, kind = _rename_code(old)
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
                tier, same = self._removed_repeats.tier(name, node)
                self.report(node, "GM610", f"`{name}` was removed in Gymnasium 1.0: {REMOVED[name]}{same}", tier=tier)
                return

    def _is_call_func(self, node: ast.AST) -> bool:
        parent = self.facts.parent(node)
        return isinstance(parent, ast.Call) and parent.func is node

    # -- calls: GM609, GM611, GM613, GM615 ------------------------------------------------------

    def _call(self, call: ast.Call) -> None:
        wrapper = self._called_wrapper(call)
        if wrapper is not None and isinstance(call.func, ast.Name) and self._guarded_monitors.intersection(self.facts.bindings_of(call.func)):
            return  # under Gymnasium the name is the ImportError fallback's: reported at the import
        if wrapper is None:
            self._time_limit_super_init(call)
            subclass = self._time_limit_subclass(call)
            if subclass is not None:
                build = time_limit_without_limit(self, call, subclass)
                if build is not None:
                    self.plan.replace(call, build)
            self._check_final_info_get(call)
            return
        old, new = wrapper
        if old in self._monitor_locals or old == "Monitor":
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

    def _time_limit_super_init(self, call: ast.Call) -> None:
        """``super().__init__(env)`` in the ``__init__`` of a subclass of gym's ``TimeLimit``,
        without ``max_episode_steps``: legacy defaulted it to the wrapped env's
        ``spec.max_episode_steps`` (None without a spec), Gymnasium's requires a positive int
        (TypeError). Where the ``__init__`` itself sets ``self._max_episode_steps`` and
        ``self._elapsed_steps`` afterwards (it decides the limit, as gym's body did) and its
        arguments are on record (GM617, or its own ``RecordConstructorArgs``), what TimeLimit's
        ``__init__`` did is all done by the subclass save ``Wrapper.__init__``: the call
        becomes that (its reset and step are TimeLimit's, reading those attributes). Anything
        else is reported."""
        func = call.func
        if not (
            isinstance(func, ast.Attribute)
            and func.attr == "__init__"
            and isinstance(func.value, ast.Call)
            and isinstance(func.value.func, ast.Name)
            and func.value.func.id == "super"
        ):
            return
        init = self.facts.enclosing_function(call)
        classdef = self.facts.parent(init) if init is not None else None
        if init is None or init.name != "__init__" or not isinstance(classdef, ast.ClassDef):
            return
        bases = [b for b in classdef.bases if not (isinstance(b, ast.Name) and b.id == "object")]
        if len(bases) != 1 or not any(
            wrapper_rest(q) == "TimeLimit" and q.startswith("gym.") for q in self.facts.qualified_names(bases[0])
        ):
            return
        if not missing_or_none(call, "max_episode_steps", 1):
            return
        env = parameter(call, "env", 0)
        statement = self.facts.parent(call)
        alias = gym_alias(self.facts)
        if (
            isinstance(statement, ast.Expr)
            and statement in init.body
            and env is not None
            and len(call.args) + len(call.keywords) == 1
            and alias is not None
            and _sets_after(init, statement, ("_max_episode_steps", "_elapsed_steps"))
            and _arguments_recorded(classdef, init)
        ):
            env_text = self.facts.segment(env)
            self.report(
                call,
                "GM609",
                f"`{classdef.name}` sets `_max_episode_steps` and `_elapsed_steps` itself, but Gymnasium's TimeLimit "
                "requires max_episode_steps (TypeError without it; gym read the spec's): "
                f"`{alias}.Wrapper.__init__(self, {env_text})` does the rest of what TimeLimit's __init__ did",
                kind=FixKind.AUTO,
                tier=Tier.NOTE,
            )
            self.plan.replace(call, lambda node: cst.parse_expression(f"{alias}.Wrapper.__init__(self, {env_text})"))
            return
        self.report(
            call,
            "GM609",
            f"`{classdef.name}` subclasses TimeLimit, whose __init__ requires max_episode_steps in Gymnasium 1.x "
            "(a positive int, TypeError without it; gym took the wrapped env's spec.max_episode_steps, None without "
            "a spec): compute the limit before this call and pass it",
            kind=FixKind.FLAG,
        )

    def _time_limit_subclass(self, call: ast.Call) -> str | None:
        """The name of the class of this module ``call`` builds when it derives from gym's
        ``TimeLimit`` (through classes here) and neither it nor a class between defines
        ``__init__``: TimeLimit's own takes the arguments (``max_episode_steps`` required now)."""
        classdef = self.receivers.local_class(call.func)
        name = classdef.name if classdef is not None else None
        seen: set[int] = set()
        while classdef is not None and id(classdef) not in seen:
            seen.add(id(classdef))
            if any(isinstance(s, (ast.FunctionDef, ast.AsyncFunctionDef)) and s.name == "__init__" for s in classdef.body):
                return None
            bases = [b for b in classdef.bases if not (isinstance(b, ast.Name) and b.id == "object")]
            if len(bases) != 1:
                return None
            if any(wrapper_rest(q) == "TimeLimit" for q in self.facts.qualified_names(bases[0])):
                return name
            classdef = self.receivers.local_class(bases[0])
        return None

    def _called_wrapper(self, call: ast.Call) -> tuple[str, str] | None:
        """(legacy name, 1.x name) of the gym/gymnasium wrapper class this call constructs."""
        func = call.func
        if isinstance(func, ast.Name) and func.id in self._monitor_locals:
            # By the binding that reaches the call, not by its spelling: a later import of
            # the project's own ``Monitor`` replaces gym's.
            reaching = self.facts.reaching_bindings(func)
            dropped = {alias for alias, _ in self._monitor_aliases}
            if dropped.issuperset(reaching):
                return func.id, "Monitor"
            if dropped.intersection(reaching):
                self._report_unsure_monitor(call, [b for b in reaching if b not in dropped])
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

    def _report_unsure_monitor(self, call: ast.Call, others: list[ast.AST]) -> None:
        """A ``Monitor`` name bound both to gym's Monitor and to something else, where which
        binding holds at the call is not known (one is under ``if``, in a loop...)."""
        assert isinstance(call.func, ast.Name)
        lines = lines_text(sorted({getattr(other, "lineno", None) or self.facts.statement_of(other).lineno for other in others}))
        self.report(
            call,
            "GM611",
            f"not rewritten: `{call.func.id}` here is gym's removed `Monitor` or what {lines} bind{'s' if len(others) == 1 else ''} it to, and which "
            "one holds at this call is not known; if it is gym's, rebuild it on RecordVideo and RecordEpisodeStatistics",
            kind=FixKind.FLAG,
        )
        self._monitor_calls.add(id(call.func))  # asked here: not asked again as an uncovered read

    # GM613

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


def _rename_code(old: str) -> tuple[str, FixKind | None]:
    if old == "AutoResetWrapper":
        return "GM612", None
    if old == "PixelObservationWrapper":
        return "GM608", FixKind.ASSIST
    return "GM608", None


def _root_name(node: ast.AST) -> str:
    while isinstance(node, ast.Attribute):
        node = node.value
    return node.id if isinstance(node, ast.Name) else "gymnasium"


def _dotted_build(text: str):
    def build(node: cst.BaseExpression) -> cst.BaseExpression:
        return dotted_node(text).with_changes(lpar=node.lpar, rpar=node.rpar)

    return build


def _sets_after(init: ast.FunctionDef | ast.AsyncFunctionDef, statement: ast.stmt, names: tuple[str, ...]) -> bool:
    """Every ``self.<name> = ...`` is a statement of the ``__init__`` body itself (not under
    a branch) after ``statement``."""
    after = init.body[init.body.index(statement) + 1 :]
    set_here = {
        target.attr
        for s in after
        if isinstance(s, (ast.Assign, ast.AnnAssign))
        for target in (s.targets if isinstance(s, ast.Assign) else [s.target])
        if isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self"
    }
    return set(names) <= set_here


def _arguments_recorded(classdef: ast.ClassDef, init: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    """``RecordConstructorArgs`` gets this wrapper's arguments without TimeLimit's __init__:
    the class calls it itself, or GM617 adds the call (arguments besides the env, none in
    ``*args``). Gymnasium's ``Wrapper.spec`` reads ``_saved_kwargs`` of a TimeLimit."""
    named = {n.attr if isinstance(n, ast.Attribute) else n.id for n in ast.walk(classdef) if isinstance(n, (ast.Attribute, ast.Name))}
    if "EzPickle" in named:
        return False
    if "RecordConstructorArgs" in named:
        return True
    args = init.args
    positional = [*args.posonlyargs, *args.args]
    return (
        not args.posonlyargs
        and args.vararg is None
        and len(positional) >= 2
        and bool(positional[2:] or args.kwonlyargs or args.kwarg)
    )
