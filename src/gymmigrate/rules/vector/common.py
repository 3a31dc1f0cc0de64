"""What every vector rule shares: the names it recognises and small ast helpers.

Not a rule: the family (``rules/vector/__init__.py``) and its rule modules import it.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N

if TYPE_CHECKING:
    from gymmigrate.facts.creation import CreationFinder
    from gymmigrate.rules.base import RuleFamily

# Legacy ``gym.vector.make(id, num_envs=1, asynchronous=True, wrappers=None,
# disable_env_checker=None, **kwargs)`` positional parameters.
LEGACY_POSITIONS = ("id", "num_envs", "asynchronous", "wrappers", "disable_env_checker")
# Constructor arguments of SyncVectorEnv/AsyncVectorEnv: make_vec wants them in vector_kwargs.
VECTOR_CLASS_KWARGS = ("shared_memory", "copy", "context", "daemon", "worker", "observation_mode", "autoreset_mode")
ASYNC_ONLY_KWARGS = ("shared_memory", "context", "daemon", "worker")
VECTOR_CLASSES = frozenset(
    {
        "vector.SyncVectorEnv",
        "vector.AsyncVectorEnv",
        "vector.sync_vector_env.SyncVectorEnv",
        "vector.async_vector_env.AsyncVectorEnv",
    }
)
LIST_INFO_WRAPPERS = ("DictInfoToList", "VectorListInfo")


@dataclass
class VectorDecisions:
    """What the family decided about creation calls, keyed by ``id(ast.Call)``.

    One creation call can be converted (GM701), given SAME_STEP autoreset (GM706) and
    wrapped in DictInfoToList (GM705); its edits are put together once at the end.
    """

    vector_makes: dict[int, ast.Call] = field(default_factory=dict)  # gym.vector.make calls
    autoreset: dict[int, ast.Call] = field(default_factory=dict)  # calls that get SAME_STEP
    list_infos: dict[int, ast.Call] = field(default_factory=dict)  # calls to wrap in DictInfoToList
    wrapper_safe: dict[int, bool] = field(default_factory=dict)  # may the creation be wrapped?


def gym_rest(facts: ModuleFacts, node: ast.AST) -> frozenset[str]:
    """``{"vector.make"}`` for ``gym.vector.make``: the names under gym/gymnasium ``node`` stands for."""

    def compute() -> frozenset[str]:
        rests = (N.strip_gym_prefix(q) for q in facts.qualified_names(node))
        return frozenset(rest for rest in rests if rest is not None)

    return facts.memo(("vector-gym-rest", id(node)), compute)


def arguments_in_order(call: ast.Call) -> list[ast.expr | ast.keyword]:
    """Positional arguments and keywords in source order (LibCST's ``call.args``)."""
    arguments: list[ast.expr | ast.keyword] = [*call.args, *call.keywords]
    return sorted(arguments, key=lambda a: (a.lineno, a.col_offset))


def argument_value(argument: ast.expr | ast.keyword) -> ast.expr:
    return argument.value if isinstance(argument, (ast.keyword, ast.Starred)) else argument


def quote_of(facts: ModuleFacts, node: ast.AST) -> str | None:
    """The quote character of a plain string literal, as written."""
    if not (isinstance(node, ast.Constant) and isinstance(node.value, str)):
        return None
    if isinstance(facts.parent(node), ast.JoinedStr):
        return None
    text = facts.segment(node).lstrip("rRuU")
    return text[0] if text[:1] in ("'", '"') else None


def quote_style(facts: ModuleFacts, call: ast.Call) -> str:
    """The quote character the call already uses for its strings (the env id), for the strings we add."""
    for argument in arguments_in_order(call):
        quote = quote_of(facts, argument_value(argument))
        if quote is not None:
            return quote
    return '"'


def is_false(node: ast.AST | None) -> bool:
    return isinstance(node, ast.Constant) and node.value is False


def code(node: cst.CSTNode) -> str:
    return cst.Module(body=[]).code_for_node(node)


def renamed_string(node: cst.SimpleString, value: str) -> cst.SimpleString:
    return node.with_changes(value=f"{node.prefix}{node.quote}{value}{node.quote}")


if TYPE_CHECKING:

    class VectorFamilyBase(RuleFamily):
        """What the rule modules' mixins (``Construction``, ``Infos``, ``VectorWrappers``)
        see of the family they are mixed into (``rules/vector/__init__.py``)."""

        decisions: VectorDecisions
        finder: CreationFinder

else:
    VectorFamilyBase = object  # the mixins add methods only; RuleFamily comes with the family
