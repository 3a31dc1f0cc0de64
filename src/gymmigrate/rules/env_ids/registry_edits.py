"""The CST edits of rules/env_ids/registry.py: keyword arguments of ``register(...)`` /
``EnvSpec(...)`` renamed or dropped, the env checker turned off in ``**kwargs``, entry-point
strings renamed."""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.module import string_value

TIME_LIMIT_TAG = "wrapper_config.TimeLimit.max_episode_steps"


def sets_checker(kw: ast.keyword) -> bool:
    """``**{"disable_env_checker": ..., **kwargs}``: GM808's own spelling."""
    return kw.arg is None and isinstance(kw.value, ast.Dict) and any(string_value(key) == "disable_env_checker" for key in kw.value.keys)


def checker_off_before(node: cst.BaseExpression) -> cst.BaseExpression:
    """``**kwargs`` -> ``**{"disable_env_checker": True, **kwargs}``: a caller that passes
    the keyword keeps its own choice."""
    return cst.Dict(
        [
            cst.DictElement(cst.SimpleString('"disable_env_checker"'), cst.Name("True")),
            cst.StarredDictElement(node),
        ]
    )


def checker_off_when_bare(node: cst.BaseExpression, set_order: bool) -> cst.BaseExpression:
    """``**kwargs`` -> ``**{"disable_env_checker": not kwargs.get("order_enforce", True) and
    kwargs.get("max_episode_steps") is None, **kwargs}``: the checker goes off where gym 0.21's
    make returned the bare env (order_enforce was True by default); a caller's own keyword wins."""
    name = cst.ensure_type(node, cst.Name).value
    limit = f'{name}.get("max_episode_steps") is None'
    test = f'not {name}.get("order_enforce", True) and {limit}' if set_order else limit
    return cst.Dict(
        [
            cst.DictElement(cst.SimpleString('"disable_env_checker"'), cst.parse_expression(test)),
            cst.StarredDictElement(node),
        ]
    )


def renamed_gym_envs(node: cst.BaseExpression) -> cst.BaseExpression:
    """``node`` with a ``"gym.envs..."`` string literal in it renamed to ``"gymnasium.envs..."``."""

    def rename(string: cst.SimpleString) -> cst.SimpleString:
        quote = string.quote
        body = string.value[len(string.prefix) + len(quote) : -len(quote)]
        if body.startswith("gym.envs"):
            return string.with_changes(value=f"{string.prefix}{quote}gymnasium{body[3:]}{quote}")
        return string

    if isinstance(node, cst.SimpleString):
        return rename(node)
    if isinstance(node, cst.Comparison):
        return node.with_changes(left=renamed_gym_envs(node.left))
    if isinstance(node, cst.Call):
        return node.with_changes(args=[arg.with_changes(value=renamed_gym_envs(arg.value)) for arg in node.args])
    return node


def with_string(node: cst.BaseExpression, text: str) -> cst.BaseExpression:
    """The string literal ``node`` holding ``text`` instead, in the same quotes."""
    if isinstance(node, cst.SimpleString):
        quote = node.quote
        return node.with_changes(value=f"{node.prefix}{quote}{text}{quote}")
    return cst.SimpleString(f'"{text}"', lpar=node.lpar, rpar=node.rpar)  # an implicit concatenation


def called_name(call: ast.Call) -> str:
    func = call.func
    return func.attr if isinstance(func, ast.Attribute) else func.id if isinstance(func, ast.Name) else ""


def spec_max_episode_steps(node: cst.BaseExpression) -> cst.BaseExpression:
    """``<spec>.tags.get(tag)`` / ``<spec>.tags[tag]`` -> ``<spec>.max_episode_steps``."""
    tags = node.func.value if isinstance(node, cst.Call) else node.value  # type: ignore[attr-defined]
    return cst.Attribute(value=tags.value, attr=cst.Name("max_episode_steps"), lpar=node.lpar, rpar=node.rpar)


def limit_tag(kw: ast.keyword) -> ast.expr | None:
    """The value of ``tags={"wrapper_config.TimeLimit.max_episode_steps": N}``, a dict
    literal whose one key is the time-limit tag; None for any other ``tags``."""
    value = kw.value
    if kw.arg != "tags" or not isinstance(value, ast.Dict) or len(value.keys) != 1:
        return None
    key = value.keys[0]
    return value.values[0] if key is not None and string_value(key) == TIME_LIMIT_TAG else None


def without_keywords(node: cst.BaseExpression, names: tuple[str, ...]) -> cst.BaseExpression:
    """The call without its ``names=`` keyword arguments. Where the last argument goes, the
    one now last takes its comma and the space before ``)``: the call's layout stays."""
    if not isinstance(node, cst.Call) or not node.args:
        return node
    kept = [arg for arg in node.args if arg.keyword is None or arg.keyword.value not in names]
    if kept and kept[-1] is not node.args[-1]:
        # the space before ``)`` (a newline in a call laid out one argument a line) goes with it
        kept[-1] = kept[-1].with_changes(comma=node.args[-1].comma, whitespace_after_arg=node.args[-1].whitespace_after_arg)
    return node.with_changes(args=kept)


def limit_as_max_episode_steps(node: cst.BaseExpression, keyword: str) -> cst.BaseExpression:
    """The call with its ``timestep_limit=N`` (or time-limit ``tags``) spelled ``max_episode_steps=N``."""
    if not isinstance(node, cst.Call):
        return node
    args = []
    for arg in node.args:
        if arg.keyword is not None and arg.keyword.value == keyword:
            value = arg.value
            if keyword == "tags" and isinstance(value, cst.Dict) and isinstance(element := value.elements[0], cst.DictElement):
                value = element.value
            arg = arg.with_changes(keyword=cst.Name("max_episode_steps"), value=value)
        args.append(arg)
    return node.with_changes(args=args)
