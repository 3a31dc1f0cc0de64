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

import os
from collections import defaultdict
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

from gymmigrate.facts import names as N
from gymmigrate.facts.kinds import EnvKind, join_kinds
from gymmigrate.facts.limits import Cause, DoneCause, Limit

# Kinds an unresolved ``x.fit(venv)`` still reports against every ``fit`` of the run.
GUARD_KINDS = frozenset({EnvKind.SB3_VEC, EnvKind.GYM_VEC, EnvKind.PZ_AEC, EnvKind.PZ_PARALLEL})
UNRESOLVED = "?."
NEW = "new:"
REF = "ref:"
OWN = "@"  # a def of the calling module itself
PARAM = "param:"
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
    # qualified names of the run that made the receivers of ``x.render(mode)`` calls no make
    # of the module created (``pkg.make_board``): a def among them leaves the mode in place
    render_makers: frozenset[str] = frozenset()
    imported: tuple[str, ...] = ()  # qualified names its imports bind
    # ``# gymmigrate: skip-file``: the module stays as it is, so the run must not assume it migrated.
    skips_file: bool = False
    # Top-level name -> the kind of what calling it gives (a class: its instances; a def or
    # an alias of ``gym.make``: what it returns), or ``ref:<qualified>`` for a name bound to
    # another module's (a re-export, ``from .utils import make``, a subclass of a class of
    # the run): the join follows it. Every top-level def, class and import is listed, so the
    # run knows which names it defines itself.
    exports: dict[str, Kind] = field(default_factory=dict)
    star_imports: tuple[str, ...] = ()  # ``from .utils import *``: modules whose names it re-exports
    # Top-level name -> the library callable it is bound to (``make = gym.make``,
    # ``from gym import make``): a creation site of the run that takes ``make``'s keywords.
    aliases: dict[str, str] = field(default_factory=dict)
    # -- method contracts across modules (rules/custom_env/hooks.py) --
    # Each top-level class with a base imported from elsewhere: (class, qualified base
    # names as the imports spell them, the methods the class defines).
    subclasses: tuple[tuple[str, tuple[str, ...], tuple[str, ...]], ...] = ()
    # Top-level Gym wrapper classes (``Wrapper`` subclasses, through local bases): an
    # instance made elsewhere is a wrapper, so what it does not define was forwarded.
    wrapper_classes: frozenset[str] = frozenset()
    # Top-level PettingZoo wrapper classes and aliases of PettingZoo's wrapper bases
    # (``facts/pz_wrappers.py``): name -> ("aec" | "parallel" | "ref:<qualified>", methods).
    pz_wrappers: dict[str, tuple[str, tuple[str, ...]]] = field(default_factory=dict)
    # -- spaces that are not Spaces (rules/env_ids/registry.py, GM807) --
    # Top-level classes that certainly are not ``gymnasium.spaces.Space``: no base, or only
    # ``list``/``tuple``/``dict``/``object``, with what they derive from ("list").
    plain_classes: dict[str, str] = field(default_factory=dict)
    # Top-level class -> ((space attribute, callee as the module spells it), ...) for each
    # ``self.action_space = C(...)`` / ``self.observation_space = C(...)`` in its methods;
    # ``@C`` for a class of the module itself.
    space_calls: dict[str, tuple[tuple[str, str], ...]] = field(default_factory=dict)
    # Top-level names bound once to a list of the registry's EnvSpecs
    # (``[spec for spec in gym.envs.registry.values() if ...]``): ``spec.make(...)`` on one
    # of them makes an env (``facts/env_specs.py``).
    spec_lists: frozenset[str] = frozenset()
    # Top-level defs every return of which is a ``make(...)`` result (maybe in Gym wrappers):
    # what they return is a wrapper stack, so attribute reads on it go through forwarding.
    made_factories: frozenset[str] = frozenset()
    classes: frozenset[str] = frozenset()  # top-level class names
    # -- what a flag passed to a def is for (facts/bootstrap.py, GM302) --
    # "Agent.train_model" -> (flag parameter, next-state parameter) pairs: the def masks
    # bootstrapping from the next state with the flag (a target or a stored transition).
    bootstrap_masks: dict[str, frozenset[tuple[str, str]]] = field(default_factory=dict)
    # A module with no Gym code (an agent's ``learn``): only its ``bootstrap_masks`` count,
    # it takes no other part in the join (``summaries.summarize_masks``).
    masks_only: bool = False
    # -- done values across modules (facts/limits.py) --
    # Class (with an imported base) -> its methods that take only ``self`` and return a
    # value -> why that value is True (a step limit, the task's end...), traced in the class.
    done_methods: dict[str, dict[str, DoneCause]] = field(default_factory=dict)
    # -- contracts the run keeps (facts/receivers.py keeps_legacy_step) --
    # Top-level env classes whose step keeps the four-field contract (a batch the rules do
    # not migrate): the callers of their instances keep unpacking four values.
    legacy_steps: frozenset[str] = frozenset()
    # Top-level classes with a base of the run (``@Name`` for one of this module): (class,
    # bases, whether its ``__init__`` hands ``render_mode`` on once a base takes it). The
    # join threads ``render_mode`` down every chain of subclasses (custom_env/render.py).
    render_mode_heirs: tuple[tuple[str, tuple[str, ...], bool], ...] = ()
    # ``register(id, entry_point="pkg.mod:Class")``: (the id if a literal, the entry point).
    registrations: tuple[tuple[str | None, str], ...] = ()


@dataclass
class ProjectFacts:
    """The run's joined facts; picklable, sent once to each worker with the options."""

    # (path, "Agent.fit", "env") -> the kinds other modules pass there
    param_kinds: dict[tuple[str, str, str], list[EnvKind]] = field(default_factory=dict)
    defs: dict[str, frozenset[str]] = field(default_factory=dict)  # path -> qualnames defined
    env_classes: dict[str, frozenset[str]] = field(default_factory=dict)  # path -> env classes
    wrapper_classes: dict[str, frozenset[str]] = field(default_factory=dict)  # path -> Gym wrapper classes
    # path -> its PettingZoo wrapper classes (``ModuleSummary.pz_wrappers``)
    pz_wrappers: dict[str, dict[str, tuple[str, tuple[str, ...]]]] = field(default_factory=dict)
    spec_lists: dict[str, frozenset[str]] = field(default_factory=dict)  # path -> names bound to lists of EnvSpecs
    render_mode_classes: dict[str, frozenset[str]] = field(default_factory=dict)
    modules: dict[str, str] = field(default_factory=dict)  # dotted suffix -> path ("" if ambiguous)
    # dotted suffix -> every path it may name, where more than one does (see ``_module_path``)
    ambiguous: dict[str, tuple[str, ...]] = field(default_factory=dict)
    # Modules whose env classes an untraced ``x.seed(...)`` elsewhere in the run may reach.
    seed_called: set[str] = field(default_factory=set)
    render_called: set[str] = field(default_factory=set)  # ...and an untraced ``x.render(mode)``
    # Modules with env classes, and the modules of the run that import them.
    importers: dict[str, set[str]] = field(default_factory=dict)
    # Modules the run leaves as they are (refused, skip-file), with the reason: their
    # classes count as unknown, so no other module is rewritten as if they had migrated.
    blocked: dict[str, str] = field(default_factory=dict)
    # (path, top-level name) -> what calling that name gives, re-exports and subclasses
    # across modules followed: ``pkg.make`` re-exported from ``utils.make = gym.make`` is a
    # Gym env factory, ``from hunt import HuntEnv`` a PettingZoo parallel env class.
    call_kinds: dict[tuple[str, str], EnvKind] = field(default_factory=dict)
    # (path, top-level name) of the Gym env factories among them whose every return is a
    # ``make(...)`` result (``ModuleSummary.made_factories``, re-exports followed).
    made: set[tuple[str, str]] = field(default_factory=set)
    # (path, top-level name) of the run's Gym env classes (re-exports and subclasses across
    # modules followed) that are no wrapper: an instance is the env itself, no stack.
    bare_env_classes: set[tuple[str, str]] = field(default_factory=set)
    # (path, top-level name) -> the library callable it stands for, re-exports followed.
    aliases: dict[tuple[str, str], str] = field(default_factory=dict)
    # (path, class) -> the methods subclasses in other modules of the run override, with
    # where ("pkg/far.py:FarEnv"): a hook a base class migrates must migrate there too.
    overrides: dict[tuple[str, str], dict[str, list[str]]] = field(default_factory=dict)
    # (path, class) -> its direct subclasses in other modules of the run, and (path, class)
    # -> the done causes of their self-only methods (``ModuleSummary.done_methods``).
    subclasses_of: dict[tuple[str, str], list[tuple[str, str]]] = field(default_factory=dict)
    done_methods: dict[tuple[str, str], dict[str, DoneCause]] = field(default_factory=dict)
    subclass_methods: dict[tuple[str, str], frozenset[str]] = field(default_factory=dict)
    # Packages the migrated code imports that its dependency files must declare: ``mpe2``
    # where a module imports ``pettingzoo.mpe`` (PZ111 moves the import there).
    requires: frozenset[str] = frozenset()
    # ``gym.envs`` plugin entry points of the run's dependency files (GM111): the module
    # path -> the (function, namespace or None) calls to append to it, and the dependency
    # file's path -> entry target -> (the module that calls it, as shown, or None; why not).
    plugin_calls: dict[str, tuple[tuple[str, str | None], ...]] = field(default_factory=dict)
    plugin_routes: dict[str, dict[str, tuple[str | None, str]]] = field(default_factory=dict)
    # (path, top-level name) -> (space attribute, space class, what it derives from) for a
    # class (or a re-export of one) that sets a space to an instance of a class of the run
    # that is not a ``gymnasium.spaces.Space``: Gymnasium 1.x's env checker rejects it.
    non_space_envs: dict[tuple[str, str], tuple[str, str, str]] = field(default_factory=dict)
    # (path, top-level name) of a class (or a re-export of one) whose step keeps the legacy
    # four-field contract after the run.
    legacy_steps: frozenset[tuple[str, str]] = frozenset()
    # Ids the run registers for an env class of the run whose constructor will not take
    # ``render_mode`` (its ``__init__`` cannot hand it on): id (None: not a literal) -> class.
    # ``gymnasium.make(id, render_mode=...)`` of one would raise TypeError.
    no_render_mode_ids: dict[str | None, str] = field(default_factory=dict)
    # path -> the top-level packages the module imports, with those of the run's modules it
    # imports and of those that import it (one step each way): a project's neighbourhood,
    # not every project of a run over several.
    nearby_packages: dict[str, frozenset[str]] = field(default_factory=dict)
    # (path, "Agent.train_model") -> ``ModuleSummary.bootstrap_masks`` of that def, with
    # its parameters in order (a call passes them by position).
    bootstrap_masks: dict[tuple[str, str], tuple[tuple[str, ...], frozenset[tuple[str, str]]]] = field(default_factory=dict)
    # dotted suffix -> paths of the modules with no Gym code that have bootstrap masks (the
    # nearest to the importer counts when several); no module of the run for anything else.
    mask_modules: dict[str, tuple[str, ...]] = field(default_factory=dict)

    @classmethod
    def join(cls, summaries: list[ModuleSummary], blocked: dict[str, str] | None = None) -> ProjectFacts:
        facts = cls()
        facts.blocked = dict(blocked or {})
        facts.blocked.update(
            (s.path, "it says `# gymmigrate: skip-file`") for s in summaries if s.skips_file and s.path not in facts.blocked
        )
        for summary in summaries:
            for qualname, masks in summary.bootstrap_masks.items():
                facts.bootstrap_masks[(summary.path, qualname)] = (summary.defs[qualname].params, masks)
            if summary.masks_only:
                for name in _module_names(summary.path):
                    facts.mask_modules[name] = (*facts.mask_modules.get(name, ()), summary.path)
        summaries = [s for s in summaries if not s.masks_only]
        by_path = {s.path: s for s in summaries}
        for summary in summaries:
            facts.defs[summary.path] = frozenset(summary.defs)
            left = summary.path in facts.blocked
            facts.env_classes[summary.path] = frozenset() if left else summary.env_classes
            facts.wrapper_classes[summary.path] = frozenset() if left else summary.wrapper_classes
            facts.pz_wrappers[summary.path] = summary.pz_wrappers
            facts.spec_lists[summary.path] = summary.spec_lists
            facts.render_mode_classes[summary.path] = frozenset() if left else summary.render_mode_classes
            for name in _module_names(summary.path):
                if name in facts.modules and facts.modules[name] != summary.path:
                    previous = facts.ambiguous.get(name) or (facts.modules[name],)
                    facts.ambiguous[name] = (*previous, summary.path)
                    facts.modules[name] = ""
                else:
                    facts.modules[name] = summary.path
        methods_named: dict[str, list[tuple[str, str]]] = defaultdict(list)
        for summary in summaries:
            for qualname, signature in summary.defs.items():
                if signature.is_method:
                    methods_named[qualname.rsplit(".", 1)[1]].append((summary.path, qualname))
        calls_to: dict[tuple[str, str], list[tuple[str, CallSummary]]] = defaultdict(list)
        for summary in summaries:
            for call in summary.calls:
                if call.target.startswith(UNRESOLVED):
                    # A VecEnv passed to some ``x.fit``: every ``fit`` of the run may get it.
                    for path, qualname in methods_named.get(call.target[len(UNRESOLVED) :], ()):
                        calls_to[(path, qualname)].append((summary.path, call))
                    continue
                if call.target.startswith(OWN):
                    qualname = call.target[len(OWN) :]
                    if qualname in summary.defs:
                        calls_to[(summary.path, qualname)].append((summary.path, call))
                    continue
                resolved = facts._resolve(call.target, summary.path)
                if resolved is not None:
                    calls_to[resolved].append((summary.path, call))
        imported = {q for summary in summaries for q in summary.imported}
        facts._join_nearby_packages(summaries)
        requires = {
            package
            for family, (package, rewritten) in N.PZ_MOVED_FAMILIES.items()
            if rewritten and any(
                q == family or q.startswith(family + ".") or q == package or q.startswith(package + ".")
                for q in imported
            )
        }
        # Gymnasium 1.x's ``envs/mujoco/__init__.py`` imports its renderer, which imports
        # imageio: any import under ``gym.envs.mujoco`` (``gymnasium.envs.mujoco``) needs it.
        if any(q.split(".")[:3] in (["gym", "envs", "mujoco"], ["gymnasium", "envs", "mujoco"]) for q in imported):
            requires.add("imageio")
        facts.requires = frozenset(requires)
        _Exports(facts, by_path).run()
        _Join(facts, by_path, calls_to).run()
        for summary in summaries:
            if summary.untraced_seed_call:
                facts.seed_called.update(facts._imported_env_modules(summary))
            if summary.untraced_render_call or any(facts._made_by_def(maker, summary.path, by_path) for maker in summary.render_makers):
                # ``import pkg`` reaches the env classes ``pkg/__init__.py`` imports too
                # (``env = pkg.make_benchmark(...)``; ``env.render(mode="readable")``)
                facts.render_called.update(facts._env_modules_through_packages(summary, by_path))
            for provider in facts._imported_env_modules(summary, declared=by_path):
                facts.importers.setdefault(provider, set()).add(summary.path)
        for path in facts.render_called:  # their classes keep render(mode): no render_mode to pass
            facts.render_mode_classes[path] = frozenset()
        _thread_render_mode(facts, by_path)
        facts._join_overrides(summaries)
        _NonSpaces(facts, by_path).run()
        _reexport_wrappers(facts, by_path)
        facts.legacy_steps = _legacy_steps(facts, by_path)
        return facts

    def _join_nearby_packages(self, summaries: list[ModuleSummary]) -> None:
        own = {s.path: frozenset(q.split(".", 1)[0] for q in s.imported if not q.startswith(".")) for s in summaries}
        nearby = {path: set(tops) for path, tops in own.items()}
        for summary in summaries:
            for qualified in summary.imported:
                split = self._split(qualified, summary.path)
                if split is None or split[0] == summary.path or split[0] not in own:
                    continue
                nearby[summary.path] |= own[split[0]]
                nearby[split[0]] |= own[summary.path]
        self.nearby_packages = {path: frozenset(tops) for path, tops in nearby.items()}

    def _join_overrides(self, summaries: list[ModuleSummary]) -> None:
        """Which methods of a run's class are overridden by subclasses in other modules."""
        for summary in summaries:
            for name, bases, methods in summary.subclasses:
                for qualified in bases:
                    level = len(qualified) - len(qualified.lstrip("."))
                    parts = qualified.lstrip(".").split(".")
                    path = self._module_path(parts[:-1], level, summary.path) if len(parts) > 1 else None
                    if not path or path == summary.path:
                        continue
                    found = self.overrides.setdefault((path, parts[-1]), {})
                    for method in methods:
                        found.setdefault(method, []).append(f"{summary.path}:{name}")
                    self.subclasses_of.setdefault((path, parts[-1]), []).append((summary.path, name))
                self.subclass_methods[(summary.path, name)] = frozenset(methods)
            for name, methods_done in summary.done_methods.items():
                self.done_methods[(summary.path, name)] = methods_done

    def _imported_env_modules(self, summary: ModuleSummary, declared: dict[str, ModuleSummary] | None = None) -> set[str]:
        """The other modules of the run with env classes that ``summary``'s module imports
        (``declared``: by the classes each module declares, blocked or not)."""
        found = set()
        for qualified in summary.imported:
            level = len(qualified) - len(qualified.lstrip("."))
            parts = qualified.lstrip(".").split(".")
            for module in (parts, parts[:-1]):  # `import envs` / `from envs import Dice`
                path = self._module_path(module, level, summary.path) if module else None
                if path and path != summary.path and (
                    self.env_classes.get(path) or (declared is not None and path in declared and declared[path].env_classes)
                ):
                    found.add(path)
        return found

    def _made_by_def(self, qualified: str, importer: str, by_path: dict[str, ModuleSummary]) -> bool:
        """``pkg.make_board`` names a def of the run (not a class, whose construction the
        rendering rules give a ``render_mode``), followed through re-exports."""
        resolved = self._resolve(qualified, importer)
        if resolved is None:
            return False
        path, name = resolved
        summary = by_path.get(path)
        return summary is not None and "." not in name and name in summary.defs and name not in summary.classes

    def _env_modules_through_packages(self, summary: ModuleSummary, by_path: dict[str, ModuleSummary]) -> set[str]:
        """``_imported_env_modules``, and those of every package ``__init__`` of the run it
        imports, followed through the ``__init__`` modules those import."""
        found = self._imported_env_modules(summary)
        seen = {summary.path}
        queue = [summary]
        while queue:
            current = queue.pop()
            for qualified in current.imported:
                level = len(qualified) - len(qualified.lstrip("."))
                parts = qualified.lstrip(".").split(".")
                for module in (parts, parts[:-1]):
                    path = self._module_path(module, level, current.path) if module else None
                    if path is None or path in seen or os.path.basename(path) != "__init__.py" or path not in by_path:
                        continue
                    seen.add(path)
                    found |= self._imported_env_modules(by_path[path])
                    queue.append(by_path[path])
        return found

    def _class_kind(self, kind: str, importer: str) -> EnvKind:
        """``new:envs.GridEnv`` is a Gym env when ``GridEnv`` is an env class of the run (or
        derives from one, or is re-exported); a PettingZoo env class of the run likewise."""
        found = self.view(importer).call_kind(kind[len(NEW) :])
        if found is not None and found is not EnvKind.NOT_ENV:
            return found
        imported = self.view(importer).imported_class(kind[len(NEW) :])
        return EnvKind.GYM_ENV if imported is not None and imported[0] else EnvKind.UNKNOWN

    def _split(self, qualified: str, importer: str) -> tuple[str, str] | None:
        """``("/run/pkg/utils.py", "make")`` for ``pkg.utils.make`` (or ``.utils.make``)."""
        level = len(qualified) - len(qualified.lstrip("."))
        parts = qualified.lstrip(".").split(".")
        for cut in range(len(parts) - 1, -1, -1):
            if cut == 0 and level == 0:
                break
            path = self._module_path(parts[:cut], level, importer)
            if path and cut < len(parts):
                return path, ".".join(parts[cut:])
        return None

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
            dotted = ".".join(module)
            found = self.modules.get(dotted)
            if found == "":
                return _nearest_root(self.ambiguous.get(dotted, ()), len(module), importer)
            return found or None
        base = Path(importer).parent
        for _ in range(level - 1):
            base = base.parent
        candidate = base.joinpath(*module)
        if not module:  # ``from . import x``: the package itself
            path = str(base / "__init__.py")
            return path if path in self.defs else None
        for path in (f"{candidate}.py", str(candidate / "__init__.py")):
            if path in self.defs:
                return path
        return None

    def view(self, path: str) -> ProjectView:
        return ProjectView(self, os.path.realpath(path))


class _Exports:
    """``ProjectFacts.call_kinds``: every top-level name of the run with what calling it
    gives, re-exports (``__init__``, star imports, ``make = utils.make``) and subclasses
    followed to the module that decides. One memoized answer per name; a cycle or a chain
    longer than ``_MAX_CHAIN`` is unknown."""

    def __init__(self, facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> None:
        self.facts = facts
        self.by_path = by_path
        self.depth = 0

    def run(self) -> None:
        for path, summary in self.by_path.items():
            for name in summary.exports:
                self.kind(path, name)
                alias = self._alias(path, name)
                if alias is not None:
                    self.facts.aliases[(path, name)] = alias
            for name in self._star_names(summary, set()):
                self.kind(path, name)  # ``from .envs import *``: its names are this module's too
        for key, kind in self.facts.call_kinds.items():
            if kind is EnvKind.GYM_ENV:
                trail: list[tuple[str, str]] = []
                where = self.origin(*key, set(), trail)
                if where is None:
                    continue
                defining = self.by_path[where[0]]
                if where[1] in defining.made_factories:
                    self.facts.made.add(key)
                if (
                    where[1] in defining.classes
                    and where[1] in self.facts.env_classes.get(where[0], ())
                    and not any(n in self.by_path[p].wrapper_classes for p, n in trail)
                ):
                    self.facts.bare_env_classes.add(key)

    def origin(
        self, path: str, name: str, seen: set[tuple[str, str]], trail: list[tuple[str, str]] | None = None
    ) -> tuple[str, str] | None:
        """The module and name that define ``name`` of module ``path``: re-exports, star
        imports and subclasses of a class of another module (``ref:``) followed, each once;
        ``trail`` gets every name passed on the way."""
        summary = self.by_path.get(path)
        if summary is None or (path, name) in seen or len(seen) >= _MAX_CHAIN:
            return None
        seen.add((path, name))
        kind = summary.exports.get(name)
        if kind is None:
            for star in self._star_paths(summary):
                found = self.origin(star, name, seen, trail)
                if found is not None:
                    return found
            return None
        if trail is not None:
            trail.append((path, name))
        if isinstance(kind, EnvKind):
            return path, name
        split = self.facts._split(kind[len(REF) :], path)
        return None if split is None or "." in split[1] else self.origin(*split, seen, trail)

    def _star_names(self, summary: ModuleSummary, seen: set[str]) -> set[str]:
        """The public names a module's star imports bring in (star chains followed once)."""
        seen.add(summary.path)
        names: set[str] = set()
        for path in self._star_paths(summary):
            if path in seen:
                continue
            star = self.by_path[path]
            names.update(n for n in star.exports if not n.startswith("_"))
            names.update(self._star_names(star, seen))
        return names

    def _star_paths(self, summary: ModuleSummary) -> list[str]:
        found = []
        for module in summary.star_imports:
            level = len(module) - len(module.lstrip("."))
            path = self.facts._module_path(module.lstrip(".").split(".") if module.strip(".") else [], level, summary.path)
            if path and path != summary.path and path in self.by_path:
                found.append(path)
        return found

    def _alias(self, path: str, name: str) -> str | None:
        """``gym.make`` for a name bound to it here or through a chain of re-exports."""
        for _ in range(_MAX_CHAIN):
            summary = self.by_path.get(path)
            if summary is None:
                return None
            if name in summary.aliases:
                return summary.aliases[name]
            kind = summary.exports.get(name)
            if not _is_ref(kind):
                return None
            split = self.facts._split(str(kind)[len(REF) :], path)
            if split is None:
                return None
            path, name = split
        return None

    def kind(self, path: str, name: str) -> EnvKind | None:
        """What calling ``name`` of module ``path`` gives; None when the module does not
        bind it (not even through a star import)."""
        key = (path, name)
        known = self.facts.call_kinds.get(key)
        if known is not None:
            return known
        summary = self.by_path.get(path)
        if summary is None or self.depth >= _MAX_CHAIN:
            return None
        kind = summary.exports.get(name)
        self.facts.call_kinds[key] = EnvKind.UNKNOWN  # a cycle adds no evidence
        self.depth += 1
        try:
            if kind is None:
                found = self._from_stars(summary, name)
                if found is None:
                    del self.facts.call_kinds[key]
                    return None
            elif isinstance(kind, EnvKind):
                # A module the run leaves as it is: its classes did not migrate.
                found = EnvKind.UNKNOWN if path in self.facts.blocked and kind is not EnvKind.NOT_ENV else kind
            else:
                found = self._follow(kind[len(REF) :], path)
        finally:
            self.depth -= 1
        self.facts.call_kinds[key] = found
        return found

    def _follow(self, qualified: str, importer: str) -> EnvKind:
        split = self.facts._split(qualified, importer)
        if split is None:
            return EnvKind.UNKNOWN  # a library name the module could not classify
        path, name = split
        if "." in name:
            return EnvKind.UNKNOWN  # ``module.Class.method``: not a top-level name
        found = self.kind(path, name)
        return EnvKind.UNKNOWN if found is None else found

    def _from_stars(self, summary: ModuleSummary, name: str) -> EnvKind | None:
        for path in self._star_paths(summary):
            found = self.kind(path, name)
            if found is not None:
                return found
        return None


class _NonSpaces:
    """``ProjectFacts.non_space_envs``: classes of the run whose ``action_space`` or
    ``observation_space`` is an instance of a class of the run that certainly is not a
    ``Space`` (``class MultiAgentActionSpace(list)``), and every name re-exporting them."""

    def __init__(self, facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> None:
        self.facts = facts
        self.by_path = by_path

    def origin(self, path: str, name: str) -> tuple[str, str] | None:
        """The module and name that define ``name`` of module ``path``, re-exports followed."""
        for _ in range(_MAX_CHAIN):
            summary = self.by_path.get(path)
            if summary is None:
                return None
            if name in summary.plain_classes or name in summary.space_calls:
                return path, name  # defined here (a subclass's export refers to its base)
            kind = summary.exports.get(name)
            if not _is_ref(kind):
                return (path, name) if kind is not None else None
            split = self.facts._split(str(kind)[len(REF) :], path)
            if split is None or "." in split[1]:
                return None
            path, name = split
        return None

    def run(self) -> None:
        found: dict[tuple[str, str], tuple[str, str, str]] = {}
        for path, summary in self.by_path.items():
            if path in self.facts.blocked:
                continue
            for classname, calls in summary.space_calls.items():
                for attribute, callee in calls:
                    if callee.startswith(OWN):
                        where: tuple[str, str] | None = (path, callee[len(OWN) :])
                    else:
                        split = self.facts._split(callee, path)
                        where = self.origin(*split) if split is not None and "." not in split[1] else None
                    if where is None:
                        continue
                    base = self.by_path[where[0]].plain_classes.get(where[1])
                    if base is not None:
                        found.setdefault((path, classname), (attribute, where[1], base))
        if not found:
            return
        for path, summary in self.by_path.items():
            for name in summary.exports:
                where = self.origin(path, name)
                if where is not None and where in found:
                    self.facts.non_space_envs[(path, name)] = found[where]


def _reexport_wrappers(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> None:
    """A name that re-exports a wrapper class of another module (``from .utils import
    Stats`` in a package's ``__init__``) is that wrapper class too."""
    added: dict[str, set[str]] = defaultdict(set)
    for path, summary in by_path.items():
        if path in facts.blocked:
            continue
        for name, first in summary.exports.items():
            where = (path, name)
            export: EnvKind | str | None = first
            for _ in range(_MAX_CHAIN):
                if not isinstance(export, str):
                    break
                split = facts._split(export[len(REF) :], where[0])
                if split is None or "." in split[1] or split[0] not in by_path:
                    break
                where = split
                if where[1] in facts.wrapper_classes.get(where[0], ()):
                    added[path].add(name)
                    break
                export = by_path[where[0]].exports.get(where[1])
    for path, names in added.items():
        facts.wrapper_classes[path] = facts.wrapper_classes.get(path, frozenset()) | names
def _definer(facts: ProjectFacts, by_path: dict[str, ModuleSummary], path: str, name: str) -> tuple[str, str] | None:
    """The module and name of the class ``name`` of module ``path`` is, re-exports followed."""
    for _ in range(_MAX_CHAIN):
        summary = by_path.get(path)
        if summary is None:
            return None
        if name in summary.env_classes or any(heir[0] == name for heir in summary.render_mode_heirs):
            return path, name
        kind = summary.exports.get(name)
        if not _is_ref(kind):
            return (path, name) if kind is not None else None
        split = facts._split(str(kind)[len(REF) :], path)
        if split is None or "." in split[1]:
            return None
        path, name = split
    return None


def _thread_render_mode(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> None:
    """A subclass (in any module of the run) of a class whose constructor takes
    ``render_mode`` takes it too when its ``__init__`` can hand it on: custom_env/render.py
    adds the parameter and passes it to the base's ``__init__``. Without that, render() of
    every such subclass is a silent no-op and ``gymnasium.make(id, render_mode=...)`` of a
    registered one a TypeError. Every name re-exporting such a class counts too."""
    takes = {(path, name) for path, names in facts.render_mode_classes.items() for name in names}

    def resolve(base: str, path: str) -> tuple[str, str] | None:
        if base.startswith(OWN):
            return path, base[len(OWN) :]
        split = facts._split(base, path)
        if split is None or "." in split[1] or facts.call_kinds.get(split) is not EnvKind.GYM_ENV:
            return None  # only a base that makes the subclass an env class the rules decide
        return _definer(facts, by_path, *split)

    changed = True
    while changed:
        changed = False
        for path, summary in by_path.items():
            if path in facts.blocked or path in facts.render_called:
                continue
            for name, bases, passes_on in summary.render_mode_heirs:
                if passes_on and (path, name) not in takes and any(resolve(b, path) in takes for b in bases):
                    takes.add((path, name))
                    changed = True
    for path, summary in by_path.items():
        for name in summary.exports:
            if (path, name) not in takes and _definer(facts, by_path, path, name) in takes:
                takes.add((path, name))
    for summary in by_path.values():
        for env_id, entry in summary.registrations:
            module, _, name = entry.partition(":")
            where = facts.modules.get(module)
            definer = _definer(facts, by_path, where, name) if where else None
            if definer is None or definer in takes:
                continue
            defined = by_path[definer[0]]
            if definer[1] in defined.env_classes or any(h[0] == definer[1] for h in defined.render_mode_heirs):
                facts.no_render_mode_ids.setdefault(env_id, definer[1])
    found: dict[str, set[str]] = defaultdict(set)
    for path, name in takes:
        found[path].add(name)
    facts.render_mode_classes = {path: frozenset(found.get(path, ())) for path in set(facts.render_mode_classes) | set(found)}


def _legacy_steps(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> frozenset[tuple[str, str]]:
    """Every (path, name) of the run that calls a class whose step keeps the legacy
    contract: the class itself, its re-exports and subclasses that define no step."""
    found = set()
    for path, summary in by_path.items():
        if path in facts.blocked:
            continue
        for name in summary.exports:
            where: tuple[str, str] | None = (path, name)
            for _ in range(_MAX_CHAIN):
                if where is None or where[0] in facts.blocked:
                    break
                here = by_path.get(where[0])
                if here is None:
                    break
                if where[1] in here.legacy_steps:
                    found.add((path, name))
                    break
                kind = here.exports.get(where[1])
                if f"{where[1]}.step" in here.defs or not _is_ref(kind):
                    break  # its own step, or not a name of the run to follow
                split = facts._split(str(kind)[len(REF) :], where[0])
                where = split if split is not None and "." not in split[1] else None
    return frozenset(found)


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
        if kind.startswith(NEW):
            return self.facts._class_kind(kind, caller)
        qualname, _, param = kind[len(PARAM) :].rpartition(":")
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


def _nearest_root(paths: tuple[str, ...], depth: int, importer: str) -> str | None:
    """Of the files a dotted name of ``depth`` parts may name, the one whose import root (the
    folder the name is taken from) is the nearest folder above ``importer``: Python finds
    ``import utils`` from the script's folder or a folder above it (the working directory),
    not from a sibling project's package. None when no root is above it or two are as near."""
    above = {str(p) for p in Path(importer).parents}
    roots: dict[str, list[str]] = {}
    for path in paths:
        folder = Path(path).parent if Path(path).name == "__init__.py" else Path(path).with_suffix("")
        for _ in range(depth):
            folder = folder.parent
        if str(folder) in above:
            roots.setdefault(str(folder), []).append(path)
    if not roots:
        return None
    nearest = roots[max(roots, key=len)]
    return nearest[0] if len(nearest) == 1 else None


def _is_ref(kind: object) -> bool:
    """A re-export (``ref:<module>.<name>``), not a resolved kind: ``EnvKind`` is a ``str``
    enum, so ``isinstance(kind, str)`` alone does not tell them apart."""
    return isinstance(kind, str) and not isinstance(kind, EnvKind) and kind.startswith(REF)


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

    def call_kind(self, qualified: str) -> EnvKind | None:
        """What calling an imported name of the run gives (``from hunt import HuntEnv``:
        a PettingZoo parallel env; ``pkg.make``: a Gym env). ``EnvKind.UNKNOWN`` for a name
        a module of the run binds but cannot classify; None when the run does not define it."""
        split = self.facts._split(qualified, self.path)
        if split is None:
            return None
        path, name = split
        if "." in name:
            return None
        found = self.facts.call_kinds.get((path, name))
        return found if found is not None else EnvKind.UNKNOWN

    def returns_made(self, qualified: str) -> bool:
        """An imported def of the run that returns ``make(...)`` results (``utils.make_env``):
        a wrapper stack, whatever its caller does with it."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.made

    def makes_bare_env(self, qualified: str) -> bool:
        """An imported Gym env class of the run that is no wrapper (``TakeoffAviary``): its
        instance is the env itself, whose attributes need no forwarding."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.bare_env_classes
    def star_call_kind(self, name: str, stars: tuple[str, ...]) -> EnvKind | None:
        """What calling ``name`` gives where this file binds it only through star imports
        (``stars``: ``from utils.wrappers import *`` gives ``"utils.wrappers"``) of modules of
        the run; None when none of them binds it."""
        for path in self._star_paths(stars):
            found = self.facts.call_kinds.get((path, name))
            if found is not None:
                return found
        return None

    def star_wrapper_class(self, name: str, stars: tuple[str, ...]) -> bool:
        """``name``, bound in this file only by star imports, is a Gym wrapper class of the
        run module that defines it."""
        return any(name in self.facts.wrapper_classes.get(path, ()) for path in self._star_paths(stars))

    def _star_paths(self, stars: tuple[str, ...]) -> list[str]:
        found = []
        for module in stars:
            level = len(module) - len(module.lstrip("."))
            path = self.facts._module_path(module.lstrip(".").split(".") if module.strip(".") else [], level, self.path)
            if path and path != self.path:
                found.append(path)
        return found

    def library_alias(self, qualified: str) -> str | None:
        """The library callable an imported name of the run is bound to (``pkg.make`` ->
        ``gym.make``), or None."""
        split = self.facts._split(qualified, self.path)
        return None if split is None else self.facts.aliases.get(split)

    def imports_multi_agent(self, qualified_names: Iterable[str]) -> bool:
        """One of these imported names is a PettingZoo env class or factory of the run."""
        return any(self.call_kind(q) in (EnvKind.PZ_AEC, EnvKind.PZ_PARALLEL) for q in qualified_names)

    def bootstrap_masks(self, qualified: str) -> tuple[tuple[str, ...], frozenset[tuple[str, str]]] | None:
        """For a def or method of another module of the run (``agents.Agent.learn``): its
        parameters and which of them mask bootstrapping from which (``facts/bootstrap.py``);
        None when the run does not define it."""
        resolved = self.facts._resolve(qualified, self.path)
        if resolved is not None:
            return self.facts.bootstrap_masks.get(resolved, ((), frozenset()))
        parts = qualified.split(".")  # a module with no Gym code (absolute imports only)
        for cut in range(len(parts) - 1, 0, -1):
            paths = self.facts.mask_modules.get(".".join(parts[:cut]), ())
            path = _nearest_root(paths, cut, self.path) if paths else None
            if path:
                return self.facts.bootstrap_masks.get((path, ".".join(parts[cut:])))
        return None

    def defines(self, qualified: str) -> bool:
        """The name comes from a module of the run (its own code, not a library's)."""
        return self.facts._split(qualified, self.path) is not None
    def has_module(self, dotted: str) -> bool:
        """A module of the run may be imported as ``dotted`` (``gym_minigrid`` in the
        gym-minigrid repository itself)."""
        return dotted in self.facts.modules

    def plugin_calls(self) -> tuple[tuple[str, str | None], ...]:
        """The register functions of ``gym.envs`` entry points this module must call on
        import, each with the namespace gym registered its ids in (None: the root)."""
        return self.facts.plugin_calls.get(self.path, ())

    def imported_packages(self) -> frozenset[str]:
        """The top-level packages this module imports, and the run's modules it imports or that
        import it (``multiagent`` imported by the script that builds this module's agents)."""
        return self.facts.nearby_packages.get(self.path, frozenset())

    def is_module(self, dotted: str) -> bool:
        """``dotted`` names a module or package of the run (``multiagent`` when the project has
        its own ``multiagent/`` package)."""
        return any(path == dotted or path.startswith(dotted + ".") for path in self.facts.modules)

    def built_elsewhere(self, classname: str) -> bool:
        """Another module of the run calls this file's class ``classname``."""
        return any(
            path == self.path and qualname in (classname, f"{classname}.__init__") for path, qualname, _ in self.facts.param_kinds
        )

    def subclassed_elsewhere(self, classname: str) -> bool:
        """Another module of the run derives a class from this file's ``classname``."""
        return (self.path, classname) in self.facts.overrides

    def overridden_elsewhere(self, classname: str, method: str) -> list[str]:
        """Subclasses in other modules of the run that override ``classname.method``."""
        return self.facts.overrides.get((self.path, classname), {}).get(method, [])

    def done_overrides(self, classname: str, method: str) -> list[DoneCause]:
        """Why what ``method`` returns is True in each override of it by subclasses in
        other modules of the run, at any depth (``Base`` <- ``Single`` <- ``Hover``); each
        limit names the module it is in."""
        found: list[DoneCause] = []
        seen: set[tuple[str, str]] = set()
        todo = list(self.facts.subclasses_of.get((self.path, classname), ()))
        while todo:
            sub = todo.pop(0)
            if sub in seen:
                continue
            seen.add(sub)
            cause = self.facts.done_methods.get(sub, {}).get(method)
            if cause is None and method in self.facts.subclass_methods.get(sub, ()):
                cause = DoneCause(Cause.UNKNOWN)  # an override that takes arguments, or returns nothing
            if cause is not None:
                where = os.path.basename(sub[0])
                found.append(DoneCause(cause.cause, tuple(Limit(limit.line, limit.text, where, limit.by_counter) for limit in cause.limits)))
            todo += self.facts.subclasses_of.get(sub, ())
        return found
    def registered_without_render_mode(self, env_id: str | None) -> str | None:
        """The class of the run that ``gymnasium.make(env_id)`` builds (any registered one
        when ``env_id`` is None: not a literal) if its constructor takes no ``render_mode``."""
        ids = self.facts.no_render_mode_ids
        if env_id is not None:
            return ids.get(env_id)
        return next(iter(sorted(ids.values())), None)

    def takes_render_mode(self, qualified: str) -> bool:
        """An imported class of the run whose constructor takes ``render_mode`` once migrated
        (its own, or threaded down from a base: ``_thread_render_mode``)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split[1] in self.facts.render_mode_classes.get(split[0], ())

    def keeps_legacy_step(self, qualified: str) -> bool:
        """An imported name of the run makes instances whose step keeps the four-field
        contract (the run does not migrate that step): their callers keep it too."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.legacy_steps

    def is_spec_list(self, qualified: str) -> bool:
        """An imported name of the run is bound to a list of the registry's EnvSpecs."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split[1] in self.facts.spec_lists.get(split[0], ())

    def pz_wrapper(self, qualified: str) -> tuple[str, frozenset[str]] | None:
        """For an imported name of the run that is a PettingZoo wrapper class (or an alias of
        PettingZoo's wrapper bases): ("aec" | "parallel", the methods the run's classes on the
        way define); None otherwise. References are followed a few modules deep."""
        split = self.facts._split(qualified, self.path)
        methods: set[str] = set()
        for _ in range(_MAX_CHAIN):
            if split is None:
                return None
            path, name = split
            entry = self.facts.pz_wrappers.get(path, {}).get(name)
            if entry is None:
                return None
            api, defined = entry
            methods.update(defined)
            if not api.startswith(REF):
                return api, frozenset(methods)
            split = self.facts._split(api[len(REF) :], path)
        return None

    def is_wrapper_class(self, qualified: str) -> bool:
        """An imported name of the run is a Gym wrapper class (``from pkg.wrappers import X``)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split[1] in self.facts.wrapper_classes.get(split[0], ())
    def non_space_env(self, module: str, name: str) -> tuple[str, str, str] | None:
        """For ``module:name`` as an ``entry_point`` spells it, a class of the run whose
        spaces are not Spaces: (attribute, space class, what that class derives from)."""
        path = self.facts.modules.get(module)
        return self.facts.non_space_envs.get((path, name)) if path else None

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
