"""``--seed N``: seed the first reset of every env the code never seeds (GM204).

An env that is never seeded draws its seed from entropy, so no two runs of a migrated
script agree. With ``--seed N`` the first reset after the env is created gets
``seed=N``; when that reset is inside a loop (which would reseed every episode), a
seeding ``env.reset(seed=N)`` is inserted before the loop instead. Envs the code seeds
itself, SB3 VecEnvs, and vector envs whose sub-envs are seeded are left alone.
"""

from __future__ import annotations

import ast
from collections import defaultdict

from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import Scope
from gymmigrate.facts.reset_flow import enclosing_loops, position
from gymmigrate.findings import FixKind
from gymmigrate.rules.reset_seed.call_edits import seed_literal, seeding_reset
from gymmigrate.rules.reset_seed.common import ResetSeedBase, is_seeding, is_space


class CliSeed(ResetSeedBase):
    def _decide_cli_seed(self, seed: int, calls: list[ast.Call]) -> None:
        """Seed the first reset of every env created here that the code never seeds."""
        facts = self.facts
        # Envs created by ``name = <Gym env or vector env>``, per (scope, name), in source order.
        creations: dict[tuple[Scope, str], list[ast.Assign]] = defaultdict(list)
        for scope in facts.scopes.values():
            for bindings in scope.bindings.values():
                for target in bindings:
                    assign = facts.parent(target)
                    if not (isinstance(target, ast.Name) and isinstance(assign, ast.Assign)):
                        continue
                    if len(assign.targets) != 1 or assign.targets[0] is not target:
                        continue
                    if self.receivers.kind_of(assign.value) in (EnvKind.GYM_ENV, EnvKind.GYM_VEC):
                        creations[(facts.scope_of(target), target.id)].append(assign)
        if not creations:
            return
        # ``x.seed(...)`` and ``x.reset(...)`` on a plain name, by the scope the name is read in.
        by_receiver: dict[tuple[Scope, str], list[ast.Call]] = defaultdict(list)
        for call in calls:
            func = call.func
            if not isinstance(func, ast.Attribute):  # ``x.method(...)`` calls only
                continue
            receiver = func.value
            if isinstance(receiver, ast.Name):
                by_receiver[(facts.scope_of(receiver), receiver.id)].append(call)
        seeded_somewhere = any(self._seeds_a_gym_env(call) for call in calls)
        envs = sorted(creations.items(), key=lambda item: min(position(a) for a in item[1]))
        for (scope, name), assigns in envs:
            assigns.sort(key=position)
            uses = by_receiver.get((scope, name), [])
            if any(is_seeding(call) for call in uses):
                continue
            created_at = position(assigns[0])
            resets = sorted((call for call in uses if position(call) > created_at), key=position)
            if not resets:
                continue
            first = resets[0]
            func = first.func
            if not isinstance(func, ast.Attribute):  # ``x.reset(...)`` calls only (above)
                continue
            kind = self.receivers.kind_of(func.value)
            if not kind.is_gym or (kind is EnvKind.GYM_VEC and seeded_somewhere):
                continue  # a vector env whose sub-envs are seeded already
            self._seed_first_reset(first, assigns[0], name, seed)

    def _seed_first_reset(self, first: ast.Call, creation: ast.Assign, name: str, seed: int) -> None:
        creation_loops = {id(loop) for loop in enclosing_loops(self.facts, creation)}
        loops = [loop for loop in enclosing_loops(self.facts, first) if id(loop) not in creation_loops]
        if not loops:
            self._edit(first).add_seed = seed_literal(seed)
            self.report(first, "GM204", f"--seed {seed}: `{name}` had no seed; its first reset is seeded", FixKind.ASSIST)
            return
        self.plan.insert_before(self.facts.statement_of(loops[-1]), seeding_reset(name, seed))
        self.report(
            first,
            "GM204",
            f"--seed {seed}: `{name}` had no seed and is first reset inside a loop; "
            f"`{name}.reset(seed={seed})` inserted before the loop",
            FixKind.ASSIST,
        )

    def _seeds_a_gym_env(self, call: ast.Call) -> bool:
        func = call.func
        if not isinstance(func, ast.Attribute):  # ``x.method(...)`` calls only
            return False
        receiver = func.value
        return is_seeding(call) and not is_space(receiver) and self._receiver_kind(receiver).is_gym
