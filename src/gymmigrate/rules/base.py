"""The rule framework.

A *rule* is one catalog entry (``GM301``: its id, title, fix kind and summary). A
*family* (``RuleFamily``) implements a few related rules: it reads the file's facts
(``gymmigrate.facts``, built once from CPython's ``ast``), reports findings and records
edits in the file's ``Plan``. Every family decides on the same original module, in the
order of ``rules/__init__.py``'s ``PIPELINE``; the edits are applied afterwards in one LibCST traversal
(``gymmigrate.edits.apply``), so a single run reaches the fixed point.

Adding a rule family is adding a module under ``gymmigrate.rules`` that defines a
``RuleFamily`` subclass; it registers itself and is picked up by ``rules/__init__.py``.
"""

from __future__ import annotations

import ast
import importlib
from collections.abc import Hashable, Iterator
from dataclasses import dataclass, field
from functools import lru_cache
from typing import TYPE_CHECKING, ClassVar, NamedTuple

from gymmigrate.facts import names as N
from gymmigrate.facts.decisions import Action, Decision
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.module import full_name, walk
from gymmigrate.facts.profile import FileProfile
from gymmigrate.facts.self_attributes import binds_self_attribute, class_self_stores
from gymmigrate.facts.version_checks import dead_version_branch
from gymmigrate.findings import RUN_QUESTION, FixKind, Tier, gym_only_question
from gymmigrate.options import RewriteOptions
from gymmigrate.rules.notes import FamilyNotes

if TYPE_CHECKING:
    from gymmigrate.edits.plan import Need, Plan
    from gymmigrate.facts import ModuleFacts
    from gymmigrate.facts.receivers import Receivers


@dataclass(frozen=True)
class Rule:
    """One catalog entry: what the README documents and what ``--select`` will name."""

    code: str
    title: str
    kind: FixKind
    summary: str
    # The item names a decision of the whole run (a library's route, an env id's new
    # version), not of its file: the same item in several files is asked once
    # (``report.decide_once``), the other files' items point at it.
    once_per_run: bool = False


@dataclass
class FileContext:
    """What every family of one file knows besides the facts: its path, the run's options
    and the cheap import profile."""

    path: str
    options: RewriteOptions
    profile: FileProfile
    notes: FamilyNotes = field(default_factory=FamilyNotes)  # what the families tell each other


_FAMILIES: list[type[RuleFamily]] = []


class RuleFamily:
    """A family of rules that decides from facts and records edits in a ``Plan``.

    Subclasses set ``RULES`` (and ``after`` where they read another family's notes), may narrow ``may_fire`` with a cheap test on
    the facts, and implement ``decide``. They report with ``self.report(node, code,
    message)`` (``node`` is an ``ast`` node of the original source) and edit through
    ``self.plan`` (``replace``, ``insert_after``, ``ensure_import``...).
    """

    RULES: ClassVar[tuple[Rule, ...]] = ()
    # Codes of standalone rules (``register_rules``) whose Python side this family carries
    # out: GM111's dependency files name a module, and the module gets the edit.
    CARRIES_OUT: ClassVar[tuple[str, ...]] = ()
    # Families whose notes this one reads (``rules/notes.py``): the pipeline runs them first.
    after: ClassVar[tuple[str, ...]] = ()
    # Decides whether the module is migrated at all (``FamilyNotes.module_kept_for``): it
    # runs whatever rules are selected, and its findings are filtered afterwards as any.
    decides_the_module: ClassVar[bool] = False

    def __init_subclass__(cls, **kwargs: object) -> None:
        super().__init_subclass__(**kwargs)
        if cls.RULES or cls.CARRIES_OUT:
            _FAMILIES.append(cls)

    def __init__(self, context: FileContext, facts: ModuleFacts, receivers: Receivers, plan: Plan) -> None:
        self.context = context
        self.facts = facts
        self.receivers = receivers
        self.plan = plan
        self.notes = context.notes
        self._rules = {rule.code: rule for rule in (*self.RULES, *standalone_rules()) if rule in self.RULES or rule.code in self.CARRIES_OUT}

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        """Cheap test on the facts: can this family fire at all in this file?"""
        return True

    def decide(self) -> None:
        raise NotImplementedError

    def report(
        self,
        node: ast.AST,
        code: str,
        message: str,
        kind: FixKind | None = None,
        tier: Tier | None = None,
        question: Hashable | None = None,
        needs: Need | None = None,
        together: Hashable | None = None,
    ) -> None:
        """``tier`` only where it differs from what the kind implies (see findings.Tier).
        ``question``: what the item asks, where other items of the file may ask the same
        (``receiver_question``): the file's review list asks it once (``Plan.ask_once``).
        ``needs``: another family's edit this change reads a name of (``edits.plan.Need``);
        ``together``: changes of the file with this key are made at every place or at none.
        Code in the branch of a ``gym.__version__`` check that never runs on Gymnasium 1.x
        raises nothing: GM108 reports the check itself."""
        if code != "GM108" and dead_version_branch(node, self.facts) is not None:
            return
        self.plan.report(node, code, kind or self._rules[code].kind, message, tier, question, needs, together)

    def receiver_question(self, receiver: ast.AST, decision: Decision) -> Hashable | None:
        """The question an item on an untraced receiver asks: "is `env` a Gym env?". The
        same spelling asks it once per function (``self.x``: once per class), whatever the
        method called on it, as long as the run answers it the same way (rewrites or not)."""
        if decision.action not in (Action.REWRITE_FOR_REVIEW, Action.REPORT):
            return None
        library = self._gym_only_origin(receiver) or self.receivers.gym_only_stack(receiver)
        if library is not None:
            return gym_only_question(library)  # decided by the library's port, asked at its import (GM107)
        # ``[env.reset() for env in self.envs]`` and ``self.envs[i].step(a)``: one collection of envs
        receiver = self._iterated_collection(receiver) or self._fed_collection(receiver) or receiver
        name = full_name(receiver)
        if not name:
            return None
        fed = self._fed_question(receiver)
        if fed is not None:
            return ("fed", decision.action, fed)
        if name.split(".", 1)[0] == "self":
            owner: ast.AST | None = self.facts.enclosing_class(receiver)
            if isinstance(owner, ast.ClassDef):
                owner = self._twin_class(owner, name.split(".")[1] if name.count(".") >= 1 else "")
            decided_by = self._attribute_owner(owner, name) if isinstance(owner, ast.ClassDef) else None
            if decided_by is not None:
                return (RUN_QUESTION, decision.action, *decided_by, name)
            if isinstance(owner, ast.ClassDef):
                # subclasses of one class of this file that binds the attribute read what it
                # binds: one question for them all
                owner = self._local_definer(owner, name.split(".")[1] if name.count(".") >= 1 else "") or owner
        else:
            owner = self.facts.enclosing_function(receiver)
        return ("receiver", decision.action, id(owner), name)

    def _fed_question(self, receiver: ast.AST) -> frozenset[str] | None:
        """A parameter the def never rebinds, every call of which (in the run) hands on the
        same variables (``Receivers.argument_sources``): whether it is a Gym env is whether
        those are, one question for every def they feed (``evaluate(env)`` and
        ``evaluate_rtg(env)`` called with one ``env``). A parameter whose calls are not all
        known is its own source: the defs it alone feeds (``helper(env)``) ask its question
        (``Receivers.argument_sources`` follows them up to it). None for any other receiver."""
        if not isinstance(receiver, ast.Name):
            return None
        bindings = self.facts.bindings_of(receiver)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.arg):
            return None
        fed = self.receivers.argument_sources(bindings[0])
        if fed is not None:
            return fed
        source = Flow.of(self.facts).source_of(receiver)
        here = self.receivers.project.path if self.receivers.project is not None else ""
        return frozenset({f"{here}|{source}"}) if source is not None else None

    def origin_question(self, receiver: ast.AST) -> frozenset[str] | None:
        """What a parameter receiver holds, as one question for every def fed the same
        variables (``_fed_question``); None for any other receiver."""
        return self._fed_question(receiver)

    def _twin_class(self, cls: ast.ClassDef, attribute: str) -> ast.ClassDef:
        """The first class of the module that stores the very same values in
        ``self.<attribute>`` as ``cls``, each made by a call (a local and a remote twin of one
        env holder, each building its env with the same code): what those values are is one question, asked
        once for both; ``cls`` itself when no earlier class does."""
        if not attribute or cls not in self.facts.tree.body:
            return cls
        values = class_self_stores(self.facts, cls).get(attribute)
        if not values or not all(isinstance(v, ast.Call) for v in values):
            # an env handed in (``self.env = env``) is whatever each class's callers pass
            return cls
        shape = [ast.dump(v) for v in values]
        for other in self.facts.tree.body:
            if other is cls:
                break
            if isinstance(other, ast.ClassDef) and [
                ast.dump(v) for v in class_self_stores(self.facts, other).get(attribute, ())
            ] == shape:
                return other
        return cls

    def _attribute_owner(self, cls: ast.ClassDef, name: str) -> tuple[str, str] | None:
        """The run's class whose code decides ``self.env`` of ``cls``: ``cls`` itself where it
        binds the attribute, else its first base of the run (``class DQN(Policy)``,
        ``Policy`` in another module). Policies of one base class spread over modules ask where
        ``self.env`` comes from once for the run, not once per module (``report.decide_once``).
        None outside a run, or for a class the question cannot be pinned to."""
        project = self.receivers.project
        if project is None or cls not in self.facts.tree.body:
            return None
        attribute = name.split(".")[1] if name.count(".") >= 1 else ""
        seen: set[int] = set()
        while id(cls) not in seen:
            seen.add(id(cls))
            if binds_self_attribute(cls, attribute):
                return (project.path, cls.name)
            # the first base of the run: its ``__init__`` is the one that runs (``class
            # DqnPolicy(Policy, ModelMixin)``: ``Policy`` stores the env); a base of this
            # module that binds nothing hands the question on to its own bases
            # (``Learner(Worker)``, ``Worker(Agent)`` with ``Agent`` elsewhere)
            local = next((held for base in cls.bases if (held := self.receivers.local_class(base)) is not None), None)
            for base in cls.bases:
                if local is not None and self.receivers.local_class(base) is local:
                    break
                for qualified in sorted(self.facts.qualified_names(base)):
                    found = project.class_of_run(qualified)
                    if found is not None:
                        return found
            if local is None or local not in self.facts.tree.body:
                return None
            cls = local
        return None

    def _local_definer(self, cls: ast.ClassDef, attribute: str) -> ast.ClassDef | None:
        """The class of this module that binds ``self.<attribute>`` for ``cls``: ``cls``
        itself, or the first base of this module up its chain that does (``class
        Evaluator(Worker)`` reads ``Worker``'s ``self.env``). None when no class of the
        module binds it on that chain."""
        seen: set[int] = set()
        current: ast.ClassDef | None = cls
        while current is not None and id(current) not in seen:
            seen.add(id(current))
            if binds_self_attribute(current, attribute):
                return current
            current = next((found for base in current.bases if (found := self.receivers.local_class(base)) is not None), None)
        return None


    def _iterated_collection(self, receiver: ast.AST) -> ast.expr | None:
        """The collection a loop or comprehension variable runs over (``env`` of ``for env in
        self.envs``), where that is its only binding; else None."""
        if not isinstance(receiver, ast.Name):
            return None
        bindings = self.facts.bindings_of(receiver)
        if len(bindings) != 1:
            return None
        holder = self.facts.parent(bindings[0])
        collection: ast.expr | None = None
        if isinstance(holder, (ast.comprehension, ast.For)) and holder.target is bindings[0]:
            collection = holder.iter
        elif isinstance(holder, ast.Tuple):
            loop = self.facts.parent(holder)
            if isinstance(loop, (ast.comprehension, ast.For)) and loop.target is holder:
                # ``for env, action in zip(self.envs, actions)``, ``for i, env in enumerate(self.envs)``
                position = next(i for i, element in enumerate(holder.elts) if element is bindings[0])
                collection = _zipped_part(loop.iter, position)
        if collection is not None:
            if isinstance(collection, ast.Subscript) and isinstance(collection.slice, ast.Slice):
                collection = collection.value  # ``for env in self.envs[1:]``: part of the same envs
            if isinstance(collection, (ast.Name, ast.Attribute)) and full_name(collection):
                return collection
        return None

    def _fed_collection(self, receiver: ast.AST) -> ast.expr | None:
        """A parameter of a def that every call of the module (``worker(conn, env)``, or a
        ``Process(target=worker, args=(remote, env))``) feeds from one loop over the same
        collection (``for env in self.envs[1:]``): that collection, whose question this is."""
        function = self.facts.enclosing_function(receiver)
        if not isinstance(receiver, ast.Name) or function is None:
            return None
        params = [a.arg for a in (*function.args.posonlyargs, *function.args.args)]
        if receiver.id not in params or len(self.facts.bindings_of(receiver)) != 1:
            return None
        position = params.index(receiver.id)
        fed: list[ast.expr] = []
        for node in walk(self.facts.tree):
            if not isinstance(node, ast.Call):
                continue
            if isinstance(node.func, ast.Name) and node.func.id == function.name:
                arguments: list[ast.expr] | None = list(node.args)
            else:
                keywords = {k.arg: k.value for k in node.keywords}
                target, args = keywords.get("target"), keywords.get("args")
                if not (isinstance(target, ast.Name) and target.id == function.name):
                    continue
                arguments = list(args.elts) if isinstance(args, (ast.Tuple, ast.List)) else None
            if arguments is None or position >= len(arguments) or any(isinstance(a, ast.Starred) for a in arguments):
                return None
            fed.append(arguments[position])
        collections = [self._iterated_collection(value) for value in fed]
        if not collections or any(c is None for c in collections):
            return None
        keys = {(full_name(c), id(self.facts.enclosing_class(c))) for c in collections if c is not None}
        return collections[0] if len(keys) == 1 else None

    def _gym_only_origin(self, receiver: ast.AST) -> str | None:
        """The library with no Gymnasium release (``baselines``) every value of ``receiver``
        comes from (``env = make_atari(id)``, ``env = wrap_deepmind(env)``), if there is one."""
        if isinstance(receiver, ast.Attribute):
            # ``self.env`` stored from a Gym-only library's call in the class (``__init__``)
            made = self.receivers.library_made(receiver)
            top = made.split(".", 1)[0] if made is not None else None
            return N.gym_only_stack(top) if top in N.GYM_ONLY_PACKAGES else None
        if not isinstance(receiver, ast.Name):
            return None
        bindings = self.facts.bindings_of(receiver)
        flow = Flow.of(self.facts)
        last = flow.last_binding_of(receiver)
        statement = self.facts.statement_of(last) if isinstance(last, ast.Name) else None
        if last is not None and isinstance(statement, ast.Assign) and flow.dominates(statement, receiver, receiver):
            bindings = [last]  # the value this read certainly sees
        else:
            # ``env = Monitor(env, d)`` in one branch, after ``env = Monitor(gym.make(...), d)``:
            # the values that may reach the read, not those overwritten before it
            bindings = flow.reaching(receiver) or bindings
        tops: set[str] = set()
        for binding in bindings:
            assign = self.facts.parent(binding)
            if isinstance(assign, ast.Assign) and isinstance(assign.value, ast.Constant) and assign.value.value is None:
                continue  # ``eval_env = None``: a method call on it would fail, so it is not what is asked about
            if not (isinstance(binding, ast.Name) and isinstance(assign, ast.Assign) and isinstance(assign.value, ast.Call)):
                return None
            packages = self._call_packages(assign.value)
            if not packages:
                return None  # an unbound name, or a def of this file that returns something else
            tops.update(packages)
        # ``JoypadSpace(gym_super_mario_bros.make(...))``: two packages of one stack (nes_py)
        stacks = {N.gym_only_stack(top) if top in N.GYM_ONLY_PACKAGES else top for top in tops}
        library = stacks.pop() if len(stacks) == 1 else None
        return library if library in N.GYM_ONLY_PACKAGES else None

    def _call_packages(self, call: ast.Call) -> set[str]:
        """The top-level packages ``call`` is bound to; for a module-level def of this file
        (``def make_env(s): return MultiAgentEnv(...)``), those of the calls it returns."""
        packages = {q.split(".", 1)[0] for q in self.facts.qualified_names(call.func)}
        if packages or not isinstance(call.func, ast.Name):
            return packages
        function = self.facts.functions.get(call.func.id)
        if function is None:
            return set()
        returns = [n for n in walk(function) if isinstance(n, ast.Return) and self.facts.enclosing_function(n) is function]
        for ret in returns:
            if not isinstance(ret.value, ast.Call):
                return set()  # it may return something else: not the library's alone
            packages |= {q.split(".", 1)[0] for q in self.facts.qualified_names(ret.value.func)}
        return packages if all(packages) else set()


class FamilySpec(NamedTuple):
    """One family in the pipeline: where it lives, and the words without which it cannot fire.

    A family's module is imported the first time a file spells one of ``words`` (None:
    every file), so ``check`` on a file pays only for the families that may fire on it.
    The words are a necessary condition of the family's ``may_fire``, which still decides
    (``tests/test_pipeline.py`` holds every fixture to that).
    """

    name: str  # the RuleFamily subclass
    module: str  # the module that defines it
    words: tuple[str, ...] | None = None
    # The family may also fire on what other modules of the run say (a PettingZoo class
    # imported from the project): in a run of several files the words do not decide.
    follows_the_run: bool = False

    def may_fire_in(self, text: str, in_a_run: bool = False) -> bool:
        return self.words is None or (in_a_run and self.follows_the_run) or any(word in text for word in self.words)

    def load(self) -> type[RuleFamily]:
        found = _by_name().get(self.name)
        if found is None:
            importlib.import_module(self.module)  # its classes register themselves
            found = _by_name().get(self.name)
        if found is None:
            raise RuntimeError(f"rules/__init__.py PIPELINE: {self.module} defines no family {self.name}")
        return found


def _zipped_part(iterated: ast.expr, position: int) -> ast.expr | None:
    """What the ``position``-th name of a tuple loop target runs over: ``zip(self.envs,
    actions)`` gives ``self.envs`` at 0, ``enumerate(self.envs)`` gives it at 1; else None."""
    if not isinstance(iterated, ast.Call) or not isinstance(iterated.func, ast.Name):
        return None
    if any(isinstance(a, ast.Starred) for a in iterated.args):
        return None
    if iterated.func.id == "zip" and position < len(iterated.args):
        return iterated.args[position]
    if iterated.func.id == "enumerate" and position == 1 and iterated.args:
        return iterated.args[0]
    return None


def _by_name() -> dict[str, type[RuleFamily]]:
    return {cls.__name__: cls for cls in _FAMILIES}


def set_pipeline(specs: tuple[FamilySpec, ...]) -> None:
    """The order families decide in; each must come after the families it names in ``after``."""
    global _PIPELINE
    _PIPELINE = specs
    _ordered_families.cache_clear()


_PIPELINE: tuple[FamilySpec, ...] = ()


def families_for(text: str, in_a_run: bool = False) -> Iterator[type[RuleFamily]]:
    """The families that may fire on ``text`` (a module of a run of several files when
    ``in_a_run``), in pipeline order, loaded on first use."""
    for spec in _PIPELINE:
        if spec.may_fire_in(text, in_a_run):
            yield spec.load()


def registered_families() -> list[type[RuleFamily]]:
    """Every family, in the order of ``PIPELINE`` (``rules/__init__.py``); loads them all."""
    return list(_ordered_families())


@lru_cache(maxsize=1)
def _ordered_families() -> tuple[type[RuleFamily], ...]:
    loaded = [spec.load() for spec in _PIPELINE]
    names = [spec.name for spec in _PIPELINE]
    by_name = _by_name()
    missing = sorted(set(by_name) - set(names))
    if missing:
        raise RuntimeError(f"rules/__init__.py PIPELINE: families not listed {missing}")
    for position, family in enumerate(loaded):
        for before in family.after:
            if before not in by_name:
                raise RuntimeError(f"{family.__name__}.after names {before!r}, which is no family")
            if names.index(before) > position:
                raise RuntimeError(f"{family.__name__} reads the notes of {before}, which the PIPELINE runs later")
    return tuple(loaded)


# Rules carried out outside the Python engine (``rules/dependency_files.py``).
_STANDALONE_RULES: list[Rule] = []


def register_rules(*rules: Rule) -> None:
    """Declare rules that no family of the Python engine implements."""
    _STANDALONE_RULES.extend(rules)


def standalone_rules() -> list[Rule]:
    return list(_STANDALONE_RULES)
