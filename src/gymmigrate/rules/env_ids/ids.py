"""Env id strings: retired ids, Atari variants, removed families, plugin registration.

* GM803 retired ids are bumped to the id Gymnasium 1.4 registers (``catalog.RETIRED_IDS``).
  Only strings in an env-id position are touched: the id argument of ``make`` /
  ``make_vec`` / ``vector.make`` / ``spec`` / the legacy registry methods / SB3's
  ``make_vec_env`` and ``make_atari_env``, a constant that is only ever assigned one
  literal and is passed there, and the ``default=`` of an ``--env...`` argparse option.
  Gymnasium raises ``DeprecatedEnv`` for every retired id.
* GM804 Atari ids removed in ale-py 0.11.1 (``*Deterministic*``, ``*-ram*``) become the
  base id plus ``frameskip=`` / ``obs_type="ram"`` on the call that makes the env; where
  that call cannot take the keywords (``spec``, a constant, one branch of a conditional)
  they are reported instead.
* GM805 ids of removed families (robotics, Striker/Thrower, the unittest envs) are reported.
* GM106 Gymnasium 1.0 removed plugin auto-registration: a module that makes an Atari id
  gets ``import ale_py`` + ``gym.register_envs(ale_py)`` (AUTO; ``register_envs`` keeps
  linters from deleting an import that looks unused); MiniGrid and highway-env ids get
  their package import (ASSIST).
"""

from __future__ import annotations

import ast
import re
from dataclasses import dataclass

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.module import call_argument, full_name
from gymmigrate.findings import FixKind, Tier, gym_only_question
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.env_ids.catalog import (
    ALE,
    EnvPackage,
    IdMigration,
    env_package,
    is_atari_id,
    migration_for,
    plugin_of,
    removed_family,
)
from gymmigrate.rules.env_ids.syntax import (
    FORWARDS_KWARGS,
    ID_FUNCTIONS,
    SB3_ID_FUNCTIONS,
    gym_alias,
    id_argument,
    is_registry,
    plain_string,
)

RULES = (
    Rule(
        "GM106",
        "register third-party env packages",
        FixKind.ASSIST,
        "Atari ids get `import ale_py` + `gym.register_envs(ale_py)`; MiniGrid/highway ids get their package import.",
    ),
    Rule("GM803", "retired env ids", FixKind.AUTO, "Retired env ids are bumped to the version Gymnasium 1.4 registers.", once_per_run=True),
    Rule(
        "GM804",
        "Atari ids",
        FixKind.ASSIST,
        "Removed `*Deterministic*` / `*-ram*` Atari ids become the base id plus keywords; `info[\"ale.lives\"]` reads `\"lives\"`.",
        once_per_run=True,
    ),
    Rule("GM805", "removed env families", FixKind.FLAG, "Ids of env families Gymnasium removed are reported.", once_per_run=True),
)

# ``notes.gymnasium_imported`` is set when the registration block imports ``gymnasium`` itself, so the
# registry family does not import it a second time.

_ENV_OPTION = re.compile(r"^--?env", re.IGNORECASE)


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


# What loading an earlier run's policy, weights or normaliser looks like.
_LOADS_SAVED_STATE = re.compile(
    r"\b(load_state_dict|load_weights|load_model|from_pretrained|restore|load_from_checkpoint)\s*\(|(\w*)\.load\s*\("
)


def _loads_saved_state(text: str) -> bool:
    """Does the program load what an earlier run saved? tf_agents' ``suite_gym.load("CartPole-v1")``
    (``suite_atari``, ``suite_mujoco``...) makes an env: it loads nothing."""
    return any(not (match.group(2) or "").startswith("suite_") for match in _LOADS_SAVED_STATE.finditer(text))


_ALE_LIVES = "ale.lives"
# how many functions an id parameter is followed through to the literal its callers pass
_PARAMETER_HOPS = 4
_ATARI_WORDS = (_ALE_LIVES, ".ale", "NoFrameskip", "get_action_meanings")


class EnvIds(RuleFamily):
    RULES = RULES

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        # ids, gym's Atari info key, and what only an Atari env has (``_atari_helper``), here
        # or in a def or class of another module of the run this one imports
        if "-v" in facts.text or any(sign in facts.text for sign in _ATARI_WORDS):
            return True
        project = context.options.project
        if project is None or "make" not in facts.text:
            return False
        view = project.view(context.path)
        return any(view.uses_atari(q) for q in facts.imports.values())

    def decide(self) -> None:
        if self.notes.gym_kept_for is not None:
            return  # the file stays on gym with the library its envs go to: gym registers its ids
        self._rename_lives_key()
        self._planned: set[ast.Constant] = set()
        self._new_keywords: dict[ast.Call, list[tuple[str, str]]] = {}
        # package module -> (package, the first id string that needs it, and for a helper
        # known only by what it does with its env, the message and kind that say why)
        self._packages: dict[str, tuple[EnvPackage, ast.expr, tuple[str, FixKind] | None]] = {}
        self._bumped: dict[str, tuple[str, ast.Constant]] = {}  # old id -> new id, the first site bumped
        for site in self._id_sites():
            self._decide_site(site)
        self._bump_comparisons()
        for call, keywords in self._new_keywords.items():
            self.plan.replace(call, lambda node, keywords=keywords: _append_keywords(node, keywords))
        self._decide_registration()

    # -- GM804: gym's Atari info key ------------------------------------------------------

    def _rename_lives_key(self) -> None:
        """``info["ale.lives"]`` (``info.get("ale.lives")``): gym's AtariEnv named the key so;
        ale-py's envs, which Gymnasium's Atari ids make, call it ``"lives"`` (KeyError now)."""
        if _ALE_LIVES not in self.facts.text or not self.context.profile.imports_gym:
            return
        for node in self.facts.strings:
            if node.value != _ALE_LIVES:
                continue
            parent = self.facts.parent(node)
            keyed = isinstance(parent, ast.Subscript) and parent.slice is node
            got = (
                isinstance(parent, ast.Call)
                and isinstance(parent.func, ast.Attribute)
                and parent.func.attr in ("get", "pop")
                and parent.args[:1] == [node]
            )
            if keyed or got:
                self.plan.replace(node, lambda cst_node: _with_string_value(cst_node, "lives"))
                self.report(node, "GM804", '"ale.lives" -> "lives": ale-py\'s Atari envs name the info key so', FixKind.AUTO)

    # -- where env ids are ---------------------------------------------------------------

    def _id_sites(self) -> list[IdSite]:
        sites: list[IdSite] = []
        self._option_ids = self._options_read_as_ids()
        for call in _calls_in_source_order(self.facts):
            forwards = self._id_call(call)
            if forwards is None:
                sites.extend(self._argparse_default(call))
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
                literal = self._literal_of(arg)
                if literal is not None:
                    site = self._site(literal, None, False, via=f"the constant `{arg.id}`")
                    if site is not None:
                        sites.append(site)
                else:
                    sites.extend(self._parameter_ids(arg))
                    self._atari_helper(call, arg)
                    self._formatted_atari_id(arg)
            elif _atari_template(self.facts, arg) is not None:
                self._formatted_atari_id(arg)
        sites.extend(self._constants_passed_on())
        sites.extend(self._ids_passed_on())
        return sites

    def _literal_of(self, name: ast.Name) -> ast.Constant | None:
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
        default = _default(function, param)
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
        for call in self.facts.calls_by_name.get(callee, []) if callee else []:
            argument = call_argument(call, position, param.arg)
            if argument is not None:
                values.append((argument, f"an argument of `{callee}(...)`"))
        sites = []
        for value, via in values:
            if isinstance(value, ast.Subscript):
                sites.extend(self._listed_ids(value, via))
                continue
            if isinstance(value, ast.Name):
                literal = self._literal_of(value)
                if literal is None:
                    sites.extend(self._parameter_ids(value, seen))
                    continue
                via = f"the constant `{value.id}`, {via}"
                value = literal
            site = self._site(value, None, False, via=via)
            if site is not None:
                sites.append(site)
        return sites

    def _formatted_atari_id(self, arg: ast.expr) -> None:
        """``gym.make('{}NoFrameskip-{}'.format(game, version))`` (or an f-string, directly or
        through the name it is assigned to): the literal part of the template names an Atari id
        (``NoFrameskip``, ``-ramNoFrameskip``, the ``ALE/`` namespace) whatever is filled in, so
        the module makes Atari envs and needs ``import ale_py``. Where only some of the
        assignments that may reach the call build such an id, it is for review."""
        if ALE.module in self._packages:
            return
        values: list[ast.expr] = [arg]
        if isinstance(arg, ast.Name):
            values = []
            for binding in self.facts.bindings_of(arg):
                statement = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
                if not (isinstance(statement, ast.Assign) and statement.targets == [binding]):
                    return  # a parameter, a loop variable...: what reaches the call is unknown
                values.append(statement.value)
        templates = [(value, _atari_template(self.facts, value)) for value in values]
        found = [(value, part) for value, part in templates if part is not None]
        if not found:
            return
        value, part = found[0]
        if len(found) == len(templates):
            message = (
                f"the id is built from a template holding `{part}`, an Atari id whatever is filled in: since Gymnasium 1.0 "
                "Atari envs need `import ale_py`; added it with `register_envs(ale_py)`"
            )
            kind = FixKind.AUTO
        else:
            message = (
                f"the id may be built from a template holding `{part}` (an Atari id), other assignments reach the call too: "
                "since Gymnasium 1.0 Atari envs need `import ale_py`; added it with `register_envs(ale_py)`: drop it if "
                "this module never makes Atari envs"
            )
            kind = FixKind.ASSIST
        self._packages[ALE.module] = (ALE, value, (message, kind))

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

    def _atari_helper(self, call: ast.Call, name: ast.Name) -> None:
        """``def make_atari(env_id): env = gym.make(env_id); assert "NoFrameskip" in env.spec.id``:
        a helper that makes its env from a parameter and uses what only Atari envs have (the
        ``ale`` interface, ``get_action_meanings()``, a ``NoFrameskip`` check, directly or in
        a def or class of this module it calls) makes Atari envs, whatever id its callers
        pass: its module needs ``import ale_py``. Where every sign sits under a condition
        (``if "NoFrameskip" in env_id:``), the helper may make other envs too: for review."""
        bindings = self.facts.bindings_of(name)
        assign = self.facts.parent(bindings[0]) if len(bindings) == 1 else None
        read = assign.value if isinstance(assign, ast.Assign) and assign.targets == bindings else None
        if isinstance(read, ast.Attribute) and isinstance(read.value, ast.Name):  # ``env_id = task.env_id``
            bindings = self.facts.bindings_of(read.value)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.arg):
            return
        function = self.facts.enclosing_function(call)
        if function is None or ALE.module in self._packages:
            return
        signs = [(sign, node) for node in ast.walk(function) for sign in self._atari_signs(node, function)]
        signs.sort(key=lambda found: found[0].startswith("through"))  # its own signs first
        where = {id(node): function for _, node in signs}
        owner = self.facts.parent(function)
        if not signs and isinstance(owner, ast.ClassDef):
            # ``self.env = gym.make(env_id)`` in ``__init__``, and ``self.env.unwrapped.ale.lives()``
            # in another method: the class holds an env that has what only Atari envs have.
            for method in owner.body:
                if isinstance(method, (ast.FunctionDef, ast.AsyncFunctionDef)) and method is not function:
                    for node in ast.walk(method):
                        for sign in self._atari_signs(node, method):
                            signs.append((sign.replace("it ", f"its class `{owner.name}` ", 1), node))
                            where[id(node)] = method
            signs.sort(key=lambda found: found[0].startswith("through"))
        if not signs:
            return
        certain = [
            sign
            for sign, node in signs
            if not ("tests for" in sign or _under_condition(self.facts, node, where[id(node)]))
        ]
        evidence = (certain or [sign for sign, _ in signs])[0]
        given = None if certain or read is not None else self._ids_given(function, bindings[0])
        if given is not None and not any(is_atari_id(i) for i in given):
            return  # every caller of the run passes an id, none an Atari one: no ale_py needed
        if given is not None:
            atari = next(i for i in given if is_atari_id(i))
            certain = [f"{evidence}, and its callers in the run pass Atari ids such as `{atari}`"]
            evidence = certain[0]
        maker = f"{owner.name}.{function.name}" if isinstance(owner, ast.ClassDef) else function.name
        if certain:
            message = (
                f"`{maker}` makes Atari envs ({evidence}): since Gymnasium 1.0 they need `import ale_py`; "
                "added it with `register_envs(ale_py)`"
            )
            kind = FixKind.AUTO
        else:
            message = (
                f"`{maker}` may make Atari envs ({evidence}, under a condition): since Gymnasium 1.0 they need "
                "`import ale_py`; added it with `register_envs(ale_py)`: drop it if this project never makes Atari envs here"
            )
            kind = FixKind.ASSIST
        self._packages[ALE.module] = (ALE, name, (message, kind))

    def _ids_given(self, function: ast.AST, param: ast.arg) -> list[str] | None:
        """The env ids every call of the run gives ``param`` of the top-level def
        ``function``: the calls of this module and of the others (``ProjectView.passed_ids``),
        a default where a call passes none. None when a call passes something else, when the
        def is read as a value anywhere (it may be called unseen), or when nobody calls it."""
        project = self.receivers.project
        if project is None or not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
            return None
        if self.facts.parent(function) is not self.facts.tree or project.handed_on(function.name):
            return None
        params = [*function.args.posonlyargs, *function.args.args]
        if param not in params:
            return None
        position = params.index(param)
        default = _default(function, param)
        default_id = plain_string(self.facts, default) if isinstance(default, ast.Constant) else None
        found: list[str] = []
        reads = [read for scope in self.facts.scopes.values() for read in scope.reads.get(function.name, ())]
        for read in reads:
            call = self.facts.parent(read)
            if not (isinstance(call, ast.Call) and call.func is read) or self.facts.bindings_of(read) != [function]:
                return None  # handed on as a value (or another binding of the name)
            if any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords):
                return None
            argument = call_argument(call, position, param.arg)
            if argument is None:
                value = default_id
            elif isinstance(argument, ast.Name):
                literal = self._literal_of(argument)
                value = plain_string(self.facts, literal) if literal is not None else None
            else:
                value = plain_string(self.facts, argument) if isinstance(argument, ast.Constant) else None
            if value is None:
                return None
            found.append(_split_module_prefix(value)[1])
        for value in project.passed_ids(function.name, param.arg):
            value = default_id if value == "" else value
            if value is None:
                return None
            found.append(_split_module_prefix(value)[1])
        return found or None

    def _atari_signs(self, node: ast.AST, function: ast.AST) -> list[str]:
        """What in ``node`` only an Atari env has: ``.ale``, ``get_action_meanings()``, a
        ``"NoFrameskip"`` check; or a call of a def or class of this module that has one."""
        if isinstance(node, ast.Attribute) and node.attr == "ale":
            return ["it uses `.ale`"]
        if isinstance(node, ast.Attribute) and node.attr == "get_action_meanings":
            return ["it calls `get_action_meanings()`"]
        if isinstance(node, ast.Constant) and node.value == "NoFrameskip":
            # ``assert "NoFrameskip" in env.spec.id`` says what it makes; an ``if`` on the id
            # says that it sometimes does
            return ['it asserts `"NoFrameskip"`'] if self.facts.enclosing(node, ast.Assert) else ['it tests for `"NoFrameskip"`']
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
            called = self.facts.functions.get(node.func.id) or self.facts.classes.get(node.func.id)
            if called is not None and called is not function and self._has_atari_sign(called):
                return [f"through `{node.func.id}`"]
        if isinstance(node, ast.Call) and isinstance(node.func, (ast.Name, ast.Attribute)):
            # ``wrap_deepmind(env)`` imported from another module of the run that has a sign
            project = self.receivers.project
            if project is not None and any(project.uses_atari(q) for q in self.facts.qualified_names(node.func)):
                return [f"through `{full_name(node.func)}` of another module"]
        return []

    def _has_atari_sign(self, definition: ast.AST) -> bool:
        def compute() -> bool:
            for node in ast.walk(definition):
                if isinstance(node, ast.Attribute) and node.attr in ("ale", "get_action_meanings"):
                    return True
                if isinstance(node, ast.Constant) and node.value == "NoFrameskip":
                    return True
            return False

        return bool(self.facts.memo(("atari-sign", id(definition)), compute))

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
            if text is None or env_package(_split_module_prefix(text)[1]) is None:
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
                        site.report_only = not ({"gym", "gymnasium"} & _imported_modules(self.facts.tree, self.facts))
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
        without_gym = not ({"gym", "gymnasium"} & _imported_modules(self.facts.tree, self.facts))
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
                    literal = self._literal_of(passed)
                    if literal is None:
                        continue
                    argument, via = literal, f"`{passed.id}`, {via}"
                text = plain_string(self.facts, argument)
                if text is None or env_package(_split_module_prefix(text)[1]) is None:
                    continue
                site = self._site(argument, None, False, via=via)
                if site is not None:
                    site.report_only = without_gym
                    sites.append(site)
        return sites

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
        prefix, env_id = _split_module_prefix(text)
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

    # -- GM803 / GM804 / GM805 -------------------------------------------------------------

    def _decide_site(self, site: IdSite) -> None:
        if site.string in self._planned:  # a constant passed to several calls
            return
        self._planned.add(site.string)
        if site.report_only:
            package = env_package(site.env_id)
            self.report(
                site.string,
                "GM106",
                f"`{site.env_id}` ({site.via}) is handed to code elsewhere that makes the env: since Gymnasium 1.0 that "
                f"module (or this one) must `import {package.module}` and call `gymnasium.register_envs({package.module})`"
                if package is not None
                else f"`{site.env_id}` ({site.via}) is handed to code elsewhere that makes the env",
                kind=FixKind.FLAG,
            )
            return
        migration = migration_for(site.env_id)
        if migration is not None:
            self._decide_migration(site, migration)
        hint = removed_family(site.env_id)
        if hint is not None:
            plugin = plugin_of(site.env_id)
            # The import of the plugin package asks the same question (GM107): the file's
            # review list asks it once, at the first of them; where the import's item is
            # silenced (a bare noqa comment on ``import pybullet_envs``), the id's site asks it.
            question = gym_only_question(N.gym_only_stack(plugin)) if plugin is not None else None
            self.report(site.string, "GM805", f"`{site.env_id}` no longer exists: {hint}", question=question)
        final_id = migration.new_id if migration is not None else site.env_id
        package = env_package(final_id)
        if package is not None and not site.module_prefix and package.module not in self._packages:
            self._packages[package.module] = (package, site.string, None)

    def _decide_migration(self, site: IdSite, migration: IdMigration) -> None:
        old, new = site.env_id, migration.new_id
        where = f" ({site.via})" if site.via else ""
        if migration.kwargs:
            keywords = ", ".join(f"{k}={v}" for k, v in migration.kwargs)
            taken = {kw.arg for kw in site.call.keywords if kw.arg is not None} if site.call else set()
            clash = [k for k, _ in migration.kwargs if k in taken]
            if not site.forwards_kwargs or clash or site.call is None or site.conditional:
                if clash:
                    why = f"the call already passes {', '.join(clash)}"
                elif site.via:
                    why = f"the id comes from {site.via}"
                elif site.conditional:
                    why = "the id is one branch of a conditional"
                else:
                    why = "this call cannot pass keywords to the env"
                self.report(
                    site.string,
                    migration.rule,
                    f"`{old}` no longer exists: make `{new}` with {keywords} ({why}); {migration.reason}",
                    kind=FixKind.FLAG,
                )
                return
            planned = self._new_keywords.setdefault(site.call, [])
            planned.extend(k for k in migration.kwargs if k not in planned)
            new_text = f"`{new}` with {keywords}"
        else:
            new_text = f"`{new}`"
        new_value = site.module_prefix + new
        self.plan.replace(site.string, lambda node: _with_string_value(node, new_value))
        if not migration.kwargs and not site.module_prefix:
            self._bumped.setdefault(old, (new, site.string))
        # A new version is a question for a program that loads what an earlier run saved
        # (a policy, a normaliser); one that trains from scratch just gets the current env.
        settled = migration.kind is FixKind.ASSIST and not _loads_saved_state(self.facts.text)
        self.report(
            site.string,
            migration.rule,
            f"`{old}` -> {new_text}{where}: {migration.reason}" + ("; nothing here loads a saved model" if settled else ""),
            kind=migration.kind,
            tier=Tier.NOTE if settled else None,
            # the same bump at several places of a file (notebook cells) is one decision
            question=None if settled or migration.kind is FixKind.AUTO else (migration.rule, old, new),
        )

    def _bump_comparisons(self) -> None:
        """``if self.env_name == 'LunarLander-v2':`` where this module bumps that id: the test
        would never hold again, so the compared string moves with the id."""
        if not self._bumped:
            return
        for node in self.facts.strings:
            if node in self._planned or node.value not in self._bumped:
                continue
            compare = self.facts.parent(node)
            if isinstance(compare, (ast.List, ast.Tuple, ast.Set)):  # ``env_id in ('A-v2', 'B-v2')``
                compare = self.facts.parent(compare)
            if not (isinstance(compare, ast.Compare) and all(isinstance(op, (ast.Eq, ast.NotEq, ast.In, ast.NotIn)) for op in compare.ops)):
                continue
            new, first = self._bumped[node.value]
            self._planned.add(node)
            self.plan.replace(node, lambda cst_node, new=new: _with_string_value(cst_node, new))
            self.report(
                node,
                "GM803",
                f"`{node.value}` -> `{new}` in a comparison: the id is bumped at line {first.lineno}, so the test moves with it",
                kind=FixKind.AUTO,
            )

    # -- GM106 -----------------------------------------------------------------------------

    def _decide_registration(self) -> None:
        if not self._packages:
            return
        imported = _imported_modules(self.facts.tree, self.facts)
        needed = []
        for package, string, why in self._packages.values():
            if package.module in imported:
                continue
            if package.legacy_module and package.legacy_module in imported:
                continue  # the gym-era package: GM112 renames its import or reports it
            needed.append(package)
            message, kind = why if why is not None else (_registration_message(package), package.kind)
            self.report(string, "GM106", message, kind=kind)
        if needed:
            self._insert_registration([p.module for p in needed], [s for _, s, _ in self._packages.values()])

    def _insert_registration(self, packages: list[str], strings: list[ast.expr]) -> None:
        """``import ale_py`` after the last top-level import that comes before the first use
        of an id, then a blank line and ``gym.register_envs(ale_py)``."""
        body = self.facts.tree.body
        first_use = min(body.index(self._top_level_statement(s)) for s in strings)
        alias = gym_alias(self.facts)
        lines = []
        if alias is None:
            alias = "gymnasium"
            lines.append("import gymnasium")
            self.notes.gymnasium_imported = True
        lines += [f"import {package}" for package in packages]
        calls = [f"{alias}.register_envs({package})" for package in packages]
        calls[0] = "\n" + calls[0]
        last_import = next((s for s in reversed(body[:first_use]) if isinstance(s, (ast.Import, ast.ImportFrom))), None)
        if last_import is not None:
            self.plan.insert_after(last_import, *lines, *calls)
            return
        # No import before the first use: after a module docstring, else first, with a
        # blank line before the module's own code where its first statement can take one.
        if _is_docstring(body[0]):
            self.plan.insert_after(body[0], *lines, *calls)
            return
        self.plan.insert_before(body[0], *lines, *calls)
        if isinstance(body[0], (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.If, ast.For, ast.While, ast.With, ast.Try)):
            self.plan.replace(body[0], lambda node: node.with_changes(leading_lines=[cst.EmptyLine()]))

    def _top_level_statement(self, node: ast.AST) -> ast.stmt:
        statement = self.facts.statement_of(node)
        tree = self.facts.tree
        while self.facts.parent(statement) is not tree:
            statement = self.facts.statement_of(self.facts.parent(statement))  # type: ignore[arg-type]
        return statement


def _option_dest(call: ast.Call, flag: str) -> str | None:
    """The attribute ``parse_args()`` stores an option under: ``dest=``, else its long flag
    without dashes (``--env-name`` -> ``env_name``); None for a short flag."""
    for kw in call.keywords:
        if kw.arg == "dest" and isinstance(kw.value, ast.Constant) and isinstance(kw.value.value, str):
            return kw.value.value
    if not flag.startswith("--"):
        return None
    return flag[2:].replace("-", "_")


# What the literal part of a built id names for certain: an Atari id, whatever the
# placeholders hold (``'{}NoFrameskip-{}'``, ``f"ALE/{game}-v5"``).
_ATARI_TEMPLATE_PARTS = ("NoFrameskip", "ALE/")


def _atari_template(facts: ModuleFacts, value: ast.expr) -> str | None:
    """The Atari part of ``'...'.format(...)`` / ``'...' % ...`` / an f-string / a concatenation, or None."""
    parts: list[str] = []
    if isinstance(value, ast.JoinedStr):
        parts = [v.value for v in value.values if isinstance(v, ast.Constant) and isinstance(v.value, str)]
    elif (
        isinstance(value, ast.Call)
        and isinstance(value.func, ast.Attribute)
        and value.func.attr == "format"
        and isinstance(value.func.value, ast.Constant)
        and isinstance(value.func.value.value, str)
    ):
        parts = [value.func.value.value]
    elif isinstance(value, ast.BinOp) and isinstance(value.op, ast.Mod) and isinstance(value.left, ast.Constant) and isinstance(value.left.value, str):
        parts = [value.left.value]
    elif isinstance(value, ast.BinOp) and isinstance(value.op, ast.Add):
        # ``game + "NoFrameskip-v4"``: the literal operands of the concatenation
        operands: list[ast.expr] = [value]
        while operands:
            operand = operands.pop()
            if isinstance(operand, ast.BinOp) and isinstance(operand.op, ast.Add):
                operands += [operand.left, operand.right]
            elif isinstance(operand, ast.Constant) and isinstance(operand.value, str):
                parts.append(operand.value)
    for part in parts:
        for sign in _ATARI_TEMPLATE_PARTS:
            if sign in part and (sign != "ALE/" or part.lstrip().startswith("ALE/")):
                return sign
    return None


def _calls_in_source_order(facts: ModuleFacts) -> list[ast.Call]:
    """Every call whose callee is a name or an attribute, outer calls before the calls inside them.

    The order decides which string a shared constant's finding names and which id a
    package's registration finding points at, as a walk of the tree would.
    """
    calls = [call for index in (facts.calls_by_name, facts.attribute_calls) for found in index.values() for call in found]
    calls.sort(key=lambda c: (c.lineno, c.col_offset, -(c.end_lineno or 0), -(c.end_col_offset or 0)))
    return calls


# Libraries with no Gymnasium release whose factories make envs through legacy gym's own
# registry: registering ale_py with Gymnasium does nothing for them.
_LEGACY_GYM_LIBRARIES = frozenset({"baselines", "stable_baselines", "ptan"})


def _default(function: ast.FunctionDef | ast.AsyncFunctionDef, param: ast.arg) -> ast.expr | None:
    """The default value of ``param`` in ``function``'s signature, if it has one."""
    args = function.args
    positional = [*args.posonlyargs, *args.args]
    if param in positional:
        index = positional.index(param) - (len(positional) - len(args.defaults))
        return args.defaults[index] if index >= 0 else None
    if param in args.kwonlyargs:
        return args.kw_defaults[args.kwonlyargs.index(param)]
    return None


def _under_condition(facts: ModuleFacts, node: ast.AST, function: ast.AST) -> bool:
    """``node`` runs only on one branch of a test inside ``function`` (the body of an ``if``,
    a branch of a conditional expression or of ``and``/``or``); a test itself always runs."""
    child = node
    for ancestor in facts.ancestors(node):
        if ancestor is function:
            return False
        if isinstance(ancestor, (ast.If, ast.IfExp, ast.While)) and child is not ancestor.test:
            return True
        if isinstance(ancestor, ast.BoolOp) and child is not ancestor.values[0]:
            return True
        if isinstance(ancestor, ast.ExceptHandler):
            return True
        child = ancestor
    return False


def _split_module_prefix(text: str) -> tuple[str, str]:
    if ":" in text:
        module, env_id = text.split(":", 1)
        return module + ":", env_id
    return "", text


def _is_docstring(statement: ast.stmt) -> bool:
    return isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Constant) and isinstance(statement.value.value, str)


def _imported_modules(tree: ast.Module, facts: ModuleFacts) -> set[str]:
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


def _registration_message(package: EnvPackage) -> str:
    if package is ALE:
        return "Atari ids need `import ale_py` since Gymnasium 1.0 removed plugin auto-registration; added it with `register_envs(ale_py)`"
    return (
        f"these ids need `import {package.module}` since Gymnasium 1.0 removed plugin auto-registration; "
        f"added it: check the package is installed and registers the ids on import"
    )


# -- building the new code ------------------------------------------------------------------


def _with_string_value(node: cst.SimpleString, text: str) -> cst.SimpleString:
    return node.with_changes(value=f"{node.prefix}{node.quote}{text}{node.quote}")


def _append_keywords(call: cst.Call, keywords: list[tuple[str, str]]) -> cst.Call:
    """Add ``name=value`` arguments at the end, following the call's comma style."""
    args = list(call.args)
    no_space = cst.SimpleWhitespace("")
    new_args = [
        cst.Arg(keyword=cst.Name(name), value=cst.parse_expression(value), equal=cst.AssignEqual(whitespace_before=no_space, whitespace_after=no_space))
        for name, value in keywords
    ]
    if not args:
        return call.with_changes(args=new_args)
    last = args[-1]
    separator = cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))
    if isinstance(last.comma, cst.Comma):
        # Trailing-comma style (often one argument per line): copy the separator of the
        # previous argument so new arguments land on their own lines.
        if len(args) > 1 and isinstance(args[-2].comma, cst.Comma):
            between = args[-2].comma
        elif isinstance(call.whitespace_before_args, cst.ParenthesizedWhitespace):
            between = cst.Comma(whitespace_after=call.whitespace_before_args)  # the line break after "("
        else:
            between = separator
        args[-1] = last.with_changes(comma=between)
        new_args = [a.with_changes(comma=between) for a in new_args[:-1]] + [new_args[-1].with_changes(comma=last.comma)]
    else:
        args[-1] = last.with_changes(comma=separator)
        new_args = [a.with_changes(comma=separator) for a in new_args[:-1]] + [new_args[-1]]
    return call.with_changes(args=args + new_args)
