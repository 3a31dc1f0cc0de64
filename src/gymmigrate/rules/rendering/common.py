"""What the rendering rules share: the catalog entries, the modes, a ``RenderSite``, and
``RenderingBase``, the state of one file's decision with the questions every part asks
(is this call a ``make``, which mode does a render call pass, is this env stepped the
legacy way). ``RenderingBase`` has no ``RULES``: it is not a family of its own."""

from __future__ import annotations

import ast
from collections.abc import Callable
from dataclasses import dataclass

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.creation import Creation, CreationFinder
from gymmigrate.facts.decisions import Action, looks_like_env
from gymmigrate.facts.env_specs import is_spec_make
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import walk
from gymmigrate.facts.render_modes import (
    declared_render_modes,
    local_env_class_takes_render_mode,
    not_a_mode_call,
)
from gymmigrate.facts.wrapper_attributes import lookup_forwarded_to
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.render_calls import arguments_in_order, mode_argument

RULES = (
    Rule(
        "GM401",
        "render mode at make",
        FixKind.ASSIST,
        "`env.render(mode=X)` becomes `env.render()` with `render_mode=X` on the `gym.make` that created the env.",
    ),
    Rule(
        "GM402",
        "bare render() was human",
        FixKind.ASSIST,
        "A bare `env.render()` drew to a window: the make gets `render_mode=\"human\"`.",
    ),
    Rule("GM403", "gym 0.25 render modes", FixKind.AUTO, "`\"single_rgb_array\"` becomes `\"rgb_array\"`."),
    Rule("GM406", "render(close=True)", FixKind.AUTO, "`env.render(close=True)` becomes `env.close()`."),
    Rule(
        "GM407",
        "recording needs rgb_array",
        FixKind.ASSIST,
        "RecordVideo, `utils.play.play` and VecVideoRecorder need `render_mode=\"rgb_array\"` at the make.",
    ),
)

HUMAN = "human"
RGB_ARRAY = "rgb_array"
LEGACY_SINGLE_FRAME = "single_rgb_array"  # gym 0.25 only


@dataclass
class RenderSite:
    """One call that needs its env created in one render mode."""

    node: ast.Call  # the render / recorder call
    code: str  # GM401, GM402 or GM407
    mode: str  # the mode it needs
    accepted: tuple[str, ...]  # modes at the make that satisfy it
    decision: Action
    creation: Creation
    legacy_spelling: bool = False  # it said "single_rgb_array" (GM403)
    consumer: str = "render()"
    quote: str = '"'  # the user's quote style, taken from their mode literal
    variable: bool = False  # ``mode`` is a name holding the mode (its text), not a literal


class RenderingBase(RuleFamily):
    """The state ``Rendering.decide`` sets up for one file, and the questions its parts share."""

    finder: CreationFinder  # the make of each rendered env
    _legacy_025: bool  # the file spells gym 0.25's "single_rgb_array"
    _added: dict[int, str]  # id(make) -> the mode given to it in this run (``notes.render_modes_added``)
    _mode_builds: dict[int, tuple[ast.Call, Callable[[object], object]]]  # id(make) -> (make, its build)
    _noted: dict[int, str]  # modes another family gives a make in this run
    _scheduled: dict[int, str]  # id(make) -> the creation-time condition of its renders
    _unscheduled: dict[int, str]  # id(make) -> the run-time condition of its renders
    _switched_off: dict[int, str]  # id(make) -> the constant that keeps all its renders from running
    _framed: dict[int, tuple[str, int]]  # id(make) -> (the recorder, its line) whose rgb_array overrides bare renders
    _idle_recorders: dict[int, str]  # id(recorder call) -> why it never runs (its make serves the renders)
    _mode_dropped: set[int]  # render calls that lose their mode argument
    _has_legacy_mode_calls: bool  # some render() call of the file still passes a mode
    _makes_by_id: dict[int, ast.Call]  # the makes of the sites, by id
    _kept_default: dict[int, str]  # id(make) -> the class whose render() keeps its default mode (bare renders stay)
    _rendered_nodes: set[int]  # the render and recorder calls of the sites, by id
    _drawn_by_forward: set[int]  # id(make) whose env a render forward's callers draw every step
    _forwarded_sites: list[RenderSite]  # the callers of a render forward (sites.py)
    _forwards: list[tuple[ast.Call, list[int]]]  # (the forward, the makes of its env)
    # (wrapper name, its rendering methods, the build, the make) for envs a wrapper renders
    _wrapped: list[tuple[str, list[str], ast.Call, ast.Call]]
    _class_finder: CreationFinder  # set on first use: the local env class an env is made from
    _own_render_finder: CreationFinder  # set on first use: the classes whose render(mode) stays the project's own

    def _mode_argument(self, call: ast.Call) -> ast.AST | None:
        """The mode a legacy render call passes; None when its argument is certainly no mode
        string (``obj.render(img)`` on a grid cell drawing into an array: not a Gym render),
        or is a mode of another API's render on an object not shown to be an env
        (``self.sim.render(w, h, mode="offscreen")``: ``_foreign_mode``)."""
        found = mode_argument(call)
        if found is None or not_a_mode_call(call, self.facts) or self._foreign_mode(call, found):
            return None
        return found

    def _foreign_mode(self, call: ast.Call, found: ast.AST) -> bool:
        """``x.render(mode="offscreen")``: a literal mode that no Gym env renders in and no
        class of this module lists in its metadata, on a receiver that neither looks like an
        env nor is shown to be one. The mode was the only sign of a legacy Gym render; a mode
        Gym never had is no such sign (a simulator's own render, mujoco-py's ``MjSim``)."""
        value = found.value if isinstance(found, ast.keyword) else found
        if not (isinstance(value, ast.Constant) and isinstance(value.value, str)) or value.value in N.GYM_RENDER_MODES:
            return False
        receiver = call.func.value if isinstance(call.func, ast.Attribute) else None
        if receiver is None or looks_like_env(receiver) or self.receivers.kind_of(receiver) is not EnvKind.UNKNOWN:
            return False
        return value.value not in self.facts.memo(("declared-render-modes", 0), lambda: declared_render_modes(self.facts))

    def _is_make(self, call: ast.Call) -> bool:
        return self.facts.memo(
            ("rendering-is-make", id(call)),
            lambda: self._is_gym_make(call) or local_env_class_takes_render_mode(self.facts, self.receivers, call),
        )

    def _is_gym_make(self, call: ast.Call) -> bool:
        """gym.make and its aliases (not the construction of an env class, whose own render
        signature may take more)."""
        return (
            any(N.strip_gym_prefix(q) in N.GYM_ENV_FACTORIES for q in self.facts.qualified_names(call.func))
            or self._is_project_make(call)
            or is_spec_make(self.facts, self.receivers.project, call)
        )

    def _is_project_make(self, call: ast.Call) -> bool:
        """``make(...)`` / ``pkg.make(...)`` where the run binds that name to ``gym.make``."""
        project = self.receivers.project
        if project is None:
            return False
        return any(
            (alias := project.library_alias(q)) is not None and N.strip_gym_prefix(alias) in N.GYM_ENV_FACTORIES
            for q in self.facts.qualified_names(call.func)
        )

    def _quote(self, node: ast.AST) -> str | None:
        """The quote character of a plain string literal, as written."""
        if not (isinstance(node, ast.Constant) and isinstance(node.value, str)):
            return None
        text = self.facts.segment(node).lstrip("rRuU")
        return text[0] if text[:1] in ("'", '"') else None

    def _call_summary(self, call: ast.Call) -> str:
        """``gym.make("CartPole-v1", ...)``: names a make call in a message."""
        arguments = arguments_in_order(call)
        first = ""
        if arguments:
            value = arguments[0].value if isinstance(arguments[0], (ast.keyword, ast.Starred)) else arguments[0]
            first = self.facts.segment(value)
        more = ", ..." if len(arguments) > 1 else ""
        return f"{self.facts.segment(call.func)}({first}{more})"

    def _argument_name(self, argument: ast.AST) -> str:
        if isinstance(argument, ast.keyword) and argument.arg is not None:
            return argument.arg
        value = argument.value if isinstance(argument, (ast.keyword, ast.Starred)) else argument
        return self.facts.segment(value)

    def _stepped_the_legacy_way(self, receiver: ast.expr, traced: bool = True) -> bool:
        """A file that never names gym but steps this env the legacy way (four values):
        an env another module of the run made and passed in, so its bare render() is a
        legacy human render too. ``traced=False``: any receiver, a Gym env or not. ``self.env``
        (an agent storing the env it is given): the ``self.env.step`` calls of the same class."""
        if traced and self.receivers.kind_of(receiver) is not EnvKind.GYM_ENV:
            return False
        if isinstance(receiver, ast.Attribute) and isinstance(receiver.value, ast.Name) and self.receivers.is_self(receiver.value):
            classdef = self.facts.enclosing_class(receiver)
            return classdef is not None and any(
                unpacks_four(self.facts, call)
                for call in self.facts.attribute_calls.get("step", ())
                if isinstance(call.func, ast.Attribute)
                and isinstance(owner := call.func.value, ast.Attribute)
                and owner.attr == receiver.attr
                and isinstance(owner.value, ast.Name)
                and self.receivers.is_self(owner.value)
                and self.facts.enclosing_class(call) is classdef
            )
        if not isinstance(receiver, ast.Name):
            return False
        bindings = self.facts.bindings_of(receiver)
        return any(unpacks_four(self.facts, call) for call in self._steps_of(receiver.id, lambda read: self.facts.bindings_of(read) == bindings))

    def _steps_of(self, name: str, same: Callable[[ast.Name], bool]) -> list[ast.Call]:
        """The ``name.step(...)`` calls of the module whose ``name`` passes ``same`` (it reads
        the binding in question), in any function: the scopes already index their reads."""
        steps = []
        for read in self.facts.reads_of(name):
            attribute = self.facts.parent(read)
            if isinstance(attribute, ast.Attribute) and attribute.attr == "step" and same(read):
                call = self.facts.parent(attribute)
                if isinstance(call, ast.Call) and call.func is attribute:
                    steps.append(call)
        return steps


def four_value_steps(facts: ModuleFacts) -> bool:
    """``obs, reward, done, info = x.step(a)`` somewhere in the file: legacy stepping, though
    the file never names gym (an env another module of the run passes in)."""
    return any(unpacks_four(facts, call) for call in facts.attribute_calls.get("step", ()))


def unpacks_four(facts: ModuleFacts, call: ast.AST) -> bool:
    """``a, b, c, d = call``: the legacy step's four values."""
    statement = facts.parent(call)
    return (
        isinstance(statement, ast.Assign)
        and len(statement.targets) == 1
        and isinstance(statement.targets[0], (ast.Tuple, ast.List))
        and len(statement.targets[0].elts) == 4
    )


def imports_legacy_make(facts: ModuleFacts, context: FileContext) -> bool:
    """The file imports a name another module of the run binds to the legacy ``gym.make``
    (``from .utils import make``): its bare ``render()`` calls are legacy Gym code too."""
    project = context.options.project
    if project is None:
        return False
    view = project.view(context.path)
    return any(_is_legacy_gym_make(view.library_alias(q)) for q in facts.imports.values())


def imports_legacy_gym_module(facts: ModuleFacts, context: FileContext) -> bool:
    """The file imports a module of the run that imports legacy ``gym`` (the project's
    wrappers, whose factories it calls): a bare ``render()`` of a Gym env there (one the
    run traced, ``holder.gym_env``) renders a legacy env."""
    project = context.options.project
    if project is None:
        return False
    view = project.view(context.path)
    return facts.memo(("imports-legacy-gym-module", 0), lambda: any(view.imports_legacy_gym(q) for q in facts.imports.values()))


def _is_legacy_gym_make(alias: str | None) -> bool:
    return alias is not None and alias.split(".", 1)[0] == "gym" and N.strip_gym_prefix(alias) in N.GYM_ENV_FACTORIES


def forwards_to_first_argument(classdef: ast.ClassDef) -> bool:
    """A plain class (no bases) without render() whose ``__init__(self, env)`` stores ``env``
    as ``self.x`` and whose ``__getattr__(self, name)`` returns ``getattr(self.x, name)`` (or
    ``self.x.get_wrapper_attr(name)``): ``adapter.render`` is the held env's render."""
    if classdef.bases or classdef.keywords:
        return False
    methods = {s.name: s for s in classdef.body if isinstance(s, ast.FunctionDef)}
    init, lookup = methods.get("__init__"), methods.get("__getattr__")
    if init is None or lookup is None or "render" in methods or any(isinstance(s, ast.Assign) for s in classdef.body):
        return False
    params = init.args.args
    if len(params) != 2 or init.args.vararg or init.args.kwonlyargs or init.args.kwarg:
        return False
    held = {
        target.attr
        for s in init.body
        if isinstance(s, ast.Assign) and isinstance(s.value, ast.Name) and s.value.id == params[1].arg
        for target in s.targets
        if isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == params[0].arg
    }
    stored_elsewhere = {
        n.attr
        for n in walk(classdef)
        if isinstance(n, ast.Attribute) and isinstance(n.ctx, ast.Store) and n.attr in held
    }
    if len(held) != 1 or len(stored_elsewhere) != 1:
        return False
    # one statement: a ``__getattr__`` that first tests the name (``if name == "render": raise``)
    # may not let ``render`` through
    if len(lookup.body) != 1 or not isinstance(lookup.body[0], ast.Return):
        return False
    return lookup_forwarded_to(lookup) == held.pop()
