"""Vector envs: construction, infos and autoreset (GM701, GM702, GM705-GM708).

One family, one module per concern:

* ``construction.py``: GM701 ``gym.vector.make`` -> ``gym.make_vec`` with the mode
  written out; GM702 the removed space arguments of ``SyncVectorEnv``/``AsyncVectorEnv``.
* ``infos.py``: GM705 list-style readers of vector ``infos`` (a dict of arrays); GM706
  ``final_observation`` readers (SAME_STEP autoreset) and the keys that are gone.
* ``wrappers.py``: GM707 ``VectorEnvWrapper`` -> ``VectorWrapper``; GM708 a vector env
  where a single ``Env`` is expected.
* ``common.py``: the names and small helpers they share.

They are one family because they edit the same calls: a ``gym.vector.make`` that
becomes ``make_vec`` (GM701) may also need ``autoreset_mode`` in its ``vector_kwargs``
(GM706) and a ``DictInfoToList`` around it (GM705). Each rule module decides; the
edits of one creation call are put together here, once, in that order.

Stable-Baselines3 VecEnvs keep their list of info dicts and ``terminal_observation``
(SB104): receivers go through ``facts.decisions.decide``. Envs are traced back to their
creation call with ``facts.creation``.
"""

from __future__ import annotations

import ast

from gymmigrate.edits.arguments import append_keyword
from gymmigrate.edits.lazy import cst
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.creation import CreationFinder
from gymmigrate.facts.module import keyword
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.vector.common import (
    LIST_INFO_WRAPPERS,
    VECTOR_CLASSES,
    VectorDecisions,
    gym_rest,
    quote_style,
)
from gymmigrate.rules.vector.construction import Construction
from gymmigrate.rules.vector.infos import Infos
from gymmigrate.rules.vector.wrappers import VectorWrappers

RULES = (
    Rule(
        "GM701",
        "gym.vector.make",
        FixKind.AUTO,
        "`gym.vector.make(id, n, asynchronous=...)` becomes `gym.make_vec(id, num_envs=n, vectorization_mode=...)`.",
    ),
    Rule(
        "GM702",
        "vector env spaces arguments",
        FixKind.FLAG,
        "`SyncVectorEnv/AsyncVectorEnv(..., observation_space=, action_space=)` no longer exist: dropped where they are "
        "the spaces of the one env every env function copies, reported otherwise.",
    ),
    Rule(
        "GM705",
        "vector infos are a dict",
        FixKind.ASSIST,
        "Vector `infos` is a dict of arrays: list-style readers get `DictInfoToList` or are reported.",
    ),
    Rule(
        "GM706",
        "vector autoreset and final observation",
        FixKind.ASSIST,
        "`final_observation` readers get `autoreset_mode=SAME_STEP` and `final_obs`; other legacy autoreset uses are reported, once per file.",
    ),
    Rule(
        "GM707",
        "VectorEnvWrapper",
        FixKind.ASSIST,
        "`VectorEnvWrapper` becomes `VectorWrapper`; `step_wait`/`reset_wait` overrides are reported.",
    ),
    Rule("GM708", "VectorEnv is not an Env", FixKind.FLAG, "A vector env used where a single `Env` is expected."),
)


class VectorEnvs(Construction, Infos, VectorWrappers, RuleFamily):
    RULES = RULES

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        text = facts.text
        return "vector" in text or "VectorEnv" in text or "final_" in text or "terminal_observation" in text

    def decide(self) -> None:
        self.finder = CreationFinder(self.facts, self.receivers, self._is_vector_creation)
        self.decisions = VectorDecisions()
        calls = _all_calls(self.facts)
        for call in calls:
            if self.is_legacy_vector_make(call):
                self.decisions.vector_makes[id(call)] = call
            elif self.is_vector_class(call):
                self.check_spaces_arguments(call)
            self.check_single_env_use(call)
        handled: set[int] = set()
        self.plan_infos(handled)
        self.flag_stray_final_keys(handled)
        self.plan_vector_wrappers()
        self.plan_wrapper_autoreset()
        for call in self.decisions.vector_makes.values():
            self.report_vector_make(call)
        self._edit_creations()

    def _is_vector_creation(self, call: ast.Call) -> bool:
        rests = gym_rest(self.facts, call.func)
        return bool(rests & (N.GYM_VEC_FACTORIES | VECTOR_CLASSES)) or any(
            r.startswith(N.GYM_VEC_PREFIXES) or r.rsplit(".", 1)[-1] in LIST_INFO_WRAPPERS for r in rests
        )

    def _edit_creations(self) -> None:
        """Each creation call's edits, in order: convert or add SAME_STEP, then wrap."""
        decisions = self.decisions
        for key, call in {**decisions.vector_makes, **decisions.autoreset, **decisions.list_infos}.items():
            same_step = self._same_step(call) if key in decisions.autoreset else None
            if key in decisions.vector_makes:
                self.plan.replace(call, self.make_vec_build(call, same_step))
            elif same_step is not None:
                self.plan.replace(call, self._same_step_build(call, same_step))
            if key in decisions.list_infos:
                wrapper = self.plan.ensure_import("gymnasium.wrappers.vector", "DictInfoToList")
                self.plan.replace(call, lambda node, wrapper=wrapper: cst.Call(func=cst.parse_expression(wrapper), args=[cst.Arg(node)]))

    def _same_step(self, creation: ast.Call) -> str:
        """``gym.vector.AutoresetMode.SAME_STEP`` through the file's own gymnasium name."""
        root = creation.func
        while isinstance(root, ast.Attribute):
            root = root.value
        if isinstance(root, ast.Name) and self.facts.qualified_names(root) & {"gymnasium", "gym"}:
            return f"{root.id}.vector.AutoresetMode.SAME_STEP"
        return self.plan.ensure_import("gymnasium.vector", "AutoresetMode") + ".SAME_STEP"

    def _same_step_build(self, creation: ast.Call, same_step: str):
        """``autoreset_mode=`` on a vector class; ``vector_kwargs={"autoreset_mode": ...}`` on make_vec."""
        if gym_rest(self.facts, creation.func) & VECTOR_CLASSES:
            return lambda node: append_keyword(node, "autoreset_mode", cst.parse_expression(same_step))
        q = quote_style(self.facts, creation)
        has_vector_kwargs = keyword(creation, "vector_kwargs") is not None

        def build(node):
            entry = cst.DictElement(cst.SimpleString(f"{q}autoreset_mode{q}"), cst.parse_expression(same_step))
            existing = next((a for a in node.args if a.keyword is not None and a.keyword.value == "vector_kwargs"), None)
            if existing is None or not has_vector_kwargs or not isinstance(existing.value, cst.Dict):
                return append_keyword(node, "vector_kwargs", cst.Dict([entry]))
            elements = list(existing.value.elements)
            if elements and not isinstance(elements[-1].comma, cst.Comma):
                elements[-1] = elements[-1].with_changes(comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" ")))
            elements.append(entry)
            new_dict = existing.value.with_changes(elements=elements)
            return node.with_changes(args=[a.with_changes(value=new_dict) if a is existing else a for a in node.args])

        return build


def _all_calls(facts: ModuleFacts) -> list[ast.Call]:
    """Every call of a name or an attribute, in source order (outer before inner)."""
    calls = [call for index in (facts.calls_by_name, facts.attribute_calls) for group in index.values() for call in group]
    return sorted(calls, key=lambda c: (c.lineno, c.col_offset, -(c.end_lineno or 0), -(c.end_col_offset or 0)))


__all__ = ["RULES", "VectorEnvs"]
