"""What one file asks of the run about registration (``RegistryView``, a part of
``ProjectView``): the ids and entry points the run registers, and what their classes need.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from gymmigrate.facts.kinds import EnvKind

if TYPE_CHECKING:
    from gymmigrate.facts.project import ProjectFacts


class RegistryView:
    """The run's registrations as one file sees them (``facts`` and ``path`` are ``ProjectView``'s)."""

    facts: ProjectFacts
    path: str

    def env_classes_named(self, name: str) -> list[str]:
        """The modules of the run that define a Gym env class ``name`` (paths relative to this
        module's folder): what an entry point naming ``name`` in a module gym lacked meant."""
        here = os.path.dirname(self.path)
        methods = name + "."
        return sorted(
            os.path.relpath(path, here)
            for (path, bound), kind in self.facts.call_kinds.items()
            if bound == name
            and kind in (EnvKind.GYM_ENV, EnvKind.OWN_API)
            # defined there (a Gym env class of its own, or a subclass of one with methods), not re-exported
            and (name in self.facts.env_classes.get(path, ()) or any(d.startswith(methods) for d in self.facts.defs.get(path, ())))
        )

    def step_action_of_id(self, env_id: str) -> str | None:
        """The name of the action parameter (the first after ``self``) of the ``step`` of the
        class the run registers ``env_id`` for (``"pkg:Task-v0"`` names ``Task-v0``), where that
        class defines step itself; None where the run does not tell."""
        found = self.facts.id_classes.get(env_id.rpartition(":")[2])
        if found is None:
            return None
        params = self.facts.def_params.get((found[0], found[1] + ".step"), ())
        return params[1] if len(params) > 1 else None

    def class_of_id(self, env_id: str) -> tuple[str, str] | None:
        """(module path, class) of the class of the run that ``make(env_id)`` builds
        (``"pkg:Task-v0"`` names ``Task-v0``): the run registers that literal id for it, and
        every registration of the run spells its id and entry point, so no other may
        replace it. None where the run does not tell."""
        if None in self.facts.registered_ids or self.facts.registers_from_data:
            return None
        return self.facts.id_classes.get(env_id.rpartition(":")[2])

    def render_takes_of_id(self, env_id: str, keywords: tuple[str, ...], positional: int = 0, modeless: bool = False) -> str | None:
        """The class of the run defining the render() that ``make(env_id)``'s class has
        (its own, or a base's of another module of the run, each class with one base there),
        where that render (``_render`` in gym <= 0.9) takes ``positional`` arguments after
        ``self`` and every one of ``keywords`` (``close``, ``record_dir``...) as its own
        parameters, and, with ``modeless``, takes no ``mode`` (a render the run leaves as it
        is, not one drawing only with a render_mode); else None."""
        current = self.class_of_id(env_id)
        seen = set()
        while current is not None and current not in seen:
            seen.add(current)
            for method in ("render", "_render"):
                params = self.facts.def_params.get((current[0], f"{current[1]}.{method}"))
                if params is not None:
                    named = params[1 + positional :]
                    takes = len(params) > positional and all(k in named for k in keywords) and not (modeless and "mode" in params)
                    return current[1] if takes else None
            bases = [base for base, subs in self.facts.subclasses_of.items() if current in subs]
            current = bases[0] if len(bases) == 1 else None
        return None

    def seed_class_of_id(self, env_id: str) -> str | None:
        """The class of the run that keeps seed() which the run registers ``env_id`` for."""
        return self.facts.seed_ids.get(env_id)

    def plugin_calls(self) -> tuple[tuple[str, str | None], ...]:
        """The register functions of ``gym.envs`` entry points this module must call on
        import, each with the namespace gym registered its ids in (None: the root)."""
        return self.facts.plugin_calls.get(self.path, ())

    def unset_spaces(self, name: str) -> frozenset[str]:
        """The spaces a class of this module leaves unset with its bases, where an entry point
        of the run makes it (the class itself, or a registered def that constructs it)."""
        return self.facts.unset_spaces.get((self.path, name), frozenset())

    def unset_owner(self, name: str) -> tuple[str, str] | None:
        """For a class of this module ``unset_spaces`` names: the base of the run GM511 asks
        at instead (path, class), whose construction leaves the same spaces unset."""
        return self.facts.unset_owner.get((self.path, name))

    def unset_heirs(self, name: str) -> list[tuple[str, str, frozenset[str], bool]]:
        """The made classes whose unset spaces GM511 asks about at this module's ``name``:
        (path, class, the spaces, made by nothing of the run)."""
        return [
            (path, heir, self.facts.unset_spaces[(path, heir)], (path, heir) in self.facts.unmade_classes)
            for path, heir in sorted(self.facts.unset_heirs.get((self.path, name), ()))
        ]

    def made_by_nothing(self, name: str) -> bool:
        """A class of this module whose spaces are unset (``unset_spaces``) that every
        registration names by a literal id no module of the run names, while every make() of
        the run passes a literal id: nothing of the run makes it."""
        return (self.path, name) in self.facts.unmade_classes

    def may_register(self, env_id: str) -> bool:
        """The run may register ``env_id`` with the Gym registry: it registers that literal,
        or ids it does not spell as literals."""
        ids = self.facts.registered_ids
        return env_id in ids or None in ids

    def registered_here(self, name: str) -> bool:
        """A class of this module that the run registers as an ``entry_point``."""
        return (self.path, name) in self.facts.registered_classes

    def reached_from_outside(self, name: str) -> bool:
        """Code of the run beyond this module may get hold of its env class ``name``:
        another module imports this one, or registers ``name`` (or any class, from
        entry points that are no literal) for ``make`` to build."""
        return bool(self.facts.importers.get(self.path)) or self.registered_here(name) or self.facts.registers_from_data

    def non_space_env(self, module: str, name: str) -> tuple[str, str, str] | None:
        """For ``module:name`` as an ``entry_point`` spells it, a class of the run whose
        spaces are not Spaces: (attribute, space class, what that class derives from)."""
        path = self.facts.modules.get(module)
        return self.facts.non_space_envs.get((path, name)) if path else None

    def rootless_env(self, module: str, name: str) -> tuple[str, str] | None:
        """For ``module:name`` as an ``entry_point`` spells it, a class of the run none of
        whose bases is a library's: (the plain class of the run it ends in, that module,
        named as from the entry point's package where the run knows it so)."""
        path = self.facts.modules.get(module)
        found = self.facts.rootless_envs.get((path, name)) if path else None
        return None if found is None else self._named_root(found, module)

    def rootless_class(self, qualified: str) -> tuple[str, str] | None:
        """``rootless_env`` for a class this module defines (``Flatten``) or imports
        (``lab.proxy.Flatten``, a def's own import too): what a def registered as an entry
        point returns an instance of."""
        split = (self.path, qualified) if "." not in qualified else self.facts._split(qualified, self.path)
        found = self.facts.rootless_envs.get(split) if split is not None else None
        if found is None:
            return None
        # named from the package the class is imported from, or this module's shortest dotted name
        here = sorted((m for m, p in self.facts.modules.items() if p == self.path and "." in m), key=lambda m: (m.count("."), m))
        module = qualified if "." in qualified else next(iter(here), qualified)
        return self._named_root(found, module)

    def _named_root(self, found: tuple[str, str], module: str) -> tuple[str, str]:
        """(root class, its module named as from ``module``'s package where the run knows it so)."""
        root, root_path = found
        known = [*self.facts.modules.items(), *((m, p) for m, paths in self.facts.mask_modules.items() for p in paths)]
        names = sorted((m for m, p in known if p == root_path), key=lambda m: (m.count("."), m))
        package = module.split(".")[0] + "."
        named = next((m for m in names if m.startswith(package)), names[-1] if names else root_path)
        return root, named

    def wrapper_stepper(self, module: str, name: str) -> str | None:
        """For ``module:name`` as an ``entry_point`` spells it, the class of the run whose
        reset steps the wrapper around it (that class, or a base of it)."""
        path = self.facts.modules.get(module)
        return self.facts.wrapper_steppers.get((path, name)) if path else None

    def wrapper_stepper_here(self, name: str) -> str | None:
        """``wrapper_stepper`` for a class of this module."""
        return self.facts.wrapper_steppers.get((self.path, name))

    def wrapper_stepper_of(self, qualified: str) -> str | None:
        """``wrapper_stepper`` for a name this module imports (``from .tasks import Task``)."""
        split = self.facts._split(qualified, self.path)
        return None if split is None else self.facts.wrapper_steppers.get(split)

    def any_wrapper_stepper(self) -> str | None:
        """A class of the run whose reset steps the wrapper around it, if any: what an
        ``entry_point`` the run cannot resolve may name."""
        return min(self.facts.wrapper_steppers.values(), default=None)
