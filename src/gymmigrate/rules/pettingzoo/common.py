"""What the PettingZoo families share: the catalog entries, the gate, and small syntax helpers.

PettingZoo 1.21 replaced the per-agent ``dones`` by ``terminations`` and ``truncations``
(``last()`` returns five values, a parallel ``step`` five dicts); 1.22 moved to
Gymnasium spaces and ``render_mode`` at construction; 1.23 made parallel ``reset``
return ``(observations, infos)``, dropped ``return_info`` and ``seed()``.
"""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.multi_agent import MultiAgent
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.multi_agent_gate import pettingzoo_in_reach

PZ101 = Rule("PZ101", "AEC `last()` returns termination and truncation", FixKind.AUTO,
             "`obs, rew, done, info = env.last()` -> `obs, rew, termination, truncation, info = env.last()`")
PZ102 = Rule("PZ102", "no action for a dead agent", FixKind.AUTO,
             "`action = None if done else ...` -> `None if termination or truncation else ...`")
PZ103 = Rule("PZ103", "`env.dones` split into terminations and truncations", FixKind.AUTO,
             "`env.dones[a]` -> `(env.terminations[a] or env.truncations[a])`; `all(env.dones.values())` -> `not env.agents`")
PZ104 = Rule("PZ104", "parallel `step` returns five dicts", FixKind.AUTO,
             "`obs, rews, dones, infos = penv.step(a)` -> five dicts; `while not all(dones.values())` -> `while penv.agents`")
PZ105 = Rule("PZ105", "parallel `reset` returns observations and infos", FixKind.AUTO,
             "`obs = penv.reset()` -> `obs, infos = penv.reset()`; `return_info=` dropped")
PZ106 = Rule("PZ106", "`env.seed(s)` becomes `env.reset(seed=s)`", FixKind.AUTO,
             "`env.seed(s)` -> `env.reset(seed=s)` (the first reset only)")
PZ107 = Rule("PZ107", "render mode moves to construction", FixKind.ASSIST,
             "`env.render(mode=m)` -> `xxx_vN.env(render_mode=m)` + `env.render()`")
PZ108 = Rule("PZ108", "custom AEC and parallel env internals", FixKind.AUTO,
             "`_was_done_step` -> `_was_dead_step`, `_dones_step_first` -> `_deads_step_first`, `self.dones` split in two")
PZ109 = Rule("PZ109", "PettingZoo spaces come from Gymnasium", FixKind.AUTO,
             "`gym.spaces` in PettingZoo envs -> `gymnasium.spaces`")
PZ110 = Rule("PZ110", "`pettingzoo.make` replaces module-level creation", FixKind.FLAG,
             "`rps_v2.env()` -> `pettingzoo.make(\"aec\", \"classic/rps-v2\")` (PettingZoo 1.27)")
PZ111 = Rule("PZ111", "env modules that moved or were bumped", FixKind.ASSIST,
             "`from pettingzoo.mpe import simple_spread_v2` -> `from mpe2 import simple_spread_v3` (what changed is reported)")
PZ112 = Rule("PZ112", "wrappers no longer copy the wrapped env's agents, rewards and dones", FixKind.AUTO,
             "`super().reset(...)` in a wrapper that assigns `self.rewards` -> followed by `self.rewards = self.env.rewards`")

# The loop variable written into generated comprehensions.
AGENT = "agent"


class PettingZooFamily(RuleFamily):
    """Base of the PettingZoo families: gated on the file importing PettingZoo or SuperSuit,
    iterating ``x.agent_iter()`` (a loop over an env passed in from elsewhere), or importing
    a PettingZoo env class or factory another module of the run defines (a driver script
    of the project's own env), or being passed a PettingZoo env by another module of the run
    (its receivers are PettingZoo envs: no other family rewrites their calls)."""

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        return pettingzoo_in_reach(facts, context)

    @property
    def multi_agent(self) -> MultiAgent:
        return MultiAgent.of(self.facts, self.receivers)

    def changed(self) -> None:
        self.notes.pettingzoo_edited = True

    def replace_text(self, node: ast.AST, text: str) -> None:
        """Replace ``node`` by an expression written as source text."""
        self.changed()
        self.plan.replace(node, lambda _: cst.parse_expression(text))

    def rename_attribute(self, attr: ast.Attribute, name: str) -> None:
        self.changed()
        self.plan.replace(attr, lambda node: node.with_changes(attr=cst.Name(name)))

    def rename(self, name: ast.Name, new: str) -> None:
        self.changed()
        self.plan.replace(name, lambda node: node.with_changes(value=new))

    def split_target(self, target: ast.Tuple | ast.List, index: int, first: str, second: str) -> None:
        """``a, b, done, d`` -> ``a, b, first, second, d`` (the user's spacing kept)."""
        self.changed()
        self.plan.replace(target, lambda node: split_element(node, index, first, second))


def split_element(target: cst.BaseExpression, index: int, first: str, second: str) -> cst.BaseExpression:
    elements = list(target.elements)  # type: ignore[attr-defined]
    old = elements[index]
    comma = old.comma if isinstance(old.comma, cst.Comma) else cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))
    elements[index : index + 1] = [
        cst.Element(value=cst.parse_expression(first), comma=comma),
        cst.Element(value=cst.parse_expression(second), comma=old.comma),
    ]
    return target.with_changes(elements=elements)


def tuple_target(assign: ast.AST | None, size: int) -> ast.Tuple | ast.List | None:
    """The target of ``a, b, c = ...`` when it unpacks exactly ``size`` plain elements."""
    if not (isinstance(assign, ast.Assign) and len(assign.targets) == 1):
        return None
    target = assign.targets[0]
    if isinstance(target, (ast.Tuple, ast.List)) and len(target.elts) == size:
        if not any(isinstance(el, ast.Starred) for el in target.elts):
            return target
    return None


# Where ``a or b`` can stand without parentheses.
def needs_parentheses(node: ast.AST, facts: ModuleFacts) -> bool:
    parent = facts.parent(node)
    if isinstance(parent, (ast.If, ast.While, ast.IfExp, ast.Assert)) and parent.test is node:
        return False
    if isinstance(parent, (ast.Assign, ast.Return, ast.keyword, ast.AnnAssign)) and parent.value is node:
        return False
    if isinstance(parent, ast.Call) and node in parent.args:
        return False
    return True


def either(node: ast.AST, text: str, facts: ModuleFacts) -> str:
    return f"({text})" if needs_parentheses(node, facts) else text


def values_call(dones: ast.AST, facts: ModuleFacts) -> tuple[ast.Call, str] | None:
    """``all(X.values())`` / ``any(X.values())`` around ``X``: the outer call and its name."""
    attribute = facts.parent(dones)
    if not (isinstance(attribute, ast.Attribute) and attribute.attr == "values"):
        return None
    inner = facts.parent(attribute)
    if not (isinstance(inner, ast.Call) and inner.func is attribute and not inner.args and not inner.keywords):
        return None
    outer = facts.parent(inner)
    if isinstance(outer, ast.Call) and isinstance(outer.func, ast.Name) and outer.func.id in ("all", "any"):
        if len(outer.args) == 1 and not outer.keywords:
            return outer, outer.func.id
    return None


def without_param(node: cst.FunctionDef, name: str) -> cst.FunctionDef:
    params = node.params
    kept = [p for p in params.params if p.name.value != name]
    if len(kept) != len(params.params) and kept:
        kept[-1] = kept[-1].with_changes(comma=params.params[-1].comma)
    return node.with_changes(params=params.with_changes(params=kept))


def with_params(node: cst.FunctionDef, missing: list[str]) -> cst.FunctionDef:
    params = node.params
    kept = list(params.params)
    comma = cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))
    for name in missing:
        if kept:
            kept[-1] = kept[-1].with_changes(comma=comma)
        kept.append(
            cst.Param(
                name=cst.Name(name),
                default=cst.Name("None"),
                equal=cst.AssignEqual(whitespace_before=cst.SimpleWhitespace(""), whitespace_after=cst.SimpleWhitespace("")),
            )
        )
    return node.with_changes(params=params.with_changes(params=kept))


def insert_first(plan, function: ast.FunctionDef | ast.AsyncFunctionDef, code: str) -> None:
    """``code`` as the first statement of ``function`` (after its docstring)."""
    first = function.body[0]
    if is_docstring(first) and len(function.body) > 1:
        plan.insert_after(first, code)
    else:
        plan.insert_before(first, code)



def is_docstring(statement: ast.stmt) -> bool:
    return isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Constant) and isinstance(statement.value.value, str)
