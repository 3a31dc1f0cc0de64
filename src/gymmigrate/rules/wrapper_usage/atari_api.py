"""Methods of gym's AtariEnv that ale-py's no longer has (GM604): ``_get_image()``,
``_get_ram()``, ``clone_full_state()``, ``restore_full_state(s)``, ``seed(s)``.

Gymnasium's Atari ids make ale-py's AtariEnv, so a call of one of them raises
AttributeError. Where the run shows the receiver is an Atari env, the call becomes what
replaces it on the env itself (``builtin_attributes.ATARI_REPLACED``), through
``.unwrapped`` as legacy forwarding reached it; ``seed(s)``, which has no exact
replacement, is reported. An Atari env is shown by

* every creation of the receiver being a make of Atari ids (``atari_limits.atari_make``);
* or, for ``self.env`` and, in a Gym wrapper class or a class that forwards unknown
  attributes (``__getattr__``), ``self``, ``self.unwrapped``: the class itself reading what
  only an Atari env has (``.ale``, ``get_action_meanings()``) on that env outside any
  branch: the class works on Atari envs only, whatever its callers hand it.

A call on a Gym env the run cannot tell that of (a wrapper's ``self.env.unwrapped`` with no
such read) is reported, as these names are gym's AtariEnv's: the call raises on
Gymnasium unless the env is the project's own that defines the method. One the run shows is
another env is left, as is a call where a class of the module defines the method itself.
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.atari_signs import (
    reads_atari_interface,
    self_stored,
    under_condition,
)
from gymmigrate.facts.creation import CreationFinder
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import self_attribute, walk
from gymmigrate.findings import FixKind
from gymmigrate.rules.env_ids.catalog import is_atari_id
from gymmigrate.rules.wrapper_usage.atari_limits import (
    Atari,
    atari_make,
    is_make_call,
    make_ids,
)
from gymmigrate.rules.wrapper_usage.builtin_attributes import ATARI_GONE, ATARI_REPLACED

if TYPE_CHECKING:
    from gymmigrate.rules.wrapper_usage.self_forwarding import ForwardingFamily

ATARI_METHODS = frozenset(ATARI_REPLACED) | frozenset(ATARI_GONE)
# How a module spells a call of one: where the forwarding family must run though the module
# never names gym (also ``rules/__init__.py``'s words for it).
ATARI_METHOD_WORDS = (*(f".{name}(" for name in ATARI_REPLACED), ".unwrapped.seed(")


def atari_method_call(family: ForwardingFamily, attr: ast.Attribute, legacy_module: bool) -> bool:
    """``x.unwrapped._get_image()`` and the others of the table: rewritten, reported, or
    left to the other forwarding rules (False). ``legacy_module``: the module imports gym,
    so what the run cannot trace is asked about."""
    name = attr.attr
    call = family.facts.parent(attr)
    if name not in ATARI_METHODS or not (isinstance(call, ast.Call) and call.func is attr):
        return False
    receiver = attr.value
    through_unwrapped = isinstance(receiver, ast.Attribute) and receiver.attr == "unwrapped"
    env = receiver.value if isinstance(receiver, ast.Attribute) and through_unwrapped else receiver
    if not through_unwrapped and isinstance(env, ast.Name) and env.id in ("self", "cls"):
        return False  # the class's own method, or one it forwards: the wrapper rules decide
    if name in ATARI_GONE and (not through_unwrapped or family.receivers.kind_of(receiver) is EnvKind.GYM_ENV):
        return False  # ``env.seed(s)`` on an env the receivers know: the seeding rules' (GM203)
    if _defined_here(family, name):
        return False  # a class of the module has this method: maybe the one called
    atari = _is_atari_env(family, env)
    if atari is False:
        return False  # another env: its own API
    text = family.facts.segment(attr)
    if atari is None:
        if name in ATARI_GONE or not legacy_module or not _may_be_gym_env(family, env, through_unwrapped):
            return False
        family.report(
            attr,
            "GM604",
            f"`{text}()`: gym's AtariEnv had `{name}`, ale-py's (which Gymnasium's Atari ids make) has not "
            f"(AttributeError); the run could not tell which env this is: on an Atari env use "
            f"{_replacement_text(name)}",
            kind=FixKind.FLAG,
            question=("GM604", "atari-method", name),
        )
        return True
    if name in ATARI_GONE:
        family.report(attr, "GM604", f"`{text}()`: {ATARI_GONE[name]}", kind=FixKind.FLAG)
        return True
    path, keywords, arity = ATARI_REPLACED[name]
    if not _takes(call, arity):
        family.report(
            attr,
            "GM604",
            f"`{text}()` on an Atari env: ale-py's AtariEnv has no `{name}`; use {_replacement_text(name)}",
            kind=FixKind.FLAG,
        )
        return True
    family.plan.replace(call, _build(path, keywords, through_unwrapped))
    new = ".".join(("unwrapped", *path) if not through_unwrapped else path)
    family.report(
        attr,
        "GM604",
        f"`{name}` -> `{new}`" + (f" with {', '.join(f'{k}={v}' for k, v in keywords)}" if keywords else "")
        + f": gym's AtariEnv had `{name}`, ale-py's (which Gymnasium's Atari ids make) has this instead, "
        "the same values",
        kind=FixKind.AUTO,
    )
    return True


def _replacement_text(name: str) -> str:
    if name in ATARI_GONE:
        return "reset(seed=s)"
    path, keywords, _ = ATARI_REPLACED[name]
    arguments = ", ".join(f"{k}={v}" for k, v in keywords) or ("s" if name.startswith("restore") else "")
    return f"`.unwrapped.{'.'.join(path)}({arguments})`"


def _takes(call: ast.Call, arity: int) -> bool:
    """The call passes what the legacy method took: nothing, or the one state."""
    if any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords):
        return False
    passed = len(call.args) + sum(1 for k in call.keywords if k.arg == "state")
    return passed == arity and len(call.args) + len(call.keywords) == arity


def _defined_here(family: ForwardingFamily, name: str) -> bool:
    return any(
        isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)) and item.name == name
        for classdef in family.facts.all_classes
        for item in classdef.body
    )


def _is_atari_env(family: ForwardingFamily, env: ast.expr) -> bool | None:
    """True: the run shows ``env`` (an env, or the env a class works on) is an Atari env;
    False: it shows another env; None: it cannot tell."""
    facts = family.facts
    classdef = facts.enclosing_class(env)
    if classdef is not None and _class_env(family, env, classdef):
        if _works_on_atari(family, classdef):
            return True
    if isinstance(env, ast.Name) and env.id in ("self", "cls"):
        return None
    finder = facts.memo(("atari-api-finder", 0), lambda: CreationFinder(facts, family.receivers, lambda call: is_make_call(facts, call)))
    creation = finder.find(env)
    if not creation.found or not creation.calls:
        return None
    answers = [atari_make(facts, family.receivers, call) for call in creation.calls]
    if creation.complete and all(answer is not None and answer[0] is Atari.CERTAIN for answer in answers):
        return True
    if creation.complete and all(_other_ids(family, call) for call in creation.calls):
        return False
    return None


def _other_ids(family: ForwardingFamily, call: ast.Call) -> bool:
    """Every id the make gets is known, and none is an Atari id."""
    ids = make_ids(family.facts, family.receivers, call)
    return bool(ids) and all(i is not None and not is_atari_id(i) for i in ids or ())


def _class_env(family: ForwardingFamily, env: ast.expr, classdef: ast.ClassDef) -> bool:
    """``self.env``, or ``self`` in a class whose unknown attributes reach its env (a Gym
    wrapper, a class with ``__getattr__``): the env the class works on."""
    if self_attribute(env) == "env":
        return True
    if isinstance(env, ast.Name) and env.id == "self":
        return family.receivers.is_gym_wrapper_class(classdef) or any(
            isinstance(item, ast.FunctionDef) and item.name == "__getattr__" for item in classdef.body
        )
    return False


def _works_on_atari(family: ForwardingFamily, classdef: ast.ClassDef) -> bool:
    """The class reads what only an Atari env has on its env (``self.env.unwrapped.ale``,
    ``self.unwrapped.get_action_meanings()``), outside any branch of its method."""

    def compute() -> bool:
        own = self_stored(classdef)
        for method in classdef.body:
            if not isinstance(method, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            for node in walk(method):
                if not (isinstance(node, ast.Attribute) and reads_atari_interface(node, own)):
                    continue
                if _on_class_env(node.value) and not under_condition(family.facts, node, method):
                    return True
        return False

    return bool(family.facts.memo(("atari-class", id(classdef)), compute))


def _on_class_env(value: ast.expr) -> bool:
    """``self.env.unwrapped``, ``self.unwrapped``, ``self.env``: the env of the class."""
    while isinstance(value, ast.Attribute) and value.attr in ("env", "unwrapped"):
        value = value.value
    return isinstance(value, ast.Name) and value.id == "self"


def _may_be_gym_env(family: ForwardingFamily, env: ast.expr, through_unwrapped: bool) -> bool:
    """What a call of gym's AtariEnv's names is asked about on: ``x.unwrapped`` (only Gym
    envs have it), a class's ``self.env``, or an expression the receivers call a Gym env."""
    if through_unwrapped:
        return True
    if self_attribute(env) == "env":
        return True
    return family.receivers.kind_of(env) is EnvKind.GYM_ENV


def _build(path: tuple[str, ...], keywords: tuple[tuple[str, str], ...], through_unwrapped: bool):
    """``x.unwrapped.clone_full_state()`` -> ``x.unwrapped.clone_state(include_rng=True)``;
    without ``.unwrapped`` (legacy forwarding reached the method) it is added."""

    def build(node: cst.Call) -> cst.Call:
        func = node.func
        assert isinstance(func, cst.Attribute)
        value: cst.BaseExpression = func.value
        if not through_unwrapped:
            value = cst.Attribute(value=value, attr=cst.Name("unwrapped"))
        for part in path[:-1]:
            value = cst.Attribute(value=value, attr=cst.Name(part))
        no_space = cst.SimpleWhitespace("")
        added = [
            cst.Arg(keyword=cst.Name(k), value=cst.Name(v), equal=cst.AssignEqual(whitespace_before=no_space, whitespace_after=no_space))
            for k, v in keywords
        ]
        return node.with_changes(func=func.with_changes(value=value, attr=cst.Name(path[-1])), args=[*node.args, *added])

    return build
