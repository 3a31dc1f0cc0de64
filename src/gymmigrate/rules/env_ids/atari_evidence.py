"""Atari envs made where no literal id says so (GM106): a module that makes them needs
``import ale_py`` + ``gym.register_envs(ale_py)``. ``ids.py`` asks about the id reads
``IdSites.find`` noted: an id built from a template whose literal part names an Atari id
(``'{}NoFrameskip-v4'.format(game)``), and a helper that makes its env from a parameter
and uses what only Atari envs have (``.ale``, ``get_action_meanings()``, a
``NoFrameskip`` check), unless every caller of the run passes non-Atari ids.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Callable

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.atari_signs import (
    has_own_sign,
    reads_atari_interface,
    self_stored,
    under_condition,
)
from gymmigrate.facts.module import call_argument, full_name, param_default, walk
from gymmigrate.facts.receivers import Receivers
from gymmigrate.findings import FixKind
from gymmigrate.rules.env_ids.catalog import is_atari_id
from gymmigrate.rules.env_ids.syntax import (
    plain_string,
    split_module_prefix,
)

# What says a module makes Atari envs: the node to report at, the message and the fix kind.
Evidence = tuple[ast.expr, str, FixKind]


class AtariEvidence:
    """The Atari signs of one module's id reads."""

    def __init__(self, facts: ModuleFacts, receivers: Receivers, literal_of: Callable[[ast.Name], ast.Constant | None]) -> None:
        self.facts = facts
        self.receivers = receivers
        self.literal_of = literal_of  # ``IdSites.literal_of``: the literal a name holds where it is read

    def formatted_id(self, arg: ast.expr) -> Evidence | None:
        """``gym.make('{}NoFrameskip-{}'.format(game, version))`` (or an f-string, directly or
        through the name it is assigned to): the literal part of the template names an Atari id
        (``NoFrameskip``, ``-ramNoFrameskip``, the ``ALE/`` namespace) whatever is filled in, so
        the module makes Atari envs and needs ``import ale_py``. Where only some of the
        assignments that may reach the call build such an id, it is for review."""
        values: list[ast.expr] = [arg]
        if isinstance(arg, ast.Name):
            values = []
            for binding in self.facts.bindings_of(arg):
                statement = self.facts.parent(binding) if isinstance(binding, ast.Name) else None
                if not (isinstance(statement, ast.Assign) and statement.targets == [binding]):
                    return None  # a parameter, a loop variable...: what reaches the call is unknown
                values.append(statement.value)
        templates = [(value, atari_template(self.facts, value)) for value in values]
        found = [(value, part) for value, part in templates if part is not None]
        if not found:
            return None
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
                "since Gymnasium 1.0 Atari envs need `import ale_py`; added it with `register_envs(ale_py)`"
            )
            kind = FixKind.ASSIST
        return value, message, kind

    def helper(self, call: ast.Call, name: ast.Name | ast.Attribute | ast.Subscript) -> Evidence | None:
        """``def make_atari(env_id): env = gym.make(env_id); assert "NoFrameskip" in env.spec.id``:
        a helper that makes its env from a parameter and uses what only Atari envs have (the
        ``ale`` interface, ``get_action_meanings()``, a ``NoFrameskip`` check, directly or in
        a def or class of this module it calls) makes Atari envs, whatever id its callers
        pass: its module needs ``import ale_py``. Where every sign sits under a condition
        (``if "NoFrameskip" in env_id:``), the helper may make other envs too: for review."""
        function = self.facts.enclosing_function(call)
        if function is None:
            if isinstance(name, ast.Name):
                return None
            # ``env = gym.make(sys.argv[1])`` in a script's top level: the script's top-level
            # code is what uses the env it makes
            return self._script(call, name)
        bindings: list[ast.AST] = []
        if isinstance(name, ast.Name):
            bindings = self.facts.bindings_of(name)
            if len(bindings) > 1:
                # ``env = gym.make(env)``: the parameter rebound by the make itself (and later)
                bindings = _parameter_alone(self.facts, name, bindings, function)
            # a parameter, or a local bound once from what the run cannot read (``env_id = task.env_id``)
            if len(bindings) != 1 or not isinstance(bindings[0], (ast.arg, ast.Name)):
                return None
        # else ``gym.make(self.game)``: what the instance holds is set elsewhere; only signs can tell
        signs = [(sign, node) for node in walk(function) for sign in self._atari_signs(node, function)]
        signs.sort(key=lambda found: found[0].startswith("through"))  # its own signs first
        where = {id(node): function for _, node in signs}
        owner = self.facts.parent(function)
        # an env class named for Atari (``class AtariRamEnv``) says what the env it holds is
        named = isinstance(owner, ast.ClassDef) and _named_for_atari(owner.name)
        if not signs and isinstance(owner, ast.ClassDef):
            # ``self.env = gym.make(env_id)`` in ``__init__``, and ``self.env.unwrapped.ale.lives()``
            # in another method: the class holds an env that has what only Atari envs have.
            for method in owner.body:
                if isinstance(method, (ast.FunctionDef, ast.AsyncFunctionDef)) and method is not function:
                    for node in walk(method):
                        for sign in self._atari_signs(node, method):
                            signs.append((sign.replace("it ", f"its class `{owner.name}` ", 1), node))
                            where[id(node)] = method
            signs.sort(key=lambda found: found[0].startswith("through"))
        if not signs and named and isinstance(owner, ast.ClassDef):
            # ``class AtariRamEnv`` making ``gym.make(self.game)``: the author's word for what it makes
            signs.append((f"its class `{owner.name}` is {_NAMED}", function))
            where[id(function)] = function
        if not signs:
            return None
        certain = [
            sign
            for sign, node in signs
            if not ("tests for" in sign or _NAMED in sign or under_condition(self.facts, node, where[id(node)]))
        ]
        evidence = (certain or [sign for sign, _ in signs])[0]
        given, complete = ([], False) if certain or not bindings or not isinstance(bindings[0], ast.arg) else self._ids_given(function, bindings[0])
        if complete and given and not any(is_atari_id(i) for i in given):
            return None  # every caller of the run passes an id, none an Atari one: no ale_py needed
        if any(is_atari_id(i) for i in given):
            atari = next(i for i in given if is_atari_id(i))
            evidence = f"{evidence}, and a call of the run passes it the Atari id `{atari}`"
            if complete and all(is_atari_id(i) for i in given):
                certain = [evidence]  # every id it is given is an Atari one
            # else other ids reach the make too (another family's, or ones the run cannot
            # read): it makes Atari envs, not only them
        maker = f"{owner.name}.{function.name}" if isinstance(owner, ast.ClassDef) else function.name
        if certain:
            message = (
                f"`{maker}` makes Atari envs ({evidence}): since Gymnasium 1.0 they need `import ale_py`; "
                "added it with `register_envs(ale_py)`"
            )
            kind = FixKind.AUTO
        else:
            condition = "" if _NAMED in evidence else ", under a condition"
            message = (
                f"`{maker}` may make Atari envs ({evidence}{condition}): since Gymnasium 1.0 they need "
                "`import ale_py`; added it with `register_envs(ale_py)`"
            )
            kind = FixKind.ASSIST
        return name, message, kind

    def _script(self, call: ast.Call, name: ast.Attribute | ast.Subscript) -> Evidence | None:
        """``env = gym.make(sys.argv[1])`` at a script's top level (or under its ``if __name__ ==
        "__main__":``) whose top-level code uses what only Atari envs have: the script makes
        Atari envs, and any other id the command line names too, so the registration is for
        review (an import that may fail where ale-py is not installed)."""
        scope: ast.AST = self.facts.enclosing(call, ast.If) or self.facts.tree
        signs: list[str] = []
        pending = list(ast.iter_child_nodes(scope))
        while pending:
            node = pending.pop(0)
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.Lambda)):
                continue  # what a def does runs only where it is called (``through`` below)
            signs += self._atari_signs(node, scope)
            pending.extend(ast.iter_child_nodes(node))
        if not signs:
            return None
        message = (
            f"this script makes its env from an id it is given and {signs[0].removeprefix('it ')}, which only Atari envs have: "
            "since Gymnasium 1.0 Atari envs need `import ale_py`; added it with `register_envs(ale_py)`"
        )
        return name, message, FixKind.ASSIST

    def _ids_given(self, function: ast.AST, param: ast.arg) -> tuple[list[str], bool]:
        """The env ids the calls of the run give ``param`` of the top-level def ``function``:
        the calls of this module and of the others (``ProjectView.passed_ids``), a default
        where a call passes none; and whether that is every call. Not every call when one
        passes something else, when the def is read as a value anywhere (it may be called
        unseen), when nobody calls it, or when the other modules of the run are not read."""
        project = self.receivers.project
        if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)) or self.facts.parent(function) is not self.facts.tree:
            return [], False
        params = [*function.args.posonlyargs, *function.args.args]
        if param not in params:
            return [], False
        complete = project is not None and not project.handed_on(function.name)
        position = params.index(param)
        default = param_default(function, param)
        default_id = plain_string(self.facts, default) if isinstance(default, ast.Constant) else None
        found: list[str] = []
        reads = self.facts.reads_of(function.name)
        for read in reads:
            call = self.facts.parent(read)
            if not (isinstance(call, ast.Call) and call.func is read) or self.facts.bindings_of(read) != [function]:
                complete = False  # handed on as a value (or another binding of the name)
                continue
            if any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords):
                complete = False
                continue
            argument = call_argument(call, position, param.arg)
            if argument is None:
                value = default_id
            elif isinstance(argument, ast.Name):
                literal = self.literal_of(argument)
                value = plain_string(self.facts, literal) if literal is not None else None
            else:
                value = plain_string(self.facts, argument) if isinstance(argument, ast.Constant) else None
            if value is None:
                complete = False
                continue
            found.append(split_module_prefix(value)[1])
        for passed in project.passed_ids(function.name, param.arg) if project is not None else ():
            passed = default_id if passed == "" else passed
            if passed is None:
                complete = False
                continue
            found.append(split_module_prefix(passed)[1])
        return found, complete and bool(found)

    def _atari_signs(self, node: ast.AST, function: ast.AST) -> list[str]:
        """What in ``node`` only an Atari env has: ``.ale``, ``get_action_meanings()``, a
        ``"NoFrameskip"`` check; or a call of a def or class of this module that has one."""
        if isinstance(node, ast.Attribute) and reads_atari_interface(node, self_stored(self.facts.enclosing_class(node))):
            return ["it uses `.ale`"] if node.attr == "ale" else ["it calls `get_action_meanings()`"]
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
            callee = node.func.id if isinstance(node.func, ast.Name) else node.func.attr
            if _named_for_atari(callee):
                # ``preprocessAtari(frame)``, ``AtariPreprocessing(env)``: a helper named for Atari frames
                return [f"it calls `{callee}`, {_NAMED}"]
        return []

    def _has_atari_sign(self, definition: ast.AST) -> bool:
        return bool(self.facts.memo(("atari-sign", id(definition)), lambda: has_own_sign(definition)))


# How a sign that is only a name reads: the author's word, not what the code does with the
# env, so the registration it brings is for review.
_NAMED = "named for Atari"
_WORDS = re.compile(r"[A-Z]+(?![a-z])|[A-Z]?[a-z]+|[0-9]+")


def _named_for_atari(name: str) -> bool:
    """``AtariRamEnv``, ``preprocessAtari``, ``make_atari``: one of the name's words is Atari."""
    return any(word.lower() == "atari" for word in _WORDS.findall(name))


# What the literal part of a built id names for certain: an Atari id, whatever the
# placeholders hold (``'{}NoFrameskip-{}'``, ``f"ALE/{game}-v5"``).
_ATARI_TEMPLATE_PARTS = ("NoFrameskip", "ALE/")


def atari_template(facts: ModuleFacts, value: ast.expr) -> str | None:
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


def _parameter_alone(facts: ModuleFacts, read: ast.Name, bindings: list[ast.AST], function: ast.AST) -> list[ast.AST]:
    """The parameter of ``bindings`` when it is the only one that can reach ``read``: every
    other binding is a plain assignment in the statement of the read (``env = make(env)``)
    or after it, and no loop of ``function`` runs the read again. Else ``bindings``."""
    params: list[ast.AST] = [b for b in bindings if isinstance(b, ast.arg)]
    if len(params) != 1:
        return bindings
    statement = facts.statement_of(read)
    for ancestor in facts.ancestors(read):
        if ancestor is function:
            break
        if isinstance(ancestor, (ast.For, ast.AsyncFor, ast.While)):
            return bindings
    for binding in bindings:
        if binding is params[0]:
            continue
        if not isinstance(binding, ast.Name):
            return bindings
        bound = facts.statement_of(binding)
        if bound is None or facts.enclosing_function(binding) is not function:
            return bindings
        if bound is not statement and (bound.lineno, bound.col_offset) <= (read.lineno, read.col_offset):
            return bindings
    return params
