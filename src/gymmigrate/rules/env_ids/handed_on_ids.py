"""Env ids handed on (GM106, GM803): literals that reach a make through the project's
code rather than a call of this module taking an id. A constant or literal of a plugin
package passed to a function of the project, a literal another module of the run makes,
and a retired Gym id handed to code the run cannot follow or passed along through names,
tables and loops (``facts.handovers``) to the call that receives it. ``reaches`` says
where such a call takes it; ``id_sites.py`` gathers these with the direct sites.
"""

from __future__ import annotations

import ast
import sys

from gymmigrate.facts import names as N
from gymmigrate.facts.handovers import Handover, handovers
from gymmigrate.facts.id_params import def_qualname, escaping_parameters
from gymmigrate.facts.module import FUNCTIONS, full_name, walk
from gymmigrate.rules.env_ids.catalog import env_package, migration_for, removed_family
from gymmigrate.rules.env_ids.id_literals import (
    IdLiterals,
    IdSite,
    calls_in_source_order,
    imported_modules,
)
from gymmigrate.rules.env_ids.syntax import (
    ID_KEYWORDS,
    id_argument,
    plain_string,
    split_module_prefix,
)

# The registry's ``register`` under gym/gymnasium, whose first argument (``id=``) is the id registered.
_REGISTER_FUNCTIONS = frozenset({"register", "envs.register", "envs.registration.register"})

# Libraries with no Gymnasium release whose factories make envs through legacy gym's own
# registry: registering ale_py with Gymnasium does nothing for them.
_LEGACY_GYM_LIBRARIES = frozenset({"baselines", "stable_baselines", "ptan"})
# Packages whose other calls never make an env from an id they are handed: Gym's own API
# (its id-taking calls are ``_id_call``'s) and the legacy-Gym libraries above.
_NEVER_MAKES = _LEGACY_GYM_LIBRARIES | {"gym", "gymnasium"}


class HandedOnIds(IdLiterals):
    """The id sites of one module that the project's code, not this module's call, makes."""

    def _constants_passed_on(self) -> list[IdSite]:
        """A module constant holding the id of a plugin package (``ENV = "PongNoFrameskip-v4"``)
        handed to a function of the project (``make_env(ENV)``, ``def train(env_id=ENV)``,
        ``parser.add_argument("--env", default=ENV)``): the make call is elsewhere, but the id
        is unmistakable, and Gymnasium only finds it once its package is imported."""
        sites = []
        for statement in self.facts.tree.body:
            if not (isinstance(statement, ast.Assign) and len(statement.targets) == 1 and isinstance(statement.targets[0], ast.Name)):
                continue
            target = statement.targets[0]
            literal = self._single_literal_constant(target)
            if literal is None:
                continue
            text = plain_string(self.facts, literal)
            if text is None or env_package(split_module_prefix(text)[1]) is None:
                continue
            reads = (
                node
                for node in walk(self.facts.tree)
                if isinstance(node, ast.Name) and node.id == target.id and isinstance(node.ctx, ast.Load) and target in self.facts.bindings_of(node)
            )
            for read in reads:
                if self._hands_on(read):
                    site = self._site(literal, None, False, via=f"the constant `{target.id}`")
                    if site is not None:
                        site.report_only = not ({"gym", "gymnasium"} & imported_modules(self.facts.tree, self.facts))
                        sites.append(site)
                    break
        return sites

    def _ids_passed_on(self) -> list[IdSite]:
        """An id of a plugin package handed to a function of the project as an argument: a
        literal (``make_atari("PongNoFrameskip-v4")``, the make call in another module of the
        run) or a name the literal certainly reaches the call through (``env_id`` assigned
        ``"CartPole-v0"`` first, then ``"PongNoFrameskip-v4"``). Constants bound once are
        ``_constants_passed_on``'s."""
        sites = []
        without_gym = not ({"gym", "gymnasium"} & imported_modules(self.facts.tree, self.facts))
        for call in calls_in_source_order(self.facts):
            if self._id_call(call) is not None or not self._project_callee(call):
                continue
            callee = full_name(call.func) or "the project's function"
            for passed in (*call.args, *(kw.value for kw in call.keywords)):
                via = f"an argument of `{callee}(...)`"
                argument: ast.expr = passed
                if isinstance(passed, ast.Name):
                    if self._single_literal_constant(passed) is not None:
                        continue  # a constant: ``_constants_passed_on``
                    literal = self.literal_of(passed)
                    if literal is None:
                        continue
                    argument, via = literal, f"`{passed.id}`, {via}"
                text = plain_string(self.facts, argument)
                if text is None or env_package(split_module_prefix(text)[1]) is None:
                    continue
                site = self._site(argument, None, False, via=via)
                if site is not None:
                    site.report_only = without_gym
                    sites.append(site)
        return sites

    def _ids_made_elsewhere(self) -> list[IdSite]:
        """``MultiEnv("Pendulum-v0", 8)`` with ``make(self.env_id)`` in the module of the run
        that defines ``MultiEnv`` (``ProjectView.passes_id_to_make``): the literal is an id."""
        project = self.receivers.project
        if project is None:
            return []
        sites = []
        for call in calls_in_source_order(self.facts):
            line = getattr(call, "lineno", 0)
            passed = [(str(i), a) for i, a in enumerate(call.args)] + [(k.arg, k.value) for k in call.keywords if k.arg is not None]
            for key, argument in passed:
                if not isinstance(argument, ast.Constant) or not project.passes_id_to_make(line, key):
                    continue
                callee = full_name(call.func) or "the project's function"
                site = self._site(argument, None, False, via=f"an argument of `{callee}(...)`, which makes it")
                if site is not None:
                    sites.append(site)
        return sites

    def _retired_ids_handed_on(self) -> list[IdSite]:
        """``self.unittest(environment="LunarLander-v2")`` in a module that uses Gym, where the
        helper (the project's: a method of the class or of a base of the run, a def of the
        run) passes it on in ways the run cannot follow (rebound, dispatched by a registry):
        a literal that is exactly a Gym id Gymnasium retired or removed is asked about there,
        never rewritten (the run has not seen it reach a make)."""
        if not ({"gym", "gymnasium"} & imported_modules(self.facts.tree, self.facts)):
            return []
        sites = []
        for call in calls_in_source_order(self.facts):
            if self._id_call(call) is not None or not (self._project_callee(call) or self._run_method(call)):
                continue
            callee = full_name(call.func) or "the project's function"
            passed_on = [(str(i), a) for i, a in enumerate(call.args)] + [(k.arg or "", k.value) for k in call.keywords]
            for key, passed in passed_on:
                text = plain_string(self.facts, passed)
                if text is None or not (migration_for(text) or removed_family(text)) or self._kept_there(call, key):
                    continue
                site = self._site(passed, None, False, via=f"handed to `{callee}(...)`")
                if site is not None and not site.module_prefix:
                    site.untraced = True
                    sites.append(site)
        return sites

    def _retired_ids_passed_along(self, known: set[int]) -> list[IdSite]:
        """A literal that is exactly a Gym id Gymnasium retired or removed, which no call
        taking an id receives directly, followed through the names, ``self`` attributes,
        tables and loops of the module (``facts.handovers``) to the calls that receive it:

        * ``for env_id in ["Hopper-v3", ...]: gym.make(env_id)`` (a branch's assignment, an
          item of a dict): it reaches a make, so it is an id site like any other;
        * ``{"task": "Ant-v2", ...}`` in a table whose entry is handed to another
          library (``Simulator(settings=table[name])``) or to the project's code that does
          not keep it where it is: asked, not rewritten (the run has not seen it reach a
          make). Every literal handed on by one argument of one call is one question.

        A literal only printed, logged, joined into a path, compared or used as a dict key
        reaches no make: nothing is said."""
        sites = []
        for string in self.facts.strings:
            if id(string) in known or "-v" not in str(string.value):
                continue
            text = plain_string(self.facts, string)
            if text is None:
                continue
            prefix, env_id = split_module_prefix(text)
            if not (migration_for(env_id) or removed_family(env_id)):
                continue
            for handover in handovers(self.facts, self.receivers, string):
                reaches = self.reaches(handover)
                if reaches is None or (reaches == "code" and prefix):
                    continue
                callee = full_name(handover.call.func) or "a call"
                held = f"an item of `{handover.table}`" if handover.table else "an item of a table" if handover.held else ""
                if reaches == "make":
                    site = self._site(string, None, False, via=f"{held + ', ' if held else ''}reaching `{callee}(...)` on line {handover.call.lineno}")
                else:
                    site = self._site(string, None, False, via=f"{held + ', ' if held else ''}handed to `{callee}(...)`")
                    if site is not None:
                        site.untraced = True
                        site.question = ("GM803 handed on", handover.call.lineno, handover.call.col_offset, handover.key)
                if site is not None:
                    sites.append(site)
                break
        return sites

    def reaches(self, handover: Handover) -> str | None:
        """Where the call that receives a retired id takes it: ``"make"`` for a call taking
        an id that receives it as its id; ``"code"``, from a module that uses Gym, for the
        project's code that the run cannot follow, or for a library's code handed a table
        that holds the id; None where it never reaches a make (a builtin, the standard
        library, Gym's other API, a Gym-only library's factory, a method of an object the
        module does not name, a def of the project that only uses it where it is, a string
        handed to a library as it is), or where the module does not use Gym at all."""
        call = handover.call
        if self._id_call(call) is not None:
            takes_id = handover.key in ID_KEYWORDS or (handover.key == "0" and not any(k.arg in ID_KEYWORDS for k in call.keywords))
            return "make" if takes_id and not handover.held else None
        func = call.func
        if isinstance(func, ast.Name) and not self.facts.bindings_of(func):
            return None  # a builtin: ``print``, ``str``, ``sorted``...
        if not self.facts.memo(("imports-gym", 0), lambda: bool({"gym", "gymnasium"} & imported_modules(self.facts.tree, self.facts))):
            return None
        if self._project_callee(call) or self._run_method(call):
            return None if self._kept_there(call, handover.key) else "code"
        if not handover.held:
            # ``other.make("Pendulum-v0")``: a library reads a string it is handed by its own
            # conventions (its own registry); a table of settings is handed on to be used
            return None
        called = self.facts.qualified_names(func)
        if not called or any(q.split(".", 1)[0] in _NEVER_MAKES for q in called) or any(
            q.split(".", 1)[0] in sys.stdlib_module_names for q in called
        ):
            return None
        return "code"

    def _kept_there(self, call: ast.Call, key: str) -> bool:
        """The project's callee uses argument ``key`` only where it is (a label, a log line):
        it hands it to no call and stores it nowhere, so it never reaches a make."""
        function = self.receivers.local_function(call.func) or self.receivers.own_method(call.func)
        local_class = self.receivers.local_class(call.func) if function is None else None
        if local_class is not None:
            function = next((s for s in local_class.body if isinstance(s, FUNCTIONS) and s.name == "__init__"), None)
        if function is not None:
            if self._registers(function, key):
                return True  # the project's own id, registered with the registry this module imports
            qualname = def_qualname(self.facts, function)
            escaping = self.facts.memo(("escaping-params", 0), lambda: escaping_parameters(self.facts))
            params = [a.arg for a in (*function.args.posonlyargs, *function.args.args)]
            if isinstance(self.facts.parent(function), ast.ClassDef):
                params = params[1:]
            param = params[int(key)] if key.isdigit() and int(key) < len(params) else key
            return qualname in escaping and param in params and param not in escaping[qualname]
        project = self.receivers.project
        if project is None:
            return False
        names = set(self.facts.qualified_names(call.func))
        func = call.func
        classdef = self.facts.enclosing_class(call)
        if isinstance(func, ast.Attribute) and classdef is not None and self._run_method(call):
            names |= {f"{q}.{func.attr}" for base in classdef.bases for q in self.facts.qualified_names(base)}
        return any(project.keeps_argument(q, key) for q in names)

    def _registers(self, function: ast.FunctionDef | ast.AsyncFunctionDef, key: str) -> bool:
        """``def _register_env(id, **kwargs): gym.envs.registration.register(id=id, ...)``: the
        helper hands argument ``key`` to the registry's ``register`` as the id, so the literal
        is an id this run registers (with Gymnasium once the import is rewritten), not a make."""
        params = [a.arg for a in (*function.args.posonlyargs, *function.args.args)]
        if isinstance(self.facts.parent(function), ast.ClassDef):
            params = params[1:]
        param = params[int(key)] if key.isdigit() and int(key) < len(params) else key
        for node in walk(function):
            if not isinstance(node, ast.Call):
                continue
            if not any(N.strip_gym_prefix(q) in _REGISTER_FUNCTIONS for q in self.facts.qualified_names(node.func)):
                continue
            argument = id_argument(node)
            if isinstance(argument, ast.Name) and argument.id == param:
                bindings = self.facts.bindings_of(argument)
                if len(bindings) == 1 and isinstance(bindings[0], ast.arg) and bindings[0].arg == param:
                    return True
        return False

    def _run_method(self, call: ast.Call) -> bool:
        """``self.m(...)`` on a method of the class, or inherited from a base the run defines."""
        func = call.func
        if not (isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name) and self.receivers.is_self(func.value)):
            return False
        if self.receivers.own_method(func) is not None:
            return True
        classdef = self.facts.enclosing_class(call)
        project = self.receivers.project
        if classdef is None or project is None:
            return False
        return any(
            q.startswith(".") or project.defines(q) for base in classdef.bases for q in self.facts.qualified_names(base)
        )

    def _hands_on(self, read: ast.AST) -> bool:
        """The constant is passed on as an id: an argument of a function of the project (a
        def of this module, a relative import, a name another module of the run defines), a
        parameter default, or the default of an argparse option. A library's call
        (``os.path.join(log_dir, env_id)``) is not one, nor a Gym-only library's factory."""
        parent = self.facts.parent(read)
        if isinstance(parent, ast.keyword):
            parent = self.facts.parent(parent)
        if isinstance(parent, ast.arguments):
            return True
        if not (isinstance(parent, ast.Call) and read is not parent.func):
            return False
        if isinstance(parent.func, ast.Attribute) and parent.func.attr == "add_argument":
            return True  # ``parser.add_argument("--env", default=ENV)``
        return self._project_callee(parent)

    def _project_callee(self, call: ast.Call) -> bool:
        """``call`` calls a function of the project (a def of this module, a relative import,
        a name another module of the run defines), not a library's nor a Gym-only library's
        factory."""
        if self.receivers.local_function(call.func) is not None:
            return True
        called = self.facts.qualified_names(call.func)
        project = self.receivers.project
        aliases = {a for a in (project.library_alias(q) for q in called) if a is not None} if project is not None else set()
        if any(q.split(".", 1)[0] in _LEGACY_GYM_LIBRARIES for q in called | aliases):
            return False  # ``make_atari(env_id)`` of baselines makes it with legacy gym (GM107 says so)
        return any(q.startswith(".") or (project is not None and project.defines(q)) for q in called)
