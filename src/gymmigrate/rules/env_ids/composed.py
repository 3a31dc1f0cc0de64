"""Env ids built from parts (GM809).

``def make(domain, task): return gym.make(f"{domain}-{task}")`` called as
``make("Swimmer", "v3")``: no literal holds the id, so the id rules (GM803/GM805) never see
it. Where every part is a literal at a call of that def in this module (an argument or the
parameter's default), the id is computed and checked like a literal one; a retired or
removed id is reported at the call, since the parts may serve other ids too (a version
shared by several domains) and are not rewritten. Parts that come from elsewhere (a loop
over a table, another module) are not followed.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.env_ids.catalog import migration_for, removed_family
from gymmigrate.rules.env_ids.syntax import ID_FUNCTIONS, id_argument

RULES = (
    Rule(
        "GM809",
        "ids built from parts",
        FixKind.FLAG,
        "An id a make builds from a def's parameters (`f\"{domain}-{task}\"`) whose parts are literals at a call of that def "
        "is checked like a literal id: a retired or removed one is reported at the call.",
    ),
)


class ComposedIds(RuleFamily):
    RULES = RULES

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        return "make" in facts.text and ("{" in facts.text or ".join" in facts.text)

    def decide(self) -> None:
        if self.notes.gym_kept_for is not None:
            return  # the file stays on gym with the library its envs go to: gym registers its ids
        for call in self._id_calls():
            parts = _parts(id_argument(call))
            if parts is None or not any(isinstance(p, ast.Name) for p in parts):
                continue
            function = self.facts.enclosing_function(call)
            if function is None:
                continue
            self._check_callers(call, function, parts)

    def _id_calls(self) -> list[ast.Call]:
        found = []
        for node in ast.walk(self.facts.tree):
            if isinstance(node, ast.Call) and any(N.strip_gym_prefix(q) in ID_FUNCTIONS for q in self.facts.qualified_names(node.func)):
                if any(q.split(".", 1)[0] in ("gym", "gymnasium") for q in self.facts.qualified_names(node.func)):
                    found.append(node)
        return found

    def _check_callers(self, make: ast.Call, function: ast.FunctionDef | ast.AsyncFunctionDef, parts: list[ast.expr]) -> None:
        params = [a.arg for a in (*function.args.posonlyargs, *function.args.args)]
        names = {p.id for p in parts if isinstance(p, ast.Name)}
        if not names <= set(params) | {a.arg for a in function.args.kwonlyargs}:
            return  # a part that is not a parameter: not followed
        for name in names:  # a parameter rebound in the def is not what the callers pass
            if any(isinstance(n, ast.Name) and n.id == name and isinstance(n.ctx, ast.Store) for n in ast.walk(function)):
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
