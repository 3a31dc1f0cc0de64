"""Which ``render`` calls pass a legacy mode, and which env classes must keep one.

A legacy ``x.render(mode)`` may reach an env class's ``render(self, mode)``
(``passes_mode``, unless the argument is certainly no mode string: ``not_a_mode_call``).
Where such a call's receiver cannot be traced to its creation (``creation.CreationFinder``),
the module's env classes keep ``render(self, mode)`` and take no ``render_mode``
(``render_kept_classes``) where that mode cannot become optional, so constructing one is no
creation site for the render rules (``local_env_class_takes_render_mode``); one whose mode
stays optional takes ``render_mode`` beside it.

An env class whose ``render(self, mode="human")`` only hands its mode on to an object of
the project's own that is no Gym env (``self._engine.render(mode=mode)``), and that no
render call passes a mode to, keeps that render as the project's API
(``own_object_render``): it takes no ``render_mode`` either. An env class whose own
``render(self)`` takes no mode, hands no render on and never meets ``render_mode``
(``modeless_render``) draws the same whatever the env is made with.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import names as N
from gymmigrate.facts.creation import CreationFinder
from gymmigrate.facts.creation_shapes import first_argument
from gymmigrate.facts.env_classes import (
    DIRECT_ENV_BASES,
    EnvClasses,
    mode_can_stay_optional,
)
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import (
    FUNCTIONS,
    ModuleFacts,
    call_argument,
    is_super_call,
    string_value,
    walk,
)
from gymmigrate.facts.receivers import Receivers


def local_env_class_takes_render_mode(facts: ModuleFacts, receivers: Receivers, call: ast.Call) -> bool:
    """``GridEnv()`` where ``GridEnv`` is an env class of this module whose constructor takes
    ``render_mode`` once migrated: a creation site exactly like ``gym.make``."""
    classdef = receivers.local_class(call.func)
    if classdef is None:
        # An env class of another module of the run that takes render_mode once migrated.
        project = receivers.project
        return project is not None and any(
            (found := project.imported_class(q)) is not None and found[1] for q in facts.qualified_names(call.func)
        )
    return (
        EnvClasses.of(facts, receivers).takes_render_mode(classdef)
        and id(classdef) not in render_kept_classes(facts, receivers)
        and own_object_render(facts, receivers, classdef) is None
    )


def render_kept_classes(facts: ModuleFacts, receivers: Receivers) -> frozenset[int]:
    """Local env classes (by id) whose ``render(self, mode)`` must stay as it is.

    A ``render`` call that passes a mode, on a receiver whose creation cannot be traced,
    may reach an instance of any env class of the module: removing ``mode`` from that
    class's render() would make the call a TypeError (custom_env/render.py keeps it).
    Where ``mode`` cannot become optional, such a class takes no ``render_mode``, so
    ``GridEnv()`` is then no creation site; where it can, the class takes ``render_mode``
    beside it and is not kept here.
    """

    def compute() -> frozenset[int]:

        def is_creation(call: ast.Call) -> bool:
            return receivers.local_class(call.func) is not None or any(
                N.strip_gym_prefix(q) in N.GYM_ENV_FACTORIES for q in facts.qualified_names(call.func)
            )

        classes = EnvClasses.of(facts, receivers)
        project = receivers.project
        # A subclass in another module renders itself with a mode through this render(),
        # which cannot keep ``mode`` beside render_mode (custom_env/render.py).
        below = frozenset(
            id(c)
            for c in facts.classes.values()
            if project is not None
            and project.mode_renders_below(c.name)
            and any(isinstance(s, FUNCTIONS) and s.name == "render" and not mode_can_stay_optional(s) for s in c.body)
        )
        if project is not None and project.render_called_elsewhere():
            # Another module of the run passes modes to objects it cannot trace.
            return frozenset(id(c) for c in facts.all_classes if classes.is_custom_env(c) and not _mode_stays_optional(c))
        finder = CreationFinder(facts, receivers, is_creation)
        untraced: list[ast.Call] = []
        for call in facts.attribute_calls.get("render", []):
            if not passes_mode(call, facts):
                continue
            receiver = call.func.value  # type: ignore[attr-defined]
            if receivers.kind_of(receiver) not in (EnvKind.GYM_ENV, EnvKind.UNKNOWN):
                continue
            if not finder.find(receiver).found:
                untraced.append(call)
        if not untraced:
            return below
        return below | frozenset(
            id(classdef)
            for classdef in facts.all_classes
            if classes.is_custom_env(classdef)
            and not _mode_stays_optional(classdef)
            and any(facts.enclosing_class(call) is not classdef for call in untraced)
        )

    return facts.memo(("render-kept-classes", 0), compute)


def _mode_stays_optional(classdef: ast.ClassDef) -> bool:
    """The class's own ``render(self, mode)`` keeps ``mode`` as an optional parameter beside
    ``render_mode`` (custom_env/render.py): calls that pass a mode keep working, and its
    constructor takes ``render_mode`` all the same."""
    return any(isinstance(s, FUNCTIONS) and s.name == "render" and mode_can_stay_optional(s) for s in classdef.body)


def passes_mode(call: ast.Call, facts: ModuleFacts) -> bool:
    """A legacy ``x.render(mode)`` call that may reach an env class's ``render(self, mode)``:
    a ``mode`` keyword or any positional argument (``*args`` may carry one), outside a
    render method (which forwards its own mode: the class rules own it). A call whose
    argument is certainly no mode string (``obj.render(img)`` drawing into an array) is
    some other class's render."""
    if not (any(k.arg == "mode" for k in call.keywords) or call.args):
        return False
    if not_a_mode_call(call, facts):
        return False
    return getattr(facts.enclosing_function(call), "name", None) not in ("render", "_render")


# numpy callables that build an array: their result is never a mode string.
_ARRAY_BUILDERS = frozenset(
    {"zeros", "ones", "empty", "full", "array", "asarray", "zeros_like", "ones_like", "empty_like", "full_like",
     "arange", "linspace", "stack", "concatenate", "eye", "identity"}
)
_NOT_STRINGS = (ast.List, ast.Tuple, ast.Dict, ast.Set, ast.ListComp, ast.SetComp, ast.DictComp, ast.GeneratorExp, ast.Lambda)


def not_a_mode_call(call: ast.Call, facts: ModuleFacts) -> bool:
    """``x.render(arg)`` whose mode argument (``mode=`` or the first positional) is certainly
    not a string, so not a Gym render mode: a literal that is no string, a container, a
    numpy array built there, or a name whose binding reaching the call is one of those
    (``img = np.zeros(...)`` then ``obj.render(img)``). A ``*args`` may hold anything."""
    if any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords):
        return False
    named = next((k.value for k in call.keywords if k.arg == "mode"), None)
    value = named if named is not None else first_argument(call)
    return value is not None and _not_a_string(value, facts, 0)


def declared_render_modes(facts: ModuleFacts) -> frozenset[str]:
    """The strings of the module's render-mode lists: a ``"render.modes"`` or
    ``"render_modes"`` entry of any dict display (an env class's ``metadata``)."""
    found: set[str] = set()
    for node in walk(facts.tree):
        if not isinstance(node, ast.Dict):
            continue
        for key, value in zip(node.keys, node.values):
            if isinstance(key, ast.Constant) and key.value in ("render.modes", "render_modes"):
                found.update(n.value for n in walk(value) if isinstance(n, ast.Constant) and isinstance(n.value, str))
    return frozenset(found)


def _not_a_string(value: ast.AST, facts: ModuleFacts, depth: int) -> bool:
    if isinstance(value, ast.Constant):
        return not isinstance(value.value, str)
    if isinstance(value, _NOT_STRINGS):
        return True
    if isinstance(value, ast.Call):
        return any(
            q.split(".")[0] == "numpy" and q.rsplit(".", 1)[-1] in _ARRAY_BUILDERS for q in facts.qualified_names(value.func)
        )
    if isinstance(value, ast.Name) and depth < 8:
        flow = Flow.of(facts)
        binding = flow.last_binding_of(value)
        statement = facts.statement_of(binding) if isinstance(binding, ast.Name) else None
        if not (isinstance(statement, ast.Assign) and len(statement.targets) == 1 and statement.targets[0] is binding):
            return False
        return flow.dominates(statement, value, value) and _not_a_string(statement.value, facts, depth + 1)
    return False


def own_object_render(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> ast.Call | None:
    """The call by which an env class's ``render(self, mode="human")`` hands its mode on to an
    object of the project's own that is no Gym env (``self._engine.render(mode=mode)``, an
    engine class of the run), when that is all the render does with ``mode`` and no render
    call that passes a mode may reach the class; None for any other class.

    Such a render is the project's API, not Gym's: its callers call it bare (often to switch
    the engine's drawing on), and so do Gymnasium's wrappers, which keeps its default. A
    migration to ``render_mode`` would turn those calls into no-ops (Gymnasium's render()
    draws nothing without a mode) and call the engine without the mode it needs, so the
    class keeps its render and takes no ``render_mode``. In a run of several files the join
    decides (``ProjectView.own_render_here``): it also knows the render calls and the
    registrations of the other modules. Alone, the module's own calls decide."""
    return facts.memo(("own-object-render", id(classdef)), lambda: _own_object_render(facts, receivers, classdef))


def _own_object_render(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> ast.Call | None:
    calls = mode_handed_on(facts, classdef)
    if not calls or not EnvClasses.of(facts, receivers).is_custom_env(classdef):
        return None
    project = receivers.project
    if project is not None:
        top_level = facts.classes.get(classdef.name) is classdef
        return calls[0] if top_level and project.own_render_here(classdef.name) else None
    if not all(own_object(receivers, call) for call in calls) or mode_may_reach(facts, receivers, classdef):
        return None
    return calls[0]


def mode_handed_on(facts: ModuleFacts, classdef: ast.ClassDef) -> list[ast.Call] | None:
    """The calls to which the class's own ``render(self, mode=...)`` hands ``mode``, when that
    is all it does with it: every read of ``mode`` is an argument of a method call on some
    object (``x.render(mode=mode)``, not ``super()``'s), nothing rebinds it, and ``mode`` and
    every parameter after ``self`` have defaults (Gymnasium's wrappers call render() bare).
    None for any other render: one that compares its mode, returns per mode, or has none."""
    render = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "render"), None)
    if render is None:
        return None
    args = render.args
    if args.posonlyargs or len(args.args) < 2 or args.args[1].arg != "mode":
        return None
    if len(args.defaults) < len(args.args) - 1 or any(d is None for d in args.kw_defaults):
        return None
    calls: list[ast.Call] = []
    for node in walk(render):
        if isinstance(node, (ast.Lambda, *FUNCTIONS)) and node is not render:
            return None  # a nested def may read ``mode`` some other way
        if not (isinstance(node, ast.Name) and node.id == "mode"):
            continue
        holder = facts.parent(node)
        call = facts.parent(holder) if isinstance(holder, ast.keyword) else holder
        if not (
            isinstance(node.ctx, ast.Load)
            and isinstance(call, ast.Call)
            and (node in call.args or (isinstance(holder, ast.keyword) and holder.arg is not None and holder in call.keywords))
            and isinstance(call.func, ast.Attribute)
            and not is_super_call(call.func.value)
        ):
            return None
        calls.append(call)
    return calls or None


def own_object(receivers: Receivers, call: ast.Call) -> bool:
    """The object whose method ``call`` calls is the project's own and no Gym env."""
    receiver = call.func.value  # type: ignore[attr-defined]
    return receivers.kind_of(receiver) is EnvKind.NOT_ENV and receivers.run_defined(receiver)


def mode_may_reach(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> bool:
    """A render mode may reach ``classdef`` (or a subclass of it here) from this module: a
    ``register(...)`` names it (``make`` takes a render_mode), or a render call that passes a
    mode (``passes_mode``) has a receiver not shown to be made by other constructions only
    (``self.render("rgb_array")`` in the class itself reaches it)."""
    if _registered_here(facts, receivers, classdef):
        return True
    family = {id(classdef)}
    changed = True
    while changed:
        changed = False
        for other in facts.all_classes:
            if id(other) not in family and any((base := receivers.local_class(b)) is not None and id(base) in family for b in other.bases):
                family.add(id(other))
                changed = True

    def is_creation(call: ast.Call) -> bool:
        return receivers.local_class(call.func) is not None or any(
            N.strip_gym_prefix(q) in N.GYM_ENV_FACTORIES for q in facts.qualified_names(call.func)
        )

    finder = facts.memo(("own-render-finder", 0), lambda: CreationFinder(facts, receivers, is_creation))
    for call in facts.attribute_calls.get("render", []):
        if not passes_mode(call, facts):
            continue
        receiver = call.func.value  # type: ignore[attr-defined]
        holder = facts.enclosing_class(call)
        if isinstance(receiver, ast.Name) and receivers.is_self(receiver) and holder is not None and id(holder) in family:
            return True  # the class (or a subclass here) renders itself with a mode
        if receivers.kind_of(receiver) not in (EnvKind.GYM_ENV, EnvKind.UNKNOWN):
            continue
        creation = finder.find(receiver)
        made = [receivers.local_class(c.func) for c in creation.calls]
        if creation.found and creation.complete and not any(m is not None and id(m) in family for m in made):
            continue  # made by other constructions (gym.make, another class) only
        return True
    return False


def modeless_render(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> bool:
    """The render() a bare call on an instance of env class ``classdef`` runs is the
    project's own drawing, which no render mode can change: the class or a base of this
    module defines it with no parameter but ``self``, it hands no render on
    (``self.viewer.render()``, ``super().render()``: what those draw may hang on a mode),
    and neither the class nor a base of this module mentions ``render_mode`` (a helper of
    the render may read it). No ``register(...)`` here names the class: ``make`` would
    reach it. Gymnasium's render_mode only tells an env's render what to draw; this one
    ignores it, so a bare call made on an instance built by its constructor asks for none."""
    return facts.memo(("modeless-render", id(classdef)), lambda: _modeless_render(facts, receivers, classdef))


def _lineage_of_this_module(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> list[ast.ClassDef] | None:
    """The class and its bases of this module, where every base is one of them, ``object``
    or Gym's env (or a removed Gym base its port replaces by Gym's env,
    ``PORTED_TO_ENV_BASES``): a base of no module here (a library's env, a mix-in) may
    define the render that runs, or what it calls. None where one is not, or where a class of the
    lineage names ``render_mode`` (it draws by mode already)."""
    lineage = list(receivers.local_lineage(classdef))
    for current in lineage:
        for base in current.bases:
            if not (
                receivers.local_class(base) is not None
                or (isinstance(base, ast.Name) and base.id == "object")
                or any(N.strip_gym_prefix(q) in DIRECT_ENV_BASES for q in facts.qualified_names(base))
                or any(N.strip_gym_prefix(q) in N.PORTED_TO_ENV_BASES for q in facts.qualified_names(base))
            ):
                return None
        if any(_names_render_mode(node) for node in walk(current)):
            return None
    return lineage


def _modeless_render(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> bool:
    if not EnvClasses.of(facts, receivers).is_custom_env(classdef) or _registered_here(facts, receivers, classdef):
        return False
    lineage = _lineage_of_this_module(facts, receivers, classdef)
    if lineage is None:
        return False
    render = next(
        (s for current in lineage for s in current.body if isinstance(s, FUNCTIONS) and s.name == "render"),
        None,
    )
    if render is None:
        return False
    args = render.args
    if args.posonlyargs or args.vararg or args.kwarg or args.kwonlyargs or len(args.args) != 1:
        return False
    return not any(
        isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "render"
        for node in walk(render)
    )


def _names_render_mode(node: ast.AST) -> bool:
    """``render_mode`` as a name, attribute, parameter or string (``getattr(self, "render_mode")``)."""
    if isinstance(node, ast.Name):
        return node.id == "render_mode"
    if isinstance(node, ast.Attribute):
        return node.attr == "render_mode"
    if isinstance(node, ast.arg):
        return node.arg == "render_mode"
    return isinstance(node, ast.Constant) and node.value == "render_mode"


def _registered_here(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> bool:
    """A ``register(...)`` call of the module names the class as its entry point: the class
    itself, or a string ending in ``:Name``."""
    for call in (*facts.calls_by_name.get("register", ()), *facts.attribute_calls.get("register", ())):
        entry = call_argument(call, 1, "entry_point")
        if entry is None:
            continue
        if receivers.local_class(entry) is classdef:
            return True
        text = string_value(entry)
        if text is None and isinstance(entry, ast.BinOp):
            text = string_value(entry.right)  # ``__name__ + ":Sim"``
        if text is not None and text.rpartition(":")[2] == classdef.name:
            return True
    return False


def draws_only_in_render(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> bool:
    """An env class of the module whose drawing is its render() alone: the class or a base of
    this module defines render() and step(), no base comes from elsewhere (but Gym's Env),
    nothing in them mentions ``render_mode``, and neither step() nor reset(), nor a method of
    the class they call on ``self``, calls a render(). Gymnasium's human mode draws inside
    step() only where step() calls render(): made with ``render_mode="human"``, an instance of
    this class still draws only when render() is called, as before."""
    return facts.memo(("render-only", id(classdef)), lambda: _draws_only_in_render(facts, receivers, classdef))


def _draws_only_in_render(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> bool:
    renders = _step_renders(facts, receivers, classdef)
    return renders is not None and not renders


def steps_draw_on_own_flags(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> bool:
    """The same class shape as ``draws_only_in_render``, where step() or reset() (or a method
    they call on ``self``) may call a render(), but each such call runs only under a condition
    of the class's own (``if self.gui:``): nothing of the class reads ``render_mode``, so made
    with ``render_mode="human"`` its step() draws no more than before, and an explicit
    render() call is still what draws where those conditions do not hold."""
    return facts.memo(("own-flag-steps", id(classdef)), lambda: _steps_draw_on_own_flags(facts, receivers, classdef))


def _steps_draw_on_own_flags(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> bool:
    renders = _step_renders(facts, receivers, classdef)
    return renders is not None and all(guarded for _, guarded in renders)


def _step_renders(facts: ModuleFacts, receivers: Receivers, classdef: ast.ClassDef) -> list[tuple[ast.Call, bool]] | None:
    """The render() calls step() and reset() reach (through the methods of the class they
    call on ``self``), each with whether a condition guards it on the way; None where the class
    is no env of this module's own lineage defining render() and step()."""
    if not EnvClasses.of(facts, receivers).is_custom_env(classdef):
        return None
    lineage = _lineage_of_this_module(facts, receivers, classdef)
    if lineage is None:
        return None
    methods: dict[str, ast.FunctionDef | ast.AsyncFunctionDef] = {}
    for current in lineage:
        for statement in current.body:
            if isinstance(statement, FUNCTIONS):
                methods.setdefault(statement.name, statement)
    if "render" not in methods or "step" not in methods:
        return None
    found: list[tuple[ast.Call, bool]] = []
    pending: list[tuple[str, bool]] = [(name, False) for name in ("step", "reset") if name in methods]
    # a method reached unguarded once is walked unguarded; guarded first, it may be walked again
    seen: dict[str, bool] = dict(pending)
    while pending:
        name, outer = pending.pop()
        method = methods[name]
        for node in walk(method):
            if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)):
                continue
            guarded = outer or _guarded_within(facts, node, method)
            if node.func.attr == "render":
                found.append((node, guarded))
                continue
            called = node.func.attr
            if isinstance(node.func.value, ast.Name) and node.func.value.id == "self" and called in methods:
                if called not in seen or (seen[called] and not guarded):
                    seen[called] = guarded
                    pending.append((called, guarded))
    return found


def _guarded_within(facts: ModuleFacts, node: ast.AST, method: ast.AST) -> bool:
    """A condition of ``method`` decides whether ``node`` runs: it lies in a branch of an
    ``if``/``while``/conditional expression, past the first operand of ``and``/``or``, in an
    ``except`` or a ``match`` case (the tests themselves always run)."""
    child: ast.AST = node
    parent = facts.parent(node)
    while parent is not None and parent is not method:
        if isinstance(parent, (ast.If, ast.IfExp, ast.While)) and child is not parent.test:
            return True
        if isinstance(parent, ast.BoolOp) and child is not parent.values[0]:
            return True
        if isinstance(parent, (ast.ExceptHandler, ast.Match)) and child is not getattr(parent, "subject", None):
            return True
        child, parent = parent, facts.parent(parent)
    return False
