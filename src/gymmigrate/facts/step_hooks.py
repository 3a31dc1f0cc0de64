"""Step hooks across modules (rules/custom_env/hooks.py): ``def step(self, a): ...;
return self.post_step(ob, reward, done, info)`` makes ``post_step`` part of the step
contract, and a subclass in another module (``class Task(pkg.BaseEnv)``) that overrides
it must return five values with the base, or neither may change. Two per-module facts,
joined by ``ProjectFacts`` (``followed_hooks``):

* ``step_hooks``: per top-level class, the methods its ``step`` returns the result of that
  the rewrite can follow in this module (no other caller, every override of a local
  subclass a plain one);
* ``plain_overrides``: per top-level class, its methods whose every return the rewrite can
  carry to five values (a four- or five-value literal, or the base's own
  ``super().name(...)``, called nowhere else).
"""

from __future__ import annotations

import ast

from gymmigrate.facts import names as N
from gymmigrate.facts.env_classes import DIRECT_ENV_BASES, is_super_method_call
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts, own_returns, walk


def tuple_len(value: ast.AST | None) -> int | None:
    if isinstance(value, ast.Tuple) and not any(isinstance(e, ast.Starred) for e in value.elts):
        return len(value.elts)
    return None


# What gym.Env (or Gymnasium's) defines: a step returning one of these is no hook of the class.
ENV_API = frozenset({"step", "reset", "render", "close", "seed", "unwrapped", "get_wrapper_attr", "set_wrapper_attr", "has_wrapper_attr"})


def _extends_env_alone(facts: ModuleFacts, classdef: ast.ClassDef) -> bool:
    """The class's one base is gym.Env itself: a method it does not define comes from no base."""
    return len(classdef.bases) == 1 and any(N.strip_gym_prefix(q) in DIRECT_ENV_BASES for q in facts.qualified_names(classdef.bases[0]))


def plain_override(method: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    """Every return is a four- or five-value literal or ``super().<name>(...)``, and the
    base's result is read nowhere else."""
    supers = [n for n in walk(method) if is_super_method_call(n, method.name)]
    returned = []
    for ret in own_returns(method):
        if ret.value is None:
            return False
        if is_super_method_call(ret.value, method.name):
            returned.append(ret.value)
        elif tuple_len(ret.value) not in (4, 5):
            return False
    return len(supers) == len(returned)


def _methods(classdef: ast.ClassDef) -> dict[str, ast.FunctionDef | ast.AsyncFunctionDef]:
    return {s.name: s for s in classdef.body if isinstance(s, FUNCTIONS)}


def plain_overrides(facts: ModuleFacts) -> dict[str, frozenset[str]]:
    found = {}
    for name, classdef in facts.classes.items():
        if classdef.bases:
            plain = frozenset(m for m, f in _methods(classdef).items() if m != "step" and plain_override(f))
            if plain:
                found[name] = plain
    return found


def step_hooks(facts: ModuleFacts) -> dict[str, frozenset[str]]:
    """``return self.<hook>(...)`` in the class's own ``step``, for a hook of the class that
    returns a value and that no other method of the class calls; none of a tuple already
    of five. Local subclasses (this module) must override it plainly."""
    children: dict[str, list[ast.ClassDef]] = {}
    for classdef in facts.all_classes:
        for base in classdef.bases:
            if isinstance(base, ast.Name) and base.id in facts.classes:
                children.setdefault(base.id, []).append(classdef)
    found = {}
    for name, classdef in facts.classes.items():
        methods = _methods(classdef)
        step = methods.get("step")
        if step is None or any(tuple_len(r.value) == 5 for r in own_returns(step)):
            continue
        hooks = set()
        for ret in own_returns(step):
            call = ret.value
            if not (isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute)):
                continue
            if not (isinstance(call.func.value, ast.Name) and call.func.value.id == "self"):
                continue
            hook_name = call.func.attr
            hook = methods.get(hook_name)
            if hook is None:
                # a hook only subclasses define, under a class of gym.Env alone
                # (rules/custom_env/step.py ``_absent_hooks``): followed the same way
                if hook_name in ENV_API or not _extends_env_alone(facts, classdef):
                    continue
            elif hook is step or not any(r.value is not None for r in own_returns(hook)):
                continue
            calls = [
                n for m in methods.values() if m is not step for n in walk(m)
                if isinstance(n, ast.Attribute) and n.attr == hook_name and isinstance(n.value, ast.Name) and n.value.id == "self"
            ]
            if calls:
                continue
            subs, todo = [], list(children.get(name, ()))
            while todo:
                sub = todo.pop()
                if sub not in subs:
                    subs.append(sub)
                    todo += children.get(sub.name, ())
            if all(hook_name not in _methods(s) or plain_override(_methods(s)[hook_name]) for s in subs):
                hooks.add(hook_name)
        if hooks:
            found[name] = frozenset(hooks)
    return found
