"""``seed()`` calls: ``env.seed(s)`` is gone, a seed goes to the first reset (GM203, GM205, GM206, GM208).

``env.seed(s)`` raises ``AttributeError: 'TimeLimit' object has no attribute 'seed'`` since
gym 0.26: a seed is passed to ``reset(seed=s)``, "right after initialization and then
never again" (``Env.reset`` docstring). So:

* GM203/GM208 ``env.seed(s)`` (``envs.seed(s)`` on a vector env) is merged into the reset
  of the same env that follows it in the same block (statements in between must leave
  the env alone), keeping the comments above it; otherwise it becomes
  ``env.reset(seed=s)`` in place (listed for review where a later loop resets an env whose
  reset may have side effects). A seed moves into a loop only as the first iteration's seed of
  a counted loop's reset, ``env.reset(seed=s if i == 0 else None)``. A ``seed()`` whose
  result is used, that has no single seed, or that sits in a ``seed()`` method is reported;
  in a project's own ``seed()`` (a plain class's) on envs ``make`` built, while env classes
  of the run keep their seed() (GM503), it becomes ``env.unwrapped.seed(s)``. On an env the
  run keeps on the legacy API whose wrapper chain holds a class of the run defining seed(),
  it is left (on that class) or becomes ``env.get_wrapper_attr("seed")(s)``. Where a Gym
  wrapper class of the run defines a seed() of its own (which reset(seed=...) never calls)
  and the env classes keep theirs, ``env.seed(s)`` on a made env, in a plain class's seed()
  or in that wrapper's seed() becomes ``env.get_wrapper_attr("seed")(s)``: the seed() gym's
  forwarding reached, not merged into a reset. In the seed() of a plain class of the
  project (an adapter deriving its own base), which the project calls itself, it becomes
  ``env.reset(seed=s)`` in place, listed once for review (it also resets the env).
* GM206 a numpy scalar seed is wrapped in ``int()`` (``Seed must be a python integer``).
* GM204 a seed that is the same on every iteration of a loop is reported.
* GM205 ``space.seed(s)`` stays, but it returns an int (a dict for Dict spaces), not
  ``[seed]``: a subscript of its result is reported.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import names as N
from gymmigrate.facts.decisions import Action, receiver_text
from gymmigrate.facts.legacy_wrapper_hooks import in_dead_hook
from gymmigrate.facts.module import COMPOUND_STATEMENTS, string_value, walk
from gymmigrate.facts.multi_agent import MultiAgent
from gymmigrate.facts.reset_flow import segment
from gymmigrate.facts.version_checks import dead_version_branch
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.env_ids.catalog import known_elsewhere
from gymmigrate.rules.multi_agent_gate import pettingzoo_in_reach
from gymmigrate.rules.reset_seed.call_edits import SeedValue, int_call
from gymmigrate.rules.reset_seed.common import (
    _seed_argument,
    is_space,
    moving_seed_question,
)
from gymmigrate.rules.reset_seed.seed_merges import SeedMerges
from gymmigrate.rules.reset_seed.seed_methods import SeedMethods


class SeedCalls(SeedMethods, SeedMerges):
    def _decide_seed(self, call: ast.Call) -> None:
        func = call.func
        if not isinstance(func, ast.Attribute):  # ``x.method(...)`` calls only
            return
        receiver = func.value
        if dead_version_branch(call, self.facts) is not None:
            return  # the legacy branch of a gym version check: it never runs on Gymnasium (GM108)
        if in_dead_hook(self.receivers, call):
            return  # a gym < 0.9 wrapper hook left dead (GM616): its body stays whole
        if is_space(receiver):
            self._check_space_seed(call)
            return
        if self._seed_in_kept_chain(call, receiver):
            return
        if self._pettingzoo_seed(receiver):
            return  # PZ106 rewrites it: there is no Gym question left
        decision, vector = self._decide(receiver)
        if decision.action is Action.LEAVE:
            return
        code = "GM208" if vector else "GM203"
        name = receiver_text(receiver)
        called = f"{name}.{func.attr}"  # ``env.seed``, or gym < 0.9's ``env._seed``
        if decision.action is Action.REPORT:
            self.report(
                call,
                code,
                f"{decision.reason}: if it is a Gym env, replace {func.attr}(s) with reset(seed=s)",
                FixKind.FLAG,
                question=self.receiver_question(receiver, decision),
            )
            return
        function = self.facts.enclosing_function(call)
        if function is not None and function.name in ("seed", "_seed"):
            if self._seed_reaches_own_seed(call, function, receiver, name):
                return
            if self._seed_through_unwrapped(call, function, decision, code, name):
                return
            if self._seed_in_wrapper_seed(call, function, decision, code, name):
                return
            if self._seed_in_own_seed(call, function, decision, code, name):
                return
            self.report(
                call,
                code,
                "inside a seed() method, which Gymnasium never calls: move the seeding into reset(seed=...)",
                FixKind.FLAG,
                question=moving_seed_question(function),  # a wrapper's space seeding there asks the same (GM205)
            )
            return
        statement = self.facts.parent(call)
        if not isinstance(statement, ast.Expr):
            self.report(
                call,
                code,
                f"`{called}()` is gone and its result (legacy: [seed]) is used here: call "
                f"`{name}.reset(seed=s)` and keep the seed value yourself",
                FixKind.FLAG,
            )
            return
        seed = _seed_argument(call)
        if seed is None:
            self.report(
                call,
                code,
                f"`{called}()` without exactly one seed is gone: pass the seed to the first "
                f"`{name}.reset(seed=s)` (with no seed Gymnasium draws one from entropy); then delete this call",
                FixKind.FLAG,
            )
            return
        if not vector and self._seed_through_chain(call, receiver, decision, code, name):
            return
        numpy = self.numpy_seeds.is_numpy(seed)
        if numpy:
            # int() of a numpy integer is the same seed legacy gym took: nothing to decide, a note
            self.report(seed, "GM206", "numpy seed wrapped in int(): Gymnasium accepts only Python ints as seeds", tier=Tier.NOTE)
        self._check_seed_in_loop(call, seed, f"`{name}.seed(...)`")
        merged, setup = self._next_reset(statement, receiver)
        why = self._why(decision)
        if merged is not None:
            value = SeedValue()
            self.plan.replace(call, value.take)
            self.plan.remove(statement, keep_comments=True)
            self._edit(merged).add_seed = value.get(as_int=numpy, moved=lambda: statement in self.plan.removed)
            if setup is not None:
                # ``env.seed(0); env.set_agents(...); env.reset()``: a reset in place of the
                # seed would run before the set-up the reset needs; the seed goes to the reset
                # that comes next, after it.
                self.report(
                    call,
                    code,
                    f"`{called}(s)` merged into the reset that follows the set-up "
                    f"(`{segment(self.facts, setup.func)}(...)`, line {setup.lineno}): `{name}.reset(seed=s)`; "
                    f"a reset here would run before that set-up. If the set-up draws from the env's "
                    f"random generator, it is no longer seeded: seed it yourself{why}",
                    FixKind.ASSIST,
                    question=self.receiver_question(receiver, decision),
                )
                return
            self.report(
                call,
                code,
                f"`{called}(s)` merged into the reset that follows it: `{name}.reset(seed=s)`{why}",
                self._kind(decision, FixKind.AUTO),
                question=self.receiver_question(receiver, decision),
            )
            return
        if self._merge_from_branch(call, statement, receiver, decision, code, called, numpy):
            return
        if self._merge_into_counted_loop(call, statement, receiver, decision, code, called, numpy):
            return
        edit = self._edit(call)
        edit.to_reset = True
        edit.int_seed = numpy
        said = (
            f"`{called}(s)` -> `{name}.reset(seed=s)` at the same place: it seeds once here and starts an extra "
            f"episode; later resets continue the seeded stream"
        )
        if (
            decision.action is Action.REWRITE
            and (later := self._reset_later(statement, receiver))[0]
            and not self._made_from_gym_id(receiver)
        ):
            # the env's class is the project's own or unknown: its reset may reconnect, play or
            # count, so the extra episode may shift every later one
            fix = (
                f"pass the seed to the reset of line {later[1].lineno} (`{name}.reset(seed=s)`)"
                + (" if the statements in between do not need the seeding" if self._between(statement, later[1]) else "")
                + ", and delete this line"
                if later[1] is not None
                else f"delete this line and pass the seed to the first reset only (`{name}.reset(seed=s if first else None)`)"
            )
            self.report(
                call,
                code,
                f"{said}. The env's reset may have side effects (its class is not a Gym-registered env): if the "
                f"extra episode matters, {fix}",
                FixKind.ASSIST,
                question=self.receiver_question(receiver, decision),
            )
            return
        self.report(
            call,
            code,
            f"{said}{why}",
            self._kind(decision),
            tier=Tier.NOTE if decision.action is Action.REWRITE else None,  # it explains the rewrite: nothing to decide
            question=self.receiver_question(receiver, decision),
        )

    def _reset_later(self, statement: ast.Expr, receiver: ast.expr) -> tuple[bool, ast.stmt | None]:
        """A compound statement after ``statement`` in its block (a loop, a branch) resets the
        env, or a later statement calls a function of this module that resets it by that name:
        the reset in the seed's place adds an episode before the program's own first one, on a
        path no merge follows. So does a plain statement of the same block that resets it, which
        the merge did not reach (a statement in between blocked it: ``env.seed(i)``, an
        attribute set, then the loop's ``obs = env.reset()``): every pass then runs two resets.
        ``(found, that plain statement or None)``."""
        found = self._place_in_block(statement)
        if found is None:
            return False, None
        block, position = found
        wanted = segment(self.facts, receiver)

        def resets(part: ast.AST) -> bool:
            return bool(self._resets_in(part, wanted))

        functions = self.facts.memo(("seed-local-functions", 0), lambda: _functions_by_name(self.facts.tree))
        for later in block[position + 1 :]:
            # a plain statement's reset runs with it, unless a lambda only holds it
            if isinstance(later, COMPOUND_STATEMENTS) and resets(later):
                return True, None
            if resets(later) and not any(isinstance(node, ast.Lambda) for node in walk(later)):
                return True, later
            for node in walk(later):
                if isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
                    if any(resets(function) for function in functions.get(node.func.id, ())):
                        return True, None
        return False, None

    def _between(self, statement: ast.stmt, later: ast.stmt) -> bool:
        """Statements of the block stand between ``statement`` and ``later``."""
        found = self._place_in_block(statement)
        return found is not None and later in found[0] and found[0].index(later) > found[1] + 1

    def _made_from_gym_id(self, receiver: ast.expr) -> bool:
        """Every env ``receiver`` may be is ``gym.make`` of a literal id Gym (or a package
        registered with Gymnasium) registers and the run does not: a reset without side
        effects beyond drawing the episode."""
        makes = self._makes_behind(receiver)
        if not makes.complete or not makes.calls:
            return False
        project = self.receivers.project
        for make in makes.calls:
            if not any(N.strip_gym_prefix(q) in N.GYM_ENV_FACTORIES for q in self.facts.qualified_names(make.func)):
                return False
            env_id = string_value(make.args[0]) if make.args else None
            if env_id is None or not known_elsewhere(env_id):
                return False
            if project is not None and project.may_register(env_id):
                return False  # the run's own class, whatever the id says
        return True

    def _pettingzoo_seed(self, receiver: ast.expr) -> bool:
        """``self._env.seed(s)`` on a PettingZoo env, under the same conditions on which PZ106
        (``rules/pettingzoo/seed_render.py``) rewrites it."""
        if isinstance(receiver, ast.Name) and receiver.id == "self":
            return False
        if not pettingzoo_in_reach(self.facts, self.context):
            return False
        return MultiAgent.of(self.facts, self.receivers).kind(receiver) is not None

    def _check_space_seed(self, call: ast.Call) -> None:
        seed = _seed_argument(call)
        if seed is not None and self.numpy_seeds.is_numpy(seed):
            # ``space.seed(rng.integers(...))``: Gymnasium's Space.seed raises on a numpy
            # integer (legacy RandomState.randint gave a Python int); int() is the same seed
            self.plan.replace(seed, int_call)
            self.report(seed, "GM206", "numpy seed wrapped in int(): Gymnasium's Space.seed accepts only Python ints", tier=Tier.NOTE)
        parent = self.facts.parent(call)
        if isinstance(parent, ast.Subscript) and parent.value is call:
            self.report(
                parent,
                "GM205",
                "Space.seed() returns an int (a dict for Dict spaces) since Gymnasium 1.0, not [seed]: drop the subscript",
            )


def _functions_by_name(tree: ast.AST) -> dict[str, list[ast.FunctionDef | ast.AsyncFunctionDef]]:
    found: dict[str, list[ast.FunctionDef | ast.AsyncFunctionDef]] = {}
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            found.setdefault(node.name, []).append(node)
    return found
