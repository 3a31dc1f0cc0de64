"""A module whose every env comes from a Gym-only plugin stays on gym as it is (GM101).

Some packages register their env ids with gym when imported and never had a Gymnasium
release (``d4rl``, ``pybullet_envs``...: ``catalog.PLUGIN_OF_FAMILY``). ``gymnasium.make`` of
their ids fails (NameNotFound), and their envs keep gym's API and their own methods
(``get_dataset``), so migrating a module that only makes such envs breaks it on every path:
its imports, resets, steps and forwarded reads would all be changed for envs that stay
gym's. Such a module is left whole, with one item: keep it on gym with the plugin, or port
both (Shimmy, Minari, the package's Gymnasium successor).

A module's envs come only from the plugin when every ``make`` in it makes the plugin's ids:
ids it registers, or, where the module imports the plugin (which registers its ids), ids
that are not Gymnasium's (none of its own envs, of gym's that moved, of a package
registered with Gymnasium) and that the run does not register. The ids must be known: a
literal, a constant, what the run's calls pass, or every value the module spells for one
(``f"{task}-medium-v2"`` in a loop over literal tasks). Any other env settles it the other
way: a make of an id the run cannot read (it may be Gymnasium's, the plugin's envs then
coming through Shimmy), a make of another id, an env class or wrapper the module defines, a
constructor of a Gym env class, a factory of the run. A module that makes no env is decided
as before.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import call_argument, string_value
from gymmigrate.facts.receivers import Receivers
from gymmigrate.rules.env_ids.catalog import (
    REGISTERING_PLUGINS,
    known_elsewhere,
    plugin_of,
)
from gymmigrate.rules.wrapper_usage.atari_limits import make_ids

# The calls that make an env from an id (after the gym/gymnasium prefix).
_MAKERS = N.GYM_ENV_FACTORIES | frozenset({"vector.make", "make_vec"})
# gym's and Gymnasium's registry functions: a module that registers ids makes envs of its own
_REGISTER = frozenset({"register", "envs.register", "envs.registration.register"})


def plugin_only_module(facts: ModuleFacts, receivers: Receivers) -> tuple[str, ...]:
    """The Gym-only plugins that make every env of this module, in order (see the module
    docstring); empty where another env is made or none is."""
    if "make" not in facts.text or any(q.split(".", 1)[0] == "gymnasium" for q in facts.imports.values()):
        return ()  # no env made, or a module on Gymnasium already
    imported = _imported_plugins(facts, receivers)
    if not imported and not any(plugin_of(string_value(s) or "") for s in facts.strings):
        return ()  # cheap: no plugin imported here, no plugin id spelled here
    return facts.memo(("plugin-only-module", 0), lambda: _plugin_only(facts, receivers, imported))


def _imported_plugins(facts: ModuleFacts, receivers: Receivers) -> frozenset[str]:
    project = receivers.project
    tops = {q.split(".", 1)[0] for q in facts.imports.values()}
    return frozenset(t for t in tops & REGISTERING_PLUGINS if project is None or not project.is_module(t))


def _plugin_only(facts: ModuleFacts, receivers: Receivers, imported: frozenset[str]) -> tuple[str, ...]:
    if any(_gym_base(facts, base) for classdef in facts.all_classes for base in classdef.bases):
        return ()  # an env or wrapper class of its own: the module has Gym code of its own
    plugins: set[str] = set()
    made = False
    for node in facts.parents:
        if not isinstance(node, ast.Call):
            continue
        rests = {N.strip_gym_prefix(q) for q in facts.qualified_names(node.func)}
        if rests & _REGISTER:
            return ()  # it registers envs of its own
        if rests & _MAKERS:
            made = True
            ids = make_ids(facts, receivers, node)
            if ids is None or None in ids:
                argument = call_argument(node, 0, "id")
                ids = _spelled(facts, argument, 0) if argument is not None else None
            for env_id in ids if ids is not None else [None]:
                plugin = _plugin_of_id(env_id, imported, receivers)
                if plugin is None:
                    return ()  # an env that is not a plugin's
                plugins.add(plugin)
        elif _other_env(facts, receivers, node, rests):
            return ()
    return tuple(sorted(plugins)) if made else ()


def _plugin_of_id(env_id: str | None, imported: frozenset[str], receivers: Receivers) -> str | None:
    """The plugin whose env ``make(env_id)`` makes (None: the id may be another's, or is
    not known: a parameter, a command-line option)."""
    if env_id is None:
        return None
    project = receivers.project
    plugin = plugin_of(env_id)
    if plugin is not None:
        if project is not None and (project.is_module(plugin) or project.may_register(env_id)):
            return None  # the run is that package (``gfootball``'s own tests), or registers the id itself
        return plugin
    if known_elsewhere(env_id) or len(imported) != 1:
        return None  # Gymnasium's; or no plugin here to have registered it, or several that may have
    if project is not None and project.may_register(env_id):
        return None  # the run's own id
    return next(iter(imported))


# How many ids a spelled id may stand for before it counts as unknown.
_MAX_SPELLED = 64


def _spelled(facts: ModuleFacts, expr: ast.expr, depth: int) -> list[str | None] | None:
    """Every string ``expr`` may be where the module spells them all: a literal, a name
    bound only to such values or as the variable of a loop over a literal list or tuple of
    them, an f-string or ``+`` of such parts (``f"{task}-{level}-v2"`` in loops over the
    tasks and levels). None where any part is not spelled here."""
    if depth > 4:
        return None
    value = string_value(expr)
    if value is not None:
        return [value]
    if isinstance(expr, ast.Name):
        found: list[str | None] = []
        bindings = facts.bindings_of(expr)
        for binding in bindings:
            holder = facts.parent(binding)
            if isinstance(holder, (ast.For, ast.comprehension)) and holder.target is binding and isinstance(holder.iter, (ast.List, ast.Tuple)):
                items = [_spelled(facts, element, depth + 1) for element in holder.iter.elts]
            elif isinstance(holder, ast.Assign) and holder.targets == [binding]:
                items = [_spelled(facts, holder.value, depth + 1)]
            else:
                return None
            if any(item is None for item in items):
                return None
            found += [v for item in items for v in item or ()]
        return found or None
    if isinstance(expr, ast.JoinedStr):
        parts: list[list[str | None] | None] = [
            _spelled(facts, part.value, depth + 1) if isinstance(part, ast.FormattedValue) and part.format_spec is None and part.conversion == -1 else _spelled(facts, part, depth + 1)
            for part in expr.values
        ]
        return _joined(parts)
    if isinstance(expr, ast.BinOp) and isinstance(expr.op, ast.Add):
        return _joined([_spelled(facts, expr.left, depth + 1), _spelled(facts, expr.right, depth + 1)])
    return None


def _joined(parts: list[list[str | None] | None]) -> list[str | None] | None:
    combined: list[str] = [""]
    for part in parts:
        if part is None or None in part or len(combined) * len(part) > _MAX_SPELLED:
            return None
        combined = [left + right for left in combined for right in part if right is not None]
    return list(combined)


def _gym_base(facts: ModuleFacts, base: ast.expr) -> bool:
    return any(N.strip_gym_prefix(q) is not None for q in facts.qualified_names(base))


def _other_env(facts: ModuleFacts, receivers: Receivers, call: ast.Call, rests: set[str | None]) -> bool:
    """``call`` makes a Gym env other than by an id: a constructor of gym's env classes, an
    env class or factory of the run."""
    if any(rest is not None and rest.startswith("envs.") and "registr" not in rest and rest.rsplit(".", 1)[-1][:1].isupper() for rest in rests):
        return True  # ``CartPoleEnv()``
    project = receivers.project
    if project is None:
        return False
    return any(project.call_kind(q) in (EnvKind.GYM_ENV, EnvKind.GYM_VEC) for q in facts.qualified_names(call.func))


def first_gym_import(facts: ModuleFacts) -> ast.Import | ast.ImportFrom | None:
    """Where the module's item goes: its first import of gym."""
    for statement in facts.import_statements:
        if isinstance(statement, ast.Import) and any(N.strip_gym_prefix(a.name) is not None for a in statement.names):
            return statement
        if isinstance(statement, ast.ImportFrom) and not statement.level and N.strip_gym_prefix(statement.module or "") is not None:
            return statement
    return None

