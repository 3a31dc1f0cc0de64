"""One module's summary for the facts across the run (``facts/project.py`` joins it; the
record is ``facts/module_summary.py``): its defs, its env classes, and the ``EnvKind`` of
each argument it passes into other modules.

Pure: text in, ``ModuleSummary`` out. Reading the files of a run, and mapping this over
them on the worker pool, is the runner's.
"""

from __future__ import annotations

import ast
import os
import re
from collections.abc import Mapping
from dataclasses import replace

from gymmigrate.facts import names as N
from gymmigrate.facts import pz_wrappers
from gymmigrate.facts.bootstrap import next_state_masks
from gymmigrate.facts.creation import CreationFinder, passes_mode, render_kept_classes
from gymmigrate.facts.decisions import Action, decide
from gymmigrate.facts.done_uses import top_level_records
from gymmigrate.facts.env_classes import (
    EnvClasses,
    is_super_method_call,
    mode_can_stay_optional,
)
from gymmigrate.facts.env_specs import module_spec_lists
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.limits import Cause, DoneCause, DoneTracer
from gymmigrate.facts.module import (
    FUNCTIONS,
    ModuleFacts,
    call_argument,
    own_returns,
    string_value,
)
from gymmigrate.facts.module_summary import (
    GUARD_KINDS,
    NEW,
    OWN,
    PARAM,
    REF,
    UNRESOLVED,
    CallSummary,
    Kind,
    ModuleSummary,
    Signature,
)
from gymmigrate.facts.profile import FileProfile
from gymmigrate.facts.receiver_classes import (
    duck_wrapper_param,
    renders_nothing,
    wrapped_env_renders,
)
from gymmigrate.facts.receivers import Receivers
from gymmigrate.source_text import first_statement_line
from gymmigrate.suppressions import skips_file


def summarize(path: str, text: str) -> ModuleSummary | None:
    """The summary of one module's text (already screened by its reader), or None when it
    does not parse."""
    try:
        tree = ast.parse(text)
        facts = ModuleFacts(tree, text)
        summary = _Summarizer(facts, Receivers(facts), os.path.realpath(path)).summary()
        return replace(summary, skips_file=True) if skips_file(text, first_statement_line(tree)) else summary
    except Exception:  # noqa: BLE001  (the file's own run reports why; it just adds no facts)
        return None


def summarize_masks(path: str, text: str) -> ModuleSummary | None:
    """The summary of a module with no Gym code: only the defs that mask bootstrapping
    with a flag parameter (an agent's ``learn``, a memory's ``store``), for the callers of
    the run (``facts/bootstrap.py``), and its record classes (a memory's ``Transition``).
    None when it has neither or does not parse."""
    try:
        tree = ast.parse(text)
    except (SyntaxError, ValueError):
        return None
    # Only the module's defs are read: no ModuleFacts (its indexes cost more than the parse).
    functions = {s.name: s for s in tree.body if isinstance(s, FUNCTIONS)}
    classes = {s.name: s for s in tree.body if isinstance(s, ast.ClassDef)}
    masks = _masks_of(functions, classes)
    records = top_level_records(tree)
    if not masks and not records:
        return None
    defs = {name: _signature(_named(functions, classes, name), is_method="." in name) for name in masks}
    return ModuleSummary(
        os.path.realpath(path), defs, frozenset(), frozenset(), (), bootstrap_masks=masks, masks_only=True, record_classes=records
    )


def _named(
    functions: Mapping[str, ast.FunctionDef | ast.AsyncFunctionDef], classes: Mapping[str, ast.ClassDef], qualname: str
) -> ast.FunctionDef | ast.AsyncFunctionDef:
    if "." not in qualname:
        return functions[qualname]
    owner, name = qualname.split(".", 1)
    return next(s for s in classes[owner].body if isinstance(s, FUNCTIONS) and s.name == name)


class _Summarizer:
    def __init__(self, facts: ModuleFacts, receivers: Receivers, path: str) -> None:
        self.render_makers: set[str] = set()  # what made the receivers of render(mode) calls (run names)
        self.facts = facts
        self.receivers = receivers
        self.path = path

    def summary(self) -> ModuleSummary:
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
        calls = [c for calls in self.facts.calls_by_name.values() for call in calls for c in self._name_calls(call)]
        calls += [c for call in (c for calls in self.facts.attribute_calls.values() for c in calls) for c in self._method_calls(call)]
        return ModuleSummary(
            self.path,
            defs,
            frozenset(env_classes),
            frozenset(render_mode),
            tuple(calls),
            untraced_seed_call=self._has_untraced_call("seed"),
            untraced_render_call=self._has_untraced_call("render"),
            render_makers=frozenset(self.render_makers),  # filled by the line above
            imported=tuple(sorted(set(self.facts.imports.values()))),
            exports=self._exports(env_classes),
            aliases=self._aliases(),
            star_imports=tuple(
                "." * s.level + (s.module or "") for s in self.facts.tree.body if isinstance(s, ast.ImportFrom) and any(a.name == "*" for a in s.names)
            ),
            subclasses=_subclasses(self.facts),
            wrapper_classes=frozenset(name for name, classdef in self.facts.classes.items() if self.receivers.is_gym_wrapper_class(classdef)),
            wrapping_helpers=frozenset(name for name, function in self.facts.functions.items() if self.receivers.wraps_argument(function)),
            pz_wrappers=pz_wrappers.summarize(self.facts),
            plain_classes=plain_classes(self.facts),
            space_calls=self._space_calls(),
            spec_lists=module_spec_lists(self.facts),
            made_factories=made_factories(self.facts, self.receivers),
            classes=frozenset(self.facts.classes),
            bootstrap_masks=_bootstrap_masks(self.facts),
            record_classes=top_level_records(self.facts.tree),
            done_methods=_done_methods(self.facts),
            render_mode_heirs=_render_mode_heirs(self.facts, self.receivers),
            registrations=_registrations(self.facts),
            held_params=held_params(self.facts, self.receivers),
            handed_on=handed_on(self.facts),
            silent_renders=frozenset(name for name, classdef in self.facts.classes.items() if renders_nothing(self.facts, classdef)),
            mode_renders=_mode_renders(self.facts),
            opaque_registrations=_opaque_registrations(self.facts),
            fixed_mode_renders=frozenset(
                name
                for name, classdef in self.facts.classes.items()
                for method in classdef.body
                if isinstance(method, FUNCTIONS)
                and method.name == "render"
                and "mode" in [a.arg for a in method.args.args]
                and not mode_can_stay_optional(method)
            ),
            rendering_wrappers=frozenset(
                name
                for name, classdef in self.facts.classes.items()
                if self.receivers.is_gym_wrapper_class(classdef) and wrapped_env_renders(self.facts, classdef)
            ),
            legacy_steps=frozenset(
                name for name, classdef in self.facts.classes.items() if name in env_classes and self.receivers.class_keeps_legacy_step(classdef)
            ),
        )

    def _space_calls(self) -> dict[str, tuple[tuple[str, str], ...]]:
        return space_calls(self.facts, self.receivers)

    def _exports(self, env_classes: set[str]) -> dict[str, Kind]:
        """Every top-level name the module binds with what calling it gives (see
        ``ModuleSummary.exports``)."""
        exports: dict[str, Kind] = {}
        for name, bindings in self.facts.module_scope.bindings.items():
            kinds = {self._export(name, binding, env_classes) for binding in bindings}
            kinds.discard(None)
            if len(kinds) == 1:
                exports[name] = kinds.pop()  # type: ignore[assignment]
            elif kinds:
                exports[name] = EnvKind.UNKNOWN
        return exports

    def _export(self, name: str, binding: ast.AST, env_classes: set[str]) -> Kind | None:
        if isinstance(binding, ast.alias):
            return self._reference(self.facts.imports[binding])
        if isinstance(binding, ast.ClassDef):
            kind = self.receivers.class_kind(binding)
            if name in env_classes and kind is not EnvKind.OWN_API:
                kind = EnvKind.GYM_ENV
            if kind is EnvKind.NOT_ENV and duck_wrapper_param(binding) is not None:
                # A duck wrapper its own module cannot prove (other modules build it): what
                # its instances are is decided where they are made, never "no env".
                return EnvKind.UNKNOWN
            if kind is EnvKind.UNKNOWN:
                # ``class Hunter(HuntEnv)`` with ``HuntEnv`` from another module of the run.
                # With several such bases (``class Flock(BaseAviary, MultiAgentEnv)``), the
                # first one's, as ``class_kind`` takes the first base that says anything.
                for base in binding.bases:
                    run_bases = [q for q in self.facts.qualified_names(base) if not _is_library(q)]
                    if len(run_bases) == 1:
                        return REF + run_bases[0]
                    if run_bases:
                        break
            return kind
        if isinstance(binding, FUNCTIONS):
            kind = self.receivers.returns_kind(binding)
            if kind is EnvKind.UNKNOWN:
                # ``def make_benchmark(...): return NASimEnv(scenario, **kwargs)`` with the class
                # imported from another module of the run: what calling that name gives
                made = self._returned_run_call(binding)
                if made is not None:
                    return REF + made
            return kind
        if isinstance(binding, ast.Name):
            parent = self.facts.parent(binding)
            if isinstance(parent, ast.Assign) and len(parent.targets) == 1 and parent.targets[0] is binding:
                value = parent.value
                if isinstance(value, (ast.Name, ast.Attribute)):
                    qualified = self.facts.qualified_names(value)
                    if len(qualified) == 1:
                        return self._reference(qualified.pop())  # ``make = gym.make``
                    return self.receivers.returned_kind(value)
                if isinstance(value, ast.Call):
                    # ``parallel_env = parallel_wrapper_fn(env)``: a factory made by a factory.
                    if any(q.endswith(".parallel_wrapper_fn") for q in self.facts.qualified_names(value.func)):
                        return EnvKind.PZ_PARALLEL
                    return self.receivers.returned_kind(value)
        return EnvKind.UNKNOWN

    def _returned_run_call(self, function: ast.FunctionDef | ast.AsyncFunctionDef) -> str | None:
        """The one imported name every return of ``function`` calls (``return Env(...)``),
        when it is no library's; else None."""
        found: set[str] = set()
        for ret in own_returns(function):
            value = ret.value
            if not (isinstance(value, ast.Call) and isinstance(value.func, (ast.Name, ast.Attribute))):
                return None
            qualified = self.facts.qualified_names(value.func)
            if len(qualified) != 1:
                return None
            name = next(iter(qualified))
            if _is_library(name) or "." not in name:
                return None  # a library's, or a name of this module (``returns_kind`` judged it)
            found.add(name)
        return found.pop() if len(found) == 1 else None

    def _aliases(self) -> dict[str, str]:
        """Top-level names bound to a Gym callable: ``make = gym.make``, ``from gym import make``."""
        found: dict[str, str] = {}
        for name, bindings in self.facts.module_scope.bindings.items():
            if len(bindings) != 1:
                continue
            binding = bindings[0]
            if isinstance(binding, ast.alias):
                qualified = {self.facts.imports[binding]}
            elif isinstance(binding, ast.Name) and isinstance(assign := self.facts.parent(binding), ast.Assign) and isinstance(assign.value, (ast.Name, ast.Attribute)):
                qualified = self.facts.qualified_names(assign.value)
            else:
                continue
            if len(qualified) == 1 and N.strip_gym_prefix(next(iter(qualified))) is not None:
                found[name] = qualified.pop()
        return found

    def _reference(self, qualified: str) -> Kind:
        if not _is_library(qualified):
            return REF + qualified
        kind = self.receivers.kind_from_qualified(qualified, ast.Call(func=ast.Name(id="_"), args=[], keywords=[]))
        return kind if kind is not None else EnvKind.UNKNOWN

    def _has_untraced_call(self, method: str) -> bool:
        """``x.seed(...)`` / ``x.render(mode)`` on a receiver this module cannot trace."""
        for call in self.facts.attribute_calls.get(method, ()):
            receiver = call.func.value  # type: ignore[attr-defined]
            if isinstance(receiver, ast.Name) and receiver.id == "self":
                continue  # a class's own call: decided with that class
            if isinstance(receiver, ast.Call) and isinstance(receiver.func, ast.Name) and receiver.func.id == "super":
                continue
            if method == "render" and not passes_mode(call, self.facts):
                continue  # a bare render() (the Gymnasium call), or a render method forwarding
            kind = self.receivers.kind_of(receiver)
            if method == "render" and kind is EnvKind.GYM_ENV and _keeps_mode(call):
                return True  # a Gym env the rendering rules leave passing its mode: any class's render
            if method == "render" and kind in (EnvKind.GYM_ENV, EnvKind.UNKNOWN):
                made_by = self._instance_class(receiver)
                if made_by is not None and not _is_library(made_by) and not self._made_here(receiver):
                    # ``env = pkg.make_board()``: the join tells a class of the run (its
                    # construction takes the mode, GM401) from a def, where no mode can move
                    self.render_makers.add(made_by)
                    continue
            if method == "seed" and kind is EnvKind.GYM_ENV and self._in_own_seed_method(call):
                # ``def seed(self, s): for env in self.envs: env.seed(s)`` of a plain class: the
                # seed rules leave it (or send it to ``env.unwrapped.seed``), so the env classes
                # it may build keep their seed()
                return True
            if kind is not EnvKind.UNKNOWN:
                continue
            if method == "seed" and self._seed_call_rewritten_here(call):
                continue  # GM203 makes it reset(seed=...) in this run: no seed() caller is left
            made_by = self._instance_class(receiver)
            if made_by is not None and not _is_library(made_by):
                continue  # an instance of a class it imports: the run knows that class
            return True
        return False

    def _made_here(self, receiver: ast.AST) -> bool:
        """``receiver`` goes back to a ``make`` (or a construction of an env class of this
        module): where the rendering rules move a literal mode to (GM401)."""
        facts, receivers = self.facts, self.receivers

        def is_creation(call: ast.Call) -> bool:
            return receivers.local_class(call.func) is not None or any(
                N.strip_gym_prefix(q) in N.GYM_ENV_FACTORIES for q in facts.qualified_names(call.func)
            )

        finder = facts.memo(("summary-make-finder", 0), lambda: CreationFinder(facts, receivers, is_creation))
        return finder.find(receiver).found

    def _in_own_seed_method(self, call: ast.Call) -> bool:
        """``call`` sits in a ``seed()`` of a plain class (or a def): the project's own, not
        the Gym hook of an env or wrapper class."""
        function = self.facts.enclosing_function(call)
        if function is None or function.name != "seed":
            return False
        classdef = self.facts.enclosing_class(function)
        return classdef is None or not (
            self.receivers.class_kind(classdef) is EnvKind.GYM_ENV or self.receivers.is_gym_wrapper_class(classdef)
        )

    def _seed_call_rewritten_here(self, call: ast.Call) -> bool:
        """``env.seed(s)`` as a statement, with one seed, on an untraced receiver that GM203
        rewrites anyway (an env-like name in a file that uses only Gym). Counting it as a
        caller kept a class's seed() in one run and removed it in the next."""
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
        if target.startswith(UNRESOLVED):
            kinds = {*summary.args, *(k for _, k in summary.keywords)}
            return summary if kinds & GUARD_KINDS else None
        return summary

    def _name_calls(self, call: ast.Call) -> list[CallSummary]:
        """``Agent(env)``; with ``Agent`` imported from several modules of the run
        (``from agents.dqn import Agent`` in one branch, ``from agents.a2c import Agent`` in
        another), one call of each: every binding may be the one called."""
        found = self._call(call)
        if found is not None:
            return [found]
        if self._own_target(call.func) is not None:
            return []
        targets = sorted({q for q in self.facts.qualified_names(call.func) if not _is_library(q)})
        if len(targets) < 2 or len(targets) != len(self.facts.qualified_names(call.func)):
            return []  # a library binding among them: not all of the run's
        return [self._arguments(call, target) for target in targets]

    def _method_calls(self, call: ast.Call) -> list[CallSummary]:
        """``x.fit(env)``; with ``x`` bound to instances of several classes of the run
        (``algo = DDQN(...)`` in one branch, ``algo = A2C(...)`` in another), one call of
        each class's method."""
        found = self._call(call)
        if found is not None or not isinstance(call.func, ast.Attribute) or not isinstance(call.func.value, ast.Name):
            return [found] if found is not None else []
        made = self._made_by_run_call(call.func.value)
        if made is None or "|" not in made:
            return []
        return [self._arguments(call, f"{cls}.{call.func.attr}") for cls in made.split("|")]

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
        if isinstance(func, ast.Name):
            return self._instance_call_target(func)
        if not isinstance(func, ast.Attribute):
            return None
        owner = func.value
        if isinstance(owner, ast.Name) and self.receivers.is_self(owner):
            return None  # a method the class does not define (inherited)
        cls = self._instance_class(owner)
        if cls is not None:
            return f"{cls}.{func.attr}" if not _is_library(cls) else None
        return UNRESOLVED + func.attr

    def _instance_call_target(self, func: ast.Name) -> str | None:
        """``Evaluator.__call__`` (qualified through the imports) for ``evaluate(env)``,
        where ``evaluate`` holds an instance of a class of the run every way it is bound
        (``evaluate = Evaluator(3)``, or passed so to the def whose parameter it is)."""
        values = self.receivers.called_instances(func)
        classes = set()
        for value in values:
            if not isinstance(value, ast.Call):
                return None
            local = self.receivers.local_class(value.func)
            if local is not None:
                if self.facts.classes.get(local.name) is not local:
                    return None
                classes.add(OWN + local.name)
                continue
            found = [q for q in self.facts.qualified_names(value.func) if not _is_library(q)]
            if len(found) != 1 or "." not in found[0]:
                return None
            classes.add(found[0])
        if len(classes) != 1:
            return None
        return f"{classes.pop()}.__call__"

    def _own_target(self, func: ast.expr) -> str | None:
        function = self.receivers.local_function(func)
        if function is not None:
            return OWN + function.name
        classdef = self.receivers.local_class(func)
        if classdef is not None:
            return OWN + f"{classdef.name}.__init__"
        method = self.receivers.own_method(func)
        if method is not None:
            owner = self.facts.parent(method)
            # own_method takes the def from the class body, so owner is always that ClassDef
            if isinstance(owner, ast.ClassDef) and self.facts.parent(owner) is self.facts.tree:
                return OWN + f"{owner.name}.{method.name}"
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
            return self.facts.memo(("instance-class", id(bindings)), lambda: self._class_of_bindings(bindings))
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
        ids = [(str(i), text) for i, a in enumerate(call.args) if (text := self._env_id(a)) is not None]
        ids += [(k.arg, text) for k in call.keywords if k.arg is not None and (text := self._env_id(k.value)) is not None]
        return CallSummary(target, tuple(args), tuple(keywords), open_ended, tuple(ids), getattr(call, "lineno", 0))

    def _env_id(self, argument: ast.expr) -> str | None:
        """An env id the argument certainly is: a literal ``"Name-v4"``, or a module-level
        name bound once to one (``ENV = "PongNoFrameskip-v4"``)."""
        if isinstance(argument, ast.Name):
            bindings = self.facts.module_scope.bindings.get(argument.id, [])
            if self.facts.bindings_of(argument) != bindings or len(bindings) != 1:
                return None
            assign = self.facts.parent(bindings[0])
            if not (isinstance(assign, ast.Assign) and assign.targets == [bindings[0]]):
                return None
            argument = assign.value
        text = string_value(argument) if isinstance(argument, ast.Constant) else None
        return text if text is not None and _ENV_ID.fullmatch(text) else None

    def _kind(self, argument: ast.expr) -> Kind:
        """The argument's kind; ``new:agent.GridEnv`` for an instance of a class this
        module imports, which the join resolves against the env classes of the run."""
        kind = self.receivers.kind_of(argument)
        if kind is EnvKind.NOT_ENV and self._env_like_instance(argument, 0):
            # The project's own reset/step object (``Holder(Board())``): not NOT_ENV, which
            # a Gym env passed by another caller outweighs in the join; the def is asked about.
            return EnvKind.OWN_API
        if kind is EnvKind.UNKNOWN and isinstance(argument, ast.Call):
            found = [q for q in self.facts.qualified_names(argument.func) if not _is_library(q)]
            if len(found) == 1:
                return NEW + found[0]
            own = self._own_factory(argument.func)
            if own is not None:
                return NEW + own  # ``Holder(create_env(name))``: what the run says ``create_env`` gives
        if kind is EnvKind.UNKNOWN and isinstance(argument, ast.Name):
            parameter = self._parameter_of_def(argument)
            if parameter is not None:
                return parameter
            made = self._made_by_run_call(argument) or self._made_by_passed_class(argument)
            if made is not None:
                return NEW + made  # ``env = pkg.make_benchmark(...)``; ``run(env)``
        return kind

    def _made_by_passed_class(self, name: ast.Name) -> str | None:
        """``env_instance = env_class(config)`` in a top-level def that this module's every
        call passes classes imported from the run for ``env_class`` (``test(env_class=
        TradeEnv)``): those classes' names, joined by ``|``, for the join to resolve."""
        bindings = self.facts.bindings_of(name)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.Name):
            return None
        statement = self.facts.parent(bindings[0])
        if not (isinstance(statement, ast.Assign) and statement.targets == [bindings[0]] and isinstance(statement.value, ast.Call)):
            return None
        func = statement.value.func
        params = self.facts.bindings_of(func) if isinstance(func, ast.Name) else []
        if len(params) != 1 or not isinstance(params[0], ast.arg):
            return None
        param = params[0]
        function = self.facts.parent(self.facts.parent(param))
        if not isinstance(function, FUNCTIONS) or self.facts.functions.get(function.name) is not function:
            return None  # a top-level def: its call sites are this module's own
        if function.args.vararg is not None or function.args.kwarg is not None:
            return None
        positional = [*function.args.posonlyargs, *function.args.args]
        position = next((i for i, p in enumerate(positional) if p is param), None)
        found: set[str] = set()
        calls = self.receivers.call_sites(function, None)
        for call in calls:
            argument = call_argument(call, position, param.arg)
            if argument is None:
                return None
            qualified = [q for q in self.facts.qualified_names(argument) if not _is_library(q)]
            if len(qualified) != 1 or "." not in qualified[0]:
                return None
            found.add(qualified[0])
        return "|".join(sorted(found)) if found else None

    def _made_by_run_call(self, name: ast.Name) -> str | None:
        """The names of the run (imported, no library's) the bindings of ``name`` call,
        joined by ``|``: ``env = nasim.make_benchmark(...)``, or ``env = AtariEnvironment(args)``
        in one branch and ``env = Environment(gym.make(id))`` in the other; None when a
        binding calls anything else."""
        bindings = self.facts.bindings_of(name)
        found: set[str] = set()
        for binding in bindings:
            statement = self.facts.parent(binding)
            if not (isinstance(binding, ast.Name) and isinstance(statement, ast.Assign) and statement.targets == [binding]):
                return None
            value = statement.value
            if not isinstance(value, ast.Call):
                return None
            qualified = [q for q in self.facts.qualified_names(value.func) if not _is_library(q)]
            if len(qualified) != 1 or "." not in qualified[0]:
                own = self._own_factory(value.func)
                if own is None:
                    return None
                qualified = [own]
            found.add(qualified[0])
        return "|".join(sorted(found)) if found else None

    def _env_like_instance(self, value: ast.expr, depth: int) -> bool:
        """An instance of a plain class of this module with a reset or step of its own:
        ``Board()``, a name bound to one, or a def of this module returning one."""
        if depth > 4:
            return False
        if isinstance(value, ast.Name):
            bindings = self.facts.bindings_of(value)
            statements = [self.facts.parent(b) for b in bindings if isinstance(b, ast.Name)]
            values = [s.value for s in statements if isinstance(s, ast.Assign)]
            return bool(values) and len(values) == len(bindings) and any(self._env_like_instance(v, depth + 1) for v in values)
        if not isinstance(value, ast.Call):
            return False
        classdef = self.receivers.local_class(value.func)
        if classdef is not None:
            return self.receivers.class_kind(classdef) is EnvKind.NOT_ENV and any(
                isinstance(s, FUNCTIONS) and s.name in ("reset", "step") for s in classdef.body
            )
        function = self.receivers.local_function(value.func)
        return function is not None and any(
            r.value is not None and self._env_like_instance(r.value, depth + 1) for r in own_returns(function)
        )

    def _own_factory(self, func: ast.expr) -> str | None:
        """``@create_env`` for a top-level def of this module whose returns its own module
        cannot classify (``return wrappers.wrap(wrappers.make_atari(name))``, calls of
        another module of the run): the join knows what calling it gives (``call_kinds``)."""
        function = self.receivers.local_function(func)
        if function is None or self.facts.functions.get(function.name) is not function:
            return None
        return OWN + function.name

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
        return f"{PARAM}{qualname}:{name.id}"


# ``PongNoFrameskip-v4``, ``ALE/Pong-v5``, ``mod:Name-v0``: what the summaries keep of string arguments.
_ENV_ID = re.compile(r"(?:[\w.]+:)?(?:\w+/)?[\w.-]+-v\d+")


def _signature(function: ast.FunctionDef | ast.AsyncFunctionDef, is_method: bool) -> Signature:
    args = function.args
    positional = [*args.posonlyargs, *args.args]
    with_default = positional[len(positional) - len(args.defaults) :]
    defaults = {a.arg for a in with_default}
    defaults |= {a.arg for a, d in zip(args.kwonlyargs, args.kw_defaults) if d is not None}
    params = tuple(a.arg for a in (*positional, *args.kwonlyargs))
    return Signature(params, frozenset(defaults), is_method)


def _bootstrap_masks(facts: ModuleFacts) -> dict[str, frozenset[tuple[str, str]]]:
    """Top-level defs and methods of top-level classes whose flag parameter masks
    bootstrapping from a next-state parameter (``facts/bootstrap.py``)."""
    return _masks_of(facts.functions, facts.classes)


def _masks_of(
    functions: Mapping[str, ast.FunctionDef | ast.AsyncFunctionDef], classes: Mapping[str, ast.ClassDef]
) -> dict[str, frozenset[tuple[str, str]]]:
    found: dict[str, frozenset[tuple[str, str]]] = {}
    defs = list(functions.items())
    defs += [
        (f"{name}.{statement.name}", statement)
        for name, classdef in classes.items()
        for statement in classdef.body
        if isinstance(statement, FUNCTIONS)
    ]
    for qualname, function in defs:
        masks = next_state_masks(function)
        if masks:
            found[qualname] = masks
    return found


def _is_library(qualified: str) -> bool:
    """Gym, Stable-Baselines, PettingZoo, numpy...: never a module of the run."""
    return N.is_library(qualified)




def made_factories(facts: ModuleFacts, receivers: Receivers | None = None) -> frozenset[str]:
    """Top-level defs every return of which is a ``make(...)`` result, maybe wrapped in Gym
    wrappers and kept in a local name first (``env = gym.make(key); env.seed(s); return env``);
    with ``receivers``, the module's own Gym wrapper classes around a made env count as Gym
    wrappers too (``env = FireReset(env)``)."""
    found = set()
    for name, function in facts.functions.items():
        values = [r.value for r in own_returns(function)]
        if values and all(v is not None and _made(facts, v, function, 0, receivers) for v in values):
            found.add(name)
    return frozenset(found)


def _made(facts: ModuleFacts, value: ast.expr, function: ast.AST, depth: int, receivers: Receivers | None = None) -> bool:
    if depth > 8:
        return False
    if isinstance(value, ast.Call):
        for q in facts.qualified_names(value.func):
            rest = N.strip_gym_prefix(q)
            if rest in N.GYM_ENV_FACTORIES:
                return True
        if _is_gym_wrapper(facts, value.func, receivers) and value.args:
            return _made(facts, value.args[0], function, depth + 1, receivers)  # a wrapper around a made env
        return False
    if not isinstance(value, ast.Name):
        return False
    bindings = facts.bindings_of(value)
    if not bindings:
        return False
    for binding in bindings:
        assign = facts.parent(binding) if isinstance(binding, ast.Name) else None
        if not (isinstance(assign, ast.Assign) and assign.targets == [binding]) or facts.enclosing_function(assign) is not function:
            return False
        wrapped = assign.value.args[0] if isinstance(assign.value, ast.Call) and assign.value.args else None
        if isinstance(wrapped, ast.Name) and wrapped.id == value.id and _is_gym_wrapper(facts, assign.value.func, receivers):  # type: ignore[attr-defined]
            continue  # ``env = TimeLimit(env)``: as made as the env's other values
        if not _made(facts, assign.value, function, depth + 1, receivers):
            return False
    return True


def _is_gym_wrapper(facts: ModuleFacts, func: ast.expr, receivers: Receivers | None = None) -> bool:
    if receivers is not None:
        local = receivers.local_class(func)
        if local is not None:
            return receivers.is_gym_wrapper_class(local)
    for q in facts.qualified_names(func):
        rest = N.strip_gym_prefix(q)
        if rest is not None and rest.startswith("wrappers.") and not rest.startswith("wrappers.vector."):
            return True
    return False


_SPACE_ATTRIBUTES = ("action_space", "observation_space")


def space_calls(facts: ModuleFacts, receivers: Receivers) -> dict[str, tuple[tuple[str, str], ...]]:
    """``self.action_space = C(...)`` / ``self.observation_space = C(...)`` in the methods
    of each top-level class: (attribute, ``C`` qualified, or ``@C`` for a class here)."""
    found: dict[str, tuple[tuple[str, str], ...]] = {}
    for name, classdef in facts.classes.items():
        stores = receivers.self_stores(classdef)
        calls = []
        for attribute in _SPACE_ATTRIBUTES:
            for value in stores.get(attribute, ()):
                if not isinstance(value, ast.Call):
                    continue
                local = receivers.local_class(value.func)
                if local is not None:
                    calls.append((attribute, OWN + local.name))
                    continue
                qualified = [q for q in facts.qualified_names(value.func) if not _is_library(q)]
                if len(qualified) == 1:
                    calls.append((attribute, qualified[0]))
        if calls:
            found[name] = tuple(calls)
    return found
_PLAIN_BASES = frozenset({"list", "tuple", "dict", "object"})


def plain_classes(facts: ModuleFacts) -> dict[str, str]:
    """Top-level classes that certainly are not Spaces: no base, or only builtin
    containers (``class MultiAgentActionSpace(list)``), with what they derive from."""
    found = {}
    for name, classdef in facts.classes.items():
        if classdef.keywords or classdef.decorator_list:
            continue  # a metaclass or a decorator may make it anything
        bases = []
        for base in classdef.bases:
            if not (isinstance(base, ast.Name) and base.id in _PLAIN_BASES and not facts.module_scope.bindings.get(base.id)):
                break
            bases.append(base.id)
        else:
            found[name] = ", ".join(bases) or "object"
    return found


def handed_on(facts: ModuleFacts) -> frozenset[str]:
    """``ModuleSummary.handed_on``: imported names of the run (``make_env``, ``wrappers.make_env``)
    read anywhere in the module other than as the callee of a call."""
    imported = {}
    for name, bindings in facts.module_scope.bindings.items():
        if len(bindings) == 1 and isinstance(bindings[0], ast.alias):
            qualified = facts.imports.get(bindings[0])
            if qualified is not None and not _is_library(qualified):
                imported[name] = qualified
    found = set()
    for scope in facts.scopes.values() if imported else ():
        for name in imported.keys() & scope.reads.keys():
            qualified = imported[name]
            for read in scope.reads[name]:
                node: ast.AST = read
                parent = facts.parent(read)
                shown = qualified
                if isinstance(parent, ast.Attribute) and parent.value is read:
                    node, shown = parent, f"{qualified}.{parent.attr}"
                    parent = facts.parent(parent)
                if not (isinstance(parent, ast.Call) and parent.func is node):
                    found.add(shown)
    return frozenset(found)


def held_params(facts: ModuleFacts, receivers: Receivers) -> dict[str, dict[str, str]]:
    """``ModuleSummary.held_params``: per top-level plain class, the attributes its methods
    store only from a parameter of its ``__init__`` that nothing rebinds."""
    found: dict[str, dict[str, str]] = {}
    for name, classdef in facts.classes.items():
        init = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "__init__"), None)
        if init is None or receivers.class_kind(classdef) is not EnvKind.NOT_ENV:
            continue
        params = {a.arg for a in (*init.args.posonlyargs, *init.args.args[1:], *init.args.kwonlyargs)}
        held = {}
        for attribute, values in receivers.self_stores(classdef).items():
            if len(values) != 1 or not isinstance(values[0], ast.Name) or values[0].id not in params:
                continue
            bindings = facts.bindings_of(values[0])
            if len(bindings) == 1 and isinstance(bindings[0], ast.arg) and facts.enclosing_function(values[0]) is init:
                held[attribute] = values[0].id
        if held:
            found[name] = held
    return found


def _registrations(facts: ModuleFacts) -> tuple[tuple[str | None, str], ...]:
    """``register(id=..., entry_point="pkg.mod:Class")`` calls: (the id if a literal, the entry point)."""
    found = []
    for call in (*facts.calls_by_name.get("register", ()), *facts.attribute_calls.get("register", ())):
        entry = call_argument(call, 1, "entry_point")
        text = string_value(entry) if entry is not None else None
        if text is None or ":" not in text:
            continue
        env_id = call_argument(call, 0, "id")
        found.append((string_value(env_id) if env_id is not None else None, text))
    return tuple(found)


def _render_mode_heirs(facts: ModuleFacts, receivers: Receivers) -> tuple[tuple[str, tuple[str, ...], bool], ...]:
    """Top-level classes with a base of the run (imported, or ``@Name`` of this module):
    (name, bases, whether its constructor hands ``render_mode`` on once its base takes it:
    no ``__init__`` of its own, ``**kwargs``, or one ``__init__`` call of a base that
    custom_env/render.py gives ``render_mode=render_mode``)."""
    found = []
    for name, classdef in facts.classes.items():
        bases = []
        for base in classdef.bases:
            local = receivers.local_class(base)
            if local is not None and local is not classdef:
                bases.append(OWN + local.name)
            else:
                bases.extend(q for q in facts.qualified_names(base) if not _is_library(q))
        if not bases:
            continue
        init = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "__init__"), None)
        if "gym" not in facts.text:
            passes_on = False  # the env-class rules never run here (EnvClassFamily.may_fire)
        elif init is None or init.args.kwarg is not None:
            passes_on = True
        else:
            calls = [n for n in ast.walk(init) if isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute) and n.func.attr == "__init__"]
            passes_on = len(calls) == 1 and all(k.arg is not None for k in calls[0].keywords)
        found.append((name, tuple(sorted(bases)), passes_on))
    return tuple(found)


def _subclasses(facts: ModuleFacts) -> tuple[tuple[str, tuple[str, ...], tuple[str, ...]], ...]:
    """Top-level classes with an imported base: (name, the bases' qualified names, the
    methods it defines). The join finds which methods of the run's classes are overridden
    in other modules (method contracts follow their class: rules/custom_env/hooks.py)."""
    found = []
    for name, classdef in facts.classes.items():
        bases = tuple(sorted(q for base in classdef.bases for q in facts.qualified_names(base) if not _is_library(q)))
        if bases:
            methods = tuple(s.name for s in classdef.body if isinstance(s, FUNCTIONS))
            found.append((name, bases, methods))
    return tuple(found)


def _opaque_registrations(facts: ModuleFacts) -> bool:
    """A Gym ``register(id=..., entry_point=...)`` call whose entry point is no literal
    (``entry_point=env["entry_point"]`` from a JSON file)."""
    for call in (*facts.calls_by_name.get("register", ()), *facts.attribute_calls.get("register", ())):
        if not any(q in ("gym.register", "gym.envs.register", "gym.envs.registration.register") for q in facts.qualified_names(call.func)):
            continue
        entry = call_argument(call, 1, "entry_point")
        if entry is not None and string_value(entry) is None and not isinstance(entry, (ast.Name, ast.Attribute)):
            return True
    return False


def _mode_renders(facts: ModuleFacts) -> dict[str, tuple[int, str]]:
    """Classes with an imported base, no render() of their own, that call
    ``self.render(mode)`` or ``super().render(mode)``: (line, call) of the first. The join
    tells the base's module, whose render() keeps ``mode`` for them (custom_env/render.py)."""
    found: dict[str, tuple[int, str]] = {}
    for name, classdef in facts.classes.items():
        if not any(not _is_library(q) for base in classdef.bases for q in facts.qualified_names(base)):
            continue
        if any(isinstance(s, FUNCTIONS) and s.name == "render" for s in classdef.body):
            continue  # its calls reach its own render(), decided with the class
        for node in ast.walk(classdef):
            if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "render"):
                continue
            receiver = node.func.value
            own = (isinstance(receiver, ast.Name) and receiver.id == "self") or is_super_method_call(node, "render")
            if own and facts.enclosing_class(node) is classdef and passes_mode(node, facts):
                found[name] = (node.lineno, facts.segment(node))
                break
    return found


def _done_methods(facts: ModuleFacts) -> dict[str, dict[str, DoneCause]]:
    """For each class with an imported base, why its self-only methods' values are True:
    a subclass's ``def _computeDone(self): return self.t > self.T`` tells its base class in
    another module that the done of its ``step`` is a step limit (facts/limits.py)."""
    found: dict[str, dict[str, DoneCause]] = {}
    for name, classdef in facts.classes.items():
        if not any(not _is_library(q) for base in classdef.bases for q in facts.qualified_names(base)):
            continue
        tracer = DoneTracer(facts, classdef)
        methods = {}
        for statement in classdef.body:
            if not isinstance(statement, FUNCTIONS) or len(statement.args.args) != 1 or statement.args.vararg or statement.args.kwonlyargs:
                continue
            if not any(r.value is not None for r in own_returns(statement)):
                continue
            try:
                methods[statement.name] = tracer.returns_cause(statement, 0)
            except RecursionError:  # a pathological nesting: the override counts as untraced
                methods[statement.name] = DoneCause(Cause.UNKNOWN)
        if methods:
            found[name] = methods
    return found


def _keeps_mode(call: ast.Call) -> bool:
    """A render call on a Gym env that the rendering rules report and leave passing its
    mode (GM401): a mode that is not a string literal, or other arguments beside it
    (``env.render(mode="rgb_array", tile_size=8)`` on an env class that takes them)."""
    mode = next((k.value for k in call.keywords if k.arg == "mode"), None)
    if mode is None and call.args:
        mode = call.args[0]
    others = len(call.args) + len(call.keywords) - 1
    return others > 0 or not (isinstance(mode, ast.Constant) and isinstance(mode.value, str))
