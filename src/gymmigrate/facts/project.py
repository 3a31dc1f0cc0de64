"""Facts across the files of one run: which parameters receive Gym envs from other modules.

A library method that steps an env (``def fit(self, env)``) is usually called from a
training script in another module that passes ``gym.make(...)``. One file on its own
cannot tell what ``env`` is; the run can. The run is processed in two cheap steps:

1. ``summarize`` reads each module once, on the same ``ast`` facts the rules use, into a
   small picklable ``ModuleSummary``: its top-level functions and the methods of its
   top-level classes with their parameters, its env classes, and for every call of one
   of its own defs or of an imported function, class or method (``agent.fit(env)`` where
   ``agent = Agent()`` and ``Agent`` is imported) the ``EnvKind`` of each argument.
2. ``ProjectFacts.join`` resolves those calls to the modules of the run (absolute and
   relative imports) once, and keeps, per parameter, the kinds the other modules pass.
   An argument that is a parameter of the calling def, or a new instance of a class
   imported from the run, is resolved here, once per parameter (``_Join``).

Each file is then migrated with ``ProjectFacts.view(path)`` in its context: the receiver
analysis joins those kinds with the file's own call sites (``Receivers._param_kind``), and
imported env classes of the run count as env classes. A file checked alone has no view
and keeps its own, more cautious, answer. A call whose owner cannot be resolved but which
passes a VecEnv, vector env or PettingZoo env to a method of the same name still counts
against every method of that name: a guard kind wins.
"""

from __future__ import annotations

import ast
import os
from collections import defaultdict
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from pathlib import Path

from gymmigrate.facts import names as N
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts
from gymmigrate.facts.receivers import EnvKind, Receivers, join_kinds

# Kinds an unresolved ``x.fit(venv)`` still reports against every ``fit`` of the run.
_GUARD_KINDS = frozenset({EnvKind.SB3_VEC, EnvKind.GYM_VEC, EnvKind.PZ_AEC, EnvKind.PZ_PARALLEL})
_UNRESOLVED = "?."
_NEW = "new:"
_OWN = "@"  # a def of the calling module itself
_PARAM = "param:"
# Beyond this many parameters passed on from call to call the join stops following.
_MAX_CHAIN = 50
Kind = EnvKind | str  # a kind, or ``new:<class>`` / ``param:<def>:<name>`` until the join resolves it


@dataclass(frozen=True)
class CallSummary:
    target: str  # "agent.Agent.fit", ".agent.train", "?.fit" (owner unknown)
    args: tuple[Kind, ...]  # by position, up to the first starred argument
    keywords: tuple[tuple[str, Kind], ...]
    open_ended: bool  # ``*args`` / ``**kwargs`` at the call: later parameters are unknown


@dataclass(frozen=True)
class Signature:
    params: tuple[str, ...]  # positional-or-keyword, ``self`` included for methods
    defaults: frozenset[str]  # parameters with a default value
    is_method: bool


@dataclass(frozen=True)
class ModuleSummary:
    path: str  # os.path.realpath of the file
    defs: dict[str, Signature]  # "train", "Agent.fit", "Agent.__init__"
    env_classes: frozenset[str]  # top-level classes whose instances are Gym envs
    render_mode_classes: frozenset[str]  # ...whose constructor takes render_mode once migrated
    calls: tuple[CallSummary, ...]
    # ``x.seed(...)`` on a receiver this module cannot trace: an env class it imports from
    # the run must keep its seed() (removing it would make that call an AttributeError).
    untraced_seed_call: bool = False
    # ``x.render(mode)`` likewise: an env class it imports must keep render(mode).
    untraced_render_call: bool = False
    imported: tuple[str, ...] = ()  # qualified names its imports bind


def summarize(path: str, source: bytes) -> ModuleSummary | None:
    """The summary of one module, or None when it holds no Gym code or does not parse."""
    from gymmigrate.engine import decode, may_hold_gym_code

    if not may_hold_gym_code(source):
        return None
    try:
        text, _ = decode(source)
        facts = ModuleFacts(ast.parse(text), text)
        return _Summarizer(facts, Receivers(facts), os.path.realpath(path)).summary()
    except Exception:  # noqa: BLE001  (the file's own run reports why; it just adds no facts)
        return None


def summarize_run(paths: list[Path], summaries: Callable[[list[Path]], Iterable[object]] | None = None) -> ProjectFacts | None:
    """Facts across ``paths``; None for a single file (nothing to join).

    ``summaries`` maps ``summarize_path`` over the paths (the runner passes its worker
    pool); by default it runs here, one file after the other.
    """
    if len(paths) < 2:
        return None
    python = [path for path in paths if Path(path).suffix in (".py", ".pyw")]
    # Notebooks and documents: their code is not importable by the run.
    found = summaries(python) if summaries is not None else map(summarize_path, python)
    return ProjectFacts.join([summary for summary in found if isinstance(summary, ModuleSummary)])


def summarize_path(path: Path) -> ModuleSummary | None:
    """The summary of the module at ``path``, read and screened as its own run will."""
    from gymmigrate.engine import may_hold_gym_code
    from gymmigrate.safety import Refused, read_source, screen

    try:
        # The same screening as the file's own run: never parse what it refuses.
        source = read_source(Path(path), may_hold_gym_code)
        if source is None or not screen(source, may_hold_gym_code):
            return None
    except (OSError, Refused):
        return None
    return summarize(str(path), source)


class _Summarizer:
    def __init__(self, facts: ModuleFacts, receivers: Receivers, path: str) -> None:
        self.facts = facts
        self.receivers = receivers
        self.path = path

    def summary(self) -> ModuleSummary:
        from gymmigrate.facts.creation import render_kept_classes
        from gymmigrate.facts.env_classes import EnvClasses

        defs: dict[str, Signature] = {}
        for name, function in self.facts.functions.items():
            defs[name] = _signature(function, is_method=False)
        env = EnvClasses.of(self.facts, self.receivers)
        env_classes, render_mode = set(), set()
        for name, classdef in self.facts.classes.items():
            for statement in classdef.body:
                if isinstance(statement, FUNCTIONS):
                    defs[f"{name}.{statement.name}"] = _signature(statement, is_method=True)
            if self.receivers.class_kind(classdef) is EnvKind.GYM_ENV or env.is_custom_env(classdef):
                env_classes.add(name)
                if env.takes_render_mode(classdef) and id(classdef) not in render_kept_classes(self.facts, self.receivers):
                    render_mode.add(name)
        calls = [c for c in (self._call(call) for calls in self.facts.calls_by_name.values() for call in calls) if c]
        calls += [c for c in (self._call(call) for calls in self.facts.attribute_calls.values() for call in calls) if c]
        return ModuleSummary(
            self.path,
            defs,
            frozenset(env_classes),
            frozenset(render_mode),
            tuple(calls),
            untraced_seed_call=self._has_untraced_call("seed"),
            untraced_render_call=self._has_untraced_call("render"),
            imported=tuple(sorted(set(self.facts.imports.values()))),
        )

    def _has_untraced_call(self, method: str) -> bool:
        """``x.seed(...)`` / ``x.render(mode)`` on a receiver this module cannot trace."""
        from gymmigrate.facts.creation import passes_mode

        for call in self.facts.attribute_calls.get(method, ()):
            receiver = call.func.value  # type: ignore[attr-defined]
            if isinstance(receiver, ast.Name) and receiver.id == "self":
                continue  # a class's own call: decided with that class
            if isinstance(receiver, ast.Call) and isinstance(receiver.func, ast.Name) and receiver.func.id == "super":
                continue
            if method == "render" and not passes_mode(call, self.facts):
                continue  # a bare render() (the Gymnasium call), or a render method forwarding
            if self.receivers.kind_of(receiver) is not EnvKind.UNKNOWN:
                continue
            if method == "seed" and self._seed_call_rewritten_here(call):
                continue  # GM203 makes it reset(seed=...) in this run: no seed() caller is left
            made_by = self._instance_class(receiver)
            if made_by is not None and not _is_library(made_by):
                continue  # an instance of a class it imports: the run knows that class
            return True
        return False

    def _seed_call_rewritten_here(self, call: ast.Call) -> bool:
        """``env.seed(s)`` as a statement, with one seed, on an untraced receiver that GM203
        rewrites anyway (an env-like name in a file that uses only Gym). Counting it as a
        caller kept a class's seed() in one run and removed it in the next."""
        from gymmigrate.facts.decisions import Action, decide
        from gymmigrate.rules.base import FileProfile

        if not isinstance(self.facts.parent(call), ast.Expr) or len(call.args) + len(call.keywords) != 1:
            return False
        if (call.args and isinstance(call.args[0], ast.Starred)) or (call.keywords and call.keywords[0].arg != "seed"):
            return False
        function = self.facts.enclosing_function(call)
        if function is not None and function.name == "seed":
            return False
        receiver = call.func.value  # type: ignore[attr-defined]
        profile = FileProfile.from_source(self.facts.text)
        return decide(EnvKind.UNKNOWN, receiver, profile).action is Action.REWRITE_FOR_REVIEW

    def _call(self, call: ast.Call) -> CallSummary | None:
        target = self._target(call.func)
        if target is None:
            return None
        summary = self._arguments(call, target)
        if target.startswith(_UNRESOLVED):
            kinds = {*summary.args, *(k for _, k in summary.keywords)}
            return summary if kinds & _GUARD_KINDS else None
        return summary

    def _target(self, func: ast.expr) -> str | None:
        """The qualified callee in another module, ``@name`` for a def of this module
        (``@Agent.fit`` for ``self.fit(...)``), ``?.name`` for a method of an unknown
        owner, None for library calls."""
        own = self._own_target(func)
        if own is not None:
            return own
        qualified = self.facts.qualified_names(func)
        if qualified:
            found = sorted(q for q in qualified if not _is_library(q))
            return found[0] if len(found) == 1 else None
        if not isinstance(func, ast.Attribute):
            return None
        owner = func.value
        if isinstance(owner, ast.Name) and self.receivers.is_self(owner):
            return None  # a method the class does not define (inherited)
        cls = self._instance_class(owner)
        if cls is not None:
            return f"{cls}.{func.attr}" if not _is_library(cls) else None
        return _UNRESOLVED + func.attr

    def _own_target(self, func: ast.expr) -> str | None:
        function = self.receivers.local_function(func)
        if function is not None:
            return _OWN + function.name
        classdef = self.receivers.local_class(func)
        if classdef is not None:
            return _OWN + f"{classdef.name}.__init__"
        method = self.receivers.own_method(func)
        if method is not None:
            classdef = self.facts.parent(method)  # type: ignore[assignment]
            if self.facts.parent(classdef) is self.facts.tree:  # type: ignore[arg-type]
                return _OWN + f"{classdef.name}.{method.name}"  # type: ignore[union-attr]
        return None

    def _instance_class(self, owner: ast.expr) -> str | None:
        """``Agent`` (qualified through the imports) for ``Agent(...)``, a name or a
        ``self.x`` every binding of which is ``Agent(...)``; None otherwise."""
        if isinstance(owner, ast.Call):
            found = self.facts.qualified_names(owner.func)
            return next(iter(found)) if len(found) == 1 else None
        if isinstance(owner, ast.Name):
            # One answer per set of bindings: a name read n times is resolved once.
            bindings = self.facts.bindings_of(owner)
            if not bindings:
                return None  # (an empty list is a fresh object: its id is no key)
            return self.facts.memo(("instance-class", id(bindings)), lambda: self._class_of_bindings(bindings))  # type: ignore[no-any-return]
        if isinstance(owner, ast.Attribute) and isinstance(owner.value, ast.Name) and self.receivers.is_self(owner.value):
            values = list(self.receivers.self_attribute_values(owner, owner.attr))
        else:
            return None
        return self._class_of_values(values)

    def _class_of_bindings(self, bindings: list[ast.AST]) -> str | None:
        values = []
        for binding in bindings:
            parent = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
            if not isinstance(parent, ast.Assign):
                return None
            values.append(parent.value)
        return self._class_of_values(values)

    def _class_of_values(self, values: list[ast.expr]) -> str | None:
        classes = {self._instance_class(v) if isinstance(v, ast.Call) else None for v in values}
        return classes.pop() if len(classes) == 1 else None

    def _arguments(self, call: ast.Call, target: str) -> CallSummary:
        args: list[Kind] = []
        open_ended = False
        for argument in call.args:
            if isinstance(argument, ast.Starred):
                open_ended = True
                break
            args.append(self._kind(argument))
        keywords = []
        for keyword in call.keywords:
            if keyword.arg is None:
                open_ended = True
            else:
                keywords.append((keyword.arg, self._kind(keyword.value)))
        return CallSummary(target, tuple(args), tuple(keywords), open_ended)

    def _kind(self, argument: ast.expr) -> Kind:
        """The argument's kind; ``new:agent.GridEnv`` for an instance of a class this
        module imports, which the join resolves against the env classes of the run."""
        kind = self.receivers.kind_of(argument)
        if kind is EnvKind.UNKNOWN and isinstance(argument, ast.Call):
            found = [q for q in self.facts.qualified_names(argument.func) if not _is_library(q)]
            if len(found) == 1:
                return _NEW + found[0]
        if kind is EnvKind.UNKNOWN and isinstance(argument, ast.Name):
            parameter = self._parameter_of_def(argument)
            if parameter is not None:
                return parameter
        return kind

    def _parameter_of_def(self, name: ast.Name) -> str | None:
        """``param:Agent.fit:env`` when ``name`` is only ever the parameter ``env`` of a def
        the summary lists: the join gives it the kinds the run passes there."""
        bindings = self.facts.bindings_of(name)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.arg):
            return None
        function = self.facts.parent(self.facts.parent(bindings[0]))
        if not isinstance(function, FUNCTIONS):
            return None
        holder = self.facts.parent(function)
        if holder is self.facts.tree:
            qualname = function.name
        elif isinstance(holder, ast.ClassDef) and self.facts.parent(holder) is self.facts.tree:
            qualname = f"{holder.name}.{function.name}"
        else:
            return None
        return f"{_PARAM}{qualname}:{name.id}"


def _signature(function: ast.FunctionDef | ast.AsyncFunctionDef, is_method: bool) -> Signature:
    args = function.args
    positional = [*args.posonlyargs, *args.args]
    with_default = positional[len(positional) - len(args.defaults) :]
    defaults = {a.arg for a in with_default}
    defaults |= {a.arg for a, d in zip(args.kwonlyargs, args.kw_defaults) if d is not None}
    params = tuple(a.arg for a in (*positional, *args.kwonlyargs))
    return Signature(params, frozenset(defaults), is_method)


def _is_library(qualified: str) -> bool:
    """Gym, Stable-Baselines, PettingZoo, numpy...: never a module of the run."""
    package = N.top_package(qualified)
    return (
        N.strip_gym_prefix(qualified) is not None
        or package in N.SB3_PACKAGES
        or package == N.PETTINGZOO_PACKAGE
        or package in N.NOT_ENV_PACKAGES
        or package in ("typing", "collections", "functools", "os", "sys", "math", "random", "time", "logging")
    )


@dataclass
class ProjectFacts:
    """The run's joined facts; picklable, sent once to each worker with the options."""

    # (path, "Agent.fit", "env") -> the kinds other modules pass there
    param_kinds: dict[tuple[str, str, str], list[EnvKind]] = field(default_factory=dict)
    defs: dict[str, frozenset[str]] = field(default_factory=dict)  # path -> qualnames defined
    env_classes: dict[str, frozenset[str]] = field(default_factory=dict)  # path -> env classes
    render_mode_classes: dict[str, frozenset[str]] = field(default_factory=dict)
    modules: dict[str, str] = field(default_factory=dict)  # dotted suffix -> path ("" if ambiguous)
    # Modules whose env classes an untraced ``x.seed(...)`` elsewhere in the run may reach.
    seed_called: set[str] = field(default_factory=set)
    render_called: set[str] = field(default_factory=set)  # ...and an untraced ``x.render(mode)``

    @classmethod
    def join(cls, summaries: list[ModuleSummary]) -> ProjectFacts:
        facts = cls()
        by_path = {s.path: s for s in summaries}
        for summary in summaries:
            facts.defs[summary.path] = frozenset(summary.defs)
            facts.env_classes[summary.path] = summary.env_classes
            facts.render_mode_classes[summary.path] = summary.render_mode_classes
            for name in _module_names(summary.path):
                facts.modules[name] = "" if name in facts.modules and facts.modules[name] != summary.path else summary.path
        methods_named: dict[str, list[tuple[str, str]]] = defaultdict(list)
        for summary in summaries:
            for qualname, signature in summary.defs.items():
                if signature.is_method:
                    methods_named[qualname.rsplit(".", 1)[1]].append((summary.path, qualname))
        calls_to: dict[tuple[str, str], list[tuple[str, CallSummary]]] = defaultdict(list)
        for summary in summaries:
            for call in summary.calls:
                if call.target.startswith(_UNRESOLVED):
                    # A VecEnv passed to some ``x.fit``: every ``fit`` of the run may get it.
                    for path, qualname in methods_named.get(call.target[len(_UNRESOLVED) :], ()):
                        calls_to[(path, qualname)].append((summary.path, call))
                    continue
                if call.target.startswith(_OWN):
                    qualname = call.target[len(_OWN) :]
                    if qualname in summary.defs:
                        calls_to[(summary.path, qualname)].append((summary.path, call))
                    continue
                resolved = facts._resolve(call.target, summary.path)
                if resolved is not None:
                    calls_to[resolved].append((summary.path, call))
        _Join(facts, by_path, calls_to).run()
        for summary in summaries:
            for untraced, called in ((summary.untraced_seed_call, facts.seed_called), (summary.untraced_render_call, facts.render_called)):
                if untraced:
                    called.update(facts._imported_env_modules(summary))
        for path in facts.render_called:  # their classes keep render(mode): no render_mode to pass
            facts.render_mode_classes[path] = frozenset()
        return facts

    def _imported_env_modules(self, summary: ModuleSummary) -> set[str]:
        """The other modules of the run with env classes that ``summary``'s module imports."""
        found = set()
        for qualified in summary.imported:
            level = len(qualified) - len(qualified.lstrip("."))
            parts = qualified.lstrip(".").split(".")
            for module in (parts, parts[:-1]):  # `import envs` / `from envs import Dice`
                path = self._module_path(module, level, summary.path) if module else None
                if path and path != summary.path and self.env_classes.get(path):
                    found.add(path)
        return found

    def _class_kind(self, kind: str, importer: str) -> EnvKind:
        """``new:envs.GridEnv`` is a Gym env when ``GridEnv`` is an env class of the run."""
        found = self.view(importer).imported_class(kind[len(_NEW) :])
        return EnvKind.GYM_ENV if found is not None and found[0] else EnvKind.UNKNOWN

    def _resolve(self, target: str, importer: str) -> tuple[str, str] | None:
        """``("/run/agent.py", "Agent.fit")`` for ``agent.Agent.fit``; a class called is its ``__init__``."""
        level = len(target) - len(target.lstrip("."))
        parts = target.lstrip(".").split(".")
        for cut in range(len(parts) - 1, 0, -1):
            module, rest = parts[:cut], parts[cut:]
            path = self._module_path(module, level, importer)
            if not path:
                continue
            defined = self.defs.get(path, frozenset())
            qualname = ".".join(rest)
            if qualname in defined:
                return path, qualname
            if f"{qualname}.__init__" in defined:
                return path, f"{qualname}.__init__"
            return None
        return None

    def _module_path(self, module: list[str], level: int, importer: str) -> str | None:
        if level == 0:
            return self.modules.get(".".join(module)) or None
        base = Path(importer).parent
        for _ in range(level - 1):
            base = base.parent
        candidate = base.joinpath(*module)
        for path in (f"{candidate}.py", str(candidate / "__init__.py")):
            if path in self.defs:
                return path
        return None

    def view(self, path: str) -> ProjectView:
        return ProjectView(self, os.path.realpath(path))


class _Join:
    """Per parameter, the kinds other modules pass (``ProjectFacts.param_kinds``).

    An argument that is itself a parameter of the calling def (``_test(env)`` passing
    ``env`` on to ``demo(env)``) has the kind every call of that def gives it, in the
    whole run: one memoized answer per parameter, so the join is linear in the calls;
    a cycle or a chain longer than ``_MAX_CHAIN`` is unknown.
    """

    def __init__(self, facts: ProjectFacts, by_path: dict[str, ModuleSummary], calls_to: dict[tuple[str, str], list[tuple[str, CallSummary]]]) -> None:
        self.facts = facts
        self.by_path = by_path
        self.calls_to = calls_to
        self.memo: dict[tuple[str, str, str], EnvKind] = {}
        self.depth = 0

    def run(self) -> None:
        external: dict[tuple[str, str, str], list[EnvKind]] = defaultdict(list)
        for (path, qualname), calls in self.calls_to.items():
            signature = self.by_path[path].defs[qualname]
            for caller, call in calls:
                if caller == path:
                    continue  # the file sees its own call sites itself
                for param, kind in self._passed(signature, call):
                    external[(path, qualname, param)].append(self._resolve(kind, caller))
        self.facts.param_kinds = dict(external)

    def param_kind(self, path: str, qualname: str, param: str) -> EnvKind:
        key = (path, qualname, param)
        known = self.memo.get(key)
        if known is not None:
            return known
        if self.depth >= _MAX_CHAIN:
            return EnvKind.UNKNOWN
        self.memo[key] = EnvKind.UNKNOWN  # a cycle adds no evidence
        signature = self.by_path[path].defs.get(qualname)
        kinds: list[EnvKind] = []
        self.depth += 1
        try:
            for caller, call in self.calls_to.get((path, qualname), ()) if signature is not None else ():
                kinds.extend(self._resolve(k, caller) for p, k in self._passed(signature, call) if p == param)  # type: ignore[arg-type]
        finally:
            self.depth -= 1
        result = self.memo[key] = join_kinds(kinds)
        return result

    def _resolve(self, kind: Kind, caller: str) -> EnvKind:
        if isinstance(kind, EnvKind):
            return kind
        if kind.startswith(_NEW):
            return self.facts._class_kind(kind, caller)
        qualname, _, param = kind[len(_PARAM) :].rpartition(":")
        return self.param_kind(caller, qualname, param)

    @staticmethod
    def _passed(signature: Signature, call: CallSummary) -> list[tuple[str, Kind]]:
        """(parameter, kind of what the call passes there) for every parameter."""
        params = list(signature.params[1:] if signature.is_method else signature.params)
        given = dict(call.keywords)
        found: list[tuple[str, Kind]] = []
        for index, param in enumerate(params):
            if index < len(call.args):
                found.append((param, call.args[index]))
            elif param in given:
                found.append((param, given[param]))
            elif call.open_ended or param not in signature.defaults:
                found.append((param, EnvKind.UNKNOWN))  # may be passed unseen, or the call would fail
        return found


def _module_names(path: str) -> list[str]:
    """Every dotted name the file may be imported as: ``c``, ``b.c``, ``a.b.c`` for a/b/c.py."""
    parts = list(Path(path).with_suffix("").parts[1:])
    if parts and parts[-1] == "__init__":
        parts.pop()
    return [".".join(parts[i:]) for i in range(len(parts) - 1, -1, -1) if parts[i:]]


@dataclass(frozen=True)
class ProjectView:
    """The run's facts as one file sees them."""

    facts: ProjectFacts
    path: str

    def param_kinds(self, qualname: str, param: str) -> list[EnvKind]:
        """What other modules of the run pass for ``param`` of this file's ``qualname``."""
        return self.facts.param_kinds.get((self.path, qualname, param), [])

    def seed_called_elsewhere(self) -> bool:
        """Another module of the run calls ``x.seed(...)`` on something it cannot trace and
        imports this module's env classes: their seed() may be what it calls."""
        return self.path in self.facts.seed_called

    def render_called_elsewhere(self) -> bool:
        """The same for ``x.render(mode)``: this module's env classes keep render(mode)."""
        return self.path in self.facts.render_called

    def imported_class(self, qualified: str) -> tuple[bool, bool] | None:
        """For an imported class of the run: (is an env class, takes render_mode)."""
        level = len(qualified) - len(qualified.lstrip("."))
        parts = qualified.lstrip(".").split(".")
        if len(parts) < 2:
            return None
        path = self.facts._module_path(parts[:-1], level, self.path)
        if not path:
            return None
        name = parts[-1]
        return name in self.facts.env_classes.get(path, ()), name in self.facts.render_mode_classes.get(path, ())
