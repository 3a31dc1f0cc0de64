"""GM507: reads of ``reward_range``, removed from ``Env`` and ``Wrapper`` in Gymnasium 1.0.

Reported: the value only exists where an env class defines it. One exception is rewritten:
an env ``gym.make`` made from a literal id of gym's own classic-control, Box2D, MuJoCo or
Atari envs, none of which set ``reward_range``, so it was gym's default ``(-inf, inf)``
(``best_score = env.reward_range[0]`` -> ``-float("inf")``).
"""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import names as N
from gymmigrate.facts.decisions import Action, decide
from gymmigrate.facts.env_classes import EnvClasses, is_self_attribute
from gymmigrate.facts.init_attributes import local_init_attributes
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import ModuleFacts
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.base import FileContext, Rule, RuleFamily


class RewardRange(RuleFamily):
    RULES = (
        Rule(
            "GM507",
            "reward_range",
            FixKind.FLAG,
            "Reads of `reward_range`, removed from `Env` and `Wrapper`, are reported; gym's default is written out for its own envs.",
        ),
    )

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        return "reward_range" in facts.text

    def decide(self) -> None:
        env = EnvClasses.of(self.facts, self.receivers)
        for node in list(self.facts.parents):
            if isinstance(node, ast.Attribute) and node.attr == "reward_range" and not self._is_store(node):
                self._check(env, node)

    def _is_store(self, node: ast.Attribute) -> bool:
        parent = self.facts.parent(node)
        if isinstance(parent, ast.Assign):
            return any(target is node for target in parent.targets)
        return isinstance(parent, ast.AnnAssign) and parent.target is node

    def _check(self, env: EnvClasses, node: ast.Attribute) -> None:
        owner = node.value
        classdef = self.facts.enclosing_class(node)
        if isinstance(owner, ast.Name) and owner.id == "self" and classdef is not None:
            if self.receivers.is_gym_wrapper_class(classdef):
                self.report(node, "GM507", "Wrapper.reward_range was removed in Gymnasium 1.0; read `self.env.unwrapped.reward_range` if the env defines it")
            elif env.is_custom_env(classdef) and not _defines_reward_range(env, classdef):
                self.report(node, "GM507", "Env.reward_range was removed in Gymnasium 1.0; define `reward_range` on this class or drop the read")
            return
        holders = self._constructed_holding(owner)
        if holders is not None:
            self.report(
                node,
                "GM507",
                f"`{ast.unparse(owner)}` is an env built by its own class, with no wrapper around it, and "
                f"{', '.join(holders)} sets `reward_range` when constructed: the read works as it did",
                tier=Tier.NOTE,
            )
            return
        kind = self.receivers.kind_of(owner)
        if kind is EnvKind.GYM_ENV and self._default_range(owner):
            self._replace_with_default(node)
            return
        decision = decide(kind, owner, self.context.profile)
        if decision.action is not Action.LEAVE or kind is EnvKind.GYM_ENV:
            self.report(
                node,
                "GM507",
                "reward_range was removed from Env and Wrapper in Gymnasium 1.0 (reads through a wrapper raise AttributeError); use `env.unwrapped.reward_range` if the env defines it",
            )


    def _constructed_holding(self, owner: ast.expr) -> list[str] | None:
        """The classes whose constructions ``owner`` holds on every path (``env =
        Track(...)``, a class of the file or of the run), where each certainly stores
        ``reward_range`` once constructed (``facts/init_attributes.py``); None otherwise.
        Gymnasium's Env has no ``reward_range`` any more: only the class's own counts."""
        if not isinstance(owner, ast.Name):
            return None
        bindings = self.facts.bindings_of(owner)
        if not bindings:
            return None
        found: set[str] = set()
        for binding in bindings:
            statement = self.facts.parent(binding)
            if not (isinstance(statement, ast.Assign) and statement.targets == [binding] and isinstance(statement.value, ast.Call)):
                return None
            name = self._class_holding(statement.value.func)
            if name is None:
                return None
            found.add(name)
        return sorted(found)

    def _class_holding(self, func: ast.expr) -> str | None:
        view = self.receivers.project
        local = self.receivers.local_class(func)
        if local is not None:
            attributes = view.init_attributes_here(local.name) if view is not None else local_init_attributes(self.facts, local)
            return local.name if "reward_range" in attributes else None
        if view is None:
            return None
        for qualified in self.facts.qualified_names(func):
            if "reward_range" in view.init_attributes(qualified):
                return qualified.rsplit(".", 1)[-1]
        return None

    def _default_range(self, owner: ast.expr) -> bool:
        """Every binding of ``owner`` is ``gym.make("<id>")`` of an env that kept gym's
        default reward range."""
        if not isinstance(owner, ast.Name):
            return False
        bindings = self.facts.bindings_of(owner)
        for binding in bindings:
            assign = self.facts.parent(binding)
            if not (isinstance(assign, ast.Assign) and isinstance(assign.value, ast.Call) and assign.value.args):
                return False
            call = assign.value
            if not any(N.strip_gym_prefix(q) in N.GYM_ENV_FACTORIES for q in self.facts.qualified_names(call.func)):
                return False
            env_id = call.args[0]
            if not (isinstance(env_id, ast.Constant) and isinstance(env_id.value, str)):
                return False
            if env_id.value.split("/")[-1].split("-v")[0] not in _DEFAULT_RANGE_FAMILIES:
                return False
        return bool(bindings)

    def _replace_with_default(self, node: ast.Attribute) -> None:
        parent = self.facts.parent(node)
        index = parent.slice if isinstance(parent, ast.Subscript) and parent.value is node else None
        if parent is not None and isinstance(index, ast.Constant) and index.value in (0, 1) and type(index.value) is int:
            text = '-float("inf")' if index.value == 0 else 'float("inf")'
            self.plan.replace(parent, lambda _node: cst.parse_expression(text))
        else:
            self.plan.replace(node, lambda _node: cst.parse_expression('(-float("inf"), float("inf"))'))
        self.report(
            node,
            "GM507",
            "reward_range was removed in Gymnasium 1.0; this env never set it, so it was gym's default (-inf, inf): "
            "written out",
            FixKind.AUTO,
        )


# Families of gym's own envs that never set ``reward_range`` (gym's default, (-inf, inf)).
# toy_text is left out: some of its envs set their own.
_DEFAULT_RANGE_FAMILIES = frozenset(
    {
        "CartPole", "MountainCar", "MountainCarContinuous", "Pendulum", "Acrobot",
        "LunarLander", "LunarLanderContinuous", "BipedalWalker", "BipedalWalkerHardcore", "CarRacing",
        "Ant", "HalfCheetah", "Hopper", "Humanoid", "HumanoidStandup", "InvertedPendulum",
        "InvertedDoublePendulum", "Reacher", "Swimmer", "Walker2d", "Pusher",
        "Breakout", "BreakoutNoFrameskip", "Pong", "PongNoFrameskip", "SpaceInvaders", "SpaceInvadersNoFrameskip",
        "Seaquest", "SeaquestNoFrameskip", "Qbert", "QbertNoFrameskip", "MsPacman", "MsPacmanNoFrameskip",
        "BeamRider", "BeamRiderNoFrameskip", "Enduro", "EnduroNoFrameskip",
    }
)  # fmt: skip


def _defines_reward_range(env: EnvClasses, classdef: ast.ClassDef) -> bool:
    for assign in env.index(classdef).assigns:
        for target in assign.targets:
            if (isinstance(target, ast.Name) and target.id == "reward_range") or is_self_attribute(target, ("reward_range",)):
                return True
    return False
