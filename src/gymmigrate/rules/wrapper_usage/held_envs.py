"""What the project's own classes hold from their constructions: the questions the
forwarding rules (GM604-GM606) ask of ``self.x`` and of a constructor parameter in a class
of the run that is no Gym env, answered from every construction in the run (``EnvOrigins``
takes them in; they read only the file's facts and the receiver analysis).

``handed_gym_env`` tells EVERY (every construction hands a Gym env: ``get_wrapper_attr``
reads as forwarding did) from SOME (some do, the others pass what the run cannot trace:
asked) for an attribute a base of another module stores, or a parameter a plain class
holds; ``traced_gym_env`` and ``gym_envs_from_elsewhere`` answer the same for a holder's
attribute and a module function's parameter.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import FUNCTIONS, call_argument
from gymmigrate.facts.receivers import Receivers

# How many constructions of a class hand a Gym env to the attribute a base stores (``handed_gym_env``).
EVERY = "every"
SOME = "some"


def _every_or_some(kinds: list[EnvKind]) -> str | None:
    """EVERY where every construction passes a Gym env, SOME where the others pass what the
    run cannot trace, else None (none, or something else at one)."""
    found = set(kinds)
    if found == {EnvKind.GYM_ENV}:
        return EVERY
    return SOME if found == {EnvKind.GYM_ENV, EnvKind.UNKNOWN} else None


def _every_or_asked(kinds: list[EnvKind]) -> str | None:
    """For what a plain class holds from its constructor: EVERY where every construction
    passes a Gym env; SOME where one does and the others pass anything else (a make result
    at one is what the reads must work on, an object of the project's own at another is
    what ``.unwrapped`` would break: asked); else None."""
    found = set(kinds)
    if found == {EnvKind.GYM_ENV}:
        return EVERY
    return SOME if EnvKind.GYM_ENV in found else None


class HeldEnvQuestions:
    """The held-env questions of ``EnvOrigins`` (mixed in: one per file, memoized in its facts)."""

    facts: ModuleFacts
    receivers: Receivers

    def gym_envs_from_elsewhere(self, receiver: ast.expr, origin: str | None) -> bool:
        """``env``, a parameter of a module function that every call from other modules of
        the run passes a Gym env, a bare one or a wrapper stack (``run_agent(gym.make(...))``
        in one test, ``run_agent(MyEnv())`` in another), and that this module's own calls
        (its ``__main__`` block) pass the bare env (``origin`` RAW), or never make."""
        project = self.receivers.project
        if project is None or not isinstance(receiver, ast.Name):
            return False
        bindings = self.facts.bindings_of(receiver)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.arg):
            return False
        arguments = self.facts.parent(bindings[0])
        function = self.facts.parent(arguments) if arguments is not None else None
        if not isinstance(function, FUNCTIONS) or self.facts.functions.get(function.name) is not function:
            return False
        if origin is None and self.receivers.call_sites(function, None):
            return False  # this module's own calls pass something untraced
        kinds = project.param_kinds(function.name, bindings[0].arg)
        return bool(kinds) and all(kind is EnvKind.GYM_ENV for kind in kinds)

    def handed_gym_env(self, receiver: ast.expr) -> str | None:
        """``self._inner`` (or a property of a base returning it, ``self.inner``) in a class
        that never stores it, whose ``__init__`` hands its own parameter up to a base of
        another module of the run that stores it there from its ``__init__`` (``class
        Camera(Proxy)``, ``super().__init__(inner)``; ``SelfAttributes.handed_up``): EVERY
        where every construction of the class, here and in the other modules of the run,
        passes a Gym env (made or bare, ``get_wrapper_attr`` reads it as forwarding did, and
        ``set_wrapper_attr`` reaches the env that has the name); SOME where some pass one and
        the others pass what the run cannot trace (the reads are asked about); else None.
        The same for a constructor parameter of a plain class of the run, read in its
        ``__init__`` or held in ``self.x`` (``held_init_param``)."""
        held = self.held_init_param(receiver)
        if held is not None:
            param = self.facts.bindings_of(held)[0]
            return self.facts.memo(("held-init-param", id(param)), lambda: self._held_answer(held))
        if not (isinstance(receiver, ast.Attribute) and isinstance(receiver.value, ast.Name) and self.receivers.is_self(receiver.value)):
            return None
        classdef = self.facts.enclosing_class(receiver)
        if classdef is None or self.receivers.project is None:
            return None
        # asked of every read of an untraced ``self.x.y``: one answer per class and attribute
        return self.facts.memo((f"handed-gym-env:{receiver.attr}", id(classdef)), lambda: self._handed(receiver, classdef))

    def _handed(self, receiver: ast.Attribute, classdef: ast.ClassDef) -> str | None:
        if self._stored_in_lineage(receiver, classdef):
            return None
        handed = self.receivers.attributes.handed_up(receiver)
        return _every_or_some(self._handed_kinds(handed.argument) if handed is not None else [])

    def _held_answer(self, held: ast.Name) -> str | None:
        kinds = self._handed_kinds(held)
        answer = _every_or_asked(kinds)
        if answer is None and not any(k.is_gym or k not in (EnvKind.UNKNOWN, EnvKind.NOT_ENV) for k in kinds) and self._handers(held):
            # every construction hands on what it was given, joined unknown, but a Gym env up
            # the chain at some: asked, never left in silence
            return SOME
        return answer

    def _handers(self, held: ast.Name) -> list[str]:
        """``held_constructions``' calls that hand on a Gym env from further up."""
        classdef = self.facts.enclosing_class(held)
        project = self.receivers.project
        if classdef is None or project is None:
            return []
        param = self.facts.bindings_of(held)[0]
        assert isinstance(param, ast.arg)
        return [c for name in (f"{classdef.name}.__init__", classdef.name) for c in project.gym_env_handers(name, param.arg)]

    def held_constructions(self, held: ast.Name) -> list[str]:
        """``run.py:6`` for each construction of the run that passes a Gym env for the
        constructor parameter ``held`` (``held_init_param``): this module's by line, the
        other modules' as ``ProjectView.gym_env_callers`` names them."""
        param = self.facts.bindings_of(held)[0]
        function = self.facts.parent(self.facts.parent(param))
        classdef = self.facts.parent(function) if isinstance(function, FUNCTIONS) else None
        if not isinstance(classdef, ast.ClassDef) or not isinstance(param, ast.arg) or self.receivers.project is None:
            return []
        params = [*function.args.posonlyargs, *function.args.args]  # type: ignore[union-attr]
        position = params.index(param) - 1 if param in params else None
        constructions, _ = self.receivers.constructions(classdef)
        found = [
            f"line {call.lineno}"
            for call, shift in constructions
            if (argument := call_argument(call, None if position is None else position + shift, param.arg)) is not None
            and self.receivers.kind_of(argument) is EnvKind.GYM_ENV
        ]
        for name in (f"{classdef.name}.__init__", classdef.name):
            found += [c for c in self.receivers.project.gym_env_callers(name, param.arg) if c not in found]
        return found + [f"{c} (handing on one from further up)" for c in self._handers(held) if c not in found]

    def held_init_param(self, receiver: ast.expr) -> ast.Name | None:
        """``task`` in ``__init__(self, task)``, or ``self.task`` that every store in the
        class sets from that parameter (``self.task = task``), in a plain class of the
        project's own (no base but ``object``: a base could store it otherwise; no Gym env
        or wrapper, whose ``self.env`` is told apart): the parameter's name where it is
        read or stored. What the class holds there is what its constructions pass."""
        if self.receivers.project is None:
            return None
        classdef = self.facts.enclosing_class(receiver)
        if classdef is None or classdef.keywords or any(not (isinstance(b, ast.Name) and b.id == "object") for b in classdef.bases):
            return None
        values: list[ast.expr]
        if isinstance(receiver, ast.Name):
            values = [receiver]
        elif isinstance(receiver, ast.Attribute) and isinstance(receiver.value, ast.Name) and self.receivers.is_self(receiver.value):
            values = self.receivers.self_stores(classdef).get(receiver.attr, [])
        else:
            return None
        params: set[int] = set()
        for value in values:
            bindings = self.facts.bindings_of(value) if isinstance(value, ast.Name) else []
            if len(bindings) != 1 or not isinstance(bindings[0], ast.arg):
                return None  # rebound (``task = task.unwrapped``), or stored from something else
            function = self.facts.parent(self.facts.parent(bindings[0]))
            if not (isinstance(function, FUNCTIONS) and function.name == "__init__" and self.facts.parent(function) is classdef):
                return None
            params.add(id(bindings[0]))
        if len(params) != 1:
            return None
        if self.receivers.is_gym_wrapper_class(classdef) or self.receivers.class_kind(classdef) not in (EnvKind.UNKNOWN, EnvKind.NOT_ENV):
            return None
        held = values[0]
        assert isinstance(held, ast.Name)
        return held

    def _stored_in_lineage(self, receiver: ast.Attribute, classdef: ast.ClassDef) -> bool:
        """``self.<attr>`` is stored by ``classdef`` or a class of this module it derives from."""
        return any(receiver.attr in self.receivers.self_stores(c) for c in self.receivers.local_lineage(classdef))

    def stored_as(self, receiver: ast.expr) -> str | None:
        """``self._inner`` for ``self.inner``, a property of a base of the run returning that
        attribute, in a class that never stores ``inner``; None for anything else."""
        if not (isinstance(receiver, ast.Attribute) and isinstance(receiver.value, ast.Name) and self.receivers.is_self(receiver.value)):
            return None
        classdef = self.facts.enclosing_class(receiver)
        if classdef is None:
            return None
        if self._stored_in_lineage(receiver, classdef):
            return None
        alias = self.receivers.attributes.property_alias(classdef, receiver.attr)
        return f"self.{alias}" if alias is not None else None

    def _handed_kinds(self, param: ast.Name) -> list[EnvKind]:
        """What each construction of the run passes for the ``__init__`` parameter ``param``
        reads: this module's (subclasses that inherit the ``__init__`` too) and the others'."""
        bindings = self.facts.bindings_of(param)
        function = self.facts.parent(self.facts.parent(bindings[0])) if len(bindings) == 1 and isinstance(bindings[0], ast.arg) else None
        classdef = self.facts.parent(function) if isinstance(function, FUNCTIONS) else None
        if not isinstance(classdef, ast.ClassDef) or self.receivers.project is None:
            return []
        constructions, elsewhere = self.receivers.constructions(classdef)
        params = [*function.args.posonlyargs, *function.args.args]  # type: ignore[union-attr]
        position = params.index(bindings[0]) - 1 if bindings[0] in params else None
        kinds = [EnvKind.UNKNOWN] if elsewhere else []
        for call, shift in constructions:
            argument = call_argument(call, None if position is None else position + shift, param.id)
            kinds.append(self.receivers.kind_of(argument) if argument is not None else EnvKind.UNKNOWN)
        if self.facts.parent(classdef) is self.facts.tree:
            kinds += self.receivers.project.param_kinds(f"{classdef.name}.__init__", param.id)
        return kinds

    def traced_gym_env(self, receiver: ast.expr) -> bool:
        """``holder.env`` where ``holder`` is only ever an object of a class of this module
        that is no env (``player = Agent(model, env)``), or of a plain class of another module
        of the run that every construction hands a Gym env there (``ProjectView.held_kind``),
        and the receiver analysis traced the attribute to a Gym env: bare or wrapped,
        ``get_wrapper_attr`` reads the attribute as forwarding did. The origin walk here
        follows ``self.x`` only inside the class."""
        if not (isinstance(receiver, ast.Attribute) and isinstance(receiver.value, ast.Name)):
            return False
        bindings = self.facts.bindings_of(receiver.value)
        if not bindings:
            return False
        project = self.receivers.project
        for binding in bindings:
            statement = self.facts.parent(binding)
            if not (isinstance(statement, ast.Assign) and statement.targets == [binding] and isinstance(statement.value, ast.Call)):
                return False
            func = statement.value.func
            holder = self.receivers.local_class(func)
            if holder is not None:
                if self.receivers.class_kind(holder) not in (EnvKind.UNKNOWN, EnvKind.NOT_ENV):
                    return False
            elif project is None or not any(project.held_kind(q, receiver.attr) is EnvKind.GYM_ENV for q in self.facts.qualified_names(func)):
                return False  # not a plain class of the run whose every construction passes a Gym env there
        return self.receivers.kind_of(receiver) is EnvKind.GYM_ENV
