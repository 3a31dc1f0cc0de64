"""Where a module's env ids are (GM106, GM803-GM805, ``ids.py``): the string literals an
id-taking call receives, directly or through a constant, a list item, a parameter (its
default and what the module's calls pass, a few hops deep), an argparse default, or handed
on to a function of the project. ``IdSites.find`` lists them in source order and notes
the reads ``atari_evidence.py`` looks at for Atari signs.
"""

from __future__ import annotations

import ast
import re
import sys
from collections.abc import Hashable
from dataclasses import dataclass

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.handovers import Handover, handovers
from gymmigrate.facts.id_params import def_qualname, escaping_parameters
from gymmigrate.facts.module import FUNCTIONS, call_argument, full_name
from gymmigrate.facts.receivers import Receivers
from gymmigrate.rules.env_ids.atari_evidence import atari_template
from gymmigrate.rules.env_ids.catalog import env_package, migration_for, removed_family
from gymmigrate.rules.env_ids.syntax import (
    FORWARDS_KWARGS,
    ID_FUNCTIONS,
    ID_KEYWORDS,
    SB3_ID_FUNCTIONS,
    id_argument,
    is_registry,
    param_default,
    plain_string,
    split_module_prefix,
)

_ENV_OPTION = re.compile(r"^--?env", re.IGNORECASE)
# The registry's ``register`` under gym/gymnasium, whose first argument (``id=``) is the id registered.
_REGISTER_FUNCTIONS = frozenset({"register", "envs.register", "envs.registration.register"})
# absl's flag definitions whose second argument (``default=``) is the flag's value unless the
# command line sets it
_ABSL_DEFINES = frozenset({"absl.flags.DEFINE_string", "absl.flags.DEFINE_enum"})


@dataclass
class IdSite:
    """One string literal used as an env id, and the call that receives it (if known)."""

    string: ast.Constant
    env_id: str
    module_prefix: str  # "ale_py:" in "ale_py:ALE/Pong-v5"
    call: ast.Call | None
    forwards_kwargs: bool
    via: str = ""  # how the string reaches the call ("the constant ENV_ID"), for messages
    report_only: bool = False  # handed to another module's code from a file without Gym: say so, add nothing
    conditional: bool = False  # one branch of ``a if c else b``: keywords would hit both
    untraced: bool = False  # a known retired id handed to the project's code the run cannot follow to a make
    keywords_at_call: bool = False  # via a constant only ``call`` reads: new keywords go to that call
    question: Hashable | None = None  # what an untraced item asks, where other items ask the same


# how many functions an id parameter is followed through to the literal its callers pass
_PARAMETER_HOPS = 4

# Libraries with no Gymnasium release whose factories make envs through legacy gym's own
# registry: registering ale_py with Gymnasium does nothing for them.
_LEGACY_GYM_LIBRARIES = frozenset({"baselines", "stable_baselines", "ptan"})
# Packages whose other calls never make an env from an id they are handed: Gym's own API
# (its id-taking calls are ``_id_call``'s) and the legacy-Gym libraries above.
_NEVER_MAKES = _LEGACY_GYM_LIBRARIES | {"gym", "gymnasium"}



class IdSites:
    """The id sites of one module (one per ``EnvIds`` decision)."""

    def __init__(self, facts: ModuleFacts, receivers: Receivers) -> None:
        self.facts = facts
        self.receivers = receivers
        self._option_ids: frozenset[str] = frozenset()
        # what ``find`` hands an id call that is no literal, in source order: (the call, a
        # name) for a helper's parameter, (None, the value) for a name or a built id
        self.atari_reads: list[tuple[ast.Call | None, ast.expr]] = []

    def find(self) -> list[IdSite]:
        sites: list[IdSite] = []
        self._option_ids = self._options_read_as_ids()
        for call in _calls_in_source_order(self.facts):
            forwards = self._id_call(call)
            if forwards is None:
                sites.extend(self._argparse_default(call))
                sites.extend(self._absl_flag_default(call))
                continue
            arg = id_argument(call)
            if arg is None:
                continue
            # ``gym.make("A-v0" if continuous else "B-v0")``: both branches are ids.
            branches = [arg.body, arg.orelse] if isinstance(arg, ast.IfExp) else [arg]
            for branch in branches:
                site = self._site(branch, call, forwards)
                if site is not None:
                    site.conditional = len(branches) > 1
                    sites.append(site)
            if isinstance(arg, ast.Subscript):
                sites.extend(self._listed_ids(arg))
            if isinstance(arg, ast.Name):
                literal = self.literal_of(arg)
                if literal is not None:
                    sole = self._only_read(literal) is arg
                    site = self._site(literal, call if sole else None, forwards if sole else False, via=f"the constant `{arg.id}`")
                    if site is not None:
                        site.keywords_at_call = sole
                        sites.append(site)
                else:
                    sites.extend(self._parameter_ids(arg))
                    self.atari_reads += [(call, arg), (None, arg)]
            elif isinstance(arg, ast.Attribute) and isinstance(arg.value, ast.Name) and arg.value.id == "self":
                sites.extend(self._stored_ids(arg))
            elif atari_template(self.facts, arg) is not None:
                self.atari_reads.append((None, arg))
        sites.extend(self._constants_passed_on())
        sites.extend(self._ids_passed_on())
        # a call of this module's own def is found both ways: one site per literal
        known = {id(site.string) for site in sites}
        sites.extend(site for site in self._ids_made_elsewhere() if id(site.string) not in known)
        known = {id(site.string) for site in sites}
        sites.extend(site for site in self._retired_ids_handed_on() if id(site.string) not in known)
        known = {id(site.string) for site in sites}
        sites.extend(self._retired_ids_passed_along(known))
        return sites

    def literal_of(self, name: ast.Name) -> ast.Constant | None:
        """The string literal ``name`` holds where it is read: the one literal a constant is
        ever assigned, or the literal of the assignment that certainly reaches the read
        (``env_id = "CartPole-v0"`` ... ``env_id = "PongNoFrameskip-v4"; make_atari(env_id)``)."""
        literal = self._single_literal_constant(name)
        if literal is not None:
            return literal
        flow = Flow.of(self.facts)
        last = flow.last_binding_of(name)
        statement = self.facts.parent(last) if isinstance(last, ast.Name) else None
        if not (isinstance(last, ast.Name) and isinstance(statement, ast.Assign) and statement.targets == [last]):
            return None
        if not flow.dominates(statement, name, last):
            return None  # another value may reach the read (a branch, a loop)
        value = statement.value
        return value if isinstance(value, ast.Constant) and isinstance(value.value, str) else None

    def _only_read(self, literal: ast.Constant) -> ast.Name | None:
        """The one read of the name that ``literal`` is assigned to (``ENV = "..."``), when
        the module reads it exactly once and binds it nowhere else: a keyword the new id
        needs can go to the call that read passes it to."""
        statement = self.facts.parent(literal)
        if not (isinstance(statement, ast.Assign) and len(statement.targets) == 1 and isinstance(statement.targets[0], ast.Name)):
            return None
        target = statement.targets[0]
        for scope in self.facts.scopes.values():
            if any(isinstance(b, ast.Name) and b is not target for b in scope.bindings.get(target.id, ())):
                return None  # rebound somewhere: another value may reach some read
            if target.id in scope.declared_global or target.id in scope.declared_nonlocal:
                return None
        reads = self.facts.reads_of(target.id)
        if len(reads) != 1 or target not in self.facts.bindings_of(reads[0]):
            return None
        return reads[0]

    def _listed_ids(self, subscript: ast.Subscript, via: str = "") -> list[IdSite]:
        """``env_names = ['CartPole-v1', 'LunarLander-v2']`` ... ``gym.make(env_names[i])``: every
        string of the list or tuple literal a name is bound to once (and never changed in
        place) is an id the call may receive."""
        name = subscript.value
        if not isinstance(name, ast.Name):
            return []
        bindings = self.facts.bindings_of(name)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.Name):
            return []
        statement = self.facts.parent(bindings[0])
        if not (isinstance(statement, ast.Assign) and statement.targets == [bindings[0]]):
            return []
        value = statement.value
        if not isinstance(value, (ast.List, ast.Tuple)) or not value.elts:
            return []
        if not all(isinstance(e, ast.Constant) and isinstance(e.value, str) for e in value.elts):
            return []
        where = f"an item of `{name.id}`" + (f", {via}" if via else "")
        sites = []
        for element in value.elts:
            site = self._site(element, None, False, via=where)
            if site is not None:
                sites.append(site)
        return sites

    def _stored_ids(self, attribute: ast.Attribute) -> list[IdSite]:
        """``make(self.env_id)`` with ``self.env_id = env_id`` stored by ``__init__`` (or a
        literal stored): the literals the class's constructions here pass for that parameter
        (``Worker("Pendulum-v0")``), as for a parameter of the function around the call."""
        sites: list[IdSite] = []
        for value in self.receivers.self_attribute_values(attribute, attribute.attr):
            if isinstance(value, ast.Name):
                sites.extend(self._parameter_ids(value))
            else:
                site = self._site(value, None, False, via=f"`self.{attribute.attr}`")
                if site is not None:
                    sites.append(site)
        return sites

    def _parameter_ids(self, name: ast.Name, seen: frozenset[ast.arg] = frozenset()) -> list[IdSite]:
        """``def make_env(env_id="PongNoFrameskip-v4"): return gym.make(env_id)``: the id is a
        parameter of the function around the call; its default and what the module's calls of
        that function pass (string literals, or constants bound once to one) are ids. A call
        that passes a parameter of its own function on (``Task(name)`` calling
        ``make_env(name)``, whose thunk makes ``gym.make(env_id)``) is followed to that
        function's callers in turn, a few hops deep."""
        bindings = self.facts.bindings_of(name)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.arg):
            return []
        param = bindings[0]
        if param in seen or len(seen) >= _PARAMETER_HOPS:
            return []
        seen = seen | {param}
        function = self.facts.parent(self.facts.parent(param))
        if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
            return []
        values: list[tuple[ast.expr, str]] = []
        default = param_default(function, param)
        if default is not None:
            values.append((default, f"the default of `{param.arg}`"))
        params = [*function.args.posonlyargs, *function.args.args]
        position = params.index(param) if param in params else None
        owner = self.facts.parent(function)
        callee: str | None = None
        if owner is self.facts.tree:
            callee = function.name
        elif isinstance(owner, ast.ClassDef) and function.name == "__init__" and self.facts.parent(owner) is self.facts.tree:
            # ``Task("Hopper-v2")`` with ``self.env = gym.make(name)`` in ``Task.__init__``
            callee = owner.name
            position = position - 1 if position else None  # ``self`` is not passed
        calls = self.facts.calls_by_name.get(callee, []) if callee else []
        if isinstance(owner, ast.ClassDef) and function.name != "__init__" and self.facts.parent(owner) is self.facts.tree:
            # a test helper method, ``self.check(level="LunarLander-v2")`` with ``def check(self,
            # level): ... make(level)``: its calls through ``self`` in the class pass the id
            callee = f"self.{function.name}"
            position = position - 1 if position else None
            calls = [c for c in self.facts.attribute_calls.get(function.name, []) if self.receivers.own_method(c.func) is function]
        for call in calls:
            argument = call_argument(call, position, param.arg)
            if argument is not None:
                values.append((argument, f"an argument of `{callee}(...)`"))
        sites = []
        for value, via in values:
            if isinstance(value, ast.Subscript):
                sites.extend(self._listed_ids(value, via))
                continue
            if isinstance(value, ast.Name):
                literal = self.literal_of(value)
                if literal is None:
                    sites.extend(self._parameter_ids(value, seen))
                    continue
                via = f"the constant `{value.id}`, {via}"
                value = literal
            site = self._site(value, None, False, via=via)
            if site is not None:
                sites.append(site)
        return sites

    def _options_read_as_ids(self) -> frozenset[str]:
        """``gym.make(args.game)`` (``str(args.game)``): the attribute names of parsed options that
        this module hands to a call taking an env id, so ``--game``'s argparse default is an id too."""
        names = set()
        for call in _calls_in_source_order(self.facts):
            if self._id_call(call) is None:
                continue
            arg = id_argument(call)
            if isinstance(arg, ast.Call) and isinstance(arg.func, ast.Name) and arg.func.id == "str" and len(arg.args) == 1:
                arg = arg.args[0]
            if isinstance(arg, ast.Attribute) and isinstance(arg.value, ast.Name):
                names.add(arg.attr)
        return frozenset(names)

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
                for node in ast.walk(self.facts.tree)
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
        for call in _calls_in_source_order(self.facts):
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
        for call in _calls_in_source_order(self.facts):
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
        for call in _calls_in_source_order(self.facts):
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
        for node in ast.walk(function):
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

    def _site(self, string: ast.AST, call: ast.Call | None, forwards: bool, via: str = "") -> IdSite | None:
        text = plain_string(self.facts, string)
        if text is None or not isinstance(string, ast.Constant):  # a text comes only from a Constant
            return None
        prefix, env_id = split_module_prefix(text)
        return IdSite(string, env_id, prefix, call, forwards, via)

    def _id_call(self, call: ast.Call) -> bool | None:
        """Does ``call`` take an env id? True if it also forwards keywords to the env, None if no id."""
        for qualified in self.facts.qualified_names(call.func):
            rest = N.strip_gym_prefix(qualified)
            if rest in ID_FUNCTIONS:
                return rest in FORWARDS_KWARGS
            if qualified in SB3_ID_FUNCTIONS:
                return False
        func = call.func
        if isinstance(func, ast.Attribute) and func.attr in ("spec", "make") and is_registry(self.facts, func.value):
            return func.attr == "make"
        return None

    def _argparse_default(self, call: ast.Call) -> list[IdSite]:
        """``parser.add_argument("--env-id", default="LunarLander-v2")``: the default is an id."""
        if not (isinstance(call.func, ast.Attribute) and call.func.attr == "add_argument"):
            return []
        flags = [plain_string(self.facts, a) for a in call.args]
        if not any(flag and (_ENV_OPTION.match(flag) or _option_dest(call, flag) in self._option_ids) for flag in flags):
            return []
        sites = []
        for kw in call.keywords:
            if kw.arg == "default":
                value, via = kw.value, "this argparse default"
                if isinstance(value, ast.Name):
                    # ``default=DEFAULT_ENV_NAME``: the constant's one literal
                    literal = self._single_literal_constant(value)
                    value, via = (literal, f"the constant `{value.id}`, an argparse default") if literal is not None else (value, via)
                site = self._site(value, None, False, via=via)
                if site is not None:
                    sites.append(site)
        return sites

    def _absl_flag_default(self, call: ast.Call) -> list[IdSite]:
        """``flags.DEFINE_string("level", "PongNoFrameskip-v4", ...)`` read back as ``FLAGS.level``
        by a call taking an env id (or a flag named ``env...``): absl's default is an id, as an
        argparse option's is."""
        if not any(q in _ABSL_DEFINES for q in self.facts.qualified_names(call.func)):
            return []
        name = call_argument(call, 0, "name")
        flag = plain_string(self.facts, name) if name is not None else None
        if not flag or not (_ENV_OPTION.match(flag) or flag.lower().startswith("env") or flag in self._option_ids):
            return []
        value = call_argument(call, 1, "default")
        if value is None:
            return []
        via = f"the default of the absl flag `{flag}`"
        if isinstance(value, ast.Name):
            literal = self._single_literal_constant(value)
            if literal is None:
                return []
            via = f"the constant `{value.id}`, {via}"
            value = literal
        sites = [self._site(value, None, False, via=via)]
        choices = call_argument(call, 2, "enum_values")
        if any(q.endswith("DEFINE_enum") for q in self.facts.qualified_names(call.func)) and isinstance(choices, (ast.List, ast.Tuple)):
            # absl rejects a default that is not one of the choices: a bumped id is bumped in both
            sites += [self._site(choice, None, False, via=f"a choice of the absl flag `{flag}`") for choice in choices.elts]
        return [site for site in sites if site is not None]

    def _single_literal_constant(self, name: ast.Name) -> ast.Constant | None:
        """The literal of ``ENV_ID = "..."`` when that is the name's only assignment."""
        bindings = self.facts.bindings_of(name)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.Name):
            return None
        target = bindings[0]
        statement = self.facts.parent(target)
        value: ast.expr | None
        if isinstance(statement, ast.Assign) and statement.targets == [target]:
            value = statement.value
        elif isinstance(statement, ast.AnnAssign) and statement.target is target:
            value = statement.value
        else:
            return None
        return value if isinstance(value, ast.Constant) and isinstance(value.value, str) else None


def _option_dest(call: ast.Call, flag: str) -> str | None:
    """The attribute ``parse_args()`` stores an option under: ``dest=``, else its long flag
    without dashes (``--env-name`` -> ``env_name``); None for a short flag."""
    for kw in call.keywords:
        if kw.arg == "dest" and isinstance(kw.value, ast.Constant) and isinstance(kw.value.value, str):
            return kw.value.value
    if not flag.startswith("--"):
        return None
    return flag[2:].replace("-", "_")


def _calls_in_source_order(facts: ModuleFacts) -> list[ast.Call]:
    """Every call whose callee is a name or an attribute, outer calls before the calls inside them.

    The order decides which string a shared constant's finding names and which id a
    package's registration finding points at, as a walk of the tree would.
    """
    calls = [call for index in (facts.calls_by_name, facts.attribute_calls) for found in index.values() for call in found]
    calls.sort(key=lambda c: (c.lineno, c.col_offset, -(c.end_lineno or 0), -(c.end_col_offset or 0)))
    return calls


def imported_modules(tree: ast.Module, facts: ModuleFacts) -> set[str]:
    """Top-level package of every absolute import in the module (any scope, star imports too)."""
    found: set[str] = set()
    statements = {facts.parent(alias) for alias in facts.imports}
    statements.update(_star_imports(tree.body))
    for statement in statements:
        if isinstance(statement, ast.Import):
            found.update(alias.name.split(".")[0] for alias in statement.names)
        elif isinstance(statement, ast.ImportFrom) and statement.module and not statement.level:
            found.add(statement.module.split(".")[0])
    return found


def _star_imports(body: list[ast.stmt]) -> list[ast.ImportFrom]:
    """``from m import *`` (module level only, but possibly under ``if`` / ``try``)."""
    found = []
    for statement in body:
        if isinstance(statement, ast.ImportFrom) and statement.names[0].name == "*":
            found.append(statement)
        elif isinstance(statement, (ast.If, ast.Try, ast.With, ast.For, ast.While)):
            for block in ("body", "orelse", "finalbody"):
                found.extend(_star_imports(getattr(statement, block, [])))
            for handler in getattr(statement, "handlers", []):
                found.extend(_star_imports(handler.body))
    return found
