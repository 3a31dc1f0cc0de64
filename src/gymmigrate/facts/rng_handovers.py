"""Where a module stores an ``np_random`` (GM505 across modules, ``rules/rng.py``).

A Gym env seeded by ``seeding.np_random`` hands its generator to an object it holds
(``self.robot.np_random = self.np_random``): that object's class, perhaps in another module
that never sets ``np_random`` itself, draws from a Generator and needs the same rewrite
(``randint`` -> ``integers``). Each store is recorded with whether it goes to another
object (a handover) and whether the value is sure to be a Generator; the join
(``ProjectFacts.rng_stores``) lets a class that only reads ``self.np_random`` follow the
run's handovers when every store of the run is a Generator.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import names as N
from gymmigrate.facts.env_classes import EnvClasses, is_self_attribute
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.module import ModuleFacts, walk
from gymmigrate.facts.receivers import Receivers

NP_RANDOM = ("np_random", "_np_random")
# (line, to another object rather than ``self``, the value is a Generator, the class whose
# instance the statement just before built into that object: ``s = Scene()`` then
# ``s.np_random = self.np_random`` gives "Scene"; "" for any other store)
Store = tuple[int, bool, bool, str]


def reads_np_random(facts: ModuleFacts) -> bool:
    """Some code of the module reads an ``np_random`` (draws from it, hands it on), beyond
    storing one (``self.np_random, seed = seeding.np_random(seed)``, the seeding function
    itself): where none does, nothing of the module draws from a generator left unseeded."""
    if "np_random" not in facts.text:
        return False

    def compute() -> bool:
        for node in walk(facts.tree):
            name = node.attr if isinstance(node, ast.Attribute) else node.id if isinstance(node, ast.Name) else None
            if name not in NP_RANDOM or not isinstance(node.ctx, ast.Load):  # type: ignore[attr-defined]
                continue
            if any(N.strip_gym_prefix(q) == "utils.seeding.np_random" for q in facts.qualified_names(node)):
                continue
            return True
        return False

    return facts.memo(("reads-np-random", id(facts.tree)), compute)


def rng_stores(facts: ModuleFacts, receivers: Receivers) -> tuple[Store, ...]:
    if "np_random" not in facts.text:
        return ()
    env = EnvClasses.of(facts, receivers)
    found: list[Store] = []
    for node in walk(facts.tree):
        if not isinstance(node, ast.Assign):
            continue
        for target in node.targets:
            slots = target.elts if isinstance(target, (ast.Tuple, ast.List)) else [target]
            for position, slot in enumerate(slots):
                if not (isinstance(slot, ast.Attribute) and slot.attr in NP_RANDOM):
                    continue
                handover = not is_self_attribute(slot)
                if isinstance(target, (ast.Tuple, ast.List)):
                    generator = position == 0 and env.is_seeding_np_random(node.value)
                else:
                    generator = _generator_value(facts, receivers, env, node.value)
                built = _built_just_before(facts, node, slot.value) if handover else ""
                found.append((node.lineno, handover, generator, built))
    return tuple(found)


def _built_just_before(facts: ModuleFacts, store: ast.Assign, receiver: ast.expr) -> str:
    """The class name ``Name(...)`` in ``receiver = Name(...)``, where that is the statement
    right before ``store`` in the same block: nothing ran on the new object in between, so
    its methods first draw from the value handed over (whatever a base set in __init__)."""
    if not isinstance(receiver, ast.Name):
        return ""
    found = Flow.of(facts).block_of(store)
    if found is None or found[1] == 0:
        return ""
    block, index = found
    before = block[index - 1]
    if (
        isinstance(before, ast.Assign)
        and len(before.targets) == 1
        and isinstance(before.targets[0], ast.Name)
        and before.targets[0].id == receiver.id
        and isinstance(before.value, ast.Call)
        and isinstance(before.value.func, (ast.Name, ast.Attribute))
    ):
        func = before.value.func
        return func.id if isinstance(func, ast.Name) else func.attr
    return ""


def _generator_value(facts: ModuleFacts, receivers: Receivers, env: EnvClasses, value: ast.expr) -> bool:
    """``seeding.np_random(s)[0]``, or ``self.np_random`` of a Gym env class whose own stores
    of it are all ``seeding.np_random`` (none: Env's own, a Generator)."""
    if isinstance(value, ast.Subscript) and env.is_seeding_np_random(value.value):
        return isinstance(value.slice, ast.Constant) and value.slice.value == 0
    if isinstance(value, ast.Name):
        # ``np_random, seed = seeding.np_random()`` then ``robot.np_random = np_random``
        bindings = facts.bindings_of(value)
        return bool(bindings) and all(_bound_from_seeding(facts, env, b) for b in bindings)
    if not is_self_attribute(value, NP_RANDOM):
        return False
    classdef = facts.enclosing_class(value)
    if classdef is None or not (receivers.class_kind(classdef).is_gym or env.is_custom_env(classdef)):
        return False
    index = env.index(classdef)
    stores = index.stores_to_self("np_random") + index.stores_to_self("_np_random")
    return all(env.is_seeding_np_random(v) for v in stores)


def _bound_from_seeding(facts: ModuleFacts, env: EnvClasses, target: ast.AST) -> bool:
    parent = facts.parent(target)
    if isinstance(parent, (ast.Tuple, ast.List)) and parent.elts and parent.elts[0] is target:
        assign = facts.parent(parent)
        return isinstance(assign, ast.Assign) and env.is_seeding_np_random(assign.value)
    if isinstance(parent, ast.Assign) and isinstance(parent.value, ast.Subscript):
        value = parent.value
        return env.is_seeding_np_random(value.value) and isinstance(value.slice, ast.Constant) and value.slice.value == 0
    return False
