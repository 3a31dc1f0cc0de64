"""Vector envs: construction, infos and autoreset (GM701, GM702, GM705-GM708).

* GM701 ``gym.vector.make(id, n, asynchronous=..., wrappers=w, **kw)`` ->
  ``gym.make_vec(id, num_envs=n, vectorization_mode="async"/"sync", wrappers=[w], **kw)``.
  Gymnasium 1.0 removed ``gymnasium.vector.make``. The mode is always written out: the
  legacy default was async, while ``make_vec`` without a mode picks the env's
  ``vector_entry_point`` (for CartPole a different class, which rejects ``wrappers=``).
  ``wrappers`` must be a sequence; arguments of the vector class go in ``vector_kwargs``.
* GM702 ``SyncVectorEnv/AsyncVectorEnv(fns, observation_space, action_space)``: those
  parameters are gone (1.x has ``observation_mode``); reported.
* GM705 vector ``infos`` is one dict of arrays with ``_key`` masks (since gym 0.24):
  list-style readers (``for info in infos``, ``infos[i]``) either get the env wrapped in
  ``gymnasium.wrappers.vector.DictInfoToList`` (when the env is created right here and
  nothing reads infos as a dict) or are reported.
* GM706 Gymnasium 1.0 autoresets on the *next* step and drops ``final_observation``.
  Readers of ``infos["final_observation"]`` get the least change: the env is created with
  ``autoreset_mode=AutoresetMode.SAME_STEP`` and the key renamed ``final_obs``; readers of
  ``final_info`` (now a dict of arrays) and ``terminal_observation`` are reported.
* GM707 ``VectorEnvWrapper`` -> ``VectorWrapper``; ``step_wait``/``reset_wait`` overrides
  are reported (the base class no longer calls them).
* GM708 ``VectorEnv`` is no longer an ``Env``: ``isinstance(envs, gym.Env)`` and
  single-env utilities given a vector env are reported.

Stable-Baselines3 VecEnvs keep their list of info dicts and ``terminal_observation``
(SB104): receivers go through ``analysis.decisions.decide``.
Sources: Gymnasium ``envs/registration.py::make_vec``, ``vector/*.py``,
``wrappers/vector/dict_info_to_list.py``; gym 0.24/0.26.2 release notes; Farama blog
"Vector Autoreset Mode" (2025-02-20); Gymnasium#1103.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, field

import libcst as cst
from libcst.codemod.visitors import AddImportsVisitor, RemoveImportsVisitor
from libcst.metadata import Assignment, PositionProvider, ScopeProvider

from gymmigrate.analysis import names as N
from gymmigrate.analysis.creation import CreationFinder, append_keyword
from gymmigrate.analysis.decisions import Action, decide, receiver_text
from gymmigrate.analysis.receivers import METADATA, EnvKind, ReceiverAnalysis
from gymmigrate.analysis.syntax import keyword_argument, string_value
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileProfile, Rule, RulePass

RULES = (
    Rule(
        "GM701",
        "gym.vector.make",
        FixKind.AUTO,
        "`gym.vector.make(id, n, asynchronous=...)` becomes `gym.make_vec(id, num_envs=n, vectorization_mode=...)`.",
    ),
    Rule(
        "GM702",
        "vector env spaces arguments",
        FixKind.FLAG,
        "`SyncVectorEnv/AsyncVectorEnv(..., observation_space=, action_space=)` no longer exist.",
    ),
    Rule(
        "GM705",
        "vector infos are a dict",
        FixKind.ASSIST,
        "Vector `infos` is a dict of arrays: list-style readers get `DictInfoToList` or are reported.",
    ),
    Rule(
        "GM706",
        "vector autoreset and final observation",
        FixKind.ASSIST,
        "`final_observation` readers get `autoreset_mode=SAME_STEP` and `final_obs`; other readers are reported.",
    ),
    Rule(
        "GM707",
        "VectorEnvWrapper",
        FixKind.ASSIST,
        "`VectorEnvWrapper` becomes `VectorWrapper`; `step_wait`/`reset_wait` overrides are reported.",
    ),
    Rule("GM708", "VectorEnv is not an Env", FixKind.FLAG, "A vector env used where a single `Env` is expected."),
)

# Legacy ``gym.vector.make(id, num_envs=1, asynchronous=True, wrappers=None,
# disable_env_checker=None, **kwargs)`` positional parameters.
_LEGACY_POSITIONS = ("id", "num_envs", "asynchronous", "wrappers", "disable_env_checker")
# Constructor arguments of SyncVectorEnv/AsyncVectorEnv: make_vec wants them in vector_kwargs.
_VECTOR_CLASS_KWARGS = ("shared_memory", "copy", "context", "daemon", "worker", "observation_mode", "autoreset_mode")
_ASYNC_ONLY_KWARGS = ("shared_memory", "context", "daemon", "worker")
_VECTOR_CLASSES = frozenset(
    {
        "vector.SyncVectorEnv",
        "vector.AsyncVectorEnv",
        "vector.sync_vector_env.SyncVectorEnv",
        "vector.async_vector_env.AsyncVectorEnv",
    }
)
_VECTOR_WRAPPER_BASES = frozenset({"vector.VectorEnvWrapper", "vector.vector_env.VectorEnvWrapper"})
_LIST_INFO_WRAPPERS = ("DictInfoToList", "VectorListInfo")
# What a gymnasium VectorWrapper such as DictInfoToList exposes (it has no __getattr__):
# ``envs.call(...)``, ``envs.get_attr(...)`` or ``envs.envs`` would break once wrapped.
_VECTOR_WRAPPER_API = frozenset(
    {
        "reset",
        "step",
        "close",
        "render",
        "seed",  # becomes reset(seed=...) (GM208)
        "action_space",
        "observation_space",
        "single_action_space",
        "single_observation_space",
        "num_envs",
        "metadata",
        "render_mode",
        "spec",
        "unwrapped",
        "np_random",
        "closed",
        "env",
    }
)
# Keys the legacy vector envs put in infos when a sub-env ended.
_FINAL_OBS_KEYS = {"final_observation": "final_obs", "_final_observation": "_final_obs"}
_FINAL_INFO_KEYS = ("final_info", "_final_info")
_TERMINAL_KEYS = ("terminal_observation", "_terminal_observation")
_POSITIONAL_CONSUMERS = ("enumerate", "zip", "len", "list", "tuple", "iter", "sorted", "reversed")
# Single-env utilities (under gym/gymnasium) that reject vector envs.
_SINGLE_ENV_UTILITIES = frozenset(
    {"utils.env_checker.check_env", "utils.play.play", "utils.passive_env_checker.env_reset_passive_checker"}
)
@dataclass
class _VecMake:
    """The planned rewrite of one ``gym.vector.make`` call."""

    autoreset: bool = False


@dataclass
class _Plan:
    vector_makes: dict[int, _VecMake] = field(default_factory=dict)  # id(gym.vector.make call)
    autoreset: set[int] = field(default_factory=set)  # id(make_vec / Sync/AsyncVectorEnv call)
    list_infos: set[int] = field(default_factory=set)  # id(creation call) to wrap in DictInfoToList
    renamed_keys: dict[int, str] = field(default_factory=dict)  # id(SimpleString) -> new key
    renamed_bases: set[int] = field(default_factory=set)  # id(Name/Attribute) VectorEnvWrapper


@dataclass
class _InfosReaders:
    """How the ``infos`` of one step call are read."""

    positional: list[cst.CSTNode] = field(default_factory=list)  # infos[i], for info in infos
    keyed: list[cst.CSTNode] = field(default_factory=list)  # infos["k"], "k" in infos
    final_obs: list[cst.SimpleString] = field(default_factory=list)
    final_info: list[cst.CSTNode] = field(default_factory=list)
    terminal: list[cst.CSTNode] = field(default_factory=list)
    key_strings: list[cst.SimpleString] = field(default_factory=list)  # every key literal seen




def _code(node: cst.CSTNode) -> str:
    return cst.Module(body=[]).code_for_node(node)


def _kwarg(name: str, value: cst.BaseExpression, comma: cst.Comma | cst.MaybeSentinel = cst.MaybeSentinel.DEFAULT) -> cst.Arg:
    return cst.Arg(
        keyword=cst.Name(name),
        value=value,
        equal=cst.AssignEqual(whitespace_before=cst.SimpleWhitespace(""), whitespace_after=cst.SimpleWhitespace("")),
        comma=comma,
    )


class VectorPass(RulePass):
    RULES = RULES
    ORDER = 35
    METADATA_DEPENDENCIES = (PositionProvider, *METADATA)

    @classmethod
    def applies_to(cls, source: str, profile: FileProfile) -> bool:
        return "vector" in source or "VectorEnv" in source or "final_" in source or "terminal_observation" in source

    # -- planning (input tree) ---------------------------------------------------------

    def visit_Module(self, node: cst.Module) -> None:
        self.analysis = ReceiverAnalysis(node, self.metadata)
        self.finder = CreationFinder(self.analysis, self.metadata, self._is_vector_creation)
        self.plan = _Plan()
        self._wrapper_safe: dict[int, bool] = {}  # id(creation call) -> may it be wrapped?
        collector = _Collector()
        node.visit(collector)
        for call in collector.calls:
            if self._is_legacy_vector_make(call):
                self.plan.vector_makes[id(call)] = _VecMake()
            elif self._is_vector_class(call):
                self._check_spaces_arguments(call)
            self._check_single_env_use(call)
        handled: set[int] = set()
        self._plan_infos(collector.step_assigns, handled)
        self._flag_stray_final_keys(collector.strings, handled)
        for classdef in collector.classes:
            self._plan_vector_wrapper(classdef)
        for call in collector.calls:
            if id(call) in self.plan.vector_makes:
                self._report_vector_make(call)

    def _gym_rest(self, node: cst.BaseExpression) -> set[str]:
        rests = set()
        for q in self.analysis.qualified_names(node):
            rest = N.strip_gym_prefix(q)
            if rest is not None:
                rests.add(rest)
        return rests

    def _is_legacy_vector_make(self, call: cst.Call) -> bool:
        return "vector.make" in self._gym_rest(call.func)

    def _is_vector_class(self, call: cst.Call) -> bool:
        return bool(self._gym_rest(call.func) & _VECTOR_CLASSES)

    def _is_vector_creation(self, call: cst.Call) -> bool:
        rests = self._gym_rest(call.func)
        return bool(rests & (N.GYM_VEC_FACTORIES | _VECTOR_CLASSES)) or any(
            r.startswith(N.GYM_VEC_PREFIXES) or r.rsplit(".", 1)[-1] in _LIST_INFO_WRAPPERS for r in rests
        )

    # -- GM701 ------------------------------------------------------------------------------

    def _is_sync(self, call: cst.Call) -> bool:
        mode = self._legacy_argument(call, "asynchronous")
        return mode is not None and isinstance(mode.value, cst.Name) and mode.value.value == "False"

    def _report_vector_make(self, call: cst.Call) -> None:
        moved = [a.keyword.value for a in call.args if a.keyword is not None and a.keyword.value in _VECTOR_CLASS_KWARGS]
        if self._is_sync(call) and any(name in _ASYNC_ONLY_KWARGS for name in moved):
            dropped = [name for name in moved if name in _ASYNC_ONLY_KWARGS]
            self.report(
                call,
                "GM701",
                f"gym.vector.make -> gym.make_vec(vectorization_mode=\"sync\"); dropped {', '.join(dropped)}: "
                "SyncVectorEnv has no such parameter (gym.vector.make passed it to each sub-env's constructor)",
                FixKind.ASSIST,
            )
            return
        wrappers = self._legacy_argument(call, "wrappers")
        unknown_wrappers = wrappers is not None and self._wrappers_shape(wrappers.value) == "unknown"
        mode = self._legacy_argument(call, "asynchronous")
        if mode is None:
            mode_text = '"async" (the legacy default, written out)'
        elif isinstance(mode.value, cst.Name) and mode.value.value in ("True", "False"):
            mode_text = '"async"' if mode.value.value == "True" else '"sync"'
        else:
            mode_text = f"chosen from asynchronous={_code(mode.value)}"
        message = f"gym.vector.make -> gym.make_vec with vectorization_mode {mode_text}"
        star = next((a for a in call.args if a.star == "**"), None)
        if star is not None:
            self.report(
                call,
                "GM701",
                f"{message}; make sure {_code(star.value)} holds no asynchronous/wrappers entry (make_vec would pass it "
                "to each sub-env's constructor)",
                FixKind.ASSIST,
            )
            return
        if moved:
            caveat = ""
            if mode is not None and mode_text.startswith("chosen") and any(n in _ASYNC_ONLY_KWARGS for n in moved):
                caveat = "; in sync mode SyncVectorEnv rejects shared_memory/context/daemon/worker"
            self.report(
                call,
                "GM701",
                f"{message}; {', '.join(moved)} moved into vector_kwargs: gym.vector.make passed them to each "
                f"sub-env's constructor, make_vec gives them to the vector env class{caveat}",
                FixKind.ASSIST,
            )
        elif unknown_wrappers:
            self.report(
                call,
                "GM701",
                f"{message}; make_vec needs wrappers= to be a list and `{_code(wrappers.value)}` could not be "
                "checked: wrap a single callable in [...]",
                FixKind.ASSIST,
            )
        else:
            self.report(call, "GM701", message)

    def _legacy_argument(self, call: cst.Call, name: str) -> cst.Arg | None:
        found = keyword_argument(call, name)
        if found is not None:
            return found
        index = _LEGACY_POSITIONS.index(name)
        positional = [a for a in call.args if a.keyword is None]
        if any(a.star for a in positional[: index + 1]):
            return None
        return positional[index] if index < len(positional) else None

    def _wrappers_shape(self, value: cst.BaseExpression) -> str:
        """"sequence", "callable", "none" or "unknown": legacy accepted one callable or a list."""
        if isinstance(value, (cst.List, cst.Tuple, cst.ListComp)):
            return "sequence"
        if isinstance(value, cst.Name) and value.value == "None":
            return "none"
        if isinstance(value, (cst.Lambda, cst.Attribute)) and self.analysis.qualified_names(value):
            return "callable"
        if isinstance(value, cst.Lambda):
            return "callable"
        if isinstance(value, cst.Name):
            scope = self.metadata[ScopeProvider].get(value)
            shapes = set()
            for assignment in scope[value.value] if scope is not None else ():
                if not isinstance(assignment, Assignment):
                    shapes.add("callable")  # an imported wrapper class or function
                    continue
                target = assignment.node
                if isinstance(target, (cst.FunctionDef, cst.ClassDef)):
                    shapes.add("callable")
                    continue
                parent = self.analysis.parent(target)
                assign = self.analysis.parent(parent) if isinstance(parent, cst.AssignTarget) else None
                if isinstance(assign, cst.Assign):
                    shapes.add(self._wrappers_shape(assign.value))
                else:
                    shapes.add("unknown")
            if len(shapes) == 1:
                return shapes.pop()
        return "unknown"

    def _make_vec_call(self, original: cst.Call, updated: cst.Call, plan: _VecMake) -> cst.BaseExpression:
        """Build ``make_vec(...)`` from ``gym.vector.make(...)``, editing arguments in place."""
        args = list(updated.args)
        positional_index = 0
        new_args: list[cst.Arg] = []
        vector_kwargs: list[tuple[str, cst.BaseExpression]] = []
        q = _quote_style(original)
        mode_value: cst.BaseExpression = cst.SimpleString(f"{q}async{q}")
        saw_mode = False
        last_kept = False
        for i, (arg, old) in enumerate(zip(args, original.args)):
            name = arg.keyword.value if arg.keyword is not None else None
            if name is None and not arg.star:
                name = _LEGACY_POSITIONS[positional_index] if positional_index < len(_LEGACY_POSITIONS) else None
                positional_index += 1
                if name in ("num_envs", "asynchronous", "wrappers", "disable_env_checker"):
                    arg = arg.with_changes(keyword=cst.Name(name), equal=_kwarg(name, arg.value).equal)
            if name == "asynchronous":
                mode_value = self._mode_expression(arg.value, q)
                saw_mode = True
                arg = arg.with_changes(keyword=cst.Name("vectorization_mode"), value=mode_value)
            elif name == "wrappers" and self._wrappers_shape(old.value) == "callable":
                arg = arg.with_changes(value=cst.List([cst.Element(arg.value)]))
            elif name in _VECTOR_CLASS_KWARGS and arg.keyword is not None:
                if not (name in _ASYNC_ONLY_KWARGS and self._is_sync(original)):
                    vector_kwargs.append((name, arg.value))
                continue
            new_args.append(arg)
            last_kept = i == len(args) - 1
        if new_args and not last_kept:
            # The old last argument moved into vector_kwargs: keep its trailing comma style.
            new_args[-1] = new_args[-1].with_changes(comma=args[-1].comma, whitespace_after_arg=args[-1].whitespace_after_arg)
        if plan.autoreset:
            vector_kwargs.append(("autoreset_mode", self._same_step(original)))
        if not saw_mode:
            new_args = self._insert_mode(new_args, updated, mode_value)
        if vector_kwargs:
            new_args = self._insert_after_mode(new_args, updated, "vector_kwargs", _dict_literal(vector_kwargs, q))
        return updated.with_changes(func=self._make_vec_func(original), args=new_args)

    def _mode_expression(self, value: cst.BaseExpression, q: str) -> cst.BaseExpression:
        if isinstance(value, cst.Name) and value.value in ("True", "False"):
            return cst.SimpleString(f"{q}async{q}" if value.value == "True" else f"{q}sync{q}")
        return cst.IfExp(test=value, body=cst.SimpleString(f"{q}async{q}"), orelse=cst.SimpleString(f"{q}sync{q}"))

    def _insert_mode(self, args: list[cst.Arg], call: cst.Call, value: cst.BaseExpression) -> list[cst.Arg]:
        """``vectorization_mode=`` goes right after num_envs (or the id)."""
        index = 1
        for i, arg in enumerate(args):
            if arg.keyword is not None and arg.keyword.value == "num_envs":
                index = i + 1
        return _insert(args, index, _kwarg("vectorization_mode", value), call)

    def _insert_after_mode(self, args: list[cst.Arg], call: cst.Call, name: str, value: cst.BaseExpression) -> list[cst.Arg]:
        index = None
        for i, arg in enumerate(args):
            if arg.keyword is not None and arg.keyword.value in ("vectorization_mode", "num_envs"):
                index = i + 1
        if index is None:
            index = min(len([a for a in args if a.keyword is None and not a.star]), len(args))
            index = max(index, 1)
        return _insert(args, index, _kwarg(name, value), call)

    def _make_vec_func(self, original: cst.Call) -> cst.BaseExpression:
        func = original.func
        if isinstance(func, cst.Attribute) and isinstance(func.value, cst.Attribute):
            root = func.value.value
            if any(q in ("gymnasium", "gym") for q in self.analysis.qualified_names(root)):
                return func.with_changes(value=root, attr=cst.Name("make_vec"))
        if isinstance(func, cst.Name):
            for q in self.analysis.qualified_names(func):
                module = q.rsplit(".", 1)[0]
                RemoveImportsVisitor.remove_unused_import(self.context.codemod, module, func.value)
        AddImportsVisitor.add_needed_import(self.context.codemod, "gymnasium", "make_vec")
        return cst.Name("make_vec")

    def _same_step(self, creation: cst.Call) -> cst.BaseExpression:
        """``gym.vector.AutoresetMode.SAME_STEP`` through the file's own gymnasium name."""
        func = creation.func
        root = func
        while isinstance(root, cst.Attribute):
            root = root.value
        if isinstance(root, cst.Name) and any(q in ("gymnasium", "gym") for q in self.analysis.qualified_names(root)):
            return cst.parse_expression(f"{root.value}.vector.AutoresetMode.SAME_STEP")
        AddImportsVisitor.add_needed_import(self.context.codemod, "gymnasium.vector", "AutoresetMode")
        return cst.parse_expression("AutoresetMode.SAME_STEP")

    # -- GM702 ------------------------------------------------------------------------------

    def _check_spaces_arguments(self, call: cst.Call) -> None:
        named = [a.keyword.value for a in call.args if a.keyword is not None and a.keyword.value in ("observation_space", "action_space")]
        positional = [a for a in call.args if a.keyword is None and not a.star]
        if named or len(positional) > 1:
            what = (
                f"{'/'.join(named)} are no longer parameters of Gymnasium vector envs"
                if named
                else "legacy positional observation_space/action_space would now land on copy/shared_memory"
            )
            self.report(
                call,
                "GM702",
                f"{what}: remove them, or pass observation_mode=\"different\" or (batched_space, single_space) "
                "if the sub-env spaces differ",
            )

    # -- GM705 / GM706 ------------------------------------------------------------------------

    def _plan_infos(self, step_assigns: list[tuple[cst.Assign, cst.Call, cst.Name]], handled: set[int]) -> None:
        by_creation: dict[int, list[tuple[cst.Call, _InfosReaders]]] = defaultdict(list)
        creations: dict[int, cst.Call | None] = {}
        for assign, step, infos in step_assigns:
            receiver = step.func.value  # type: ignore[attr-defined]
            kind = self.analysis.kind_of(receiver)
            decision = decide(kind, receiver, self.context.profile, legacy_shape=True, expected=EnvKind.GYM_VEC)
            if decision.action is Action.LEAVE:
                continue
            readers = self._readers(infos)
            for node in readers.key_strings:
                handled.add(id(node))
            creation = self._direct_creation(receiver) if decision.action is Action.REWRITE else None
            key = id(creation) if creation is not None else id(step)
            creations[key] = creation
            by_creation[key].append((step, readers))
        for key, uses in by_creation.items():
            self._plan_creation(creations[key], uses)

    def _direct_creation(self, receiver: cst.BaseExpression) -> cst.Call | None:
        """The vector creation call, if ``receiver`` is bound exactly once, straight to it."""
        found = self.finder.find(receiver)
        if not found.found or len(found.calls) != 1:
            return None
        call = found.calls[0]
        if not isinstance(receiver, cst.Name):
            return None
        scope = self.metadata[ScopeProvider].get(receiver)
        bindings = list(scope[receiver.value]) if scope is not None else []
        if len(bindings) != 1 or not isinstance(bindings[0], Assignment):
            return None
        target = bindings[0].node
        parent = self.analysis.parent(target)
        assign = self.analysis.parent(parent) if isinstance(parent, cst.AssignTarget) else None
        if not (isinstance(assign, cst.Assign) and assign.value is call):
            return None
        self._wrapper_safe[id(call)] = all(self._wrapper_keeps(access.node) for access in bindings[0].references)
        return call

    def _wrapper_keeps(self, use: cst.CSTNode) -> bool:
        """Does ``envs.<attr>`` still work once ``envs`` is a VectorWrapper (which forwards nothing)?"""
        parent = self.analysis.parent(use)
        if isinstance(parent, cst.Attribute) and parent.value is use:
            return parent.attr.value in _VECTOR_WRAPPER_API
        return True

    def _plan_creation(self, creation: cst.Call | None, uses: list[tuple[cst.Call, _InfosReaders]]) -> None:
        positional = [n for _, r in uses for n in r.positional]
        keyed = [n for _, r in uses for n in r.keyed]
        final_obs = [n for _, r in uses for n in r.final_obs]
        final_info = [n for _, r in uses for n in r.final_info]
        terminal = [n for _, r in uses for n in r.terminal]
        lists_already = creation is not None and self._creates_list_infos(creation)
        if positional and not lists_already:
            if (
                creation is not None
                and not keyed
                and not final_obs
                and not final_info
                and self._can_edit(creation)
                and self._wrapper_safe.get(id(creation), False)
            ):
                self.plan.list_infos.add(id(creation))
                infos_names = ", ".join(sorted({f"`{_infos_name(n)}`" for n in positional}))
                self.report(
                    creation,
                    "GM705",
                    f"vector infos are a dict of arrays in Gymnasium: wrapped the env in DictInfoToList so the "
                    f"list-style reads of {infos_names} still get one dict per sub-env",
                )
            else:
                caveat = ""
                if creation is not None and not self._wrapper_safe.get(id(creation), True):
                    caveat = " (not done here: the env is also used through methods the wrapper does not forward)"
                for node in positional:
                    self.report(
                        node,
                        "GM705",
                        "vector infos are one dict of arrays with `_key` masks, so this list-style read breaks "
                        "(iterating gives keys): wrap the env in gymnasium.wrappers.vector.DictInfoToList"
                        f'{caveat} or read infos["k"][i] where infos["_k"][i]',
                        FixKind.FLAG,
                    )
        same_step = bool(final_obs) and creation is not None and self._can_set_autoreset(creation)
        if same_step:
            self.plan.autoreset.add(id(creation))  # type: ignore[arg-type]
            if id(creation) in self.plan.vector_makes:
                self.plan.vector_makes[id(creation)].autoreset = True  # type: ignore[arg-type]
            creator = _code(creation.func)  # type: ignore[union-attr]
            for node in final_obs:
                old = string_value(node)
                self.plan.renamed_keys[id(node)] = _FINAL_OBS_KEYS[old]  # type: ignore[index]
                self.report(
                    node,
                    "GM706",
                    f'Gymnasium resets sub-envs on the next step by default: the {creator}(...) env now uses '
                    f'autoreset_mode=SAME_STEP, which keeps the legacy timing, and "{old}" is "{_FINAL_OBS_KEYS[old]}"',  # type: ignore[index]
                )
        else:
            for node in final_obs:
                self.report(
                    node,
                    "GM706",
                    "Gymnasium 1.x has no final_observation: by default the final obs is in obs and the sub-env resets "
                    'on the next step; create the env with autoreset_mode=AutoresetMode.SAME_STEP and read "final_obs"',
                    FixKind.FLAG,
                )
        for node in final_info:
            hint = (
                "with SAME_STEP autoreset" if same_step else 'with autoreset_mode=SAME_STEP (the default NEXT_STEP has none)'
            )
            self.report(
                node,
                "GM706",
                f'infos["final_info"] exists only {hint} and is now a dict of arrays with a "_final_info" mask, not '
                "an array of per-env dicts: rewrite this reader",
                FixKind.FLAG,
            )
        for node in terminal:
            self.report(
                node,
                "GM706",
                "terminal_observation (gym 0.22-0.24) is gone: with the default NEXT_STEP autoreset the final obs is in "
                'obs itself; with autoreset_mode=SAME_STEP read infos["final_obs"][i] where infos["_final_obs"][i]',
                FixKind.FLAG,
            )

    def _creates_list_infos(self, creation: cst.Call) -> bool:
        return any(r.rsplit(".", 1)[-1] in _LIST_INFO_WRAPPERS for r in self._gym_rest(creation.func))

    def _can_edit(self, creation: cst.Call) -> bool:
        return id(creation) in self.plan.vector_makes or bool(self._gym_rest(creation.func) & (N.GYM_VEC_FACTORIES | _VECTOR_CLASSES))

    def _can_set_autoreset(self, creation: cst.Call) -> bool:
        rests = self._gym_rest(creation.func)
        if id(creation) in self.plan.vector_makes:
            return keyword_argument(creation, "autoreset_mode") is None
        if "make_vec" in rests:
            existing = keyword_argument(creation, "vector_kwargs")
            if existing is None:
                return True
            return isinstance(existing.value, cst.Dict) and not any(
                isinstance(el, cst.DictElement) and string_value(el.key) == "autoreset_mode" for el in existing.value.elements
            )
        if rests & _VECTOR_CLASSES:
            return keyword_argument(creation, "autoreset_mode") is None and not any(a.star for a in creation.args)
        return False

    def _readers(self, infos: cst.Name) -> _InfosReaders:
        readers = _InfosReaders()
        scope = self.metadata[ScopeProvider].get(infos)
        if scope is None:
            return readers
        for assignment in scope.assignments[infos.value]:
            if not isinstance(assignment, Assignment) or assignment.node is not infos:
                continue
            for access in assignment.references:
                self._classify_read(access.node, readers)
        return readers

    def _classify_read(self, node: cst.CSTNode, readers: _InfosReaders) -> None:
        parent = self.analysis.parent(node)
        if isinstance(parent, (cst.For, cst.CompFor)) and parent.iter is node:
            readers.positional.append(node)
        elif isinstance(parent, cst.Subscript) and parent.value is node:
            key = _subscript_key(parent)
            if key is None:
                outer = self.analysis.parent(parent)
                outer_key = _subscript_key(outer) if isinstance(outer, cst.Subscript) and outer.value is parent else None
                if outer_key in _TERMINAL_KEYS or outer_key in _FINAL_INFO_KEYS or outer_key in _FINAL_OBS_KEYS:
                    readers.terminal.append(outer)
                    readers.key_strings.append(_subscript_string(outer))  # type: ignore[arg-type]  # ``infos[i]["terminal_observation"]``: list form, 0.22-0.23
                else:
                    readers.positional.append(parent)
            else:
                self._keyed(parent, key, _subscript_string(parent), readers)
        elif isinstance(parent, cst.Arg):
            call = self.analysis.parent(parent)
            if isinstance(call, cst.Call) and isinstance(call.func, cst.Name) and call.func.value in _POSITIONAL_CONSUMERS:
                readers.positional.append(call)
        elif isinstance(parent, cst.ComparisonTarget):
            comparison = self.analysis.parent(parent)
            if isinstance(comparison, cst.Comparison) and isinstance(parent.operator, (cst.In, cst.NotIn)):
                key = string_value(comparison.left)
                if key is not None:
                    self._keyed(comparison, key, comparison.left, readers, presence=True)  # type: ignore[arg-type]
        elif isinstance(parent, cst.Attribute) and parent.value is node and parent.attr.value in ("get", "pop"):
            call = self.analysis.parent(parent)
            if isinstance(call, cst.Call) and call.args:
                key = string_value(call.args[0].value)
                if key is not None:
                    self._keyed(call, key, call.args[0].value, readers)  # type: ignore[arg-type]

    def _keyed(
        self, node: cst.CSTNode, key: str, string: cst.SimpleString | None, readers: _InfosReaders, presence: bool = False
    ) -> None:
        if string is not None:
            readers.key_strings.append(string)
        if presence and key in _FINAL_INFO_KEYS:
            return  # ``"final_info" in infos`` still works; the reads below it are what break
        if key in _FINAL_OBS_KEYS and string is not None:
            readers.final_obs.append(string)
        elif key in _FINAL_INFO_KEYS:
            readers.final_info.append(node)
        elif key in _TERMINAL_KEYS:
            readers.terminal.append(node)
        else:
            readers.keyed.append(node)

    def _flag_stray_final_keys(self, strings: list[cst.SimpleString], handled: set[int]) -> None:
        """``final_observation`` read off something that is not traced to a step (e.g. a loop variable)."""
        if self.context.profile.imports_sb3 or not self.context.profile.imports_gym:
            return  # SB3 VecEnvs keep terminal_observation (SB104); Gymnasium-era files keep their keys
        for string in strings:
            key = string_value(string)
            if key not in ("terminal_observation", "final_observation", "final_info") or id(string) in handled:
                continue
            if not self._reads_a_key(string):
                continue
            self.report(
                string,
                "GM706",
                f'"{key}" comes from legacy vector autoreset: Gymnasium 1.x resets sub-envs on the next step and has no '
                'such key (with autoreset_mode=SAME_STEP: "final_obs"/"final_info", dicts of arrays); rewrite this reader',
                FixKind.FLAG,
            )

    def _reads_a_key(self, string: cst.SimpleString) -> bool:
        """``x["k"]``, ``"k" in x``, ``x.get("k")``: the string is used as a dict key."""
        parent = self.analysis.parent(string)
        grandparent = self.analysis.parent(parent) if parent is not None else None
        if isinstance(parent, cst.Index):
            return isinstance(grandparent, cst.SubscriptElement)
        if isinstance(parent, cst.Comparison):
            return parent.left is string
        if isinstance(parent, cst.Arg) and isinstance(grandparent, cst.Call):
            func = grandparent.func
            return isinstance(func, cst.Attribute) and func.attr.value in ("get", "pop") and grandparent.args[0] is parent
        return False

    # -- GM707 --------------------------------------------------------------------------------

    def _plan_vector_wrapper(self, classdef: cst.ClassDef) -> None:
        bases = [b.value for b in classdef.bases if self._gym_rest(b.value) & _VECTOR_WRAPPER_BASES]
        if not bases:
            return
        self.report(
            classdef,
            "GM707",
            "VectorEnvWrapper -> VectorWrapper: attribute forwarding is gone (use envs.get_attr/call or .unwrapped)",
        )
        for statement in classdef.body.body:
            if isinstance(statement, cst.FunctionDef) and statement.name.value in (
                "step_wait",
                "reset_wait",
                "step_async",
                "reset_async",
            ):
                public = statement.name.value.split("_")[0]
                self.report(
                    statement,
                    "GM707",
                    f"VectorWrapper never calls {statement.name.value}(): move this logic into {public}()",
                    FixKind.FLAG,
                )

    def leave_Attribute(self, original_node: cst.Attribute, updated_node: cst.Attribute) -> cst.Attribute:
        if original_node.attr.value == "VectorEnvWrapper" and self._gym_rest(original_node) & _VECTOR_WRAPPER_BASES:
            return updated_node.with_changes(attr=cst.Name("VectorWrapper"))
        return updated_node

    def leave_Name(self, original_node: cst.Name, updated_node: cst.Name) -> cst.Name:
        if original_node.value != "VectorEnvWrapper":
            return updated_node
        parent = self.analysis.parent(original_node)
        if isinstance(parent, cst.Attribute) and parent.attr is original_node:
            return updated_node
        if isinstance(parent, (cst.ImportAlias, cst.AsName)):
            return updated_node
        if self._gym_rest(original_node) & _VECTOR_WRAPPER_BASES:
            return updated_node.with_changes(value="VectorWrapper")
        return updated_node

    def leave_ImportFrom(self, original_node: cst.ImportFrom, updated_node: cst.ImportFrom) -> cst.ImportFrom:
        module = _code(original_node.module) if original_node.module is not None else ""
        if module not in ("gym.vector", "gymnasium.vector", "gym.vector.vector_env", "gymnasium.vector.vector_env"):
            return updated_node
        if isinstance(updated_node.names, cst.ImportStar):
            return updated_node
        names = [
            alias.with_changes(name=cst.Name("VectorWrapper"))
            if isinstance(alias.name, cst.Name) and alias.name.value == "VectorEnvWrapper"
            else alias
            for alias in updated_node.names
        ]
        return updated_node.with_changes(names=names)

    # -- GM708 --------------------------------------------------------------------------------

    def _check_single_env_use(self, call: cst.Call) -> None:
        func = call.func
        if isinstance(func, cst.Name) and func.value == "isinstance" and len(call.args) == 2:
            classes = call.args[1].value
            candidates = [el.value for el in classes.elements] if isinstance(classes, cst.Tuple) else [classes]
            if any(self._gym_rest(c) & N.GYM_ENV_BASE_CLASSES for c in candidates):
                if self.analysis.kind_of(call.args[0].value) is EnvKind.GYM_VEC:
                    self.report(
                        call,
                        "GM708",
                        "a Gymnasium vector env is not a gym.Env any more, so this is False: test for "
                        "gymnasium.vector.VectorEnv",
                    )
            return
        if not call.args or call.args[0].keyword is not None or call.args[0].star:
            return
        if self.analysis.kind_of(call.args[0].value) is not EnvKind.GYM_VEC:
            return
        rests = self._gym_rest(func)
        what = None
        if rests & _SINGLE_ENV_UTILITIES:
            what = f"{_code(func)}() expects a single env"
        elif any(r.startswith("wrappers.") for r in rests):
            pass  # gymnasium's own wrappers on a vector env are GM613's (wrapper_usage.py)
        else:
            local = self.analysis.local_class(func)
            if local is not None and self.analysis.is_gym_wrapper_class(local):
                what = f"{local.name.value} is a single-env gym.Wrapper (port it to gymnasium.vector.VectorWrapper or apply it per sub-env)"
        if what:
            self.report(
                call,
                "GM708",
                f"`{receiver_text(call.args[0].value)}` is a vector env, which is not a gym.Env in Gymnasium 1.x: {what}",
            )

    # -- rewriting ------------------------------------------------------------------------------

    def leave_SimpleString(self, original_node: cst.SimpleString, updated_node: cst.SimpleString) -> cst.SimpleString:
        new = self.plan.renamed_keys.get(id(original_node))
        if new is None:
            return updated_node
        return updated_node.with_changes(value=f"{updated_node.prefix}{updated_node.quote}{new}{updated_node.quote}")

    def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.BaseExpression:
        key = id(original_node)
        result: cst.BaseExpression = updated_node
        if key in self.plan.vector_makes:
            result = self._make_vec_call(original_node, updated_node, self.plan.vector_makes[key])
        elif key in self.plan.autoreset:
            result = self._with_same_step(original_node, updated_node)
        if key in self.plan.list_infos:
            AddImportsVisitor.add_needed_import(self.context.codemod, "gymnasium.wrappers.vector", "DictInfoToList")
            result = cst.Call(func=cst.Name("DictInfoToList"), args=[cst.Arg(result)])
        return result

    def _with_same_step(self, original: cst.Call, updated: cst.Call) -> cst.Call:
        same_step = self._same_step(original)
        if self._gym_rest(original.func) & _VECTOR_CLASSES:
            return append_keyword(updated, "autoreset_mode", same_step)
        existing = keyword_argument(updated, "vector_kwargs")
        q = _quote_style(original)
        entry = cst.DictElement(cst.SimpleString(f"{q}autoreset_mode{q}"), same_step)
        if existing is None:
            return append_keyword(updated, "vector_kwargs", cst.Dict([entry]))
        assert isinstance(existing.value, cst.Dict)
        elements = list(existing.value.elements)
        if elements and not isinstance(elements[-1].comma, cst.Comma):
            elements[-1] = elements[-1].with_changes(comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" ")))
        elements.append(entry)
        new_dict = existing.value.with_changes(elements=elements)
        return updated.with_changes(args=[a.with_changes(value=new_dict) if a is existing else a for a in updated.args])


# -- helpers ----------------------------------------------------------------------------------------


def _infos_name(reader: cst.CSTNode) -> str:
    """The infos variable a list-style read uses (``infos`` in ``infos[i]`` or ``enumerate(infos)``)."""
    if isinstance(reader, cst.Name):
        return reader.value
    if isinstance(reader, cst.Subscript):
        return _code(reader.value)
    if isinstance(reader, cst.Call):
        return next((a.value.value for a in reader.args if isinstance(a.value, cst.Name)), "infos")
    return "infos"


def _subscript_string(subscript: cst.Subscript) -> cst.SimpleString | None:
    if len(subscript.slice) != 1:
        return None
    index = subscript.slice[0].slice
    if isinstance(index, cst.Index) and isinstance(index.value, cst.SimpleString):
        return index.value
    return None


def _subscript_key(subscript: cst.CSTNode) -> str | None:
    if not isinstance(subscript, cst.Subscript):
        return None
    return string_value(_subscript_string(subscript))


def _quote_style(call: cst.Call) -> str:
    """The quote character the call already uses for its strings (the env id), for the strings we add."""
    for arg in call.args:
        if isinstance(arg.value, cst.SimpleString):
            return arg.value.quote[0]
    return '"'


def _dict_literal(items: list[tuple[str, cst.BaseExpression]], q: str = '"') -> cst.Dict:
    elements = []
    for i, (name, value) in enumerate(items):
        comma = cst.Comma(whitespace_after=cst.SimpleWhitespace(" ")) if i < len(items) - 1 else cst.MaybeSentinel.DEFAULT
        elements.append(cst.DictElement(cst.SimpleString(f"{q}{name}{q}"), value, comma=comma))
    return cst.Dict(elements)


def _insert(args: list[cst.Arg], index: int, new: cst.Arg, call: cst.Call) -> list[cst.Arg]:
    """Insert ``new`` at ``index`` with the separators of its neighbours."""
    index = min(max(index, 0), len(args))
    if index == len(args):
        return list(append_keyword(call.with_changes(args=args), new.keyword.value, new.value).args)  # type: ignore[union-attr]
    previous_comma = args[index - 1].comma if index > 0 else cst.MaybeSentinel.DEFAULT
    comma = previous_comma if isinstance(previous_comma, cst.Comma) else cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))
    return [*args[:index], new.with_changes(comma=comma), *args[index:]]


class _Collector(cst.CSTVisitor):
    def __init__(self) -> None:
        self.calls: list[cst.Call] = []
        self.step_assigns: list[tuple[cst.Assign, cst.Call, cst.Name]] = []
        self.strings: list[cst.SimpleString] = []
        self.classes: list[cst.ClassDef] = []

    def visit_Call(self, node: cst.Call) -> None:
        self.calls.append(node)

    def visit_SimpleString(self, node: cst.SimpleString) -> None:
        self.strings.append(node)

    def visit_ClassDef(self, node: cst.ClassDef) -> None:
        self.classes.append(node)

    def visit_Assign(self, node: cst.Assign) -> None:
        value = node.value
        if not (isinstance(value, cst.Call) and isinstance(value.func, cst.Attribute) and value.func.attr.value == "step"):
            return
        if len(node.targets) != 1:
            return
        target = node.targets[0].target
        if isinstance(target, (cst.Tuple, cst.List)) and len(target.elements) in (4, 5):
            last = target.elements[-1].value
            if isinstance(last, cst.Name):
                self.step_assigns.append((node, value, last))
