"""GM405: ``def render(self, mode="human")`` -> ``def render(self)`` reading ``self.render_mode``.

``gymnasium.make(id, render_mode=...)`` passes the mode to the constructor, so
``__init__`` takes ``render_mode=None`` and stores it; without a mode, ``render()``
draws nothing (Gymnasium's convention). No caller is left broken: a forwarding
``env.render(mode, ...)`` to inner envs stops passing the mode (reviewed), and the
signature is kept (reported) while a render call elsewhere in the file still passes a
mode and may reach an instance of the class. A render that only hands its mode on to an
object of the project's own that is no Gym env, and that no render call passes a mode to,
is the project's API and stays as it is (``render_modes.own_object_render``).
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from typing import TYPE_CHECKING

from gymmigrate.edits.arguments import append_keyword
from gymmigrate.edits.lazy import cst
from gymmigrate.facts import names as N
from gymmigrate.facts.creation import CreationFinder
from gymmigrate.facts.env_classes import (
    DIRECT_ENV_BASES,
    is_super_method_call,
    mode_can_stay_optional,
)
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import is_super_call, walk
from gymmigrate.facts.multi_agent import MultiAgent
from gymmigrate.facts.receiver_classes import is_object
from gymmigrate.facts.render_modes import own_object, own_object_render, passes_mode
from gymmigrate.findings import FixKind, Tier, kept_render_question
from gymmigrate.rules.custom_env.common import (
    ClassDecision,
    Method,
    local_bases,
    method_of,
    param_names,
)
from gymmigrate.rules.custom_env.hooks import local_subclasses
from gymmigrate.rules.wrapper_usage.origins import EnvOrigins

if TYPE_CHECKING:
    from gymmigrate.rules.base import RuleFamily


def decide_render(decision: ClassDecision) -> None:
    function = decision.method("render")
    if function is None:
        return
    args = function.args
    params = args.args  # LibCST's ``params``: positional-or-keyword parameters
    mode_index = next((i for i, p in enumerate(params) if p.arg == "mode"), None)
    if mode_index is None:
        return
    first_default = len(params) - len(args.defaults)
    default = args.defaults[mode_index - first_default] if mode_index >= first_default else None
    old_default = ""
    if default is not None:
        text = decision.family.facts.segment(default)
        old_default = f" (the old default was {text}: pass render_mode={text} to gymnasium.make to keep it)"
    if _keeps_mode_already(function, default):
        return  # render(self, mode=None) reading self.render_mode: migrated by an earlier run
    setup = _own_setup_render(decision, function)
    if setup is not None:
        # Its own ``self.render()`` (``if gui: self.render()`` in __init__) runs set-up the
        # env needs (a GUI client connected); the check that draws nothing without a
        # render_mode would skip it. The body is the same for every mode, so it stays whole;
        # gymnasium.make and subclasses still pass render_mode, so __init__ takes it.
        decision.plan.render_init_only = True
        decision.report(
            function,
            "GM405",
            f"render(mode) kept as it is: the class's __init__ calls `self.render()` on line {setup.lineno} and its body never "
            "reads `mode` (set-up, not a frame), which a render() drawing nothing without a render_mode would skip; "
            "__init__ takes render_mode and stores it: decide whether render_mode=\"human\" should run that set-up",
            FixKind.FLAG,
        )
        _add_init_render_mode(decision)
        return
    mechanism = decision.env.own_render_mode(decision.classdef)
    if mechanism is not None:
        decision.report(
            function,
            "GM405",
            f"render(mode) kept: the class chooses its render mode itself ({mechanism}); Gymnasium's "
            "`render_mode` (given to gymnasium.make, stored by __init__, read by a render() without arguments) "
            "would bypass that mechanism: fold it into render_mode by hand, or keep the class off gymnasium.make's "
            "render_mode",
            FixKind.FLAG,
        )
        return
    own = _own_mode_call(decision)
    if own is not None:
        decision.report(
            function,
            "GM405",
            f"render(mode) kept: `{decision.family.facts.segment(own)}` on line {own.lineno} (this class, a base or a "
            "subclass in this file) asks render() for a mode, a TypeError once render() takes none; render that mode "
            "another way (or drop the argument), then run again",
            FixKind.FLAG,
        )
        return
    project = decision.family.receivers.project
    top_level = decision.family.facts.classes.get(decision.classdef.name) is decision.classdef
    below = project.mode_renders_below(decision.classdef.name) if project is not None and top_level else []
    blocking = _unmigrated_mode_call(decision)
    elsewhere = blocking is None and project is not None and project.render_called_elsewhere()
    if below or elsewhere or blocking is not None:
        facts = decision.family.facts
        if below:
            where, call = below[0]
            more = f" (and {len(below) - 1} more)" if len(below) > 1 else ""
            caller = f"`{call}` at {where}{more}, in a subclass in another module of this run, asks it for a mode"
        elif elsewhere:
            caller = (
                "another module of this run imports this class (or a factory of the run whose module does) and passes "
                "a mode to `.render()` on an object that "
                "could not be traced, or on a Gym env with a mode or arguments the rendering rules leave (GM401), "
                "which may be an instance of it"
            )
        else:
            assert blocking is not None  # not elsewhere: a blocking call of this module
            caller = (
                f"`{facts.segment(blocking)}` on line {blocking.lineno} still passes a mode (its env's creation could "
                "not be followed, so it was not migrated) and may reach this class"
            )
        # The untraced calls of other modules that reach this class alone ask this item's
        # question (rendering/sites.py): one decision, listed here.
        question = kept_render_question(project.path, decision.classdef.name) if elsewhere and not below and project is not None else None
        if not _can_keep_mode(function):
            then = (
                "render that mode another way (or drop the argument), then run again"
                if below
                else "give that env its render_mode where it is made, then run again"
            )
            decision.report(function, "GM405", f"render(mode) kept: {caller}; {then}", FixKind.FLAG, question=question)
            return
        # Those callers keep working, and so does Gymnasium's render() without arguments.
        decision.plan.render = True
        decision.plan.render_keeps_mode = True
        _declare_render_modes(decision, function, default)
        decision.report(
            function,
            "GM405",
            f"render() reads self.render_mode (fixed when the env is made) when no mode is passed, but keeps `mode` as an "
            f"optional parameter: {caller}; once every caller passes none, remove the parameter{old_default}",
            question=question,
        )
        _add_init_render_mode(decision)
        return
    handed = own_object_render(decision.family.facts, decision.family.receivers, decision.classdef)
    if handed is not None:
        # Its callers call render() bare (a switch that turns the engine's drawing on), and so
        # do Gymnasium's wrappers: the default mode keeps them working as they did, where
        # Gymnasium's render() would draw nothing without a render_mode and call the engine
        # without the mode it takes.
        where = "of the run" if decision.family.receivers.project is not None else "of this file"
        decision.report(
            function,
            "GM405",
            f"render(mode) kept: it only hands `mode` on to `{decision.family.facts.segment(handed)}`, an object of the "
            f"project's own that is no Gym env, and no render call {where} passes it a mode: bare calls (its callers', "
            "Gymnasium's wrappers') keep its default as before; the class takes no render_mode",
            FixKind.FLAG,
            tier=Tier.NOTE,
        )
        return
    decision.plan.render = True
    _plan_internal_renders(decision, function, default)
    _declare_render_modes(decision, function, default)
    _report_forwarded_modes(decision, function)
    _report_bare_inner_renders(decision, function)
    # Notes: the standard Gymnasium signature, applied; the render calls and creation
    # sites in the run are reviewed where they are (GM401/GM402), not here.
    decision.report(function, "GM405", f"render() takes no mode: it reads self.render_mode, fixed when the env is made, and draws nothing when that is None{old_default}", tier=Tier.NOTE)
    _add_init_render_mode(decision)


def report_kept_render_options(decision: ClassDecision) -> None:
    """A class the run leaves whole (its step and reset keep their own API) keeps its
    ``render(self, mode, <options>...)``; where ``gymnasium.make`` of an id the run
    registers reaches that render, the wrappers make adds (OrderEnforcing, the env checker)
    expose ``render(self)`` only, so a caller of the made env passing a mode or an option
    raises TypeError. Porting it is a design decision: one item, at the def."""
    function = decision.method("render")
    project = decision.family.receivers.project
    if function is None or project is None or not project.made_render(decision.classdef.name):
        return
    names = param_names(function)
    options = [n for n in names[1:] if n != "mode"]
    if "mode" not in names or not options:
        return
    decision.report(
        function,
        "GM405",
        f"render(mode, {', '.join(options)}) kept with the class's own step/reset, but gymnasium.make builds it for an "
        "id this run registers, and the wrappers make adds expose render() without arguments: a caller passing a mode or "
        "an option raises TypeError. Map the modes to render_mode at construction, move the options to the constructor "
        'or attributes, and declare metadata["render_modes"]',
        FixKind.FLAG,
    )


def _declare_render_modes(decision: ClassDecision, function: Method, default: ast.expr | None) -> None:
    """Gymnasium's env checker (on by default in gymnasium.make) asserts that an env whose
    ``metadata["render_modes"]`` is empty (``Env``'s own) has ``render_mode`` None: the ported
    render, given its mode by make, would fail on its first call. A class whose hierarchy (this
    module's classes up to ``gym.Env``) declares no ``metadata`` gets one listing the modes its
    render drew: its old default and the modes its body tests ``mode`` against. Where those
    are unknown, or a ``metadata`` exists without the key, the place is reported. A hierarchy
    that leaves this module (another class of the run, one of Gymnasium's envs) is not known,
    and a local base with its own render(mode) declares them in its own migration."""
    hierarchy = [decision.classdef, *local_bases(decision)]
    env = decision.env
    if not all(_local_or_env_bases(decision, c) for c in hierarchy):
        return
    if any("render" in env.index(base).methods for base in hierarchy[1:]):
        return  # the base's own render is migrated (and declares its modes) or drew already
    declared = [c for c in hierarchy if _class_metadata(c) is not None or env.index(c).stores_to_self("metadata")]
    if declared:
        metadata = _class_metadata(declared[0])
        if not isinstance(metadata, ast.Dict) or any(
            isinstance(k, ast.Constant) and k.value in ("render_modes", "render.modes") for k in metadata.keys
        ):
            return  # declared, or built in a way this run does not read: as before
        decision.report(
            declared[0],
            "GM405",
            "render() now reads self.render_mode, but this `metadata` declares no \"render_modes\": gymnasium.make's env "
            "checker then asserts render_mode is None, so the first render() of an env made with one fails; list the "
            "modes render() draws there",
            FixKind.FLAG,
        )
        return
    modes = _legacy_modes(function, default)
    if not modes and _draws_a_window(decision, function):
        modes = ("human",)
    if not modes:
        decision.report(
            decision.classdef,
            "GM405",
            "render() now reads self.render_mode, but the class declares no metadata[\"render_modes\"] and its old "
            "render names no mode (no default, no test of `mode`): gymnasium.make's env checker then asserts "
            "render_mode is None; add `metadata = {\"render_modes\": [...]}` with the modes it draws",
            FixKind.FLAG,
        )
        return
    decision.plan.declare_render_modes = modes
    listed = ", ".join(f'"{mode}"' for mode in modes)
    drew = (
        "its default and the modes it tests"
        if _legacy_modes(function, default)
        else "it names no mode, but opens a window and returns no frame: a \"human\" render"
    )
    decision.report(
        decision.classdef,
        "GM405",
        f"metadata = {{\"render_modes\": [{listed}]}} added (the modes the old render drew: {drew}): gymnasium.make's env "
        "checker asserts render_mode is None for an env that declares none",
        tier=Tier.NOTE,
    )


def _local_or_env_bases(decision: ClassDecision, classdef: ast.ClassDef) -> bool:
    receivers = decision.family.receivers
    return all(
        is_object(base)
        or receivers.local_class(base) is not None
        or any(N.strip_gym_prefix(q) in DIRECT_ENV_BASES for q in decision.family.facts.qualified_names(base))
        for base in classdef.bases
    ) and not classdef.keywords


def _class_metadata(classdef: ast.ClassDef) -> ast.expr | None:
    """The value of a class-level ``metadata = ...`` (or annotated), else None."""
    for statement in classdef.body:
        if isinstance(statement, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "metadata" for t in statement.targets):
            return statement.value
        if isinstance(statement, ast.AnnAssign) and isinstance(statement.target, ast.Name) and statement.target.id == "metadata":
            return statement.value or ast.Constant(None)
    return None


def _legacy_modes(function: Method, default: ast.expr | None) -> tuple[str, ...]:
    """The old default mode, then each string the body compares ``mode`` with (``==``, ``!=``,
    ``in``, ``not in`` a literal tuple/list/set), in order of appearance."""
    modes: list[str] = []
    if isinstance(default, ast.Constant) and isinstance(default.value, str):
        modes.append(default.value)
    for node in walk(function):
        if not isinstance(node, ast.Compare) or len(node.ops) != 1:
            continue
        left, right = node.left, node.comparators[0]
        if isinstance(right, ast.Name) and right.id == "mode":
            left, right = right, left
        if not (isinstance(left, ast.Name) and left.id == "mode"):
            continue
        values = right.elts if isinstance(right, (ast.Tuple, ast.List, ast.Set)) else [right]
        modes.extend(v.value for v in values if isinstance(v, ast.Constant) and isinstance(v.value, str))
    return tuple(dict.fromkeys(modes))


# The calls that show a frame in a window of the screen, and nothing else: a render that
# makes one is a "human" render.
_WINDOW_CALLS = frozenset(
    {
        "cv2.imshow",
        "cv2.waitKey",
        "matplotlib.pyplot.show",
        "matplotlib.pyplot.pause",
        "pygame.display.flip",
        "pygame.display.update",
    }
)


def _draws_a_window(decision: ClassDecision, function: Method) -> bool:
    """The old render, naming no mode, shows its frame in a window (``cv2.imshow``,
    ``plt.show``/``plt.pause``, ``pygame.display.flip``) and returns no value: the one mode
    it drew is "human". A render returning anything (an array, text) may be another mode,
    and stays asked."""
    facts = decision.family.facts
    nodes = list(walk(function))
    if any(isinstance(n, (ast.Lambda, ast.FunctionDef, ast.AsyncFunctionDef, ast.Yield, ast.YieldFrom)) and n is not function for n in nodes):
        return False  # nested code: its returns and calls are not the render's own
    if any(isinstance(n, ast.Return) and not (n.value is None or (isinstance(n.value, ast.Constant) and n.value.value is None)) for n in nodes):
        return False
    return any(isinstance(n, ast.Call) and facts.qualified_names(n.func) & _WINDOW_CALLS for n in nodes)


def _keeps_mode_already(function: ast.FunctionDef | ast.AsyncFunctionDef, default: ast.AST | None) -> bool:
    """``def render(self, mode=None)`` starting ``if mode is None: mode = self.render_mode``."""
    if not (isinstance(default, ast.Constant) and default.value is None):
        return False
    body = function.body
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) and isinstance(body[0].value.value, str):
        body = body[1:]
    first = body[0] if body else None
    return (
        isinstance(first, ast.If)
        and ast.unparse(first.test) == "mode is None"
        and len(first.body) == 1
        and ast.unparse(first.body[0]) == "mode = self.render_mode"
    )


def _own_setup_render(decision: ClassDecision, function: ast.FunctionDef | ast.AsyncFunctionDef) -> ast.Call | None:
    """A bare ``self.render()`` in the class's ``__init__``, where render's body never reads
    ``mode``: the class uses render() to set itself up, whatever the mode. A bare call in
    step or reset draws each frame (Gymnasium's 'human' idiom, which the check keeps)."""
    if any(isinstance(n, ast.Name) and n.id == "mode" for n in walk(function)):
        return None
    for call in decision.env.index(decision.classdef).self_calls.get("render", ()):
        method = method_of(decision, call)
        if not call.args and not call.keywords and method is not None and method.name == "__init__":
            return call
    return None


def _can_keep_mode(function: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    """``mode`` can become ``mode=None`` in place (``mode_can_stay_optional``; the run's
    facts decide the same way for a class whose subclasses elsewhere pass a mode)."""
    return mode_can_stay_optional(function)


def _add_init_render_mode(decision: ClassDecision) -> None:
    init = decision.method("__init__")
    if init is None:
        if decision.env.has_local_env_base(decision.classdef):
            decision.plan.local_env_base = True
            decision.report(decision.classdef, "GM405", "render_mode must reach __init__: add a render_mode=None parameter to the base class and store self.render_mode", FixKind.FLAG)
            return
        inherited = decision.env.inherited_init(decision.classdef)
        if inherited is not None:
            # An __init__ added here would shadow the base's: its set-up would never run.
            decision.plan.local_env_base = True
            if (N.strip_gym_prefix(inherited) or "").startswith("envs."):
                decision.report(
                    decision.classdef,
                    "GM405",
                    f"`{inherited}`'s __init__ takes render_mode (Gymnasium's envs do) and stores self.render_mode: "
                    "this class inherits it",
                    tier=Tier.NOTE,
                )
            elif (project := decision.family.receivers.project) is not None and project.takes_render_mode(inherited):
                decision.report(
                    decision.classdef,
                    "GM405",
                    f"`{inherited}` (a class of this run) takes render_mode in its __init__ once migrated and stores "
                    "self.render_mode: this class inherits it",
                    tier=Tier.NOTE,
                )
            else:
                decision.report(
                    decision.classdef,
                    "GM405",
                    f"render_mode must reach __init__, which this class inherits from `{inherited}`: add a "
                    "render_mode=None parameter there (or an __init__ here that passes the rest on) and store "
                    "self.render_mode",
                    FixKind.FLAG,
                )
            return
        decision.report(decision.classdef, "GM405", "added __init__(self, render_mode=None) storing self.render_mode: gymnasium.make passes render_mode to the constructor", tier=Tier.NOTE)
        return
    if "render_mode" not in param_names(init):
        decision.report(init, "GM405", "__init__ takes render_mode=None (gymnasium.make passes it) and stores self.render_mode", tier=Tier.NOTE)


def _own_mode_call(decision: ClassDecision) -> ast.Call | None:
    """``self.render(mode="ansi")`` (or ``super().render("ansi")``) outside a render method,
    in a local base or a local subclass: it reaches this render(), and with the mode
    removed it would be a TypeError; the class keeps render(mode) with the call. The
    class's own ``self.render(mode)`` calls are rewritten to call the old body kept as a
    helper (``_plan_internal_renders``), unless a local subclass overrides render: the
    helper would then bypass the override, so render(mode) is kept for them too."""
    facts = decision.family.facts
    subclasses = local_subclasses(decision)
    hierarchy = [*subclasses]
    receivers = decision.family.receivers
    todo = list(decision.classdef.bases)
    while todo:
        base = receivers.local_class(todo.pop())
        if base is not None and base not in hierarchy and base is not decision.classdef:
            hierarchy.append(base)
            todo.extend(base.bases)
    for classdef in hierarchy:
        for call in (*decision.env.index(classdef).self_calls.get("render", ()), *_super_render_calls(decision, classdef)):
            if passes_mode(call, facts):
                return call
    if any("render" in decision.env.index(sub).methods for sub in subclasses):
        for call in decision.env.index(decision.classdef).self_calls.get("render", ()):
            if passes_mode(call, facts):
                return call
    return None


def _super_render_calls(decision: ClassDecision, classdef: ast.ClassDef) -> list[ast.Call]:
    return [c for c in decision.env.index(classdef).nodes[ast.Call] if is_super_method_call(c, "render")]  # type: ignore[misc]


def decide_subclass_render_mode(decision: ClassDecision) -> None:
    """A subclass of a local env whose ``__init__`` takes ``render_mode`` (or gets it here)
    must take it too and pass it on: ``gymnasium.make(id, render_mode=...)`` passes it to
    the registered class, and ``BigGrid.__init__(self)`` would raise TypeError."""
    if decision.plan.render or decision.plan.render_init_only:
        return  # its own render(mode) migration adds render_mode to __init__
    init = decision.method("__init__")
    if init is None or "render_mode" in param_names(init) or init.args.kwarg is not None:
        return
    builtin = decision.env.render_mode_builtin_base(decision.classdef)
    if builtin is not None:
        # One of Gymnasium's own envs (``CartPoleEnv(render_mode=None)``), whose __init__ the
        # class calls once: it takes the mode there and draws with it.
        decision.plan.pass_render_mode = True
        decision.report(
            init,
            "GM405",
            f"__init__ takes render_mode=None and passes it to `{decision.family.facts.segment(builtin)}`'s __init__, "
            "which takes it in Gymnasium: gymnasium.make passes render_mode to the registered class",
            tier=Tier.NOTE,
        )
        return
    builtin_init = decision.env.builtin_render_mode_first_base(decision.classdef) is not None and not _renders_with_mode(decision)
    if not builtin_init and not _ancestor_takes_render_mode(decision, decision.classdef, set()):
        return
    calls = [
        node
        for node in walk(init)
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "__init__"
    ]
    if len(calls) != 1 or any(k.arg is None for k in calls[0].keywords):
        decision.report(
            init,
            "GM405",
            "the base env's __init__ takes render_mode (gymnasium.make passes it to this class): add a render_mode=None "
            "parameter here and pass it to the base __init__",
            FixKind.FLAG,
        )
        return
    decision.plan.pass_render_mode = True
    decision.report(
        init,
        "GM405",
        "__init__ takes render_mode=None and passes it to the base env's __init__: gymnasium.make passes render_mode "
        "to the registered class",
        tier=Tier.NOTE,
    )


def _renders_with_mode(decision: ClassDecision) -> bool:
    """The class defines render(mode) (``_render`` in gym <= 0.9): its own migration decides."""
    render = decision.method("render") or decision.method("_render")
    return render is not None and "mode" in param_names(render)


def _ancestor_takes_render_mode(decision: ClassDecision, classdef: ast.ClassDef, seen: set[int]) -> bool:
    receivers = decision.family.receivers
    project = receivers.project
    for base_expr in classdef.bases:
        base = receivers.local_class(base_expr)
        if base is None and project is not None and any(project.takes_render_mode(q) for q in receivers.qualified_names(base_expr)):
            return True  # a class of another module of the run (or its subclass) takes it
        if base is None or id(base) in seen:
            continue
        seen.add(id(base))
        methods = {s.name: s for s in base.body if isinstance(s, (ast.FunctionDef, ast.AsyncFunctionDef))}
        render, init = methods.get("render"), methods.get("__init__")
        if (
            render is not None
            and "mode" in param_names(render)
            and own_object_render(decision.family.facts, receivers, base) is None
            # a base whose step and reset the run keeps on their own API keeps render(mode)
            # too (env_class.py): no render_mode reaches its __init__, so none goes there
            and not receivers.keeps_own_reset(base)
        ):
            return True  # its migration adds render_mode to its __init__
        if init is not None:
            if "render_mode" in param_names(init):
                return True
            continue  # a base __init__ without it: that class is decided on its own
        if _ancestor_takes_render_mode(decision, base, seen):
            return True
    return False


def _plan_internal_renders(
    decision: ClassDecision, function: ast.FunctionDef | ast.AsyncFunctionDef, default: ast.expr | None
) -> None:
    """The class renders itself with a mode (``obs = self.render(mode="rgb_array")`` in
    ``reset``/``step``): those calls must keep working once ``render()`` takes no mode. The
    old body is kept as a helper that takes the mode, ``render()`` calls it with
    ``self.render_mode``, and the internal calls call the helper. A bare ``self.render()``
    where the old default is a mode other than "human" (a plot refreshed each step with
    ``mode="rgb_array"``) rendered in that mode whatever the env was made with: the
    render_mode check would silence it, so it calls the helper with the old default. So does
    a bare call the class makes under a switch of its own (``if self.render_gui:
    self.render()``, the flag set by the project's own ``configure(render=True)`` or
    constructor), whatever the old default: the project turned drawing on there, and an env
    made without a render_mode would silently stop drawing. An unconditional bare call
    with the default "human" (or None) is Gymnasium's own idiom (a frame each step of a
    'human' env), which the check keeps."""
    facts = decision.family.facts
    own = [
        call
        for call in facts.attribute_calls.get("render", ())
        if isinstance(call.func.value, ast.Name)  # type: ignore[attr-defined]
        and call.func.value.id == "self"  # type: ignore[attr-defined]
        and method_of(decision, call) is not None
    ]
    calls = [call for call in own if call.args or call.keywords]
    bare = [c for c in own if not (c.args or c.keywords) and method_of(decision, c) is not function]
    # Each method's bare calls all become helper calls (the build rewrites per method), so
    # the class's switch keeps them only where every one of them is under such a switch.
    switched = bool(bare) and all(_under_own_switch(decision, c) for c in bare)
    if not _bare_keeps_default(decision, default, switched):
        bare = []
    switch = ""
    if bare:
        decision.plan.render_helper_default = facts.segment(default)  # type: ignore[arg-type]
        if switched:
            switch = " under the class's own switch, which the project sets to draw,"
        calls += bare
    if not calls:
        return
    taken = set(decision.methods) | {n.attr for node in walk(decision.classdef) for n in [node] if isinstance(n, ast.Attribute)}
    helper, number = "_render_frame", 2
    while helper in taken:
        helper, number = f"_render_frame{number}", number + 1
    decision.plan.render_helper = helper
    decision.plan.render_helper_callers = {method.name for call in calls if (method := method_of(decision, call)) is not None}
    lines = ", ".join(str(call.lineno) for call in calls[:3]) + (", ..." if len(calls) > 3 else "")
    decision.report(
        function,
        "GM405",
        f"the class renders itself with a mode (`self.render(...)` on line {lines}): the old body is kept as "
        f"`{helper}(mode)`, which those calls now use, and render() calls it with self.render_mode"
        + (
            f"; a bare `self.render()`{switch} drew in the old default {decision.plan.render_helper_default} whatever the env "
            "was made with, so it passes that mode to the helper (render() would draw nothing without a render_mode)"
            if bare
            else ""
        ),
        tier=Tier.NOTE,
    )


def _bare_keeps_default(decision: ClassDecision, default: ast.expr | None, switched: bool) -> bool:
    """The old default is a literal mode other than "human" (or any literal default, None
    included, where the class's bare calls are all ``switched`` on by a switch of its own),
    the class does not read render_mode already (a bare call guarded by it is Gymnasium's
    idiom), and no local subclass overrides render (the helper would bypass the override)."""
    literal = isinstance(default, ast.Constant) and (default.value is None or isinstance(default.value, str))
    if not (literal and (switched or (isinstance(default.value, str) and default.value != "human"))):  # type: ignore[union-attr]
        return False
    if any(isinstance(n, ast.Attribute) and n.attr == "render_mode" for n in walk(decision.classdef)):
        return False
    return not any("render" in decision.env.index(sub).methods for sub in local_subclasses(decision))


def _under_own_switch(decision: ClassDecision, call: ast.Call) -> bool:
    """``call`` sits under an ``if`` of its method whose test reads an attribute of ``self``
    (a flag of the instance: ``if self.render_gui:``) and no render_mode."""
    facts = decision.family.facts
    method = method_of(decision, call)
    for ancestor in facts.ancestors(call):
        if ancestor is method:
            return False
        if isinstance(ancestor, ast.If):
            reads = [n for n in walk(ancestor.test) if isinstance(n, ast.Attribute)]
            if any(n.attr == "render_mode" for n in reads):
                return False
            if any(isinstance(n.value, ast.Name) and n.value.id == "self" for n in reads):
                return True
    return False


def _report_forwarded_modes(decision: ClassDecision, function: ast.AST) -> None:
    """``env.render(mode, close)`` to an inner env the run proves a Gym (or PettingZoo) env
    loses its ``mode`` argument (the build drops it: Gymnasium's render() takes none); the
    inner env then renders in the mode it was made with, and any other argument must still
    be one it accepts. Any other receiver (an object of the project's own, or one the run
    cannot trace) keeps getting a mode in the same place: ``self.render_mode``. Dropping it
    there would shift the next argument into the mode parameter."""
    origins = EnvOrigins(decision.family.facts, decision.family.receivers)
    for call in decision.function(function).of(ast.Call):
        func = call.func  # type: ignore[attr-defined]
        if not (isinstance(func, ast.Attribute) and func.attr == "render") or is_super_call(func.value):
            continue
        passes_mode = [a for a in call.args if isinstance(a, ast.Name) and a.id == "mode"]  # type: ignore[attr-defined]
        passes_mode += [k for k in call.keywords if k.arg == "mode" and isinstance(k.value, ast.Name) and k.value.id == "mode"]  # type: ignore[attr-defined]
        if not passes_mode:
            continue
        if isinstance(call, ast.Call) and own_object(decision.family.receivers, call):
            # The project's own object, no Gym env: it still takes a mode, and gets the one
            # the env is made with (the build hands it self.render_mode).
            decision.plan.render_mode_receivers.add(decision.family.facts.segment(func.value))
            decision.report(
                call,
                "GM405",
                f"{decision.family.facts.segment(func.value)}.render() is handed self.render_mode, the mode the env is "
                "made with: it is an object of the project's own, no Gym env, and takes the mode as before",
                tier=Tier.NOTE,
            )
            continue
        if not _renders_without_mode(decision, origins, func.value):
            # Not shown to be an env whose render() lost the mode: it keeps the mode where
            # it took it, now the one the env is made with.
            text = decision.family.facts.segment(func.value)
            decision.plan.render_mode_receivers.add(text)
            decision.report(
                call,
                "GM405",
                f"`{text}.render()` is handed self.render_mode where it was handed `mode` (its other arguments stay "
                f"where they were): the run does not show `{text}` to be a Gym env. If it is one, its render() takes "
                "no mode on Gymnasium: drop the argument and make it with render_mode",
                FixKind.ASSIST,
            )
            continue
        others = len(call.args) + len(call.keywords) - len(passes_mode)  # type: ignore[attr-defined]
        rest = " and the arguments left must be ones its render() accepts (Gymnasium's takes none)" if others else ""
        made = _made_in_init(decision, func.value)
        if made is not None and not others:
            # Made in the __init__ that now takes render_mode: the inner env gets it there,
            # so it renders in the mode the outer env is made with (PettingZoo envs take it).
            decision.family.plan.replace(made, lambda node: append_keyword(node, "render_mode", cst.Name("render_mode")))
            decision.report(
                call,
                "GM405",
                f"the mode is no longer passed on to {decision.family.facts.segment(func.value)}.render(): that env is "
                f"made in __init__ (line {made.lineno}), which now passes it render_mode, so it renders in the env's mode",
                FixKind.ASSIST,
                tier=Tier.NOTE,
            )
            continue
        decision.report(
            call,
            "GM405",
            f"the mode is no longer passed on to {decision.family.facts.segment(func.value)}.render(): make the inner envs "
            f"with render_mode=self.render_mode{rest}",
            FixKind.ASSIST,
        )


def _renders_without_mode(decision: ClassDecision, origins: EnvOrigins, held: ast.expr) -> bool:
    """``held`` is proven an env whose render() takes no mode once migrated: a Gym env or
    vector env, a PettingZoo env, or a Gym env handed to the class from outside."""
    kind = decision.family.receivers.kind_of(held)
    if kind.is_gym or kind in (EnvKind.PZ_AEC, EnvKind.PZ_PARALLEL):
        return True
    return origins.handed_gym_env(held) is not None


def _report_bare_inner_renders(decision: ClassDecision, function: ast.AST) -> None:
    """``self.wrapped_env.render()``, bare, on the Gym env the class holds: legacy drew that
    env in its own default mode ("human"); on Gymnasium it draws only in the render_mode it
    was made with, and nothing where it was made without one, whatever this env's mode. Where
    the inner env comes from is not this class's to change: reported (FLAG). The project's own
    objects (a viewer, a simulator) and objects the run does not show to be Gym envs are not."""
    family = decision.family
    origins = EnvOrigins(family.facts, family.receivers)
    for call in decision.function(function).of(ast.Call):
        func = call.func  # type: ignore[attr-defined]
        if not (isinstance(func, ast.Attribute) and func.attr == "render") or call.args or call.keywords:  # type: ignore[attr-defined]
            continue
        held = func.value
        if not (isinstance(held, ast.Attribute) and isinstance(held.value, ast.Name) and held.value.id == "self"):
            continue
        if isinstance(call, ast.Call) and own_object(family.receivers, call):
            continue
        if family.receivers.kind_of(held) is not EnvKind.GYM_ENV and origins.handed_gym_env(held) is None:
            continue
        text = family.facts.segment(held)
        decision.report(
            call,
            "GM405",
            f"`{text}.render()` drew that env in its own default mode (\"human\"); on Gymnasium it draws only in the "
            f"render_mode `{text}` was made with, and nothing where it was made without one: give it "
            "render_mode=\"human\" (or this env's self.render_mode) where it is made",
            FixKind.FLAG,
        )


def _made_in_init(decision: ClassDecision, held: ast.expr) -> ast.Call | None:
    """The call that makes ``self.<held>`` where the class stores it only once, directly in
    its own ``__init__`` (which takes ``render_mode`` once render is migrated), as a
    PettingZoo env with no ``render_mode`` or ``**`` argument yet; else None."""
    init = decision.method("__init__")
    if init is None or not (isinstance(held, ast.Attribute) and isinstance(held.value, ast.Name) and held.value.id == "self"):
        return None
    if len(decision.index.stores_to_self(held.attr)) != 1:
        return None
    facts = decision.family.facts
    for statement in init.body:
        if (
            isinstance(statement, ast.Assign)
            and len(statement.targets) == 1
            and isinstance(statement.targets[0], ast.Attribute)
            and isinstance(statement.targets[0].value, ast.Name)
            and statement.targets[0].value.id == "self"
            and statement.targets[0].attr == held.attr
        ):
            made = statement.value
            if not isinstance(made, ast.Call) or any(k.arg in ("render_mode", None) for k in made.keywords):
                return None
            if any(isinstance(a, ast.Starred) for a in made.args):
                return None
            kind = MultiAgent.of(facts, decision.family.receivers).kind(made)
            return made if kind in (EnvKind.PZ_AEC, EnvKind.PZ_PARALLEL) else None
    return None


def _unmigrated_mode_call(decision: ClassDecision) -> ast.Call | None:
    """A render call elsewhere in the file that the rendering rules leave passing a mode
    and that may reach an instance of this class: removing ``mode`` from this render()
    would turn it into a TypeError."""
    family = decision.family
    left = family.notes.render_mode_calls_left
    if not left:
        return None
    finder = family.facts.memo(("custom-env-render-finder", 0), lambda: CreationFinder(family.facts, family.receivers, _is_creation(family)))
    for call in left:
        if family.facts.enclosing_class(call) is decision.classdef:
            continue  # its own calls: forwarding (above) or self.render(...)
        receiver = call.func.value  # type: ignore[attr-defined]
        if family.receivers.kind_of(receiver) not in (EnvKind.GYM_ENV, EnvKind.UNKNOWN):
            continue
        creation = finder.find(receiver)
        if creation.found and not any(family.receivers.local_class(c.func) is decision.classdef for c in creation.calls):
            continue  # made elsewhere (gym.make or another class): not this class's render
        return call
    return None


def _is_creation(family: RuleFamily) -> Callable[[ast.Call], bool]:
    """gym.make and friends, or a call of a class defined in this file."""
    def is_creation(call: ast.Call) -> bool:
        if family.receivers.local_class(call.func) is not None:
            return True
        return any(N.strip_gym_prefix(q) in N.GYM_ENV_FACTORIES for q in family.facts.qualified_names(call.func))

    return is_creation
