"""Env ids built from parts (GM809).

``def make(domain, task): return gym.make(f"{domain}-{task}")`` called as
``make("Swimmer", "v3")``: no literal holds the id, so the id rules (GM803/GM805) never see
it. Where every part is a literal at a call of that def in this module (an argument or the
parameter's default), the id is computed and checked like a literal one; a retired or
removed id is reported at the call, since the parts may serve other ids too (a version
shared by several domains) and are not rewritten. Parts that come from elsewhere (a loop
over a table, another module) are not followed.

``ROBOT + "-v2"`` (or ``f"{ROBOT}-v2"``) where every name is bound once to a literal
(``ROBOT = "Swimmer"``) is an id the module builds whatever calls it: it is computed, and
where it goes is followed as a literal's is (``facts.handovers``). One that reaches a make,
or another library's or the project's code the run cannot follow, is reported where it is
built; several builds of the same id are one question.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.handovers import handovers
from gymmigrate.facts.module import full_name, walk
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.env_ids.catalog import migration_for, removed_family
from gymmigrate.rules.env_ids.id_sites import IdSites
from gymmigrate.rules.env_ids.syntax import ID_FUNCTIONS, id_argument

RULES = (
    Rule(
        "GM809",
        "ids built from parts",
        FixKind.FLAG,
        "An id a make builds from a def's parameters (`f\"{domain}-{task}\"`) whose parts are literals at a call of that def, "
        "or from names bound to literals (`ROBOT + \"-v2\"`), is checked like a literal id: a retired or removed one is reported.",
    ),
)


class ComposedIds(RuleFamily):
    RULES = RULES

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        text = facts.text
        return ("make" in text and ("{" in text or ".join" in text)) or "-v" in text

    def decide(self) -> None:
        if self.notes.gym_kept_for is not None:
            return  # the file stays on gym with the library its envs go to: gym registers its ids
        text = self.facts.text
        calls = self._id_calls() if "make" in text and ("{" in text or ".join" in text) else []
        for call in calls:
            parts = _parts(id_argument(call))
            if parts is None or not any(isinstance(p, ast.Name) and _literal_of(self.facts, p) is None for p in parts):
                continue  # no parameter among the parts: a built id of the module, below
            function = self.facts.enclosing_function(call)
            if function is None:
                continue
            self._check_callers(call, function, parts)
        self._check_built_ids()

    def _check_built_ids(self) -> None:
        """``gym.make(ROBOT + "-v2")`` with ``ROBOT = "Swimmer"``: the id the module
        builds, checked where it goes."""
        sites = IdSites(self.facts, self.receivers)
        for built in _built_strings(self.facts):
            value = _built_value(self.facts, built)
            if value is None or not any(isinstance(n, ast.Name) for n in walk(built)):
                continue  # ``f"Pendulum-v0"`` is a literal written oddly: nothing is built from names
            migration = migration_for(value)
            hint = removed_family(value)
            if migration is None and hint is None:
                continue
            for handover in handovers(self.facts, self.receivers, built):
                reaches = sites.reaches(handover)
                if reaches is None:
                    continue
                names = sorted({f"`{n.id}` is `{_literal_of(self.facts, n)}`" for n in walk(built) if isinstance(n, ast.Name)})
                built_text = f"`{self.facts.segment(built)}` builds the id `{value}` ({', '.join(names)})"
                callee = full_name(handover.call.func) or "a call"
                now = f"it is `{migration.new_id}` now ({migration.reason})" if migration is not None else f"it no longer exists: {hint}"
                if reaches == "make":
                    message = f"{built_text}, which `{callee}(...)` makes: {now}; change the parts by hand"
                else:
                    message = f"{built_text}, handed to `{callee}(...)`, which the run could not follow to a make; if it reaches gym.make, {now}"
                self.report(built, "GM809", message, question=("GM809 built", value))
                break

    def _id_calls(self) -> list[ast.Call]:
        found = []
        for node in walk(self.facts.tree):
            if isinstance(node, ast.Call) and any(N.strip_gym_prefix(q) in ID_FUNCTIONS for q in self.facts.qualified_names(node.func)):
                if any(q.split(".", 1)[0] in ("gym", "gymnasium") for q in self.facts.qualified_names(node.func)):
                    found.append(node)
        return found

    def _check_callers(self, make: ast.Call, function: ast.FunctionDef | ast.AsyncFunctionDef, parts: list[ast.expr]) -> None:
        params = [a.arg for a in (*function.args.posonlyargs, *function.args.args)]
        # a name bound once to a literal (``SEPARATOR = "-"``) is that literal at every call
        parts = [_constant_part(self.facts, p) for p in parts]
        names = {p.id for p in parts if isinstance(p, ast.Name)}
        if not names <= set(params) | {a.arg for a in function.args.kwonlyargs}:
            return  # a part that is not a parameter: not followed
        for name in names:  # a parameter rebound in the def is not what the callers pass
            if any(isinstance(n, ast.Name) and n.id == name and isinstance(n.ctx, ast.Store) for n in walk(function)):
                return
        classdef = self.facts.parent(function)
        method = isinstance(classdef, ast.ClassDef)
        if method and function.name != "__init__":
            return
        sites = self.receivers.call_sites(function, classdef if method else None)  # type: ignore[arg-type]
        positional = params[1:] if method else params
        template = self.facts.segment(id_argument(make))  # type: ignore[arg-type]
        for site in sites:
            values = _literal_arguments(site, function, positional)
            if values is None or not all(isinstance(values.get(n), str) for n in names):
                continue
            env_id = "".join(p.value if isinstance(p, ast.Constant) else values[p.id] for p in parts)  # type: ignore[attr-defined,misc]
            built = f"this call builds the id `{env_id}` (`{template}` on line {make.lineno})"
            migration = migration_for(env_id)
            if migration is not None:
                self.report(site, "GM809", f"{built}: it is `{migration.new_id}` now ({migration.reason}); change the parts by hand")
                continue
            hint = removed_family(env_id)
            if hint is not None:
                self.report(site, "GM809", f"{built}, which no longer exists: {hint}")


def _literal_of(facts: ModuleFacts, name: ast.Name) -> str | None:
    """The string a name holds wherever it is read: its one binding assigns a literal."""
    values = facts.assigned_values(name, sole_target=True)
    if values is None or len(values) != 1:
        return None
    value = values[0]
    return value.value if isinstance(value, ast.Constant) and isinstance(value.value, str) else None


def _constant_part(facts: ModuleFacts, part: ast.expr) -> ast.expr:
    if isinstance(part, ast.Name):
        literal = _literal_of(facts, part)
        if literal is not None:
            return ast.copy_location(ast.Constant(literal), part)
    return part


def _built_strings(facts: ModuleFacts) -> list[ast.expr]:
    """The outermost ``+`` chains and f-strings with a part that may end an id: a literal
    holding ``-v`` (``"-v2"``, ``f"{name}-v{version}"``) or a read of a name bound to one
    (``f"{ROBOT}{VERSION}"``), in source order."""
    found: list[ast.expr] = []
    seen: set[int] = set()
    for string in facts.strings:
        if "-v" not in str(string.value):
            continue
        parts: list[ast.AST] = [string]
        statement = facts.parent(string)
        if isinstance(statement, ast.Assign) and len(statement.targets) == 1 and isinstance(statement.targets[0], ast.Name):
            target = statement.targets[0]
            parts += facts.reads_of(target.id, target)
        for part in parts:
            node, parent = part, facts.parent(part)
            while isinstance(parent, (ast.FormattedValue, ast.JoinedStr)) or (isinstance(parent, ast.BinOp) and isinstance(parent.op, ast.Add)):
                node, parent = parent, facts.parent(parent)
            if node is not part and id(node) not in seen and isinstance(node, ast.expr):
                seen.add(id(node))
                found.append(node)
    found.sort(key=lambda node: (node.lineno, node.col_offset))
    return found


def _built_value(facts: ModuleFacts, node: ast.expr) -> str | None:
    """The text a ``+`` chain or f-string of literals and names bound once to literals
    always builds; None when any part may be something else."""
    if isinstance(node, ast.Constant):
        return node.value if isinstance(node.value, str) else None
    if isinstance(node, ast.Name):
        return _literal_of(facts, node)
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add):
        left, right = _built_value(facts, node.left), _built_value(facts, node.right)
        return None if left is None or right is None else left + right
    if isinstance(node, ast.JoinedStr):
        pieces = []
        for piece in node.values:
            if isinstance(piece, ast.FormattedValue):
                if piece.conversion != -1 or piece.format_spec is not None:
                    return None
                piece = piece.value
            text = _built_value(facts, piece)
            if text is None:
                return None
            pieces.append(text)
        return "".join(pieces)
    return None


def _parts(value: ast.expr | None) -> list[ast.expr] | None:
    """``f"{a}-{b}"`` / ``"-".join([a, b])`` -> ``[a, "-", b]`` (string constants and names), else None."""
    if isinstance(value, ast.JoinedStr):
        parts: list[ast.expr] = []
        for piece in value.values:
            if isinstance(piece, ast.Constant) and isinstance(piece.value, str):
                parts.append(piece)
            elif isinstance(piece, ast.FormattedValue) and piece.conversion == -1 and piece.format_spec is None and isinstance(piece.value, ast.Name):
                parts.append(piece.value)
            else:
                return None
        return parts
    if (
        isinstance(value, ast.Call)
        and isinstance(value.func, ast.Attribute)
        and value.func.attr == "join"
        and isinstance(value.func.value, ast.Constant)
        and isinstance(value.func.value.value, str)
        and len(value.args) == 1
        and not value.keywords
        and isinstance(value.args[0], (ast.List, ast.Tuple))
        and all(isinstance(e, (ast.Name, ast.Constant)) for e in value.args[0].elts)
    ):
        separator = value.func.value
        joined: list[ast.expr] = []
        for i, element in enumerate(value.args[0].elts):
            if i:
                joined.append(separator)
            joined.append(element)
        return joined
    return None


def _literal_arguments(call: ast.Call, function: ast.FunctionDef | ast.AsyncFunctionDef, positional: list[str]) -> dict[str, object] | None:
    """What each parameter holds at ``call``: a literal argument, else a literal default."""
    if any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords):
        return None
    values: dict[str, object] = {}
    args = function.args
    defaults = dict(zip([a.arg for a in (*args.posonlyargs, *args.args)][-len(args.defaults) :] if args.defaults else [], args.defaults))
    defaults.update({a.arg: d for a, d in zip(args.kwonlyargs, args.kw_defaults) if d is not None})
    for name, default in defaults.items():
        if isinstance(default, ast.Constant):
            values[name] = default.value
    for name, argument in zip(positional, call.args):
        values[name] = argument.value if isinstance(argument, ast.Constant) else None
    for keyword in call.keywords:
        values[keyword.arg] = keyword.value.value if isinstance(keyword.value, ast.Constant) else None  # type: ignore[index]
    return values
