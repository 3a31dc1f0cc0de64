"""Which ``make`` results are Atari envs, where that changes what a time-limit test means.

gym registered every Atari id with a step limit (``max_episode_steps``: 10000 for the v0/v4
ids, 400000 for ``*NoFrameskip-v4``), so ``gym.make`` put a ``TimeLimit`` outermost on
them as on any registered env. ale-py 0.12, which registers them for Gymnasium, gives none
(its only cap is ``max_num_frames_per_episode=108000``): ``gymnasium.make`` of an Atari id
returns ``OrderEnforcing<PassiveEnvChecker<AtariEnv>>``. On such a make result
``isinstance(env, TimeLimit)`` is False, ``env.spec.max_episode_steps`` is None, and
``env._max_episode_steps = N`` caps nothing (checked on Gymnasium 1.4 + ale-py 0.12.1:
``PongNoFrameskip-v4`` made plainly; with ``max_episode_steps=5`` it truncates at step 5).

``atari_make`` tells the forwarding rules (GM605, GM606) and TimeLimit's argument rule
(GM609) whether the make an expression holds is certainly an Atari one, may be one, or
is not shown to be: from the id literal, a module constant, or, for a parameter of a
top-level def, the ids every call of the run passes (as GM106 decides its import).
"""

from __future__ import annotations

import ast
from collections.abc import Hashable
from enum import Enum
from typing import TYPE_CHECKING, Protocol

from gymmigrate.edits.arguments import append_keyword
from gymmigrate.edits.lazy import cst
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.flow import Flow, contains, is_after
from gymmigrate.facts.module import FUNCTIONS, call_argument, walk
from gymmigrate.facts.receivers import Receivers
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.env_ids.catalog import is_atari_id

if TYPE_CHECKING:
    from gymmigrate.edits.plan import Plan


class Family(Protocol):
    """What these checks use of the family that asks them (forwarding, renames)."""

    facts: ModuleFacts
    receivers: Receivers
    plan: Plan

    def report(
        self, node: ast.AST, code: str, message: str, kind: FixKind | None = None, tier: Tier | None = None, question: Hashable | None = None
    ) -> None: ...


class Atari(Enum):
    CERTAIN = "certain"  # every id the make may get is an Atari id
    MAYBE = "maybe"  # some are


def is_make_call(facts: ModuleFacts, expr: ast.AST) -> bool:
    return isinstance(expr, ast.Call) and any(
        N.strip_gym_prefix(q) in ("make", "envs.make", "envs.registration.make") for q in facts.qualified_names(expr.func)
    )


def made_on_every_path(facts: ModuleFacts, expr: ast.expr) -> list[ast.Call] | None:
    """The ``make(...)`` calls ``expr`` holds the direct result of on every path (the call
    itself, or a name every binding of which assigns one), else None."""
    if is_make_call(facts, expr):
        return [expr]  # type: ignore[list-item]
    if not isinstance(expr, ast.Name):
        return None
    makes: list[ast.Call] = []
    for binding in facts.bindings_of(expr):
        statement = facts.parent(binding)
        if not (isinstance(statement, ast.Assign) and statement.targets == [binding] and is_make_call(facts, statement.value)):
            return None
        makes.append(statement.value)  # type: ignore[arg-type]
    return makes or None


def reaching_make(facts: ModuleFacts, expr: ast.AST) -> ast.Call | None:
    """The ``make(...)`` call whose result ``expr`` certainly holds where it is read: the
    call itself, or the assignment of one that dominates a read of a name."""
    if is_make_call(facts, expr):
        return expr  # type: ignore[return-value]
    if not isinstance(expr, ast.Name):
        return None
    statement = facts.statement_of(expr)
    if isinstance(statement, ast.Assign) and any(isinstance(t, ast.Name) and t.id == expr.id for t in statement.targets):
        return _make_before(facts, expr, statement)
    flow = Flow.of(facts)
    last = flow.last_binding_of(expr)
    assign = facts.parent(last) if isinstance(last, ast.Name) else None
    if not (isinstance(last, ast.Name) and isinstance(assign, ast.Assign) and assign.targets == [last]):
        return None
    if not (isinstance(assign.value, ast.Call) and is_make_call(facts, assign.value)):
        return _make_past_other_arm(facts, expr)
    if not flow.dominates(assign, expr, last) or not isinstance(assign.value, ast.Call) or not is_make_call(facts, assign.value):
        return None
    return assign.value


def _make_past_other_arm(facts: ModuleFacts, read: ast.Name) -> ast.Call | None:
    """``env = make(id)``, then ``if ...: env = W(env) else: env._max_episode_steps = N``:
    the read in one arm of an ``if`` sees the make, since every binding between them sits in
    the other arm of an ``if`` holding both (the flow's last binding is the textual one).
    Not in a loop. The make, or None."""
    if any(isinstance(a, (ast.For, ast.AsyncFor, ast.While)) for a in facts.ancestors(read)):
        return None
    makes: list[ast.Assign] = []
    others: list[ast.AST] = []
    for binding in facts.bindings_of(read):
        if not isinstance(binding, ast.Name):
            return None
        statement = facts.parent(binding)
        if not is_after(read, binding):
            continue  # after the read, outside any loop: not seen
        if isinstance(statement, ast.Assign) and statement.targets == [binding] and isinstance(statement.value, ast.Call) and is_make_call(facts, statement.value):
            makes.append(statement)
        else:
            others.append(binding)
    if len(makes) != 1 or not others:
        return None
    make = makes[0]
    flow = Flow.of(facts)
    if not (flow.same_frame(read, facts.scope_of(make.value)) and is_after(read, make)):
        return None
    for binding in others:
        if not is_after(binding, make) or not _other_arm(facts, binding, read):
            return None
    holder = facts.parent(make)
    # the make's block holds the read's ``if`` (no arm of another test skips the make)
    if not any(facts.parent(a) is holder for a in facts.ancestors(read) if isinstance(a, ast.stmt)):
        return None
    return make.value  # type: ignore[return-value]


def _other_arm(facts: ModuleFacts, binding: ast.AST, read: ast.AST) -> bool:
    """``binding`` and ``read`` sit in different arms (body / orelse) of one ``if``."""
    for ancestor in facts.ancestors(binding):
        if isinstance(ancestor, ast.If) and contains(ancestor, read):
            in_body = any(contains(s, binding) for s in ancestor.body)
            read_in_body = any(contains(s, read) for s in ancestor.body)
            read_in_else = any(contains(s, read) for s in ancestor.orelse)
            return (in_body and read_in_else) or (not in_body and read_in_body)
    return False


def _make_before(facts: ModuleFacts, read: ast.Name, statement: ast.Assign) -> ast.Call | None:
    """What a read in the value of an assignment that rebinds the name sees (``env =
    Limit(env.env)``): the one make assignment of the name above it in the same frame, where
    every other binding of the name (the statement's own aside) comes after the statement
    and outside any loop around it."""
    makes: list[ast.Call] = []
    loops = [a for a in facts.ancestors(statement) if isinstance(a, (ast.For, ast.AsyncFor, ast.While))]
    for binding in facts.bindings_of(read):
        if not isinstance(binding, ast.Name):
            return None
        if binding in statement.targets:
            continue
        above = facts.parent(binding)
        if isinstance(above, ast.Assign) and above.targets == [binding] and isinstance(above.value, ast.Call) and is_make_call(facts, above.value) and is_after(statement, above):
            makes.append(above.value)
        elif not is_after(binding, statement) or any(contains(loop, binding) for loop in loops):
            return None
    if len(makes) != 1 or not Flow.of(facts).same_frame(read, facts.scope_of(makes[0])):
        return None
    return makes[0]


def atari_make(facts: ModuleFacts, receivers: Receivers, call: ast.Call) -> tuple[Atari, str] | None:
    """Whether ``call`` (a make) makes Atari envs, with an Atari id it gets (or the sign
    that shows it), or None."""
    ids = make_ids(facts, receivers, call)
    if ids is None:
        sign = _asserted_atari(facts, call)
        return (Atari.CERTAIN, sign) if sign is not None else None
    atari = [i for i in ids or () if i is not None and is_atari_id(i)]
    if not atari:
        return None
    return (Atari.CERTAIN if len(atari) == len(ids or ()) else Atari.MAYBE), atari[0]


def _asserted_atari(facts: ModuleFacts, call: ast.Call) -> str | None:
    """An id the def that makes ``call`` asserts is an Atari one, whatever its callers pass
    (``assert "NoFrameskip" in env.spec.id`` outside any branch): the assertion's text."""
    function = facts.enclosing_function(call)
    if function is None:
        return None
    for node in walk(function):
        if not (isinstance(node, ast.Assert) and facts.enclosing_function(node) is function):
            continue
        if any(isinstance(n, ast.Constant) and n.value == "NoFrameskip" for n in walk(node.test)) and not _in_branch(facts, node, function):
            return facts.segment(node)
    return _atari_call_on_made_env(facts, call, function)


# What only an Atari env has: a non-Atari env raises AttributeError on these.
_ATARI_ONLY = frozenset({"get_action_meanings", "ale"})


def _atari_call_on_made_env(facts: ModuleFacts, call: ast.Call, function: ast.AST) -> str | None:
    """``env = make(env_id)``, then, on every path of the def, ``env.unwrapped.
    get_action_meanings()`` (or ``.ale``) on that env or on a wrapper of it (``env =
    Wrapper(env)`` between): whatever id the callers pass, a non-Atari env would raise
    there, so the make is an Atari one. The read's text, or None."""
    assign = facts.parent(call)
    if not (isinstance(assign, ast.Assign) and len(assign.targets) == 1 and isinstance(assign.targets[0], ast.Name)):
        return None
    name = assign.targets[0].id
    for node in walk(function):
        if not (isinstance(node, ast.Attribute) and node.attr in _ATARI_ONLY and isinstance(node.ctx, ast.Load)):
            continue
        held = node.value.value if isinstance(node.value, ast.Attribute) and node.value.attr == "unwrapped" else node.value
        if not (isinstance(held, ast.Name) and held.id == name) or facts.enclosing_function(node) is not function:
            continue
        if _in_branch(facts, node, function) or not is_after(node, assign):
            continue
        if all(_made_or_wrapped(facts, binding, assign, name) for binding in facts.bindings_of(held)):
            return f"reads {facts.segment(node)}"
    return None


def _made_or_wrapped(facts: ModuleFacts, binding: ast.AST, make: ast.Assign, name: str) -> bool:
    """``binding`` of ``name`` is the make's, or ``name = Something(name, ...)``."""
    statement = facts.parent(binding)
    if statement is make:
        return True
    return (
        isinstance(statement, ast.Assign)
        and statement.targets == [binding]
        and isinstance(statement.value, ast.Call)
        and any(isinstance(a, ast.Name) and a.id == name for a in statement.value.args)
    )


def _in_branch(facts: ModuleFacts, node: ast.AST, function: ast.AST) -> bool:
    """``node`` runs only on some paths of ``function`` (an ``if`` test runs on all)."""
    child = node
    for ancestor in facts.ancestors(node):
        if ancestor is function:
            return False
        if isinstance(ancestor, (ast.If, ast.While)) and child is ancestor.test:
            child = ancestor
            continue
        if isinstance(ancestor, (ast.If, ast.While, ast.For, ast.AsyncFor, ast.Try, ast.With, ast.AsyncWith)):
            return True
        child = ancestor
    return False


def make_ids(facts: ModuleFacts, receivers: Receivers, call: ast.Call) -> list[str | None] | None:
    """The ids a make call gets: its literal, a constant's, or what every call of the run
    passes the parameter it reads (None: not known; a None item: one call not known)."""
    return _ids(facts, receivers, call_argument(call, 0, "id"))


def _ids(facts: ModuleFacts, receivers: Receivers, argument: ast.expr | None) -> list[str | None] | None:
    literal = _literal(facts, argument)
    if literal is not None:
        return [literal]
    if not isinstance(argument, ast.Name):
        return None
    bindings = facts.bindings_of(argument)
    if len(bindings) != 1 or not isinstance(bindings[0], ast.arg):
        return None
    return _given(facts, receivers, bindings[0])


def _literal(facts: ModuleFacts, node: ast.AST | None) -> str | None:
    """The string ``node`` is, or a name holds where it is read (one assignment of a literal
    that reaches the read)."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value
    if not isinstance(node, ast.Name):
        return None
    bindings = facts.bindings_of(node)
    flow = Flow.of(facts)
    last = flow.last_binding_of(node)
    if len(bindings) == 1 and isinstance(bindings[0], ast.Name):
        last = bindings[0]  # a module constant read in a def
    statement = facts.parent(last) if isinstance(last, ast.Name) else None
    if not (isinstance(last, ast.Name) and isinstance(statement, ast.Assign) and statement.targets == [last]):
        return None
    if len(bindings) != 1 and not flow.dominates(statement, node, last):
        return None
    value = statement.value
    return value.value if isinstance(value, ast.Constant) and isinstance(value.value, str) else None


def _given(facts: ModuleFacts, receivers: Receivers, param: ast.arg) -> list[str | None] | None:
    """The ids every call of the run gives ``param`` of a top-level def (None: unknown)."""
    function = facts.parent(facts.parent(param))
    if not isinstance(function, FUNCTIONS) or facts.functions.get(function.name) is not function:
        return None
    project = receivers.project
    if project is not None and project.handed_on(function.name):
        return None
    params = [*function.args.posonlyargs, *function.args.args]
    if param not in params:
        return None
    position = params.index(param)
    defaults = function.args.defaults
    offset = len(params) - len(defaults)
    default = _literal(facts, defaults[position - offset]) if position >= offset else None
    found: list[str | None] = []
    for read in facts.reads_of(function.name):
        call = facts.parent(read)
        if not (isinstance(call, ast.Call) and call.func is read) or facts.bindings_of(read) != [function]:
            return None  # handed on as a value: called where the run cannot see
        if any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords):
            found.append(None)
            continue
        argument = call_argument(call, position, param.arg)
        found.append(default if argument is None else _literal(facts, argument))
    if project is not None:
        found += [default if value == "" else value for value in project.passed_ids(function.name, param.arg)]
    return found or None


# -- the forwarding rules' questions (GM605, GM606) ------------------------------------------------


def _atari_of(family: Family, receiver: ast.AST) -> tuple[Atari, str, ast.Call] | None:
    make = reaching_make(family.facts, receiver)
    found = atari_make(family.facts, family.receivers, make) if make is not None else None
    return (found[0], found[1], make) if found is not None and make is not None else None


def _made_from(text: str, atari: Atari, env_id: str) -> str:
    if env_id.startswith("assert "):
        return f"`{text}` is made from an Atari id (`{env_id}`)"
    if env_id.startswith("reads "):
        return f"`{text}` is made from an Atari id (the def {env_id.split(' ', 1)[0]} `{env_id.split(' ', 1)[1]}` of it)"
    if atari is Atari.CERTAIN:
        return f"`{text}` is made from `{env_id}`, an Atari id"
    return f"if `{text}` is made from an Atari id (its callers pass `{env_id}` among others)"


_NO_LIMIT = "ale-py registers Atari ids with no TimeLimit (only a 108000-frame cap), where gym registered a step limit"


def max_episode_steps_on_atari(family: Family, attr: ast.Attribute) -> bool:
    """GM605 for ``env._max_episode_steps`` on an Atari make: a write caps nothing now, a
    read raises. A write right after the make (``env = gym.make(id)`` then ``env.
    _max_episode_steps = N``, N a plain value) becomes ``max_episode_steps=N`` of the make,
    which puts that TimeLimit outermost as gym's registered one was; anything else is an
    item. True when it reported."""
    found = _atari_of(family, attr.value)
    if found is None:
        return False
    atari, env_id, make = found
    text = family.facts.segment(attr.value)
    statement = family.facts.parent(attr)
    if isinstance(attr.ctx, ast.Store) and isinstance(statement, ast.Assign):
        if atari is Atari.CERTAIN and _right_after_make(family.facts, statement, make, attr.value):
            value = family.facts.segment(statement.value)
            family.report(
                attr,
                "GM605",
                f"{_made_from(text, atari, env_id)}: {_NO_LIMIT}, so this write would cap nothing on Gymnasium: the limit "
                "is passed to make as `max_episode_steps=`, a TimeLimit outermost as before",
                kind=FixKind.AUTO,
            )
            family.plan.replace(make, lambda node: append_keyword(node, "max_episode_steps", cst.parse_expression(value)))
            family.plan.remove(statement)
            return True
        if atari is Atari.CERTAIN and _wraps_in_place(family.facts, statement, make, attr.value):
            # In a branch after the make (``if "NoFrameskip" in env_id: env._max_episode_steps
            # = a else: ... = b``): the make is shared, so the limit wraps the env there,
            # with nothing between, as gym's registered TimeLimit sat right on the make.
            value = family.facts.segment(statement.value)
            limit = family.plan.ensure_import("gymnasium.wrappers", "TimeLimit")
            family.report(
                attr,
                "GM605",
                f"{_made_from(text, atari, env_id)}: {_NO_LIMIT}, so this write would cap nothing on Gymnasium: the env is "
                f"wrapped in `{limit}(..., max_episode_steps=...)` here instead, on the make's result as before",
                kind=FixKind.AUTO,
            )
            env = attr.value.id  # type: ignore[attr-defined]
            family.plan.replace(statement, lambda node: _time_limit_assign(env, limit, value))
            return True
        family.report(
            attr,
            "GM605",
            f"{_made_from(text, atari, env_id)}: {_NO_LIMIT}, so on Gymnasium this write caps nothing (in gym it set the "
            "registered TimeLimit's limit): pass `max_episode_steps=` to make, or wrap the env in `TimeLimit(env, N)`",
            kind=FixKind.FLAG,
            question=("GM605", "atari-limit", id(make)),
        )
        return True
    family.report(
        attr,
        "GM605",
        f"{_made_from(text, atari, env_id)}: {_NO_LIMIT}, so `_max_episode_steps` raises AttributeError on Gymnasium (gym "
        "gave the registered limit): pass `max_episode_steps=` to make, or keep the limit in a variable of your own",
        kind=FixKind.FLAG,
        question=("GM605", "atari-limit", id(make)),
    )
    return True


def spec_limit_on_atari(family: Family, attr: ast.Attribute) -> bool:
    """GM605 for a read of ``env.spec.max_episode_steps`` on an Atari make: None now."""
    spec = attr.value
    if not (isinstance(spec, ast.Attribute) and spec.attr == "spec" and isinstance(attr.ctx, ast.Load)):
        return False
    found = _atari_of(family, spec.value)
    if found is None:
        return False
    atari, env_id, _ = found
    family.report(
        attr,
        "GM605",
        f"{_made_from(family.facts.segment(spec.value), atari, env_id)}: {_NO_LIMIT}, so this reads None on Gymnasium: "
        "pass `max_episode_steps=` to make if the code needs a limit",
        kind=FixKind.FLAG,
    )
    return True


def isinstance_time_limit_on_atari(family: Family, call: ast.Call) -> bool:
    """GM606 for ``isinstance(env, TimeLimit)`` on an Atari make: False now (an ``assert``
    of it fails, and the ``env.env`` unwrapping it guards strips OrderEnforcing)."""
    if len(call.args) != 2:
        return False
    found = _atari_of(family, call.args[0])
    if found is None:
        return False
    atari, env_id, _ = found
    test = family.facts.parent(call)
    if isinstance(test, (ast.If, ast.IfExp)) and test.test is call:
        # ``if isinstance(env, TimeLimit): env = env.env``: the branch is skipped, which leaves
        # the env without a TimeLimit as the unwrapping did: an explanation, no question.
        family.report(
            call,
            "GM606",
            f"{_made_from(family.facts.segment(call.args[0]), atari, env_id)}: {_NO_LIMIT}, so this test is False on "
            "Gymnasium and its branch is skipped (the env has no TimeLimit to remove)",
            kind=FixKind.FLAG,
            tier=Tier.NOTE,
        )
        return True
    family.report(
        call,
        "GM606",
        f"{_made_from(family.facts.segment(call.args[0]), atari, env_id)}: {_NO_LIMIT}, so this test is False on "
        "Gymnasium: unwrap only when a TimeLimit is there (`if isinstance(...)`), or drop the test",
        kind=FixKind.FLAG,
    )
    return True


def _right_after_make(facts: ModuleFacts, statement: ast.Assign, make: ast.Call, receiver: ast.AST) -> bool:
    """``env = make(id, ...)`` is the statement just before ``env._max_episode_steps = N`` in
    the same block, with N a plain value (literals and other names, in arithmetic), and the
    make takes no ``max_episode_steps`` nor ``**kwargs`` yet."""
    if len(statement.targets) != 1 or not isinstance(receiver, ast.Name):
        return False
    above = facts.parent(make)
    if not (isinstance(above, ast.Assign) and len(above.targets) == 1 and isinstance(above.targets[0], ast.Name)):
        return False
    if above.targets[0].id != receiver.id or any(k.arg in ("max_episode_steps", None) for k in make.keywords) or len(make.args) > 1:
        return False
    holder = facts.parent(statement)
    for field in ("body", "orelse", "finalbody"):
        block = getattr(holder, field, None)
        if isinstance(block, list) and statement in block:
            index = block.index(statement)
            return index > 0 and block[index - 1] is above and _plain(statement.value, receiver.id)
    return False


def _time_limit_assign(env: str, limit: str, value: str) -> cst.CSTNode:
    """``env = TimeLimit(env, max_episode_steps=value)``, the assignment that replaces a write."""
    line = cst.parse_statement(f"{env} = {limit}({env}, max_episode_steps={value})\n")
    assert isinstance(line, cst.SimpleStatementLine)
    return line.body[0]


def _wraps_in_place(facts: ModuleFacts, statement: ast.Assign, make: ast.Call, receiver: ast.AST) -> bool:
    """``env._max_episode_steps = N`` (N plain) where ``env`` still holds the make's result
    (``reaching_make`` found it through the flow), outside any loop between the two, and the
    make takes no ``max_episode_steps`` nor ``**kwargs``: rebinding ``env`` there to a
    TimeLimit runs once, on the made env."""
    if len(statement.targets) != 1 or not isinstance(receiver, ast.Name) or not _plain(statement.value, receiver.id):
        return False
    if any(k.arg in ("max_episode_steps", None) for k in make.keywords) or len(make.args) > 1:
        return False
    above = facts.parent(make)
    if not (isinstance(above, ast.Assign) and len(above.targets) == 1 and isinstance(above.targets[0], ast.Name)):
        return False
    if above.targets[0].id != receiver.id:
        return False
    home = facts.parent(above)
    for ancestor in facts.ancestors(statement):
        if ancestor is home:
            return True
        if isinstance(ancestor, (ast.For, ast.AsyncFor, ast.While, *FUNCTIONS, ast.ClassDef, ast.Lambda)):
            return False
    return False


def _plain(value: ast.expr, env: str) -> bool:
    if isinstance(value, ast.Constant):
        return isinstance(value.value, int) and not isinstance(value.value, bool)
    if isinstance(value, ast.Name):
        return value.id != env
    if isinstance(value, ast.Attribute):  # ``args.max_episode_length``
        return isinstance(value.ctx, ast.Load) and _plain(value.value, env) and not isinstance(value.value, ast.Constant)
    if isinstance(value, ast.UnaryOp):
        return _plain(value.operand, env)
    if isinstance(value, ast.BinOp):
        return _plain(value.left, env) and _plain(value.right, env)
    return False
