"""PZ104 / PZ108: a custom parallel env's ``dones`` unpacked from the step of an object it holds.

``obs, rews, self.dones, infos = self.board.step(actions)`` (or a local ``dones``) takes
the per-agent dones of a simulation the env drives; ``del self.dones["__all__"]`` right
after it drops the simulation's own episode flag. Which of those dones are terminations
is settled only where the run sees every way they can come true: the held object is only
ever an instance of a class of this module (``self.board = Board(...)``) with no base
outside it, and neither that class nor its bases counts anything or tests a step limit
(``facts/step_counts.py``, the test GM504 settles a single-agent ``truncated=False``
with). Then its dones are the game's own ends: the store goes to ``terminations``, the
dels with it, and ``truncations`` starts all False beside it (the env's own step or
cycle limit, split by ``dones_split.py``, fills it). Anything else is one question for
the class, asked at the unpack (``question``): the dels and the return point at it.
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.facts.module import FUNCTIONS
from gymmigrate.facts.self_attributes import class_self_stores
from gymmigrate.facts.step_counts import counts_in
from gymmigrate.findings import FixKind
from gymmigrate.rules.pettingzoo.common import AGENT

if TYPE_CHECKING:
    from collections.abc import Callable, Hashable

    from gymmigrate.rules.pettingzoo.env_classes import EnvClasses


def dones_question(classdef: ast.ClassDef) -> Hashable:
    """What every use of a class's ``dones`` that is left to a person asks: how they split."""
    return ("PZ108", "dones split", id(classdef))


def inner_step_unpack(family: EnvClasses, target: ast.expr) -> tuple[ast.Assign, ast.expr] | None:
    """``target`` is the third of four names unpacked from ``<held>.step(...)``: that
    assignment and ``<held>``; else None."""
    holder = family.facts.parent(target)
    assign = family.facts.parent(holder) if isinstance(holder, (ast.Tuple, ast.List)) else None
    if not (isinstance(assign, ast.Assign) and assign.targets == [holder] and isinstance(assign.value, ast.Call)):
        return None
    func = assign.value.func
    if not (isinstance(func, ast.Attribute) and func.attr == "step"):
        return None
    if len(holder.elts) != 4 or holder.elts[2] is not target:  # type: ignore[union-attr]
        return None
    return assign, func.value


def trailing_dels(family: EnvClasses, assign: ast.Assign, spelled: str) -> list[ast.Delete]:
    """The ``del <spelled>[<constant>]`` statements right after ``assign`` in its block."""
    block = next(
        (body for body in _blocks(family.facts.parent(assign)) if assign in body),
        [],
    )
    found: list[ast.Delete] = []
    for statement in block[block.index(assign) + 1 :] if block else ():
        if not (
            isinstance(statement, ast.Delete)
            and statement.targets
            and all(
                isinstance(t, ast.Subscript) and isinstance(t.slice, ast.Constant) and family.facts.segment(t.value) == spelled
                for t in statement.targets
            )
        ):
            break
        found.append(statement)
    return found


def _blocks(parent: ast.AST | None) -> list[list[ast.stmt]]:
    return [getattr(parent, name) for name in ("body", "orelse", "finalbody") if isinstance(getattr(parent, name, None), list)]


def game_ends_only(family: EnvClasses, held: ast.expr) -> tuple[ast.ClassDef | None, str]:
    """The class whose step gives ``held.step()``'s dones, when they can only be the game's
    own ends (see the module docstring), and ""; else None and why not."""
    spelled = family.facts.segment(held)
    if not (isinstance(held, ast.Attribute) and isinstance(held.value, ast.Name) and family.receivers.is_self(held.value)):
        return None, f"`{spelled}` is not an attribute of the env"
    env = family.facts.enclosing_class(held)
    project = family.receivers.project
    if env is None or (project is not None and project.subclassed_elsewhere(env.name)):
        return None, f"a subclass in another module may store its own `{spelled}`"
    # What the env's own hierarchy stores, and what subclasses of it in this module store.
    values = family.receivers.self_attribute_values(held, held.attr) + [
        value for sub in _local_subclasses(family, env) for value in class_self_stores(family.facts, sub).get(held.attr, [])
    ]
    classes: list[ast.ClassDef] = []
    for value in values:
        classdef = family.receivers.local_class(value.func) if isinstance(value, ast.Call) else None
        if classdef is None:
            return None, f"`{spelled}` is not shown to hold only instances of a class of this module"
        if classdef not in classes:
            classes.append(classdef)
    if not classes:
        return None, f"`{spelled}` is not shown to hold only instances of a class of this module"
    if len(classes) != 1:
        return None, f"`{spelled}` holds instances of several classes"
    found = classes[0]
    chain = _local_chain(family, found)
    if chain is None:
        return None, f"`{found.name}` derives a class from outside this module"
    if not any(isinstance(m, FUNCTIONS) and m.name == "step" for c in chain for m in c.body):
        return None, f"`{found.name}` defines no step() of its own"
    counting = next((c for c in chain if counts_in(family.facts, c)), None)
    if counting is not None:
        return None, f"`{counting.name}` counts something or tests a step limit"
    return found, ""


def _local_subclasses(family: EnvClasses, classdef: ast.ClassDef) -> list[ast.ClassDef]:
    """The classes of this module that derive ``classdef``, at any depth."""
    found: list[ast.ClassDef] = []
    grew = True
    while grew:
        grew = False
        for other in family.facts.all_classes:
            if other is classdef or other in found:
                continue
            if any((base := family.receivers.local_class(b)) is classdef or base in found for b in other.bases):
                found.append(other)
                grew = True
    return found


def _local_chain(family: EnvClasses, classdef: ast.ClassDef) -> list[ast.ClassDef] | None:
    """The class and all its bases, when each is a class of this module (or ``object``)."""
    chain: list[ast.ClassDef] = []
    todo = [classdef]
    while todo:
        current = todo.pop()
        if current in chain:
            continue
        chain.append(current)
        for base in current.bases:
            if isinstance(base, ast.Name) and base.id == "object":
                continue
            local = family.receivers.local_class(base)
            if local is None:
                return None
            todo.append(local)
    return chain


def settled(family: EnvClasses, assign: ast.Assign, held: ast.expr, dels: list[ast.Delete]) -> tuple[ast.ClassDef | None, str]:
    """``game_ends_only``, where the unpack and its dels can also be rewritten in place."""
    inner, why = game_ends_only(family, held)
    last = dels[-1] if dels else assign
    if inner is not None and not (family.own_line(assign) and family.own_line(last)):
        return None, "the unpack shares its line with other code"
    return inner, why


def plan_inner_dones(
    family: EnvClasses,
    classdef: ast.ClassDef,
    assign: ast.Assign,
    held: ast.expr,
    spelled: str,
    rename: Callable[[str], None],
    dels: list[ast.Delete],
) -> bool:
    """Send the unpacked dones (``spelled``: ``self.dones`` or ``dones``) to the
    terminations where ``game_ends_only`` settles it, the ``dels`` with them, with the
    truncations all False after the last of them (True). Otherwise the class's one
    question, asked here (False: nothing planned)."""
    own = spelled.startswith("self.")
    code = "PZ108" if own else "PZ104"
    terminations, truncations = ("self.terminations", "self.truncations") if own else ("terminations", "truncations")
    inner, why = settled(family, assign, held, dels)
    last = dels[-1] if dels else assign
    if inner is None:
        family.report(
            assign,
            code,
            f"`{spelled}` takes the per-agent dones of `{family.facts.segment(held)}.step()`, which the run cannot "
            f"settle as the game's own ends ({why}; PettingZoo 1.21 split dones): unpack those ends into "
            f"`{terminations}`, put a step or time limit among them in `{truncations}` (all False if there is none), "
            "and return both dicts",
            FixKind.FLAG,
            question=dones_question(classdef),
        )
        return False
    rename("terminations")
    for statement in dels:
        for target in statement.targets:
            family.replace_text(target.value, terminations)  # type: ignore[attr-defined]
    family.plan.insert_after(last, f"{truncations} = {{{AGENT}: False for {AGENT} in {terminations}}}")
    family.report(
        assign,
        code,
        f"`{spelled}` split by meaning (PettingZoo 1.21): the dones of `{family.facts.segment(held)}.step()` go to "
        f"`{terminations}` (`{inner.name}` counts nothing and tests no step limit: they are the game's own ends), "
        f"and `{truncations}` starts all False",
        FixKind.AUTO,
    )
    return True
