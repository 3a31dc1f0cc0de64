"""Reset and seeding at call sites (GM201-GM208, GM704).

Gym 0.26 (and so Gymnasium) changed three things about starting an episode:

* ``reset()`` returns ``(obs, info)`` (``Env.reset -> tuple[ObsType, dict]``), for single
  and vector envs alike, and the 0.22-0.25 ``return_info=`` keyword is gone
  (GM201, GM202, GM704: ``resets``).
* ``env.seed(s)`` is gone (``AttributeError: 'TimeLimit' object has no attribute 'seed'``):
  a seed is passed to ``reset(seed=s)``, "right after initialization and then never
  again" (``Env.reset`` docstring). A seed moved onto every reset of an episode loop makes
  every episode identical, the most common hand-migration bug (GM203, GM208: ``seeds``,
  with its mixins ``seed_methods`` for the seed()s of the project a call still reaches,
  ``seed_merges`` for a seed merged into a loop's or an if's later reset, and
  ``next_reset`` for finding the reset a seed leads to; GM204, with ``--seed N``: ``cli_seed``).
  gym < 0.9's ``env._seed(s)`` (the hook its ``Env.seed`` called) is the same call, decided
  as ``env.seed(s)``: no Gymnasium env has a ``_seed``, and the run renames or removes it in
  its own env classes (custom_env/seed.py), so reading it through the wrappers cannot work.
* Seeds must be Python ints (``Seed must be a python integer``, GM206); ``Space.seed()``
  returns an int or a dict, not ``[seed]`` (GM205); custom reset keywords go into
  ``options={...}`` (GM207).

Every call site asks ``facts.decisions.decide`` about its receiver first, so
Stable-Baselines3 VecEnvs (obs-only ``reset()``, ``vec_env.seed(s)``: their current API,
SB102/SB103), PettingZoo envs and unrelated objects are never touched. Already migrated
code (a two-name reset unpack, ``reset(seed=...)``) is left alone.

The family decides on the original module (``ast``): seeds first (a seed merged into
the next reset adds to that reset's edit), then resets, then ``--seed``. Control- and
data-flow questions (loops, constant seeds, numpy seeds, a free ``info`` name) are
answered by ``gymmigrate.facts.reset_flow``.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.module import is_super_call
from gymmigrate.rules.base import FileContext
from gymmigrate.rules.reset_seed.catalog import RULES
from gymmigrate.rules.reset_seed.cli_seed import CliSeed
from gymmigrate.rules.reset_seed.contract import ResetContractSites
from gymmigrate.rules.reset_seed.resets import ResetCalls
from gymmigrate.rules.reset_seed.seeds import SeedCalls

__all__ = ["RULES", "ResetSeed"]


class ResetSeed(ResetCalls, SeedCalls, CliSeed, ResetContractSites):
    RULES = RULES

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        # ``def reset``: an env class of a reset contract the run's wrappers pass keywords to (GM207)
        return bool(facts.attribute_calls.get("reset") or _seed_calls(facts)) or "def reset" in facts.text

    def decide(self) -> None:
        self._start()
        seeds = _seed_calls(self.facts)
        resets: list[ast.Call] = self.facts.attribute_calls.get("reset", [])
        self.contract_keywords = self._plan_contract()
        for call in seeds:
            self._decide_seed(call)
        for call in resets:
            self._decide_reset(call)
        if self.context.options.seed is not None:
            self._decide_cli_seed(self.context.options.seed, [*seeds, *resets])


def _seed_calls(facts: ModuleFacts) -> list[ast.Call]:
    """``x.seed(...)``, and gym < 0.9's ``x._seed(...)`` on another object than the class's
    own (``self._seed(s)``, ``super()._seed(s)`` and ``Base._seed(self, s)`` are its hook,
    the custom-env rules' business), in source order."""
    hooks = [call for call in facts.attribute_calls.get("_seed", []) if not _on_own_class(call)]
    seeds = facts.attribute_calls.get("seed", [])
    return sorted([*seeds, *hooks], key=lambda call: (call.lineno, call.col_offset)) if hooks else seeds


def _on_own_class(call: ast.Call) -> bool:
    receiver = call.func.value  # type: ignore[attr-defined]
    if (isinstance(receiver, ast.Name) and receiver.id == "self") or is_super_call(receiver):
        return True
    return bool(call.args) and isinstance(call.args[0], ast.Name) and call.args[0].id == "self"
