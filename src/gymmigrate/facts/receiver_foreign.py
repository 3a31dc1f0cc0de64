"""What shows that an object is not a Gym env, whatever the file's imports suggest: a
class that forwards an env API of its own to ``self.X`` (``own_api_holder``: tf_agents'
``PyEnvironment`` wrappers, a project ``Environment`` base whose ``reset`` returns the
states only), a callable of another library that made it (``library_made``), or an
annotation naming a class the run does not show to be Gym's (``annotated_class``); and
whether the module handles Gym envs at all (``handles_gym_envs``), the condition of the
"this file uses only Gym" fallback these facts outweigh.

Separate from ``receiver_origins.py`` because these are the evidence against that
fallback guess, asked by ``decide`` only for a receiver whose kind is unknown; the
origins the rules act on (legacy-step classes, the run's own code) stay there.
``ForeignObjects``, a base of ``MadeObjects``, mixed into ``Receivers``.
"""

from __future__ import annotations

import ast
import sys
from typing import TYPE_CHECKING

from gymmigrate.facts import names as N
from gymmigrate.facts.callables import (
    optional_of,
    parse_annotation,
    string_names,
    union_members,
)
from gymmigrate.facts.gym_use import handles_gym_envs
from gymmigrate.facts.kinds import MAX_DEPTH, EnvKind
from gymmigrate.facts.module import FUNCTIONS, walk

if TYPE_CHECKING:
    from gymmigrate.facts.kinds import ReceiverFacade as _Facade
else:
    _Facade = object

# What a tuple answers besides its items: a read of any other attribute of a step's result
# shows a record (dm_env's ``TimeStep``), not Gym's tuple.
_TUPLE_METHODS = frozenset({"count", "index"})


class ForeignObjects(_Facade):
    """What shows an object is not Gym's (part of ``Receivers``)."""

    def own_api_holder(self, expr: ast.AST) -> str | None:
        """``self.X`` of a class that is no Gym class, derives from a base with an env API of
        its own, and forwards that API to ``self.X``: a method of the class named like a
        method of that base (``reset`` or its hook ``_reset``) calls the same method on
        ``self.X``. The base is a class of the run that is not a Gym env and declares that
        method (``class Wrapper(Environment)`` where ``Environment.reset`` returns the
        states only), or a class of a library with its own env API (tf_agents'
        ``PyEnvironment`` wrappers, whose reset gives a TimeStep). What such a class holds
        is not shown to be a Gym env by the file's imports: a description for the message,
        else None.

        A fact of the receiver, not of the call: where the class forwards its ``reset`` or
        ``step`` so, every call on ``self.X`` in it gets the same answer (``reset`` is never
        left while ``step`` is rewritten on the "this file uses only Gym" guess); another
        method (``close``, ``render``) forwarded so speaks for its own call only. ``decide``
        asks it only for a receiver whose kind is unknown: proved a Gym env, it is rewritten."""
        read = self._self_read(expr)
        if read is None:
            return None
        expr, classdef = read
        attribute = expr.attr
        forwarded = self.facts.memo((f"own-api-forwarded:{attribute}", id(classdef)), lambda: self._own_api_forwarded(classdef, attribute))
        called = self.facts.parent(expr)
        function = self.facts.enclosing_function(expr)
        own = next((f for f in forwarded if f[0] is function and isinstance(called, ast.Attribute) and f[1] == called.attr), None)
        found = own or next((f for f in forwarded if f[1].lstrip("_") in ("reset", "step")), None)
        if found is None:
            return None
        return f"`{classdef.name}`, whose `{found[0].name}` forwards to it and which derives from `{found[2]}`, an env API other than Gym's"

    def _self_read(self, expr: ast.AST) -> tuple[ast.Attribute, ast.ClassDef] | None:
        """``expr`` as a ``self.X`` and the class whose method reads it; None for anything else."""
        if not (isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and self.is_self(expr.value)):
            return None
        classdef = self.facts.enclosing_class(expr)
        return None if classdef is None else (expr, classdef)

    def dispatched_from_gym(self, expr: ast.AST) -> str | None:
        """``self.X`` of a class that every construction of this module builds in a def that
        sends Gym envs to another class first (``if isinstance(env, gym.Env): return
        GymWrapper(env)`` ... ``return IsaacWrapper(env)``, or ``elif ...: return
        DeepMindWrapper(env)``): the code says this class is for envs that are not Gym's.
        Asked with ``own_api_holder`` only, so the class also forwards an API of its own. The
        dispatching def's name, or None."""
        read = self._self_read(expr)
        if read is None:
            return None
        expr, classdef = read
        return self.facts.memo(("dispatched-from-gym", id(classdef)), lambda: self._dispatched_from_gym(classdef), while_computing=None)

    def _dispatched_from_gym(self, classdef: ast.ClassDef) -> str | None:
        calls = self.facts.calls_by_name.get(classdef.name, [])
        if not calls or (self.project is not None and self.project.built_elsewhere(classdef.name)):
            return None
        found = None
        for call in calls:
            dispatch = self._gym_dispatch(call, classdef)
            if dispatch is None or dispatch[1]:
                return None
            found = dispatch[0]
        return found

    def sent_past_gym_check(self, call: ast.Call, classdef: ast.ClassDef) -> bool:
        """``call`` builds ``classdef`` in a def that sends Gym envs to another class of this
        module, outside that branch (``_gym_dispatch``)."""
        dispatch = self._gym_dispatch(call, classdef)
        return dispatch is not None and not dispatch[1]

    def built_for_gym_by(self, classdef: ast.ClassDef) -> str | None:
        """Some construction of ``classdef`` sits where an ``isinstance(env, gym.Env)`` check
        holds, in a def that sends other envs to other classes (``if isinstance(env,
        gym.Env): return GymWrapper(env)``): the class wraps Gym envs, whatever else its
        other constructions pass. The dispatching def's name, or None."""
        for call in self.facts.calls_by_name.get(classdef.name, []):
            dispatch = self._gym_dispatch(call, classdef)
            if dispatch is not None and dispatch[1]:
                return dispatch[0]
        return None

    def _gym_dispatch(self, call: ast.Call, classdef: ast.ClassDef) -> tuple[str, bool] | None:
        """``call`` builds ``classdef`` from a name of a def that has an ``if`` checking that
        name for a Gym env and building another class of this module from it in that branch:
        the def's name, and whether ``call`` sits in that branch. None for any other shape."""
        function = self.facts.enclosing_function(call)
        held = call.args[0] if call.args and isinstance(call.args[0], ast.Name) else None
        if not isinstance(function, FUNCTIONS) or held is None or self.local_class(call.func) is not classdef:
            return None
        ancestors = {id(a) for a in self.facts.ancestors(call)}
        for node in walk(function):
            if not (isinstance(node, ast.If) and self.narrowing.checks_gym_env(node.test, held.id)):
                continue
            inside = any(id(s) in ancestors for s in node.body)
            built = [
                c
                for s in node.body
                for c in walk(s)
                if isinstance(c, ast.Call) and c.args and isinstance(c.args[0], ast.Name) and c.args[0].id == held.id
                and self.local_class(c.func) is not None
            ]
            if inside or any(self.local_class(c.func) is not classdef for c in built):
                return function.name, inside
        return None

    def _own_api_forwarded(self, classdef: ast.ClassDef, attribute: str) -> list[tuple[ast.AST, str, str]]:
        """(method, forwarded method, base) for each method of ``classdef`` that calls its
        namesake on ``self.<attribute>`` where a base shows that method with an env API
        other than Gym's (``_own_api_base_name``), in source order."""
        if self.is_gym_wrapper_class(classdef) or self._known_kind(classdef) not in (EnvKind.UNKNOWN, EnvKind.NOT_ENV):
            return []
        found: list[tuple[ast.AST, str, str]] = []
        for held in self.facts.attributes.get(attribute, ()):
            called = self.facts.parent(held)
            function = self.facts.enclosing_function(held)
            call = self.facts.parent(called) if called is not None else None
            if not (
                isinstance(held.value, ast.Name) and self.is_self(held.value)
                and isinstance(called, ast.Attribute) and called.value is held
                and isinstance(call, ast.Call) and call.func is called
                and function is not None and self.facts.parent(function) is classdef
                and function.name.lstrip("_") == called.attr.lstrip("_")
            ):
                continue
            base = self._own_api_base_name(classdef, called.attr)
            if base is not None:
                found.append((function, called.attr, base))
        return sorted(found, key=lambda f: (f[0].lineno, f[1]))  # type: ignore[attr-defined]

    def _known_kind(self, classdef: ast.ClassDef) -> EnvKind:
        return self.facts.memo(("class-kind", id(classdef)), lambda: self.class_kind(classdef), while_computing=EnvKind.UNKNOWN)

    def _own_api_base_name(self, classdef: ast.ClassDef, method: str) -> str | None:
        """The first base (through the module's classes) that shows an env API other than
        Gym's with ``method`` (``_own_api_holder``), or None."""
        wanted = {method.lstrip("_"), "_" + method.lstrip("_")}
        seen = {id(classdef)}
        todo = [classdef]
        while todo:
            for base in todo.pop().bases:
                if self._own_api_base(base):
                    return self.facts.segment(base)
                local = self.local_class(base)
                if local is not None:
                    if id(local) in seen or self.is_gym_wrapper_class(local):
                        continue
                    seen.add(id(local))
                    if self._known_kind(local) not in (EnvKind.UNKNOWN, EnvKind.NOT_ENV):
                        continue
                    if any(isinstance(s, FUNCTIONS) and s.name in wanted for s in local.body):
                        return local.name
                    todo.append(local)
                elif self.project is not None:
                    for qualified in self.qualified_names(base):
                        if (
                            self._from_run(qualified)
                            and self.project.call_kind(qualified) in (None, EnvKind.UNKNOWN, EnvKind.NOT_ENV)
                            and not self.project.is_wrapper_class(qualified)
                            and self.project.class_methods(qualified) & wanted
                        ):
                            return self.facts.segment(base)
        return None

    def library_made(self, expr: ast.AST) -> str | None:
        """The callable of a library other than Gym that made ``expr`` (``env =
        suite_gym.load(...)`` of tf_agents: ``tf_agents.environments.suite_gym.load``), or
        None. Such an object is not shown to be a Gym env by a file using only Gym."""
        return self.facts.memo(("library-made", id(expr)), lambda: self._library_made(expr), while_computing=None)

    def _library_made(self, expr: ast.AST) -> str | None:
        if self.depth > MAX_DEPTH:
            return None
        self.depth += 1
        try:
            if isinstance(expr, ast.Call):
                imported = set(self.facts.imports.values())
                for qualified in sorted(self.qualified_names(expr.func)):
                    top = qualified.split(".", 1)[0]
                    if (
                        top not in ("gym", "gymnasium")
                        and top not in sys.stdlib_module_names
                        and any(qualified == m or qualified.startswith(m + ".") for m in imported)
                        and not self._from_run(qualified)
                    ):
                        return qualified
                return None
            if isinstance(expr, ast.Name):
                last = self._dominating_binding(expr)  # the one binding this read can reach
                if last is not None:
                    statement = self.facts.statement_of(last)
                    return self.library_made(statement.value) if isinstance(statement, ast.Assign) else None
                found = []
                for binding in self.facts.bindings_of(expr):
                    parent = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
                    if not (isinstance(parent, ast.Assign) and binding in parent.targets):
                        return None
                    found.append(self.library_made(parent.value))
                return found[0] if found and all(f is not None for f in found) else None
            if isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and self.is_self(expr.value):
                # ``self._env = suite.load(...)`` in ``__init__``: every value the class stores
                values = self.self_attribute_values(expr, expr.attr)
                made = [self.library_made(value) for value in values]
                return made[0] if made and all(m is not None for m in made) else None
            return None
        finally:
            self.depth -= 1

    def library_record_env(self, expr: ast.AST) -> str | None:
        """``self.X`` that its class fills from a call of a library other than Gym
        (``self._env = suite.load(domain, task)``) and whose ``step()`` result the class reads
        as a record (``time_step = self._env.step(a)``, then ``time_step.reward``): a Gym
        step returns a tuple, which has no such fields, so the object keeps another library's
        API and every call on it is left alone. The class's other stores there, if any, are
        ones the run cannot place (no env of a known kind, nothing the run makes itself): the
        class reads them all the same way. The library's callable, or None.

        A fact of the receiver, not of the call: each reset, step and spec read on
        ``self.X`` in the class gets the same answer."""
        read = self._self_read(expr)
        if read is None:
            return None
        expr, classdef = read
        attribute = expr.attr
        return self.facts.memo(
            (f"library-record-env:{attribute}", id(classdef)), lambda: self._library_record_env(expr, classdef), while_computing=None
        )

    def _library_record_env(self, expr: ast.Attribute, classdef: ast.ClassDef) -> str | None:
        library = None
        for value in self.self_attribute_values(expr, expr.attr):
            if self.kind_of(value) is not EnvKind.UNKNOWN or self.run_defined(value):
                return None  # a value the run places otherwise: the class is no adapter of one library
            made = self.library_made(value)
            if made is not None and made.split(".", 1)[0] in N.GYM_ONLY_PACKAGES:
                return None  # a Gym-only stack's env (GM107): that decision's
            library = library or made
        if library is None or not self._step_read_as_record(classdef, expr.attr):
            return None
        return library

    def _step_read_as_record(self, classdef: ast.ClassDef, attribute: str) -> bool:
        """A ``self.<attribute>.step(...)`` in a method of ``classdef`` whose result is read
        by a field (``.reward``, ``.last()``), directly or through the one name it is
        stored in: no method of a tuple (``count``, ``index``)."""
        for call in self.facts.attribute_calls.get("step", ()):
            receiver = call.func.value  # type: ignore[attr-defined]
            if not (
                isinstance(receiver, ast.Attribute) and receiver.attr == attribute
                and isinstance(receiver.value, ast.Name) and self.is_self(receiver.value)
                and self.facts.enclosing_class(call) is classdef
            ):
                continue
            if any(self._record_field(read) for read in self._result_reads(call)):
                return True
        return False

    def _result_reads(self, call: ast.Call) -> list[ast.AST]:
        """The expressions that read ``call``'s result: the call itself, and each read of the
        one name a plain assignment stores it in, within the same function."""
        parent = self.facts.parent(call)
        if not (isinstance(parent, ast.Assign) and parent.value is call and len(parent.targets) == 1 and isinstance(parent.targets[0], ast.Name)):
            return [call]
        target = parent.targets[0]
        function = self.facts.enclosing_function(call)
        if function is None:
            return []
        return [
            node
            for node in walk(function)
            if isinstance(node, ast.Name) and node.id == target.id and isinstance(node.ctx, ast.Load)
            and any(binding is target for binding in self.facts.bindings_of(node))
        ]

    def _record_field(self, read: ast.AST) -> bool:
        """``read`` is the value of an attribute read that is no method of a tuple."""
        parent = self.facts.parent(read)
        return isinstance(parent, ast.Attribute) and parent.value is read and parent.attr not in _TUPLE_METHODS

    def _from_run(self, qualified: str) -> bool:
        if qualified.startswith("."):
            return True  # a relative import: a module of the project
        return self.project is not None and self.project.defines(qualified)

    def handles_gym_envs(self) -> bool:
        """The module handles Gym envs (``gym_use.handles_gym_envs``), or defines a class the
        run shows to be a Gym env or wrapper (``class Schedule(TrialWrapper)`` where
        ``TrialWrapper``, of another module, derives ``gym.Wrapper``): only then may the "this
        file uses only Gym" fallback guess that an untraced env-like name holds a Gym env.
        (The seed summaries, which know no other module, ask the module fact alone: they
        differ only for a seed call outside a seed() method of such a module, where the
        first run keeps the env classes' seed() with a GM503 item.)"""
        return self.facts.memo(("handles-gym-envs-run", 0), self._handles_gym_envs, while_computing=False)

    def _handles_gym_envs(self) -> bool:
        if handles_gym_envs(self.facts):
            return True
        return any(self.is_gym_wrapper_class(c) or self._known_kind(c) in (EnvKind.GYM_ENV, EnvKind.GYM_VEC) for c in self.facts.all_classes)

    def tested_other_class(self, expr: ast.AST) -> str | None:
        """A class shown to be no Gym env (the project's own plain env class) that an
        ``isinstance`` of the read's frame tests the name against, spelled as written: the
        code itself says the name may hold one, so the "this file uses only Gym" fallback
        has nothing to go on (``Narrowing.other_class_tested``)."""
        if not isinstance(expr, ast.Name):
            return None
        return self.narrowing.other_class_tested(expr)

    def annotated_class(self, expr: ast.AST) -> str | None:
        """The annotation, as written, of a binding that reaches ``expr`` (``def __init__(self,
        environment: VecEnv)`` then ``self.environment = environment``; ``env: MyEnv = ...``)
        when it names a class the run does not show to be a Gym env (a project class that is
        no ``gym.Env``, a name of an unknown module). The code says what the object is, and
        it is not Gym's: a file's imports do not outweigh that. None without one."""
        return self.facts.memo(("annotated-class", id(expr)), lambda: self._annotated_class(expr, 0), while_computing=None)

    def _annotated_class(self, expr: ast.AST, depth: int) -> str | None:
        if depth > 4:
            return None
        annotations: list[ast.expr] = []
        values: list[ast.expr] = []
        if isinstance(expr, ast.Name):
            for binding in self.facts.bindings_of(expr):
                if isinstance(binding, ast.arg) and binding.annotation is not None:
                    annotations.append(binding.annotation)
                parent = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
                if isinstance(parent, ast.AnnAssign) and parent.target is binding:
                    annotations.append(parent.annotation)
                elif isinstance(parent, ast.Assign) and binding in parent.targets:
                    values.append(parent.value)
        elif isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name) and self.is_self(expr.value):
            classdef = self.facts.enclosing_class(expr)
            for node in self.facts.attributes.get(expr.attr, ()):
                parent = self.facts.parent(node)
                if (
                    isinstance(parent, ast.AnnAssign) and parent.target is node and isinstance(node.value, ast.Name)
                    and self.is_self(node.value) and self.facts.enclosing_class(node) is classdef
                ):
                    annotations.append(parent.annotation)  # ``self.env: VecEnv = env``
            values = self.self_attribute_values(expr, expr.attr)
        for annotation in annotations:
            other = self._other_class_named(annotation)
            if other is not None:
                whole = self.facts.segment(annotation)
                if other is annotation or other is optional_of(annotation, self.qualified_names):
                    return f"`{whole}`, a class not shown to be a Gym env"
                # ``Union[gym.Env, VecEnv]``: one member is Gym's, but the code says the
                # object may as well be the other, so the Gym member proves nothing
                return f"`{whole}`, which admits `{self.facts.segment(other)}`, a class not shown to be a Gym env"
        for value in values:
            if isinstance(value, (ast.Name, ast.Attribute)):
                found = self._annotated_class(value, depth + 1)
                if found is not None:
                    return found
        return None

    def _other_class_named(self, annotation: ast.AST) -> ast.AST | None:
        """The part of ``annotation`` that names a class not shown to be a Gym env (the
        annotation itself, or a member of a ``Union``/``|``), else None."""
        optional = optional_of(annotation, self.qualified_names)
        if optional is not None:
            return self._other_class_named(optional)  # ``Optional[VecEnv]``
        members = union_members(annotation, self.qualified_names)
        if members is not None:
            for member in members:
                other = self._other_class_named(member)
                if other is not None:
                    return other
            return None
        return annotation if self._names_other_class(annotation) else None

    def _names_other_class(self, annotation: ast.AST) -> bool:
        """``annotation`` names a class not shown to be a Gym env: not Gym's own, not ``Any``
        or another ``typing`` form, not ``object``."""
        if self.annotation_kind(annotation) in (EnvKind.GYM_ENV, EnvKind.GYM_VEC):
            return False
        target: ast.AST | None = annotation
        string = isinstance(annotation, ast.Constant) and isinstance(annotation.value, str)
        if string:
            target = parse_annotation(annotation.value)  # type: ignore[attr-defined]  # ``env: "MyEnv"``
        if not isinstance(target, (ast.Name, ast.Attribute)):
            return False  # ``Optional[...]``, ``Union[...]``, a string that is not a dotted name
        names = string_names(self.facts, target) if string else self.qualified_names(target)
        if any(N.strip_gym_prefix(q) is not None or q.split(".", 1)[0] in ("typing", "typing_extensions", "builtins") for q in names):
            return False
        return not (isinstance(target, ast.Name) and target.id in ("object", "Any") and not names)

