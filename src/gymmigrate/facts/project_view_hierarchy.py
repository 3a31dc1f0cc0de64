"""What one file asks of the run about its classes' subclasses and bases in other modules
(``HierarchyView``, a part of ``ProjectView``): overrides, construction, step hooks, done causes.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from typing import TYPE_CHECKING

from gymmigrate.facts.done_causes import Cause, DoneCause, Limit
from gymmigrate.facts.kinds import EnvKind

if TYPE_CHECKING:
    from gymmigrate.facts.project import ProjectFacts


class HierarchyView:
    """The run's class hierarchies as one file sees them (``facts`` and ``path`` are
    ``ProjectView``'s)."""

    facts: ProjectFacts
    path: str

    def built_elsewhere(self, classname: str) -> bool:
        """Another module of the run calls this file's class ``classname``."""
        if (self.path, classname) in self.facts.called_elsewhere:
            return True  # a class with no ``__init__`` of its own, whose calls pass no parameter
        return any(
            path == self.path and qualname in (classname, f"{classname}.__init__") for path, qualname, _ in self.facts.param_kinds
        )

    def called_from_outside(self, classname: str) -> bool:
        """Another module of the run calls this file's class ``classname`` (builds one),
        with arguments or without (``built_elsewhere``: the calls that pass parameters)."""
        calls = self.facts.called_from_outside
        return self.built_elsewhere(classname) or (self.path, classname) in calls or (self.path, f"{classname}.__init__") in calls

    def built_from_outside(self, classname: str) -> bool:
        """Another module of the run builds an instance of this file's ``classname``: a call
        of it, or of its ``__init__`` other than a subclass's ``super().__init__(...)``
        (which builds the subclass); a class without ``__init__`` of its own called there."""
        calls = self.facts.built_from_outside
        return (
            (self.path, classname) in self.facts.called_elsewhere
            or (self.path, classname) in calls
            or (self.path, f"{classname}.__init__") in calls
        )

    def subclassed_elsewhere(self, classname: str) -> bool:
        """Another module of the run derives a class from this file's ``classname``."""
        return (self.path, classname) in self.facts.overrides

    def subclasses_elsewhere_without(self, classname: str, method: str) -> list[str]:
        """The subclasses of this file's ``classname`` in other modules of the run that do
        not define ``method`` themselves ("pkg/far.py:FarEnv")."""
        subs = self.facts.subclasses_of.get((self.path, classname), [])
        return [f"{path}:{name}" for path, name in subs if method not in self.facts.subclass_methods.get((path, name), frozenset())]

    def built_through_super_elsewhere(self, classname: str) -> bool:
        """Every subclass of this file's ``classname`` in another module runs its
        ``__init__`` only through its own ``super().__init__(...)``, which the join follows,
        and is subclassed nowhere else itself: what they pass reaches ``param_kinds``."""
        subs = self.facts.subclasses_of.get((self.path, classname), [])
        return bool(subs) and all(sub in self.facts.init_passers and sub not in self.facts.subclasses_of for sub in subs)

    def overridden_elsewhere(self, classname: str, method: str) -> list[str]:
        """Subclasses in other modules of the run that override ``classname.method``."""
        return self.facts.overrides.get((self.path, classname), {}).get(method, [])

    def called_in_hierarchy_elsewhere(self, classname: str, method: str) -> list[str]:
        """Classes of other modules of the run above or below ``classname`` (bases it
        imports, subclasses, at any depth) whose methods call ``self.<method>(...)``: the
        base's ``step`` reading a helper its subclass defines, as ("pkg/base.py:Base")."""
        start = (self.path, classname)
        below: dict[tuple[str, str], list[tuple[str, str]]] = self.facts.subclasses_of
        above: dict[tuple[str, str], list[tuple[str, str]]] = {}
        for base, subs in below.items():
            for sub in subs:
                above.setdefault(sub, []).append(base)
        found: list[str] = []
        for links in (above, below):
            seen = {start}
            todo = list(links.get(start, ()))
            while todo:
                other = todo.pop(0)
                if other in seen:
                    continue
                seen.add(other)
                if other[0] != self.path and method in self.facts.self_calls.get(other, ()):
                    found.append(f"{other[0]}:{other[1]}")
                todo += links.get(other, ())
        return found

    def called_below_elsewhere(self, classname: str, method: str) -> list[str]:
        """Classes of other modules of the run, below this file's ``classname`` at any depth,
        whose ``self.<method>(...)`` or ``super().<method>(...)`` reaches its ``method``, as
        "pkg/far.py:FarEnv" (``facts/project_hooks.py``; a ``self.seed(...)`` reaching a
        ``_seed`` is listed under ``_seed``)."""
        return self.facts.called_below.get((self.path, classname), {}).get(method, [])

    def hooks_renamed_above(self, qualified: str) -> frozenset[str]:
        """The gym <= 0.9 hooks (``_reset``) that the imported class of the run ``qualified``,
        or the base of it that defines each, renames: ``super()._reset()`` in a subclass
        here reaches a method the run renames ``reset``."""
        split = self.facts._split(qualified, self.path)
        return frozenset() if split is None else self.facts.renamed_above.get(split, frozenset())

    def called_on_instances_elsewhere(self, method: str) -> list[str]:
        """Other modules of the run that call ``x.<method>(...)`` on a receiver other than
        ``self``: one of them may be an instance of this file's class."""
        return sorted(path for path in self.facts.instance_calls.get(method, ()) if path != self.path)

    def contains_calls(self, name: str) -> list[str]:
        """Where the run calls ``contains()`` on a receiver read by ``name`` (``space`` or
        ``x.space``), as "utils.py:55", relative to this module's folder, in source order."""
        return _places(self.path, self.facts.contains_calls.get(name, ()))

    def mujoco_py_uses(self) -> list[str]:
        """Where the modules its imports connect this one to read the mujoco-py MujocoEnv's
        API outside such a class (``ProjectFacts.mujoco_py_uses``, ``import_components``):
        per module, its first such line and how many more ("agents/agent.py:94 and 23 more
        lines"), relative to this module's folder."""
        here = os.path.dirname(self.path)
        components = self.facts.import_components
        by_path: dict[str, list[int]] = {}
        for where, line in sorted(set(self.facts.mujoco_py_uses)):
            if components.get(where, where) == components.get(self.path, self.path):  # this module's project
                by_path.setdefault(where, []).append(line)
        return [
            f"{os.path.relpath(where, here)}:{lines[0]}" + (f" and {len(lines) - 1} more line{'s' if len(lines) > 2 else ''}" if len(lines) > 1 else "")
            for where, lines in by_path.items()
        ]

    def hook_followed_elsewhere(self, classname: str, method: str) -> bool:
        """Every override of ``classname``'s step hook ``method`` in other modules of the run
        can return five values with it (facts/step_hooks.py): they follow the base."""
        return method in self.facts.followed_hooks.get((self.path, classname), ())

    def helper_step_here(self, classname: str) -> bool:
        """This file's ``classname`` has a helper step its overrides in the run build on
        (facts/own_steps.py)."""
        return (self.path, classname) in self.facts.helper_steps

    def helper_step(self, qualified: str) -> bool:
        """``super().step(...)`` in a subclass of the imported name ``qualified`` reaches a
        helper step (the class itself, a re-export, a subclass defining no step)."""
        split = self.facts._split(qualified, self.path)
        return split is not None and split in self.facts.helper_step_names

    def steps_below_give_five(self, classname: str, method: str | None = None) -> int | None:
        """How many classes of other modules of the run below this file's ``classname`` (at
        any depth) define a step, where every step they and the classes of their own modules
        below them define gives five values once migrated (facts/own_steps.py); None where
        one may not: a subclass that is no env class the run migrates, keeps its legacy
        step, or returns what the run does not carry to five values. With ``method`` (the
        one calling ``self.step``) named, a subclass that defines it and never calls a
        base's never runs the call, nor do the classes below it: they are left out."""
        facts = self.facts
        steps = 0
        seen: set[tuple[str, str]] = set()
        cut = self._replacing(classname, method) if method is not None else set()
        todo = list(facts.subclasses_of.get((self.path, classname), ()))
        while todo:
            sub = todo.pop()
            if sub in seen:
                continue
            seen.add(sub)
            if sub in cut:
                continue
            if sub[0] in facts.blocked or sub not in facts.five_step_trees or sub in facts.legacy_steps or sub in facts.own_api_classes:
                return None
            if facts.call_kinds.get(sub) is not EnvKind.GYM_ENV:
                return None
            if "step" in facts.subclass_methods.get(sub, ()):
                steps += 1
            todo += facts.subclasses_of.get(sub, ())
        return steps

    def _replacing(self, classname: str, method: str) -> set[tuple[str, str]]:
        """The classes of other modules below this file's ``classname`` that never run its
        ``method``: one that defines it and calls no base's, and every class derived from
        that one (its definition precedes ``classname``'s in their MRO, and ``super()`` goes
        through it); not where one of them calls ``Cls.method(self)``, which may skip past
        it to ``classname``'s with the replacing class's step."""
        facts = self.facts
        below: list[tuple[str, str]] = []
        todo = list(facts.subclasses_of.get((self.path, classname), ()))
        while todo:
            sub = todo.pop()
            if sub not in below:
                below.append(sub)
                todo += facts.subclasses_of.get(sub, ())
        cut: set[tuple[str, str]] = set()
        for replacing in below:
            if method not in facts.subclass_methods.get(replacing, ()) or method in facts.base_calls.get(replacing, ()):
                continue
            tree: set[tuple[str, str]] = set()
            todo = [replacing]
            while todo:
                sub = todo.pop()
                if sub not in tree:
                    tree.add(sub)
                    todo += facts.subclasses_of.get(sub, ())
            if not any(method in facts.named_calls.get(sub, ()) for sub in tree):
                cut |= tree
        return cut

    def inherited_hooks(self, classname: str) -> frozenset[str]:
        """The step hooks that bases of ``classname`` in other modules migrate, which its
        overrides follow."""
        return self.facts.inherited_hooks.get((self.path, classname), frozenset())

    def mode_renders_below(self, classname: str) -> list[tuple[str, str]]:
        """The ``self.render(mode)`` calls of subclasses in other modules of the run that
        reach ``classname``'s render(), as ("pull.py:5", call)."""
        return self.facts.mode_renders_below.get((self.path, classname), [])

    def done_overrides(self, classname: str, method: str, index: int | None = None) -> list[DoneCause]:
        """Why what ``method`` returns is True in each override of it by subclasses in
        other modules of the run, at any depth (``Base`` <- ``Single`` <- ``Hover``); each
        limit names the module it is in. ``index``: why the value at that position of the
        tuples it returns is True."""
        found: list[DoneCause] = []
        seen: set[tuple[str, str]] = set()
        todo = list(self.facts.subclasses_of.get((self.path, classname), ()))
        while todo:
            sub = todo.pop(0)
            if sub in seen:
                continue
            seen.add(sub)
            if index is None:
                cause = self.facts.done_methods.get(sub, {}).get(method)
            else:
                items = self.facts.done_items.get(sub, {}).get(method, ())
                cause = items[index] if index < len(items) else None
            if cause is None and method in self.facts.subclass_methods.get(sub, ()):
                cause = DoneCause(Cause.UNKNOWN)  # an override that returns nothing, or no tuple of the base's shape
            if cause is not None:
                where = os.path.basename(sub[0])
                found.append(
                    DoneCause(
                        cause.cause,
                        tuple(Limit(limit.line, limit.text, where, limit.by_counter, limit.drawn) for limit in cause.limits),
                        held=tuple(Limit(read.line, read.text, where) for read in cause.held),
                    )
                )
            todo += self.facts.subclasses_of.get(sub, ())
        return found

    def init_attributes(self, qualified: str) -> frozenset[str]:
        """What an instance of the imported class of the run ``qualified`` certainly holds
        once constructed, its bases in any module followed (``facts/init_attributes.py``);
        empty for anything else."""
        split = self.facts._split(qualified, self.path)
        return frozenset() if split is None else self.facts.init_attributes.get(split, frozenset())

    def init_attributes_here(self, name: str) -> frozenset[str]:
        """``init_attributes`` of a class of this module."""
        return self.facts.init_attributes.get((self.path, name), frozenset())


def _places(path: str, found: Iterable[tuple[str, int]]) -> list[str]:
    """``[(path, line), ...]`` in source order as "utils.py:55", ":62" (the same file again),
    relative to the folder of the module at ``path``."""
    here = os.path.dirname(path)
    shown: list[str] = []
    previous = None
    for where, line in sorted(set(found)):
        shown.append(f":{line}" if where == previous else f"{os.path.relpath(where, here)}:{line}")
        previous = where
    return shown
