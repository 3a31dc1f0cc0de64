"""Attributes looked up by a name held in a value (GM604): ``getattr`` in a class's own
``__getattr__``, and ``hasattr`` guards of reads the run rewrote or asked about.

Legacy ``Wrapper.__getattr__`` forwarded a lookup that failed on a wrapper to the env below
it; Gymnasium's wrappers do not. A class that hands its unknown attributes on to a held
make result (``getattr(self._env, name)``) lost the layers below, and ``hasattr(env, "x")``
over a made env is False for what only the base env has. Part of
``forwarding.WrapperForwarding``, which records the reads it rewrote or asked about (``WrappedReads``).
"""

from __future__ import annotations

import ast
from collections.abc import Hashable
from typing import TYPE_CHECKING

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import dotted_name
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.wrapper_usage.forwarding_edits import (
    get_wrapper_attr_of,
    has_wrapper_attr,
    hasattr_unwrapped,
)
from gymmigrate.rules.wrapper_usage.origins import MADE, RAW, WRAPPED

if TYPE_CHECKING:
    from gymmigrate.rules.wrapper_usage.self_forwarding import ForwardingFamily


# How the run rewrote a read (``WrappedReads``): the hasattr guarding it follows.
GET_WRAPPER_ATTR = "get_wrapper_attr"
UNWRAPPED = "unwrapped"


class WrappedReads:
    """The reads the run rewrote (to ``get_wrapper_attr`` or through ``.unwrapped``), or asked
    about, by the object read (owner, receiver text) and the name: a ``hasattr`` of the same
    name on the same receiver rests on the same proof that the object is wrapped, or on the
    same open question."""

    def __init__(self, facts: ModuleFacts) -> None:
        self.facts = facts
        self._reads: dict[tuple[int, str, str], str] = {}  # (owner id, receiver text, name) -> how
        # (owner id, receiver text, name) -> the question of the first read asked about, its message
        self._asked: dict[tuple[int, str, str], tuple[Hashable, str]] = {}

    def _owner(self, node: ast.AST, text: str) -> ast.AST | None:
        """What one receiver text names the same object in: the class for ``self.x``, else
        the function (or module) the read sits in."""
        if text.startswith("self."):
            return self.facts.enclosing_class(node)
        return self.facts.enclosing_function(node) or self.facts.tree

    def _key(self, node: ast.AST, text: str | None, name: str) -> tuple[int, str, str] | None:
        owner = self._owner(node, text) if text else None
        return (id(owner), text, name) if text and owner is not None else None

    def note(self, attr: ast.Attribute, name: str, how: str = GET_WRAPPER_ATTR) -> None:
        key = self._key(attr, dotted_name(attr.value), name)
        if key is not None:
            self._reads.setdefault(key, how)

    def ask(self, attr: ast.Attribute, question: Hashable, message: str) -> None:
        """A review item asked ``question`` about the read ``attr``."""
        key = self._key(attr, dotted_name(attr.value), attr.attr)
        if key is not None:
            self._asked.setdefault(key, (question, message))

    def rewrote(self, node: ast.AST, text: str, name: str) -> str | None:
        """How a read of ``name`` on the object ``text`` names where ``node`` sits was
        rewritten, or None."""
        key = self._key(node, text, name)
        return self._reads.get(key) if key is not None else None

    def asked(self, node: ast.AST, text: str, name: str) -> tuple[Hashable, str] | None:
        key = self._key(node, text, name)
        return self._asked.get(key) if key is not None else None


def hasattr_through_wrappers(family: ForwardingFamily, reads: WrappedReads, call: ast.Call) -> None:
    """``hasattr(env, "x")`` guarding a read ``env.x`` the run rewrote: the same proof
    says ``env`` is wrapped, and without forwarding the test is False for what only an
    inner layer has, so the guarded branch would be dead. Beside a ``get_wrapper_attr``
    read, ``has_wrapper_attr`` looks through every layer (gymnasium 1.4: a Wrapper asks
    itself, then its env; an Env itself), as legacy forwarding answered for public names
    (gym refused to forward ``_private`` ones: left alone); beside an ``.unwrapped`` read,
    the test asks the env that read does. Beside a read asked about, the same question
    names the test: it goes with the reads, whatever the answer."""
    if family.facts.bindings_of(call.func) or len(call.args) != 2 or call.keywords:  # type: ignore[arg-type]
        return
    receiver, key = call.args
    if not (isinstance(key, ast.Constant) and isinstance(key.value, str)) or key.value.startswith("_"):
        return
    text = dotted_name(receiver)
    if not text:
        return
    how = reads.rewrote(call, text, key.value)
    if how == UNWRAPPED:
        family.report(
            call,
            "GM604",
            f"attribute forwarding is gone in Gymnasium 1.0, so `hasattr` is False for what only the env below the "
            f"wrappers has: `hasattr({text}.unwrapped, \"{key.value}\")` tests the env the `.unwrapped.{key.value}` "
            "read it guards reads",
            tier=Tier.NOTE,
        )
        family.plan.replace(call, hasattr_unwrapped())
        return
    if how == GET_WRAPPER_ATTR:
        family.report(
            call,
            "GM604",
            f"attribute forwarding is gone in Gymnasium 1.0, so `hasattr` is False for what only the env below the "
            f"wrappers has: `{text}.has_wrapper_attr(\"{key.value}\")` looks through every layer, as the "
            f"`get_wrapper_attr(\"{key.value}\")` read it guards does",
            tier=Tier.NOTE,
        )
        family.plan.replace(call, has_wrapper_attr())
        return
    asked = reads.asked(call, text, key.value)
    if asked is None:
        return
    question, message = asked
    family.report(
        call,
        "GM604",
        f"`hasattr({text}, \"{key.value}\")` is silently False where the reads of `{text}.{key.value}` would raise "
        f"AttributeError (forwarding is gone), so it goes with them: test `hasattr({text}.unwrapped, \"{key.value}\")` "
        f"or `{text}.has_wrapper_attr(\"{key.value}\")` as they are read. {message}",
        kind=FixKind.FLAG,
        question=question,
    )


def getattr_forwarding(family: ForwardingFamily, call: ast.Call) -> None:
    """``def __getattr__(self, name): return getattr(self._env, name)`` with ``self._env``
    a make result or a wrapper stack: legacy gym's wrappers forwarded the lookup on to the
    base env, Gymnasium's do not, so what only the base env (or an inner wrapper) has now
    raises AttributeError through this class. One question at the lookup: the fix
    (``get_wrapper_attr``, ``.unwrapped``) depends on what callers read through it."""
    if family.facts.bindings_of(call.func) or len(call.args) != 2 or call.keywords:  # type: ignore[arg-type]
        return
    function = family.facts.enclosing_function(call)
    classdef = family.facts.enclosing_class(call)
    if function is None or classdef is None or family.facts.parent(function) is not classdef:
        return
    params = [*function.args.posonlyargs, *function.args.args]
    if function.name not in ("__getattr__", "__getattribute__") or len(params) != 2:
        return
    target, looked_up = call.args
    if not (isinstance(looked_up, ast.Name) and looked_up.id == params[1].arg and family.facts.bindings_of(looked_up) == [params[1]]):
        return
    held = dotted_name(target)
    stored = _looked_up_attribute(family.facts, target)
    values: list[ast.expr] = [target]
    if stored is not None:
        held = f"self.{stored}"
        values = family.receivers.self_stores(classdef).get(stored, [])
    if not values or held is None:
        return
    verdict = _forwarded_to(family, values)
    if verdict is None:
        return
    if verdict:
        # Every object it can hold is a Gym env: ``get_wrapper_attr`` looks the name up
        # on each layer down to the base env, as gym's forwarding did, and raises
        # AttributeError for a name none has (checked on gymnasium 1.4), so ``hasattr``
        # and ``getattr(x, name, default)`` on this class answer as they did.
        family.report(
            call,
            "GM604",
            f"`{classdef.name}.{function.name}` forwards unknown attributes to `{held}`, a Gym env: Gymnasium's "
            f"wrappers no longer forward them to the env below, `{held}.get_wrapper_attr({looked_up.id})` looks "
            "through every layer as gym's forwarding did",
            tier=Tier.NOTE,
        )
        family.plan.replace(call, get_wrapper_attr_of())
        return
    family.report(
        call,
        "GM604",
        f"`{classdef.name}.{function.name}` forwards unknown attributes to `{held}`, which holds a Gym env made "
        "with make or wrappers (and, at other stores, objects not shown to be Gym envs): Gymnasium's wrappers "
        "no longer forward attribute reads to the env below them, so what only the base env or an inner "
        "wrapper defines now raises AttributeError here; forward with "
        f"`{held}.get_wrapper_attr({looked_up.id})` (every layer, as gym's forwarding did) or read `{held}.unwrapped`",
        kind=FixKind.FLAG,
    )


def _forwarded_to(family: ForwardingFamily, values: list[ast.expr]) -> bool | None:
    """What a ``__getattr__`` forwarding to an object stored as ``values`` is rewritten to:
    True where every value is a Gym env (``get_wrapper_attr``), False where only some are (a
    question), None where none is shown to be one, or one is a bare env (left)."""
    # a make result or wrappers; or a Gym env by type (an isinstance test, an annotation),
    # which callers make with make: a raw env has its attributes itself, an unknown
    # target is not asked about
    origins = [family.origins.origin(v) for v in values]
    if not (any(o in (MADE, WRAPPED) for o in origins) or any(family.receivers.kind_of(v) is EnvKind.GYM_ENV for v in values)):
        return None
    if any(o == RAW for o in origins):
        return None
    return all(o in (MADE, WRAPPED) or family.receivers.kind_of(v) is EnvKind.GYM_ENV for o, v in zip(origins, values))


def forwarded_through_wrapper_attr(family: ForwardingFamily, receiver: ast.expr) -> bool:
    """``self.x`` in a class whose ``__getattr__(self, name)`` returns ``getattr(self.x,
    name)`` and is rewritten to ``self.x.get_wrapper_attr(name)`` (every object stored there
    a Gym env): the class's own reads of ``self.x`` rest on the same proof."""
    if not (isinstance(receiver, ast.Attribute) and isinstance(receiver.value, ast.Name) and family.receivers.is_self(receiver.value)):
        return False
    classdef = family.facts.enclosing_class(receiver)
    if classdef is None:
        return False
    lookup = next((s for s in classdef.body if isinstance(s, ast.FunctionDef) and s.name == "__getattr__"), None)
    params = [*lookup.args.posonlyargs, *lookup.args.args] if lookup is not None else []
    if lookup is None or len(params) != 2:
        return False
    for node in ast.walk(lookup):
        if (
            isinstance(node, ast.Return)
            and isinstance(node.value, ast.Call)
            and isinstance(node.value.func, ast.Name)
            and node.value.func.id == "getattr"
            and not family.facts.bindings_of(node.value.func)
            and len(node.value.args) == 2
            and not node.value.keywords
        ):
            target, looked_up = node.value.args
            if (
                isinstance(target, ast.Attribute)
                and target.attr == receiver.attr
                and isinstance(target.value, ast.Name)
                and family.receivers.is_self(target.value)
                and isinstance(looked_up, ast.Name)
                and looked_up.id == params[1].arg
            ):
                values = family.receivers.self_stores(classdef).get(receiver.attr, [])
                return bool(values) and _forwarded_to(family, values) is True
    return False


def _looked_up_attribute(facts: ModuleFacts, target: ast.expr) -> str | None:
    """``x`` for a name bound once to ``super().__getattribute__("x")`` or
    ``object.__getattribute__(self, "x")`` (how a ``__getattr__`` reads its own slot
    without recursing), else None."""
    if not isinstance(target, ast.Name):
        return None
    bindings = facts.bindings_of(target)
    statement = facts.parent(bindings[0]) if len(bindings) == 1 else None
    if not (isinstance(statement, ast.Assign) and statement.targets == bindings and isinstance(statement.value, ast.Call)):
        return None
    call = statement.value
    if not (isinstance(call.func, ast.Attribute) and call.func.attr == "__getattribute__") or call.keywords or not call.args:
        return None
    name = call.args[-1]
    return name.value if isinstance(name, ast.Constant) and isinstance(name.value, str) and len(call.args) <= 2 else None
