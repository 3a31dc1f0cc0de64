"""Facts about user-defined environment classes, shared by the custom-env and RNG families.

A class is a *custom env* when it subclasses ``gym.Env`` (or ``gymnasium.Env``), a
built-in env class under ``gym.envs`` (``CartPoleEnv``, ``MujocoEnv``...), or another
custom env of the same module, and is not a wrapper (wrappers keep their own rules).

Env classes run to hundreds of lines and dozens of methods, and every rule asks about
their methods, their ``self.x`` stores and the names they use. ``ClassIndex`` walks a
class once and answers all of that from lists; ``EnvClasses`` memoizes one per class
and one ``FunctionIndex`` per method.
"""

from __future__ import annotations

import ast
from collections import defaultdict
from collections.abc import Callable, Iterable

from gymmigrate.facts import names as N
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import (
    FUNCTIONS,
    ModuleFacts,
    is_super_call,
    named_class_call,
    self_attribute,
    walk,
)
from gymmigrate.facts.receiver_classes import is_object
from gymmigrate.facts.receivers import Receivers

# Qualified names (without the gym/gymnasium prefix) of the mujoco-py era base class.
MUJOCO_BASES = frozenset({"envs.mujoco.MujocoEnv", "envs.mujoco.mujoco_env.MujocoEnv", "envs.mujoco.MuJocoPyEnv"})
DIRECT_ENV_BASES = frozenset({"Env", "core.Env", "GoalEnv", "core.GoalEnv"})


# The API methods gym <= 0.9 spelled with a leading underscore (``_reset`` for ``reset``).
HOOK_NAMES = frozenset({"step", "reset", "seed", "render", "close", "configure"})
# gym <= 0.9's ``Env.step`` called ``self._step`` and so on: each hook and its public name,
# in the order the rules report them.
UNDERSCORE_HOOKS = {"_step": "step", "_reset": "reset", "_seed": "seed", "_render": "render", "_close": "close", "_configure": "configure"}


def class_level_bindings(
    classdef: ast.ClassDef, methods: dict[str, ast.FunctionDef | ast.AsyncFunctionDef]
) -> tuple[dict[str, ast.Assign], frozenset[str]]:
    """The class body's aliases of gym < 0.9 hooks (``reset = _reset``: public name -> that
    assignment, naming a hook of the class), at its top level or under an ``if`` / ``try``
    there; and every public API name bound in those nested blocks (a ``def reset`` under
    ``if``, as custom_env writes it): such a name is the class's own, no hook may be
    renamed onto it. With such aliases the hooks keep their names (custom_env/reset.py)."""
    aliases: dict[str, ast.Assign] = {}
    bound: set[str] = set()

    def visit(statements: list[ast.stmt], nested: bool) -> None:
        for statement in statements:
            if isinstance(statement, ast.Assign) and isinstance(statement.value, ast.Name):
                hook = statement.value.id
                for target in statement.targets:
                    if isinstance(target, ast.Name) and target.id in HOOK_NAMES and hook == "_" + target.id and hook in methods:
                        aliases[target.id] = statement
            elif nested and isinstance(statement, (ast.FunctionDef, ast.AsyncFunctionDef)) and statement.name in HOOK_NAMES:
                bound.add(statement.name)
            elif isinstance(statement, (ast.If, ast.Try)):
                for block in (statement.body, statement.orelse, getattr(statement, "finalbody", [])):
                    visit(block, True)
                for handler in getattr(statement, "handlers", []):
                    visit(handler.body, True)

    visit(classdef.body, False)
    return aliases, frozenset(bound | set(aliases))


def hook_renames(
    classdef: ast.ClassDef,
    methods: dict[str, ast.FunctionDef | ast.AsyncFunctionDef],
    inherited: Callable[[], frozenset[str]],
) -> dict[str, str]:
    """The gym <= 0.9 hooks the class renames (public name -> hook): it defines ``_reset`` and
    nothing of the run above or beside it defines ``reset`` (``inherited``: the methods of
    its bases of the run, asked only when there is a hook). Gymnasium's base class calls
    none of the hooks. Not a hook the class publishes (``reset = _reset``: subclasses call it
    by name) nor ``_seed`` where the reset seeds through it: those keep their names."""
    aliases, bound = class_level_bindings(classdef, methods)
    kept = {alias.value.id for alias in aliases.values()}  # type: ignore[attr-defined]
    reset = methods.get("reset")
    if "reset" in aliases or (reset is not None and seeds_through_hook(reset)):
        # the reset written at the alias seeds through it (and so does that reset once
        # written, on the next pass): ``_seed`` is the class's own helper then
        kept.add("_seed")
    olds = [old for old in UNDERSCORE_HOOKS if old in methods and old not in kept]
    above = inherited() if olds else frozenset()
    return {
        UNDERSCORE_HOOKS[old]: old
        for old in olds
        if UNDERSCORE_HOOKS[old] not in methods and UNDERSCORE_HOOKS[old] not in above and UNDERSCORE_HOOKS[old] not in bound
    }


def seeds_through_hook(reset: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    """A Gymnasium reset (keyword ``seed`` and ``options``) that calls ``self._seed(seed)``."""
    if not {"seed", "options"} <= {a.arg for a in reset.args.kwonlyargs}:
        return False
    return any(
        isinstance(node, ast.Call)
        and self_attribute(node.func) == "_seed"
        and [a.id for a in node.args if isinstance(a, ast.Name)] == ["seed"]
        for node in walk(reset)
    )


def identifiers(node: ast.AST) -> list[str]:
    """Every identifier spelled in ``node``: variables, attribute and keyword names,
    parameters, def/class names. What a LibCST ``Name`` search finds, on ``ast``."""
    found: list[str] = []
    for child in walk(node):
        if isinstance(child, ast.Name):
            found.append(child.id)
        elif isinstance(child, ast.Attribute):
            found.append(child.attr)
        elif isinstance(child, ast.keyword) and child.arg is not None:
            found.append(child.arg)
        elif isinstance(child, ast.arg):
            found.append(child.arg)
        elif isinstance(child, (*FUNCTIONS, ast.ClassDef)):
            found.append(child.name)
        elif isinstance(child, (ast.Global, ast.Nonlocal)):
            found.extend(child.names)
    return found


def is_super_method_call(node: ast.AST | None, method: str) -> bool:
    """``super().method(...)`` or ``super(Cls, self).method(...)``."""
    return (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and node.func.attr == method
        and is_super_call(node.func.value)
    )


def env_base_call(facts: ModuleFacts, node: ast.AST | None, method: str, function: ast.AST | None) -> bool:
    """``gym.Env.method(self, ...)`` (Gymnasium's ``Env`` however imported) in ``function``, a
    method, handing on its own first parameter: every env class derives from Env, so this is
    the unbound call of Env's own method on this very instance, as ``Base.method(self)`` is."""
    if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)):
        return False
    receiver = node.func.value
    named = named_class_call(node, method, function, [receiver])
    return named is not None and any(N.strip_gym_prefix(q) in DIRECT_ENV_BASES for q in facts.qualified_names(receiver))


def self_calls(facts: ModuleFacts, classdef: ast.ClassDef, name: str) -> list[ast.Call]:
    """``self.<name>(...)`` calls in the methods of ``classdef`` (not of a class nested in it)."""
    return [
        call
        for call in facts.attribute_calls.get(name, ())
        if isinstance(call.func, ast.Attribute)
        and isinstance(call.func.value, ast.Name)
        and call.func.value.id == "self"
        and facts.enclosing_class(call) is classdef
    ]


def is_self_attribute(node: ast.AST, names: tuple[str, ...] | frozenset[str] | None = None) -> bool:
    return (
        isinstance(node, ast.Attribute)
        and isinstance(node.value, ast.Name)
        and node.value.id == "self"
        and (names is None or node.attr in names)
    )


class FunctionIndex:
    """One walk over a function (nested defs included, as a LibCST search would)."""

    def __init__(self, function: ast.AST) -> None:
        self.function = function
        self.nodes: dict[type, list[ast.AST]] = defaultdict(list)
        for node in walk(function):
            self.nodes[type(node)].append(node)
        for found in self.nodes.values():
            found.sort(key=lambda n: (getattr(n, "lineno", 0), getattr(n, "col_offset", 0)))
        self._names: set[str] | None = None

    @property
    def names(self) -> set[str]:
        """Every identifier in the function (computed on first use)."""
        if self._names is None:
            self._names = set(identifiers(self.function))
        return self._names

    def of(self, *kinds: type) -> list[ast.AST]:
        return [node for kind in kinds for node in self.nodes.get(kind, ())]

    def assigns_name(self, name: str) -> bool:
        """``name = ...`` or ``a, name = ...`` (a direct target, as the old matcher had it)."""
        for assign in self.nodes.get(ast.Assign, ()):
            for target in assign.targets:  # type: ignore[attr-defined]
                if isinstance(target, ast.Name) and target.id == name:
                    return True
                if isinstance(target, ast.Tuple) and any(isinstance(e, ast.Name) and e.id == name for e in target.elts):
                    return True
        return False


class ClassIndex:
    """A class's methods, ``self`` calls and stores, from one walk."""

    def __init__(self, classdef: ast.ClassDef) -> None:
        self.classdef = classdef
        self.methods: dict[str, ast.FunctionDef | ast.AsyncFunctionDef] = {}
        for statement in classdef.body:
            if isinstance(statement, FUNCTIONS):
                self.methods[statement.name] = statement
        self.self_calls: dict[str, list[ast.Call]] = defaultdict(list)  # self.<name>(...)
        self.assigns: list[ast.Assign] = []
        self.nodes: dict[type, list[ast.AST]] = defaultdict(list)
        for node in walk(classdef):
            self.nodes[type(node)].append(node)
            if isinstance(node, ast.Call) and is_self_attribute(node.func):
                self.self_calls[node.func.attr].append(node)  # type: ignore[attr-defined]
            elif isinstance(node, ast.Assign):
                self.assigns.append(node)
        for calls in self.self_calls.values():
            calls.sort(key=lambda c: (c.lineno, c.col_offset))
        self.assigns.sort(key=lambda a: (a.lineno, a.col_offset))

    def stores_to_self(self, attribute: str) -> list[ast.expr]:
        """Values assigned to ``self.<attribute>``, including the first slot of a tuple unpack."""
        values = []
        for assign in self.assigns:
            for target in assign.targets:
                if is_self_attribute(target, (attribute,)):
                    values.append(assign.value)
                elif isinstance(target, (ast.Tuple, ast.List)) and any(is_self_attribute(e, (attribute,)) for e in target.elts):
                    values.append(assign.value)
        return values


class EnvClasses:
    """Which classes of a module are custom envs, and their indexes. One per file."""

    def __init__(self, facts: ModuleFacts, receivers: Receivers) -> None:
        self.facts = facts
        self.receivers = receivers
        self._custom: dict[ast.ClassDef, bool] = {}
        self._classes: dict[ast.ClassDef, ClassIndex] = {}
        self._functions: dict[ast.AST, FunctionIndex] = {}

    @classmethod
    def of(cls, facts: ModuleFacts, receivers: Receivers) -> EnvClasses:
        return facts.memo(("env-classes", id(receivers)), lambda: cls(facts, receivers))

    def index(self, classdef: ast.ClassDef) -> ClassIndex:
        found = self._classes.get(classdef)
        if found is None:
            found = self._classes[classdef] = ClassIndex(classdef)
        return found

    def function(self, function: ast.AST) -> FunctionIndex:
        found = self._functions.get(function)
        if found is None:
            found = self._functions[function] = FunctionIndex(function)
        return found

    def is_custom_env(self, classdef: ast.ClassDef) -> bool:
        known = self._custom.get(classdef)
        if known is not None:
            return known
        self._custom[classdef] = False  # a cycle of local bases adds no evidence
        result = self._is_custom_env(classdef)
        self._custom[classdef] = result
        return result

    def _is_custom_env(self, classdef: ast.ClassDef) -> bool:
        receivers = self.receivers
        if receivers.is_gym_wrapper_class(classdef):
            return False
        if receivers.class_kind(classdef) in (EnvKind.GYM_ENV, EnvKind.OWN_API):
            return True
        for base in classdef.bases:
            if any(_is_builtin_env_class(q) for q in self.facts.qualified_names(base)):
                return True
            local = receivers.local_class(base)
            if local is not None and self.is_custom_env(local):
                return True
        return False

    def takes_render_mode(self, classdef: ast.ClassDef) -> bool:
        """Its constructor takes ``render_mode`` once migrated, so ``GridEnv()`` is a creation
        site like ``gym.make``: ``__init__`` has the parameter, or the class's
        ``render(self, mode)`` (``_render`` in gym <= 0.9) gets it there (GM405)."""
        return self.facts.memo(("takes-render-mode", id(classdef)), lambda: self._takes_render_mode(classdef))

    def _takes_render_mode(self, classdef: ast.ClassDef) -> bool:
        return self.is_custom_env(classdef) and self.would_take_render_mode(classdef)

    def would_take_render_mode(self, classdef: ast.ClassDef) -> bool:
        """``takes_render_mode`` were the class an env class: what the run decides of a
        class whose bases only another module shows to be env classes."""
        methods = self.index(classdef).methods
        init = methods.get("__init__")
        if init is not None:
            params = [a.arg for a in (*init.args.args, *init.args.kwonlyargs)]
            if "render_mode" in params:
                return True
        if self.render_mode_builtin_base(classdef) is not None:
            return True
        render = methods.get("render") or methods.get("_render")
        if render is None or not any(a.arg == "mode" for a in render.args.args):
            return False
        if "render" in class_level_bindings(classdef, methods)[0]:
            return False  # ``render = _render`` keeps render(mode), reported (custom_env/reset.py)
        if self.own_render_mode(classdef) is not None:
            return False  # its render(mode) is kept (GM405): no render_mode to give it
        return init is not None or not self.has_local_env_base(classdef)

    def render_mode_builtin_base(self, classdef: ast.ClassDef) -> ast.expr | None:
        """The class's first base where it is one of Gymnasium's own envs whose ``__init__``
        takes ``render_mode`` (``CartPoleEnv``) and the class, with no render(mode) of its
        own, either inherits that ``__init__`` or calls it exactly once from its own, by
        ``super()`` or by naming the base, with no ``**`` argument: custom_env/render.py hands
        ``render_mode`` on there (GM405). None otherwise."""
        return self.facts.memo(("render-mode-builtin-base", id(classdef)), lambda: self._render_mode_builtin_base(classdef))

    def builtin_render_mode_first_base(self, classdef: ast.ClassDef) -> ast.expr | None:
        """The class's first base where it is one of Gymnasium's own envs whose ``__init__``
        takes ``render_mode`` (``N.RENDER_MODE_ENV_CLASSES``), else None."""
        base = _first_base(classdef)
        if base is None or not any(N.takes_render_mode_builtin(q) for q in self.facts.qualified_names(base)):
            return None
        return base

    def _render_mode_builtin_base(self, classdef: ast.ClassDef) -> ast.expr | None:
        base = self.builtin_render_mode_first_base(classdef)
        if base is None:
            return None
        methods = self.index(classdef).methods
        render = methods.get("render") or methods.get("_render")
        if render is not None and any(a.arg == "mode" for a in render.args.args):
            return None  # its render(mode) migration decides (GM405)
        init = methods.get("__init__")
        if init is None:
            return base
        if init.args.kwarg is not None:
            return None  # ``**kwargs`` reach the base as they are
        calls = [n for n in walk(init) if isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute) and n.func.attr == "__init__"]
        if len(calls) != 1 or any(k.arg is None or k.arg == "render_mode" for k in calls[0].keywords):
            return None
        call = calls[0]
        assert isinstance(call.func, ast.Attribute)
        if is_super_call(call.func.value) or ast.dump(call.func.value) == ast.dump(base):
            return base
        return None

    def own_render_mode(self, classdef: ast.ClassDef) -> str | None:
        """The class's own way of choosing its render mode, which a migration to
        ``render_mode`` would bypass: a method that sets it (``set_render_mode``), or
        ``render(self, mode=None)`` falling back to an attribute of its own (``if mode is
        None: mode = self._render_mode``). Says how, for a message; None if it has none."""
        return self.facts.memo(("own-render-mode", id(classdef)), lambda: _own_render_mode(self.index(classdef).methods))

    def extends_gym_env_directly(self, classdef: ast.ClassDef) -> bool:
        """A base is ``gym.Env`` / ``gymnasium.Env`` itself (so ``super().reset`` only seeds)."""
        return any(
            N.strip_gym_prefix(q) in DIRECT_ENV_BASES for base in classdef.bases for q in self.facts.qualified_names(base)
        )

    def only_gym_env_bases(self, classdef: ast.ClassDef) -> bool:
        """Every base is ``gym.Env`` / ``gymnasium.Env`` itself (``object`` aside), and there is
        one: nothing else the class inherits from may define a method."""
        bases = [b for b in classdef.bases if not is_object(b)]
        return bool(bases) and not classdef.keywords and all(
            any(N.strip_gym_prefix(q) in DIRECT_ENV_BASES for q in self.facts.qualified_names(base)) for base in bases
        )

    def inherited_init(self, classdef: ast.ClassDef) -> str | None:
        """A base other than ``gym.Env`` itself whose ``__init__`` the class inherits
        (``HalfCheetahEnv``, a mix-in): its qualified name, or the base's text. An
        ``__init__`` added to the class would shadow it."""
        for base in classdef.bases:
            names = self.facts.qualified_names(base)
            if any(N.strip_gym_prefix(q) in DIRECT_ENV_BASES for q in names):
                continue
            if isinstance(base, ast.Name) and base.id == "object":
                continue
            return sorted(names)[0] if names else self.facts.segment(base)
        return None

    def has_local_env_base(self, classdef: ast.ClassDef) -> bool:
        """The class extends another class of this module (so ``__init__`` comes from there)."""
        return any(self.receivers.local_class(base) is not None for base in classdef.bases)

    def base_step_migrates(self, classdef: ast.ClassDef, named: ast.expr | None = None) -> bool | None:
        """What ``super().step(a)`` in the class runs after the migration, from its first
        base (the one ``super()`` reaches first), or ``Named.step(self, a)`` from the class
        it names (``named``: a base, the class itself or a class of this module it derives
        from): True when that step returns Gymnasium's five values (an env class of this
        module, or of another module of the run whose step the run migrates, or one of
        Gym's own env classes); None when the run does not show it (a class of no module of
        the run, one whose step keeps four fields)."""
        base = _first_base(classdef) if named is None else named
        if base is None:
            return None
        local = self.receivers.local_class(base)
        if local is not None:
            return True if self.is_custom_env(local) else None
        names = self.facts.qualified_names(base)
        if any(_is_builtin_env_class(q) for q in names) or self._run_env_class(names):
            return True
        return None

    def base_method_target(self, classdef: ast.ClassDef, node: ast.AST | None, method: str) -> ast.expr | None:
        """The class a call of a base's ``method`` in a method of ``classdef`` reaches:
        ``super().step(a)`` its first base, ``Base.step(self, a)`` the base it names, and
        ``Cls.step(self, a)`` the class itself or a class of this module it derives from
        (as a ``Name``). None for any other call, and for ``super()`` of a class with no base."""
        if is_super_method_call(node, method):
            return _first_base(classdef)
        function = self.facts.enclosing_function(node) if node is not None else None
        if function is None or self.facts.parent(function) is not classdef:
            return None
        named = named_class_call(node, method, function, classdef.bases)
        if named is not None:
            return named
        lineage = [ast.Name(id=c.name, ctx=ast.Load()) for c in self.receivers.local_lineage(classdef)]
        return named_class_call(node, method, function, lineage)

    def builtin_env_base(self, classdef: ast.ClassDef) -> bool:
        """The first base, the one ``super()`` reaches first, is one of Gym's own env classes
        (``CartPoleEnv``): its reset returns (obs, info) in Gymnasium, whatever the run does."""
        base = _first_base(classdef)
        if base is None or self.receivers.local_class(base) is not None:
            return False
        return any(_is_builtin_env_class(q) for q in self.facts.qualified_names(base))

    def has_run_env_base(self, classdef: ast.ClassDef) -> bool:
        """The first base is an env class of another module of the run whose step the run
        migrates (such a base may count steps for the class); Gym's own env classes, such
        as MujocoEnv, count none: TimeLimit does."""
        base = _first_base(classdef)
        if base is None or self.receivers.local_class(base) is not None:
            return False
        names = self.facts.qualified_names(base)
        return not any(_is_builtin_env_class(q) for q in names) and self._run_env_class(names)

    def _run_env_class(self, names: Iterable[str]) -> bool:
        """One of these names is an env class of another module of the run whose step the
        run migrates (not one it keeps on four fields)."""
        project = self.receivers.project
        return project is not None and any(
            project.call_kind(q) is EnvKind.GYM_ENV and not project.keeps_legacy_step(q) for q in names
        )

    def mujoco_base(self, classdef: ast.ClassDef) -> bool:
        return any(N.strip_gym_prefix(q) in MUJOCO_BASES for base in classdef.bases for q in self.facts.qualified_names(base))

    def legacy_mujoco_env_base(self, classdef: ast.ClassDef) -> str | None:
        """A base that is one of old Gym's own mujoco-py env classes (``gym.envs.mujoco.
        HalfCheetahEnv``, v2/v3): its qualified name. The import rules retarget it to
        Gymnasium's v4 class, a different base (mujoco bindings, a fixed observation space)."""
        for base in classdef.bases:
            for q in sorted(self.facts.qualified_names(base)):
                rest = N.strip_gym_prefix(q)
                if (
                    q.startswith("gym.")
                    and rest is not None
                    and rest.startswith("envs.mujoco.")
                    and rest not in MUJOCO_BASES
                    and _is_builtin_env_class(q)
                ):
                    return q
        return None

    def is_seeding_np_random(self, call: ast.AST | None) -> bool:
        """A call of ``gym.utils.seeding.np_random`` / ``gymnasium.utils.seeding.np_random``."""
        if not isinstance(call, ast.Call):
            return False
        return any(N.strip_gym_prefix(q) == "utils.seeding.np_random" for q in self.facts.qualified_names(call.func))


def _first_base(classdef: ast.ClassDef) -> ast.expr | None:
    """The base ``super()`` reaches first (``object`` aside)."""
    bases = [b for b in classdef.bases if not is_object(b)]
    return bases[0] if bases else None


def _is_builtin_env_class(qualified: str) -> bool:
    rest = N.strip_gym_prefix(qualified)
    return rest is not None and N.is_builtin_env_class_path(rest)


def _own_render_mode(methods: dict[str, ast.FunctionDef | ast.AsyncFunctionDef]) -> str | None:
    render = methods.get("render") or methods.get("_render")
    if render is None or not any(a.arg == "mode" for a in render.args.args):
        return None
    setters = sorted(name for name in methods if "render_mode" in name.lower() and name not in ("render", "_render"))
    if setters:
        return f"`{setters[0]}()` sets it"
    init = methods.get("__init__")
    if init is not None and _render_mode_is_a_flag(init):
        return "its `self.render_mode` is an on/off flag of its own, a bool in `__init__`, not Gymnasium's mode string"
    params = render.args.args
    index = next(i for i, a in enumerate(params) if a.arg == "mode")
    first_default = len(params) - len(render.args.defaults)
    default = render.args.defaults[index - first_default] if index >= first_default else None
    if not (isinstance(default, ast.Constant) and default.value is None):
        return None
    for statement in render.body:
        if not (isinstance(statement, ast.If) and ast.unparse(statement.test) == "mode is None"):
            continue
        for inner in statement.body:
            value = inner.value if isinstance(inner, ast.Assign) and [ast.unparse(t) for t in inner.targets] == ["mode"] else None
            if (
                isinstance(value, ast.Attribute)
                and isinstance(value.value, ast.Name)
                and value.value.id == "self"
                and value.attr != "render_mode"
            ):
                return f"`render(mode=None)` falls back to `self.{value.attr}`"
    return None


def _render_mode_is_a_flag(init: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    """``def __init__(self, render_mode=False)`` or ``self.render_mode = True``: the class
    already has a ``render_mode``, a bool of its own that Gymnasium's (``"human"``,
    ``"rgb_array"`` or None) would clash with."""
    params = [*init.args.posonlyargs, *init.args.args]
    defaults = dict(zip([p.arg for p in params[len(params) - len(init.args.defaults) :]], init.args.defaults))
    defaults.update({p.arg: d for p, d in zip(init.args.kwonlyargs, init.args.kw_defaults) if d is not None})
    default = defaults.get("render_mode")
    if isinstance(default, ast.Constant) and isinstance(default.value, bool):
        return True
    for node in walk(init):
        if (
            isinstance(node, ast.Assign)
            and isinstance(node.value, ast.Constant)
            and isinstance(node.value.value, bool)
            and any(self_attribute(t) == "render_mode" for t in node.targets)
        ):
            return True
    return False


def mode_can_stay_optional(function: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    """``render(self, mode="human", ...)`` can become ``render(self, mode=None, ...)`` in
    place: a ``mode`` parameter every parameter after which has a default (else the
    signature would not compile), in a body that hands no ``mode`` on to inner envs
    (``env.render(mode)``: the plain migration drops it). Callers that still pass a mode
    then keep working beside Gymnasium's render() without one (custom_env/render.py)."""
    args = function.args
    params = args.args
    mode_index = next((i for i, p in enumerate(params) if p.arg == "mode"), None)
    if mode_index is None:
        return False
    first_default = len(params) - len(args.defaults)
    if mode_index < first_default and first_default > mode_index + 1:
        return False
    for call in walk(function):
        if not (isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute) and call.func.attr == "render"):
            continue
        values = [*call.args, *(k.value for k in call.keywords)]
        if any(isinstance(v, ast.Name) and v.id == "mode" for v in values):
            return False
    return True
