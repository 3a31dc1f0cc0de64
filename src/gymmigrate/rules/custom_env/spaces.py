"""GM511: an env class that ``gymnasium.make`` builds but that never sets a space, or whose
space is a plain list or tuple of spaces (report only).

gym 0.21's ``Env`` gave every env ``action_space = None`` and ``observation_space = None``;
Gymnasium's only annotates them, and the env checker ``make`` puts around every env raises
``AttributeError: The environment must specify an observation space`` the moment the env is
built. Asked once at the class, where an entry point of the run makes it (the class itself or
a registered def that constructs it) and neither the class nor a base sets the space by the
end of its construction (``facts/space_setters.py``). Where two made classes or more
inherit the unset spaces from one base whose ``__init__`` they run (single bases all the
way up), it is asked once at the highest such base, naming them; each gets a note.

A space stored as a list or tuple display (``self.action_space = [spaces.Discrete(5) for _ in
agents]``, a multi-agent env written before PettingZoo) is no ``Space``: gym <= 0.23 never looked,
while Gymnasium's checker raises ``TypeError: action space does not inherit from
gymnasium.spaces.Space`` and wrappers read ``.shape`` or ``.sample()`` from it. Asked once at the
class wherever it is built, since a list is never a space whatever it holds.

Source: Gymnasium 1.4 ``wrappers/common.py`` (``PassiveEnvChecker.__init__``), ``core.py``.
"""

from __future__ import annotations

import ast
import os

from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import (
    ModuleFacts,
    call_argument,
    own_returns,
    self_attribute,
    string_value,
)
from gymmigrate.facts.receivers import Receivers
from gymmigrate.facts.self_attributes import self_stores
from gymmigrate.facts.space_setters import (
    SPACES,
    local_unset_owner,
    local_unset_spaces,
    registered_here,
)
from gymmigrate.facts.summaries.defs import named_ids
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.custom_env.common import ClassDecision
from gymmigrate.rules.spaces.values import LIST_MUTATORS, SpaceValues


def decide_unset_spaces(decision: ClassDecision) -> None:
    classdef = decision.classdef
    family = decision.family
    facts, receivers = family.facts, family.receivers
    profile = family.context.profile
    if profile.imports_gymnasium and not profile.imports_gym:
        # written for Gymnasium: no legacy default was ever there. A module that imports
        # neither gets its Env from a base of the run (``class Cart(SimBase)``), which the
        # join below follows to gym.Env, so it is asked like the base's own module.
        return
    if facts.classes.get(classdef.name) is not classdef or receivers.class_kind(classdef) is not EnvKind.GYM_ENV:
        return
    project = receivers.project
    unset = project.unset_spaces(classdef.name) if project is not None else frozenset()
    owner: str | None = None  # the base GM511 asks at instead
    heirs: list[tuple[str, frozenset[str], bool]] = []  # (subclass, its spaces, made by nothing)
    if project is not None:
        above = project.unset_owner(classdef.name)
        owner = f"`{above[1]}` ({_shown(decision, above[0])})" if above is not None else None
        heirs = [(name, spaces, unmade) for _, name, spaces, unmade in project.unset_heirs(classdef.name)]
    if not unset and not heirs:
        # ``register(id=..., entry_point=Sim)`` in this module (a run of one file, or an entry
        # point the join does not read: the class object itself)
        made = facts.memo(("registered-here", 0), lambda: registered_here(facts, receivers, None))
        unset = (local_unset_spaces(facts, receivers, classdef) or frozenset()) if classdef.name in made else frozenset()
        owners = facts.memo(("unset-owners", 0), lambda: _local_owners(facts, receivers, made))
        if unset and (above_here := owners.get(classdef.name)) is not None:
            owner = f"`{above_here.name}` (line {above_here.lineno})"
        heirs = [
            (name, local_unset_spaces(facts, receivers, facts.classes[name]) or frozenset(), _made_by_nothing_here(facts, name))
            for name, above_here in owners.items()
            if above_here is classdef
        ]
    if owner is not None:
        # its base's construction leaves them unset as well and runs in this class's: set there,
        # they are set here too, so the base's item asks once for the whole hierarchy
        named = " and ".join(f"`{space}`" for space in SPACES if space in unset)
        decision.report(
            classdef,
            "GM511",
            f"`{classdef.name}` leaves {named} unset once built as its base {owner} does, whose __init__ it runs: "
            "the GM511 item at that base asks it once for its subclasses",
            FixKind.FLAG,
            Tier.NOTE,
        )
        return
    made_here = bool(unset)
    unset = unset.union(*(spaces for _, spaces, _ in heirs))
    if not unset:
        return
    missing = [space for space in SPACES if space in unset]
    named = " and ".join(f"`{space}`" for space in missing)
    first = missing[0].split("_")[0]
    subclasses = ", ".join(f"`{name}`" for name, _, _ in heirs)
    what, run = ("subclass", "runs") if len(heirs) == 1 else ("subclasses", "run")
    unmade = all(nothing for _, _, nothing in heirs) and (
        not made_here or (project.made_by_nothing(classdef.name) if project is not None else _made_by_nothing_here(facts, classdef.name))
    )
    who = (
        f"`{classdef.name}`{f' (and its registered {what} {subclasses}, which {run} its __init__)' if heirs and made_here else ''}"
        if made_here or not heirs
        else f"`{classdef.name}`'s registered {what} {subclasses}, which {run} its __init__,"
    )
    leaves = "leaves" if made_here and not heirs or not made_here and len(heirs) == 1 else "leave"
    if unmade:
        # registered, but no module of the run names its id: no make of the run builds it,
        # and a make elsewhere met the same unset spaces under gym (its reset raised first)
        decision.report(
            classdef,
            "GM511",
            f"{who} {leaves} {named} unset once built; registered, but no make of the run names the id: "
            f"where something else makes it, the env checker `gymnasium.make` puts around it raises AttributeError "
            f"(\"The environment must specify an {first} space\")",
            FixKind.FLAG,
            Tier.NOTE,
        )
        return
    decision.report(
        classdef,
        "GM511",
        f"{who} {leaves} {named} unset once built (gym 0.21's Env had None there; Gymnasium's has no default), and an entry "
        f"point of the run makes {'them' if heirs else 'it'}: the env checker `gymnasium.make` puts around it raises AttributeError (\"The environment "
        f"must specify an {first} space\") where no wrapper in between sets one; set "
        + " and ".join(f"`self.{space}`" for space in missing)
        + (f" in `{classdef.name}.__init__`" if heirs else " in `__init__`")
        + ", or register (or make) it with `disable_env_checker=True`",
        FixKind.FLAG,
    )


def _local_owners(facts: ModuleFacts, receivers: Receivers, made: frozenset[str]) -> dict[str, ast.ClassDef]:
    """A run of this module alone: each made class that leaves spaces unset -> the base GM511
    asks at instead (``local_unset_owner``), where that base covers two made classes or more
    (itself among them when made): one made class keeps its own item."""
    groups: dict[int, list[str]] = {}
    tops: dict[int, ast.ClassDef] = {}
    for name in made:
        classdef = facts.classes.get(name)
        if classdef is None or not local_unset_spaces(facts, receivers, classdef):
            continue
        top = local_unset_owner(facts, receivers, classdef)
        if top is not classdef:
            groups.setdefault(id(top), []).append(name)
            tops[id(top)] = top
    owners: dict[str, ast.ClassDef] = {}
    for key, names in groups.items():
        top = tops[key]
        if len(names) + (top.name in made and bool(local_unset_spaces(facts, receivers, top))) >= 2:
            owners.update((name, top) for name in sorted(names))
    return owners


def _shown(decision: ClassDecision, path: str) -> str:
    """A module of the run as the item shows it: relative to the reporting module."""
    here = os.path.abspath(decision.family.context.path)
    if os.path.abspath(path) == here:
        return "this file"
    return os.path.relpath(path, os.path.dirname(here))


def _made_by_nothing_here(facts: ModuleFacts, name: str) -> bool:
    """A run of this module alone: every ``register()`` naming class ``name`` as its entry
    point passes a literal id that no other string of the module names, the module names
    another id it registers, and every make() of the module passes a literal id
    (``ProjectFacts.unmade_classes`` for one module)."""
    named, opaque = named_ids(facts)
    if opaque:
        return False
    ids = []
    others = False  # the module makes another id it registers: its users are here
    for call in (*facts.calls_by_name.get("register", ()), *facts.attribute_calls.get("register", ())):
        entry = call_argument(call, 1, "entry_point")
        if entry is None:
            continue
        text = string_value(entry)
        if text is None and isinstance(entry, ast.BinOp) and isinstance(entry.right, ast.Constant):
            text = string_value(entry.right)  # ``__name__ + ":Class"``
        if text is None and isinstance(entry, ast.Name):
            text = ":" + entry.id
        env_id = call_argument(call, 0, "id")
        literal = string_value(env_id) if env_id is not None else None
        if text is None or text.rpartition(":")[2] != name:
            others = others or literal in named
            continue
        ids.append(literal)
    return others and bool(ids) and None not in ids and not (set(ids) & named)


def decide_list_spaces(decision: ClassDecision) -> None:
    """An env class whose ``action_space``/``observation_space`` is a list or tuple display."""
    classdef = decision.classdef
    family = decision.family
    facts, receivers = family.facts, family.receivers
    if not family.context.profile.imports_gym or receivers.class_kind(classdef) is not EnvKind.GYM_ENV:
        return  # code written for Gymnasium met the checker already
    found: list[tuple[str, ast.expr]] = []
    for space in SPACES:
        displays = _list_displays(facts, SpaceValues(facts, receivers), classdef, space)
        if displays:
            found.append((space, displays[0]))
    if not found:
        return
    named = " and ".join(f"`{space}` (line {value.lineno})" for space, value in found)
    first = found[0][0].split("_")[0]
    message = (
        f"`{classdef.name}` sets {named} to a plain list (or tuple) of spaces, which is no Space: the env checker `gymnasium.make` puts "
        f'around it raises TypeError ("{first} space does not inherit from gymnasium.spaces.Space"), and wrappers that read '
        "`.shape` or `.sample()` fail; where the list is fixed make it `spaces.Tuple([...])` (indexing and `len()` still work), "
        "or keep the list and make the env with `disable_env_checker=True` (or build it directly, never through make)"
    )
    mutated = _mutations(facts, classdef, {space for space, _ in found})
    if mutated:
        message += (
            f"; {', '.join(mutated)} change{'s' if len(mutated) == 1 else ''} it in place, which a Tuple space cannot do: "
            "assign a new Tuple there, or keep the list"
        )
    decision.report(classdef, "GM511", message, FixKind.FLAG)


def _list_displays(facts: ModuleFacts, spaces: SpaceValues, classdef: ast.ClassDef, space: str) -> list[ast.expr]:
    """The list or tuple displays the class stores as ``space`` (in a method as ``self.<space>``,
    or in its body), where no store of it is a space: ``self.action_space = []`` that a loop
    fills and a later ``spaces.Tuple(self.action_space)`` replaces is a builder, not the space.
    Empty where a store is one the class cannot show (``self.action_space += ...``)."""
    stored = self_stores(facts, classdef, space)
    if stored is None:
        return []
    values = list(stored)
    for statement in classdef.body:
        if isinstance(statement, ast.Assign) and any(isinstance(t, ast.Name) and t.id == space for t in statement.targets):
            values.append(statement.value)
    displays = [value for value in values if _is_display(facts, value)]
    if not displays or any(spaces.space_class(value) is not None for value in values):
        return []
    return displays


def _is_display(facts: ModuleFacts, value: ast.expr) -> bool:
    """A list or tuple built in place, or a name every binding of which is one."""
    if isinstance(value, (ast.List, ast.Tuple, ast.ListComp)):
        return True
    if isinstance(value, ast.BinOp) and isinstance(value.op, ast.Mult):
        return isinstance(value.left, (ast.List, ast.Tuple)) or isinstance(value.right, (ast.List, ast.Tuple))  # ``[space] * n``
    if isinstance(value, ast.Name):
        bound = facts.assigned_values(value) or []
        return bool(bound) and all(isinstance(v, (ast.List, ast.Tuple, ast.ListComp)) for v in bound)
    return False


def _mutations(facts: ModuleFacts, classdef: ast.ClassDef, names: set[str]) -> list[str]:
    """``self.<space>.append(...)`` and the like in the class: the lines that change the list."""
    found = []
    for mutator in LIST_MUTATORS:
        for call in facts.attribute_calls.get(mutator, ()):
            held = call.func.value if isinstance(call.func, ast.Attribute) else None
            if (
                isinstance(held, ast.Attribute)
                and held.attr in names
                and self_attribute(held) is not None
                and facts.enclosing_class(call) is classdef
            ):
                found.append((call.lineno, f"`self.{held.attr}.{mutator}()` (line {call.lineno})"))
    return [text for _, text in sorted(found)]


# The methods whose returned observation is the env's: step's first item, reset's value
_OBSERVING = frozenset({"step", "reset", "_step", "_reset"})
# numpy conversions that hand the value on as an array (``np.asarray(self.observation_space)``)
_ARRAY_OF = frozenset({"asarray", "array", "copy", "ravel", "float32"})


def decide_observation_stores(decision: ClassDecision) -> None:
    """An env class that keeps its observation in ``self.observation_space`` (or a value in
    ``self.action_space``) outside ``__init__``: gym never looked, Gymnasium's env checker
    asks for a Space there. Proved where the class returns that attribute as its observation
    (from step or reset), or stores a number or a numpy call there; anything else is left."""
    classdef = decision.classdef
    family = decision.family
    facts, receivers = family.facts, family.receivers
    profile = family.context.profile
    if profile.imports_gymnasium and not profile.imports_gym:
        return  # code written for Gymnasium met the checker already
    if receivers.class_kind(classdef) is not EnvKind.GYM_ENV:
        return
    returned = _returned_as_observation(facts, classdef)
    values = SpaceValues(facts, receivers)
    for method in classdef.body:
        if not isinstance(method, (ast.FunctionDef, ast.AsyncFunctionDef)) or method.name == "__init__":
            continue
        for node in ast.walk(method):
            if not (isinstance(node, ast.Assign) and len(node.targets) == 1):
                continue
            space = self_attribute(node.targets[0])
            if space not in SPACES or values.space_class(node.value) is not None:
                continue  # a space rebuilt outside __init__ (``spaces.Box(...)`` for a new size) is one
            why = (
                "it returns that attribute as its observation"
                if space in returned
                else "a number"
                if _is_number(node.value)
                else f"`{facts.segment(node.value.func)}(...)` returns an array"
                if isinstance(node.value, ast.Call) and _numpy_call(facts, node.value)
                else None
            )
            if why is None:
                continue
            decision.report(
                node,
                "GM511",
                f"`{classdef.name}` stores a value that is no Space in `self.{space}` in {method.name}() ({why}): the env "
                f"checker `gymnasium.make` puts around it raises TypeError (\"{space.split('_')[0]} space does not inherit "
                f"from gymnasium.spaces.Space\"); set `self.{space}` to the Space once in `__init__` and keep the value in "
                "another attribute",
                FixKind.FLAG,
            )
            return  # once per class, at the first such store


def _returned_as_observation(facts: ModuleFacts, classdef: ast.ClassDef) -> set[str]:
    """The spaces (``observation_space``) that step returns as its first item or reset as its
    value (or its first item), bare or through a numpy conversion."""
    found: set[str] = set()
    for method in classdef.body:
        if not isinstance(method, (ast.FunctionDef, ast.AsyncFunctionDef)) or method.name not in _OBSERVING:
            continue
        for ret in own_returns(method):
            value = ret.value
            if isinstance(value, ast.Tuple) and value.elts:
                value = value.elts[0]
            elif method.name.endswith("step"):
                continue  # a step's value is its tuple, never the observation alone
            if isinstance(value, ast.Call) and len(value.args) == 1 and _numpy_call(facts, value) and value.func.attr in _ARRAY_OF:  # type: ignore[attr-defined]
                value = value.args[0]
            space = self_attribute(value)
            if space in SPACES:
                found.add(space)
    return found


def _is_number(value: ast.expr) -> bool:
    if isinstance(value, ast.UnaryOp) and isinstance(value.op, ast.USub):
        value = value.operand
    return isinstance(value, ast.Constant) and type(value.value) in (int, float)


def _numpy_call(facts: ModuleFacts, call: ast.Call) -> bool:
    """``np.zeros(...)``, ``numpy.random.rand(...)``: a function of numpy, which returns an array
    or a number, never a Space."""
    return isinstance(call.func, ast.Attribute) and any(q.startswith("numpy.") for q in facts.qualified_names(call.func))
