"""Which receivers are PettingZoo envs (``facts.multi_agent`` on top of ``Receivers``)."""

from __future__ import annotations

import ast

import pytest

from gymmigrate.facts.module import ModuleFacts
from gymmigrate.facts.multi_agent import MultiAgent
from gymmigrate.facts.receivers import EnvKind, Receivers


def kinds(source: str) -> dict[str, EnvKind | None]:
    """The PettingZoo kind of every name read as ``NAME.probe()`` in ``source``."""
    tree = ast.parse(source)
    facts = ModuleFacts(tree, source)
    multi_agent = MultiAgent.of(facts, Receivers(facts))
    return {call.func.value.id: multi_agent.kind(call.func.value) for call in facts.attribute_calls["probe"]}


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("from pettingzoo.classic import rps_v2\nenv = rps_v2.env()\nenv.probe()", EnvKind.PZ_AEC),
        ("from pettingzoo.classic import rps_v2\nenv = rps_v2.parallel_env()\nenv.probe()", EnvKind.PZ_PARALLEL),
        ("import pettingzoo\nenv = pettingzoo.make('parallel', 'classic/rps-v2')\nenv.probe()", EnvKind.PZ_PARALLEL),
        ("from pettingzoo.utils import aec_to_parallel\nfrom x import e\nenv = aec_to_parallel(e)\nenv.probe()", EnvKind.PZ_PARALLEL),
        # SuperSuit wrappers keep the kind of what they wrap ...
        ("import supersuit as ss\nfrom pettingzoo.butterfly import pistonball_v6\n"
         "env = ss.frame_stack_v1(ss.color_reduction_v0(pistonball_v6.parallel_env()), 3)\nenv.probe()", EnvKind.PZ_PARALLEL),
        # ... and their vector conversions are VecEnvs: not PettingZoo envs, guarded.
        ("import supersuit as ss\nfrom pettingzoo.butterfly import pistonball_v6\n"
         "env = ss.concat_vec_envs_v1(ss.pettingzoo_env_to_vec_env_v1(pistonball_v6.parallel_env()), 2)\nenv.probe()", None),
        # ``agent_iter`` only exists on AEC envs.
        ("def run(env):\n    for agent in env.agent_iter():\n        env.probe()", EnvKind.PZ_AEC),
        ("def run(env):\n    env.probe()", None),
        ("from pettingzoo.utils.conversions import parallel_wrapper_fn\nfrom x import raw\n"
         "parallel_env = parallel_wrapper_fn(raw)\nenv = parallel_env()\nenv.probe()", EnvKind.PZ_PARALLEL),
        ("import gym\nenv = gym.make('CartPole-v1')\nenv.probe()", None),
    ],
)
def test_pettingzoo_kind(source: str, expected: EnvKind | None) -> None:
    assert kinds(source) == {"env": expected}


def test_self_env_of_a_pettingzoo_wrapper_is_the_wrapped_env() -> None:
    source = (
        "from pettingzoo.utils import BaseParallelWrapper\n"
        "class W(BaseParallelWrapper):\n"
        "    def step(self, actions):\n"
        "        return self.env.step(actions)\n"
    )
    tree = ast.parse(source)
    facts = ModuleFacts(tree, source)
    receiver = facts.attribute_calls["step"][0].func.value
    assert Receivers(facts).kind_of(receiver) is EnvKind.PZ_PARALLEL


def test_supersuit_vec_env_is_guarded_like_a_vecenv() -> None:
    source = "import supersuit as ss\nvenv = ss.concat_vec_envs_v1(x, 4)\nvenv.step(a)\n"
    tree = ast.parse(source)
    facts = ModuleFacts(tree, source)
    receiver = facts.attribute_calls["step"][0].func.value
    assert Receivers(facts).kind_of(receiver) is EnvKind.SB3_VEC
