"""GM107 for RLlib: a module that imports RLlib (``ray.rllib``, ``ray.tune``) next to gym is
written for a ray release built on gym. RLlib moved to Gymnasium in ray 2.3, and its own
multi-agent API moved with it: ``MultiAgentEnv.reset`` returns ``(obs dict, infos dict)``
there and ``step`` five dicts, ``terminateds`` and ``truncateds`` each with ``"__all__"``,
where the gym-era one returned the obs dict and four dicts (``dones``). Once this module's
gym import moves to Gymnasium, the ray pin and the project's RLlib envs must move with it:
no rule rewrites an RLlib env's reset or step (``facts/names.py`` OWN_ENV_API_CLASSES leaves
them), so it is one decision of the run, asked at the first such import and pointed at from
the others. Code already on the Gymnasium-era API asks nothing."""

from __future__ import annotations

import ast

from gymmigrate.facts import names as N
from gymmigrate.facts.module import FUNCTIONS, own_returns, walk
from gymmigrate.findings import FixKind, rllib_question
from gymmigrate.rules.imports.common import ImportsBase

_RLLIB_MODULES = ("ray.rllib", "ray.tune")
# What ray >= 2.3's MultiAgentEnv step hands back instead of ``dones``.
_GYMNASIUM_ERA_NAMES = frozenset({"terminateds", "truncateds"})

RLLIB_ERA = (
    "RLlib moved from gym to Gymnasium in ray 2.3: with this module on Gymnasium, ray must be >= 2.3, whose "
    "MultiAgentEnv reset returns (obs, infos) dicts and step five dicts (`terminateds` and `truncateds` in place "
    "of `dones`, each with `\"__all__\"`); no rule rewrites an RLlib env's reset or step: move the project's "
    "MultiAgentEnv classes, their callers and its ray config to that release"
)


class RllibEra(ImportsBase):
    """The RLlib-era item of GM107 (mixed into the family)."""

    def _rllib_era(self) -> None:
        if not self.context.profile.imports_gym:
            return  # nothing here moves to Gymnasium: the ray release it runs on is not this file's question
        first = next((node for node in self._imports() if _imports_rllib(node)), None)
        project = self.receivers.project
        if first is None or (project is not None and project.is_module("ray")) or self._on_gymnasium_era_api():
            return  # (a package of the run named ``ray`` is not the library)
        self.report(first, "GM107", RLLIB_ERA, FixKind.FLAG, question=rllib_question())

    def _on_gymnasium_era_api(self) -> bool:
        """The module already speaks ray 2.3+'s multi-agent API: it names ``terminateds`` or
        ``truncateds``, or an RLlib env class of it returns five values from ``step`` or takes
        ``seed``/``options`` in ``reset``."""
        for node in walk(self.facts.tree):
            name = node.id if isinstance(node, ast.Name) else node.arg if isinstance(node, ast.arg) else None
            if name in _GYMNASIUM_ERA_NAMES:
                return True
        return any(_gymnasium_era_class(c) for c in self.facts.all_classes if self._derives_rllib_env(c))

    def _derives_rllib_env(self, classdef: ast.ClassDef) -> bool:
        return any(
            q in N.OWN_ENV_API_CLASSES and q.startswith("ray.") for base in classdef.bases for q in self.facts.qualified_names(base)
        )


def _imports_rllib(node: ast.Import | ast.ImportFrom) -> bool:
    if isinstance(node, ast.Import):
        modules = [alias.name for alias in node.names]
    elif node.level or not node.module:
        return False
    else:
        modules = [node.module] + ([f"ray.{alias.name}" for alias in node.names] if node.module == "ray" else [])
    return any(m == prefix or m.startswith(prefix + ".") for m in modules for prefix in _RLLIB_MODULES)


def _gymnasium_era_class(classdef: ast.ClassDef) -> bool:
    for method in classdef.body:
        if not isinstance(method, FUNCTIONS):
            continue
        if method.name == "step" and any(
            isinstance(r.value, ast.Tuple) and len(r.value.elts) == 5 for r in own_returns(method)
        ):
            return True
        if method.name == "reset" and any(a.arg in ("seed", "options") for a in (*method.args.args, *method.args.kwonlyargs)):
            return True
    return False
