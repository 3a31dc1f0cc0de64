"""Where a module's env ids are (GM106, GM803-GM805, ``ids.py``): the string literals an
id-taking call receives, directly or through a constant, a list item, a parameter (its
default and what the module's calls pass, a few hops deep), an argparse or absl default.
``IdSites.find`` lists them in source order, with the ids handed on to the project's code
(``handed_on_ids.py``), and notes the reads ``atari_evidence.py`` looks at for Atari signs.
"""

from __future__ import annotations

import ast
import re
from dataclasses import replace

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.module import call_argument, param_default
from gymmigrate.facts.receivers import Receivers
from gymmigrate.rules.env_ids.atari_evidence import atari_template
from gymmigrate.rules.env_ids.handed_on_ids import HandedOnIds
from gymmigrate.rules.env_ids.id_literals import IdSite, calls_in_source_order
from gymmigrate.rules.env_ids.syntax import (
    id_argument,
    leading_literal,
    plain_string,
)

_ENV_OPTION = re.compile(r"^--?env", re.IGNORECASE)
# absl's flag definitions whose second argument (``default=``) is the flag's value unless the
# command line sets it
_ABSL_DEFINES = frozenset({"absl.flags.DEFINE_string", "absl.flags.DEFINE_enum"})

# how many functions an id parameter is followed through to the literal its callers pass
_PARAMETER_HOPS = 4


class IdSites(HandedOnIds):
    """The id sites of one module (one per ``EnvIds`` decision)."""

    def __init__(self, facts: ModuleFacts, receivers: Receivers) -> None:
        super().__init__(facts, receivers)
        self._option_ids: frozenset[str] = frozenset()
        # what ``find`` hands an id call that is no literal, in source order: (the call, a
        # name) for a helper's parameter, (None, the value) for a name or a built id
        self.atari_reads: list[tuple[ast.Call | None, ast.expr]] = []
        # the literal a built id starts with (``"dm2gym:" + name``): its ``pkg:`` prefix names
        # the package ``make`` imports
        self.built_prefixes: list[tuple[ast.Constant, str]] = []

    def find(self) -> list[IdSite]:
        sites: list[IdSite] = []
        self._option_ids = self._options_read_as_ids()
        for call in calls_in_source_order(self.facts):
            forwards = self._id_call(call)
            if forwards is None:
                sites.extend(self._argparse_default(call))
                sites.extend(self._absl_flag_default(call))
                continue
            arg = id_argument(call)
            if arg is None:
                continue
            found_here = len(sites)
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
            elif isinstance(arg, (ast.Subscript, ast.Attribute)) and not (isinstance(arg, ast.Attribute) and isinstance(arg.value, ast.Name) and arg.value.id == "self"):
                # ``gym.make(sys.argv[1])``, ``gym.make(args.env)``: an id from outside; what
                # the code does with the env may still say it makes Atari envs
                self.atari_reads.append((call, arg))
            built = self._assigned_value(arg) if isinstance(arg, ast.Name) else arg
            leading = leading_literal(built) if built is not None else None
            text = leading.value if leading is not None else None
            if leading is not None and isinstance(text, str) and ":" in text:
                self.built_prefixes.append((leading, text))
            if isinstance(arg, ast.Attribute) and isinstance(arg.value, ast.Name) and arg.value.id == "self":
                self.atari_reads.append((call, arg))  # ``gym.make(self.game)`` in a class that says what it makes
            for site in sites[found_here:]:
                site.made_at = site.made_at or call
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

    def _assigned_value(self, name: ast.Name) -> ast.expr | None:
        """What ``name`` is assigned where it is its only binding (``name = "dm2gym:" + task``)."""
        bindings = self.facts.bindings_of(name)
        statement = self.facts.parent(bindings[0]) if len(bindings) == 1 else None
        if isinstance(statement, ast.Assign) and statement.targets == bindings:
            return statement.value
        return None

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
        if owner is self.facts.tree and position is not None:
            values.extend((argument, f"an argument of `{function.name}(...)` started as a worker") for argument in self._started_with(function, position))
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

    def _started_with(self, function: ast.FunctionDef | ast.AsyncFunctionDef, position: int) -> list[ast.expr]:
        """What ``Process(target=worker, args=(env_id, queue))`` (a ``Thread`` alike) passes
        at ``position`` of the module's def it starts: the process calls it with those
        arguments, as a plain call would."""
        found = []
        for calls in (*self.facts.calls_by_name.values(), *self.facts.attribute_calls.values()):
            for call in calls:
                keywords = {kw.arg: kw.value for kw in call.keywords if kw.arg is not None}
                target, args = keywords.get("target"), keywords.get("args")
                if not (isinstance(target, ast.Name) and isinstance(args, (ast.Tuple, ast.List))):
                    continue
                if self.facts.bindings_of(target) != [function]:
                    continue  # another def of that name, or a name rebound
                if position < len(args.elts) and not any(isinstance(e, ast.Starred) for e in args.elts[: position + 1]):
                    found.append(args.elts[position])
        return found

    def _options_read_as_ids(self) -> frozenset[str]:
        """``gym.make(args.game)`` (``str(args.game)``): the attribute names of parsed options that
        this module hands to a call taking an env id, so ``--game``'s argparse default is an id too."""
        names = set()
        for call in calls_in_source_order(self.facts):
            if self._id_call(call) is None:
                continue
            arg = id_argument(call)
            if isinstance(arg, ast.Call) and isinstance(arg.func, ast.Name) and arg.func.id == "str" and len(arg.args) == 1:
                arg = arg.args[0]
            if isinstance(arg, ast.Attribute) and isinstance(arg.value, ast.Name):
                names.add(arg.attr)
        return frozenset(names)

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
                    sites.append(replace(site, command_line_default=True))
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
        return [replace(site, command_line_default=True) for site in sites if site is not None]


def _option_dest(call: ast.Call, flag: str) -> str | None:
    """The attribute ``parse_args()`` stores an option under: ``dest=``, else its long flag
    without dashes (``--env-name`` -> ``env_name``); None for a short flag."""
    for kw in call.keywords:
        if kw.arg == "dest" and isinstance(kw.value, ast.Constant) and isinstance(kw.value.value, str):
            return kw.value.value
    if not flag.startswith("--"):
        return None
    return flag[2:].replace("-", "_")
