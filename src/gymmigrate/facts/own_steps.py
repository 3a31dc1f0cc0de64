"""A class's own ``step`` as its subclasses and its own methods use it: a helper that
returns the observation alone, and what ``self.step(...)`` gives in a class whose every
step the run migrates.

* **Helpers.** A step none of whose returns is a step result (``return self._get_obs()``)
  is a *helper* where every override in the run builds its own Gym step on it: ``ob =
  super().step(a)`` ... ``return ob, reward, False, info``, or ``failed = super().step(a)``
  ... ``return ob, reward, failed, info`` (a flag, one whole field, never indexed; an
  argument-less ``self.sim.step()`` it returns is no Gym step). It is on no Gym step contract
  (neither legacy nor Gymnasium: its overrides are), so it keeps its return (GM504 says
  why and asks nothing), and ``super().step(...)`` in the overrides gives them that one
  value, no step result (GM301/GM304 leave it). Each module's summary lists its
  candidates (``helper_candidates``) and its steps that return their own values
  (``own_step_shapes``: an override that calls no base step does not contradict it);
  the join keeps the candidates whose every override elsewhere is one
  (``ProjectView.helper_step``).
* **Steps that give five values.** ``self.step(...)`` in a method of a class runs the
  step of the instance's class: the class's own (or an abstract one) or an override below
  it. Where each of them gives Gymnasium's five values once the run has migrated it
  (``passes_five``: a four- or five-value literal of an env class the run migrates, the
  base's step handed on, a held Gym env's), so does the call: ``obs, r, done, info =
  self.step(zeros)`` in a base class's ``__init__`` moves with its subclasses
  (``self_step_gives_five``; the summaries' ``five_step_trees`` for subclasses elsewhere).
"""

from __future__ import annotations

import ast

from gymmigrate.facts import names as N
from gymmigrate.facts.class_shapes import is_batched_step_return
from gymmigrate.facts.env_classes import (
    DIRECT_ENV_BASES,
    EnvClasses,
    is_super_method_call,
)
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import (
    FUNCTIONS,
    ModuleFacts,
    is_super_call,
    named_class_call,
    own_returns,
    walk,
)
from gymmigrate.facts.receiver_classes import is_object
from gymmigrate.facts.receivers import Receivers
from gymmigrate.facts.step_calls import foreign_step
from gymmigrate.facts.step_hooks import tuple_len

Method = ast.FunctionDef | ast.AsyncFunctionDef


def own_step(classdef: ast.ClassDef) -> Method | None:
    return next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "step"), None)


def is_base_step_call(node: ast.AST | None, classdef: ast.ClassDef, method: Method) -> bool:
    """``super().step(...)``, or ``Base.step(self, ...)`` naming the first base (the one
    ``super()`` reaches first), in ``method`` of ``classdef``."""
    if is_super_method_call(node, "step"):
        return True
    first = [b for b in classdef.bases if not is_object(b)][:1]
    return named_class_call(node, "step", method, first) is not None


def _stores(method: Method, name: str) -> list[ast.Name]:
    return [n for n in walk(method) if isinstance(n, ast.Name) and n.id == name and isinstance(n.ctx, ast.Store)]


def hands_on_base_step(value: ast.AST | None, classdef: ast.ClassDef, method: Method) -> bool:
    """A return's ``value`` is the base's step result as it is: the call itself, or the one
    name the method binds, once and whole, to it (``results = super().step(a)`` ...
    ``return results``)."""
    if is_base_step_call(value, classdef, method):
        return True
    if not isinstance(value, ast.Name) or len(_stores(method, value.id)) != 1:
        return False
    return any(
        isinstance(node, ast.Assign)
        and len(node.targets) == 1
        and isinstance(node.targets[0], ast.Name)
        and node.targets[0].id == value.id
        and is_base_step_call(node.value, classdef, method)
        for node in walk(method)
    )


def _is_step_call(node: ast.AST | None) -> bool:
    """``x.step(a)``: some object's step that may be a Gym env's. Gym's step takes the
    action, so ``self._sim.step()`` with nothing to pass is some other object's advance."""
    return (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and node.func.attr == "step"
        and bool(node.args or node.keywords)
    )


# Builtins that make a sequence of what they are given: a step result as much as anything.
_SEQUENCE_BUILDERS = frozenset({"tuple", "list", "zip"})


def returns_observation(classdef: ast.ClassDef, step: Method) -> bool:
    """Every return of the class's own ``step`` hands back one value that is no step
    result: none is a tuple or list display, a sequence built from parts, some object's
    ``step(...)`` (the base's, a held env's) or a name the step binds to one, nor a call of
    a method of the class that returns a tuple display."""
    values = [r.value for r in own_returns(step)]
    if not values or any(v is None for v in values):
        return False
    methods = {s.name: s for s in classdef.body if isinstance(s, FUNCTIONS)}
    from_steps = {
        t.id for n in walk(step) if isinstance(n, ast.Assign) and _is_step_call(n.value) for t in n.targets if isinstance(t, ast.Name)
    }
    for value in values:
        if isinstance(value, (ast.Tuple, ast.List, ast.ListComp, ast.GeneratorExp)) or _is_step_call(value):
            return False
        if isinstance(value, ast.Name) and value.id in from_steps:
            return False
        if isinstance(value, ast.Call) and isinstance(value.func, ast.Name) and value.func.id in _SEQUENCE_BUILDERS:
            return False
        if isinstance(value, ast.Call) and isinstance(value.func, ast.Attribute) and isinstance(value.func.value, ast.Name):
            helper = methods.get(value.func.attr) if value.func.value.id == "self" else None
            if helper is not None and any(isinstance(r.value, (ast.Tuple, ast.List)) for r in own_returns(helper)):
                return False  # ``return self._observe()`` with a four-value ``_observe``: a step result
    return True


def builds_own_step(classdef: ast.ClassDef, step: Method) -> bool | None:
    """An override that returns its own step values: every return is a four- or five-value
    literal, and the base's step is called, if at all, only bound whole to one name that
    it never unpacks, one the first field of some return reads (the base's value is the
    observation). True where it builds on the base's step that way, False where it calls
    none; None for any other step."""
    calls = [n for n in walk(step) if is_base_step_call(n, classdef, step)]
    returns = own_returns(step)
    if not returns or any(tuple_len(r.value) not in (4, 5) for r in returns):
        return None
    if not calls:
        return False
    names: set[str] = set()
    assigns = [n for n in walk(step) if isinstance(n, ast.Assign)]
    for call in calls:
        binder = next((a for a in assigns if a.value is call), None)
        if binder is None or len(binder.targets) != 1 or not isinstance(binder.targets[0], ast.Name):
            return None
        names.add(binder.targets[0].id)
    for node in walk(step):
        if isinstance(node, ast.Assign) and isinstance(node.value, ast.Name) and node.value.id in names:
            if any(isinstance(t, (ast.Tuple, ast.List)) for t in node.targets):
                return None  # ``ob, r, d, i = res``: the base's value is a step result
        if isinstance(node, ast.Starred) and isinstance(node.value, ast.Name) and node.value.id in names:
            return None
    first_fields = [r.value.elts[0] for r in returns]  # type: ignore[union-attr]
    if any(isinstance(n, ast.Name) and n.id in names for field in first_fields for n in walk(field)):
        return True
    # ``failed = super().step(a)`` ... ``return ob, reward, failed, {}``: the base's value is
    # one later field whole (a flag), and nothing indexes it as a sequence would be
    if any(isinstance(n, ast.Subscript) and isinstance(n.value, ast.Name) and n.value.id in names for n in walk(step)):
        return None
    later = [field for r in returns for field in r.value.elts[1:]]  # type: ignore[union-attr]
    return True if any(isinstance(field, ast.Name) and field.id in names for field in later) else None


def _children(facts: ModuleFacts) -> dict[str, list[ast.ClassDef]]:
    """Top-level class name -> the top-level classes of the module naming it as a base."""

    def compute() -> dict[str, list[ast.ClassDef]]:
        found: dict[str, list[ast.ClassDef]] = {}
        for classdef in facts.classes.values():
            for base in classdef.bases:
                if isinstance(base, ast.Name) and base.id in facts.classes and base.id != classdef.name:
                    found.setdefault(base.id, []).append(classdef)
        return found

    return facts.memo(("own-steps-children", 0), compute)


def _below(facts: ModuleFacts, classdef: ast.ClassDef) -> list[ast.ClassDef]:
    """The top-level classes of the module derived from ``classdef``, at any depth."""
    children = _children(facts)
    found: list[ast.ClassDef] = []
    todo = list(children.get(classdef.name, ()))
    while todo:
        child = todo.pop()
        if child not in found and child is not classdef:
            found.append(child)
            todo += children.get(child.name, ())
    return found


def calls_base_method(classdef: ast.ClassDef, method: str, *, named: bool = False) -> bool:
    """Some method of ``classdef`` calls ``method`` on a base: ``super().m(...)`` (unless
    ``named``) or ``Cls.m(self, ...)`` naming any class."""
    for node in walk(classdef):
        if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == method):
            continue
        held = node.func.value
        if is_super_call(held):
            if not named:
                return True
            continue
        if isinstance(held, ast.Name) and held.id == "self":
            continue
        if isinstance(held, (ast.Name, ast.Attribute)) and node.args and isinstance(node.args[0], ast.Name) and node.args[0].id == "self":
            return True
    return False


def replaces_method(classdef: ast.ClassDef, method: str) -> bool:
    """``classdef`` defines ``method`` and none of its methods calls a base's: an instance of
    it (or of a class below it) never runs the base's ``method``, nor what that runs."""
    return any(isinstance(s, FUNCTIONS) and s.name == method for s in classdef.body) and not calls_base_method(classdef, method)


def _below_running(facts: ModuleFacts, classdef: ast.ClassDef, method: str | None) -> list[ast.ClassDef]:
    """``_below``, less the classes that run no ``method`` of ``classdef``: one that
    replaces it (``replaces_method``) and every class derived from that one, which finds
    the replacement before ``classdef``'s in its MRO, ``super()`` going through it. Where one
    of them calls ``Cls.method(self)``, which may skip past it to ``classdef``'s with the
    replacing class's step, that replacing class and those below it stay to be checked."""
    below = _below(facts, classdef)
    if method is None:
        return below
    cut: list[ast.ClassDef] = []
    for sub in below:
        if replaces_method(sub, method):
            tree = [sub, *_below(facts, sub)]
            if not any(calls_base_method(c, method, named=True) for c in tree):
                cut += tree
    return [sub for sub in below if sub not in cut]


def hands_on_only(classdef: ast.ClassDef, step: Method) -> bool:
    """Every return of the step hands its base's step result on as it is (``return
    super().step(changed_action)``): the base's step under another action, nothing more."""
    returns = own_returns(step)
    return bool(returns) and all(hands_on_base_step(r.value, classdef, step) for r in returns)


def helper_candidates(facts: ModuleFacts) -> dict[str, int]:
    """Top-level classes whose own step returns the observation alone and whose every
    override in this module returns its own step values (``builds_own_step``) or hands
    the base's on to overrides of its own (``helper_hand_ons``): class -> how many of
    those overrides build on it."""
    found: dict[str, int] = {}
    for name, classdef in facts.classes.items():
        step = own_step(classdef)
        if step is None or not returns_observation(classdef, step):
            continue
        shapes = [
            builds_own_step(sub, own)
            for sub in _below(facts, classdef)
            if (own := own_step(sub)) is not None and not hands_on_only(sub, own)
        ]
        if None not in shapes:
            found[name] = shapes.count(True)
    return found


def helper_hand_ons(facts: ModuleFacts) -> dict[str, tuple[tuple[str, bool], ...]]:
    """Helper candidate -> the top-level classes of this module below it whose step is the
    candidate's: none of their own, or one that only hands the base's on
    (``hands_on_only``), each with whether it must have a class deriving from it (a class
    of this module, or one the join finds elsewhere). Overrides elsewhere below any of
    them are overrides of the helper; a class handing the value on with none below it
    returns it as its own Gym step, and the base is no helper."""
    found: dict[str, tuple[tuple[str, bool], ...]] = {}
    for name in helper_candidates_of(facts):
        passes = tuple(
            (sub.name, own is not None and not _below(facts, sub))
            for sub in _below(facts, facts.classes[name])
            if (own := own_step(sub)) is None or hands_on_only(sub, own)
        )
        if passes:
            found[name] = passes
    return found


def own_step_shapes(facts: ModuleFacts) -> dict[str, bool]:
    """Top-level classes whose own step returns its own step values (``builds_own_step``):
    class -> whether it builds on its base's step."""
    found = {}
    for name, classdef in facts.classes.items():
        step = own_step(classdef)
        shape = None if step is None else builds_own_step(classdef, step)
        if shape is not None:
            found[name] = shape
    return found


def five_step_trees(facts: ModuleFacts, receivers: Receivers) -> frozenset[str]:
    """Top-level classes whose own step (if any) and the steps of every class of this
    module derived from them give five values once migrated (``passes_five``, a base's step
    handed on counted as the base's: the join checks the class it reaches)."""
    found = set()
    for name, classdef in facts.classes.items():
        tree = [classdef, *_below(facts, classdef)]
        if all((step := own_step(c)) is None or passes_five(facts, receivers, c, step, migrated=True, base=True) for c in tree):
            found.add(name)
    return frozenset(found)


def passes_five(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef, step: Method, *, migrated: bool, base: bool | None) -> bool:
    """Every return of ``step`` gives Gymnasium's five values after the run: a five-value
    literal; a four-value one where the run migrates the class (``migrated``; not a batch's
    stacked flags, which keep their contract); the base's step handed on where ``base``
    says that step gives five; a held Gym env's step (``return self.env.step(a)``). A step
    that only raises (abstract) returns nothing to anyone."""
    returns = own_returns(step)
    if not returns:
        return any(isinstance(n, ast.Raise) for n in walk(step))
    for ret in returns:
        value = ret.value
        size = tuple_len(value)
        if size == 5 or (size == 4 and migrated and not is_batched_step_return(value, step)):
            continue
        if hands_on_base_step(value, classdef, step):
            if base:
                continue
            return False
        if _held_gym_step(facts, receivers, value):
            continue
        return False
    return True


def _held_gym_step(facts: ModuleFacts, receivers: Receivers, value: ast.AST | None) -> bool:
    """``self.env.step(a)`` on a held object the run shows to be a Gym env, not one of a
    class whose step the run keeps on four fields."""
    if not (_is_step_call(value) and isinstance(value, ast.Call) and isinstance(value.func, ast.Attribute)):
        return False
    held = value.func.value
    if isinstance(held, ast.Call) or (isinstance(held, ast.Name) and held.id == "self"):
        return False
    return (
        receivers.kind_of(held) is EnvKind.GYM_ENV
        and receivers.legacy_step_class(held) is None
        and not foreign_step(value, receivers, facts)
    )


def _abstract_root(facts: ModuleFacts, classdef: ast.ClassDef) -> bool:
    """Every base is ``gym.Env`` itself (or ``object``): a step it does not define is the
    abstract one, which only overrides make return."""
    bases = [b for b in classdef.bases if not is_object(b)]
    return bool(bases) and all(
        any(N.strip_gym_prefix(q) in DIRECT_ENV_BASES for q in facts.qualified_names(b)) for b in bases
    )


def self_step_gives_five(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef, method: str | None = None) -> bool:
    """``self.step(...)`` in a method of ``classdef`` gives Gymnasium's five values after the
    run: the class's own step does (with none, it derives ``gym.Env`` alone, whose step is
    abstract), and so does every override below it, in this module and in the others of
    the run (``ProjectView.steps_below_give_five``); and some step exists to run. With the
    calling ``method`` named, a subclass that replaces that method without calling the
    base's (``replaces_method``) never runs this call: its step, and those below it, are
    not the call's to check."""
    return facts.memo(
        (f"self-step-five:{method or ''}", id(classdef)), lambda: _self_step_gives_five(facts, receivers, classdef, method), while_computing=False
    )


def _migrated(receivers: Receivers, classdef: ast.ClassDef) -> bool:
    """The run migrates the class's step: an env class of Gym's contract that keeps no legacy step."""
    return receivers.class_kind(classdef) is EnvKind.GYM_ENV and not receivers.is_gym_wrapper_class(classdef) and not receivers.class_keeps_legacy_step(classdef)


def _self_step_gives_five(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef, method: str | None) -> bool:
    env = EnvClasses.of(facts, receivers)
    steps = 0
    step = own_step(classdef)
    if step is None:
        if not _abstract_root(facts, classdef):
            return False
    else:
        base = env.base_step_migrates(classdef) is True and not reaches_helper_step(facts, receivers, classdef)
        if not passes_five(facts, receivers, classdef, step, migrated=_migrated(receivers, classdef), base=base):
            return False
        steps += 1
    below = _below_running(facts, classdef, method)
    for sub in below:
        own = own_step(sub)
        # a subclass's ``super().step(a)`` reaches a step of this chain, checked here
        if own is not None:
            if not passes_five(facts, receivers, sub, own, migrated=_migrated(receivers, sub), base=True):
                return False
            steps += 1
    project = receivers.project
    if project is not None:
        for owner in (classdef, *below):
            if facts.parent(owner) is not facts.tree:
                continue
            elsewhere = project.steps_below_give_five(owner.name, method)
            if elsewhere is None:
                return False
            steps += elsewhere
    return steps > 0


def helper_step(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> bool:
    """The class's own step is a helper its overrides build their steps on, as the run
    shows (its overrides elsewhere too, ``ProjectView.helper_step_here``)."""
    if facts.parent(classdef) is not facts.tree:
        return False
    local = helper_candidates_of(facts).get(classdef.name)
    if local is None:
        return False
    project = receivers.project
    if project is None:
        # a class below whose step hands the value on, with nothing below it, returns it as
        # its own Gym step (the join looks for such classes' subclasses in the whole run)
        return local > 0 and not any(needs_below for _, needs_below in helper_hand_ons(facts).get(classdef.name, ()))
    return project.helper_step_here(classdef.name)


def helper_candidates_of(facts: ModuleFacts) -> dict[str, int]:
    return facts.memo(("helper-candidates", 0), lambda: helper_candidates(facts))


def reaches_helper_step(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> bool:
    """``super().step(...)`` in ``classdef`` reaches a helper step (``helper_step``): the
    first base's own, a class of this module or of another module of the run (through
    classes of this module that define no step or one that only hands the base's on)."""
    seen: set[int] = set()
    current = classdef
    while id(current) not in seen:
        seen.add(id(current))
        bases = [b for b in current.bases if not is_object(b)]
        if not bases:
            return False
        local = receivers.local_class(bases[0])
        if local is None:
            project = receivers.project
            return project is not None and any(project.helper_step(q) for q in facts.qualified_names(bases[0]))
        step = own_step(local)
        if step is not None and not hands_on_only(local, step):
            return helper_step(facts, receivers, local)
        # no step of its own, or one that hands the base's on (an intermediate of a helper,
        # ``helper_hand_ons``): ``super().step`` gives what the base's gives
        current = local
    return False
