"""Which ``render`` calls pass a legacy mode, and which env classes must keep one.

A legacy ``x.render(mode)`` may reach an env class's ``render(self, mode)``
(``passes_mode``, unless the argument is certainly no mode string: ``not_a_mode_call``).
Where such a call's receiver cannot be traced to its creation (``creation.CreationFinder``),
the module's env classes keep ``render(self, mode)`` and take no ``render_mode``
(``render_kept_classes``), so constructing one is no creation site for the render rules
(``local_env_class_takes_render_mode``).
"""

from __future__ import annotations

import ast

from gymmigrate.facts import names as N
from gymmigrate.facts.creation import CreationFinder
from gymmigrate.facts.creation_shapes import first_argument
from gymmigrate.facts.env_classes import EnvClasses, mode_can_stay_optional
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts
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
    return EnvClasses.of(facts, receivers).takes_render_mode(classdef) and id(classdef) not in render_kept_classes(
        facts, receivers
    )


def render_kept_classes(facts: ModuleFacts, receivers: Receivers) -> frozenset[int]:
    """Local env classes (by id) whose ``render(self, mode)`` must stay as it is.

    A ``render`` call that passes a mode, on a receiver whose creation cannot be traced,
    may reach an instance of any env class of the module: removing ``mode`` from that
    class's render() would make the call a TypeError (custom_env/render.py keeps it).
    Such a class takes no ``render_mode``, so ``GridEnv()`` is then no creation site.
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
            return frozenset(id(c) for c in facts.all_classes if classes.is_custom_env(c))
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
            if classes.is_custom_env(classdef) and any(facts.enclosing_class(call) is not classdef for call in untraced)
        )

    return facts.memo(("render-kept-classes", 0), compute)


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
